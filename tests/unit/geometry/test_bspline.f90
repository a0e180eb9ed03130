!> Unit tests of ictus_geometry_bspline: FindSpan, basis values and derivatives.
program test_bspline
  use ictus_core_kinds, only: dp
  use ictus_geometry_bspline, only: find_span, ders_basis_funs
  use ictus_test_geometry, only: basis_funs
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t

  call t%start("geometry/bspline")
  call case_find_span(t)
  call case_book_example(t)
  call case_partition_and_derivatives(t, 3, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.3_dp, &
      0.5_dp, 0.5_dp, 0.8_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], "p3")
  call case_partition_and_derivatives(t, 2, [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 2.0_dp, &
      3.0_dp, 4.0_dp, 4.0_dp, 5.0_dp, 5.0_dp, 5.0_dp], "p2")
  call case_partition_and_derivatives(t, 1, [0.0_dp, 0.0_dp, 0.2_dp, 0.7_dp, 1.0_dp, &
      1.0_dp], "p1")
  call case_high_derivatives(t)
  call t%finish()

contains

  !> doc/iga.md §10.2: U = {0,0,0,1/2,1/2,1,1,1}, p = 2; 0-based spans 2,2,4,4,4 -> 1-based +1.
  subroutine case_find_span(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: u(8) = [0.0_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.5_dp, 1.0_dp, 1.0_dp, &
        1.0_dp]
    call t%equal_int(find_span(5, 2, 0.0_dp, u), 3, "span(0)")
    call t%equal_int(find_span(5, 2, 0.25_dp, u), 3, "span(0.25)")
    call t%equal_int(find_span(5, 2, 0.5_dp, u), 5, "span(0.5)")
    call t%equal_int(find_span(5, 2, 0.75_dp, u), 5, "span(0.75)")
    call t%equal_int(find_span(5, 2, 1.0_dp, u), 5, "span(1)")
  end subroutine case_find_span

  !> The NURBS Book Ex. 2.3/2.4: U = {0,0,0,1,2,3,4,4,5,5,5}, p = 2, u = 5/2:
  !! N_{2,2} = 1/8, N_{3,2} = 6/8, N_{4,2} = 1/8 and derivatives -1/2, 0, 1/2 (0-based).
  subroutine case_book_example(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: u(11) = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 2.0_dp, 3.0_dp, 4.0_dp, &
        4.0_dp, 5.0_dp, 5.0_dp, 5.0_dp]
    real(dp) :: nb(0:2), d(0:1, 0:2)
    integer :: s
    s = find_span(8, 2, 2.5_dp, u)
    call t%equal_int(s, 5, "book span")
    call basis_funs(s, 2.5_dp, 2, u, nb)
    call t%close_abs(nb(0), 0.125_dp, 1.0e-15_dp, "book N2")
    call t%close_abs(nb(1), 0.75_dp, 1.0e-15_dp, "book N3")
    call t%close_abs(nb(2), 0.125_dp, 1.0e-15_dp, "book N4")
    call ders_basis_funs(s, 2.5_dp, 2, 1, u, d)
    call t%close_abs(d(0, 1), 0.75_dp, 1.0e-15_dp, "book ders N3")
    call t%close_abs(d(1, 0), -0.5_dp, 1.0e-15_dp, "book N2'")
    call t%close_abs(d(1, 1), 0.0_dp, 1.0e-15_dp, "book N3'")
    call t%close_abs(d(1, 2), 0.5_dp, 1.0e-15_dp, "book N4'")
    ! the span at the double knot 4: knots(8) = 4 <= u < 5 -> 1-based 8
    call t%equal_int(find_span(8, 2, 4.0_dp, u), 8, "span at double knot")
    call t%equal_int(find_span(8, 2, 3.999_dp, u), 6, "span before double knot")
  end subroutine case_book_example

  !> Partition of unity, non-negativity, sum of derivatives = 0, and first and second
  !! derivatives against central differences, at points inside every non-empty span.
  subroutine case_partition_and_derivatives(t, p, knots, tag)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: p
    real(dp), intent(in) :: knots(:)
    character(len=*), intent(in) :: tag
    real(dp), parameter :: h = 1.0e-5_dp
    real(dp) :: nb(0:p), d(0:2, 0:p), dp1(0:2, 0:p), dm1(0:2, 0:p), u, err0, err1, err2, &
        neg, pu, sd
    integer :: n, i, j, s
    n = size(knots) - p - 1
    err0 = 0.0_dp
    err1 = 0.0_dp
    err2 = 0.0_dp
    neg = 0.0_dp
    pu = 0.0_dp
    sd = 0.0_dp
    do i = p + 1, n
      if (knots(i+1) <= knots(i)) cycle
      do j = 0, 20
        u = knots(i) + (knots(i+1) - knots(i))*(0.01_dp + 0.98_dp*real(j, dp)/20.0_dp)
        s = find_span(n, p, u, knots)
        call t%equal_int(s, i, tag//" span of interior point")
        call basis_funs(s, u, p, knots, nb)
        call ders_basis_funs(s, u, p, 2, knots, d)
        call ders_basis_funs(s, u + h, p, 2, knots, dp1)
        call ders_basis_funs(s, u - h, p, 2, knots, dm1)
        pu = max(pu, abs(sum(nb) - 1.0_dp))
        neg = min(neg, minval(nb))
        err0 = max(err0, maxval(abs(nb - d(0, :))))
        sd = max(sd, abs(sum(d(1, :))), abs(sum(d(2, :))))
        err1 = max(err1, maxval(abs((dp1(0, :) - dm1(0, :))/(2*h) - d(1, :))))
        err2 = max(err2, maxval(abs((dp1(1, :) - dm1(1, :))/(2*h) - d(2, :))))
      end do
    end do
    call t%close_abs(pu, 0.0_dp, 1.0e-14_dp, tag//" partition of unity")
    call t%true(neg >= 0.0_dp, tag//" non-negative")
    call t%close_abs(err0, 0.0_dp, 1.0e-14_dp, tag//" A2.2 = A2.3 values")
    call t%close_abs(sd, 0.0_dp, 1.0e-10_dp, tag//" derivatives sum to zero")
    call t%close_abs(err1, 0.0_dp, 1.0e-6_dp, tag//" N' vs finite differences")
    call t%close_abs(err2, 0.0_dp, 1.0e-5_dp, tag//" N'' vs finite differences")
  end subroutine case_partition_and_derivatives

  !> Derivatives above the degree are zero; the p-th derivative of a single Bezier span is
  !! the constant p! * (differences of binomial coefficients): for p = 2 on [0,1],
  !! N = ((1-u)^2, 2u(1-u), u^2) -> N'' = (2, -4, 2).
  subroutine case_high_derivatives(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: u(6) = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    real(dp) :: d(0:4, 0:2)
    call ders_basis_funs(3, 0.3_dp, 2, 4, u, d)
    call t%close_abs(d(0, 1), 2*0.3_dp*0.7_dp, 1.0e-15_dp, "Bezier N1")
    call t%close_abs(d(1, 0), -2*0.7_dp, 1.0e-15_dp, "Bezier N0'")
    call t%close_abs(d(2, 0), 2.0_dp, 1.0e-14_dp, "Bezier N0''")
    call t%close_abs(d(2, 1), -4.0_dp, 1.0e-14_dp, "Bezier N1''")
    call t%close_abs(d(2, 2), 2.0_dp, 1.0e-14_dp, "Bezier N2''")
    call t%true(all(d(3:4, :) == 0.0_dp), "derivatives above p are zero")
  end subroutine case_high_derivatives
end program test_bspline
