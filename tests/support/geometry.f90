!> Geometry routines that only the tests use: references the code itself does not need.
!! * `basis_funs`: the non-zero B-spline values alone (Piegl & Tiller A2.2); the code takes
!!   values and derivatives together (`ders_basis_funs`, ictus_geometry_bspline);
!! * `nurbs_curve_point`: a point of a NURBS curve (the code evaluates patches,
!!   ictus_geometry_nurbs and ictus_geometry_patch).
module ictus_test_geometry
  use ictus_core_kinds, only: dp
  use ictus_geometry_nurbs, only: nurbs_curve_basis
  implicit none
  private
  public :: basis_funs, nurbs_curve_point

contains

  !> The p+1 non-zero basis functions at `u` on span `i` (A2.2): nb(0:p) = N_{i-p..i,p}(u).
  !! @param i span from find_span; @param u parameter; @param p degree;
  !! @param knots knot vector; @param nb values (0:p)
  pure subroutine basis_funs(i, u, p, knots, nb)
    integer, intent(in) :: i, p
    real(dp), intent(in) :: u
    real(dp), intent(in) :: knots(:)
    real(dp), intent(out) :: nb(0:p)
    real(dp) :: left(p), right(p), saved, temp
    integer :: j, r
    nb(0) = 1.0_dp
    do j = 1, p
      left(j) = u - knots(i+1-j)
      right(j) = knots(i+j) - u
      saved = 0.0_dp
      do r = 0, j - 1
        temp = nb(r)/(right(r+1) + left(j-r))
        nb(r) = saved + right(r+1)*temp
        saved = left(j-r)*temp
      end do
      nb(j) = saved
    end do
  end subroutine basis_funs

  !> Point of a NURBS curve and optionally its first and second derivatives.
  !! @param n number of control points; @param p degree; @param knots (n+p+1);
  !! @param cp control points (3, n) = (x, y, w); @param u parameter; @param x point (2);
  !! @param dx dx/du (2), optional; @param ddx d2x/du2 (2), optional
  pure subroutine nurbs_curve_point(n, p, knots, cp, u, x, dx, ddx)
    integer, intent(in) :: n, p
    real(dp), intent(in) :: knots(:), cp(:,:), u
    real(dp), intent(out) :: x(2)
    real(dp), intent(out), optional :: dx(2), ddx(2)
    real(dp) :: r(0:p), dr(0:p), ddr(0:p)
    integer :: span, k
    call nurbs_curve_basis(n, p, knots, cp(3, 1:n), u, span, r, dr, ddr)
    x = 0.0_dp
    do k = 0, p
      x = x + r(k)*cp(1:2, span-p+k)
    end do
    if (present(dx)) then
      dx = 0.0_dp
      do k = 0, p
        dx = dx + dr(k)*cp(1:2, span-p+k)
      end do
    end if
    if (present(ddx)) then
      ddx = 0.0_dp
      do k = 0, p
        ddx = ddx + ddr(k)*cp(1:2, span-p+k)
      end do
    end if
  end subroutine nurbs_curve_point
end module ictus_test_geometry
