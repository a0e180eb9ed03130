!> ictus-bench: measures the kernels of an explicit step on the model of a deck.
!!
!!   ictus-bench deck.inp [--steps N] [--stream-mb M]
!!
!! Builds the model, the operators and the contact exactly as `ictus` does, then times, each
!! over N repetitions (default 50): the stiffness product alone; the whole step on the run's
!! path (fused lumped step, or predictor with the consistent-mass solve, plus contact and the
!! displacement update with the halo exchange); and, separately, its phases (stiffness product,
!! mass solve, contact search and forces, vector updates). It also measures this machine's
!! memory bandwidth with a STREAM triad in the same run. Output: one line of key=value pairs
!! starting with BENCH (read by scripts/benchmark.py). The time step is the deck's dt (give a
!! small one: nothing is checked, nothing is written).
program ictus_bench
  use, intrinsic :: iso_fortran_env, only: output_unit
  use ictus_core_kinds, only: dp, i8
  use ictus_core_errors, only: error_count, terminate, input_error
  use ictus_core_timer, only: wall_time
  use ictus_parallel_env, only: env_init, env_finalize, env_is_root, env_size, allreduce_max, &
      allreduce_sum, barrier
  use ictus_solver_model, only: model_t
  use ictus_solver_domain, only: domain_t, domain_init
  use ictus_solver_assemble, only: operators_t, assemble_operators
  use ictus_solver_sparse, only: bsr_matvec
  use ictus_solver_mass_operator, only: mass_op_t, mass_op_init, mass_solve
  use ictus_solver_explicit, only: state_t, state_init, step_predict, step_finish
  use ictus_solver_contact_step, only: contact_step_t, contact_step_init, contact_correct
  use ictus_contact_contact, only: contact_t
  use ictus_io_deck_types, only: deck_t
  use ictus_io_deck_reader, only: read_deck
  use ictus_app_build_model, only: build_model
  use ictus_app_build_contact, only: build_contact
  implicit none
  type(deck_t) :: deck
  type(model_t) :: model
  type(domain_t) :: dom
  type(operators_t) :: ops
  type(mass_op_t) :: mop
  type(contact_t) :: contact
  type(contact_step_t) :: cs
  type(state_t) :: s
  character(len=:), allocatable :: path, arg
  integer, allocatable :: bad(:)
  integer :: nsteps, stream_mb, i, nbad, ierr, n
  real(dp) :: t_kmv, t_step, t_mass, t_contact, t_update, t0, dt, stream_bw, bytes_kmv
  real(dp), allocatable :: alpha(:)
  integer(i8) :: nnzb, nrows, ncp

  call env_init()
  nsteps = 50
  stream_mb = 768
  i = 0
  do while (i < command_argument_count())
    i = i + 1
    arg = argument(i)
    select case (arg)
    case ('--steps')
      i = i + 1
      arg = argument(i)
      read(arg, *) nsteps
    case ('--stream-mb')
      i = i + 1
      arg = argument(i)
      read(arg, *) stream_mb
    case default
      path = arg
    end select
  end do
  if (.not. allocated(path)) then
    call input_error('command line', 'usage: ictus-bench deck.inp [--steps N] [--stream-mb M]')
    call terminate(1)
  end if
  call read_deck(path, deck)
  if (error_count() == 0) call build_model(deck, model)
  if (error_count() > 0) call terminate(1)
  call domain_init(dom, model, ierr)
  call assemble_operators(model, dom, ops, bad, nbad)
  call build_contact(deck, model, contact)
  if (error_count() > 0 .or. nbad > 0) call terminate(1)
  call mass_op_init(mop, dom, ops%consistent, ops%m, ops%m_diag, model%fixed(:, dom%halo%gid))
  dt = model%dt
  if (contact%npairs > 0) call contact_step_init(cs, contact, model%x0, dom)
  allocate(alpha(dom%nlocal), source=0.0_dp)
  call state_init(s, ops%k, mop, dom, model%u_fixed(:, dom%halo%gid), &
      model%v0(:, dom%halo%gid), alpha, ops%m_pos, dt)
  n = dom%nowned

  ! 1. the stiffness product alone
  call barrier()
  t0 = wall_time()
  do i = 1, nsteps
    call bsr_matvec(n, ops%k%g%row_ptr, ops%k%g%col, ops%k%val, s%u, s%f)
  end do
  t_kmv = wall_time() - t0
  ! 2. the whole step on the run's path (no output)
  call barrier()
  t0 = wall_time()
  do i = 1, nsteps
    call step_predict(s, ops%k, mop, dom, .false.)
    if (contact%npairs > 0) call contact_correct(cs, contact, s, mop, dom, model%x0)
    call step_finish(s, dom)
  end do
  t_step = wall_time() - t0
  ! 3. phases: mass solve, contact, vector updates (the unfused passes)
  s%f(:, 1:n) = -s%f(:, 1:n)
  call barrier()
  t0 = wall_time()
  do i = 1, nsteps
    call mass_solve(mop, dom, s%f, s%a, ierr)
  end do
  t_mass = wall_time() - t0
  t_contact = 0.0_dp
  if (contact%npairs > 0) then
    s%fused = .false.
    call barrier()
    t0 = wall_time()
    do i = 1, nsteps
      call contact_correct(cs, contact, s, mop, dom, model%x0)
    end do
    t_contact = wall_time() - t0
  end if
  call barrier()
  t0 = wall_time()
  do i = 1, nsteps
    s%v(:, 1:n) = s%v(:, 1:n) + dt*s%a(:, 1:n)
    s%u(:, 1:n) = s%u(:, 1:n) + dt*s%v(:, 1:n)
  end do
  t_update = wall_time() - t0
  call allreduce_max(t_kmv)
  call allreduce_max(t_step)
  call allreduce_max(t_mass)
  call allreduce_max(t_contact)
  call allreduce_max(t_update)
  ! bytes the stiffness product must move once: blocks (4 reals + a column index), row
  ! pointers, u read, f written
  nnzb = size(ops%k%g%col, kind=i8)
  nrows = int(n, i8)
  call allreduce_sum(nnzb)
  call allreduce_sum(nrows)
  bytes_kmv = real(nnzb, dp)*(4*8 + 4) + real(nrows, dp)*(4 + 2*8 + 2*8)
  ncp = 0
  if (contact%npairs > 0) then
    do i = 1, contact%npairs
      ncp = ncp + contact%pairs(i)%npoints
    end do
  end if
  stream_bw = stream_triad(stream_mb)
  if (env_is_root()) write(output_unit, '(a,i0,a,i0,a,i0,a,i0,a,l1,6(a,es12.5),a,i0,a,es12.5)') &
      'BENCH ranks=', env_size(), ' nel=', model%nel, ' nodes=', model%nn, ' steps=', nsteps, &
      ' consistent=', ops%consistent, ' t_kmv=', t_kmv/nsteps, ' t_step=', t_step/nsteps, &
      ' t_mass=', t_mass/nsteps, ' t_contact=', t_contact/nsteps, ' t_update=', &
      t_update/nsteps, ' bytes_kmv=', bytes_kmv, ' contact_points=', ncp, ' stream=', stream_bw
  call env_finalize()

