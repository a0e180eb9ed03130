!> The run: deck -> model -> operators -> time step -> time loop with output.
!!
!! Order of a run: read and check the deck (exit 1 on any problem, before anything is
!! written), build the model, assemble K and M once, estimate omega_max and choose or check
!! dt, open the results file, loop over the steps writing history and field records, close.
module ictus_app_driver
  use ictus_core_sort, only: sort
  use ictus_core_kinds, only: dp, i8
  use ictus_core_memory, only: available_memory
  use ictus_core_errors, only: input_error, error_count, fatal, terminate, warning
  use ictus_core_logger, only: log_info
  use ictus_core_strings, only: str, join_ids
  use ictus_core_timer, only: wall_time
  use ictus_core_ticker, only: ticker_t, ticker_start
  use ictus_parallel_env, only: env_size, allreduce_max, allgather_int, allgatherv_real, &
      env_node_size
  use ictus_elements_types, only: ETYPE_Q8, ETYPE_C3D20, etype_is_nurbs
  use ictus_elements_library, only: etype_name
  use ictus_mass_types, only: mass_name, MASS_ROW_SUM
  use ictus_solver_model, only: model_t
  use ictus_solver_tensor_layout, only: tensor_layout_t, tensor_layout
  use ictus_solver_assemble, only: operators_t, assemble_operators, check_jacobians, &
      mass_overflow_element
  use ictus_solver_domain, only: domain_t, domain_init
  use ictus_solver_mass_operator, only: mass_op_t, mass_op_init, mass_min_entry, &
      mass_steps_fused, MASS_SOLVER_CG, MASS_SOLVER_CORRECTOR, MASS_SOLVER_KRONECKER
  use ictus_solver_timestep, only: omega_max_power
  use ictus_solver_force_element, only: element_force_t, element_loop_init
  use ictus_solver_contact_step, only: contact_step_t, contact_step_init, contact_ratio, &
      contact_bipenalty_init
  use ictus_contact_contact, only: contact_t, PAIR_TIE
  use ictus_app_build_contact, only: build_contact
  use ictus_app_build_loads, only: build_loads
  use ictus_io_deck_types, only: deck_t
  use ictus_io_deck_reader, only: read_deck
  use ictus_io_deck_echo, only: deck_echo
  use ictus_io_iga_viz, only: iga_viz_count, iga_viz_samples
  use ictus_app_build_model, only: build_model, element_where
  use ictus_app_options, only: run_options_t
  use ictus_app_time_loop, only: time_loop, steps_for
  implicit none
  private
  public :: run_options_t, driver_run

