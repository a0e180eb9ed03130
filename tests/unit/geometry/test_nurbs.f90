!> Unit tests of ictus_geometry_nurbs: quarter/half circle values (doc/iga.md §10.2, §10.3),
!! rational basis properties and derivatives, surface derivatives.
program test_nurbs
  use ictus_core_kinds, only: dp, pi
  use ictus_geometry_nurbs, only: nurbs_curve_basis, nurbs_surface_basis, nurbs_surface_point
  use ictus_test_geometry, only: nurbs_curve_point
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  real(dp), parameter :: rr = 4.0_dp, s2 = sqrt(2.0_dp)/2.0_dp

  call t%start("geometry/nurbs")
  call case_quarter_values(t)
  call case_circle_radius(t)
  call case_basis_properties(t)
  call case_surface(t)
  call t%finish()

contains

  !> Quarter circle R = 4 of doc/contact.md §3, doc/iga.md §10.2.
  subroutine quarter(knots, cp)
    real(dp), intent(out) :: knots(6), cp(3, 3)
    knots = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    cp(:, 1) = [rr, 0.0_dp, 1.0_dp]
    cp(:, 2) = [rr, rr, s2]
    cp(:, 3) = [0.0_dp, rr, 1.0_dp]
  end subroutine quarter

  !> Half circle R = 4 of doc/iga.md §10.3 (two quarter arcs, double knot at 1/2).
  subroutine half(knots, cp)
    real(dp), intent(out) :: knots(8), cp(3, 5)
    knots = [0.0_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.5_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    cp(:, 1) = [rr, 0.0_dp, 1.0_dp]
    cp(:, 2) = [rr, rr, s2]
    cp(:, 3) = [0.0_dp, rr, 1.0_dp]
    cp(:, 4) = [-rr, rr, s2]
    cp(:, 5) = [-rr, 0.0_dp, 1.0_dp]
  end subroutine half

  !> doc/iga.md §10.2 test values at xi = 0.25 and 0.5 (given to 6 digits).
  subroutine case_quarter_values(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: knots(6), cp(3, 3), r(0:2), dr(0:2), ddr(0:2), x(2), dx(2)
    real(dp), parameter :: tol = 1.0e-6_dp
    integer :: span
    call quarter(knots, cp)
    call nurbs_curve_basis(3, 2, knots, cp(3, :), 0.25_dp, span, r, dr, ddr)
    call t%equal_int(span, 3, "quarter span")
    call t%close_abs(r(0), 0.631905_dp, tol, "R1(0.25)")
    call t%close_abs(r(1), 0.297883_dp, tol, "R2(0.25)")
    call t%close_abs(r(2), 0.070212_dp, tol, "R3(0.25)")
    call t%close_abs(dr(0), -1.477163_dp, tol, "R1'(0.25)")
    call t%close_abs(dr(1), 0.892368_dp, tol, "R2'(0.25)")
    call t%close_abs(dr(2), 0.584796_dp, tol, "R3'(0.25)")
    call nurbs_curve_point(3, 2, knots, cp, 0.25_dp, x, dx)
    call t%close_abs(x(1), 3.719153_dp, tol, "x(0.25)")
    call t%close_abs(x(2), 1.472379_dp, tol, "y(0.25)")
    call t%close_abs(dx(1), -2.339182_dp, tol, "x'(0.25)")
    call t%close_abs(dx(2), 5.908654_dp, tol, "y'(0.25)")
    call t%close_abs(norm2(x), rr, 1.0e-12_dp, "|x(0.25)| = 4")
    call t%close_abs(atan2(x(2), x(1))*180.0_dp/pi, 21.598_dp, 1.0e-3_dp, "angle(0.25)")
    call nurbs_curve_basis(3, 2, knots, cp(3, :), 0.5_dp, span, r, dr, ddr)
    call t%close_abs(r(0), 0.292893_dp, tol, "R1(0.5)")
    call t%close_abs(r(1), 0.414214_dp, tol, "R2(0.5)")
    call t%close_abs(r(2), 0.292893_dp, tol, "R3(0.5)")
    call nurbs_curve_point(3, 2, knots, cp, 0.5_dp, x)
    call t%close_abs(x(1), 2.828427_dp, tol, "x(0.5)")
    call t%close_abs(x(2), 2.828427_dp, tol, "y(0.5)")
    ! tangent orthogonal to the radius, end points interpolated
    call nurbs_curve_point(3, 2, knots, cp, 0.25_dp, x, dx)
    call t%close_abs(dot_product(x, dx), 0.0_dp, 1.0e-12_dp, "tangent perpendicular")
    call nurbs_curve_point(3, 2, knots, cp, 1.0_dp, x)
    call t%close_abs(x(1), 0.0_dp, 1.0e-15_dp, "end point x")
    call t%close_abs(x(2), rr, 1.0e-15_dp, "end point y")
  end subroutine case_quarter_values

  !> |x| = 4 to 1e-12 on the quarter and the half circle (1001 points each), and
  !! x . x' = 0, |x'|^2 + x . x'' = 0 (derivatives of |x|^2 = const).
  subroutine case_circle_radius(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: kq(6), cq(3, 3), kh(8), ch(3, 5), x(2), dx(2), ddx(2), u, eq, eh, et, ec
    integer :: i
    call quarter(kq, cq)
    call half(kh, ch)
    eq = 0.0_dp
    eh = 0.0_dp
    et = 0.0_dp
    ec = 0.0_dp
    do i = 0, 1000
      u = real(i, dp)/1000.0_dp
      call nurbs_curve_point(3, 2, kq, cq, u, x)
      eq = max(eq, abs(norm2(x) - rr))
      call nurbs_curve_point(5, 2, kh, ch, u, x, dx, ddx)
      eh = max(eh, abs(norm2(x) - rr))
      et = max(et, abs(dot_product(x, dx))/norm2(dx))
      ec = max(ec, abs(dot_product(dx, dx) + dot_product(x, ddx))/dot_product(dx, dx))
    end do
    call t%close_abs(eq, 0.0_dp, 1.0e-12_dp, "quarter circle radius")
    call t%close_abs(eh, 0.0_dp, 1.0e-12_dp, "half circle radius")
    call t%close_abs(et, 0.0_dp, 1.0e-12_dp, "half circle x.x' = 0")
    call t%close_abs(ec, 0.0_dp, 1.0e-12_dp, "half circle |x'|^2 + x.x'' = 0")
    call nurbs_curve_point(5, 2, kh, ch, 0.5_dp, x)
    call t%close_abs(x(1), 0.0_dp, 1.0e-15_dp, "half circle top x")
    call t%close_abs(x(2), rr, 1.0e-15_dp, "half circle top y")
  end subroutine case_circle_radius

  !> Partition of unity, non-negativity and derivatives vs central differences of R, x.
  subroutine case_basis_properties(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: h = 1.0e-5_dp
    real(dp) :: kh(8), ch(3, 5), r(0:2), dr(0:2), ddr(0:2), rp(0:2), drp(0:2), ddrp(0:2), &
        rm(0:2), drm(0:2), ddrm(0:2), u, pu, neg, e1, e2, ex1, ex2, sd
    real(dp) :: x(2), dx(2), ddx(2), xp(2), dxp(2), xm(2), dxm(2)
    integer :: i, span, sp, sm
    call half(kh, ch)
    pu = 0.0_dp
    neg = 0.0_dp
    e1 = 0.0_dp
    e2 = 0.0_dp
    ex1 = 0.0_dp
    ex2 = 0.0_dp
    sd = 0.0_dp
    do i = 0, 200
      u = 0.001_dp + 0.998_dp*real(i, dp)/200.0_dp
      if (abs(u - 0.5_dp) < 2*h) cycle
      call nurbs_curve_basis(5, 2, kh, ch(3, :), u, span, r, dr, ddr)
      call nurbs_curve_basis(5, 2, kh, ch(3, :), u + h, sp, rp, drp, ddrp)
      call nurbs_curve_basis(5, 2, kh, ch(3, :), u - h, sm, rm, drm, ddrm)
      call t%true(sp == span .and. sm == span, "same span for differences")
      pu = max(pu, abs(sum(r) - 1.0_dp))
      neg = min(neg, minval(r))
      sd = max(sd, abs(sum(dr)), abs(sum(ddr)))
      e1 = max(e1, maxval(abs((rp - rm)/(2*h) - dr)))
      e2 = max(e2, maxval(abs((drp - drm)/(2*h) - ddr)))
      call nurbs_curve_point(5, 2, kh, ch, u, x, dx, ddx)
      call nurbs_curve_point(5, 2, kh, ch, u + h, xp, dxp)
      call nurbs_curve_point(5, 2, kh, ch, u - h, xm, dxm)
      ex1 = max(ex1, maxval(abs((xp - xm)/(2*h) - dx))/norm2(dx))
      ex2 = max(ex2, maxval(abs((dxp - dxm)/(2*h) - ddx))/norm2(ddx))
    end do
    call t%close_abs(pu, 0.0_dp, 1.0e-14_dp, "NURBS partition of unity")
    call t%true(neg >= 0.0_dp, "NURBS non-negative")
    call t%close_abs(sd, 0.0_dp, 1.0e-11_dp, "NURBS derivatives sum to zero")
    call t%close_abs(e1, 0.0_dp, 1.0e-6_dp, "R' vs finite differences")
    call t%close_abs(e2, 0.0_dp, 1.0e-5_dp, "R'' vs finite differences")
    call t%close_abs(ex1, 0.0_dp, 1.0e-8_dp, "x' vs finite differences")
    call t%close_abs(ex2, 0.0_dp, 1.0e-8_dp, "x'' vs finite differences")
  end subroutine case_basis_properties

  !> Half-disc patch of doc/iga.md §10.4: surface basis properties, derivatives vs central
  !! differences, derivatives at A = (0, -R): dx/dxi = (0, 8), dx/deta = (8 sin 22.5°, 0).
  subroutine case_surface(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: h = 1.0e-6_dp
    real(dp) :: k(6), cp(3, 9), x(2), du(2), dv(2), xp(2), xm(2), yp(2), ym(2), u, v
    real(dp) :: r(9), ru(9), rv(9), eu, ev, pu
    integer :: idx(9), i, j
    k = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    call half_disc(cp)
    eu = 0.0_dp
    ev = 0.0_dp
    pu = 0.0_dp
    do j = 1, 9
      do i = 1, 9
        u = 0.1_dp*real(i, dp)
        v = 0.1_dp*real(j, dp)
        call nurbs_surface_point(3, 3, 2, 2, k, k, cp, u, v, x, du, dv)
        call nurbs_surface_point(3, 3, 2, 2, k, k, cp, u + h, v, xp)
        call nurbs_surface_point(3, 3, 2, 2, k, k, cp, u - h, v, xm)
        call nurbs_surface_point(3, 3, 2, 2, k, k, cp, u, v + h, yp)
        call nurbs_surface_point(3, 3, 2, 2, k, k, cp, u, v - h, ym)
        eu = max(eu, maxval(abs((xp - xm)/(2*h) - du)))
        ev = max(ev, maxval(abs((yp - ym)/(2*h) - dv)))
        call nurbs_surface_basis(3, 3, 2, 2, k, k, cp(3, :), u, v, idx, r, ru, rv)
        pu = max(pu, abs(sum(r) - 1.0_dp), abs(sum(ru)), abs(sum(rv)))
        call t%true(all(r >= 0.0_dp), "surface basis non-negative")
      end do
    end do
    call t%equal_int(idx(5), 5, "surface basis index of P[1][1]")
    call t%close_abs(pu, 0.0_dp, 1.0e-13_dp, "surface partition of unity")
    call t%close_abs(eu, 0.0_dp, 1.0e-7_dp, "dx/du vs finite differences")
    call t%close_abs(ev, 0.0_dp, 1.0e-7_dp, "dx/dv vs finite differences")
    call nurbs_surface_point(3, 3, 2, 2, k, k, cp, 0.0_dp, 0.0_dp, x, du, dv)
    call t%close_abs(x(1), 0.0_dp, 1.0e-15_dp, "A x")
    call t%close_abs(x(2), -rr, 1.0e-15_dp, "A y")
    call t%close_abs(du(1), 0.0_dp, 1.0e-14_dp, "A dx/dxi x")
    call t%close_abs(du(2), 8.0_dp, 1.0e-14_dp, "A dx/dxi y")
    call t%close_abs(dv(1), 8.0_dp*sin(pi/8.0_dp), 1.0e-14_dp, "A dx/deta x")
    call t%close_abs(dv(1), 3.06_dp, 0.005_dp, "A dx/deta x = 3.06..")
    call t%close_abs(dv(2), 0.0_dp, 1.0e-14_dp, "A dx/deta y")
  end subroutine case_surface

  !> Control points of the half-disc patch (doc/iga.md §10.4), P[i][j] -> cp(:, 1+i+3j).
  subroutine half_disc(cp)
    real(dp), intent(out) :: cp(3, 9)
    real(dp) :: c, tn
    c = cos(pi/8.0_dp)
    tn = tan(pi/8.0_dp)
    cp(:, 1) = [0.0_dp, -rr, 1.0_dp]
    cp(:, 2) = [0.0_dp, 0.0_dp, 1.0_dp]
    cp(:, 3) = [0.0_dp, rr, 1.0_dp]
    cp(:, 4) = [rr*tn, -rr, c]
    cp(:, 5) = [rr/2.0_dp, 0.0_dp, 1.0_dp]
    cp(:, 6) = [rr*tn, rr, c]
    cp(:, 7) = [rr*s2, -rr*s2, 1.0_dp]
    cp(:, 8) = [2.0_dp*rr*s2, 0.0_dp, s2]
    cp(:, 9) = [rr*s2, rr*s2, 1.0_dp]
  end subroutine half_disc
end program test_nurbs
