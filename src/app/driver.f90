!> The run: deck -> model -> operators -> time step -> time loop with output.
!!
!! Order of a run: read and check the deck (exit 1 on any problem, before anything is
!! written), build the model, assemble K and M once, estimate omega_max and choose or check
!! dt, open the results file, loop over the steps writing history and field records, close.
module ictus_app_driver
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use ictus_core_sort, only: sort
  use ictus_core_kinds, only: dp, i8
  use ictus_core_memory, only: available_memory
  use ictus_core_errors, only: input_error, error_count, fatal, terminate, warning
  use ictus_core_logger, only: log_info, log_verbose
  use ictus_core_strings, only: str, join_ids
  use ictus_core_timer, only: wall_time
  use ictus_parallel_halo, only: halo_exchange
  use ictus_parallel_env, only: allreduce_or, env_size, allreduce_max, allgather_int, &
      allgatherv_real, env_node_size, allreduce_sum
  use ictus_elements_types, only: etype_name, ETYPE_Q8, ETYPE_IGA
  use ictus_mass_types, only: mass_name, MASS_ROW_SUM
  use ictus_solver_model, only: model_t
  use ictus_solver_tensor_layout, only: tensor_layout_t, tensor_layout
  use ictus_solver_assemble, only: operators_t, assemble_operators, check_jacobians, &
      mass_overflow_element
  use ictus_solver_domain, only: domain_t, domain_init
  use ictus_solver_mass_operator, only: mass_op_t, mass_op_init, mass_min_entry, &
      mass_steps_fused, mass_op_report, MASS_SOLVER_CG, MASS_SOLVER_CORRECTOR, &
      MASS_SOLVER_KRONECKER
  use ictus_solver_timestep, only: omega_max_power
  use ictus_solver_explicit, only: state_t, state_init, step_predict, step_finish, &
      state_plan_sweep, step_window
  use ictus_solver_contact_step, only: contact_step_t, contact_step_init, contact_correct, &
      contact_ratio, contact_bipenalty_init
  use ictus_contact_contact, only: contact_t, contact_failures
  use ictus_app_build_contact, only: build_contact
  use ictus_io_deck_types, only: deck_t
  use ictus_io_deck_reader, only: read_deck
  use ictus_io_deck_echo, only: deck_echo
  use ictus_io_results, only: results_t, results_open, results_history, results_field, &
      results_close, history_record_t, results_contact, results_reopen, results_flush, &
      results_records
  use ictus_io_iga_viz, only: iga_viz_count, iga_viz_samples
  use ictus_io_checkpoint, only: checkpoint_t, checkpoint_write, checkpoint_read
  use ictus_app_build_model, only: build_model, element_where
  implicit none
  private
  public :: run_options_t, driver_run

  !> What the command line asked for.
  type :: run_options_t
    character(len=:), allocatable :: deck_path
    character(len=:), allocatable :: out_path
    !> Read, build and check the model, print the summary and stop.
    logical :: check_only = .false.
    !> Continue from this checkpoint.
    character(len=:), allocatable :: restart_path
    !> Stop with a checkpoint after this many seconds of the time loop (0: no limit).
    real(dp) :: wall_time = 0.0_dp
  end type run_options_t

  !> Exit status of a run-time failure, and of a run stopped at its wall-time limit.
  integer, parameter :: EXIT_RUNTIME = 2, EXIT_WALL_TIME = 3

