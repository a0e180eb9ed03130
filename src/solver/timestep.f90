!> Critical time step: the largest natural frequency omega_max of M^-1 K by power iteration
!! (physics.md §4.2). Central differences are stable for dt <= 2/omega_max.
module ictus_solver_timestep
  use ictus_core_kinds, only: dp, i8
  use ictus_parallel_repro, only: repro_dot
  use ictus_parallel_halo, only: halo_exchange
  use ictus_solver_sparse, only: bsr_t, bsr_matvec
  use ictus_solver_mass_operator, only: mass_op_t, mass_solve, mass_apply
  use ictus_solver_domain, only: domain_t
  implicit none
  private
  public :: omega_max_power

contains

  !> omega_max^2 = largest eigenvalue of K x = lambda M x on the free dofs, by power iteration
  !! on M^-1 K with the Rayleigh quotient as estimate (it approaches the eigenvalue from
  !! below). The start vector is a fixed pseudo-random field of the global node indices and
  !! all sums are reproducible, so the result is the same bits on any number of ranks.
  !! Stops when the estimate changes by less than `rtol` (relative) over 10 iterations, or
  !! after `max_iter` iterations.
  subroutine omega_max_power(k, mop, dom, omega, iters, rtol, max_iter)
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    real(dp), intent(out) :: omega
    integer, intent(out) :: iters
    real(dp), intent(in) :: rtol
    integer, intent(in) :: max_iter
    real(dp), allocatable :: x(:,:), kx(:,:), mx(:,:), y(:,:)
    real(dp) :: lam, lam_old, xkx, xmx, nrm
    integer :: n, i, it, ierr, g
    n = mop%nn
    allocate(x(2, mop%nlocal), kx(2, n), mx(2, n), y(2, n))
    do i = 1, n
      g = dom%halo%gid(i)
      x(1, i) = hash_uniform(2*g - 1)
      x(2, i) = hash_uniform(2*g)
    end do
    x(:, 1:n) = x(:, 1:n)*mop%free(:, 1:n)
    lam_old = 0.0_dp
    lam = 0.0_dp
    iters = 0
    do it = 1, max_iter
      nrm = sqrt(repro_dot(n, x, x, mop%nglobal))
      if (nrm == 0.0_dp) exit
      x(:, 1:n) = x(:, 1:n)/nrm
      call halo_exchange(dom%halo, x)
      call bsr_matvec(n, k%g%row_ptr, k%g%col, k%val, x, kx)
      kx = kx*mop%free(:, 1:n)
      call mass_apply(mop, x, mx)
      xkx = repro_dot(n, x, kx, mop%nglobal)
      xmx = repro_dot(n, x, mx, mop%nglobal)
      lam = xkx/xmx
      iters = it
      if (mod(it, 10) == 0) then
        if (abs(lam - lam_old) <= rtol*abs(lam)) exit
        lam_old = lam
      end if
      ! start the mass solve from its converged value lam*x
      y = lam*x(:, 1:n)
      call mass_solve(mop, dom, kx, y, ierr)
      x(:, 1:n) = y
    end do
    omega = sqrt(max(lam, 0.0_dp))
  end subroutine omega_max_power

  !> A deterministic pseudo-random number in [-1, 1) from an integer seed: the seed scrambled
  !! by rounds of a xorshift generator (bit operations only, no overflow), so neighbouring
  !! seeds give unrelated values and the start vector has a component along every mode.
  pure real(dp) function hash_uniform(seed)
    integer, intent(in) :: seed
    integer(i8) :: x
    integer :: r
    x = int(seed, i8)*2654435761_i8 + 360673760222240851_i8
    do r = 1, 4
      x = ieor(x, ishft(x, 13))
      x = ieor(x, ishft(x, -7))
      x = ieor(x, ishft(x, 17))
    end do
    ! the top 53 bits as a fraction in [0, 1)
    hash_uniform = 2.0_dp*real(ishft(x, -11), dp)/2.0_dp**53 - 1.0_dp
  end function hash_uniform
end module ictus_solver_timestep