contains

  !> Runs the deck named in `opt`. Returns normally only on success.
  subroutine driver_run(opt)
    type(run_options_t), intent(in) :: opt
    type(deck_t) :: deck
    type(model_t), target :: model
    type(domain_t), target :: dom
    type(operators_t), target :: ops
    type(mass_op_t), target :: mop
    type(tensor_layout_t) :: layout
    type(contact_t), target :: contact
    type(contact_step_t), target :: cs
    real(dp) :: omega, dt_crit, dt, r1, dt_pen
    integer :: iters, ierr
    character(len=256) :: where
    real(dp) :: t0
    t0 = wall_time()
    call read_deck(opt%deck_path, deck)
    if (error_count() > 0) call input_failure()
    call phase('deck read', t0)
    call build_model(deck, model)
    if (error_count() > 0) call input_failure()
    call build_loads(deck, model)
    if (error_count() > 0) call input_failure()
    call phase('model built', t0)
    call domain_init(dom, model, ierr)
    if (ierr /= 0) call fatal('partitioning', 'METIS could not partition the mesh into '// &
        str(env_size())//' parts')
    call phase('partitioned', t0)
    call check_operators(model, dom, ops)
    if (error_count() > 0) call input_failure()
    call phase('elements checked, stiffness and mass assembled', t0)
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
    if (ops%consistent .and. model%ndm == 2) call tensor_layout(model, layout)
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
    call phase('contact and mass operator set up', t0)
    call estimate_omega(model, dom, ops, mop, omega, iters)
    call phase('omega_max estimated', t0)
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
    ! the penalty limit of the predictor-corrector scheme (doc/contact.md §6): the contact
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
      call tie_penalties(model, dom, ops, contact, cs, dt)
      call check_contact_ratio(deck, model, dom, ops, contact, cs, dt)
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

  !> omega_max of the model without contact (ictus_solver_timestep): from the assembled K
  !! where there is one (2D; 3D with the assembled K); else (3D with the element loop) from the
  !! element loop's stiffness product, whose stored geometry is freed on return (the stepper
  !! sets up its own).
  subroutine estimate_omega(model, dom, ops, mop, omega, iters)
    type(model_t), intent(in) :: model
    type(domain_t), intent(inout) :: dom
    type(operators_t), intent(in) :: ops
    type(mass_op_t), intent(inout) :: mop
    real(dp), intent(out) :: omega
    integer, intent(out) :: iters
    type(element_force_t) :: kel
    integer :: ierr
    if (allocated(ops%k%val)) then
      call omega_max_power(ops%k, mop, dom, omega, iters, 1.0e-12_dp, 5000)
      return
    end if
    call element_loop_init(kel, model, dom, ierr)
    if (ierr /= 0) call fatal('stable step', 'the geometry of element '//str(ierr)// &
        ' cannot be set up (det J <= 0)')
    call omega_max_power(ops%k, mop, dom, omega, iters, 1.0e-12_dp, 5000, kel)
  end subroutine estimate_omega

  !> The penalty of each *TIE without PENALTY=: the one that puts its contact ratio at
  !! r = 0.9 at the run's step dt, logged (doc/contact.md §4b: near r = 1 the predictor-
  !! corrector step removes the predicted gap, as a forward-increment multiplier would, and
  !! the static compliance of the tie (1 - r)/eps is a tenth of its penalty's). Until here such ties have penalty 0, so that they do not limit
  !! the automatic step.
  subroutine tie_penalties(model, dom, ops, contact, cs, dt)
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    type(operators_t), intent(in) :: ops
    type(contact_t), intent(inout) :: contact
    type(contact_step_t), intent(inout) :: cs
    real(dp), intent(in) :: dt
    real(dp), parameter :: r_tie = 0.9_dp
    real(dp) :: r1, r_pair(contact%npairs)
    character(len=256) :: at
    logical :: auto(contact%npairs)
    integer :: k
    auto = contact%pairs%kind == PAIR_TIE .and. .not. contact%pairs%penalty > 0.0_dp
    if (.not. any(auto)) return
    do k = 1, contact%npairs
      if (auto(k)) contact%pairs(k)%penalty = 1.0_dp
    end do
    call contact_ratio(cs, contact, model%x0, 0.0_dp*model%x0(:, dom%halo%gid), ops%m_pos, &
        1.0_dp, r1, at, r_pair)
    do k = 1, contact%npairs
      if (.not. auto(k)) cycle
      contact%pairs(k)%penalty = r_tie/(dt*dt*r_pair(k))
      call log_info('tie '//trim(contact%pairs(k)%name)//': penalty '// &
          str(contact%pairs(k)%penalty)//' (contact ratio r = 0.9 at dt = '//str(dt)//')')
    end do
  end subroutine tie_penalties

  !> The contact ratio r = dt^2 eps (l_s/m_s + l_m/m_m) of each pair at the start and the
  !! chosen step (doc/contact.md §6): logged; above 1/2 (the margin of the automatic step) a
  !! warning; above the limit r = 1 of the predictor-corrector penalty an input error naming
  !! the pair, r and the largest stable penalty eps/r (r is proportional to eps), unless the
  !! card has STABILITY=WARN, which runs with a warning.
  subroutine check_contact_ratio(deck, model, dom, ops, contact, cs, dt)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    type(operators_t), intent(in) :: ops
    type(contact_t), intent(inout) :: contact
    type(contact_step_t), intent(inout) :: cs
    real(dp), intent(in) :: dt
    real(dp), parameter :: r_limit = 1.0_dp
    real(dp) :: r1, r_warn, r_pair(contact%npairs)
    character(len=256) :: where
    character(len=:), allocatable :: card, at, msg
    logical :: warn_only
    integer :: k
    call contact_ratio(cs, contact, model%x0, 0.0_dp*model%x0(:, dom%halo%gid), ops%m_pos, &
        dt, r1, where, r_pair)
    call log_info('contact: stability ratio r = dt^2 eps (l_s/m_s + l_m/m_m) = '//str(r1, 4)// &
        ' at the start ('//trim(where)//')')
    ! a *TIE without PENALTY= sits at r = 0.9 by design (tie_penalties): no margin warning
    r_warn = 0.0_dp
    do k = 1, contact%npairs
      if (k <= deck%n_pairs) then
        if (deck%pairs(k)%tie .and. .not. deck%pairs(k)%penalty > 0.0_dp) cycle
      end if
      r_warn = max(r_warn, r_pair(k))
    end do
    if (r_warn > 0.5_dp .and. .not. r1 > r_limit) call warning('contact', 'the stability '// &
        'ratio r = '//str(r1, 4)//' exceeds 1/2 at '//trim(where)//' (the margin ictus '// &
        'asks for; doc/contact.md §6 puts the limit of the predictor-corrector penalty at '// &
        'r = 1)')
    do k = 1, contact%npairs
      if (.not. r_pair(k) > r_limit) cycle
      if (k <= deck%n_pairs) then
        card = '*CONTACT PAIR'
        at = trim(deck%pairs(k)%where)
        warn_only = deck%pairs(k)%stability_warn
      else
        card = '*RIGID WALL'
        at = trim(deck%walls(k - deck%n_pairs)%where)
        warn_only = deck%walls(k - deck%n_pairs)%stability_warn
      end if
      msg = card//' '//trim(contact%pairs(k)%name)//': the contact stability ratio r = '// &
          'dt^2 eps (l_s/m_s + l_m/m_m) = '//str(r_pair(k), 4)//' at dt = '//str(dt)// &
          ' exceeds the limit r = 1 of the predictor-corrector penalty (doc/contact.md §6)'// &
          '; the largest stable penalty at this dt is about PENALTY='// &
          str(contact%pairs(k)%penalty*r_limit/r_pair(k), 4)//' (given '// &
          str(contact%pairs(k)%penalty)//')'
      if (warn_only) then
        call warning(at, msg//'; running anyway (STABILITY=WARN)')
      else
        call input_error(at, msg//', or a smaller dt; STABILITY=WARN runs anyway')
      end if
    end do
    if (error_count() > 0) call input_failure()
  end subroutine check_contact_ratio

  !> The viewing samples of the NURBS elements (src/io/iga_viz.f90) must fit in memory: while
  !! the results file is opened every rank forms the coordinates of all sample points and
  !! the cells (16 bytes each in 2D; 24 and 32 in 3D), and for the run it keeps, per sample
  !! of the elements it evaluates, a row number and the displacement and velocity (36 bytes;
  !! 52 in 3D); that times the
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
      if (.not. etype_is_nurbs(model%etype(e))) cycle
      if (dom%owner(model%conn(1, e)) /= dom%rank) cycle
      mine = mine + int(iga_viz_samples(model, model%patch(e), model%viz_samples), &
          i8)**model%ndm
    end do
    need = 8.0_dp*model%ndm*real(ns, dp) + 4.0_dp*2**model%ndm*real(nc, dp) + &
        (4.0_dp + 16.0_dp*model%ndm)*real(mine, dp)
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

  !> The log line of a set-up phase: its name and the time since t0 (reset to now).
  subroutine phase(name, t0)
    character(len=*), intent(in) :: name
    real(dp), intent(inout) :: t0
    real(dp) :: t
    t = wall_time()
    call log_info('set-up: '//name//' in '//str(t - t0, 3)//' s')
    t0 = t
  end subroutine phase

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
    type(ticker_t) :: tk
    call ticker_start(tk, 'element check', stride=1000)
    call check_jacobians(model, bad_jac, nbj, nonfinite, tk)
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
    call assemble_operators(model, dom, ops, bad_mass, nbm, tk)
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
    if (model%mass_kind(e) == MASS_ROW_SUM .and. model%etype(e) == ETYPE_C3D20) why = &
        ': row-sum lumping of 20-node serendipity elements gives their corner nodes a '// &
        'negative mass (-1/8 of the element mass on a cube). Use TYPE=HRZ or '// &
        'TYPE=CONSISTENT for these elements'
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
    if (model%nmerged > 0 .and. model%ndm == 3) call log_info('model: '//str(model%nmerged)// &
        ' coincident control points of trivariate patches merged (collapsed sides)')
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

end module ictus_app_driver
