!> One central-difference step in the predictor-corrector form of doc/theory.md §4:
!!
!!     a_pre   = M^-1 (R_n - K u_n)              (with mass-proportional damping, see below)
!!     v_pre   = v_{n-1/2} + dt a_pre
!!     u_pre   = u_n + dt v_pre                  (contact is evaluated on u_pre)
!!     a_cor   = M^-1 F_c(u_pre)
!!     v_{n+1/2} = v_pre + dt a_cor
!!     u_{n+1} = u_n + dt v_{n+1/2}
!!
!! The step is split in two: `step_predict` (up to v_pre, plus the energies at t_n when asked)
!! and `step_finish` (u_{n+1}); the contact correction of v goes between them. The internal
!! force comes from the force operator (ictus_solver_internal_force), the solve from the mass
!! operator (ictus_solver_mass_operator); the stepper (ictus_solver_stepper) runs the steps.
!! Damping: the force -alpha M v with v at t_n = (v_{n-1/2} + v_{n+1/2})/2 gives
!! v_pre = ((1 - alpha dt/2) v_{n-1/2} + dt a) / (1 + alpha dt/2) node by node, where alpha is
!! the mass-weighted mean of the element coefficients around the node.
!! Vectors hold this rank's owned nodes followed by its ghosts; updates run over owned nodes
!! and `step_finish` refreshes the ghost displacements. The step allocates nothing.
!! Without output the predictor takes a fused path that also computes u_pre = u_n + dt v_pre
!! (s%u_next, swapped in by `step_finish`): with the assembled K and a lumped mass one pass
!! over K (`fused_lumped_step`, or `fused_lumped_rows` with damping, which also leaves the
!! terms of the damping power per node; `fused_lumped_rows3` for the 3 x 3 blocks of 3D), for an undamped consistent mass solved along the
!! lattice directions on one rank the updates inside the solve's last pass (`mass_step`); all
!! with the bits of the unfused step. Several lumped steps in one sweep over K are the linear
!! lumped stepper's (ictus_solver_lumped_sweeps).
!! Loads and prescribed motion (ictus_solver_loads, doc/theory.md §4a) take the plain step:
!! a = M^-1 (f_ext(t_n) - f_int(u_n)), the prescribed dofs' v_{n+1/2} set after the velocity
!! update, and the power of the loads and of the reactions of the prescribed dofs added to the
!! external work. At a record the reaction forces of the constrained dofs are formed (s%rf).
module ictus_solver_explicit
  use ictus_core_kinds, only: dp
  use ictus_core_memory, only: alloc_stream
  use ictus_parallel_repro, only: repro_dot, repro_sum
  use ictus_parallel_halo, only: halo_exchange
  use ictus_parallel_env, only: allreduce_or
  use ictus_solver_sparse, only: fused_lumped_step, fused_lumped_rows, fused_lumped_rows3
  use ictus_solver_mass_operator, only: mass_op_t, mass_solve, mass_apply, mass_step, &
      mass_steps_fused
  use ictus_solver_domain, only: domain_t
  use ictus_solver_internal_force, only: force_op_t, force_apply, force_energy, FORCE_ASSEMBLED, &
      force_hist_shape, force_dissipation
  use ictus_solver_loads, only: loads_t, loads_force, motion_start, motion_velocity, &
      motion_set_displacement
  implicit none
  private
  public :: state_t, state_init, step_predict, step_finish, state_energies, between_steps_t, &
      add_damping_work, state_kinetic

  !> Work between the predictor and the displacement update of a step inside a sweep (the
  !! contact correction), on s%u = u_n, s%v = v_pre and s%u_next = u_pre: whoever runs the
  !! sweeps extends this type with what the work needs.
  type, abstract :: between_steps_t
  contains
    procedure(between_run_i), deferred :: run
  end type between_steps_t

  abstract interface
    subroutine between_run_i(this)
      import :: between_steps_t
      class(between_steps_t), intent(inout) :: this
    end subroutine between_run_i
  end interface

  type :: state_t
    !> Owned nodes and local nodes (owned + ghosts).
    integer :: nn = 0
    integer :: nlocal = 0
    integer :: nglobal = 0
    !> Step counter n and time t_n of the displacement `u`.
    integer :: step = 0
    real(dp) :: t = 0.0_dp
    !> The step from t_n to t_{n+1} and the one before it (they differ where the stable step
    !! follows the state: v_{n+1/2} = v_{n-1/2} + (dt_prev + dt)/2 a_n).
    real(dp) :: dt = 0.0_dp
    real(dp) :: dt_prev = 0.0_dp
    !> u_n (ndm, nlocal); v_{n-1/2} before a step and v_{n+1/2} after it; last acceleration a.
    real(dp), allocatable :: u(:,:), v(:,:), a(:,:)
    !> Work: force vector, previous half-step velocity, mean velocity, M v.
    real(dp), allocatable :: f(:,:), v_old(:,:), v_mid(:,:), mv(:,:)
    !> Damping coefficient per node, the positive nodal masses it acts on, and whether any
    !! coefficient is non-zero.
    real(dp), allocatable :: alpha(:)
    real(dp), allocatable :: m_pos(:)
    logical :: damped = .false.
    !> Terms of the damping power at t_n per node, (ndm, nn, stage): left by the fused damped
    !! step (stage 1) and by each stage of a damped sweep, summed by `add_damping_work`.
    real(dp), allocatable :: pw(:,:,:)
    !> Energies at time t_n of the last step that computed them.
    real(dp) :: e_kin = 0.0_dp, e_strain = 0.0_dp, e_contact = 0.0_dp, w_ext = 0.0_dp
    !> Energy dissipated by the material laws (plastic work) up to t_n.
    real(dp) :: e_plastic = 0.0_dp
    !> Energy dissipated by contact friction up to the last contact correction (the one
    !! evaluated on u_pre ~ u_n, like e_contact).
    real(dp) :: e_friction = 0.0_dp
    real(dp) :: e_time = 0.0_dp
    !> Work of external and damping forces from t = 0 to t_n, and the damping power at t_{n-1}.
    real(dp) :: w_acc = 0.0_dp
    real(dp) :: pw_prev = 0.0_dp
    !> Non-zero when the last mass solve failed.
    integer :: ierr = 0
    !> u_{n+1} computed by the fused lumped-mass predictor (ndm, nlocal), and whether the
    !! current step took that path (then step_finish swaps it in).
    real(dp), allocatable :: u_next(:,:)
    logical :: fused = .false.
    !> History variables of the material laws at the quadrature points of this rank's
    !! elements, (nhist, ngp, elements) (empty when no law has history).
    real(dp), allocatable :: hist(:,:,:)
    !> Loads and prescribed motion (`loaded`: any on any rank), the external force f_ext(t_n)
    !! and the applied force f_ext - f_int (ndm, nlocal; allocated when loaded).
    logical :: loaded = .false.
    type(loads_t) :: ld
    real(dp), allocatable :: fext(:,:), fa(:,:)
    !> Constrained dofs of the owned nodes (ndm, nn), and the reaction forces on them at the
    !! last record (ndm, nlocal; 0 on the other dofs): R = M a - (f_ext - f_int) - f_damp.
    logical, allocatable :: fixed(:,:)
    real(dp), allocatable :: rf(:,:)
  end type state_t

