!> The mass operator of the time loop: a = M^-1 f on the free dofs, and v -> M v.
!!
!! Lumped mass: a division by the nodal mass. Consistent mass: a Jacobi-preconditioned
!! conjugate gradient, warm-started from the caller's previous solution (accelerations change
!! little from one step to the next). It runs on this rank's rows; the search direction's
!! ghost values come by halo exchange and the dot products are reproducible global sums, so
!! the iterates are the same bits on any number of ranks. All work arrays are allocated once
!! in `mass_op_init`; a solve allocates nothing.
module ictus_solver_mass_operator
  use ictus_core_kinds, only: dp
  use ictus_parallel_repro, only: repro_dot, repro_sigma, repro_totals, levels
  use ictus_parallel_env, only: allreduce_max
  use ictus_parallel_halo, only: halo_exchange
  use ictus_core_memory, only: alloc_stream
  use ictus_solver_sparse, only: csr_t, csr_matvec, csr_diagonal, csr_copy
  use ictus_solver_domain, only: domain_t
  implicit none
  private
  public :: mass_op_t, mass_op_init, mass_solve, mass_apply, mass_set_added

  type :: mass_op_t
    !> Owned nodes (rows), local nodes (owned + ghost), global nodes.
    integer :: nn = 0
    integer :: nlocal = 0
    integer :: nglobal = 0
    logical :: consistent = .false.
    !> Consistent mass (scalar, acting on both components).
    type(csr_t) :: m
    !> Lumped masses (owned nodes).
    real(dp), allocatable :: m_diag(:)
    !> 1/m on free dofs, 0 on fixed dofs and massless nodes (2, nn); also the preconditioner.
    real(dp), allocatable :: inv_diag(:,:)
    !> 1 on free dofs, 0 on fixed ones (2, nlocal).
    real(dp), allocatable :: free(:,:)
    !> Relative residual tolerance and iteration limit of the conjugate gradient.
    real(dp) :: rtol = 1.0e-12_dp
    !> Largest absolute row sum of M and largest 1/m (global): bounds of the CG's terms.
    real(dp) :: m_inf = 0.0_dp
    real(dp) :: inv_max = 0.0_dp
    integer :: max_iter = 500
    !> Statistics: iterations of the last solve, and summed over all solves.
    integer :: last_iter = 0
    integer :: total_iter = 0
    integer :: n_solves = 0
    !> Work vectors: residual r (2, nn), direction p (2, nlocal: ghosts by halo), M p in q (2, nn).
    real(dp), allocatable :: r(:,:), p(:,:), q(:,:)
  end type mass_op_t