contains

  function argument(k) result(a)
    integer, intent(in) :: k
    character(len=:), allocatable :: a
    integer :: length
    call get_command_argument(k, length=length)
    allocate(character(len=length) :: a)
    call get_command_argument(k, a)
  end function argument

  !> STREAM triad a = b + q c on three arrays of mb/3 MB each, best of 10, in bytes per second
  !! (24 bytes per element, the STREAM convention). All ranks run it at once.
  function stream_triad(mb) result(bw)
    integer, intent(in) :: mb
    real(dp) :: bw
    real(dp), allocatable :: a(:), b(:), c(:)
    real(dp) :: t, best, q
    integer :: n, k, r
    n = max(1, mb*1024*1024/(3*8))
    allocate(a(n), b(n), c(n))
    a = 0.0_dp
    b = 1.0_dp
    c = 2.0_dp
    q = 3.0_dp
    best = huge(1.0_dp)
    do r = 1, 10
      call barrier()
      t = wall_time()
      do k = 1, n
        a(k) = b(k) + q*c(k)
      end do
      t = wall_time() - t
      call allreduce_max(t)
      best = min(best, t)
      q = q + a(n/2)*1.0e-30_dp
    end do
    bw = 24.0_dp*real(n, dp)*real(env_size(), dp)/best
  end function stream_triad
end program ictus_bench
