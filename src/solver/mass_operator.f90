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
  use ictus_parallel_repro, only: repro_dot
  use ictus_parallel_halo, only: halo_exchange
  use ictus_solver_sparse, only: csr_t, csr_matvec, csr_diagonal
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
    integer :: max_iter = 500
    !> Statistics: iterations of the last solve, and summed over all solves.
    integer :: last_iter = 0
    integer :: total_iter = 0
    integer :: n_solves = 0
    !> Work vectors (2, nlocal).
    real(dp), allocatable :: r(:,:), z(:,:), p(:,:), q(:,:)
  end type mass_op_t

contains

  !> Sets up the operator for the rows of `dom`. `m` is used only when `consistent`;
  !! `fixed(2, nlocal)` marks Dirichlet dofs, whose accelerations are zero.
  subroutine mass_op_init(op, dom, consistent, m, m_diag, fixed)
    type(mass_op_t), intent(out) :: op
    type(domain_t), intent(in) :: dom
    logical, intent(in) :: consistent
    type(csr_t), intent(in) :: m
    real(dp), intent(in) :: m_diag(:)
    logical, intent(in) :: fixed(:,:)
    real(dp), allocatable :: d(:)
    integer :: i, c, nn
    nn = dom%nowned
    op%nn = nn
    op%nlocal = dom%nlocal
    op%nglobal = dom%nn_global
    op%consistent = consistent
    op%m_diag = m_diag(1:nn)
    allocate(op%inv_diag(2, nn), op%free(2, dom%nlocal))
    allocate(d(nn))
    if (consistent) then
      op%m = m
      call csr_diagonal(m, d)
      allocate(op%r(2, nn), op%z(2, nn), op%q(2, nn), op%p(2, dom%nlocal))
      op%p = 0.0_dp
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
  subroutine mass_solve(op, dom, f, a, ierr)
    type(mass_op_t), intent(inout) :: op
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: f(:,:)
    real(dp), intent(inout) :: a(:,:)
    integer, intent(out) :: ierr
    real(dp) :: rz, rz_new, alpha, beta, fnorm2, rnorm2, pq
    integer :: it, nn
    ierr = 0
    nn = op%nn
    if (.not. op%consistent) then
      a(:, 1:nn) = f(:, 1:nn)*op%inv_diag
      return
    end if
    op%n_solves = op%n_solves + 1
    op%last_iter = 0
    ! residual of the start value
    op%p(:, 1:nn) = a(:, 1:nn)*op%free(:, 1:nn)
    call halo_exchange(dom%halo, op%p)
    call csr_matvec(nn, op%m%g%row_ptr, op%m%g%col, op%m%val, op%p, op%q)
    a(:, 1:nn) = op%p(:, 1:nn)
    op%r = (f(:, 1:nn) - op%q)*op%free(:, 1:nn)
    op%z = f(:, 1:nn)*op%free(:, 1:nn)
    fnorm2 = repro_dot(nn, op%z, op%z, op%nglobal)
    if (fnorm2 == 0.0_dp) then
      a(:, 1:nn) = 0.0_dp
      return
    end if
    rnorm2 = repro_dot(nn, op%r, op%r, op%nglobal)
    if (rnorm2 <= op%rtol**2*fnorm2) return
    op%z = op%r*op%inv_diag
    op%p(:, 1:nn) = op%z
    rz = repro_dot(nn, op%r, op%z, op%nglobal)
    do it = 1, op%max_iter
      call halo_exchange(dom%halo, op%p)
      call csr_matvec(nn, op%m%g%row_ptr, op%m%g%col, op%m%val, op%p, op%q)
      op%q = op%q*op%free(:, 1:nn)
      pq = repro_dot(nn, op%p, op%q, op%nglobal)
      alpha = rz/pq
      a(:, 1:nn) = a(:, 1:nn) + alpha*op%p(:, 1:nn)
      op%r = op%r - alpha*op%q
      rnorm2 = repro_dot(nn, op%r, op%r, op%nglobal)
      op%last_iter = it
      if (rnorm2 <= op%rtol**2*fnorm2) exit
      op%z = op%r*op%inv_diag
      rz_new = repro_dot(nn, op%r, op%z, op%nglobal)
      beta = rz_new/rz
      rz = rz_new
      op%p(:, 1:nn) = op%z + beta*op%p(:, 1:nn)
    end do
    op%total_iter = op%total_iter + op%last_iter
    if (rnorm2 > op%rtol**2*fnorm2) ierr = 1
  end subroutine mass_solve
end module ictus_solver_mass_operator
