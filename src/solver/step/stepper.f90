!> The stepper: advances the run from one step at which something must be written (a history
!! record, a field, a checkpoint, a wall-time check, a progress line) to the next, as in
!! doc/theory.md "The time step". Each step is
!!
!!     predictor (internal force, mass solve)  ->  contact correction  ->  displacement update
!!
!! The driver asks for two things: `stepper_record` runs the predictor of the current step with
!! the energies at t_n (the step then waits for its contact correction and update, which the
!! next `stepper_advance` does first), and `stepper_advance(stp, m)` runs whole steps until the
!! state is at t_m. How the steps run is the stepper's business: with the assembled K and a
!! lumped mass, windows of steps without output go in one sweep over K (ictus_solver_lumped_
!! sweeps); every other model takes single steps. Both give the same bits.
module ictus_solver_stepper
  use ictus_core_kinds, only: dp
  use ictus_core_logger, only: log_info
  use ictus_core_errors, only: warning
  use ictus_core_strings, only: str
  use ictus_parallel_env, only: env_size, allreduce_sum, allreduce_max, allreduce_min
  use ictus_elements_library, only: etype_name
  use ictus_contact_contact, only: contact_t, contact_failures
  use ictus_solver_model, only: model_t
  use ictus_solver_domain, only: domain_t
  use ictus_solver_assemble, only: operators_t
  use ictus_solver_mass_operator, only: mass_op_t
  use ictus_solver_internal_force, only: force_op_t, force_op_init, force_choice, &
      force_kind_name, force_stable, force_choice_note, FORCE_ASSEMBLED, FORCE_ELEMENT
  use ictus_solver_explicit, only: state_t, state_init, step_predict, step_finish, &
      between_steps_t, state_kinetic
  use ictus_solver_lumped_sweeps, only: lumped_sweeps_t, sweeps_plan, sweeps_window
  use ictus_solver_contact_step, only: contact_step_t, contact_correct, contact_ratio
  use ictus_solver_loads, only: loads_t, loads_init
  implicit none
  private
  public :: stepper_t, stepper_init, stepper_plan, stepper_record, stepper_advance, &
      stepper_done, stepper_estimate, stepper_settle, DT_REFRESH, DT_FLOOR

  !> With finite strain the stable step follows the state (doc/theory.md §7.1): it is
  !! estimated anew every DT_REFRESH steps, and a step below DT_FLOOR times the start-up step
  !! stops the run.
  integer, parameter :: DT_REFRESH = 10
  real(dp), parameter :: DT_FLOOR = 1.0e-3_dp

  type :: stepper_t
    !> The state of the run (u, v, history, energies, step counter).
    type(state_t) :: s
    !> The internal force.
    type(force_op_t) :: fop
    !> Sweeps of the linear lumped stepper (ls%on when planned).
    type(lumped_sweeps_t) :: ls
    !> What the steps act on, kept by the caller.
    type(model_t), pointer :: model => null()
    type(domain_t), pointer :: dom => null()
    type(operators_t), pointer :: ops => null()
    type(mass_op_t), pointer :: mop => null()
    type(contact_t), pointer :: contact => null()
    type(contact_step_t), pointer :: cs => null()
    !> Whether the predictor of the current step ran for a record and its contact correction
    !! and displacement update are still to come.
    logical :: pending = .false.
    !> Whether the contact correction of the pending step has run (stepper_settle).
    logical :: settled = .false.
    !> Contact: pairs that have been active (their first contact is logged once) and the
    !! closest-point projections that failed so far.
    logical, allocatable :: was_active(:)
    integer(8) :: failures = 0
    !> Why the last call stopped, when it failed at run time (empty otherwise).
    character(len=:), allocatable :: failure
    !> The stable step during the run: whether it follows the state (finite strain with the
    !! element loop), the start-up step, the end time, the step at which dt was last
    !! estimated, and the dt of the last log line about it.
    logical :: dt_control = .false.
    real(dp) :: dt0 = 0.0_dp
    real(dp) :: t_end = 0.0_dp
    integer :: dt_step = -1
    real(dp) :: dt_logged = 0.0_dp
  end type stepper_t

  !> The contact correction between the predictor and the update of a step inside a sweep.
  type, extends(between_steps_t) :: contact_hook_t
    type(stepper_t), pointer :: stp => null()
  contains
    procedure :: run => hook_run
  end type contact_hook_t

