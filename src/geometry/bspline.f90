!> B-spline basis functions: knot span search, values and derivatives.
!!
!! Piegl & Tiller, The NURBS Book, 2nd ed., algorithms A2.1 and A2.3, written for 1-based
!! knot vectors `knots(1:n+p+1)` with `n` basis functions of degree `p`. The span index `i`
!! returned by `find_span` satisfies knots(i) <= u < knots(i+1) and p+1 <= i <= n; the
!! non-zero basis functions on that span are N_{i-p}, ..., N_i (1-based function numbers).
!! A2.2, the values alone, is a reference of the tests (tests/support/geometry.f90).
module ictus_geometry_bspline
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: find_span, ders_basis_funs

contains

  !> Knot span of parameter `u` (A2.1, 1-based): knots(i) <= u < knots(i+1), p+1 <= i <= n.
  !! `u` at or beyond the last knot returns n, `u` at or before the first returns p+1.
  !! @param n number of basis functions; @param p degree; @param knots knot vector (n+p+1)
  pure integer function find_span(n, p, u, knots) result(span)
    integer, intent(in) :: n, p
    real(dp), intent(in) :: u
    real(dp), intent(in) :: knots(:)
    integer :: low, high, mid
    if (u >= knots(n+1)) then
      span = n
      return
    end if
    if (u <= knots(p+1)) then
      ! u at the first knot: the first non-empty span (skip repeated knots)
      span = p + 1
      do while (span < n .and. knots(span+1) <= u)
        span = span + 1
      end do
      return
    end if
    low = p + 1
    high = n + 1
    mid = (low + high)/2
    do while (u < knots(mid) .or. u >= knots(mid+1))
      if (u < knots(mid)) then
        high = mid
      else
        low = mid
      end if
      mid = (low + high)/2
    end do
    span = mid
  end function find_span

  !> Non-zero basis functions and their derivatives up to order `nd` (A2.3):
  !! ders(k, j) = d^k N_{i-p+j,p} / du^k at `u`, k = 0..nd, j = 0..p (zero for k > p).
  !! @param i span from find_span; @param u parameter; @param p degree; @param nd highest
  !! derivative order; @param knots knot vector; @param ders (0:nd, 0:p)
  pure subroutine ders_basis_funs(i, u, p, nd, knots, ders)
    integer, intent(in) :: i, p, nd
    real(dp), intent(in) :: u
    real(dp), intent(in) :: knots(:)
    real(dp), intent(out) :: ders(0:nd, 0:p)
    real(dp) :: ndu(0:p, 0:p), a(0:1, 0:p), left(p), right(p), saved, temp, d
    integer :: j, r, k, s1, s2, rk, pk, j1, j2, du
    ndu(0, 0) = 1.0_dp
    do j = 1, p
      left(j) = u - knots(i+1-j)
      right(j) = knots(i+j) - u
      saved = 0.0_dp
      do r = 0, j - 1
        ! lower triangle: knot differences; upper triangle: basis functions
        ndu(j, r) = right(r+1) + left(j-r)
        temp = ndu(r, j-1)/ndu(j, r)
        ndu(r, j) = saved + right(r+1)*temp
        saved = left(j-r)*temp
      end do
      ndu(j, j) = saved
    end do
    ders = 0.0_dp
    do j = 0, p
      ders(0, j) = ndu(j, p)
    end do
    du = min(nd, p)
    do r = 0, p
      s1 = 0
      s2 = 1
      a(0, 0) = 1.0_dp
      do k = 1, du
        d = 0.0_dp
        rk = r - k
        pk = p - k
        if (r >= k) then
          a(s2, 0) = a(s1, 0)/ndu(pk+1, rk)
          d = a(s2, 0)*ndu(rk, pk)
        end if
        if (rk >= -1) then
          j1 = 1
        else
          j1 = -rk
        end if
        if (r - 1 <= pk) then
          j2 = k - 1
        else
          j2 = p - r
        end if
        do j = j1, j2
          a(s2, j) = (a(s1, j) - a(s1, j-1))/ndu(pk+1, rk+j)
          d = d + a(s2, j)*ndu(rk+j, pk)
        end do
        if (r <= pk) then
          a(s2, k) = -a(s1, k-1)/ndu(pk+1, r)
          d = d + a(s2, k)*ndu(r, pk)
        end if
        ders(k, r) = d
        j = s1
        s1 = s2
        s2 = j
      end do
    end do
    r = p
    do k = 1, du
      ders(k, :) = ders(k, :)*real(r, dp)
      r = r*(p - k)
    end do
  end subroutine ders_basis_funs
end module ictus_geometry_bspline
