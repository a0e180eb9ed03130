!> The contact correction of the predictor-corrector step (doc/theory.md §4):
!!
!!     u_pre = u_n + dt v_pre,   a_cor = M^-1 F_c(u_pre),   v_{n+1/2} = v_pre + dt a_cor
!!
!! Contact is computed from the current coordinates of the contact-surface nodes only. Their
!! predicted positions are assembled on every rank (each node's owner contributes it; a sum
!! with one non-zero term is exact), every rank evaluates the same contact forces, and each
!! applies those of its owned nodes. So the result does not depend on the partition, and the
!! cost and the communication are proportional to the contact surface, not to the mesh.
!!
!! Bipenalty (doc/contact.md §6a, lumped mass only): pairs with a mass penalty eps_m > 0 add, at
!! each active contact point, eps_m times the absolute row sums of the point's constraint
!! rows to the lumped masses of its nodes (see doc/contact.md). The added masses of the
!! active set found on u_pre are used by the correction of this step and by the predictor
!! of the next one (mass_set_added). When a node's added mass grows, its velocity is scaled
!! by (m + dm_old)/(m + dm_new) (the added mass joins at rest, momentum m v is kept) and the
!! contact forces are evaluated again on the corrected prediction.
!!
!! Coulomb friction (doc/contact.md §4a): every evaluation of a step starts from the friction
!! state of the last step; the last evaluation is committed (contact_commit) and the
!! frictional work so far is stored in the state next to the contact energy.
module ictus_solver_contact_step
  use ictus_core_kinds, only: dp
  use ictus_core_errors, only: input_error
  use ictus_core_logger, only: log_info
  use ictus_core_strings, only: str, upper
  use ictus_parallel_env, only: allreduce_sum
  use ictus_parallel_repro, only: repro_dot
  use ictus_parallel_halo, only: halo_exchange
  use ictus_contact_contact, only: contact_t, contact_forces, contact_stability, PAIR_WALL, &
      contact_commit, contact_node_mask
  use ictus_solver_domain, only: domain_t
  use ictus_solver_sparse, only: bsr_t, bsr_matvec
  use ictus_solver_mass_operator, only: mass_op_t, mass_solve, mass_set_added
  use ictus_solver_explicit, only: state_t
  implicit none
  private
  public :: contact_step_t, contact_step_init, contact_correct, contact_ratio, &
      contact_bipenalty_init, contact_omega_max

  type :: contact_step_t
    !> Number of contact-surface nodes, their global and (if owned here) local indices.
    integer :: ncn = 0
    integer, allocatable :: cnode(:)
    integer, allocatable :: lnode(:)
    !> Exchange buffer (ndm, ncn); global coordinates and forces (ndm, nn_global), of which
    !! only the contact nodes are kept current.
    real(dp), allocatable :: buf(:,:)
    real(dp), allocatable :: xg(:,:), fcg(:,:)
    !> Consistent mass: local force vector and the correction acceleration (ndm, nlocal).
    real(dp), allocatable :: fc(:,:), ac(:,:)
    integer :: ierr = 0
    !> Bipenalty: on if some pair has eps_m > 0; added masses of the last contact
    !! evaluation (nn global) and those applied at each contact node (ncn).
    logical :: bipenalty = .false.
    real(dp), allocatable :: dmg(:)
    real(dp), allocatable :: dm_node(:)
  end type contact_step_t