contains

  !> Sets u_0 (prescribed displacements), v_0 and the start-up half-step velocity
  !! v_{-1/2} = v_0 - dt/2 a_0 with a_0 = M^-1(-K u_0). Arrays are local (ndm, nlocal) /
  !! (nlocal). `alpha` are the nodal damping coefficients, `m_pos` the positive diagonal
  !! masses that weigh the damping work. `ld`: the rank's loads and prescribed motion (with
  !! them a_0 = M^-1(f_ext(0) - f_int(u_0)) and the prescribed dofs start from their
  !! v_{-1/2}); `fixed`: the constrained dofs (ndm, >= nn) whose reactions are recorded.
  subroutine state_init(s, fop, mop, dom, u0, v0, alpha, m_pos, dt, ld, fixed)
    type(state_t), intent(out) :: s
    type(force_op_t), intent(inout) :: fop
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: u0(:,:), v0(:,:), alpha(:), m_pos(:), dt
    type(loads_t), intent(in), optional :: ld
    logical, intent(in), optional :: fixed(:,:)
    integer :: nn, nl, nd
    nd = size(u0, 1)
    nn = dom%nowned
    nl = dom%nlocal
    s%nn = nn
    s%nlocal = nl
    s%nglobal = dom%nn_global
    s%dt = dt
    s%dt_prev = dt
    call alloc_stream(s%u, nd, nl, 0.0_dp)
    call alloc_stream(s%v, nd, nl, 0.0_dp)
    call alloc_stream(s%f, nd, nl, 0.0_dp)
    call alloc_stream(s%v_old, nd, nl, 0.0_dp)
    call alloc_stream(s%v_mid, nd, nl, 0.0_dp)
    call alloc_stream(s%mv, nd, nl, 0.0_dp)
    call alloc_stream(s%a, nd, nl, 0.0_dp)
    call alloc_stream(s%u_next, nd, nl, 0.0_dp)
    call alloc_stream(s%rf, nd, nl, 0.0_dp)
    allocate(s%fixed(nd, nn), source=.false.)
    if (present(fixed)) s%fixed = fixed(:, 1:nn)
    if (present(ld)) then
      s%ld = ld
      s%loaded = ld%active
    end if
    if (s%loaded) then
      call alloc_stream(s%fext, nd, nl, 0.0_dp)
      call alloc_stream(s%fa, nd, nl, 0.0_dp)
    end if
    s%u = u0
    s%alpha = alpha(1:nn)
    s%m_pos = m_pos(1:nn)
    ! on every rank alike: the damped step has a global sum (the damping power), and a rank
    ! whose nodes have no damping takes the damped update with h = 0, the undamped bits
    s%damped = any(alpha(1:nn) /= 0.0_dp)
    call allreduce_or(s%damped)
    if (s%damped) call alloc_stream(s%pw, nd, nn, 1, 0.0_dp)
    associate (hs => force_hist_shape(fop))
      allocate(s%hist(hs(1), hs(2), hs(3)), source=0.0_dp)
    end associate
    call force_apply(fop, s%u, s%f, s%hist)
    s%f(:, 1:nn) = -s%f(:, 1:nn)
    call solve_applied(s, mop, dom)
    s%v = 0.0_dp
    s%v(:, 1:nn) = (v0(:, 1:nn) - 0.5_dp*dt*s%a(:, 1:nn))*mop%free(:, 1:nn)
    if (s%loaded) call motion_start(s%ld, dt, s%v)
  end subroutine state_init

  !> a = M^-1 (f_ext(t_n) - f_int(u_n)) from s%f = -f_int(u_n): with loads the external force
  !! at t_n is formed in s%fext and the sum in s%fa; without, s%f is solved as it is.
  subroutine solve_applied(s, mop, dom)
    type(state_t), intent(inout) :: s
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    integer :: nn
    nn = s%nn
    if (s%loaded) then
      call loads_force(s%ld, s%t, s%ld%x0, s%u, s%fext)
      s%fa(:, 1:nn) = s%f(:, 1:nn) + s%fext(:, 1:nn)
      call mass_solve(mop, dom, s%fa, s%a, s%ierr)
    else
      call mass_solve(mop, dom, s%f, s%a, s%ierr)
    end if
  end subroutine solve_applied

  !> First half of a step: internal force at u_n, predictor acceleration and velocity
  !! v_{n+1/2} (before any contact correction). With `record`, also the mean velocity
  !! v_n = (v_{n-1/2} + v_{n+1/2})/2 in s%v_mid and the energies at t_n.
  subroutine step_predict(s, fop, mop, dom, record)
    type(state_t), intent(inout) :: s
    type(force_op_t), intent(inout) :: fop
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    logical, intent(in) :: record
    integer :: i, nn
    real(dp) :: dt, h, pw
    nn = s%nn
    ! the velocity step: (dt_prev + dt)/2, which is dt itself (exactly) while dt stays
    dt = 0.5_dp*(s%dt_prev + s%dt)
    pw = 0.0_dp
    ! a damped consistent step, a step with loads and a step after a change of dt take the
    ! unfused path below
    s%fused = .not. (record .or. (s%damped .and. mop%consistent) .or. s%loaded .or. &
        s%dt_prev /= s%dt)
    if (s%fused .and. .not. mop%consistent .and. fop%kind == FORCE_ASSEMBLED) then
      ! the common step in one pass over memory (same operations in the same order as below)
      associate (k => fop%asm%k)
        if (size(k%val, 1) == 3 .and. s%damped) then
          call fused_lumped_rows3(1, nn, k%g%row_ptr, k%g%col, k%val, mop%inv_diag, dt, s%u, &
              s%v, s%u_next, s%alpha, s%m_pos, s%pw)
          call add_damping_work(s, s%step, 1)
        else if (size(k%val, 1) == 3) then
          call fused_lumped_rows3(1, nn, k%g%row_ptr, k%g%col, k%val, mop%inv_diag, dt, s%u, &
              s%v, s%u_next)
        else if (s%damped) then
          call fused_lumped_rows(1, nn, k%g%row_ptr, k%g%col, k%val, mop%inv_diag, dt, s%u, &
              s%v, s%u_next, s%alpha, s%m_pos, s%pw)
          call add_damping_work(s, s%step, 1)
        else
          call fused_lumped_step(nn, k%g%row_ptr, k%g%col, k%val, mop%inv_diag, dt, s%u, &
              s%v, s%u_next)
        end if
      end associate
      return
    end if
    if (s%fused .and. mass_steps_fused(mop)) then
      ! consistent mass on one rank: the updates of v and u_{n+1} inside the solve's last
      ! pass (same operations as below; s%f holds +f_int(u_n), s%a is not computed)
      call force_apply(fop, s%u, s%f, s%hist)
      call mass_step(mop, s%f, dt, s%u, s%v, s%u_next)
      return
    end if
    s%fused = .false.
    call force_apply(fop, s%u, s%f, s%hist)
    s%f(:, 1:nn) = -s%f(:, 1:nn)
    call solve_applied(s, mop, dom)
    ! v_{n-1/2} is needed only for the mean velocity (damping, energies, loads)
    if (s%damped .or. record .or. s%loaded) s%v_old(:, 1:nn) = s%v(:, 1:nn)
    if (s%damped) then
      do i = 1, nn
        h = 0.5_dp*s%alpha(i)*dt
        s%v(:, i) = ((1.0_dp - h)*s%v(:, i) + dt*s%a(:, i))/(1.0_dp + h)
      end do
    else
      s%v(:, 1:nn) = s%v(:, 1:nn) + dt*s%a(:, 1:nn)
    end if
    if (s%loaded) call motion_velocity(s%ld, s%t, s%dt, s%u, s%v)
    if (s%damped .or. record .or. s%loaded) s%v_mid(:, 1:nn) = 0.5_dp*(s%v_old(:, 1:nn) + &
        s%v(:, 1:nn))
    if (s%damped) then
      ! power of the damping force -alpha M v at t_n (lumped, node by node), integrated by
      ! the trapezoidal rule: w_acc = work from 0 to t_n
      do i = 1, nn
        s%mv(:, i) = -s%alpha(i)*s%m_pos(i)*s%v_mid(:, i)
      end do
      pw = repro_dot(nn, s%mv, s%v_mid, s%nglobal)
      if (s%loaded) pw = pw + load_power(s, mop)
    else if (s%loaded) then
      pw = load_power(s, mop)
    end if
    if (s%damped .or. s%loaded) then
      if (s%step > 0) s%w_acc = s%w_acc + 0.5_dp*s%dt_prev*(s%pw_prev + pw)
      s%pw_prev = pw
    end if
    if (record) call state_energies(s, fop, mop, dom)
    if (record) call state_reactions(s, mop, dom)
  end subroutine step_predict

  !> Reaction at t_n on prescribed dof d of owned node i (lumped mass m_i):
  !! R = m_i (v_{n+1/2} - v_{n-1/2})/dt_v - (f_ext - f_int) - f_damp, f_damp = -alpha m v_n,
  !! with the velocity step dt_v = (dt_prev + dt)/2.
  !! Needs s%f = -f_int(u_n), s%fext, s%v_old, s%v and s%v_mid of the current step.
  pure real(dp) function motion_reaction(s, mop, d, i) result(r)
    type(state_t), intent(in) :: s
    type(mass_op_t), intent(in) :: mop
    integer, intent(in) :: d, i
    r = mop%m_diag(i)*(s%v(d, i) - s%v_old(d, i))/(0.5_dp*(s%dt_prev + s%dt)) - s%f(d, i) - &
        s%fext(d, i) + &
        s%alpha(i)*s%m_pos(i)*s%v_mid(d, i)
  end function motion_reaction

  !> The power at t_n of the loads on every dof, f_ext . v_n, and of the reactions of the
  !! prescribed dofs, R . v_n (fixed dofs do not move), a reproducible sum over all ranks.
  real(dp) function load_power(s, mop) result(pw)
    type(state_t), intent(inout) :: s
    type(mass_op_t), intent(in) :: mop
    integer :: i, k, d
    do i = 1, s%nn
      s%mv(:, i) = s%fext(:, i)*s%v_mid(:, i)
    end do
    do k = 1, s%ld%nmot
      i = s%ld%mot_node(k)
      d = s%ld%mot_dof(k)
      s%mv(d, i) = s%mv(d, i) + motion_reaction(s, mop, d, i)*s%v_mid(d, i)
    end do
    pw = repro_sum(size(s%mv, 1)*s%nn, s%mv, size(s%mv, 1)*s%nglobal)
  end function load_power

  !> The reaction forces at t_n on the constrained dofs, s%rf = (M a)_c - (f_ext - f_int)_c
  !! (- f_damp on prescribed dofs), 0 elsewhere: a = 0 on fixed dofs (lumped mass: R =
  !! f_int - f_ext there; a consistent mass adds M_cf a_f), a_c = (v_{n+1/2} - v_{n-1/2})/dt
  !! on prescribed ones (lumped mass only). Needs s%f = -f_int(u_n) and s%a of this step.
  subroutine state_reactions(s, mop, dom)
    type(state_t), intent(inout) :: s
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    integer :: i, d, k, nn
    nn = s%nn
    if (mop%consistent) then
      s%rf(:, 1:nn) = s%a(:, 1:nn)
      call halo_exchange(dom%halo, s%rf)
      call mass_apply(mop, s%rf, s%mv)
      s%rf(:, nn + 1:) = 0.0_dp
    end if
    do i = 1, nn
      do d = 1, size(s%rf, 1)
        if (.not. s%fixed(d, i)) then
          s%rf(d, i) = 0.0_dp
          cycle
        end if
        s%rf(d, i) = -s%f(d, i)
        if (s%loaded) s%rf(d, i) = s%rf(d, i) - s%fext(d, i)
        if (mop%consistent) s%rf(d, i) = s%rf(d, i) + s%mv(d, i)
      end do
    end do
    if (.not. s%loaded) return
    do k = 1, s%ld%nmot
      i = s%ld%mot_node(k)
      d = s%ld%mot_dof(k)
      s%rf(d, i) = motion_reaction(s, mop, d, i)
    end do
  end subroutine state_reactions

  !> Adds the work of the damping forces from t_{n-1} to t_n to s%w_acc (trapezoidal rule)
  !! with the power at t_n summed from s%pw(:, :, stage), the terms the fused damped step of
  !! step n left there; n = 0 only sets the power. The same sum, in the same order, as the
  !! repro_dot of the unfused step.
  subroutine add_damping_work(s, n, stage)
    type(state_t), intent(inout) :: s
    integer, intent(in) :: n, stage
    real(dp) :: pw
    pw = repro_sum(size(s%pw, 1)*s%nn, s%pw(:, :, stage), size(s%pw, 1)*s%nglobal)
    if (n > 0) s%w_acc = s%w_acc + 0.5_dp*s%dt_prev*(s%pw_prev + pw)
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
    if (s%loaded) call motion_set_displacement(s%ld, s%t + s%dt, s%u)
    call halo_exchange(dom%halo, s%u)
    s%step = s%step + 1
    s%t = s%t + s%dt
    s%dt_prev = s%dt
  end subroutine step_finish

  !> Kinetic energy 1/2 v·M v with v at t_n and the strain energy of the force operator at u_n,
  !! recorded for time t_n. Needs s%f = -f_int(u_n) and s%v_mid set by the current step.
  subroutine state_energies(s, fop, mop, dom)
    type(state_t), intent(inout) :: s
    type(force_op_t), intent(inout) :: fop
    type(mass_op_t), intent(in) :: mop
    type(domain_t), intent(inout) :: dom
    call state_kinetic(s, mop, dom)
    s%e_strain = force_energy(fop, s%u, s%f)
    s%e_plastic = force_dissipation(fop)
    s%w_ext = s%w_acc
    s%e_time = s%t
  end subroutine state_energies

  !> Kinetic energy at t_n, 1/2 v_n.M v_n with v_n = (v_{n-1/2} + v_{n+1/2})/2 from s%v_old
  !! and s%v (also left in s%v_mid). Called by the predictor of a recorded step, and again
  !! after that step's contact correction, which changes v_{n+1/2}: with the corrected
  !! velocity the discrete energy balance of doc/theory.md §4b holds exactly.
  subroutine state_kinetic(s, mop, dom)
    type(state_t), intent(inout) :: s
    type(mass_op_t), intent(in) :: mop
    type(domain_t), intent(inout) :: dom
    s%v_mid(:, 1:s%nn) = 0.5_dp*(s%v_old(:, 1:s%nn) + s%v(:, 1:s%nn))
    if (mop%consistent) call halo_exchange(dom%halo, s%v_mid)
    call mass_apply(mop, s%v_mid, s%mv)
    s%e_kin = 0.5_dp*repro_dot(s%nn, s%v_mid, s%mv, s%nglobal)
  end subroutine state_kinetic
end module ictus_solver_explicit
