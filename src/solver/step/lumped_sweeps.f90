!> The linear lumped stepper's private speed-ups: several undamped or damped lumped-mass steps
!! without output in one sweep over the assembled K (ictus_solver_sweep), and, with
!! SWEEP STEPS=AUTO, the timing that decides between sweeps and single steps at the start of a
!! run. Every choice gives the bits of single steps; only the speed depends on it.
!!
!! A plan keeps the rows of K that a sweep holds between a row's first and last stage within
!! the L2 cache (SWEEP_CACHE_BYTES), or within a wider band (SWEEP_WIDE_BYTES) where the last-
!! level cache serves it faster than memory; doc/performance.md §3.7 has the measurements.
module ictus_solver_lumped_sweeps
  use ictus_core_kinds, only: dp
  use ictus_core_memory, only: alloc_stream
  use ictus_core_timer, only: wall_time
  use ictus_parallel_env, only: allreduce_max, allreduce_or
  use ictus_parallel_halo, only: halo_exchange
  use ictus_solver_sparse, only: bsr_t
  use ictus_solver_mass_operator, only: mass_op_t
  use ictus_solver_domain, only: domain_t
  use ictus_solver_sweep, only: sweep_t, sweep_plan, sweep_zone_stage, sweep_rows, sweep_move
  use ictus_solver_internal_force, only: force_op_t
  use ictus_solver_explicit, only: state_t, step_predict, step_finish, between_steps_t, &
      add_damping_work
  implicit none
  private
  public :: lumped_sweeps_t, sweeps_plan, sweeps_window, sweeps_run, tune_kinds, &
      SWEEP_TUNE_ROUNDS, SWEEP_AUTO_STEPS

  !> Bytes of K the rows of a sweep may hold between a row's first and last stage: what stays
  !! in a 2 MiB L2 cache next to the vectors. With SWEEP STEPS=AUTO a second plan with
  !! SWEEP_WIDE_BYTES is timed too, and kept where it is faster.
  integer, parameter :: SWEEP_CACHE_BYTES = 786432
  integer, parameter :: SWEEP_WIDE_BYTES = 4194304

  !> Trials of each kind before a run settles on sweeps (of the plan with SWEEP_CACHE_BYTES or
  !! the one with SWEEP_WIDE_BYTES) or single steps (SWEEP STEPS=AUTO), and windows per trial:
  !! the first window of a trial warms up, the others are timed, and the best trial of each
  !! kind is compared (single windows between the other kind's mislead where K sits in the
  !! last-level cache).
  integer, parameter :: SWEEP_TUNE_ROUNDS = 3, SWEEP_TUNE_WINDOWS = 4
  !> Steps per sweep with SWEEP STEPS=AUTO.
  integer, parameter :: SWEEP_AUTO_STEPS = 6

  type :: lumped_sweeps_t
    !> The plan (plan%nstage steps per sweep), when sweeps are possible (`on`), and the bytes
    !! of K its strips hold between a row's first and last stage.
    type(sweep_t) :: plan
    logical :: on = .false.
    integer :: bytes = 0
    !> Whether windows of plan%nstage steps without output run as one sweep (`kept`) or as
    !! single steps. With SWEEP STEPS=AUTO (`tuning`), the first windows run as trials of
    !! SWEEP_TUNE_WINDOWS windows each, cycling through the kinds (single steps, sweeps, and
    !! where its strips differ sweeps of the wide plan `plan_wide`), timed (`tune_acc`;
    !! `tune_time`: best seconds per window of a trial of each kind, the slowest rank's), and
    !! the fastest is kept (the wide plan then becomes `plan`). All give the same bits.
    logical :: kept = .true.
    logical :: tuning = .false.
    type(sweep_t) :: plan_wide
    logical :: has_wide = .false.
    integer :: tune_count = 0
    real(dp) :: tune_acc = 0.0_dp
    real(dp) :: tune_time(3) = huge(1.0_dp)
  end type lumped_sweeps_t

contains

  !> Plans sweeps of nstage steps for a lumped-mass state (otherwise, or for
  !! nstage = 1, ls%on stays false). nstage = 0 (SWEEP STEPS=AUTO) plans SWEEP_AUTO_STEPS,
  !! also with the wide budget, and lets step_window time the sweeps against single steps
  !! before it keeps one of them. x(2, nowned): coordinates of the owned nodes (the strips
  !! follow them); sync(nowned): nodes touched between steps (contact nodes).
  subroutine sweeps_plan(ls, s, k, mop, dom, x, sync, nstage)
    type(lumped_sweeps_t), intent(inout) :: ls
    type(state_t), intent(inout) :: s
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(in) :: mop
    type(domain_t), intent(in) :: dom
    real(dp), intent(in) :: x(:,:)
    logical, intent(in) :: sync(:)
    integer, intent(in) :: nstage
    logical, allocatable :: touched(:)
    real(dp) :: row_bytes
    integer :: window, wide, i, ns
    ns = merge(SWEEP_AUTO_STEPS, nstage, nstage == 0)
    ! on every rank alike, one that owns no node included (its plan is empty): the exchanges
    ! between steps and the tuning's sums must match
    ! (2 x 2 blocks only: a 3D K steps one step at a time, with the fused lumped step)
    ls%on = ns > 1 .and. .not. mop%consistent .and. size(k%val, 1) == 2
    ls%kept = ls%on
    ls%tuning = ls%on .and. nstage == 0
    ls%has_wide = .false.
    ls%tune_count = 0
    ls%tune_acc = 0.0_dp
    ls%tune_time = huge(1.0_dp)
    if (.not. ls%on) return
    ! about SWEEP_CACHE_BYTES of K between a row's stage 1 and its last stage
    row_bytes = 36.0_dp*real(max(1, size(k%g%col)), dp)/real(max(1, s%nn), dp)
    window = max(32, int(real(SWEEP_CACHE_BYTES, dp)/(real(ns - 1, dp)*row_bytes)))
    ! the nodes the halo exchange sends take part between steps too
    touched = sync(1:s%nn)
    do i = 1, size(dom%halo%send_idx)
      touched(dom%halo%send_idx(i)) = .true.
    end do
    call sweep_plan(ls%plan, k%g, ns, window, x, touched)
    ls%bytes = SWEEP_CACHE_BYTES
    ! the damping power of every stage, summed after the sweep
    if (s%damped) then
      deallocate(s%pw)
      call alloc_stream(s%pw, 2, s%nn, ls%plan%nstage, 0.0_dp)
    end if
    if (.not. ls%tuning) return
    ! the wide plan, where its strips are fewer (on every rank alike: the count of trials
    ! must agree)
    wide = max(32, int(real(SWEEP_WIDE_BYTES, dp)/(real(ns - 1, dp)*row_bytes)))
    call sweep_plan(ls%plan_wide, k%g, ns, wide, x, touched)
    ls%has_wide = ls%plan_wide%strip < ls%plan%strip
    call allreduce_or(ls%has_wide)
  end subroutine sweeps_plan

  !> The number of kinds the tuning of SWEEP STEPS=AUTO times: single steps and sweeps, and
  !! the wide sweeps where planned.
  pure integer function tune_kinds(ls)
    type(lumped_sweeps_t), intent(in) :: ls
    tune_kinds = merge(3, 2, ls%has_wide)
  end function tune_kinds

  !> ls%plan%nstage lumped-mass steps without output in one sweep over K: for each
  !! step, the zone rows (ghost neighbours, contact nodes and the rows around them), then
  !! `between` (the contact correction), the halo exchange and the swap of u and u_next, as
  !! in step_predict + step_finish; then all steps on the other rows. The same bits as that
  !! many single steps. Needs ls%on.
  subroutine sweeps_run(ls, s, k, mop, dom, between, wide)
    type(lumped_sweeps_t), intent(in) :: ls
    type(state_t), intent(inout) :: s
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(in) :: mop
    type(domain_t), intent(inout) :: dom
    class(between_steps_t), intent(inout) :: between
    logical, intent(in), optional :: wide
    if (present(wide)) then
      if (wide) then
        call sweep_steps(s, ls%plan_wide, k, mop, dom, between)
        return
      end if
    end if
    call sweep_steps(s, ls%plan, k, mop, dom, between)
  end subroutine sweeps_run

  !> sweeps_run with the plan sw (ls%plan or ls%plan_wide, which it does not change).
  subroutine sweep_steps(s, sw, k, mop, dom, between)
    type(state_t), intent(inout) :: s
    type(sweep_t), intent(in) :: sw
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(in) :: mop
    type(domain_t), intent(inout) :: dom
    class(between_steps_t), intent(inout) :: between
    real(dp), allocatable :: swap(:,:)
    integer :: st
    do st = 1, sw%nstage
      if (s%damped) then
        call sweep_zone_stage(sw, st, k%g%row_ptr, k%g%col, k%val, mop%inv_diag, s%dt, s%u, &
            s%v, s%u_next, s%alpha, s%m_pos, s%pw)
      else
        call sweep_zone_stage(sw, st, k%g%row_ptr, k%g%col, k%val, mop%inv_diag, s%dt, s%u, &
            s%v, s%u_next)
      end if
      s%fused = .true.
      call between%run()
      call halo_exchange(dom%halo, s%u_next)
      call move_alloc(s%u, swap)
      call move_alloc(s%u_next, s%u)
      call move_alloc(swap, s%u_next)
      s%step = s%step + 1
      s%t = s%t + s%dt
    end do
    ! the arrays of stage 0 (a) and stage 1 (b): after an even number of swaps s%u is a
    if (s%damped) then
      if (mod(sw%nstage, 2) == 0) then
        call sweep_rows(sw, k%g%row_ptr, k%g%col, k%val, mop%inv_diag, s%dt, s%u, &
            s%u_next, s%v, s%alpha, s%m_pos, s%pw)
      else
        call sweep_rows(sw, k%g%row_ptr, k%g%col, k%val, mop%inv_diag, s%dt, s%u_next, &
            s%u, s%v, s%alpha, s%m_pos, s%pw)
      end if
      ! the damping work of each step, in step order
      do st = 1, sw%nstage
        call add_damping_work(s, s%step - sw%nstage + st - 1, st)
      end do
    else if (mod(sw%nstage, 2) == 0) then
      call sweep_rows(sw, k%g%row_ptr, k%g%col, k%val, mop%inv_diag, s%dt, s%u, &
          s%u_next, s%v)
    else
      call sweep_rows(sw, k%g%row_ptr, k%g%col, k%val, mop%inv_diag, s%dt, s%u_next, &
          s%u, s%v)
    end if
  end subroutine sweep_steps

  !> ls%plan%nstage lumped-mass steps without output (needs ls%on): one sweep,
  !! or single steps (step_predict, `between`, step_finish) when the tuning chose them. While
  !! ls%tuning, the windows go in trials of SWEEP_TUNE_WINDOWS, cycling through the kinds
  !! (single steps, sweeps, wide sweeps where planned); after SWEEP_TUNE_ROUNDS trials of
  !! each, the best trials (the slowest rank's times, so every rank decides the same) decide
  !! ls%kept and the plan. Only the speed depends on the choice: the bits are the same.
  subroutine sweeps_window(ls, s, fop, mop, dom, between)
    type(lumped_sweeps_t), intent(inout) :: ls
    type(state_t), intent(inout) :: s
    type(force_op_t), intent(inout) :: fop
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    class(between_steps_t), intent(inout) :: between
    real(dp) :: t0, t
    integer :: mode, j, w, nk
    integer, parameter :: order(3) = [2, 1, 3]
    type(sweep_t) :: unused
    w = 0
    nk = tune_kinds(ls)
    if (.not. ls%tuning) then
      mode = merge(1, 2, ls%kept)
    else
      ! trials of single steps first, then sweeps, then wide sweeps; w = window in the trial
      ! (0: warm-up, not timed)
      mode = order(mod(ls%tune_count/SWEEP_TUNE_WINDOWS, nk) + 1)
      w = mod(ls%tune_count, SWEEP_TUNE_WINDOWS)
    end if
    t0 = wall_time()
    if (mode == 2) then
      do j = 1, ls%plan%nstage
        call step_predict(s, fop, mop, dom, .false.)
        call between%run()
        call step_finish(s, dom)
      end do
    else
      call sweeps_run(ls, s, fop%asm%k, mop, dom, between, wide=mode == 3)
    end if
    if (.not. ls%tuning) return
    if (w > 0) ls%tune_acc = ls%tune_acc + (wall_time() - t0)
    ls%tune_count = ls%tune_count + 1
    if (w < SWEEP_TUNE_WINDOWS - 1) return
    ! the end of a trial
    t = ls%tune_acc/(SWEEP_TUNE_WINDOWS - 1)
    call allreduce_max(t)
    ls%tune_time(mode) = min(ls%tune_time(mode), t)
    ls%tune_acc = 0.0_dp
    if (ls%tune_count < nk*SWEEP_TUNE_ROUNDS*SWEEP_TUNE_WINDOWS) return
    ls%tuning = .false.
    mode = minloc(ls%tune_time(1:nk), 1)
    ls%kept = mode /= 2
    if (mode == 3) then
      call sweep_move(ls%plan_wide, ls%plan)
      ls%bytes = SWEEP_WIDE_BYTES
    else
      ! the wide plan is not needed any more
      call sweep_move(ls%plan_wide, unused)
    end if
  end subroutine sweeps_window
end module ictus_solver_lumped_sweeps
