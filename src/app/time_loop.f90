!> The time loop of a run: from the state at t = 0 (or a checkpoint) to t_end, writing history
!! records, field snapshots and checkpoints, as doc/theory.md "The time step" describes.
!!
!! The loop moves from one step at which something is due to the next: at an output step the
!! stepper runs the predictor with the energies (`stepper_record`) and the records are written;
!! then the stepper advances to the next step at which anything is due (`stepper_advance`),
!! where checkpoints, the wall-time limit and progress lines are handled.
module ictus_app_time_loop
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use ictus_core_kinds, only: dp
  use ictus_core_errors, only: input_error, error_count, fatal, terminate, warning
  use ictus_core_logger, only: log_info, log_verbose
  use ictus_core_strings, only: str
  use ictus_core_timer, only: wall_time
  use ictus_core_ticker, only: ticker_t, ticker_start
  use ictus_parallel_halo, only: halo_exchange
  use ictus_parallel_env, only: allreduce_or, env_size, allreduce_max
  use ictus_parallel_repro, only: repro_sum
  use ictus_solver_model, only: model_t, VAR_U, VAR_V, VAR_RF
  use ictus_solver_assemble, only: operators_t
  use ictus_solver_domain, only: domain_t
  use ictus_solver_mass_operator, only: mass_op_t, mass_op_report
  use ictus_solver_explicit, only: state_t
  use ictus_solver_stepper, only: stepper_t, stepper_init, stepper_plan, stepper_record, &
      stepper_advance, stepper_done, stepper_estimate, stepper_settle
  use ictus_solver_contact_step, only: contact_step_t
  use ictus_solver_guard, only: largest_rotation, ROTATION_LIMIT
  use ictus_solver_fields, only: element_fields_t, element_fields
  use ictus_elements_library, only: etype_name
  use ictus_contact_contact, only: contact_t, pair_resultant
  use ictus_io_deck_types, only: deck_t
  use ictus_io_deck_echo, only: deck_echo, record_digest_line
  use ictus_io_deck_record, only: deck_record_write, deck_record_digest
  use ictus_io_results, only: results_t, results_open, results_history, results_field, &
      results_close, history_record_t, results_contact, results_reopen, results_flush, &
      results_records, results_element_fields, results_sets, results_want_stress, &
      results_reaction
  use ictus_io_checkpoint, only: checkpoint_t, checkpoint_write, checkpoint_read
  use ictus_app_options, only: run_options_t, EXIT_RUNTIME, EXIT_WALL_TIME
  use ictus_app_schedule, only: schedule_t, schedule_init, schedule_due, schedule_next, &
      schedule_due_at
  implicit none
  private
  public :: time_loop, steps_for

  !> This rank's owned nodes of a node set with a history (local indices), and the number of
  !! nodes of the whole set.
  type :: set_nodes_t
    integer, allocatable :: idx(:)
    integer :: nglobal = 0
  end type set_nodes_t

  !> What the loop keeps besides the stepper: the results file, paths, output schedules, the
  !! energy at the start and the clocks.
  type :: loop_t
    type(results_t) :: res
    character(len=:), allocatable :: out, ckpt, deck_text, deck_path
    !> What a checkpoint stores and compares: the record with the digest of its bulk data.
    character(len=:), allocatable :: ckpt_text
    integer :: nsteps = 0, print_every = 1
    !> When history records and field snapshots are due.
    type(schedule_t) :: history, field
    !> Whether a TIME INTERVAL is followed by time (the step follows the state): then the
    !! loop looks at every step.
    logical :: time_based = .false.
    !> The node sets with a history: this rank's nodes of each, their values at a record
    !! (ndm, slot, set: mean displacement, mean velocity, summed reaction) and a work column.
    type(set_nodes_t), allocatable :: sets(:)
    real(dp), allocatable :: set_vals(:,:,:), set_work(:)
    !> The acceleration at a snapshot (nd, owned nodes).
    real(dp), allocatable :: acc(:,:)
    integer :: restart_every = 0
    real(dp) :: wall_limit = 0.0_dp
    real(dp) :: e0 = 0.0_dp, t0 = 0.0_dp, t_last_print = 0.0_dp
    !> The step the loop started at (0, or the checkpoint's).
    integer :: n_start = 0
    !> Whether the small-strain guard has warned (once per run).
    logical :: rotation_warned = .false.
    !> The largest energy of the records so far (kinetic + strain + contact + plastic work, or
    !! |total|), and whether the energy-balance warning has been given.
    real(dp) :: e_max = 0.0_dp
    logical :: energy_warned = .false.
    !> The contact energy of the last history record.
    real(dp) :: e_contact_rec = 0.0_dp
    !> Work of the element fields of a snapshot.
    type(element_fields_t) :: ef
  end type loop_t

contains

  !> Runs the steps of the model from t = 0 (or the checkpoint of opt%restart_path) to t_end.
  !! Returns on success; stops the program with exit status 2 on a run-time failure and 3 at
  !! the wall-time limit (with a checkpoint).
  subroutine time_loop(opt, deck, model, dom, ops, mop, contact, cs, dt, omega)
    type(run_options_t), intent(in) :: opt
    type(deck_t), intent(in) :: deck
    type(model_t), target, intent(in) :: model
    type(domain_t), target, intent(inout) :: dom
    type(operators_t), target, intent(in) :: ops
    type(mass_op_t), target, intent(inout) :: mop
    type(contact_t), target, intent(inout) :: contact
    type(contact_step_t), target, intent(inout) :: cs
    real(dp), intent(in) :: dt, omega
    type(stepper_t) :: stp
    type(loop_t) :: lp
    integer :: n, n_next, ierr
    real(dp) :: t0
    type(ticker_t) :: tk
    t0 = wall_time()
    call loop_setup(lp, opt, deck, model, dt)
    call log_info('set-up: processed deck formed in '//str(wall_time() - t0, 3)//' s')
    call ticker_start(tk, 'stepper and results file')
    call stepper_init(stp, model, dom, ops, mop, contact, cs, dt, model%t_end, ierr)
    if (ierr /= 0) call fatal('internal force', 'the geometry of element '//str(ierr)// &
        ' cannot be set up (det J <= 0)')
    call tk%tick(1, 3)
    call set_nodes(lp, model, dom)
    lp%time_based = stp%dt_control .and. (lp%history%every == 0 .or. lp%field%every == 0)
    call open_results(lp, stp, opt, deck, model, dom, ops, contact, cs, dt, omega, n)
    call tk%tick(2, 3)
    lp%n_start = n
    call stepper_plan(stp)
    call log_info('set-up: stepper and results file ready in '//str(wall_time() - t0, 3)//' s')
    lp%t0 = wall_time()
    lp%t_last_print = lp%t0
    do
      call stepper_estimate(stp)
      call check_failure(lp, stp)
      if (output_due(lp, stp, n)) then
        call stepper_record(stp)
        call check_failure(lp, stp)
        call write_outputs(lp, stp, n)
        if (n == lp%nsteps) exit
      end if
      n_next = next_event(lp, n)
      call stepper_advance(stp, n_next)
      call check_failure(lp, stp)
      n_next = stp%s%step
      call steps_left(lp, stp)
      call checkpoint_or_stop(lp, stp, opt, n_next)
      call progress_line(lp, stp, n, n_next)
      n = n_next
    end do
    ! the end-of-run balance is that of the last record (its contact energy, not that of
    ! the correction stepper_settle ran after it)
    stp%s%e_contact = lp%e_contact_rec
    call end_of_run(lp, stp)
    call results_close(lp%res, 'completed')
  end subroutine time_loop

  !> Paths, output intervals and the number of steps.
  subroutine loop_setup(lp, opt, deck, model, dt)
    type(loop_t), intent(out) :: lp
    type(run_options_t), intent(in) :: opt
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    real(dp), intent(in) :: dt
    lp%deck_path = opt%deck_path
    lp%out = default_out(opt%deck_path)
    if (allocated(opt%out_path)) lp%out = opt%out_path
    lp%ckpt = checkpoint_path(lp%out)
    lp%deck_text = deck_echo(deck, .true., record=.true.)
    lp%ckpt_text = lp%deck_text//record_digest_line(deck_record_digest(deck))
    lp%nsteps = steps_for(model%t_end, dt)
    lp%history = schedule_init(model%history_every, model%history_interval, dt, lp%nsteps)
    if (model%field_every > 0) then
      lp%field = schedule_init(model%field_every, model%field_interval, dt, lp%nsteps)
    else
      lp%field = schedule_init(max(1, lp%nsteps/20), model%field_interval, dt, lp%nsteps)
    end if
    lp%print_every = max(1, lp%nsteps/10)
    lp%restart_every = model%restart_every
    lp%wall_limit = opt%wall_time
  end subroutine loop_setup

  !> This rank's owned nodes of each node set with a history.
  subroutine set_nodes(lp, model, dom)
    type(loop_t), intent(inout) :: lp
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    integer :: k, nmax
    allocate(lp%sets(model%nout_sets))
    allocate(lp%set_vals(model%ndm, 3, model%nout_sets), source=0.0_dp)
    nmax = 0
    do k = 1, model%nout_sets
      associate (nodes => model%out_sets(k)%nodes)
        lp%sets(k)%nglobal = size(nodes)
        lp%sets(k)%idx = pack(dom%g2l(nodes), dom%g2l(nodes) >= 1 .and. &
            dom%g2l(nodes) <= dom%nowned)
        nmax = max(nmax, size(lp%sets(k)%idx))
      end associate
    end do
    allocate(lp%set_work(nmax))
  end subroutine set_nodes

  !> Opens the results file, or for a restart reads the checkpoint into the stepper and cuts
  !! the results file back to it; n: the step the loop starts at.
  subroutine open_results(lp, stp, opt, deck, model, dom, ops, contact, cs, dt, omega, n)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(inout) :: stp
    type(run_options_t), intent(in) :: opt
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    type(domain_t), intent(inout) :: dom
    type(operators_t), intent(in) :: ops
    type(contact_t), intent(inout) :: contact
    type(contact_step_t), intent(inout) :: cs
    real(dp), intent(in) :: dt, omega
    integer, intent(out) :: n
    type(checkpoint_t) :: ck
    character(len=:), allocatable :: msg
    logical :: ok
    n = 0
    if (.not. allocated(opt%restart_path)) then
      call results_open(lp%res, lp%out, model, dom, contact, lp%deck_text, env_size(), &
          ops%m_diag, dom%halo%gid(1:dom%nowned), omega, dt)
      call deck_record_write(lp%res%file, deck)
      call check_failure(lp, stp)
      call log_info('results: '//lp%out)
      return
    end if
    ! continue an interrupted run: state from the checkpoint, results file cut back to it
    stp%failure = ''
    call checkpoint_read(opt%restart_path, lp%ckpt_text, dom, stp%s, cs, contact, ck, msg)
    if (len(msg) > 0) then
      call input_error(opt%restart_path, msg)
      call log_info('ictus: '//str(error_count())//' problem(s) in the input; nothing was run')
      call terminate(1)
    end if
    n = ck%next_step
    lp%e0 = ck%e0
    stp%was_active = ck%was_active
    stp%failures = ck%failures
    call results_reopen(lp%res, lp%out, model, dom, contact, ck%n_history, ck%field_steps, &
        ck%field_times, ok)
    if (.not. ok) then
      call input_error(lp%out, 'cannot reopen the results file of the interrupted run '// &
          '(give it with -o if it is not the default)')
      call log_info('ictus: '//str(error_count())//' problem(s) in the input; nothing was run')
      call terminate(1)
    end if
    call log_info('restart: continuing at step '//str(n)//', t = '//str(stp%s%t)//' from '// &
        opt%restart_path)
    call log_info('results: '//lp%out)
  end subroutine open_results

  !> Where the stable step follows the state (the stepper's dt_control), the last step of the
  !! run as the current dt foresees it: the step at which t reaches t_end. The stepper stops
  !! there even if dt grows on the way.
  subroutine steps_left(lp, stp)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(in) :: stp
    if (.not. stp%dt_control) return
    if (stepper_done(stp)) then
      lp%nsteps = stp%s%step
    else
      lp%nsteps = stp%s%step + steps_for(stp%t_end - stp%s%t, stp%s%dt)
    end if
    lp%history%nlast = lp%nsteps
    lp%field%nlast = lp%nsteps
  end subroutine steps_left

  !> Whether a history record or a field snapshot is due at step n.
  logical function output_due(lp, stp, n)
    type(loop_t), intent(in) :: lp
    type(stepper_t), intent(in) :: stp
    integer, intent(in) :: n
    output_due = due(lp, stp, lp%history, n) .or. due(lp, stp, lp%field, n)
  end function output_due

  !> Whether the output of schedule sc is due at step n: by step number; where the step
  !! follows the state, a TIME INTERVAL by time, between the steps before and after t_n.
  logical function due(lp, stp, sc, n)
    type(loop_t), intent(in) :: lp
    type(stepper_t), intent(in) :: stp
    type(schedule_t), intent(in) :: sc
    integer, intent(in) :: n
    if (stp%dt_control .and. sc%every == 0) then
      due = schedule_due_at(sc, stp%s%t, stp%s%dt_prev, stp%s%dt, n == lp%nsteps)
    else
      due = schedule_due(sc, n)
    end if
  end function due

  !> The next step after n at which anything is due: an output, a checkpoint, a wall-time
  !! check (every 10 steps when a limit is set), a progress line, or the last step.
  integer function next_event(lp, n) result(m)
    type(loop_t), intent(in) :: lp
    integer, intent(in) :: n
    m = min(lp%nsteps, schedule_next(lp%history, n), schedule_next(lp%field, n), &
        next_multiple(n, lp%print_every))
    if (lp%restart_every > 0) m = min(m, next_multiple(n, lp%restart_every))
    if (lp%wall_limit > 0.0_dp) m = min(m, next_multiple(n, 10))
    ! a TIME INTERVAL while the step follows the state: every step is looked at
    if (lp%time_based) m = n + 1
  end function next_event

  !> The smallest multiple of k above n.
  pure integer function next_multiple(n, k)
    integer, intent(in) :: n, k
    next_multiple = (n/k + 1)*k
  end function next_multiple

  !> History record (energies, contact) and field snapshot of step n, as due; the energy at
  !! the start and the blow-up check. With contact the snapshot comes first: the history
  !! record then runs the contact correction of step n (stepper_settle) for the kinetic
  !! energy at t_n with the corrected v_{n+1/2} (doc/theory.md §4b), which changes the
  !! velocities and the pairs' results that the snapshot writes.
  subroutine write_outputs(lp, stp, n)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(inout) :: stp
    integer, intent(in) :: n
    if (stp%contact%npairs > 0) then
      if (due(lp, stp, lp%field, n)) call write_field(lp, stp, n)
      if (due(lp, stp, lp%history, n)) call write_history(lp, stp, n)
    else
      if (due(lp, stp, lp%history, n)) call write_history(lp, stp, n)
      if (due(lp, stp, lp%field, n)) call write_field(lp, stp, n)
    end if
  end subroutine write_outputs

  !> The history record of step n (after the predictor with the energies at t_n): contact
  !! results and node sets as they are, then with contact the correction of step n and the
  !! kinetic energy with its v_{n+1/2}; the contact energy recorded is that of the last
  !! evaluation before the correction, as the pairs' results.
  subroutine write_history(lp, stp, n)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(inout) :: stp
    integer, intent(in) :: n
    type(history_record_t) :: rec
    real(dp) :: e_contact, e_next
    associate (s => stp%s, model => stp%model)
      call results_contact(lp%res, stp%contact)
      if (model%nout_sets > 0) then
        call set_values(lp, stp)
        call results_sets(lp%res, lp%set_vals)
      end if
      e_contact = s%e_contact
      call stepper_settle(stp)
      ! the correction's contact energy belongs to the next record: the checks below see the
      ! record's
      e_next = s%e_contact
      s%e_contact = e_contact
      rec = history_record_t(s%t, s%dt, s%e_kin, s%e_strain, s%e_contact, s%w_ext, &
          s%e_plastic, s%e_friction)
      call results_history(lp%res, rec)
      if (n == 0) lp%e0 = total_energy(s)
      call check_blowup(lp, stp)
      call check_balance(lp, stp)
      lp%e_contact_rec = e_contact
      s%e_contact = e_next
    end associate
  end subroutine write_history

  !> The field snapshot of step n.
  subroutine write_field(lp, stp, n)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(inout) :: stp
    integer, intent(in) :: n
    associate (s => stp%s, model => stp%model, dom => stp%dom)
      ! the viewing samples of NURBS elements read ghost velocities too
      if (model%npatch > 0) call halo_exchange(dom%halo, s%v_mid)
      call acceleration(lp, stp)
      call results_field(lp%res, model, dom, n, s%t, s%u, s%v_mid, lp%acc, &
          dom%halo%gid(1:dom%nowned), stp%contact)
      if (results_want_stress(lp%res)) then
        call element_fields(model, dom, s%u, s%hist, lp%ef)
        call results_element_fields(lp%res, n, lp%ef, dom%halo%gid(1:dom%nowned), &
            model%nel)
      end if
      call results_reaction(lp%res, n, s%rf, dom%halo%gid(1:dom%nowned))
      if (.not. model%nlgeom .and. .not. lp%rotation_warned) call rotation_guard(lp, stp)
    end associate
  end subroutine write_field

  !> The acceleration at t_n of the owned nodes, (v_{n+1/2} - v_{n-1/2})/dt with the
  !! half-step velocities of the field output: a_n = M^-1(-f_int(u_n)) less the damping
  !! term alpha v_n (0 at fixed dofs).
  subroutine acceleration(lp, stp)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(in) :: stp
    integer :: i, nn
    nn = stp%s%nn
    if (.not. allocated(lp%acc)) allocate(lp%acc(size(stp%s%a, 1), nn))
    associate (s => stp%s)
      do i = 1, nn
        lp%acc(:, i) = (s%a(:, i) - s%alpha(i)*s%v_mid(:, i))*stp%mop%free(:, i)
      end do
    end associate
  end subroutine acceleration

  !> The values of the node sets at a history record (t_n): the mean displacement and mean
  !! velocity v_n over each set's nodes and the sum of their reactions, reproducible sums
  !! over the owned nodes (the same bits on any number of ranks).
  subroutine set_values(lp, stp)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(in) :: stp
    integer :: k, d
    associate (s => stp%s)
      do k = 1, size(lp%sets)
        associate (o => stp%model%out_sets(k))
          do d = 1, size(s%u, 1)
            if (o%vars(VAR_U)) lp%set_vals(d, 1, k) = set_sum(lp, k, s%u(d, :))/ &
                real(max(1, lp%sets(k)%nglobal), dp)
            if (o%vars(VAR_V)) lp%set_vals(d, 2, k) = set_sum(lp, k, s%v_mid(d, :))/ &
                real(max(1, lp%sets(k)%nglobal), dp)
            if (o%vars(VAR_RF)) lp%set_vals(d, 3, k) = set_sum(lp, k, s%rf(d, :))
          end do
        end associate
      end do
    end associate
  end subroutine set_values

  !> The sum of x over the nodes of set k (collective; x local).
  real(dp) function set_sum(lp, k, x)
    type(loop_t), intent(inout) :: lp
    integer, intent(in) :: k
    real(dp), intent(in) :: x(:)
    integer :: m
    m = size(lp%sets(k)%idx)
    lp%set_work(1:m) = x(lp%sets(k)%idx)
    set_sum = repro_sum(m, lp%set_work, max(1, lp%sets(k)%nglobal))
  end function set_sum

  !> The energy-ratio warning (as LS-DYNA's glstat): once, when the balance error
  !! |E_total - E_0| exceeds ENERGY WARNING (default 1 %) of the largest energy so far.
  subroutine check_balance(lp, stp)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(in) :: stp
    real(dp) :: err
    associate (s => stp%s)
      lp%e_max = max(lp%e_max, s%e_kin + s%e_strain + s%e_contact + s%e_plastic + &
          s%e_friction, &
          abs(total_energy(s)))
      if (lp%energy_warned .or. .not. lp%e_max > 0.0_dp) return
      err = abs(total_energy(s) - lp%e0)
      if (.not. err > stp%model%energy_warning*lp%e_max) return
      lp%energy_warned = .true.
      call warning('energy', 'the energy balance error |E_total - E_0| = '//str(err, 4)// &
          ' is '//str(100.0_dp*err/lp%e_max, 3)//' % of the largest energy '// &
          str(lp%e_max, 5)//' at t = '//str(s%t, 5)//' (more than ENERGY WARNING = '// &
          str(stp%model%energy_warning, 3)//' on *DYNAMIC): check the time step (SAFETY), '// &
          'the contact penalty and the mesh')
    end associate
  end subroutine check_balance

  !> The small-strain guard at a field output: one warning when an element has turned by more
  !! than ROTATION_LIMIT.
  subroutine rotation_guard(lp, stp)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(in) :: stp
    real(dp) :: w
    integer :: e
    call largest_rotation(stp%model, stp%dom, stp%s%u, w, e)
    if (.not. w > ROTATION_LIMIT) return
    lp%rotation_warned = .true.
    call warning('small strain', etype_name(stp%model%etype(e))//' element '// &
        str(stp%model%elem_id(e))//' has turned by '//str(w, 3)//' rad at t = '// &
        str(stp%s%t, 5)//' (more than '//str(ROTATION_LIMIT, 2)//'): small-strain '// &
        'kinematics take a rotation for strain (a spun body grows); use *STEP, NLGEOM=YES')
  end subroutine rotation_guard

  !> kinetic + strain + contact (+ plastic work + frictional work) - external work at the
  !! last record.
  pure real(dp) function total_energy(s)
    type(state_t), intent(in) :: s
    total_energy = s%e_kin + s%e_strain + s%e_contact - s%w_ext
    if (s%e_plastic /= 0.0_dp) total_energy = total_energy + s%e_plastic
    if (s%e_friction /= 0.0_dp) total_energy = total_energy + s%e_friction
  end function total_energy

  !> At step n (the state at t_n): a checkpoint when one is due (every RESTART EVERY steps, or
  !! at the wall-time limit, checked every 10 steps), and the stop at the limit (exit 3).
  subroutine checkpoint_or_stop(lp, stp, opt, n)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(inout) :: stp
    type(run_options_t), intent(in) :: opt
    integer, intent(in) :: n
    type(checkpoint_t) :: ck
    character(len=:), allocatable :: again
    logical :: stop_now
    stop_now = .false.
    if (lp%wall_limit > 0.0_dp .and. mod(n, 10) == 0) then
      stop_now = wall_time() - lp%t0 > lp%wall_limit
      call allreduce_or(stop_now)
    end if
    if (stop_now .or. (lp%restart_every > 0 .and. mod(n, max(1, lp%restart_every)) == 0 &
        .and. n < lp%nsteps)) then
      call results_flush(lp%res)
      ck%next_step = n
      ck%e0 = lp%e0
      ck%n_history = results_records(lp%res)
      ck%field_steps = lp%res%field_step
      ck%field_times = lp%res%field_time
      ck%was_active = stp%was_active
      ck%failures = int(stp%failures)
      call checkpoint_write(lp%ckpt, lp%ckpt_text, stp%dom, stp%s, stp%cs, stp%contact, ck)
      call log_verbose('checkpoint at step '//str(n)//': '//lp%ckpt)
    end if
    if (.not. stop_now) return
    again = 'ictus '//opt%deck_path//' -o '//lp%out//' --restart '//lp%ckpt
    call results_close(lp%res, 'stopped at the wall-time limit at step '//str(n)// &
        '; continue with: '//again)
    call log_info('wall-time limit of '//str(opt%wall_time)//' s reached at step '//str(n)// &
        '; checkpoint written: '//lp%ckpt)
    call log_info('continue with: '//again)
    call terminate(EXIT_WALL_TIME)
  end subroutine checkpoint_or_stop

  !> A progress line (and one per contact pair) every tenth of the run or every 10 s, after
  !! the steps from n to m.
  subroutine progress_line(lp, stp, n, m)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(in) :: stp
    integer, intent(in) :: n, m
    real(dp) :: elapsed, f(3)
    character(len=:), allocatable :: fs
    integer :: k
    if (.not. (m/lp%print_every > n/lp%print_every .or. &
        wall_time() - lp%t_last_print > 10.0_dp)) return
    lp%t_last_print = wall_time()
    elapsed = lp%t_last_print - lp%t0
    call log_info('step '//str(m)//'/'//str(lp%nsteps)//'  t = '//str(stp%s%t, 5)// &
        '  dt = '//str(stp%s%dt, 4)//'  E_total = '//str(total_energy(stp%s), 8)// &
        '  elapsed '//str(elapsed, 3)//' s  ETA '// &
        str(elapsed*real(lp%nsteps - m, dp)/real(max(m, 1), dp), 3)//' s')
    do k = 1, stp%contact%npairs
      f = pair_resultant(stp%contact, k, 1)
      fs = str(f(1), 5)//', '//str(f(2), 5)
      if (stp%contact%ndm == 3) fs = fs//', '//str(f(3), 5)
      associate (p => stp%contact%pairs(k))
        call log_info('  contact '//trim(p%name)//': force '//fs// &
            '  max pressure '//str(p%max_pressure, 5)// &
            '  max penetration '//str(p%max_penetration, 4)//'  active points '// &
            str(p%active_points))
      end associate
    end do
  end subroutine progress_line

  !> The end-of-run lines: energy balance, projection failures, the mass solver's work, time.
  subroutine end_of_run(lp, stp)
    type(loop_t), intent(in) :: lp
    type(stepper_t), intent(in) :: stp
    real(dp) :: e1, drift
    character(len=:), allocatable :: line, fw
    integer :: k
    e1 = total_energy(stp%s)
    ! relative to the energy at the start, or with loads (which may start from rest) to the
    ! larger of it and the work done
    drift = abs(lp%e0)
    if (stp%s%loaded) drift = max(drift, abs(stp%s%w_ext))
    if (drift > 0.0_dp) then
      drift = (e1 - lp%e0)/drift
    else
      drift = 0.0_dp
    end if
    fw = ''
    if (stp%s%e_friction /= 0.0_dp) fw = ', frictional work '//str(stp%s%e_friction, 6)
    associate (s => stp%s, mop => stp%mop)
      call log_info('energy balance: total at start '//str(lp%e0, 10)//', at end '// &
          str(e1, 10)//' (kinetic '//str(s%e_kin, 6)//', strain '//str(s%e_strain, 6)// &
          ', contact '//str(s%e_contact, 6)//', external work '//str(s%w_ext, 6)// &
          fw//'); drift '//str(drift, 3))
      do k = 1, stp%contact%npairs
        associate (p => stp%contact%pairs(k))
          if (p%outside_total > 0) call warning('contact', 'pair '//trim(p%name)//': '// &
              str(p%outside_total)//' contact point evaluations over the run penetrated '// &
              'the other surface but projected beyond its end (no force applied; '// &
              '/history/contact/'//trim(p%name)//'/outside_points)')
        end associate
      end do
      if (stp%failures > 0) call warning('contact', str(int(stp%failures))//' closest-'// &
          'point projections failed during the run (those points were treated as open)')
      line = mass_op_report(mop)
      if (len(line) > 0) call log_info(line)
    end associate
    call log_info('wall time: '//str(wall_time() - lp%t0, 4)//' s for '// &
        str(stp%s%step - lp%n_start)//' steps')
  end subroutine end_of_run

  !> A run-time failure of the stepper (its message in stp%failure) ends the run.
  subroutine check_failure(lp, stp)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(in) :: stp
    if (len(stp%failure) > 0) call runtime_failure(lp, stp, stp%failure)
  end subroutine check_failure

  !> Stops the run (exit 2) when the energies are not finite or have grown without bound:
  !! beyond 1000 times the initial energy plus the work done on the model (loads and
  !! prescribed motion feed energy in). The energies are global sums, so every rank takes the
  !! same decision.
  subroutine check_blowup(lp, stp)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(in) :: stp
    real(dp) :: e, e_in
    e = stp%s%e_kin + stp%s%e_strain
    e_in = lp%e0
    if (stp%s%loaded) e_in = e_in + abs(stp%s%w_ext)
    if (.not. ieee_is_finite(e)) then
      call runtime_failure(lp, stp, 'the solution is not finite (NaN or overflow)')
    else if (e_in > 0.0_dp .and. e > 1.0e3_dp*e_in) then
      call runtime_failure(lp, stp, 'the solution blows up: kinetic + strain energy '// &
          str(e)//' is more than 1000 times the initial energy '//str(lp%e0)// &
          trim(merge(' plus the external work', '                       ', stp%s%loaded))// &
          ' (unstable time step?)')
    end if
  end subroutine check_blowup

  !> Reports a run-time failure with the step, time and the node with the largest (or a
  !! non-finite) velocity, closes the results as failed and exits with status 2. Collective.
  subroutine runtime_failure(lp, stp, why)
    type(loop_t), intent(inout) :: lp
    type(stepper_t), intent(in) :: stp
    character(len=*), intent(in) :: why
    integer :: i, worst
    real(dp) :: vmax, vi, vglob
    character(len=:), allocatable :: msg
    worst = 0
    vmax = -1.0_dp
    associate (s => stp%s, dom => stp%dom, model => stp%model)
      do i = 1, dom%nowned
        vi = s%v(1, i)**2 + s%v(2, i)**2
        if (size(s%v, 1) == 3) vi = vi + s%v(3, i)**2
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
          str(model%x0(2, worst), 6)
      if (model%ndm == 3) msg = msg//', '//str(model%x0(3, worst), 6)
      msg = msg//')'
    end associate
    call results_close(lp%res, 'failed: '//msg)
    call log_info('results so far: '//lp%res%path)
    call fatal('run-time failure', msg, EXIT_RUNTIME)
  end subroutine runtime_failure

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
end module ictus_app_time_loop