contains

  !> Collects the contact-surface nodes of `c` and sets up the work arrays.
  subroutine contact_step_init(cs, c, x0, dom)
    type(contact_step_t), intent(out) :: cs
    type(contact_t), intent(in) :: c
    real(dp), intent(in) :: x0(:,:)
    type(domain_t), intent(in) :: dom
    logical, allocatable :: mark(:)
    integer :: k, i, nn, nd
    nn = size(x0, 2)
    nd = size(x0, 1)
    mark = contact_node_mask(c, nn)
    cs%cnode = pack([(i, i = 1, nn)], mark)
    cs%ncn = size(cs%cnode)
    allocate(cs%lnode(cs%ncn))
    do k = 1, cs%ncn
      i = dom%g2l(cs%cnode(k))
      if (i > dom%nowned) i = 0
      cs%lnode(k) = i
    end do
    allocate(cs%buf(nd, cs%ncn))
    cs%xg = x0
    allocate(cs%fcg(nd, nn), source=0.0_dp)
    allocate(cs%fc(nd, dom%nlocal), cs%ac(nd, dom%nlocal), source=0.0_dp)
    allocate(cs%dmg(nn), source=0.0_dp)
    allocate(cs%dm_node(cs%ncn), source=0.0_dp)
  end subroutine contact_step_init

  !> Sets the mass penalty eps_m of each *CONTACT PAIR with MASS PENALTY (doc/contact.md §6a):
  !! the given value, or for AUTO eps_m = eps_N/beta with beta = min(omega0^2, 1/(2 dt^2)).
  !! beta <= omega0^2 keeps the critical step of the model without contact (mediant bound);
  !! beta <= 1/(2 dt^2) keeps the predictor-corrector ratio r = dt^2 eps (l_s/m_s + l_m/m_m)
  !! below 1/2 however stiff the penalty (with m + 2 eps_m l per side, r < dt^2 beta).
  !! The driver passes the given step, or 2/omega0 for automatic steps (beta = omega0^2/8).
  !! A consistent mass is refused (input error naming the card). Call after
  !! contact_step_init and before contact_ratio.
  !! @param cs contact step; @param c contact (pairs' eps_m set); @param mop mass operator;
  !! @param omega0 omega_max of the model without contact; @param dt time step (0: unknown)
  subroutine contact_bipenalty_init(cs, c, mop, omega0, dt)
    type(contact_step_t), intent(inout) :: cs
    type(contact_t), intent(inout) :: c
    type(mass_op_t), intent(in) :: mop
    real(dp), intent(in) :: omega0, dt
    real(dp) :: beta
    integer :: k
    cs%bipenalty = .false.
    do k = 1, c%npairs
      associate (p => c%pairs(k))
        p%eps_m = 0.0_dp
        if (p%kind == PAIR_WALL .or. p%mass_penalty < 0.0_dp) cycle
        if (mop%consistent) then
          call input_error('*CONTACT PAIR, NAME='//upper(trim(p%name)), 'MASS PENALTY '// &
              '(bipenalty) needs a lumped mass (TYPE=HRZ, ROW SUM or ALPHA on *MASS): it '// &
              'adds the mass penalty to the diagonal nodal masses; this model has a '// &
              'consistent mass')
          cycle
        end if
        if (p%mass_penalty > 0.0_dp) then
          p%eps_m = p%mass_penalty
          beta = p%penalty/p%eps_m
        else
          beta = omega0**2
          if (dt > 0.0_dp) beta = min(beta, 0.5_dp/dt**2)
          if (.not. beta > 0.0_dp) beta = 0.5_dp/dt**2
          p%eps_m = p%penalty/beta
        end if
        cs%bipenalty = .true.
        call log_info('contact '//trim(p%name)//': bipenalty, mass penalty eps_m = '// &
            str(p%eps_m)//' (beta = eps_N/eps_m = '//str(beta)//', omega0_max^2 = '// &
            str(omega0**2)//')')
      end associate
    end do
  end subroutine contact_bipenalty_init

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
    ! a loop, not cs%xg(:, cs%cnode) = cs%buf: a vector subscript makes a heap temporary
    do k = 1, cs%ncn
      cs%xg(:, cs%cnode(k)) = cs%buf(:, k)
    end do
  end subroutine gather_contact_nodes

  !> Contact forces on u_pre = u_n + dt v_pre and the velocity correction. Also stores the
  !! contact energy in the state and, with friction, commits the friction state and stores
  !! the frictional work. With bipenalty (lumped mass), also updates the added
  !! masses of the contact nodes in `mop` (used by this correction and the next predictor).
  subroutine contact_correct(cs, c, s, mop, dom, x0)
    type(contact_step_t), intent(inout) :: cs
    type(contact_t), intent(inout) :: c
    type(state_t), intent(inout) :: s
    type(mass_op_t), intent(inout) :: mop
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: x0(:,:)
    real(dp) :: energy
    integer :: k, l
    logical :: grows
    call predicted_forces(cs, c, s, x0, energy)
    if (cs%bipenalty .and. .not. mop%consistent) then
      grows = .false.
      do k = 1, cs%ncn
        if (cs%dmg(cs%cnode(k)) > cs%dm_node(k)) grows = .true.
      end do
      if (grows) then
        ! added masses join at rest: keep m v of the nodes whose added mass grows, then
        ! evaluate the contact again on the corrected prediction
        do k = 1, cs%ncn
          l = cs%lnode(k)
          if (l > 0 .and. cs%dmg(cs%cnode(k)) > cs%dm_node(k)) s%v(:, l) = s%v(:, l)* &
              ((mop%m_diag(l) + cs%dm_node(k))/(mop%m_diag(l) + cs%dmg(cs%cnode(k))))
        end do
        call predicted_forces(cs, c, s, x0, energy)
      end if
      do k = 1, cs%ncn
        cs%dm_node(k) = cs%dmg(cs%cnode(k))
        l = cs%lnode(k)
        if (l > 0) call mass_set_added(mop, l, cs%dm_node(k))
      end do
    end if
    s%e_contact = energy
    if (c%friction) then
      call contact_commit(c, size(x0, 2), cs%xg)
      s%e_friction = c%friction_work
    end if
    ! with mass-proportional damping the predictor is v_pre = ((1 - h) v + dt a)/(1 + h),
    ! h = alpha dt/2; the contact acceleration belongs to the same damped step, so it enters
    ! as dt a_cor/(1 + h) (without this the static state of a damped relaxation would carry
    ! the contact force only to a factor 1/(1 + h))
    if (.not. mop%consistent) then
      ! lumped mass: the correction touches the contact nodes only
      do k = 1, cs%ncn
        l = cs%lnode(k)
        if (l > 0) s%v(:, l) = s%v(:, l) + s%dt*cs%fcg(:, cs%cnode(k))*mop%inv_diag(:, l)/ &
            damping_factor(s, l)
      end do
    else
      do k = 1, cs%ncn
        l = cs%lnode(k)
        if (l > 0) cs%fc(:, l) = cs%fcg(:, cs%cnode(k))
      end do
      call mass_solve(mop, dom, cs%fc, cs%ac, cs%ierr)
      if (s%damped) then
        do l = 1, s%nn
          s%v(:, l) = s%v(:, l) + s%dt*cs%ac(:, l)/damping_factor(s, l)
        end do
      else
        s%v(:, 1:s%nn) = s%v(:, 1:s%nn) + s%dt*cs%ac(:, 1:s%nn)
      end if
      ! a consistent correction moves every node: u_{n+1} of a fused predictor again
      if (s%fused) s%u_next(:, 1:s%nn) = s%u(:, 1:s%nn) + s%dt*s%v(:, 1:s%nn)
    end if
    if (s%fused .and. .not. mop%consistent) then
      ! the fused predictor already computed u_{n+1} with the uncorrected velocity: redo it
      ! on the contact nodes (the only ones whose velocity changed)
      do k = 1, cs%ncn
        l = cs%lnode(k)
        if (l > 0) s%u_next(:, l) = s%u(:, l) + s%dt*s%v(:, l)
      end do
    end if
  end subroutine contact_correct

  !> 1 + alpha_l dt/2 of owned node l (1 without damping).
  pure real(dp) function damping_factor(s, l)
    type(state_t), intent(in) :: s
    integer, intent(in) :: l
    damping_factor = 1.0_dp
    if (s%damped) damping_factor = 1.0_dp + 0.5_dp*s%alpha(l)*s%dt
  end function damping_factor

  !> Contact forces (cs%fcg) and, with bipenalty, added masses (cs%dmg) on the predicted
  !! coordinates x0 + u_n + dt v of the contact nodes.
  subroutine predicted_forces(cs, c, s, x0, energy)
    type(contact_step_t), intent(inout) :: cs
    type(contact_t), intent(inout) :: c
    type(state_t), intent(in) :: s
    real(dp), intent(in) :: x0(:,:)
    real(dp), intent(out) :: energy
    integer :: k, l
    cs%buf = 0.0_dp
    do k = 1, cs%ncn
      l = cs%lnode(k)
      if (l > 0) cs%buf(:, k) = x0(:, cs%cnode(k)) + (s%u(:, l) + s%dt*s%v(:, l))
    end do
    call allreduce_sum(cs%buf)
    ! a loop, not cs%xg(:, cs%cnode) = cs%buf: a vector subscript makes a heap temporary
    do k = 1, cs%ncn
      cs%xg(:, cs%cnode(k)) = cs%buf(:, k)
    end do
    if (cs%bipenalty) then
      call contact_forces(c, size(x0, 2), cs%xg, cs%fcg, energy, cs%dmg)
    else
      call contact_forces(c, size(x0, 2), cs%xg, cs%fcg, energy)
    end if
  end subroutine predicted_forces

  !> The stability ratio r = dt^2 eps (l_s/m_s + l_m/m_m) of doc/contact.md §6 on the current
  !! coordinates (u: local displacements) with the positive lumped masses m_pos (local);
  !! r_pair (optional, npairs): the largest r of each pair.
  subroutine contact_ratio(cs, c, x0, u, m_pos, dt, r, where, r_pair)
    type(contact_step_t), intent(inout) :: cs
    type(contact_t), intent(inout) :: c
    real(dp), intent(in) :: x0(:,:), u(:,:), m_pos(:), dt
    real(dp), intent(out) :: r
    character(len=*), intent(out) :: where
    real(dp), intent(out), optional :: r_pair(:)
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
    call contact_stability(c, size(x0, 2), cs%xg, mg, dt, r, where, r_pair)
  end subroutine contact_ratio

  !> omega_max with the contact active: power iteration on (M + D)^-1 (K + K_p) at the
  !! configuration x0 + u (doc/theory.md §7, doc/contact.md §6, §6a). K_p x is applied
  !! matrix-free as minus the finite difference (F_c(x_u + h x) - F_c(x_u))/h of the contact forces, with
  !! h = 1e-4 times the largest penetration (|x| = 1), small enough not to change the active
  !! set of a flat interface; D are the bipenalty added masses of the active points at x_u
  !! (0 without bipenalty). Lumped mass only (a consistent mass returns omega = -1).
  !! Allocates its work arrays: for tests and diagnostics, not for the time loop; 2D models
  !! (two components, the 2 x 2 blocks of k).
  !! @param cs contact step (contact_step_init done); @param c contact; @param k stiffness;
  !! @param mop mass operator; @param dom domain; @param x0 reference coordinates (2, nn);
  !! @param u local displacements (2, nlocal); @param omega estimate; @param iters
  !! iterations; @param rtol relative change over 10 iterations to stop; @param max_iter
  subroutine contact_omega_max(cs, c, k, mop, dom, x0, u, omega, iters, rtol, max_iter)
    type(contact_step_t), intent(inout) :: cs
    type(contact_t), intent(inout) :: c
    type(bsr_t), intent(in) :: k
    type(mass_op_t), intent(in) :: mop
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: x0(:,:), u(:,:)
    real(dp), intent(out) :: omega
    integer, intent(out) :: iters
    real(dp), intent(in) :: rtol
    integer, intent(in) :: max_iter
    real(dp), allocatable :: x(:,:), kx(:,:), mm(:), xb(:,:), f0(:,:), dm(:)
    real(dp) :: lam, lam_old, xkx, xmx, nrm, h, energy
    integer :: n, i, it, kk, l, nng
    omega = -1.0_dp
    iters = 0
    if (mop%consistent) return
    n = mop%nn
    nng = size(x0, 2)
    allocate(x(2, mop%nlocal), kx(2, n), mm(n), dm(nng))
    ! base configuration: contact forces and added masses
    call gather_contact_nodes(cs, x0, u, 1.0_dp)
    xb = cs%xg
    dm = 0.0_dp
    call contact_forces(c, nng, xb, cs%fcg, energy, dm)
    f0 = cs%fcg
    h = 0.0_dp
    do kk = 1, c%npairs
      h = max(h, c%pairs(kk)%max_penetration)
    end do
    h = 1.0e-4_dp*h
    mm = mop%m_diag(1:n)
    do kk = 1, cs%ncn
      l = cs%lnode(kk)
      if (l > 0) mm(l) = mm(l) + dm(cs%cnode(kk))
    end do
    do i = 1, n
      x(1, i) = sin(12.9898_dp*real(dom%halo%gid(i), dp) + 1.0_dp)
      x(2, i) = sin(78.233_dp*real(dom%halo%gid(i), dp) + 2.0_dp)
    end do
    x(:, 1:n) = x(:, 1:n)*mop%free(:, 1:n)
    lam = 0.0_dp
    lam_old = 0.0_dp
    do it = 1, max_iter
      nrm = sqrt(repro_dot(n, x, x, mop%nglobal))
      if (nrm == 0.0_dp) exit
      x(:, 1:n) = x(:, 1:n)/nrm
      call halo_exchange(dom%halo, x)
      call bsr_matvec(n, k%g%row_ptr, k%g%col, k%val, x, kx)
      if (h > 0.0_dp) then
        call gather_contact_nodes(cs, xb, x, h)
        call contact_forces(c, nng, cs%xg, cs%fcg, energy)
        do kk = 1, cs%ncn
          l = cs%lnode(kk)
          if (l > 0) kx(:, l) = kx(:, l) - (cs%fcg(:, cs%cnode(kk)) - f0(:, cs%cnode(kk)))/h
        end do
      end if
      kx = kx*mop%free(:, 1:n)
      xkx = repro_dot(n, x, kx, mop%nglobal)
      do i = 1, n
        kx(:, i) = kx(:, i)/max(mm(i), tiny(1.0_dp))
      end do
      xmx = 0.0_dp
      do i = 1, n
        xmx = xmx + mm(i)*(x(1, i)**2 + x(2, i)**2)
      end do
      call allreduce_sum(xmx)
      lam = xkx/xmx
      iters = it
      if (mod(it, 10) == 0) then
        if (abs(lam - lam_old) <= rtol*abs(lam)) exit
        lam_old = lam
      end if
      x(:, 1:n) = kx
    end do
    omega = sqrt(max(lam, 0.0_dp))
    ! leave the pairs' results as at the base configuration
    call contact_forces(c, nng, xb, cs%fcg, energy)
  end subroutine contact_omega_max
end module ictus_solver_contact_step
