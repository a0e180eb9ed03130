!> The mass operator of the time loop: a = M^-1 f on the free dofs, and v -> M v.
!!
!! Lumped mass: a division by the nodal mass. Consistent mass: a Jacobi-preconditioned
!! conjugate gradient, warm-started from the caller's previous solution (accelerations change
!! little from one step to the next), which works unchanged on distributed vectors. All work
!! arrays are allocated once in `mass_op_init`; the solve allocates nothing.
module ictus_solver_mass_operator
  use ictus_core_kinds, only: dp
  use ictus_solver_sparse, only: csr_t, csr_matvec, csr_diagonal
  implicit none
  private
  public :: mass_op_t, mass_op_init, mass_solve, mass_apply

  type :: mass_op_t
    integer :: nn = 0
    logical :: consistent = .false.
    !> Consistent mass (scalar, acting on both components).
    type(csr_t) :: m
    !> Lumped masses (nn).
    real(dp), allocatable :: m_diag(:)
    !> 1/m on free dofs, 0 on fixed dofs and massless nodes (2, nn); also the preconditioner.
    real(dp), allocatable :: inv_diag(:,:)
    !> 1 on free dofs, 0 on fixed ones (2, nn).
    real(dp), allocatable :: free(:,:)
    !> Relative residual tolerance and iteration limit of the conjugate gradient.
    real(dp) :: rtol = 1.0e-12_dp
    integer :: max_iter = 500
    !> Statistics: iterations of the last solve, and summed over all solves.
    integer :: last_iter = 0
    integer :: total_iter = 0
    integer :: n_solves = 0
    !> Work vectors (2, nn).
    real(dp), allocatable :: r(:,:), z(:,:), p(:,:), q(:,:)
  end type mass_op_t

contains

  !> Sets up the operator. `m` is used only when `consistent`; `fixed(2, nn)` marks Dirichlet
  !! dofs, whose accelerations are zero.
  subroutine mass_op_init(op, nn, consistent, m, m_diag, fixed)
    type(mass_op_t), intent(out) :: op
    integer, intent(in) :: nn
    logical, intent(in) :: consistent
    type(csr_t), intent(in) :: m
    real(dp), intent(in) :: m_diag(nn)
    logical, intent(in) :: fixed(2, nn)
    real(dp), allocatable :: d(:)
    integer :: i, c
    op%nn = nn
    op%consistent = consistent
    op%m_diag = m_diag
    allocate(op%inv_diag(2, nn), op%free(2, nn))
    allocate(d(nn))
    if (consistent) then
      op%m = m
      call csr_diagonal(m, d)
      allocate(op%r(2, nn), op%z(2, nn), op%p(2, nn), op%q(2, nn))
    else
      d = m_diag
    end if
    do i = 1, nn
      do c = 1, 2
        if (fixed(c, i) .or. .not. d(i) > 0.0_dp) then
          op%free(c, i) = 0.0_dp
          op%inv_diag(c, i) = 0.0_dp
        else
          op%free(c, i) = 1.0_dp
          op%inv_diag(c, i) = 1.0_dp/d(i)
        end if
      end do
    end do
  end subroutine mass_op_init

  !> mv = M v (all dofs, no masking).
  subroutine mass_apply(op, v, mv)
    type(mass_op_t), intent(in) :: op
    real(dp), intent(in) :: v(:,:)
    real(dp), intent(out) :: mv(:,:)
    integer :: i
    if (op%consistent) then
      call csr_matvec(op%nn, op%m%g%row_ptr, op%m%g%col, op%m%val, v, mv)
    else
      do i = 1, op%nn
        mv(:, i) = op%m_diag(i)*v(:, i)
      end do
    end if
  end subroutine mass_apply

  !> Solves M a = f on the free dofs (a = 0 on fixed ones). For a consistent mass, `a` holds
  !! the start value on entry (e.g. the previous step's acceleration). `ierr` = 1 when the
  !! conjugate gradient did not converge.
  subroutine mass_solve(op, f, a, ierr)
    type(mass_op_t), intent(inout) :: op
    real(dp), intent(in) :: f(:,:)
    real(dp), intent(inout) :: a(:,:)
    integer, intent(out) :: ierr
    real(dp) :: rz, rz_new, alpha, beta, fnorm2, rnorm2, pq
    integer :: it
    ierr = 0
    if (.not. op%consistent) then
      a = f*op%inv_diag
      return
    end if
    a = a*op%free
    call csr_matvec(op%nn, op%m%g%row_ptr, op%m%g%col, op%m%val, a, op%q)
    op%r = (f - op%q)*op%free
    fnorm2 = sum((f*op%free)**2)
    op%n_solves = op%n_solves + 1
    op%last_iter = 0
    if (fnorm2 == 0.0_dp) then
      a = 0.0_dp
      return
    end if
    rnorm2 = sum(op%r**2)
    if (rnorm2 <= op%rtol**2*fnorm2) return
    op%z = op%r*op%inv_diag
    op%p = op%z
    rz = sum(op%r*op%z)
    do it = 1, op%max_iter
      call csr_matvec(op%nn, op%m%g%row_ptr, op%m%g%col, op%m%val, op%p, op%q)
      op%q = op%q*op%free
      pq = sum(op%p*op%q)
      alpha = rz/pq
      a = a + alpha*op%p
      op%r = op%r - alpha*op%q
      rnorm2 = sum(op%r**2)
      op%last_iter = it
      if (rnorm2 <= op%rtol**2*fnorm2) exit
      op%z = op%r*op%inv_diag
      rz_new = sum(op%r*op%z)
      beta = rz_new/rz
      rz = rz_new
      op%p = op%z + beta*op%p
    end do
    op%total_iter = op%total_iter + op%last_iter
    if (rnorm2 > op%rtol**2*fnorm2) ierr = 1
  end subroutine mass_solve
end module ictus_solver_mass_operator
