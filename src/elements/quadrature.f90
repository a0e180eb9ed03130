!> Gauss-Legendre quadrature on [-1, 1] and its tensor products on [-1, 1]^2 and [-1, 1]^3.
module ictus_elements_quadrature
  use ictus_core_kinds, only: dp, pi
  implicit none
  private
  public :: gauss_legendre, gauss_rule_2d, gauss_rule_3d

contains

  !> n-point Gauss-Legendre rule on [-1, 1], exact for polynomials of degree 2n - 1.
  !! The points are the roots of P_n, found by Newton's method from the Tricomi estimate and
  !! made exactly antisymmetric; they are returned in ascending order.
  !! n: number of points (1..10 are tested; any n >= 1 works); xi(n): points; w(n): weights.
  pure subroutine gauss_legendre(n, xi, w)
    integer, intent(in) :: n
    real(dp), intent(out) :: xi(n), w(n)
    integer :: i, it
    real(dp) :: x, p, dp_dx, dx
    do i = 1, (n + 1)/2
      ! i-th largest root
      x = cos(pi*(real(i, dp) - 0.25_dp)/(real(n, dp) + 0.5_dp))
      do it = 1, 100
        call legendre_p(n, x, p, dp_dx)
        dx = p/dp_dx
        x = x - dx
        if (abs(dx) <= 1.0e-16_dp) exit
      end do
      call legendre_p(n, x, p, dp_dx)
      xi(n + 1 - i) = x
      xi(i) = -x
      w(i) = 2.0_dp/((1.0_dp - x*x)*dp_dx*dp_dx)
      w(n + 1 - i) = w(i)
    end do
    if (mod(n, 2) == 1) xi((n + 1)/2) = 0.0_dp
  end subroutine gauss_legendre

  !> Legendre polynomial P_n(x) and its derivative by the three-term recurrence.
  pure subroutine legendre_p(n, x, p, dp_dx)
    integer, intent(in) :: n
    real(dp), intent(in) :: x
    real(dp), intent(out) :: p, dp_dx
    real(dp) :: p0, p1
    integer :: k
    p0 = 1.0_dp
    p1 = x
    if (n == 0) then
      p = 1.0_dp
      dp_dx = 0.0_dp
      return
    end if
    do k = 2, n
      p = (real(2*k - 1, dp)*x*p1 - real(k - 1, dp)*p0)/real(k, dp)
      p0 = p1
      p1 = p
    end do
    p = p1
    ! P_n' = n (x P_n - P_{n-1})/(x^2 - 1), valid away from x = +-1 (roots are interior)
    dp_dx = real(n, dp)*(x*p1 - p0)/(x*x - 1.0_dp)
  end subroutine legendre_p

  !> Tensor-product Gauss rule with n1 points in direction 1 (xi) and n2 in direction 2 (eta).
  !! xi(2, n1*n2): points, direction 1 running fastest; w(n1*n2): weights (sum 4).
  pure subroutine gauss_rule_2d(n1, n2, xi, w)
    integer, intent(in) :: n1, n2
    real(dp), intent(out) :: xi(2, n1*n2), w(n1*n2)
    real(dp) :: x1(n1), w1(n1), x2(n2), w2(n2)
    integer :: i, j, k
    call gauss_legendre(n1, x1, w1)
    call gauss_legendre(n2, x2, w2)
    do j = 1, n2
      do i = 1, n1
        k = i + (j - 1)*n1
        xi(1, k) = x1(i)
        xi(2, k) = x2(j)
        w(k) = w1(i)*w2(j)
      end do
    end do
  end subroutine gauss_rule_2d

  !> Tensor-product Gauss rule with n1, n2, n3 points in directions 1 (xi), 2 (eta), 3 (zeta).
  !! xi(3, n1*n2*n3): points, direction 1 running fastest, then 2; w(n1*n2*n3): weights (sum 8).
  pure subroutine gauss_rule_3d(n1, n2, n3, xi, w)
    integer, intent(in) :: n1, n2, n3
    real(dp), intent(out) :: xi(3, n1*n2*n3), w(n1*n2*n3)
    real(dp) :: x2(2, n1*n2), w2(n1*n2), x3(n3), w3(n3)
    integer :: k, l
    call gauss_rule_2d(n1, n2, x2, w2)
    call gauss_legendre(n3, x3, w3)
    do l = 1, n3
      k = (l - 1)*n1*n2
      xi(1:2, k + 1:k + n1*n2) = x2
      xi(3, k + 1:k + n1*n2) = x3(l)
      w(k + 1:k + n1*n2) = w2*w3(l)
    end do
  end subroutine gauss_rule_3d
end module ictus_elements_quadrature
