!> Unit tests of ictus_geometry_bezier: Bernstein polynomials (`bernstein`,
!! `bernstein_values`, `bernstein_d2`), Bezier curves by de Casteljau's recursion and Bezier
!! extraction (C^e B = N on every non-empty span).
program test_bezier
  use ictus_core_kinds, only: dp
  use ictus_test_geometry, only: basis_funs
  use ictus_geometry_bezier, only: bezier_extraction_1d, bernstein, count_spans, &
      bernstein_values, bernstein_d2, de_casteljau, BEZIER_MAX_DEGREE
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t

  call t%start("geometry/bezier")
  call case_bernstein(t)
  call case_bernstein_d2(t)
  call case_de_casteljau(t)
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

  !> bernstein_values and bernstein_d2 against `bernstein` (the same values and first
  !! derivatives), second derivatives: known values, sum zero, against central differences of
  !! the first, for p = 0..8 and at the highest degree.
  subroutine case_bernstein_d2(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: nb = BEZIER_MAX_DEGREE + 1
    real(dp), parameter :: h = 1.0e-6_dp
    real(dp) :: b(nb), db(nb), ddb(nb), bv(nb), bg(nb), dbg(nb), bp(nb), dbp(nb), ddbp(nb), &
        bm(nb), dbm(nb), ddbm(nb), x, e2, scale
    integer :: p, i
    logical :: same_b, same_db, unit
    call bernstein_d2(2, 0.3_dp, b(1:3), db(1:3), ddb(1:3))
    call t%true(all(ddb(1:3) == [2.0_dp, -4.0_dp, 2.0_dp]), "quadratic B'' = (2, -4, 2)")
    call bernstein_d2(3, 0.5_dp, b(1:4), db(1:4), ddb(1:4))
    call t%true(all(ddb(1:4) == [3.0_dp, -3.0_dp, -3.0_dp, 3.0_dp]), "cubic B''(1/2)")
    call bernstein_d2(1, 0.7_dp, b(1:2), db(1:2), ddb(1:2))
    call t%true(all(db(1:2) == [-1.0_dp, 1.0_dp]) .and. all(ddb(1:2) == 0.0_dp), "linear B', B''")
    call bernstein_d2(0, 0.7_dp, b(1:1), db(1:1), ddb(1:1))
    call t%true(b(1) == 1.0_dp .and. db(1) == 0.0_dp .and. ddb(1) == 0.0_dp, "constant B")
    do p = 0, 8
      same_b = .true.
      same_db = .true.
      unit = .true.
      e2 = 0.0_dp
      do i = 0, 20
        x = real(i, dp)/20.0_dp
        call bernstein_values(p, x, bv(1:p+1))
        call bernstein_d2(p, x, b(1:p+1), db(1:p+1), ddb(1:p+1))
        call bernstein(p, x, bg(1:p+1), dbg(1:p+1))
        same_b = same_b .and. all(b(1:p+1) == bv(1:p+1)) .and. all(b(1:p+1) == bg(1:p+1))
        same_db = same_db .and. all(db(1:p+1) == dbg(1:p+1))
        scale = max(1.0_dp, maxval(abs(ddb(1:p+1))))
        unit = unit .and. abs(sum(b(1:p+1)) - 1.0_dp) <= 1.0e-15_dp .and. &
            abs(sum(db(1:p+1))) <= 1.0e-13_dp*scale .and. abs(sum(ddb(1:p+1))) <= 1.0e-13_dp*scale
        if (i == 0 .or. i == 20) cycle
        call bernstein_d2(p, x + h, bp(1:p+1), dbp(1:p+1), ddbp(1:p+1))
        call bernstein_d2(p, x - h, bm(1:p+1), dbm(1:p+1), ddbm(1:p+1))
        e2 = max(e2, maxval(abs((dbp(1:p+1) - dbm(1:p+1))/(2*h) - ddb(1:p+1)))/scale)
      end do
      call t%true(same_b, "bernstein_d2 values = bernstein_values = bernstein")
      call t%true(same_db, "bernstein_d2 first derivatives = bernstein")
      call t%true(unit, "sum B = 1, sum B' = 0, sum B'' = 0")
      call t%close_abs(e2, 0.0_dp, 1.0e-7_dp, "B'' vs differences of B'")
    end do
    p = BEZIER_MAX_DEGREE
    call bernstein_d2(p, 0.375_dp, b, db, ddb)
    call bernstein(p, 0.375_dp, bg, dbg)
    call t%true(all(b == bg) .and. all(db == dbg), "bernstein_d2 at the highest degree")
  end subroutine case_bernstein_d2

  !> de_casteljau on Bezier points of 3 and 2 components against sums of Bernstein
  !! polynomials times the points: point, first and second derivatives for p = 0..7; the end
  !! points exactly; the optional derivatives change nothing.
  subroutine case_de_casteljau(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: pts(3, 8), b(8), db(8), ddb(8), h0(3), h1(3), h2(3), g0(3), x, e0, e1, e2
    real(dp) :: k0(2), k1(2), k2(2)
    integer :: p, i, j
    logical :: ends, alone
    do j = 1, 8
      pts(:, j) = [cos(0.7_dp*j) + 0.1_dp*j, sin(1.3_dp*j) - 0.2_dp*j, 1.0_dp + 0.05_dp*j*j]
    end do
    do p = 0, 7
      e0 = 0.0_dp
      e1 = 0.0_dp
      e2 = 0.0_dp
      alone = .true.
      do i = 0, 16
        x = real(i, dp)/16.0_dp
        call de_casteljau(p, pts(:, 1:p+1), x, h0, h1, h2)
        call de_casteljau(p, pts(:, 1:p+1), x, g0)
        alone = alone .and. all(g0 == h0)
        call bernstein_d2(p, x, b(1:p+1), db(1:p+1), ddb(1:p+1))
        e0 = max(e0, maxval(abs(h0 - matmul(pts(:, 1:p+1), b(1:p+1)))))
        e1 = max(e1, maxval(abs(h1 - matmul(pts(:, 1:p+1), db(1:p+1)))))
        e2 = max(e2, maxval(abs(h2 - matmul(pts(:, 1:p+1), ddb(1:p+1)))))
      end do
      call t%close_abs(e0, 0.0_dp, 1.0e-14_dp, "de Casteljau point = sum B_j h_j")
      call t%close_abs(e1, 0.0_dp, 1.0e-12_dp, "de Casteljau h' = sum B_j' h_j")
      call t%close_abs(e2, 0.0_dp, 1.0e-10_dp, "de Casteljau h'' = sum B_j'' h_j")
      call t%true(alone, "de Casteljau point without the derivatives")
      call de_casteljau(p, pts(:, 1:p+1), 0.0_dp, h0)
      ends = all(h0 == pts(:, 1))
      call de_casteljau(p, pts(:, 1:p+1), 1.0_dp, h0)
      ends = ends .and. all(h0 == pts(:, p+1))
      call t%true(ends, "de Casteljau end points exact")
    end do
    call de_casteljau(0, pts(:, 1:1), 0.4_dp, h0, h1, h2)
    call t%true(all(h1 == 0.0_dp) .and. all(h2 == 0.0_dp), "degree 0: zero derivatives")
    call de_casteljau(1, pts(:, 1:2), 0.4_dp, h0, h1, h2)
    call t%true(all(h1 == pts(:, 2) - pts(:, 1)) .and. all(h2 == 0.0_dp), "degree 1 derivatives")
    ! two components: the same numbers as the first two rows of three
    call de_casteljau(4, pts(1:2, 1:5), 0.3_dp, k0, k1, k2)
    call de_casteljau(4, pts(:, 1:5), 0.3_dp, h0, h1, h2)
    call t%true(all(k0 == h0(1:2)) .and. all(k1 == h1(1:2)) .and. all(k2 == h2(1:2)), &
        "de Casteljau on two components")
  end subroutine case_de_casteljau

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
