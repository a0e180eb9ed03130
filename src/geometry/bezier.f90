!> Bezier extraction of B-spline bases and Bernstein polynomials.
!!
!! Borden, Scott, Evans & Hughes, IJNME 87 (2011) 15-47, Algorithm 1: on the e-th non-empty
!! knot span the p+1 non-zero B-splines satisfy N^e(u) = C^e B(t), with B the Bernstein
!! polynomials of degree p in the local variable t in [0, 1] mapped linearly onto the span.
module ictus_geometry_bezier
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: bezier_extraction_1d, bernstein, count_spans

contains

  !> Number of non-empty knot spans of a knot vector with n functions of degree p.
  !! @param n number of basis functions; @param p degree; @param knots (n+p+1)
  pure integer function count_spans(n, p, knots) result(nel)
    integer, intent(in) :: n, p
    real(dp), intent(in) :: knots(:)
    integer :: i
    nel = 0
    do i = p + 1, n
      if (knots(i+1) > knots(i)) nel = nel + 1
    end do
  end function count_spans

  !> Extraction operators of all non-empty knot spans (Borden et al. 2011, Algorithm 1).
  !! @param n number of basis functions; @param p degree; @param knots open knot vector
  !! (n+p+1); @param nel number of non-empty spans (elements);
  !! @param c extraction operators (p+1, p+1, nel): N_{a-p+i-1}(u) = sum_j c(i, j, e) B_j(t)
  subroutine bezier_extraction_1d(n, p, knots, nel, c)
    integer, intent(in) :: n, p
    real(dp), intent(in) :: knots(:)
    integer, intent(out) :: nel
    real(dp), allocatable, intent(out) :: c(:,:,:)
    real(dp), allocatable :: cw(:,:,:)
    real(dp) :: alphas(p), numer, alpha
    integer :: m, a, b, nb, i, j, k, mult, r, s, save_
    m = n + p + 1
    nel = count_spans(n, p, knots)
    allocate(cw(p+1, p+1, nel+1))
    cw = 0.0_dp
    do i = 1, p + 1
      cw(i, i, 1) = 1.0_dp
    end do
    a = p + 1
    b = a + 1
    nb = 1
    do while (b < m)
      do i = 1, p + 1
        cw(i, i, nb+1) = 1.0_dp
      end do
      i = b
      do while (b < m)
        if (knots(b+1) /= knots(b)) exit
        b = b + 1
      end do
      mult = b - i + 1
      if (mult < p) then
        numer = knots(b) - knots(a)
        do j = p, mult + 1, -1
          alphas(j-mult) = numer/(knots(a+j) - knots(a))
        end do
        r = p - mult
        do j = 1, r
          save_ = r - j + 1
          s = mult + j
          do k = p + 1, s + 1, -1
            alpha = alphas(k-s)
            cw(:, k, nb) = alpha*cw(:, k, nb) + (1.0_dp - alpha)*cw(:, k-1, nb)
          end do
          if (b < m) then
            cw(save_:j+save_, save_, nb+1) = cw(p-j+1:p+1, p+1, nb)
          end if
        end do
      end if
      nb = nb + 1
      if (b < m) then
        a = b
        b = b + 1
      end if
    end do
    allocate(c(p+1, p+1, nel))
    c = cw(:, :, 1:nel)
  end subroutine bezier_extraction_1d

  !> Bernstein polynomials of degree p on t in [0, 1] and their derivatives d/dt.
  !! @param p degree; @param t local coordinate; @param b values (p+1),
  !! b(i) = binom(p, i-1) t^(i-1) (1-t)^(p-i+1); @param db derivatives (p+1)
  pure subroutine bernstein(p, t, b, db)
    integer, intent(in) :: p
    real(dp), intent(in) :: t
    real(dp), intent(out) :: b(p+1), db(p+1)
    real(dp) :: bl(p+1), s
    integer :: q, i
    ! de Casteljau-type recursion B_{i,q} = (1-t) B_{i,q-1} + t B_{i-1,q-1}
    bl = 0.0_dp
    bl(1) = 1.0_dp
    s = 1.0_dp - t
    do q = 1, p - 1
      do i = q + 1, 2, -1
        bl(i) = s*bl(i) + t*bl(i-1)
      end do
      bl(1) = s*bl(1)
    end do
    ! bl(1:p) now holds degree p-1 (for p >= 1)
    if (p == 0) then
      b(1) = 1.0_dp
      db(1) = 0.0_dp
      return
    end if
    b(1) = s*bl(1)
    db(1) = -real(p, dp)*bl(1)
    do i = 2, p
      b(i) = s*bl(i) + t*bl(i-1)
      db(i) = real(p, dp)*(bl(i-1) - bl(i))
    end do
    b(p+1) = t*bl(p)
    db(p+1) = real(p, dp)*bl(p)
  end subroutine bernstein
end module ictus_geometry_bezier