contains

  !> Sets up the operator for the rows of `dom`. `m` is used only when `consistent`;
  !! `fixed(2, nlocal)` marks Dirichlet dofs, whose accelerations are zero; `rtol` is the
  !! relative residual at which the conjugate gradient stops (default 1e-12).
  subroutine mass_op_init(op, dom, consistent, m, m_diag, fixed, rtol)
    type(mass_op_t), intent(out) :: op
    type(domain_t), intent(in) :: dom
    logical, intent(in) :: consistent
    type(csr_t), intent(in) :: m
    real(dp), intent(in) :: m_diag(:)
    logical, intent(in) :: fixed(:,:)
    real(dp), intent(in), optional :: rtol
    real(dp), allocatable :: d(:)
    integer :: i, c, nn
    nn = dom%nowned
    op%nn = nn
    op%nlocal = dom%nlocal
    op%nglobal = dom%nn_global
    op%consistent = consistent
    if (present(rtol)) op%rtol = rtol
    op%m_diag = m_diag(1:nn)
    call alloc_stream(op%inv_diag, 2, nn, 0.0_dp)
    call alloc_stream(op%free, 2, dom%nlocal, 0.0_dp)
    allocate(d(nn))
    if (consistent) then
      call csr_copy(op%m, m)
      call csr_diagonal(m, d)
      call alloc_stream(op%r, 2, nn, 0.0_dp)
      call alloc_stream(op%q, 2, nn, 0.0_dp)
      call alloc_stream(op%p, 2, dom%nlocal, 0.0_dp)
    else
      d = m_diag(1:nn)
    end if
    do i = 1, dom%nlocal
      do c = 1, 2
        op%free(c, i) = merge(0.0_dp, 1.0_dp, fixed(c, i))
      end do
    end do
    do i = 1, nn
      do c = 1, 2
        if (fixed(c, i) .or. .not. d(i) > 0.0_dp) then
          op%free(c, i) = 0.0_dp
          op%inv_diag(c, i) = 0.0_dp
        else
          op%inv_diag(c, i) = 1.0_dp/d(i)
        end if
      end do
    end do
    if (consistent) then
      do i = 1, nn
        op%m_inf = max(op%m_inf, sum(abs(op%m%val(op%m%g%row_ptr(i):op%m%g%row_ptr(i + 1) - 1))))
      end do
      op%inv_max = maxval(op%inv_diag)
      call allreduce_max(op%m_inf)
      call allreduce_max(op%inv_max)
    end if
  end subroutine mass_op_init

  !> Lumped mass only: owned node i gets the added mass dm >= 0 in the solve a = M^-1 f
  !! (bipenalty, physics.md 4.6): inv_diag = 1/(m_i + dm) on its free dofs; dm = 0 restores
  !! 1/m_i. Massless nodes and fixed dofs keep 0; m_diag (the kinetic energy and mass_apply)
  !! is not changed. Does nothing for a consistent mass.
  !! @param op operator; @param i owned node (1..nn); @param dm added mass
  pure subroutine mass_set_added(op, i, dm)
    type(mass_op_t), intent(inout) :: op
    integer, intent(in) :: i
    real(dp), intent(in) :: dm
    if (op%consistent) return
    if (op%m_diag(i) > 0.0_dp) op%inv_diag(:, i) = op%free(:, i)/(op%m_diag(i) + dm)
  end subroutine mass_set_added

  !> mv = M v on the owned rows (v must hold current ghost values for a consistent mass).
  subroutine mass_apply(op, v, mv)
    type(mass_op_t), intent(in) :: op
    real(dp), intent(in) :: v(:,:)
    real(dp), intent(inout) :: mv(:,:)
    integer :: i
    if (op%consistent) then
      call csr_matvec(op%nn, op%m%g%row_ptr, op%m%g%col, op%m%val, v, mv)
    else
      do i = 1, op%nn
        mv(:, i) = op%m_diag(i)*v(:, i)
      end do
    end if
  end subroutine mass_apply

  !> Solves M a = f on the free owned dofs (a = 0 on fixed ones); f and a are (2, >= nn).
  !! For a consistent mass, `a` holds the start value on entry (e.g. the previous step's
  !! acceleration). `ierr` = 1 when the conjugate gradient did not converge.
  !!
  !! The conjugate gradient makes three passes over memory per iteration (`cg_product`,
  !! `cg_update`, `cg_direction`); the dot products are folded into them as reproducible
  !! sums (ictus_parallel_repro) whose level boundaries come from a priori bounds of the
  !! terms, so no pass is spent on a maximum: |p_i q_i| <= pmax^2 m_inf with m_inf the largest
  !! absolute row sum of M; |r_i| <= rmax + |alpha| m_inf pmax for the updated residual. The
  !! maxima pmax, rmax are global (one allreduce per iteration), so every rank uses the same
  !! boundaries and the iterates are the same bits on any number of ranks.
  subroutine mass_solve(op, dom, f, a, ierr)
    type(mass_op_t), intent(inout) :: op
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: f(:,:)
    real(dp), intent(inout) :: a(:,:)
    integer, intent(out) :: ierr
    real(dp) :: rz, alpha, beta, fnorm2, rnorm2, pq, rbound, mx(2), tot(2)
    real(dp) :: part(2, levels, 2)
    integer :: it, nn, nterms
    ierr = 0
    nn = op%nn
    if (.not. op%consistent) then
      a(:, 1:nn) = f(:, 1:nn)*op%inv_diag
      return
    end if
    op%n_solves = op%n_solves + 1
    op%last_iter = 0
    nterms = 2*op%nglobal
    ! residual of the start value
    op%p(:, 1:nn) = a(:, 1:nn)*op%free(:, 1:nn)
    call halo_exchange(dom%halo, op%p)
    call csr_matvec(nn, op%m%g%row_ptr, op%m%g%col, op%m%val, op%p, op%q)
    a(:, 1:nn) = op%p(:, 1:nn)
    op%r = (f(:, 1:nn) - op%q)*op%free(:, 1:nn)
    op%q = f(:, 1:nn)*op%free(:, 1:nn)
    fnorm2 = repro_dot(nn, op%q, op%q, op%nglobal)
    if (fnorm2 == 0.0_dp) then
      a(:, 1:nn) = 0.0_dp
      return
    end if
    rnorm2 = repro_dot(nn, op%r, op%r, op%nglobal)
    if (rnorm2 <= op%rtol**2*fnorm2) return
    ! first direction p = r/m (beta = 0) and r.p
    call cg_direction(nn, op%r, op%inv_diag, 0.0_dp, op%p, mx(1))
    rz = repro_dot(nn, op%r, op%p, op%nglobal)
    mx(2) = maxval(abs(op%r))
    call allreduce_max(mx)
    do it = 1, op%max_iter
      call halo_exchange(dom%halo, op%p)
      call cg_product(nn, op%m%g%row_ptr, op%m%g%col, op%m%val, op%p, op%q, &
          mx(1)**2*op%m_inf, nterms, part(:, :, 1))
      tot(1:1) = repro_totals(part(:, :, 1:1))
      pq = tot(1)
      alpha = rz/pq
      rbound = mx(2) + abs(alpha)*op%m_inf*mx(1)
      call cg_update(nn, alpha, op%p, op%q, op%inv_diag, a, op%r, rbound**2, &
          rbound**2*op%inv_max, nterms, part, mx(2))
      tot = repro_totals(part)
      rnorm2 = tot(1)
      op%last_iter = it
      if (rnorm2 <= op%rtol**2*fnorm2) exit
      beta = tot(2)/rz
      rz = tot(2)
      call cg_direction(nn, op%r, op%inv_diag, beta, op%p, mx(1))
      call allreduce_max(mx)
    end do
    op%total_iter = op%total_iter + op%last_iter
    if (rnorm2 > op%rtol**2*fnorm2) ierr = 1
  end subroutine mass_solve

  !> q = M p on the n owned rows (p with current ghosts) and this rank's level sums of p.q
  !! (lanes = the two components) for terms bounded by `bound`. The rows go in chunks whose
  !! q is still in the L1 cache when its terms are summed.
  subroutine cg_product(n, row_ptr, col, val, p, q, bound, nterms, part)
    integer, intent(in) :: n, nterms
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(*), p(2, *), bound
    real(dp), intent(inout) :: q(2, *)
    real(dp), intent(out) :: part(2, levels)
    integer, parameter :: chunk = 1024
    real(dp) :: sigma(levels), t, w
    integer :: i0, i, c, l
    call repro_sigma(bound, nterms, sigma)
    part = 0.0_dp
    do i0 = 1, n, chunk
      call csr_matvec(min(chunk, n - i0 + 1), row_ptr(i0), col, val, p, q(1, i0))
      do i = i0, min(i0 + chunk - 1, n)
        do c = 1, 2
          t = p(c, i)*q(c, i)
          do l = 1, levels
            w = (t + sigma(l)) - sigma(l)
            part(c, l) = part(c, l) + w
            t = t - w
          end do
        end do
      end do
    end do
  end subroutine cg_product

  !> a += alpha p; r -= alpha q on the free dofs (inv_diag > 0); level sums of r.r and
  !! r.(r/m) (bounded by brr and brz); rmax = max |r| on this rank.
  subroutine cg_update(n, alpha, p, q, inv_diag, a, r, brr, brz, nterms, part, rmax)
    integer, intent(in) :: n, nterms
    real(dp), intent(in) :: alpha, p(2, *), q(2, *), inv_diag(2, *), brr, brz
    real(dp), intent(inout) :: a(2, *), r(2, *)
    real(dp), intent(out) :: part(2, levels, 2), rmax
    real(dp) :: s_rr(levels), s_rz(levels), rc, t, w
    integer :: i, c, l
    call repro_sigma(brr, nterms, s_rr)
    call repro_sigma(brz, nterms, s_rz)
    part = 0.0_dp
    rmax = 0.0_dp
    do i = 1, n
      do c = 1, 2
        a(c, i) = a(c, i) + alpha*p(c, i)
        rc = r(c, i)
        if (inv_diag(c, i) > 0.0_dp) rc = rc - alpha*q(c, i)
        r(c, i) = rc
        rmax = max(rmax, abs(rc))
        t = rc*rc
        do l = 1, levels
          w = (t + s_rr(l)) - s_rr(l)
          part(c, l, 1) = part(c, l, 1) + w
          t = t - w
        end do
        t = rc*(rc*inv_diag(c, i))
        do l = 1, levels
          w = (t + s_rz(l)) - s_rz(l)
          part(c, l, 2) = part(c, l, 2) + w
          t = t - w
        end do
      end do
    end do
  end subroutine cg_update

  !> p = r/m + beta p on the owned dofs; pmax = max |p| on this rank.
  subroutine cg_direction(n, r, inv_diag, beta, p, pmax)
    integer, intent(in) :: n
    real(dp), intent(in) :: r(2, *), inv_diag(2, *), beta
    real(dp), intent(inout) :: p(2, *)
    real(dp), intent(out) :: pmax
    integer :: i, c
    pmax = 0.0_dp
    do i = 1, n
      do c = 1, 2
        p(c, i) = r(c, i)*inv_diag(c, i) + beta*p(c, i)
        pmax = max(pmax, abs(p(c, i)))
      end do
    end do
  end subroutine cg_direction
end module ictus_solver_mass_operator
