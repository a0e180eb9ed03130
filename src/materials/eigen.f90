!> Eigenvalues and eigenvectors of a symmetric 3 x 3 matrix by cyclic Jacobi rotations (for
!! the logarithmic strains of the finite-strain laws).
module ictus_materials_eigen
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: sym_eigen3

contains

  !> a = V diag(lam) V^T: lam(3) the eigenvalues, v(3, 3) the eigenvectors in columns.
  !! Rotations until the off-diagonal part is below 1e-15 of the matrix (at most 50 sweeps).
  pure subroutine sym_eigen3(a, lam, v)
    real(dp), intent(in) :: a(3, 3)
    real(dp), intent(out) :: lam(3), v(3, 3)
    real(dp) :: m(3, 3), off, scale, theta, t, c, s, tau, apq
    integer :: sweep, p, q, r, k
    if (a(1, 3) == 0.0_dp .and. a(2, 3) == 0.0_dp .and. a(3, 1) == 0.0_dp .and. &
        a(3, 2) == 0.0_dp) then
      ! a block-diagonal matrix (plane strain): one rotation diagonalises the 2 x 2 block
      call eigen_block(a, lam, v)
      return
    end if
    m = a
    v = 0.0_dp
    do k = 1, 3
      v(k, k) = 1.0_dp
    end do
    scale = max(maxval(abs(a)), tiny(1.0_dp))
    do sweep = 1, 50
      off = abs(m(1, 2)) + abs(m(1, 3)) + abs(m(2, 3))
      if (off <= 1.0e-15_dp*scale) exit
      do p = 1, 2
        do q = p + 1, 3
          apq = m(p, q)
          if (abs(apq) <= 1.0e-300_dp) cycle
          theta = (m(q, q) - m(p, p))/(2.0_dp*apq)
          t = sign(1.0_dp, theta)/(abs(theta) + sqrt(theta*theta + 1.0_dp))
          c = 1.0_dp/sqrt(t*t + 1.0_dp)
          s = t*c
          tau = s/(1.0_dp + c)
          m(p, p) = m(p, p) - t*apq
          m(q, q) = m(q, q) + t*apq
          m(p, q) = 0.0_dp
          m(q, p) = 0.0_dp
          do r = 1, 3
            if (r == p .or. r == q) cycle
            call rotate(m(r, p), m(r, q), s, tau)
            m(p, r) = m(r, p)
            m(q, r) = m(r, q)
          end do
          do r = 1, 3
            call rotate(v(r, p), v(r, q), s, tau)
          end do
        end do
      end do
    end do
    lam = [m(1, 1), m(2, 2), m(3, 3)]
  end subroutine sym_eigen3

  !> sym_eigen3 of a matrix whose (1:2, 3) and (3, 1:2) parts are zero: the Jacobi rotation
  !! that zeroes a(1, 2) (the same formulas as the cyclic sweeps) and lam(3) = a(3, 3).
  pure subroutine eigen_block(a, lam, v)
    real(dp), intent(in) :: a(3, 3)
    real(dp), intent(out) :: lam(3), v(3, 3)
    real(dp) :: theta, t, c, s, apq
    v = 0.0_dp
    v(3, 3) = 1.0_dp
    apq = a(1, 2)
    lam = [a(1, 1), a(2, 2), a(3, 3)]
    if (abs(apq) <= 1.0e-15_dp*max(maxval(abs(a)), tiny(1.0_dp))) then
      v(1, 1) = 1.0_dp
      v(2, 2) = 1.0_dp
      return
    end if
    theta = (a(2, 2) - a(1, 1))/(2.0_dp*apq)
    t = sign(1.0_dp, theta)/(abs(theta) + sqrt(theta*theta + 1.0_dp))
    c = 1.0_dp/sqrt(t*t + 1.0_dp)
    s = t*c
    lam(1) = a(1, 1) - t*apq
    lam(2) = a(2, 2) + t*apq
    v(1, 1) = c
    v(2, 1) = -s
    v(1, 2) = s
    v(2, 2) = c
  end subroutine eigen_block

  pure subroutine rotate(x, y, s, tau)
    real(dp), intent(inout) :: x, y
    real(dp), intent(in) :: s, tau
    real(dp) :: g, h
    g = x
    h = y
    x = g - s*(h + g*tau)
    y = h + s*(g - h*tau)
  end subroutine rotate
end module ictus_materials_eigen
