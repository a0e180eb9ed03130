!> NURBS curves and surfaces in the plane: rational basis, points and derivatives.
!!
!! Control points are stored as cp(3, :) = (x, y, w) with the weight NOT multiplied in; for a
!! surface the direction-1 index runs fastest (cp(:, i1 + (i2-1)*n1)). Formulas of
!! doc/iga.md §10.2: R_A = w_A N_A / W, W = sum w_B N_B, R'_A = w_A (N'_A W - N_A W')/W^2.
module ictus_geometry_nurbs
  use ictus_core_kinds, only: dp
  use ictus_geometry_bspline, only: find_span, ders_basis_funs
  implicit none
  private
  public :: nurbs_curve_basis, nurbs_surface_basis, nurbs_surface_point

contains

  !> Rational basis of a NURBS curve at `u` with first and second derivatives.
  !! Only the p+1 functions that can be non-zero are returned: r(k) = R_A, A = span-p+k.
  !! @param n number of control points; @param p degree; @param knots (n+p+1);
  !! @param w weights (n); @param u parameter; @param span knot span (find_span, 1-based);
  !! @param r R_A (0:p); @param dr dR_A/du (0:p); @param ddr d2R_A/du2 (0:p)
  pure subroutine nurbs_curve_basis(n, p, knots, w, u, span, r, dr, ddr)
    integer, intent(in) :: n, p
    real(dp), intent(in) :: knots(:), w(:), u
    integer, intent(out) :: span
    real(dp), intent(out) :: r(0:p), dr(0:p), ddr(0:p)
    real(dp) :: ders(0:2, 0:p), wl(0:p), ww, dw, ddw
    integer :: k
    span = find_span(n, p, u, knots)
    call ders_basis_funs(span, u, p, 2, knots, ders)
    wl = w(span-p:span)
    ww = sum(wl*ders(0, :))
    dw = sum(wl*ders(1, :))
    ddw = sum(wl*ders(2, :))
    do k = 0, p
      r(k) = wl(k)*ders(0, k)/ww
      dr(k) = wl(k)*(ders(1, k)*ww - ders(0, k)*dw)/ww**2
      ddr(k) = wl(k)*(ders(2, k)/ww - 2.0_dp*ders(1, k)*dw/ww**2 - ders(0, k)*ddw/ww**2 &
          + 2.0_dp*ders(0, k)*dw**2/ww**3)
    end do
  end subroutine nurbs_curve_basis

  !> Rational basis of a NURBS surface at (u, v) with first derivatives.
  !! The (p1+1)(p2+1) possibly non-zero functions are returned, local index
  !! k = k1 + k2*(p1+1) + 1 (direction 1 fastest), global control point
  !! idx(k) = (s1-p1+k1) + (s2-p2+k2-1)*n1.
  !! @param n1, n2 control points per direction; @param p1, p2 degrees; @param k1, k2 knot
  !! vectors; @param w weights (n1*n2); @param u, v parameters; @param idx control points
  !! ((p1+1)*(p2+1)); @param r R; @param drdu dR/du; @param drdv dR/dv (all (p1+1)*(p2+1))
  pure subroutine nurbs_surface_basis(n1, n2, p1, p2, k1, k2, w, u, v, idx, r, drdu, drdv)
    integer, intent(in) :: n1, n2, p1, p2
    real(dp), intent(in) :: k1(:), k2(:), w(:), u, v
    integer, intent(out) :: idx((p1+1)*(p2+1))
    real(dp), intent(out) :: r((p1+1)*(p2+1)), drdu((p1+1)*(p2+1)), drdv((p1+1)*(p2+1))
    real(dp) :: d1(0:1, 0:p1), d2(0:1, 0:p2), ww, dwu, dwv, nn, nu, nv
    integer :: s1, s2, a1, a2, k
    s1 = find_span(n1, p1, u, k1)
    s2 = find_span(n2, p2, v, k2)
    call ders_basis_funs(s1, u, p1, 1, k1, d1)
    call ders_basis_funs(s2, v, p2, 1, k2, d2)
    ww = 0.0_dp
    dwu = 0.0_dp
    dwv = 0.0_dp
    k = 0
    do a2 = 0, p2
      do a1 = 0, p1
        k = k + 1
        idx(k) = (s1 - p1 + a1) + (s2 - p2 + a2 - 1)*n1
        r(k) = w(idx(k))*d1(0, a1)*d2(0, a2)
        drdu(k) = w(idx(k))*d1(1, a1)*d2(0, a2)
        drdv(k) = w(idx(k))*d1(0, a1)*d2(1, a2)
        ww = ww + r(k)
        dwu = dwu + drdu(k)
        dwv = dwv + drdv(k)
      end do
    end do
    do k = 1, size(r)
      nn = r(k)
      nu = drdu(k)
      nv = drdv(k)
      r(k) = nn/ww
      drdu(k) = (nu*ww - nn*dwu)/ww**2
      drdv(k) = (nv*ww - nn*dwv)/ww**2
    end do
  end subroutine nurbs_surface_basis

  !> Point of a NURBS surface and optionally its parameter derivatives.
  !! @param n1, n2 control points per direction; @param p1, p2 degrees; @param k1, k2 knot
  !! vectors; @param cp control points (3, n1*n2), direction 1 fastest; @param u, v
  !! parameters; @param x point (2); @param dxdu, dxdv derivatives (2), optional
  pure subroutine nurbs_surface_point(n1, n2, p1, p2, k1, k2, cp, u, v, x, dxdu, dxdv)
    integer, intent(in) :: n1, n2, p1, p2
    real(dp), intent(in) :: k1(:), k2(:), cp(:,:), u, v
    real(dp), intent(out) :: x(2)
    real(dp), intent(out), optional :: dxdu(2), dxdv(2)
    integer :: idx((p1+1)*(p2+1)), k
    real(dp) :: r((p1+1)*(p2+1)), ru((p1+1)*(p2+1)), rv((p1+1)*(p2+1))
    call nurbs_surface_basis(n1, n2, p1, p2, k1, k2, cp(3, 1:n1*n2), u, v, idx, r, ru, rv)
    x = 0.0_dp
    do k = 1, size(idx)
      x = x + r(k)*cp(1:2, idx(k))
    end do
    if (present(dxdu)) then
      dxdu = 0.0_dp
      do k = 1, size(idx)
        dxdu = dxdu + ru(k)*cp(1:2, idx(k))
      end do
    end if
    if (present(dxdv)) then
      dxdv = 0.0_dp
      do k = 1, size(idx)
        dxdv = dxdv + rv(k)*cp(1:2, idx(k))
      end do
    end if
  end subroutine nurbs_surface_point
end module ictus_geometry_nurbs