contains

  !> Runs the deck named in `opt`. Returns normally only on success.
  subroutine driver_run(opt)
    type(run_options_t), intent(in) :: opt
    type(deck_t) :: deck
    type(model_t) :: model
    type(domain_t) :: dom
    type(operators_t) :: ops
    type(mass_op_t) :: mop
    type(tensor_layout_t) :: layout
    type(contact_t) :: contact
    type(contact_step_t) :: cs
    real(dp) :: omega, dt_crit, dt, r1, dt_pen
    integer :: iters, ierr
    character(len=256) :: where
    call read_deck(opt%deck_path, deck)
    if (error_count() > 0) call input_failure()
    call build_model(deck, model)
    if (error_count() > 0) call input_failure()
    call domain_init(dom, model, ierr)
    if (ierr /= 0) call fatal('partitioning', 'METIS could not partition the mesh into '// &
        str(env_size())//' parts')
    call check_operators(model, dom, ops)
    if (error_count() > 0) call input_failure()
    call build_contact(deck, model, contact)
    if (error_count() > 0) call input_failure()
    if (ops%consistent .and. model%mass_solver == MASS_SOLVER_CORRECTOR) then
      r1 = mass_min_entry(ops%m, dom%nowned)
      if (r1 < 0.0_dp) call input_error(deck%step%dynamic_where, '*DYNAMIC, EXPLICIT: '// &
          'MASS SOLVER=CORRECTOR needs a consistent mass without negative entries (its row '// &
          'sums precondition the passes), but this one has entries down to '//str(r1)// &
          ': the consistent mass of Q8 and Q9 elements has negative entries. Use '// &
          'MASS SOLVER=CHOLESKY or CG, or TYPE=CONSISTENT only on patches and Q4 elements')
      if (error_count() > 0) call input_failure()
    end if
    if (ops%consistent) call tensor_layout(model, layout)
    call mass_op_init(mop, dom, ops%consistent, ops%m, ops%m_diag, &
        model%fixed(:, dom%halo%gid), model%mass_tol, model%mass_solver, ierr, &
        model%mass_passes, layout)
    if (ierr /= 0 .and. model%mass_solver == MASS_SOLVER_KRONECKER) then
      call input_error(deck%step%dynamic_where, '*DYNAMIC, EXPLICIT: '//mop%setup_msg// &
          '; it needs NURBS patches with separable geometry and weights '// &
          'or rectangular grids of Q4, Q8 or Q9 elements with sides parallel to the axes; '// &
          'use MASS SOLVER=AUTO (the default) or CHOLESKY')
      call input_failure()
    else if (ierr /= 0) then
      call fatal('consistent mass', mop%setup_msg, 1)
    end if
    call omega_max_power(ops%k, mop, dom, omega, iters, 1.0e-12_dp, 5000)
    dt_crit = huge(1.0_dp)
    if (omega > 0.0_dp) dt_crit = 2.0_dp/omega
    if (.not. omega <= huge(1.0_dp)) then
      ! NaN: the iteration met masses or stiffnesses out of the range of doubles; no step,
      ! given or automatic, can be checked against a stable limit
      call input_error(deck%step%dynamic_where, '*DYNAMIC, EXPLICIT: the stable time '// &
          'step cannot be computed: the frequency iteration left the range of doubles '// &
          '(omega_max = '//str(omega)//'; stiffness and mass out of range, e.g. E = 1e300 '// &
          'or element masses near 1e-308); rescale the units')
      call input_failure()
    end if
    call log_info('stability: omega_max = '//str(omega)//' (Lanczos-accelerated power '// &
        'iteration, '//str(iters)//' steps), critical time step 2/omega_max = '//str(dt_crit))
    ! the penalty limit of the predictor-corrector scheme (physics.md §4.4-4.5): the contact
    ! ratio r = dt^2 eps (l_s/m_s + l_m/m_m) grows like dt^2; automatic steps keep r <= 1/2
    dt_pen = huge(1.0_dp)
    if (contact%npairs > 0) then
      call contact_step_init(cs, contact, model%x0, dom)
      ! bipenalty pairs: eps_m from omega_max of the model without contact and the step (the
      ! given one, or for automatic steps 2/omega_max, so that the penalty limit never binds)
      call contact_bipenalty_init(cs, contact, mop, omega, merge(model%dt, dt_crit, &
          model%dt > 0.0_dp))
      if (error_count() > 0) call input_failure()
      call contact_ratio(cs, contact, model%x0, 0.0_dp*model%x0(:, dom%halo%gid), ops%m_pos, &
          1.0_dp, r1, where)
      if (r1 > 0.0_dp) dt_pen = sqrt(0.5_dp/r1)
      call log_info('contact: penalty step limit (r <= 1/2) = '//str(dt_pen)//' at '// &
          trim(where))
    end if
    if (model%dt > 0.0_dp) then
      dt = model%dt
      if (dt > dt_crit) then
        call input_error(deck%step%where, '*DYNAMIC, EXPLICIT: the time step '//str(dt)// &
            ' exceeds the stable limit 2/omega_max = '//str(dt_crit)//' (omega_max = '// &
            str(omega)//'); use a smaller step, or 0 for automatic')
        call input_failure()
      end if
    else
      if (.not. omega > 0.0_dp) then
        call input_error(deck%step%dynamic_where, '*DYNAMIC, EXPLICIT: no automatic time '// &
            'step: omega_max = 0, no dof is free; give dt')
        call input_failure()
      end if
      dt = model%safety*min(dt_crit, dt_pen)
      if (dt_pen < dt_crit) then
        call log_info('automatic time step: '//str(model%safety)//' * penalty limit = '// &
            str(dt))
      else
        call log_info('automatic time step: '//str(model%safety)//' * 2/omega_max = '//str(dt))
      end if
    end if
    if (.not. model%t_end/dt < real(huge(1) - 1, dp)) then
      call input_error(deck%step%dynamic_where, '*DYNAMIC, EXPLICIT: t_end / dt = '// &
          str(model%t_end/dt)//' steps (dt = '//str(dt)//'); at most '//str(huge(1) - 1)// &
          ' steps (a shorter t_end, or a larger dt)')
      call input_failure()
    end if
    if (contact%npairs > 0) then
      call contact_ratio(cs, contact, model%x0, 0.0_dp*model%x0(:, dom%halo%gid), ops%m_pos, &
          dt, r1, where)
      call log_info('contact: stability ratio r = dt^2 eps (l_s/m_s + l_m/m_m) = '//str(r1, 4)// &
          ' at the start ('//trim(where)//')')
      if (r1 > 0.5_dp) call warning('contact', 'the stability ratio r = '//str(r1, 4)// &
          ' exceeds 1/2 at '//trim(where)//' (the margin ictus asks for; physics.md §4.4 '// &
          'puts the limit of the predictor-corrector penalty at r = 1)')
    end if
    call check_viz_memory(deck, model, dom)
    call log_summary(model, dom, ops, mop, dt)
    if (opt%check_only) then
      call log_info('check: the deck is valid; no results written')
      return
    end if
    call log_info('processed deck:')
    call log_info(deck_echo(deck, .false.))
    call time_loop(opt, deck, model, dom, ops, mop, contact, cs, dt, omega)
  end subroutine driver_run

  !> The viewing samples of the NURBS elements (src/io/iga_viz.f90) must fit in memory: while
  !! the results file is opened every rank forms the coordinates of all sample points and
  !! the cells (16 bytes each), and for the run it keeps, per sample of the elements it
  !! evaluates, a row number and the displacement and velocity (36 bytes); that times the
  !! ranks of a node against the memory available. Refused at *OUTPUT, FIELD (or *STEP)
  !! before anything is written, with the same decision on all ranks.
  subroutine check_viz_memory(deck, model, dom)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    integer(i8) :: ns, nc, mine, avail
    real(dp) :: need, mem(2)
    character(len=:), allocatable :: where, s_text, card
    integer :: e
    if (model%npatch == 0) return
    call iga_viz_count(model, model%viz_samples, ns, nc)
    mine = 0
    do e = 1, model%nel
      if (model%etype(e) /= ETYPE_IGA) cycle
      if (dom%owner(model%conn(1, e)) /= dom%rank) cycle
      mine = mine + int(iga_viz_samples(model, model%patch(e), model%viz_samples), i8)**2
    end do
    need = 16.0_dp*real(ns + nc, dp) + 36.0_dp*real(mine, dp)
    mem(1) = need*env_node_size()
    mem(2) = -huge(1.0_dp)
    avail = available_memory()
    if (avail >= 0) mem(2) = -real(avail, dp)
    call allreduce_max(mem)
    where = trim(deck%step%field_where)
    card = '*OUTPUT, FIELD'
    if (len(where) == 0) then
      where = trim(deck%step%where)
      card = '*STEP: the default field output (*OUTPUT, FIELD)'
    end if
    s_text = 'SAMPLES='//str(model%viz_samples)
    if (model%viz_samples == 0) s_text = 'the default SAMPLES = 2 p_max + 1 per direction'
    if (ns > huge(1) - 1) then
      call input_error(where, card//': the NURBS elements would have '//str(ns)// &
          ' viewing sample points ('//s_text//'); at most '//str(huge(1) - 1)// &
          ' can be numbered; use *OUTPUT, FIELD, SAMPLES=2 (4 points per element)')
      call input_failure()
    else if (mem(2) > -huge(1.0_dp) .and. mem(1) > -mem(2)) then
      call input_error(where, card//': the '//str(ns)//' viewing sample points of '// &
          'the NURBS elements ('//s_text//') need '//str(need/1.0e6_dp, 4)// &
          ' MB on each of the '//str(env_node_size())//' rank(s) of a node, but '// &
          str(-mem(2)/1.0e6_dp, 4)//' MB are available (ICTUS_MEMORY_LIMIT_MB, '// &
          '/proc/meminfo, the control group, ulimit -v); use *OUTPUT, FIELD, SAMPLES=2 '// &
          '(4 points per element), fewer ranks per node, or more memory')
      call input_failure()
    end if
  end subroutine check_viz_memory

  !> Ends a run whose input is wrong: exit status 1, nothing written.
  subroutine input_failure()
    call log_info('ictus: '//str(error_count())//' problem(s) in the input; nothing was run')
    call terminate(1)
  end subroutine input_failure

  !> Checks the Jacobians (all ranks, whole model), assembles this rank's operators and
  !! reports non-positive nodal masses found on any rank.
  subroutine check_operators(model, dom, ops)
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    type(operators_t), intent(out) :: ops
    integer, allocatable :: bad_jac(:), bad_mass(:), counts(:)
    logical, allocatable :: nonfinite(:)
    real(dp), allocatable :: all_bad(:)
    integer :: nbj, nbm, k, e, ntot
    call check_jacobians(model, bad_jac, nbj, nonfinite)
    do k = 1, min(nbj, 20)
      e = bad_jac(k)
      if (nonfinite(k)) then
        call input_error(element_where(e), etype_name(model%etype(e))//' element '// &
            str(model%elem_id(e))//' has a Jacobian determinant that is not a finite number '// &
            '(coordinates too large: expected element sizes whose squares stay below 1e308)')
      else
        call input_error(element_where(e), etype_name(model%etype(e))//' element '// &
            str(model%elem_id(e))//' has a non-positive Jacobian determinant (inverted or '// &
            'degenerate; corners must run counter-clockwise)')
      end if
    end do
    if (nbj > 20) call input_error('', str(nbj - 20)//' more elements with a non-positive '// &
        'or non-finite Jacobian determinant')
    if (nbj > 0) return
    call assemble_operators(model, dom, ops, bad_mass, nbm)
    if (.not. ops%total_mass <= huge(1.0_dp)) then
      e = max(mass_overflow_element(model), 1)
      call input_error(element_where(e), 'the total mass is not a finite number from '// &
          etype_name(model%etype(e))//' element '//str(model%elem_id(e))//' on (expected '// &
          'element areas times densities whose sum stays below 1e308)')
      return
    end if
    ! the non-positive masses of all ranks, in increasing global index
    allocate(counts(env_size()))
    call allgather_int(nbm, counts)
    ntot = sum(counts)
    if (ntot == 0) return
    allocate(all_bad(ntot))
    call allgatherv_real(real(bad_mass(1:nbm), dp), counts, all_bad)
    bad_mass = nint(all_bad)
    call sort(bad_mass)
    e = first_element_of(model, bad_mass(1))
    call input_error(element_where(e), 'the lumped mass is not positive at nodes '// &
        join_ids(model%node_id(bad_mass), 8)//' ('//etype_name(model%etype(e))// &
        ' elements, mass type '//mass_name(model%mass_kind(e))//')'//mass_reason(model, e))
  end subroutine check_operators

  !> Why a lumping gives non-positive masses, when we know.
  function mass_reason(model, e) result(why)
    type(model_t), intent(in) :: model
    integer, intent(in) :: e
    character(len=:), allocatable :: why
    why = ''
    if (model%mass_kind(e) == MASS_ROW_SUM .and. model%etype(e) == ETYPE_Q8) why = &
        ': row-sum lumping of 8-node serendipity elements gives their corner nodes a '// &
        'negative mass (-1/12 of the element mass on a square). Use TYPE=HRZ, TYPE=ALPHA '// &
        'or TYPE=CONSISTENT for these elements'
  end function mass_reason

  !> An element that holds node i.
  integer function first_element_of(model, i)
    type(model_t), intent(in) :: model
    integer, intent(in) :: i
    integer :: e
    first_element_of = 1
    do e = 1, model%nel
      if (any(model%conn(1:model%nen(e), e) == i)) then
        first_element_of = e
        return
      end if
    end do
  end function first_element_of

  subroutine log_summary(model, dom, ops, mop, dt)
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    type(operators_t), intent(in) :: ops
    type(mass_op_t), intent(in) :: mop
    real(dp), intent(in) :: dt
    integer :: nsteps
    nsteps = steps_for(model%t_end, dt)
    call log_info('model: '//str(model%nn)//' nodes/control points, '//str(model%nel)// &
        ' elements, '//str(model%npatch)//' patches, '//str(count(model%fixed))// &
        ' fixed dofs, total mass '//str(ops%total_mass))
    if (dom%nparts > 1) call log_info('partition: '//str(dom%nparts)//' METIS parts; rank 0 '// &
        'owns '//str(dom%nowned)//' nodes and reads '//str(dom%nlocal - dom%nowned)//' ghosts')
    if (ops%consistent) then
      select case (mop%solver)
      case (MASS_SOLVER_KRONECKER)
        call log_info('mass matrix: consistent (solved every step by 1D factors along the '// &
            'lattice directions, MASS SOLVER=KRONECKER'//trim(merge( &
            '; steps without output update v and u inside the solve', &
            '                                                      ', &
            mass_steps_fused(mop)))//')')
      case (MASS_SOLVER_CG)
        call log_info('mass matrix: consistent (conjugate-gradient solve every step, '// &
            'MASS SOLVER=CG)')
      case (MASS_SOLVER_CORRECTOR)
        call log_info('mass matrix: consistent, approximated by '//str(model%mass_passes)// &
            ' row-sum-preconditioned corrector passes every step (MASS SOLVER=CORRECTOR)')
      case default
        call log_info('mass matrix: consistent (solved every step with its Cholesky factor)')
      end select
    else
      call log_info('mass matrix: lumped (diagonal)')
    end if
    call log_info('step: dt = '//str(dt)//', t_end = '//str(model%t_end)//', '// &
        str(nsteps)//' steps')
  end subroutine log_summary

  !> Checkpoint path next to the results: results.h5 -> results.chk.h5.
  function checkpoint_path(out) result(path)
    character(len=*), intent(in) :: out
    character(len=:), allocatable :: path
    integer :: k
    k = len(out) - 2
    if (k > 1) then
      if (out(k:) == '.h5') then
        path = out(1:k - 1)//'.chk.h5'
        return
      end if
    end if
    path = out//'.chk.h5'
  end function checkpoint_path

  !> Number of steps of size dt to reach t_end (the last one ends at or just after t_end).
  pure integer function steps_for(t_end, dt)
    real(dp), intent(in) :: t_end, dt
    steps_for = max(1, ceiling(t_end/dt*(1.0_dp - 1.0e-12_dp)))
  end function steps_for

  !> Default results path: the deck's name with .h5.
  function default_out(deck_path) result(out)
    character(len=*), intent(in) :: deck_path
    character(len=:), allocatable :: out
    integer :: k, s
    k = index(deck_path, '.', back=.true.)
    s = index(deck_path, '/', back=.true.)
    if (k > s + 1) then
      out = deck_path(1:k - 1)//'.h5'
    else
      out = deck_path//'.h5'
    end if
  end function default_out

  !> The time loop with history and field output, progress lines and blow-up detection.
  subroutine time_loop(opt, deck, model, dom, ops, mop, contact, cs, dt, omega)
    type(run_options_t), intent(in) :: opt
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    type(domain_t), intent(inout) :: dom
    type(operators_t), intent(in) :: ops
    type(mass_op_t), intent(inout) :: mop
    type(contact_t), intent(inout) :: contact
    type(contact_step_t), intent(inout) :: cs
    real(dp), intent(in) :: dt, omega
    type(results_t) :: res
    type(state_t) :: s
    type(history_record_t) :: rec
    character(len=:), allocatable :: out
    real(dp), allocatable :: alpha(:)
    real(dp) :: e0, e_total, t0, t_last_print, elapsed
    integer :: nsteps, n, field_every, print_every
    integer, allocatable :: gid(:), drop(:)
    logical, allocatable :: was_active(:)
    logical :: record, field, ok, stop_now, tuning
    type(checkpoint_t) :: ck
    character(len=:), allocatable :: ckpt, deck_text, msg, wmsg, line
    integer :: n_start, n_first, n_last
    integer :: k
    logical, allocatable :: sync(:)
    real(dp) :: r
    character(len=256) :: where
    integer(8) :: failures
    out = default_out(opt%deck_path)
    if (allocated(opt%out_path)) out = opt%out_path
    ckpt = checkpoint_path(out)
    deck_text = deck_echo(deck, .true.)
    nsteps = steps_for(model%t_end, dt)
    field_every = model%field_every
    if (field_every <= 0) field_every = max(1, nsteps/20)
    print_every = max(1, nsteps/10)
    gid = dom%halo%gid(1:dom%nowned)
    allocate(alpha(dom%nlocal), source=0.0_dp)
    where (ops%m_pos > 0.0_dp) alpha = ops%c_diag/ops%m_pos
    allocate(was_active(contact%npairs), source=.false.)
    failures = 0
    call state_init(s, ops%k, mop, dom, model%u_fixed(:, dom%halo%gid), &
        model%v0(:, dom%halo%gid), alpha, ops%m_pos, dt)
    e0 = 0.0_dp
    n_start = 0
    if (allocated(opt%restart_path)) then
      ! continue an interrupted run: state from the checkpoint, results file cut back to it
      call checkpoint_read(opt%restart_path, deck_text, dom, s, cs, contact, ck, msg)
      if (len(msg) > 0) then
        call input_error(opt%restart_path, msg)
        call input_failure()
      end if
      n_start = ck%next_step
      e0 = ck%e0
      was_active = ck%was_active
      failures = ck%failures
      drop = pack([(n, n = n_start, nsteps)], [(mod(n, field_every) == 0 .or. n == nsteps, &
          n = n_start, nsteps)])
      call results_reopen(res, out, model, dom, contact, ck%n_history, ck%field_steps, &
          ck%field_times, drop, ok)
      if (.not. ok) then
        call input_error(out, 'cannot reopen the results file of the interrupted run '// &
            '(give it with -o if it is not the default)')
        call input_failure()
      end if
      call log_info('restart: continuing at step '//str(n_start)//', t = '//str(s%t)// &
          ' from '//opt%restart_path)
    else
      call results_open(res, out, model, dom, contact, deck_text, env_size(), ops%m_diag, &
          gid, omega, dt)
      if (s%ierr /= 0) call runtime_failure(res, s, model, dom, 'the consistent-mass '// &
          'solve did not converge at the start')
    end if
    call log_info('results: '//out)
    if (s%ordered) call log_product(s)
    ! sweeps of several steps over K where no output falls between (lumped mass)
    allocate(sync(dom%nowned), source=.false.)
    if (contact%npairs > 0) then
      do k = 1, cs%ncn
        if (cs%lnode(k) > 0) sync(cs%lnode(k)) = .true.
      end do
    end if
    call state_plan_sweep(s, ops%k, mop, dom, model%x0(:, gid), sync, model%sweep_steps)
    if (s%sweeps) then
      msg = ''
      if (s%tuning) msg = '; timed against single steps first'
      if (s%tuning .and. s%has_wide) msg = msg//' and against wide strips'
      call log_info('sweeps: '//str(s%sweep%nstage)//' steps per sweep over K between '// &
          'outputs ('//str(s%sweep%strip)//' strips; '//str(s%sweep%zone_rows(1))// &
          ' rows of '//str(dom%nowned)//' stepped one step at a time)'//msg)
    end if
    t0 = wall_time()
    t_last_print = t0
    n = n_start
    do while (n <= nsteps)
      n_first = n
      if (sweep_fits(n)) then
        ! steps n .. n_last in one sweep; the contact correction of each comes between
        n_last = n + s%sweep%nstage - 1
        tuning = s%tuning
        call step_window(s, ops%k, mop, dom, contact_between)
        if (tuning .and. .not. s%tuning) then
          msg = 'dropped: single steps are faster'
          if (s%kept) msg = 'kept: faster than single steps'
          if (s%kept .and. s%has_wide) msg = msg//', strips of '// &
              str(s%sweep_bytes/1024)//' KiB of K'
          wmsg = ''
          if (s%has_wide) wmsg = ', '//str(1.0e3_dp*s%tune_time(3), 3)//' ms in one sweep '// &
              'of wide strips'
          call log_info('sweeps: '//msg//' here (a window of '//str(s%sweep%nstage)// &
              ' steps in the best trial of each: '//str(1.0e3_dp*s%tune_time(1), 3)// &
              ' ms in one sweep, '//str(1.0e3_dp*s%tune_time(2), 3)//' ms one step at a '// &
              'time'//wmsg//')')
        end if
      else
        n_last = n
        record = mod(n, model%history_every) == 0 .or. n == nsteps
        field = mod(n, field_every) == 0 .or. n == nsteps
        call step_predict(s, ops%k, mop, dom, record .or. field)
        if (s%ierr /= 0) call runtime_failure(res, s, model, dom, 'the consistent-mass solve '// &
            'did not converge')
        if (record) then
          rec = history_record_t(s%t, dt, s%e_kin, s%e_strain, s%e_contact, s%w_ext)
          call results_contact(res, contact)
          call results_history(res, rec)
          e_total = s%e_kin + s%e_strain + s%e_contact - s%w_ext
          if (n == 0) e0 = e_total
          call check_blowup(res, s, model, dom, e0)
        end if
        if (field) then
          ! the viewing samples of NURBS elements read ghost velocities too
          if (model%npatch > 0) call halo_exchange(dom%halo, s%v_mid)
          call results_field(res, model, dom, n, s%t, s%u, s%v_mid, gid, contact)
        end if
        if (n == nsteps) exit
        if (contact%npairs > 0) call contact_between()
        call step_finish(s, dom)
      end if
      elapsed = wall_time() - t0
      ! checkpoints: every restart_every steps, and when the wall-time limit is reached (checked
      ! when the step count passes a multiple of 10)
      stop_now = .false.
      if (opt%wall_time > 0.0_dp .and. (n_last + 1)/10 > n/10) then
        stop_now = elapsed > opt%wall_time
        call allreduce_or(stop_now)
      end if
      n = n_last
      if (stop_now .or. (model%restart_every > 0 .and. mod(n + 1, max(1, &
          model%restart_every)) == 0 .and. n + 1 < nsteps)) then
        call results_flush(res)
        ck%next_step = n + 1
        ck%e0 = e0
        ck%n_history = results_records(res)
        ck%field_steps = res%field_step
        ck%field_times = res%field_time
        ck%was_active = was_active
        ck%failures = int(failures)
        call checkpoint_write(ckpt, deck_text, dom, s, cs, contact, ck)
        call log_verbose('checkpoint at step '//str(n + 1)//': '//ckpt)
      end if
      if (stop_now) then
        call results_close(res, 'stopped at the wall-time limit at step '//str(n + 1)// &
            '; continue with: ictus '//opt%deck_path//' -o '//out//' --restart '//ckpt)
        call log_info('wall-time limit of '//str(opt%wall_time)//' s reached at step '// &
            str(n + 1)//'; checkpoint written: '//ckpt)
        call log_info('continue with: ictus '//opt%deck_path//' -o '//out//' --restart '//ckpt)
        call terminate(EXIT_WALL_TIME)
      end if
      if ((n + 1)/print_every > n_first/print_every .or. &
          wall_time() - t_last_print > 10.0_dp) then
        t_last_print = wall_time()
        call log_info('step '//str(n + 1)//'/'//str(nsteps)//'  t = '//str(s%t, 5)// &
            '  dt = '//str(dt, 4)//'  E_total = '//str(s%e_kin + s%e_strain + s%e_contact &
            - s%w_ext, 8)//'  elapsed '//str(elapsed, 3)//' s  ETA '// &
            str(elapsed*real(nsteps - n - 1, dp)/real(n + 1, dp), 3)//' s')
        do k = 1, contact%npairs
          associate (p => contact%pairs(k))
            call log_info('  contact '//trim(p%name)//': force '//str(p%force_first(1), 5)// &
                ', '//str(p%force_first(2), 5)//'  max pressure '//str(p%max_pressure, 5)// &
                '  max penetration '//str(p%max_penetration, 4)//'  active points '// &
                str(p%active_points))
          end associate
        end do
      end if
      n = n + 1
    end do
    call report_energy(s, e0)
    if (failures > 0) call warning('contact', str(int(failures))//' closest-point '// &
        'projections failed during the run (those points were treated as open)')
    line = mass_op_report(mop)
    if (len(line) > 0) call log_info(line)
    call log_info('wall time: '//str(wall_time() - t0, 4)//' s for '//str(nsteps - n_start)// &
        ' steps')
    call results_close(res, 'completed')

  contains

    !> Whether steps n .. n + nstage - 1 can run as one sweep: sweeps are planned, no output
    !! is due at any of them, the last of them is before the final step, and no checkpoint
    !! falls strictly inside.
    logical function sweep_fits(n)
      integer, intent(in) :: n
      integer :: j
      sweep_fits = .false.
      if (.not. (s%sweeps .and. s%kept)) return
      if (n + s%sweep%nstage > nsteps) return
      do j = n, n + s%sweep%nstage - 1
        if (mod(j, model%history_every) == 0 .or. mod(j, field_every) == 0) return
        if (j > n .and. model%restart_every > 0) then
          if (mod(j, model%restart_every) == 0) return
        end if
      end do
      sweep_fits = .true.
    end function sweep_fits

    !> The contact correction of the current step, its failure count and the log line of a
    !! pair that becomes active (between the predictor and the displacement update).
    subroutine contact_between()
      integer :: kp
      if (contact%npairs == 0) return
      call contact_correct(cs, contact, s, mop, dom, model%x0)
      if (cs%ierr /= 0) call runtime_failure(res, s, model, dom, 'the consistent-mass '// &
          'solve of the contact correction did not converge')
      failures = failures + contact_failures(contact)
      do kp = 1, contact%npairs
        if (contact%pairs(kp)%active_points > 0 .and. .not. was_active(kp)) then
          was_active(kp) = .true.
          call contact_ratio(cs, contact, model%x0, s%u, ops%m_pos, dt, r, where)
          call log_info('contact '//trim(contact%pairs(kp)%name)//' becomes active at t = '// &
              str(s%t + dt)//'; stability ratio r = '//str(r, 4)//' ('//trim(where)//')')
          if (r > 0.5_dp) call warning('contact', 'the stability ratio r = '//str(r, 4)// &
              ' exceeds 1/2 at '//trim(where))
        end if
      end do
    end subroutine contact_between
  end subroutine time_loop

  !> Energy balance at the end: total = kinetic + strain + contact - external work.
  subroutine report_energy(s, e0)
    type(state_t), intent(in) :: s
    real(dp), intent(in) :: e0
    real(dp) :: e1, drift
    e1 = s%e_kin + s%e_strain + s%e_contact - s%w_ext
    drift = 0.0_dp
    if (abs(e0) > 0.0_dp) drift = (e1 - e0)/abs(e0)
    call log_info('energy balance: total at start '//str(e0, 10)//', at end '//str(e1, 10)// &
        ' (kinetic '//str(s%e_kin, 6)//', strain '//str(s%e_strain, 6)//', contact '// &
        str(s%e_contact, 6)//', external work '//str(s%w_ext, 6)//'); drift '// &
        str(drift, 3))
  end subroutine report_energy

  !> Stops the run (exit 2) when the energies are not finite or have grown without bound.
  !! The energies are global sums, so every rank takes the same decision.
  subroutine check_blowup(res, s, model, dom, e0)
    type(results_t), intent(inout) :: res
    type(state_t), intent(in) :: s
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    real(dp), intent(in) :: e0
    real(dp) :: e
    e = s%e_kin + s%e_strain
    if (.not. ieee_is_finite(e)) then
      call runtime_failure(res, s, model, dom, 'the solution is not finite (NaN or overflow)')
    else if (e0 > 0.0_dp .and. e > 1.0e3_dp*e0) then
      call runtime_failure(res, s, model, dom, 'the solution blows up: kinetic + strain '// &
          'energy '//str(e)//' is more than 1000 times the initial energy '//str(e0)// &
          ' (unstable time step?)')
    end if
  end subroutine check_blowup

  !> Reports a run-time failure with the step, time and the node with the largest (or a
  !! non-finite) velocity, closes the results as failed and exits with status 2. Collective.
  subroutine runtime_failure(res, s, model, dom, why)
    type(results_t), intent(inout) :: res
    type(state_t), intent(in) :: s
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    character(len=*), intent(in) :: why
    integer :: i, worst
    real(dp) :: vmax, vi, vglob
    character(len=:), allocatable :: msg
    worst = 0
    vmax = -1.0_dp
    do i = 1, dom%nowned
      vi = s%v(1, i)**2 + s%v(2, i)**2
      if (.not. ieee_is_finite(vi)) vi = huge(1.0_dp)
      if (vi > vmax) then
        vmax = vi
        worst = dom%halo%gid(i)
      end if
    end do
    vglob = vmax
    call allreduce_max(vglob)
    if (vmax < vglob) worst = 0
    call allreduce_max(worst)
    worst = max(worst, 1)
    msg = 'step '//str(s%step)//', t = '//str(s%t)//': '//why//'; worst at node '// &
        str(model%node_id(worst))//' ('//str(model%x0(1, worst), 6)//', '// &
        str(model%x0(2, worst), 6)//')'
    call results_close(res, 'failed: '//msg)
    call log_info('results so far: '//res%path)
    call fatal('run-time failure', msg, EXIT_RUNTIME)
  end subroutine runtime_failure

  !> The log line of the stiffness product of a consistent-mass step (`stiffness_product`):
  !! from K's upper blocks on ranks that hold all rows of their nodes' neighbours (one rank;
  !! a rank whose part has no ghosts), else from the full rows; the same bits either way.
  subroutine log_product(s)
    type(state_t), intent(in) :: s
    integer :: nup, nshort
    real(dp) :: mb
    nup = merge(1, 0, s%kup%n > 0)
    nshort = merge(1, 0, s%kup%short_of_memory)
    mb = 0.0_dp
    if (s%kup%n > 0) mb = 36.0_dp*real(size(s%kup%col), dp)/1.0e6_dp
    call allreduce_sum(nup)
    call allreduce_sum(nshort)
    call allreduce_sum(mb)
    if (env_size() == 1 .and. nup == 1) then
      call log_info('stiffness product: summed in column order from the upper blocks of K ('// &
          str(mb, 3)//' MB more; half the bytes per product)')
    else if (nup == env_size()) then
      call log_info('stiffness product: summed in column order from the upper blocks of K on '// &
          'all '//str(nup)//' ranks (parts without ghosts; '//str(mb, 3)//' MB more)')
    else if (nup > 0) then
      call log_info('stiffness product: summed in column order from the upper blocks of K on '// &
          str(nup)//' of '//str(env_size())//' ranks (parts without ghosts; '//str(mb, 3)// &
          ' MB more), the full rows on the others')
    else if (nshort > 0) then
      call log_info('stiffness product: summed in column order from the full rows of K '// &
          '(its upper blocks would take more than half the memory available)')
    else
      call log_info('stiffness product: summed in column order from the full rows of K')
    end if
  end subroutine log_product
end module ictus_app_driver