contains

  !> Sets up the internal force (the deck's INTERNAL FORCE=, or AUTO), the state at t = 0
  !! (prescribed u_0, v_0, the start-up half-step velocity) and the contact bookkeeping. The
  !! arguments stay with the caller and must outlive the stepper. ierr: 0, or the global
  !! index of an element whose geometry fails.
  subroutine stepper_init(stp, model, dom, ops, mop, contact, cs, dt, t_end, ierr)
    type(stepper_t), intent(out) :: stp
    type(model_t), target, intent(in) :: model
    type(domain_t), target, intent(inout) :: dom
    type(operators_t), target, intent(in) :: ops
    type(mass_op_t), target, intent(inout) :: mop
    type(contact_t), target, intent(inout) :: contact
    type(contact_step_t), target, intent(inout) :: cs
    real(dp), intent(in) :: dt, t_end
    integer, intent(out) :: ierr
    real(dp), allocatable :: alpha(:)
    type(loads_t) :: ld
    character(len=:), allocatable :: note
    stp%model => model
    stp%dom => dom
    stp%ops => ops
    stp%mop => mop
    stp%contact => contact
    stp%cs => cs
    stp%failure = ''
    allocate(stp%was_active(contact%npairs), source=.false.)
    call force_op_init(stp%fop, force_choice(model, ops%k), model, dom, ops%k, mop%consistent, &
        ierr)
    if (ierr /= 0) return
    note = force_choice_note(stp%fop%kind, model, ops)
    if (len(note) > 0) note = '; '//note
    call log_info('internal force: '//force_kind_name(stp%fop)//note)
    stp%dt0 = dt
    stp%dt_logged = dt
    stp%t_end = t_end
    stp%dt_control = stp%fop%kind == FORCE_ELEMENT .and. model%nlgeom
    if (stp%dt_control) call log_info('stable step: estimated every '//str(DT_REFRESH)// &
        ' steps from the current state (never above the start-up dt; the run stops below '// &
        '1/1000 of it)')
    allocate(alpha(dom%nlocal), source=0.0_dp)
    where (ops%m_pos > 0.0_dp) alpha = ops%c_diag/ops%m_pos
    call loads_init(ld, model, dom)
    if (ld%active) call log_info('loads: '//str(model%loads%nnodal)//' nodal and body '// &
        'loads, '//str(model%loads%npress)//' pressures, '//str(model%loads%nmotion)// &
        ' dofs with prescribed motion; every step takes the plain path (f_ext - f_int, '// &
        'mass solve), without fused steps or sweeps')
    call state_init(stp%s, stp%fop, mop, dom, model%u_fixed(:, dom%halo%gid), &
        model%v0(:, dom%halo%gid), alpha, ops%m_pos, dt, ld, model%fixed(:, dom%halo%gid))
    if (stp%s%ierr /= 0) stp%failure = 'the consistent-mass solve did not converge at the start'
  end subroutine stepper_init

  !> Plans the sweeps of the linear lumped stepper (assembled K, lumped mass) and logs the
  !! internal-force product; call once the state is final (after a restart's checkpoint).
  subroutine stepper_plan(stp)
    type(stepper_t), intent(inout) :: stp
    logical, allocatable :: sync(:)
    character(len=:), allocatable :: msg
    integer :: k
    if (stp%fop%kind == FORCE_ASSEMBLED .and. stp%mop%consistent) call log_product(stp%fop)
    if (stp%fop%kind /= FORCE_ASSEMBLED) return
    ! loads and prescribed motion take the plain step (ictus_solver_explicit)
    if (stp%s%loaded) return
    ! the contact nodes are touched between the steps of a sweep
    allocate(sync(stp%dom%nowned), source=.false.)
    if (stp%contact%npairs > 0) then
      do k = 1, stp%cs%ncn
        if (stp%cs%lnode(k) > 0) sync(stp%cs%lnode(k)) = .true.
      end do
    end if
    call sweeps_plan(stp%ls, stp%s, stp%ops%k, stp%mop, stp%dom, &
        stp%model%x0(:, stp%dom%halo%gid(1:stp%dom%nowned)), sync, stp%model%sweep_steps)
    if (.not. stp%ls%on) return
    msg = ''
    if (stp%ls%tuning) msg = '; timed against single steps first'
    if (stp%ls%tuning .and. stp%ls%has_wide) msg = msg//' and against wide strips'
    call log_info('sweeps: '//str(stp%ls%plan%nstage)//' steps per sweep over K between '// &
        'outputs ('//str(stp%ls%plan%strip)//' strips; '//str(stp%ls%plan%zone_rows(1))// &
        ' rows of '//str(stp%dom%nowned)//' stepped one step at a time)'//msg)
  end subroutine stepper_plan

  !> The predictor of the current step n with the energies at t_n (for a history record or a
  !! field); its contact correction and displacement update come with the next
  !! `stepper_advance`.
  subroutine stepper_record(stp)
    type(stepper_t), intent(inout) :: stp
    call refresh_dt(stp)
    if (len(stp%failure) > 0) return
    call step_predict(stp%s, stp%fop, stp%mop, stp%dom, .true.)
    stp%pending = .true.
    if (stp%s%ierr /= 0) stp%failure = 'the consistent-mass solve did not converge'
    call check_inverted(stp)
  end subroutine stepper_record

  !> The contact correction of a recorded step n right after its records have taken the
  !! contact results (those of the last evaluation), and the kinetic energy at t_n with the
  !! corrected v_{n+1/2} (doc/theory.md §4b) in s%e_kin; `stepper_advance` then only updates
  !! the displacements of that step. Without contact, or with no recorded step pending,
  !! nothing happens. At t_0 the kinetic energy stays that of the initial velocities v_0 (the
  !! predictor's mean is v_0 exactly): a contact active at t = 0 would otherwise add half of
  !! its first impulse to the initial energy.
  subroutine stepper_settle(stp)
    type(stepper_t), intent(inout) :: stp
    if (.not. stp%pending .or. stp%settled .or. stp%contact%npairs == 0) return
    call contact_between(stp)
    if (stp%s%step > 0) call state_kinetic(stp%s, stp%mop, stp%dom)
    stp%settled = .true.
  end subroutine stepper_settle

  !> Runs whole steps until the state is at step n_to (t_{n_to}): first the rest of a recorded
  !! step, then windows of one sweep where the linear lumped stepper has them, single steps
  !! otherwise. Stops early with stp%failure set on a run-time failure, and where the step
  !! follows the state, at the end time (`stepper_done`).
  subroutine stepper_advance(stp, n_to)
    type(stepper_t), target, intent(inout) :: stp
    integer, intent(in) :: n_to
    type(contact_hook_t) :: hook
    logical :: tuning
    hook%stp => stp
    if (stp%pending) then
      stp%pending = .false.
      if (.not. stp%settled) call contact_between(stp)
      stp%settled = .false.
      call step_finish(stp%s, stp%dom)
    end if
    do while (stp%s%step < n_to .and. len(stp%failure) == 0)
      if (stp%dt_control .and. stepper_done(stp)) exit
      if (stp%ls%on .and. stp%ls%kept .and. stp%s%step + stp%ls%plan%nstage <= n_to) then
        tuning = stp%ls%tuning
        call sweeps_window(stp%ls, stp%s, stp%fop, stp%mop, stp%dom, hook)
        if (tuning .and. .not. stp%ls%tuning) call log_tuning(stp%ls)
      else
        call refresh_dt(stp)
        if (len(stp%failure) > 0) return
        call step_predict(stp%s, stp%fop, stp%mop, stp%dom, .false.)
        if (stp%s%ierr /= 0) stp%failure = 'the consistent-mass solve did not converge'
        call check_inverted(stp)
        if (len(stp%failure) > 0) return
        call contact_between(stp)
        call step_finish(stp%s, stp%dom)
      end if
    end do
  end subroutine stepper_advance

  !> The contact correction of the current step, its failure count and the log line of a
  !! pair that becomes active (between the predictor and the displacement update).
  subroutine contact_between(stp)
    type(stepper_t), intent(inout) :: stp
    integer :: kp
    real(dp) :: r
    character(len=256) :: at
    if (stp%contact%npairs == 0) return
    call contact_correct(stp%cs, stp%contact, stp%s, stp%mop, stp%dom, stp%model%x0)
    if (stp%cs%ierr /= 0) stp%failure = 'the consistent-mass solve of the contact '// &
        'correction did not converge'
    stp%failures = stp%failures + contact_failures(stp%contact)
    do kp = 1, stp%contact%npairs
      associate (p => stp%contact%pairs(kp))
        ! the first step of the run with outside points: name the time, point and pair
        if (p%outside_points > 0 .and. p%outside_total == p%outside_points) call warning( &
            'contact', 'pair '//trim(p%name)//': '//str(p%outside_points)//' contact '// &
            'point(s) penetrate the other surface but project beyond its end, or left '// &
            'the search radius while penetrating (no force applied) at t = '// &
            str(stp%s%t + stp%s%dt)//'; the first at ('//outside_text(stp%contact, kp)// &
            ') on surface '// &
            trim(outside_surface(stp%contact, kp))//' near node '// &
            str(outside_node_id(stp%contact, kp))//'; extend the surfaces to cover the '// &
            'contact zone (counted per step in outside_points, doc/contact.md §3)')
      end associate
      if (stp%contact%pairs(kp)%active_points > 0 .and. .not. stp%was_active(kp)) then
        stp%was_active(kp) = .true.
        call contact_ratio(stp%cs, stp%contact, stp%model%x0, stp%s%u, stp%ops%m_pos, &
            stp%s%dt, r, at)
        call log_info('contact '//trim(stp%contact%pairs(kp)%name)//' becomes active at '// &
            't = '//str(stp%s%t + stp%s%dt)//'; stability ratio r = '//str(r, 4)//' ('// &
            trim(at)//')')
        if (r > 0.5_dp) call warning('contact', 'the stability ratio r = '//str(r, 4)// &
            ' exceeds 1/2 at '//trim(at))
      end if
    end do
  end subroutine contact_between

  !> Name of the surface of pair k that holds its first outside point.
  function outside_surface(c, k) result(name)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: k
    character(len=:), allocatable :: name
    integer :: i
    i = c%pairs(k)%first
    if (c%pairs(k)%outside_surf == 2) i = c%pairs(k)%second
    name = '?'
    if (i >= 1 .and. i <= c%nsurf) name = trim(c%surfaces(i)%name)
    if (c%ndm == 3 .and. i >= 1 .and. i <= c%d3%nsurf) name = trim(c%d3%names(i))
  end function outside_surface

  !> The coordinates of the first outside point of pair k, "x, y" or "x, y, z".
  function outside_text(c, k) result(text)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: k
    character(len=:), allocatable :: text
    text = str(c%pairs(k)%outside_x(1))//', '//str(c%pairs(k)%outside_x(2))
    if (c%ndm == 3) text = str(c%d3%pairs(k)%outside_x(1))//', '// &
        str(c%d3%pairs(k)%outside_x(2))//', '//str(c%d3%pairs(k)%outside_x(3))
  end function outside_text

  !> User id of the node nearest to the first outside point of pair k.
  pure integer function outside_node_id(c, k) result(id)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: k
    id = c%pairs(k)%outside_node
    if (allocated(c%node_id) .and. id >= 1) then
      if (id <= size(c%node_id)) id = c%node_id(id)
    end if
  end function outside_node_id

  !> The contact correction of a step inside a sweep.
  subroutine hook_run(this)
    class(contact_hook_t), intent(inout) :: this
    call contact_between(this%stp)
  end subroutine hook_run

  !> The stable step from t_n (where it follows the state, every DT_REFRESH steps): call it
  !! before deciding what is due at t_n, which with TIME INTERVAL= depends on the step that
  !! leaves t_n. The steps inside `stepper_advance` and `stepper_record` estimate it
  !! themselves (once per step).
  subroutine stepper_estimate(stp)
    type(stepper_t), intent(inout) :: stp
    call refresh_dt(stp)
  end subroutine stepper_estimate

  !> Whether the state has reached the end time (the last step ends at or just after it).
  pure logical function stepper_done(stp)
    type(stepper_t), intent(in) :: stp
    stepper_done = stp%s%t >= stp%t_end*(1.0_dp - 1.0e-12_dp)
  end function stepper_done

  !> The stable step of the current state, every DT_REFRESH steps where it follows the state
  !! (doc/theory.md §7.1): dt = dt0 min(1, s) with s the smallest factor of the elements
  !! (force_stable), the same on every rank. A line in the log when dt has moved by more than
  !! 10 % since the last one; below DT_FLOOR dt0 a run-time failure naming the element.
  subroutine refresh_dt(stp)
    type(stepper_t), intent(inout) :: stp
    real(dp) :: smin, sglob, dt
    integer :: kmin
    if (.not. stp%dt_control) return
    if (mod(stp%s%step, DT_REFRESH) /= 0 .or. stp%s%step == stp%dt_step) return
    stp%dt_step = stp%s%step
    call force_stable(stp%fop, stp%s%u, stp%s%hist, smin, kmin)
    sglob = smin
    call allreduce_min(sglob)
    if (smin > sglob) kmin = 0
    kmin = -kmin
    if (kmin == 0) kmin = -huge(1)
    call allreduce_max(kmin)
    kmin = -kmin
    dt = stp%dt0*min(1.0_dp, sglob)
    if (dt < DT_FLOOR*stp%dt0) then
      stp%failure = 'the stable time step fell to '//str(dt, 4)//', below '// &
          '1/1000 of the start-up step '//str(stp%dt0, 4)//', at '// &
          etype_name(stp%model%etype(kmin))//' element '//str(stp%model%elem_id(kmin))// &
          ' (squeezed to '//str(sglob, 4)//' of its wave transit time)'
      return
    end if
    stp%s%dt = dt
    if (abs(dt - stp%dt_logged) > 0.1_dp*stp%dt_logged) then
      stp%dt_logged = dt
      call log_info('stable step: dt = '//str(dt, 4)//' ('//str(dt/stp%dt0, 4)//' of the '// &
          'start-up step) at step '//str(stp%s%step)//', t = '//str(stp%s%t, 5)//'; set by '// &
          etype_name(stp%model%etype(kmin))//' element '//str(stp%model%elem_id(kmin)))
    end if
  end subroutine refresh_dt

  !> With finite strain, an element whose deformation gradient has det F <= 0 at a quadrature
  !! point (found by the last internal force, on any rank) is a run-time failure.
  subroutine check_inverted(stp)
    type(stepper_t), intent(inout) :: stp
    integer :: e
    if (stp%fop%kind /= FORCE_ELEMENT .or. .not. stp%model%nlgeom) return
    e = stp%fop%el%inverted
    call allreduce_max(e)
    if (e > 0) stp%failure = etype_name(stp%model%etype(e))//' element '// &
        str(stp%model%elem_id(e))//' is inverted (det F <= 0 at a quadrature point): the '// &
        'mesh is too distorted, or the time step too large for the current stiffness'
  end subroutine check_inverted

  !> The log line of the end of the SWEEP STEPS=AUTO timing.
  subroutine log_tuning(ls)
    type(lumped_sweeps_t), intent(in) :: ls
    character(len=:), allocatable :: msg, wmsg
    msg = 'dropped: single steps are faster'
    if (ls%kept) msg = 'kept: faster than single steps'
    if (ls%kept .and. ls%has_wide) msg = msg//', strips of '//str(ls%bytes/1024)//' KiB of K'
    wmsg = ''
    if (ls%has_wide) wmsg = ', '//str(1.0e3_dp*ls%tune_time(3), 3)//' ms in one sweep of '// &
        'wide strips'
    call log_info('sweeps: '//msg//' here (a window of '//str(ls%plan%nstage)// &
        ' steps in the best trial of each: '//str(1.0e3_dp*ls%tune_time(1), 3)// &
        ' ms in one sweep, '//str(1.0e3_dp*ls%tune_time(2), 3)//' ms one step at a '// &
        'time'//wmsg//')')
  end subroutine log_tuning

  !> The log line of the assembled product of a consistent-mass step: from K's upper blocks on
  !! ranks that hold all rows of their nodes' neighbours (one rank; a rank whose part has no
  !! ghosts), else from the full rows; the same bits either way.
  subroutine log_product(fop)
    type(force_op_t), intent(in) :: fop
    integer :: nup, nshort
    real(dp) :: mb
    nup = merge(1, 0, fop%asm%kup%n > 0)
    nshort = merge(1, 0, fop%asm%kup%short_of_memory)
    mb = 0.0_dp
    if (fop%asm%kup%n > 0) mb = 36.0_dp*real(size(fop%asm%kup%col), dp)/1.0e6_dp
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
end module ictus_solver_stepper
