!> Critical time step: the largest natural frequency omega_max of M^-1 K by power iteration
!! (physics.md §4.2). Central differences are stable for dt <= 2/omega_max.
module ictus_solver_timestep
  use ictus_core_kinds, only: dp, i8
  use ictus_solver_sparse, only: bsr_t, bsr_matvec
  use ictus_solver_mass_operator, only: mass_op_t, mass_solve, mass_apply
  implicit none
  private
  public :: omega_max_power

contains

  !> omega_max^2 = largest eigenvalue of K x = lambda M x on the free dofs, by power iteration
  !! on M^-1 K with the Rayleigh quotient as estimate (it approaches the eigenvalue from
  !! below). The start vector is a fixed pseudo-random field of the node ids, so the result
  !! does not depend on the partition. Stops when the estimate changes by less than `rtol`
  !! (relative) over 10 iterations, or after `max_iter` iterations.
  subroutine omega_max_power(k, mop, node_id, omega, iters, rtol, max_iter)
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(inout) :: mop
    integer, intent(in) :: node_id(:)
    real(dp), intent(out) :: omega
    integer, intent(out) :: iters
    real(dp), intent(in) :: rtol
    integer, intent(in) :: max_iter
    real(dp), allocatable :: x(:,:), kx(:,:), mx(:,:), y(:,:)
    real(dp) :: lam, lam_old, xkx, xmx, nrm
    integer :: n, i, it, ierr
    n = k%g%n
    allocate(x(2, n), kx(2, n), mx(2, n), y(2, n))
    do i = 1, n
      x(1, i) = hash_uniform(2*node_id(i) - 1)
      x(2, i) = hash_uniform(2*node_id(i))
    end do
    x = x*mop%free
    lam_old = 0.0_dp
    lam = 0.0_dp
    y = 0.0_dp
    iters = 0
    do it = 1, max_iter
      nrm = sqrt(sum(x**2))
      if (nrm == 0.0_dp) exit
      x = x/nrm
      call bsr_matvec(n, k%g%row_ptr, k%g%col, k%val, x, kx)
      kx = kx*mop%free
      call mass_apply(mop, x, mx)
      xkx = sum(x*kx)
      xmx = sum(x*mx)
      lam = xkx/xmx
      iters = it
      if (mod(it, 10) == 0) then
        if (abs(lam - lam_old) <= rtol*abs(lam)) exit
        lam_old = lam
      end if
      ! start the mass solve from its converged value lam*x
      y = lam*x
      call mass_solve(mop, kx, y, ierr)
      x = y
    end do
    omega = sqrt(max(lam, 0.0_dp))
  end subroutine omega_max_power

  !> A deterministic pseudo-random number in [-1, 1) from an integer seed.
  pure real(dp) function hash_uniform(seed)
    integer, intent(in) :: seed
    integer(i8), parameter :: modulus = 2147483647_i8
    integer(i8) :: h
    integer :: r
    ! three rounds of the Park-Miller generator (products stay below 2^47)
    h = mod(int(abs(seed), i8) + 1_i8, modulus)
    do r = 1, 3
      h = mod(h*48271_i8, modulus)
    end do
    hash_uniform = 2.0_dp*real(h, dp)/real(modulus, dp) - 1.0_dp
  end function hash_uniform
end module ictus_solver_timestep
