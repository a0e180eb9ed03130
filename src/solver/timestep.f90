!> Critical time step: the largest natural frequency omega_max of M^-1 K by power iteration
!! (doc/theory.md §7). Central differences are stable for dt <= 2/omega_max.
module ictus_solver_timestep
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use ictus_core_kinds, only: dp, i8
  use ictus_core_ticker, only: ticker_t, ticker_start
  use ictus_parallel_repro, only: repro_dot
  use ictus_parallel_halo, only: halo_exchange
  use ictus_solver_sparse, only: bsr_t, bsr_matvec, bsr_product
  use ictus_solver_mass_operator, only: mass_op_t, mass_solve, mass_apply, MASS_SOLVER_CORRECTOR
  use ictus_solver_domain, only: domain_t
  use ictus_solver_force_element, only: element_force_t, element_loop_stiffness
  implicit none
  private
  public :: omega_max_power

contains

  !> omega_max^2 = largest eigenvalue of K x = lambda M x on the free dofs.
  !!
  !! The power iteration on M^-1 K, accelerated by Lanczos: the power iteration's k-th Rayleigh
  !! quotient comes from the Krylov space span{x, M^-1 K x, ..., (M^-1 K)^k x}; Lanczos (with
  !! the M inner product, in which M^-1 K is symmetric) finds the largest Ritz value of that
  !! same space, which is never below the power iteration's estimate and converges much faster
  !! when the top of the spectrum is clustered (a 1D chain; doc/theory.md §7). Both approach
  !! omega_max^2 from below. Without re-orthogonalisation,
  !! rounding only adds copies of converged Ritz values, never a larger one.
  !! The start vector is a fixed pseudo-random field of the global node indices and all sums
  !! are reproducible, so the result is the same bits on any number of ranks. Stops when the
  !! largest Ritz value changes by less than `rtol` (relative) over 5 steps, or after
  !! `max_iter` steps; `iters` is the number of operator applications. `omega` is 0 when no dof
  !! is free (or the masses are 0), and NaN when the iteration meets a value out of the range of doubles (masses
  !! near 1e-308, stiffnesses near 1e308): then it stops at once, and the caller must refuse
  !! the step, given or automatic.
  !!
  !! The corrector (MASS_SOLVER_CORRECTOR) applies an approximate inverse Mk^-1, not M^-1, and
  !! only Mk^-1 is at hand, so the M inner product is not the right one: there Lanczos runs
  !! on the forces, on K Mk^-1 (same eigenvalues as Mk^-1 K) in the Mk^-1 inner product, in
  !! which K Mk^-1 is symmetric (`lanczos_inverse`).
  !!
  !! K is the assembled stiffness `k` (2 x 2 or 3 x 3 blocks), or with `kel` (a 3D model whose
  !! stiffness is not assembled) the element loop's product of the reference tangents
  !! (`element_loop_stiffness`).
  subroutine omega_max_power(k, mop, dom, omega, iters, rtol, max_iter, kel)
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    real(dp), intent(out) :: omega
    integer, intent(out) :: iters
    real(dp), intent(in) :: rtol
    integer, intent(in) :: max_iter
    type(element_force_t), intent(inout), optional :: kel
    real(dp), allocatable :: q(:,:), q_old(:,:), w(:,:), kq(:,:), mw(:,:), alpha(:), beta(:)
    real(dp) :: nrm, lam, lam_old
    integer :: n, j, i, ierr, nd
    type(ticker_t) :: tk
    if (mop%consistent .and. mop%solver == MASS_SOLVER_CORRECTOR) then
      call lanczos_inverse(k, mop, dom, omega, iters, rtol, max_iter)
      return
    end if
    n = mop%nn
    nd = size(mop%free, 1)
    ! q and w carry ghost values: the consistent-mass product reads them
    allocate(q(nd, mop%nlocal), q_old(nd, n), w(nd, mop%nlocal), kq(nd, n), mw(nd, n))
    q = 0.0_dp
    allocate(alpha(max_iter), beta(max_iter))
    call start_vector(mop, dom, q)
    call halo_exchange(dom%halo, q)
    call mass_apply(mop, q, mw)
    nrm = sqrt(repro_dot(n, q, mw, mop%nglobal))
    lam = 0.0_dp
    lam_old = 0.0_dp
    iters = 0
    if (nrm == 0.0_dp) then
      omega = 0.0_dp
      return
    end if
    q(:, 1:n) = q(:, 1:n)/nrm
    q_old = 0.0_dp
    w = 0.0_dp
    call ticker_start(tk, 'omega_max estimate', unit='iterations')
    do j = 1, max_iter
      call tk%tick(j - 1, 0)
      iters = j
      ! w = M^-1 K q_j, alpha_j = q_j . K q_j (the M inner product of w and q_j)
      call halo_exchange(dom%halo, q)
      if (present(kel)) then
        call element_loop_stiffness(kel, n, q, kq)
      else
        call bsr_product(k, n, q, kq)
      end if
      kq = kq*mop%free(:, 1:n)
      alpha(j) = repro_dot(n, q, kq, mop%nglobal)
      ! start the mass solve from alpha q, its value for an eigenvector (a lumped solve
      ! sets every entry without a start)
      if (mop%consistent) w(:, 1:n) = alpha(j)*q(:, 1:n)
      call mass_solve(mop, dom, kq, w, ierr)
      ! w - alpha_j q_j - beta_{j-1} q_{j-1} in one pass (the same operations per entry)
      if (j > 1) then
        do i = 1, n
          w(:, i) = (w(:, i) - alpha(j)*q(:, i)) - beta(j - 1)*q_old(:, i)
        end do
      else
        w(:, 1:n) = w(:, 1:n) - alpha(j)*q(:, 1:n)
      end if
      call halo_exchange(dom%halo, w)
      call mass_apply(mop, w, mw)
      beta(j) = sqrt(max(repro_dot(n, w, mw, mop%nglobal), 0.0_dp))
      if (converged(j, alpha, beta, rtol, max_iter, lam, lam_old)) exit
      do i = 1, n
        q_old(:, i) = q(:, i)
        q(:, i) = w(:, i)/beta(j)
      end do
    end do
    omega = omega_of(lam)
  end subroutine omega_max_power

  !> omega_max by Lanczos on A = K Mk^-1 in the Mk^-1 inner product (see omega_max_power):
  !! q_j are forces with z_j = Mk^-1 q_j, alpha_j = z_j.K z_j, w = K z_j - alpha_j q_j -
  !! beta_{j-1} q_{j-1}, y = Mk^-1 w, beta_j = sqrt(w.y); one mass solve per step. Same start
  !! vector, stopping rule and reproducible sums as omega_max_power.
  subroutine lanczos_inverse(k, mop, dom, omega, iters, rtol, max_iter)
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    real(dp), intent(out) :: omega
    integer, intent(out) :: iters
    real(dp), intent(in) :: rtol
    integer, intent(in) :: max_iter
    real(dp), allocatable :: q(:,:), q_old(:,:), z(:,:), w(:,:), kz(:,:), alpha(:), beta(:)
    real(dp) :: nrm, lam, lam_old
    integer :: n, j, ierr
    type(ticker_t) :: tk
    n = mop%nn
    ! z carries ghost values: K reads them
    allocate(q(2, n), q_old(2, n), z(2, mop%nlocal), w(2, n), kz(2, n))
    ! (the corrector is a 2D solver: nd = 2)
    allocate(alpha(max_iter), beta(max_iter))
    z = 0.0_dp
    call start_vector(mop, dom, q)
    call mass_solve(mop, dom, q, z, ierr)
    nrm = sqrt(max(repro_dot(n, q, z, mop%nglobal), 0.0_dp))
    lam = 0.0_dp
    lam_old = 0.0_dp
    iters = 0
    if (nrm == 0.0_dp) then
      omega = 0.0_dp
      return
    end if
    q = q/nrm
    z(:, 1:n) = z(:, 1:n)/nrm
    q_old = 0.0_dp
    call ticker_start(tk, 'omega_max estimate', unit='iterations')
    do j = 1, max_iter
      call tk%tick(j - 1, 0)
      iters = j
      call halo_exchange(dom%halo, z)
      call bsr_matvec(n, k%g%row_ptr, k%g%col, k%val, z, kz)
      kz = kz*mop%free(:, 1:n)
      alpha(j) = repro_dot(n, z, kz, mop%nglobal)
      w = kz - alpha(j)*q
      if (j > 1) w = w - beta(j - 1)*q_old
      q_old = q
      call mass_solve(mop, dom, w, z, ierr)
      beta(j) = sqrt(max(repro_dot(n, w, z, mop%nglobal), 0.0_dp))
      if (converged(j, alpha, beta, rtol, max_iter, lam, lam_old)) exit
      q = w/beta(j)
      z(:, 1:n) = z(:, 1:n)/beta(j)
    end do
    omega = omega_of(lam)
  end subroutine lanczos_inverse

  !> sqrt(lam) of the largest Ritz value; NaN when lam is not a positive finite number. With
  !! a free dof K_ii > 0 (E > 0) and lambda_max >= K_ii/M_ii > 0, so lam <= 0 means that the
  !! sums left the range of doubles (K q overflowed, or the masses underflowed).
  real(dp) function omega_of(lam) result(omega)
    real(dp), intent(in) :: lam
    if (lam > 0.0_dp .and. lam <= huge(1.0_dp)) then
      omega = sqrt(lam)
    else
      omega = ieee_value(1.0_dp, ieee_quiet_nan)
    end if
  end function omega_of

  !> The start vector: a fixed pseudo-random field of the global dof numbers (nd (g - 1) + c
  !! for component c of node g, nd = 2 or 3) on the free owned dofs (0 elsewhere among the
  !! first nn columns).
  subroutine start_vector(mop, dom, q)
    type(mass_op_t), intent(in) :: mop
    type(domain_t), intent(in) :: dom
    real(dp), intent(inout) :: q(:,:)
    integer :: i, g, c, nd
    nd = size(q, 1)
    do i = 1, mop%nn
      g = dom%halo%gid(i)
      do c = 1, nd
        q(c, i) = hash_uniform(nd*(g - 1) + c)*mop%free(c, i)
      end do
    end do
  end subroutine start_vector

  !> The stopping rule after Lanczos step j: every 5 steps (and at the last one, or at a
  !! breakdown beta_j ~ 0) the largest Ritz value lam is updated; true at a breakdown or when
  !! lam changed by less than rtol (relative) since the previous update (from step 10 on), and
  !! at once when alpha_j, beta_j or lam is not a finite number (lam is then NaN: the
  !! iteration has left the range of doubles and would never converge).
  logical function converged(j, alpha, beta, rtol, max_iter, lam, lam_old) result(done)
    integer, intent(in) :: j, max_iter
    real(dp), intent(in) :: alpha(:), beta(:), rtol
    real(dp), intent(inout) :: lam, lam_old
    logical :: breakdown
    done = .true.
    if (.not. (abs(alpha(j)) <= huge(1.0_dp) .and. beta(j) <= huge(1.0_dp))) then
      lam = ieee_value(1.0_dp, ieee_quiet_nan)
      return
    end if
    done = .false.
    breakdown = beta(j) <= 1.0e-14_dp*abs(alpha(j))
    if (.not. (mod(j, 5) == 0 .or. j == max_iter .or. breakdown)) return
    lam = largest_ritz_value(j, alpha, beta)
    if (.not. abs(lam) <= huge(1.0_dp)) then
      done = .true.
      return
    end if
    done = breakdown .or. (j >= 10 .and. abs(lam - lam_old) <= rtol*abs(lam))
    if (.not. done) lam_old = lam
  end function converged

  !> Largest eigenvalue of the Lanczos tridiagonal matrix T_j (diagonal alpha, off-diagonal
  !! beta), by LAPACK dstev.
  function largest_ritz_value(j, alpha, beta) result(lam)
    integer, intent(in) :: j
    real(dp), intent(in) :: alpha(:), beta(:)
    real(dp) :: lam
    real(dp) :: d(j), e(max(j - 1, 1)), z(1, 1), work(1)
    integer :: info
    d = alpha(1:j)
    if (j > 1) e(1:j - 1) = beta(1:j - 1)
    call dstev('N', j, d, e, z, 1, work, info)
    lam = maxval(d)
    if (info /= 0) lam = ieee_value(1.0_dp, ieee_quiet_nan)
  end function largest_ritz_value

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
