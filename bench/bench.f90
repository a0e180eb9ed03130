!> ictus-bench: measures the kernels of an explicit step on the model of a deck.
!!
!!   ictus-bench deck.inp [--steps N] [--repeat R] [--stream-mb M] [--no-elem]
!!
!! Builds the model, the operators and the contact exactly as `ictus` does, then times, each
!! over N repetitions (default 50): the stiffness product alone; the whole step on the run's
!! path (fused lumped step, or predictor with the consistent-mass solve, plus contact and the
!! displacement update with the halo exchange; for a lumped mass, sweeps of several steps over
!! K where the run would keep them: with SWEEP STEPS=AUTO the bench first lets the state time
!! sweeps against single steps as a run does); the same one step at a time and, where sweeps
!! are planned, always in sweeps; and, separately, its phases (stiffness product, mass solve,
!! contact search and forces, vector updates). It also measures this machine's memory
!! bandwidth with a STREAM triad after each set of timings. The whole set is taken R times
!! (default 3) and each figure, the triad's too, is the median of its R values (the machine is
!! shared).
!! Output: one line of key=value pairs starting with BENCH (read by bench/benchmark.py);
!! times are seconds per step, mass_iter the mean conjugate-gradient iterations per
!! consistent-mass solve (0 for a lumped mass), mass_solver the consistent-mass solver taken
!! (MASS_SOLVER_*: 2 Cholesky, 4 Kronecker, ...; 0 for a lumped mass), sweep the steps per
!! pass over K on the run's path (1: single steps), sweep_plan the steps of a planned sweep
!! (1: none), t_sweep the step in sweeps (0 without a plan), tune_sweep and tune_single the
!! step in the best window of each kind that SWEEP STEPS=AUTO timed (0 when it did not),
!! sweep_kib the KiB of K the strips of the kept plan hold between a row's first and last step
!! (0 without sweeps), tune_wide the step in the best window of wide-strip sweeps (0 when
!! not timed), t_elem the element-loop internal force (INTERNAL FORCE=ELEMENT) of the same
!! model, t_geom the computation of the shape derivatives and volume weights that the element
!! loop stores (what recomputing them every step would add to t_elem; best of 3), dt the step
!! used (--no-elem: the element loop is neither set up nor timed, t_elem = t_geom = 0). The
!! time step is the deck's dt, or for dt = 0 the automatic
!! one (0.9 * 2/omega_max) as in a run. The motion starts from
!! a rough velocity field (see below). Nothing is checked, nothing is written.
program ictus_bench
  use, intrinsic :: iso_fortran_env, only: output_unit
  use ictus_core_kinds, only: dp, i8
  use ictus_core_strings, only: command_arg
  use ictus_core_errors, only: error_count, terminate, input_error
  use ictus_core_timer, only: wall_time
  use ictus_core_memory, only: alloc_stream
  use ictus_core_sort, only: sort
  use ictus_parallel_env, only: env_init, env_finalize, env_is_root, env_size, allreduce_max, &
      allreduce_sum, barrier
  use ictus_solver_model, only: model_t
  use ictus_solver_tensor_layout, only: tensor_layout_t, tensor_layout
  use ictus_solver_domain, only: domain_t, domain_init
  use ictus_solver_assemble, only: operators_t, assemble_operators
  use ictus_solver_sparse, only: bsr_product
  use ictus_solver_mass_operator, only: mass_op_t, mass_op_init, mass_solve
  use ictus_solver_explicit, only: state_t, state_init, step_predict, step_finish
  use ictus_solver_internal_force, only: force_op_t, force_op_init, force_apply, force_choice, &
      FORCE_ELEMENT, FORCE_ASSEMBLED
  use ictus_solver_force_element, only: element_force_t, element_loop_init, element_loop_geometry
  use ictus_solver_lumped_sweeps, only: lumped_sweeps_t, sweeps_plan, sweeps_window, sweeps_run
  use ictus_solver_contact_step, only: contact_step_t, contact_step_init, contact_correct
  use ictus_solver_timestep, only: omega_max_power
  use ictus_contact_contact, only: contact_t
  use ictus_io_deck_types, only: deck_t
  use ictus_io_deck_reader, only: read_deck
  use ictus_app_build_model, only: build_model
  use ictus_app_build_contact, only: build_contact
  use ictus_bench_hook, only: bench_hook_t
  implicit none
  type(deck_t) :: deck
  type(model_t), target :: model
  type(domain_t), target :: dom
  type(operators_t) :: ops
  type(mass_op_t), target :: mop
  type(tensor_layout_t) :: layout
  type(contact_t), target :: contact
  type(contact_step_t), target :: cs
  type(state_t), target :: s
  type(bench_hook_t) :: between
  type(force_op_t) :: fop, fop_el
  type(element_force_t) :: kel
  type(lumped_sweeps_t) :: ls
  real(dp), allocatable :: hist_el(:,:,:)
  character(len=:), allocatable :: path, arg
  integer, allocatable :: bad(:)
  integer :: nsteps, stream_mb, i, nbad, ierr, n, nrep, r, it0, ns0, nchunk, k, nd
  logical :: has_k
  real(dp) :: t_kmv, t_step, t_mass, t_contact, t_update, t_single, t_sweep, t_kread, t_kstep, t_elem, t_geom, tg0, dt, &
      stream_bw, bytes_kmv, mass_iter, sink
  logical, allocatable :: sync(:)
  logical :: tuned, with_elem
  real(dp), allocatable :: alpha(:), times(:,:), u_save(:,:), v_save(:,:), a_save(:,:), &
      sa(:), sb(:), sc(:), stream(:)
  real(dp) :: omega
  integer :: iters
  !> Amplitude of the rough start velocity.
  real(dp), parameter :: rough = 1.0e-3_dp
  integer(i8) :: nnzb, nrows, ncp

  call env_init()
  nsteps = 50
  nrep = 3
  sink = 0.0_dp
  stream_mb = 768
  with_elem = .true.
  i = 0
  do while (i < command_argument_count())
    i = i + 1
    arg = command_arg(i)
    select case (arg)
    case ('--steps')
      i = i + 1
      arg = command_arg(i)
      read(arg, *) nsteps
    case ('--repeat')
      i = i + 1
      arg = command_arg(i)
      read(arg, *) nrep
      nrep = max(1, nrep)
    case ('--stream-mb')
      i = i + 1
      arg = command_arg(i)
      read(arg, *) stream_mb
    case ('--no-elem')
      with_elem = .false.
    case default
      path = arg
    end select
  end do
  if (.not. allocated(path)) then
    call input_error('command line', 'usage: ictus-bench deck.inp [--steps N] [--repeat R] '// &
        '[--stream-mb M] [--no-elem]')
    call terminate(1)
  end if
  call read_deck(path, deck)
  if (error_count() == 0) call build_model(deck, model)
  if (error_count() > 0) call terminate(1)
  call domain_init(dom, model, ierr)
  call assemble_operators(model, dom, ops, bad, nbad)
  call build_contact(deck, model, contact)
  if (error_count() > 0 .or. nbad > 0) call terminate(1)
  if (ops%consistent) call tensor_layout(model, layout)
  call mass_op_init(mop, dom, ops%consistent, ops%m, ops%m_diag, model%fixed(:, dom%halo%gid), &
      model%mass_tol, model%mass_solver, passes=model%mass_passes, layout=layout)
  dt = model%dt
  ! a 3D model without the assembled K (INTERNAL FORCE=ELEMENT, or AUTO short of memory):
  ! no K u to time, omega_max from the element loop (as the driver's estimate_omega)
  has_k = allocated(ops%k%val)
  nd = model%ndm
  if (.not. dt > 0.0_dp) then
    ! automatic step as in a run: 0.9 (the default safety) of 2/omega_max
    if (has_k) then
      call omega_max_power(ops%k, mop, dom, omega, iters, 1.0e-6_dp, 1000)
    else
      call element_loop_init(kel, model, dom, ierr)
      call omega_max_power(ops%k, mop, dom, omega, iters, 1.0e-6_dp, 1000, kel)
    end if
    dt = model%safety*2.0_dp/omega
  end if
  if (contact%npairs > 0) call contact_step_init(cs, contact, model%x0, dom)
  ! the nodal damping coefficients of *DAMPING, as a run takes them (driver)
  allocate(alpha(dom%nlocal), source=0.0_dp)
  where (ops%m_pos > 0.0_dp) alpha = ops%c_diag/ops%m_pos
  call force_op_init(fop, force_choice(model, ops%k), model, dom, ops%k, mop%consistent, ierr)
  ! the element-loop internal force of the same model, timed beside K u
  if (with_elem) then
    call force_op_init(fop_el, FORCE_ELEMENT, model, dom, ops%k, mop%consistent, ierr)
    allocate(hist_el(fop_el%el%nhist, size(fop_el%el%dvol, 1), fop_el%el%nelem), source=0.0_dp)
  end if
  call state_init(s, fop, mop, dom, model%u_fixed(:, dom%halo%gid), &
      model%v0(:, dom%halo%gid), alpha, ops%m_pos, dt)
  between%cs => cs
  between%contact => contact
  between%s => s
  between%mop => mop
  between%dom => dom
  between%x0 => model%x0
  n = dom%nowned
  ! a rough start velocity (a fixed pseudo-random field of the global node numbers, all
  ! modes excited) on top of the deck's, so that the accelerations change from step to step
  ! as behind a wave front and a consistent-mass solve does the work it does in a run
  do i = 1, n
    s%v(1, i) = s%v(1, i) + rough*sin(12.9898_dp*real(dom%halo%gid(i), dp) + 1.0_dp)
    s%v(2, i) = s%v(2, i) + rough*sin(78.233_dp*real(dom%halo%gid(i), dp) + 2.0_dp)
    if (nd == 3) s%v(3, i) = s%v(3, i) + rough*sin(37.719_dp*real(dom%halo%gid(i), dp) + 3.0_dp)
  end do
  s%v(:, 1:n) = s%v(:, 1:n)*mop%free(:, 1:n)
  allocate(u_save(nd, dom%nlocal), v_save(nd, dom%nlocal), a_save(nd, dom%nlocal))
  ! sweeps of several steps over K, planned as a run plans them (contact nodes step singly)
  allocate(sync(n), source=.false.)
  if (contact%npairs > 0) then
    do i = 1, cs%ncn
      if (cs%lnode(i) > 0) sync(cs%lnode(i)) = .true.
    end do
  end if
  ! sweeps are the linear lumped stepper's: only with the assembled K (as stepper_plan)
  if (fop%kind == FORCE_ASSEMBLED) &
    call sweeps_plan(ls, s, ops%k, mop, dom, model%x0(:, dom%halo%gid(1:n)), sync, &
        model%sweep_steps)
  ! the steps of the first four timings go in `nchunk` chunks, interleaved (see time_phases);
  ! each chunk whole sweeps: the step count is rounded up to a multiple of nchunk sweeps
  nchunk = min(4, nsteps)
  k = nchunk*merge(ls%plan%nstage, 1, ls%on)
  nsteps = k*((nsteps + k - 1)/k)
  ! SWEEP STEPS=AUTO: sweeps against single steps, as at the start of a run (untimed here)
  tuned = ls%tuning
  do while (ls%tuning)
    call sweeps_window(ls, s, fop, mop, dom, between)
  end do
  call stream_alloc(stream_mb)
  allocate(times(10, nrep), stream(nrep))
  it0 = mop%total_iter
  ns0 = mop%n_solves
  do r = 1, nrep
    call time_phases(times(:, r))
    stream(r) = stream_triad()
  end do
  mass_iter = 0.0_dp
  if (mop%n_solves > ns0) mass_iter = real(mop%total_iter - it0, dp)/real(mop%n_solves - ns0, dp)
  t_kmv = median(times(1, :))
  t_step = median(times(2, :))
  t_mass = median(times(3, :))
  t_contact = median(times(4, :))
  t_update = median(times(5, :))
  t_single = median(times(6, :))
  t_sweep = median(times(7, :))
  t_kread = median(times(8, :))
  t_kstep = median(times(9, :))
  t_elem = median(times(10, :))
  t_geom = merge(huge(1.0_dp), 0.0_dp, with_elem)
  do r = 1, merge(3, 0, with_elem)
    call barrier()
    tg0 = wall_time()
    call element_loop_geometry(fop_el%el, model, ierr)
    t_geom = min(t_geom, wall_time() - tg0)
  end do
  ! the read's sums must be used, or the compiler may drop the pass
  if (sink /= sink) write(output_unit, '(a)') 'ictus-bench: K holds NaN'
  stream_bw = median(stream)
  ! bytes the stiffness product must move once: blocks (nd^2 reals + a column index), row
  ! pointers, u read, f written (0 without an assembled K)
  nnzb = 0
  if (has_k) nnzb = size(ops%k%g%col, kind=i8)
  nrows = int(n, i8)
  call allreduce_sum(nnzb)
  call allreduce_sum(nrows)
  bytes_kmv = real(nnzb, dp)*(nd*nd*8 + 4) + real(nrows, dp)*(4 + 2*nd*8)
  if (.not. has_k) bytes_kmv = 0.0_dp
  ncp = 0
  if (contact%npairs > 0) then
    do i = 1, contact%npairs
      ncp = ncp + contact%pairs(i)%npoints
    end do
  end if
  if (env_is_root()) write(output_unit, &
      '(a,i0,a,i0,a,i0,a,i0,a,i0,a,i0,a,l1,6(a,es11.5),a,i0,4(a,es11.5),2(a,i0),3(a,es11.5),' // &
      '2(a,i0),5(a,es11.5))') &
      'BENCH ranks=', env_size(), ' nel=', model%nel, ' nodes=', model%nn, ' ndm=', nd, &
      ' steps=', nsteps, &
      ' repeat=', nrep, ' consistent=', ops%consistent, ' t_kmv=', t_kmv, ' t_step=', t_step, &
      ' t_mass=', t_mass, ' t_contact=', t_contact, ' t_update=', t_update, &
      ' bytes_kmv=', bytes_kmv, ' contact_points=', ncp, ' stream=', stream_bw, &
      ' mass_iter=', mass_iter, ' dt=', dt, ' t_single=', t_single, ' sweep=', &
      merge(ls%plan%nstage, 1, ls%on .and. ls%kept), ' sweep_plan=', &
      merge(ls%plan%nstage, 1, ls%on), ' t_sweep=', t_sweep, ' tune_sweep=', &
      merge(ls%tune_time(1)/max(1, ls%plan%nstage), 0.0_dp, tuned), ' tune_single=', &
      merge(ls%tune_time(2)/max(1, ls%plan%nstage), 0.0_dp, tuned), &
      ' mass_solver=', merge(mop%solver, 0, ops%consistent), ' sweep_kib=', &
      merge(ls%bytes/1024, 0, ls%on), ' tune_wide=', &
      merge(ls%tune_time(3)/max(1, ls%plan%nstage), 0.0_dp, tuned .and. ls%has_wide), &
      ' t_kread=', t_kread, ' t_kstep=', t_kstep, ' t_elem=', t_elem, ' t_geom=', t_geom
  call env_finalize()

contains

  !> One set of timings, seconds per step (the slowest rank's): stiffness product, whole
  !! step on the run's path (sweeps where planned), mass solve, contact correction, separate
  !! vector updates, whole step one step at a time, whole step in sweeps (where planned), one
  !! pass that only reads the arrays of K (`read_k`), and with a consistent mass the product
  !! its step takes (`stiffness_product`: column order, K's upper blocks on one rank).
  subroutine time_phases(t)
    real(dp), intent(out) :: t(10)
    real(dp) :: t0
    integer :: k, m, ic
    ! 1.-2c. the stiffness product alone, the whole step on the run's path (no output), the
    ! same one step at a time, in sweeps where planned, the read of K alone and the consistent
    ! step's product: interleaved in nchunk chunks of steps, so that the slow drifts of a
    ! shared host's bandwidth fall on all alike
    t(1:2) = 0.0_dp
    t(6:10) = 0.0_dp
    m = nsteps/nchunk
    do ic = 1, nchunk
      call barrier()
      t0 = wall_time()
      do k = 1, merge(m, 0, has_k)
        call bsr_product(ops%k, n, s%u, s%f)
      end do
      t(1) = t(1) + (wall_time() - t0)
      call barrier()
      t0 = wall_time()
      if (ls%on .and. ls%kept) then
        call sweeps(m)
      else
        call single_steps(m)
      end if
      t(2) = t(2) + (wall_time() - t0)
      call barrier()
      t0 = wall_time()
      call single_steps(m)
      t(6) = t(6) + (wall_time() - t0)
      if (ls%on) then
        call barrier()
        t0 = wall_time()
        call sweeps(m)
        t(7) = t(7) + (wall_time() - t0)
      end if
      call barrier()
      t0 = wall_time()
      do k = 1, merge(m, 0, has_k)
        call read_k(size(ops%k%g%col), n, size(ops%k%val), ops%k%val, ops%k%g%col, &
            ops%k%g%row_ptr, sink)
      end do
      t(8) = t(8) + (wall_time() - t0)
      if (fop%asm%ordered) then
        ! the product the consistent step takes (column order; K's upper blocks on one rank)
        call barrier()
        t0 = wall_time()
        do k = 1, m
          call force_apply(fop, s%u, s%f, s%hist)
        end do
        t(9) = t(9) + (wall_time() - t0)
      end if
      ! the element-loop internal force of the same model (INTERNAL FORCE=ELEMENT)
      if (.not. with_elem) cycle
      call barrier()
      t0 = wall_time()
      do k = 1, m
        call force_apply(fop_el, s%u, s%f, hist_el)
      end do
      t(10) = t(10) + (wall_time() - t0)
    end do
    ! 3. phases: mass solve, contact, vector updates (the unfused passes); they run on a
    ! saved state, restored afterwards, so the runs of the whole step stay a real motion
    u_save = s%u
    v_save = s%v
    a_save = s%a
    ! the solve of the next step: f = -K u_n+1, warm-started from the last acceleration (the
    ! copy of the start value is timed with it; it is one pass over a vector)
    call force_apply(fop, s%u, s%f, s%hist)
    s%f(:, 1:n) = -s%f(:, 1:n)
    call barrier()
    t0 = wall_time()
    do k = 1, nsteps
      if (mop%consistent) s%a(:, 1:n) = a_save(:, 1:n)
      call mass_solve(mop, dom, s%f, s%a, ierr)
    end do
    t(3) = wall_time() - t0
    t(4) = 0.0_dp
    if (contact%npairs > 0) then
      s%fused = .false.
      call barrier()
      t0 = wall_time()
      do k = 1, nsteps
        call contact_correct(cs, contact, s, mop, dom, model%x0)
      end do
      t(4) = wall_time() - t0
    end if
    call barrier()
    t0 = wall_time()
    do k = 1, nsteps
      s%v(:, 1:n) = s%v(:, 1:n) + dt*s%a(:, 1:n)
      s%u(:, 1:n) = s%u(:, 1:n) + dt*s%v(:, 1:n)
    end do
    t(5) = wall_time() - t0
    s%u = u_save
    s%v = v_save
    s%a = a_save
    do k = 1, 10
      call allreduce_max(t(k))
    end do
    t = t/nsteps
  end subroutine time_phases

  !> m steps in sweeps of ls%plan%nstage (m a multiple of it), no output.
  subroutine sweeps(m)
    integer, intent(in) :: m
    integer :: k
    do k = 1, m/ls%plan%nstage
      call sweeps_run(ls, s, ops%k, mop, dom, between)
    end do
  end subroutine sweeps

  !> m steps one at a time (step_predict, contact, step_finish), no output.
  subroutine single_steps(m)
    integer, intent(in) :: m
    integer :: k
    do k = 1, m
      call step_predict(s, fop, mop, dom, .false.)
      call between%run()
      call step_finish(s, dom)
    end do
  end subroutine single_steps

  !> One pass that only reads what K u reads of K: the nb blocks (nv reals in all), their
  !! column indices and the n + 1 row pointers, summed into `total` (8 lanes for the reals,
  !! so that the pass is bound by memory, not by the additions). The rate at which one core
  !! can stream K, measured on K's own arrays: no product that reads K can beat it.
  subroutine read_k(nb, n, nv, val, col, row_ptr, total)
    integer, intent(in) :: nb, n, nv
    real(dp), intent(in) :: val(nv)
    integer, intent(in) :: col(nb), row_ptr(n + 1)
    real(dp), intent(out) :: total
    real(dp) :: acc(8)
    integer :: k, ic, m
    acc = 0.0_dp
    m = 8*(size(val)/8)
    do k = 1, m, 8
      acc = acc + val(k:k + 7)
    end do
    ic = 0
    do k = 1, nb
      ic = ic + col(k)
    end do
    do k = 1, n + 1
      ic = ic + row_ptr(k)
    end do
    total = sum(acc) + sum(val(m + 1:)) + real(ic, dp)
  end subroutine read_k

  !> Median of a few values.
  pure real(dp) function median(x)
    real(dp), intent(in) :: x(:)
    real(dp) :: y(size(x))
    integer :: b
    y = x
    call sort(y)
    b = size(y)
    median = 0.5_dp*(y((b + 1)/2) + y(b/2 + 1))
  end function median


  !> The arrays of the STREAM triad: three of mb/3 MB each, with the same huge-page advice as
  !! the solver's arrays (ictus_core_memory), so that the reference stream is not handicapped
  !! by 4 KiB pages.
  subroutine stream_alloc(mb)
    integer, intent(in) :: mb
    integer :: m
    m = max(1, mb*1024*1024/(3*8))
    call alloc_stream(sa, m, 0.0_dp)
    call alloc_stream(sb, m, 1.0_dp)
    call alloc_stream(sc, m, 2.0_dp)
  end subroutine stream_alloc

  !> STREAM triad a = b + q c on the arrays of stream_alloc, best of 10, in bytes per second
  !! (24 bytes per element, the STREAM convention). All ranks run it at once.
  function stream_triad() result(bw)
    real(dp) :: bw
    real(dp) :: t, best, q
    integer :: m, k, r
    m = size(sa)
    q = 3.0_dp
    best = huge(1.0_dp)
    do r = 1, 10
      call barrier()
      t = wall_time()
      do k = 1, m
        sa(k) = sb(k) + q*sc(k)
      end do
      t = wall_time() - t
      call allreduce_max(t)
      best = min(best, t)
      q = q + sa(m/2)*1.0e-30_dp
    end do
    bw = 24.0_dp*real(m, dp)*real(env_size(), dp)/best
  end function stream_triad
end program ictus_bench
