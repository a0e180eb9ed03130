!> The contact correction of the predictor-corrector step (physics.md §4.1):
!!
!!     u_pre = u_n + dt v_pre,   a_cor = M^-1 F_c(u_pre),   v_{n+1/2} = v_pre + dt a_cor
!!
!! Contact is computed from the current coordinates of the contact-surface nodes only. Their
!! predicted positions are assembled on every rank (each node's owner contributes it; a sum
!! with one non-zero term is exact), every rank evaluates the same contact forces, and each
!! applies those of its owned nodes. So the result does not depend on the partition, and the
!! cost and the communication are proportional to the contact surface, not to the mesh.
module ictus_solver_contact_step
  use ictus_core_kinds, only: dp
  use ictus_parallel_env, only: allreduce_sum
  use ictus_contact_contact, only: contact_t, contact_forces, contact_stability
  use ictus_solver_domain, only: domain_t
  use ictus_solver_mass_operator, only: mass_op_t, mass_solve
  use ictus_solver_explicit, only: state_t
  implicit none
  private
  public :: contact_step_t, contact_step_init, contact_correct, contact_ratio

  type :: contact_step_t
    !> Number of contact-surface nodes, their global and (if owned here) local indices.
    integer :: ncn = 0
    integer, allocatable :: cnode(:)
    integer, allocatable :: lnode(:)
    !> Exchange buffer (2, ncn); global coordinates and forces (2, nn_global), of which only
    !! the contact nodes are kept current.
    real(dp), allocatable :: buf(:,:)
    real(dp), allocatable :: xg(:,:), fcg(:,:)
    !> Consistent mass: local force vector and the correction acceleration (2, nlocal).
    real(dp), allocatable :: fc(:,:), ac(:,:)
    integer :: ierr = 0
  end type contact_step_t

contains

  !> Collects the contact-surface nodes of `c` and sets up the work arrays.
  subroutine contact_step_init(cs, c, x0, dom)
    type(contact_step_t), intent(out) :: cs
    type(contact_t), intent(in) :: c
    real(dp), intent(in) :: x0(:,:)
    type(domain_t), intent(in) :: dom
    logical, allocatable :: mark(:)
    integer :: k, i, nn
    nn = size(x0, 2)
    allocate(mark(nn), source=.false.)
    do k = 1, c%nsurf
      mark(c%surfaces(k)%nodes(1:c%surfaces(k)%nsn)) = .true.
    end do
    cs%cnode = pack([(i, i = 1, nn)], mark)
    cs%ncn = size(cs%cnode)
    allocate(cs%lnode(cs%ncn))
    do k = 1, cs%ncn
      i = dom%g2l(cs%cnode(k))
      if (i > dom%nowned) i = 0
      cs%lnode(k) = i
    end do
    allocate(cs%buf(2, cs%ncn))
    cs%xg = x0
    allocate(cs%fcg(2, nn), source=0.0_dp)
    allocate(cs%fc(2, dom%nlocal), cs%ac(2, dom%nlocal), source=0.0_dp)
  end subroutine contact_step_init

  !> Gathers the current values `val(2, nlocal)` (+ x0 when `add_x0`) of the contact nodes
  !! into cs%xg on every rank.
  subroutine gather_contact_nodes(cs, x0, val, scale)
    type(contact_step_t), intent(inout) :: cs
    real(dp), intent(in) :: x0(:,:), val(:,:)
    real(dp), intent(in) :: scale
    integer :: k, l
    cs%buf = 0.0_dp
    do k = 1, cs%ncn
      l = cs%lnode(k)
      if (l > 0) cs%buf(:, k) = x0(:, cs%cnode(k)) + scale*val(:, l)
    end do
    call allreduce_sum(cs%buf)
    cs%xg(:, cs%cnode) = cs%buf
  end subroutine gather_contact_nodes

  !> Contact forces on u_pre = u_n + dt v_pre and the velocity correction. Also stores the
  !! contact energy in the state.
  subroutine contact_correct(cs, c, s, mop, dom, x0)
    type(contact_step_t), intent(inout) :: cs
    type(contact_t), intent(inout) :: c
    type(state_t), intent(inout) :: s
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: x0(:,:)
    real(dp) :: energy
    integer :: k, l
    ! predicted coordinates of the contact nodes: x0 + u_n + dt v_pre
    cs%buf = 0.0_dp
    do k = 1, cs%ncn
      l = cs%lnode(k)
      if (l > 0) cs%buf(:, k) = x0(:, cs%cnode(k)) + (s%u(:, l) + s%dt*s%v(:, l))
    end do
    call allreduce_sum(cs%buf)
    cs%xg(:, cs%cnode) = cs%buf
    call contact_forces(c, size(x0, 2), cs%xg, cs%fcg, energy)
    s%e_contact = energy
    if (.not. mop%consistent) then
      ! lumped mass: the correction touches the contact nodes only
      do k = 1, cs%ncn
        l = cs%lnode(k)
        if (l > 0) s%v(:, l) = s%v(:, l) + s%dt*cs%fcg(:, cs%cnode(k))*mop%inv_diag(:, l)
      end do
    else
      do k = 1, cs%ncn
        l = cs%lnode(k)
        if (l > 0) cs%fc(:, l) = cs%fcg(:, cs%cnode(k))
      end do
      call mass_solve(mop, dom, cs%fc, cs%ac, cs%ierr)
      s%v(:, 1:s%nn) = s%v(:, 1:s%nn) + s%dt*cs%ac(:, 1:s%nn)
    end if
  end subroutine contact_correct

  !> The stability ratio r = dt^2 eps (l_s/m_s + l_m/m_m) of physics.md §4.4 on the current
  !! coordinates (u: local displacements) with the positive lumped masses m_pos (local).
  subroutine contact_ratio(cs, c, x0, u, m_pos, dt, r, where)
    type(contact_step_t), intent(inout) :: cs
    type(contact_t), intent(inout) :: c
    real(dp), intent(in) :: x0(:,:), u(:,:), m_pos(:), dt
    real(dp), intent(out) :: r
    character(len=*), intent(out) :: where
    real(dp), allocatable :: mg(:), mk(:)
    integer :: k, l
    call gather_contact_nodes(cs, x0, u, 1.0_dp)
    allocate(mg(size(x0, 2)), source=1.0_dp)
    allocate(mk(cs%ncn), source=0.0_dp)
    do k = 1, cs%ncn
      l = cs%lnode(k)
      if (l > 0) mk(k) = m_pos(l)
    end do
    call allreduce_sum(mk)
    mg(cs%cnode) = mk
    call contact_stability(c, size(x0, 2), cs%xg, mg, dt, r, where)
  end subroutine contact_ratio
end module ictus_solver_contact_step
