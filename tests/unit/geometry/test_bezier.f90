!> Unit tests of ictus_geometry_bezier: Bernstein polynomials and Bezier extraction
!! (C^e B = N on every non-empty span).
program test_bezier
  use ictus_core_kinds, only: dp
  use ictus_geometry_bspline, only: basis_funs
  use ictus_geometry_bezier, only: bezier_extraction_1d, bernstein, count_spans
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t

  call t%start("geometry/bezier")
  call case_bernstein(t)
  call case_extraction(t, 2, [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 2.0_dp, 3.0_dp, 4.0_dp, &
      4.0_dp, 5.0_dp, 5.0_dp, 5.0_dp], 5, "book p2")
  call case_extraction(t, 3, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.3_dp, 0.5_dp, 0.5_dp, &
      0.8_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], 4, "p3 double knot")
  call case_extraction(t, 2, [0.0_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.5_dp, 1.0_dp, 1.0_dp, &
      1.0_dp], 2, "half circle")
  call case_extraction(t, 2, [0.0_dp, 0.0_dp, 0.0_dp, 0.25_dp, 0.5_dp, 0.75_dp, 1.0_dp, &
      1.0_dp, 1.0_dp], 4, "uniform p2")
  call case_extraction(t, 4, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.2_dp, 0.4_dp, &
      0.4_dp, 0.4_dp, 0.9_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], 4, "p4")
  call case_extraction(t, 1, [0.0_dp, 0.0_dp, 0.3_dp, 1.0_dp, 1.0_dp], 2, "p1")
  call case_extraction(t, 2, [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], 1, "Bezier")
  call t%finish()

contains

  !> Values B = ((1-t)^2, 2t(1-t), t^2) at t = 1/4, partition of unity, derivatives vs
  !! central differences for p = 0..5.
  subroutine case_bernstein(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: h = 1.0e-6_dp
    real(dp) :: b(6), db(6), bp(6), dbp(6), bm(6), dbm(6), x, pu, e1
    integer :: p, i
    call bernstein(2, 0.25_dp, b(1:3), db(1:3))
    call t%close_abs(b(1), 0.5625_dp, 1.0e-16_dp, "B0(1/4)")
    call t%close_abs(b(2), 0.375_dp, 1.0e-16_dp, "B1(1/4)")
    call t%close_abs(b(3), 0.0625_dp, 1.0e-16_dp, "B2(1/4)")
    call t%close_abs(db(1), -1.5_dp, 1.0e-15_dp, "B0'(1/4)")
    call t%close_abs(db(2), 1.0_dp, 1.0e-15_dp, "B1'(1/4)")
    call t%close_abs(db(3), 0.5_dp, 1.0e-15_dp, "B2'(1/4)")
    call bernstein(3, 0.5_dp, b(1:4), db(1:4))
    call t%close_abs(b(2), 0.375_dp, 1.0e-16_dp, "cubic B1(1/2)")
    do p = 0, 5
      pu = 0.0_dp
      e1 = 0.0_dp
      do i = 1, 19
        x = real(i, dp)/20.0_dp
        call bernstein(p, x, b(1:p+1), db(1:p+1))
        call bernstein(p, x + h, bp(1:p+1), dbp(1:p+1))
        call bernstein(p, x - h, bm(1:p+1), dbm(1:p+1))
        pu = max(pu, abs(sum(b(1:p+1)) - 1.0_dp))
        e1 = max(e1, maxval(abs((bp(1:p+1) - bm(1:p+1))/(2*h) - db(1:p+1))))
        call t%true(all(b(1:p+1) >= 0.0_dp), "Bernstein non-negative")
      end do
      call t%close_abs(pu, 0.0_dp, 1.0e-15_dp, "Bernstein partition of unity")
      call t%close_abs(e1, 0.0_dp, 1.0e-8_dp, "Bernstein derivative vs differences")
    end do
  end subroutine case_bernstein

  !> C^e B(t) = N_{a-p..a}(u) for u = lo + t (hi - lo) on every non-empty span, to 1e-14.
  subroutine case_extraction(t, p, knots, nel_want, tag)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: p, nel_want
    real(dp), intent(in) :: knots(:)
    character(len=*), intent(in) :: tag
    real(dp), allocatable :: c(:,:,:)
    real(dp) :: b(p+1), db(p+1), nb(0:p), u, x, err
    integer :: n, nel, e, a, j
    n = size(knots) - p - 1
    call bezier_extraction_1d(n, p, knots, nel, c)
    call t%equal_int(nel, nel_want, tag//" number of elements")
    call t%equal_int(count_spans(n, p, knots), nel_want, tag//" count_spans")
    call t%equal_int(size(c, 3), nel_want, tag//" operators")
    err = 0.0_dp
    e = 0
    do a = p + 1, n
      if (knots(a+1) <= knots(a)) cycle
      e = e + 1
      do j = 0, 10
        x = real(j, dp)/10.0_dp
        u = knots(a) + x*(knots(a+1) - knots(a))
        call basis_funs(a, u, p, knots, nb)
        call bernstein(p, x, b, db)
        err = max(err, maxval(abs(matmul(c(:, :, e), b) - nb)))
      end do
    end do
    call t%close_abs(err, 0.0_dp, 1.0e-14_dp, tag//" C^e B = N")
  end subroutine case_extraction
end program test_bezier
