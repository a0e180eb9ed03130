!> One central-difference step in the predictor-corrector form of physics.md §4.1:
!!
!!     a_pre   = M^-1 (R_n - K u_n)              (with mass-proportional damping, see below)
!!     v_pre   = v_{n-1/2} + dt a_pre
!!     u_pre   = u_n + dt v_pre                  (contact is evaluated on u_pre)
!!     a_cor   = M^-1 F_c(u_pre)
!!     v_{n+1/2} = v_pre + dt a_cor
!!     u_{n+1} = u_n + dt v_{n+1/2}
!!
!! The step is split in two: `step_predict` (up to v_pre, plus the energies at t_n when asked)
!! and `step_finish` (u_{n+1}); the contact correction of v goes between them.
!! Damping: the force -alpha M v with v at t_n = (v_{n-1/2} + v_{n+1/2})/2 gives
!! v_pre = ((1 - alpha dt/2) v_{n-1/2} + dt a) / (1 + alpha dt/2) node by node, where alpha is
!! the mass-weighted mean of the element coefficients around the node.
!! Vectors hold this rank's owned nodes followed by its ghosts; updates run over owned nodes
!! and `step_finish` refreshes the ghost displacements. The step allocates nothing.
!! Without output the predictor takes a fused path that also computes u_pre = u_n + dt v_pre
!! (s%u_next, swapped in by `step_finish`): for a lumped mass one pass over K
!! (`fused_lumped_step`, or `fused_lumped_rows` with damping, which also leaves the terms of
!! the damping power per node), for an undamped consistent mass solved along the lattice
!! directions on one rank the updates inside the solve's last pass (`mass_step`); all with
!! the bits of the unfused step.
!! `step_sweep` runs several lumped-mass steps without output in one sweep over K
!! (ictus_solver_sweep), with the same bits as the same number of single steps.
module ictus_solver_explicit
  use ictus_core_kinds, only: dp
  use ictus_core_memory, only: alloc_stream
  use ictus_parallel_repro, only: repro_dot, repro_sum
  use ictus_parallel_halo, only: halo_exchange
  use ictus_parallel_env, only: allreduce_max, allreduce_or
  use ictus_core_timer, only: wall_time
  use ictus_solver_sparse, only: bsr_t, bsr_matvec, fused_lumped_step, fused_lumped_rows, &
      bsr_upper_t, bsr_upper_init, bsr_matvec_ordered, bsr_upper_matvec
  use ictus_solver_mass_operator, only: mass_op_t, mass_solve, mass_apply, mass_step, &
      mass_steps_fused
  use ictus_solver_domain, only: domain_t
  use ictus_solver_sweep, only: sweep_t, sweep_plan, sweep_zone_stage, sweep_rows, sweep_move
  implicit none
  private
  public :: state_t, state_init, step_predict, step_finish, state_energies, state_plan_sweep, &
      step_sweep, step_window, between_steps, SWEEP_TUNE_ROUNDS, SWEEP_AUTO_STEPS, &
      tune_kinds, stiffness_product

  !> Bytes of K the rows of a sweep may hold between a row's first and last stage: what stays
  !! in a 2 MiB L2 cache next to the vectors (measured: doc/performance.md §3.7). With
  !! SWEEP STEPS=AUTO a second plan with SWEEP_WIDE_BYTES is timed too: where the last-level
  !! cache serves a wider band of rows much faster than memory (a 32 MiB L3 next to a 2 MiB
  !! L2: 1.2-1.3 x faster sweeps, §3.7) it wins, elsewhere it loses and is dropped.
  integer, parameter :: SWEEP_CACHE_BYTES = 786432
  integer, parameter :: SWEEP_WIDE_BYTES = 4194304

  !> Trials of each kind before a run settles on sweeps (of the plan with SWEEP_CACHE_BYTES or
  !! the one with SWEEP_WIDE_BYTES) or single steps (SWEEP STEPS=AUTO), and windows per trial:
  !! the first window of a trial warms up, the others are timed, and the best trial of each
  !! kind is compared. (Single windows between the other kind's mislead: on a mesh whose K
  !! sits in the L3 cache they showed sweeps as fast as single steps, which were 1.5 x faster
  !! run after run.)
  integer, parameter :: SWEEP_TUNE_ROUNDS = 3, SWEEP_TUNE_WINDOWS = 4
  !> Steps per sweep with SWEEP STEPS=AUTO (the best on both hosts measured, §3.7).
  integer, parameter :: SWEEP_AUTO_STEPS = 6

  abstract interface
    !> Work between the predictor and the displacement update of a step inside a sweep (the
    !! contact correction), on s%u = u_n, s%v = v_pre and s%u_next = u_pre.
    subroutine between_steps()
    end subroutine between_steps
  end interface

  type :: state_t
    !> Owned nodes and local nodes (owned + ghosts).
    integer :: nn = 0
    integer :: nlocal = 0
    integer :: nglobal = 0
    !> Step counter n and time t_n of the displacement `u`.
    integer :: step = 0
    real(dp) :: t = 0.0_dp
    real(dp) :: dt = 0.0_dp
    !> u_n (2, nlocal); v_{n-1/2} before a step and v_{n+1/2} after it; last acceleration a.
    real(dp), allocatable :: u(:,:), v(:,:), a(:,:)
    !> Work: force vector, previous half-step velocity, mean velocity, M v.
    real(dp), allocatable :: f(:,:), v_old(:,:), v_mid(:,:), mv(:,:)
    !> Damping coefficient per node, the positive nodal masses it acts on, and whether any
    !! coefficient is non-zero.
    real(dp), allocatable :: alpha(:)
    real(dp), allocatable :: m_pos(:)
    logical :: damped = .false.
    !> Terms of the damping power at t_n per node, (2, nn, stage): left by the fused damped
    !! step (stage 1) and by each stage of a damped sweep, summed by `add_damping_work`.
    real(dp), allocatable :: pw(:,:,:)
    !> Energies at time t_n of the last step that computed them.
    real(dp) :: e_kin = 0.0_dp, e_strain = 0.0_dp, e_contact = 0.0_dp, w_ext = 0.0_dp
    real(dp) :: e_time = 0.0_dp
    !> Work of external and damping forces from t = 0 to t_n, and the damping power at t_{n-1}.
    real(dp) :: w_acc = 0.0_dp
    real(dp) :: pw_prev = 0.0_dp
    !> Non-zero when the last mass solve failed.
    integer :: ierr = 0
    !> u_{n+1} computed by the fused lumped-mass predictor (2, nlocal), and whether the
    !! current step took that path (then step_finish swaps it in).
    real(dp), allocatable :: u_next(:,:)
    logical :: fused = .false.
    !> The plan of `step_sweep` (sweep%nstage steps per sweep), when sweeps are possible, and
    !! the bytes of K its strips hold between a row's first and last stage.
    type(sweep_t) :: sweep
    logical :: sweeps = .false.
    integer :: sweep_bytes = 0
    !> Whether windows of sweep%nstage steps without output run as one sweep (`kept`) or as
    !! single steps. With SWEEP STEPS=AUTO (`tuning`), the first windows run as trials of
    !! SWEEP_TUNE_WINDOWS windows each, cycling through the kinds (single steps, sweeps, and
    !! where its strips differ sweeps of the wide plan `sweep_wide`), timed (`tune_acc`;
    !! `tune_time`: best seconds per window of a trial of each kind, the slowest rank's), and
    !! the fastest is kept (the wide plan then becomes `sweep`). All give the same bits.
    logical :: kept = .true.
    logical :: tuning = .false.
    type(sweep_t) :: sweep_wide
    logical :: has_wide = .false.
    integer :: tune_count = 0
    real(dp) :: tune_acc = 0.0_dp
    real(dp) :: tune_time(3) = huge(1.0_dp)
    !> With a consistent mass, whether K u is summed in column order (`stiffness_product`),
    !! and K's upper blocks when one rank holds all rows (kup%n > 0; half the bytes).
    logical :: ordered = .false.
    type(bsr_upper_t) :: kup
  end type state_t

contains

  !> Sets u_0 (prescribed displacements), v_0 and the start-up half-step velocity
  !! v_{-1/2} = v_0 - dt/2 a_0 with a_0 = M^-1(-K u_0). Arrays are local (2, nlocal) /
  !! (nlocal). `alpha` are the nodal damping coefficients, `m_pos` the positive diagonal
  !! masses that weigh the damping work.
  subroutine state_init(s, k, mop, dom, u0, v0, alpha, m_pos, dt)
    type(state_t), intent(out) :: s
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: u0(:,:), v0(:,:), alpha(:), m_pos(:), dt
    integer :: nn, nl
    nn = dom%nowned
    nl = dom%nlocal
    s%nn = nn
    s%nlocal = nl
    s%nglobal = dom%nn_global
    s%dt = dt
    call alloc_stream(s%u, 2, nl, 0.0_dp)
    call alloc_stream(s%v, 2, nl, 0.0_dp)
    call alloc_stream(s%f, 2, nl, 0.0_dp)
    call alloc_stream(s%v_old, 2, nl, 0.0_dp)
    call alloc_stream(s%v_mid, 2, nl, 0.0_dp)
    call alloc_stream(s%mv, 2, nl, 0.0_dp)
    call alloc_stream(s%a, 2, nl, 0.0_dp)
    call alloc_stream(s%u_next, 2, nl, 0.0_dp)
    s%u = u0
    s%alpha = alpha(1:nn)
    s%m_pos = m_pos(1:nn)
    ! on every rank alike: the damped step has a global sum (the damping power), and a rank
    ! whose nodes have no damping takes the damped update with h = 0, the undamped bits
    s%damped = any(alpha(1:nn) /= 0.0_dp)
    call allreduce_or(s%damped)
    if (s%damped) call alloc_stream(s%pw, 2, nn, 1, 0.0_dp)
    s%ordered = mop%consistent
    if (s%ordered) call bsr_upper_init(k, s%kup)
    call stiffness_product(s, k, s%u, s%f)
    s%f(:, 1:nn) = -s%f(:, 1:nn)
    call mass_solve(mop, dom, s%f, s%a, s%ierr)
    s%v = 0.0_dp
    s%v(:, 1:nn) = (v0(:, 1:nn) - 0.5_dp*dt*s%a(:, 1:nn))*mop%free(:, 1:nn)
  end subroutine state_init

  !> y = K x on the owned rows as the steps take it: with a lumped mass the product of the
  !! fused lumped kernels (`bsr_matvec`, two chains per row); with a consistent mass (whose
  !! step has no such kernel) summed in column order, from K's upper blocks where one rank
  !! holds all rows (`bsr_upper_matvec`: about half the bytes, 0.6-0.7 of the time beyond
  !! the caches) and from the full rows otherwise (`bsr_matvec_ordered`), the same bits.
  subroutine stiffness_product(s, k, x, y)
    type(state_t), intent(in) :: s
    type(bsr_t), intent(in) :: k
    real(dp), intent(in) :: x(2, *)
    real(dp), intent(inout) :: y(2, *)
    if (.not. s%ordered) then
      call bsr_matvec(s%nn, k%g%row_ptr, k%g%col, k%val, x, y)
    else if (s%kup%n > 0) then
      call bsr_upper_matvec(s%kup, x, y)
    else
      call bsr_matvec_ordered(s%nn, k%g%row_ptr, k%g%col, k%val, x, y)
    end if
  end subroutine stiffness_product

  !> First half of a step: internal force at u_n, predictor acceleration and velocity
  !! v_{n+1/2} (before any contact correction). With `record`, also the mean velocity
  !! v_n = (v_{n-1/2} + v_{n+1/2})/2 in s%v_mid and the energies at t_n.
  subroutine step_predict(s, k, mop, dom, record)
    type(state_t), intent(inout) :: s
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    logical, intent(in) :: record
    integer :: i, nn
    real(dp) :: dt, h, pw
    nn = s%nn
    dt = s%dt
    ! a damped consistent step takes the unfused path below
    s%fused = .not. (record .or. (s%damped .and. mop%consistent))
    if (s%fused .and. .not. mop%consistent) then
      ! the common step in one pass over memory (same operations in the same order as below)
      if (s%damped) then
        call fused_lumped_rows(1, nn, k%g%row_ptr, k%g%col, k%val, mop%inv_diag, dt, s%u, &
            s%v, s%u_next, s%alpha, s%m_pos, s%pw)
        call add_damping_work(s, s%step, 1)
      else
        call fused_lumped_step(nn, k%g%row_ptr, k%g%col, k%val, mop%inv_diag, dt, s%u, s%v, &
            s%u_next)
      end if
      return
    end if
    if (s%fused .and. mass_steps_fused(mop)) then
      ! consistent mass on one rank: the updates of v and u_{n+1} inside the solve's last
      ! pass (same operations as below; s%f holds +K u_n, s%a is not computed)
      call stiffness_product(s, k, s%u, s%f)
      call mass_step(mop, s%f, dt, s%u, s%v, s%u_next)
      return
    end if
    s%fused = .false.
    call stiffness_product(s, k, s%u, s%f)
    s%f(:, 1:nn) = -s%f(:, 1:nn)
    call mass_solve(mop, dom, s%f, s%a, s%ierr)
    ! v_{n-1/2} is needed only for the mean velocity (damping, energies)
    if (s%damped .or. record) s%v_old(:, 1:nn) = s%v(:, 1:nn)
    if (s%damped) then
      do i = 1, nn
        h = 0.5_dp*s%alpha(i)*dt
        s%v(:, i) = ((1.0_dp - h)*s%v(:, i) + dt*s%a(:, i))/(1.0_dp + h)
      end do
    else
      s%v(:, 1:nn) = s%v(:, 1:nn) + dt*s%a(:, 1:nn)
    end if
    if (s%damped .or. record) s%v_mid(:, 1:nn) = 0.5_dp*(s%v_old(:, 1:nn) + s%v(:, 1:nn))
    if (s%damped) then
      ! power of the damping force -alpha M v at t_n (lumped, node by node), integrated by
      ! the trapezoidal rule: w_acc = work from 0 to t_n
      do i = 1, nn
        s%mv(:, i) = -s%alpha(i)*s%m_pos(i)*s%v_mid(:, i)
      end do
      pw = repro_dot(nn, s%mv, s%v_mid, s%nglobal)
      if (s%step > 0) s%w_acc = s%w_acc + 0.5_dp*dt*(s%pw_prev + pw)
      s%pw_prev = pw
    end if
    if (record) call state_energies(s, mop, dom)
  end subroutine step_predict

  !> Adds the work of the damping forces from t_{n-1} to t_n to s%w_acc (trapezoidal rule)
  !! with the power at t_n summed from s%pw(:, :, stage), the terms the fused damped step of
  !! step n left there; n = 0 only sets the power. The same sum, in the same order, as the
  !! repro_dot of the unfused step.
  subroutine add_damping_work(s, n, stage)
    type(state_t), intent(inout) :: s
    integer, intent(in) :: n, stage
    real(dp) :: pw
    pw = repro_sum(2*s%nn, s%pw(:, :, stage), 2*s%nglobal)
    if (n > 0) s%w_acc = s%w_acc + 0.5_dp*s%dt*(s%pw_prev + pw)
    s%pw_prev = pw
  end subroutine add_damping_work

  !> Second half of a step: u_{n+1} = u_n + dt v_{n+1/2}, t_{n+1} = t_n + dt, and the ghost
  !! displacements refreshed. Contact corrections of v_{n+1/2} (evaluated on
  !! u_pre = u_n + dt v_pre) come before this.
  subroutine step_finish(s, dom)
    type(state_t), intent(inout) :: s
    type(domain_t), intent(inout) :: dom
    real(dp), allocatable :: swap(:,:)
    if (s%fused) then
      ! u_next is complete on the owned nodes: exchange the arrays (no copy, no allocation)
      call move_alloc(s%u, swap)
      call move_alloc(s%u_next, s%u)
      call move_alloc(swap, s%u_next)
    else
      s%u(:, 1:s%nn) = s%u(:, 1:s%nn) + s%dt*s%v(:, 1:s%nn)
    end if
    call halo_exchange(dom%halo, s%u)
    s%step = s%step + 1
    s%t = s%t + s%dt
  end subroutine step_finish

  !> Plans sweeps of nstage steps for a lumped-mass state (otherwise, or for
  !! nstage = 1, s%sweeps stays false). nstage = 0 (SWEEP STEPS=AUTO) plans SWEEP_AUTO_STEPS,
  !! also with the wide budget, and lets step_window time the sweeps against single steps
  !! before it keeps one of them. x(2, nowned): coordinates of the owned nodes (the strips
  !! follow them); sync(nowned): nodes touched between steps (contact nodes).
  subroutine state_plan_sweep(s, k, mop, dom, x, sync, nstage)
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
    s%sweeps = ns > 1 .and. .not. mop%consistent
    s%kept = s%sweeps
    s%tuning = s%sweeps .and. nstage == 0
    s%has_wide = .false.
    s%tune_count = 0
    s%tune_acc = 0.0_dp
    s%tune_time = huge(1.0_dp)
    if (.not. s%sweeps) return
    ! about SWEEP_CACHE_BYTES of K between a row's stage 1 and its last stage
    row_bytes = 36.0_dp*real(max(1, size(k%g%col)), dp)/real(max(1, s%nn), dp)
    window = max(32, int(real(SWEEP_CACHE_BYTES, dp)/(real(ns - 1, dp)*row_bytes)))
    ! the nodes the halo exchange sends take part between steps too
    touched = sync(1:s%nn)
    do i = 1, size(dom%halo%send_idx)
      touched(dom%halo%send_idx(i)) = .true.
    end do
    call sweep_plan(s%sweep, k%g, ns, window, x, touched)
    s%sweep_bytes = SWEEP_CACHE_BYTES
    ! the damping power of every stage, summed after the sweep
    if (s%damped) then
      deallocate(s%pw)
      call alloc_stream(s%pw, 2, s%nn, s%sweep%nstage, 0.0_dp)
    end if
    if (.not. s%tuning) return
    ! the wide plan, where its strips are fewer (on every rank alike: the count of trials
    ! must agree)
    wide = max(32, int(real(SWEEP_WIDE_BYTES, dp)/(real(ns - 1, dp)*row_bytes)))
    call sweep_plan(s%sweep_wide, k%g, ns, wide, x, touched)
    s%has_wide = s%sweep_wide%strip < s%sweep%strip
    call allreduce_or(s%has_wide)
  end subroutine state_plan_sweep

  !> The number of kinds the tuning of SWEEP STEPS=AUTO times: single steps and sweeps, and
  !! the wide sweeps where planned.
  pure integer function tune_kinds(s)
    type(state_t), intent(in) :: s
    tune_kinds = merge(3, 2, s%has_wide)
  end function tune_kinds

  !> s%sweep%nstage lumped-mass steps without output in one sweep over K: for each
  !! step, the zone rows (ghost neighbours, contact nodes and the rows around them), then
  !! `between` (the contact correction), the halo exchange and the swap of u and u_next, as
  !! in step_predict + step_finish; then all steps on the other rows. The same bits as that
  !! many single steps. Needs s%sweeps.
  subroutine step_sweep(s, k, mop, dom, between, wide)
    type(state_t), intent(inout) :: s
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(in) :: mop
    type(domain_t), intent(inout) :: dom
    procedure(between_steps) :: between
    logical, intent(in), optional :: wide
    if (present(wide)) then
      if (wide) then
        call sweep_steps(s, s%sweep_wide, k, mop, dom, between)
        return
      end if
    end if
    call sweep_steps(s, s%sweep, k, mop, dom, between)
  end subroutine step_sweep

  !> step_sweep with the plan sw (s%sweep or s%sweep_wide, which it does not change).
  subroutine sweep_steps(s, sw, k, mop, dom, between)
    type(state_t), intent(inout) :: s
    type(sweep_t), intent(in) :: sw
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(in) :: mop
    type(domain_t), intent(inout) :: dom
    procedure(between_steps) :: between
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
      call between()
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

  !> s%sweep%nstage lumped-mass steps without output (needs s%sweeps): one sweep,
  !! or single steps (step_predict, `between`, step_finish) when the tuning chose them. While
  !! s%tuning, the windows go in trials of SWEEP_TUNE_WINDOWS, cycling through the kinds
  !! (single steps, sweeps, wide sweeps where planned); after SWEEP_TUNE_ROUNDS trials of
  !! each, the best trials (the slowest rank's times, so every rank decides the same) decide
  !! s%kept and the plan. Only the speed depends on the choice: the bits are the same.
  subroutine step_window(s, k, mop, dom, between)
    type(state_t), intent(inout) :: s
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    procedure(between_steps) :: between
    real(dp) :: t0, t
    integer :: mode, j, w, nk
    integer, parameter :: order(3) = [2, 1, 3]
    type(sweep_t) :: unused
    w = 0
    nk = tune_kinds(s)
    if (.not. s%tuning) then
      mode = merge(1, 2, s%kept)
    else
      ! trials of single steps first, then sweeps, then wide sweeps; w = window in the trial
      ! (0: warm-up, not timed)
      mode = order(mod(s%tune_count/SWEEP_TUNE_WINDOWS, nk) + 1)
      w = mod(s%tune_count, SWEEP_TUNE_WINDOWS)
    end if
    t0 = wall_time()
    if (mode == 2) then
      do j = 1, s%sweep%nstage
        call step_predict(s, k, mop, dom, .false.)
        call between()
        call step_finish(s, dom)
      end do
    else
      call step_sweep(s, k, mop, dom, between, wide=mode == 3)
    end if
    if (.not. s%tuning) return
    if (w > 0) s%tune_acc = s%tune_acc + (wall_time() - t0)
    s%tune_count = s%tune_count + 1
    if (w < SWEEP_TUNE_WINDOWS - 1) return
    ! the end of a trial
    t = s%tune_acc/(SWEEP_TUNE_WINDOWS - 1)
    call allreduce_max(t)
    s%tune_time(mode) = min(s%tune_time(mode), t)
    s%tune_acc = 0.0_dp
    if (s%tune_count < nk*SWEEP_TUNE_ROUNDS*SWEEP_TUNE_WINDOWS) return
    s%tuning = .false.
    mode = minloc(s%tune_time(1:nk), 1)
    s%kept = mode /= 2
    if (mode == 3) then
      call sweep_move(s%sweep_wide, s%sweep)
      s%sweep_bytes = SWEEP_WIDE_BYTES
    else
      ! the wide plan is not needed any more
      call sweep_move(s%sweep_wide, unused)
    end if
  end subroutine step_window

  !> Kinetic energy 1/2 v·M v with v at t_n, strain energy 1/2 u_n·K u_n = -1/2 u_n·f,
  !! recorded for time t_n. Needs s%f = -K u_n and s%v_mid set by the current step.
  subroutine state_energies(s, mop, dom)
    type(state_t), intent(inout) :: s
    type(mass_op_t), intent(in) :: mop
    type(domain_t), intent(inout) :: dom
    if (mop%consistent) call halo_exchange(dom%halo, s%v_mid)
    call mass_apply(mop, s%v_mid, s%mv)
    s%e_kin = 0.5_dp*repro_dot(s%nn, s%v_mid, s%mv, s%nglobal)
    s%e_strain = -0.5_dp*repro_dot(s%nn, s%u, s%f, s%nglobal)
    s%w_ext = s%w_acc
    s%e_time = s%t
  end subroutine state_energies
end module ictus_solver_explicit
