!> The interface every mass solver of the mass operator (ictus_solver_mass_operator)
!! implements, and the data they share with it.
!!
!! A solver is a type that extends `mass_solver_t` (one file per solver in this folder). Its
!! set-up is a module procedure of its own file that takes what that solver needs, allocates
!! the operator's `class(mass_solver_t)` as its type, fills the shared `inv_diag` and `free`
!! (`core_diagonal`; a consistent solver by `consistent_setup`, which also keeps M) and its
!! own fields; `mass_op_init` calls it in one line of its `select case`. The operator then calls `solve`, `apply`, `report` (and `fused`, `step`)
!! once per call, so a solver sees whole vectors and the dispatch costs nothing per node.
module ictus_solver_mass_solver
  use ictus_core_kinds, only: dp
  use ictus_core_errors, only: fatal
  use ictus_solver_sparse, only: csr_t, csr_matvec, csr_copy, csr_diagonal, csr_row_sums
  use ictus_solver_domain, only: domain_t
  implicit none
  private
  public :: mass_core_t, mass_solver_t, consistent_solver_t, core_diagonal, consistent_setup

  !> What every solver shares with the operator, and what the stepper and the contact read.
  type :: mass_core_t
    !> Owned nodes (rows), local nodes (owned + ghost), global nodes.
    integer :: nn = 0
    integer :: nlocal = 0
    integer :: nglobal = 0
    logical :: consistent = .false.
    !> Lumped masses (owned nodes).
    real(dp), allocatable :: m_diag(:)
    !> 1/m on free dofs, 0 on fixed dofs and massless nodes (ndm, nn); also the preconditioner
    !! (for a consistent mass m is its diagonal, or with the corrector its row sum).
    real(dp), allocatable :: inv_diag(:,:)
    !> 1 on free dofs, 0 on fixed ones (ndm, nlocal).
    real(dp), allocatable :: free(:,:)
    !> Statistics: iterations of the last solve, and summed over all solves.
    integer :: last_iter = 0
    integer :: total_iter = 0
    integer :: n_solves = 0
    !> Why the set-up refused a solver (AUTO: why it is not KRONECKER).
    character(len=:), allocatable :: setup_msg
  end type mass_core_t

  !> A mass solver: a = M^-1 f on the free owned dofs and mv = M v, with the shared data `c`.
  type, abstract :: mass_solver_t
  contains
    procedure(solve_i), deferred :: solve
    procedure(apply_i), deferred :: apply
    procedure(report_i), deferred :: report
    procedure :: fused => never_fused
    procedure :: step => no_step
  end type mass_solver_t

  !> A solver of a consistent mass: it keeps the matrix, whose product is `apply`.
  type, abstract, extends(mass_solver_t) :: consistent_solver_t
    !> Consistent mass (scalar, acting on both components), this rank's rows.
    type(csr_t) :: m
  contains
    procedure :: apply => consistent_apply
  end type consistent_solver_t

  abstract interface
    !> Solves M a = f on the free owned dofs (a = 0 on fixed ones); f and a are (2, >= nn),
    !! `a` holds a start value on entry. ierr = 1 when an iterative solve did not converge.
    !! Updates c%last_iter and c%total_iter.
    subroutine solve_i(self, c, dom, f, a, ierr)
      import :: mass_solver_t, mass_core_t, domain_t, dp
      class(mass_solver_t), intent(inout) :: self
      type(mass_core_t), intent(inout) :: c
      type(domain_t), intent(inout) :: dom
      real(dp), intent(in) :: f(:,:)
      real(dp), intent(inout) :: a(:,:)
      integer, intent(out) :: ierr
    end subroutine solve_i

    !> mv = M v on the owned rows (v with current ghost values for a consistent mass).
    subroutine apply_i(self, c, v, mv)
      import :: mass_solver_t, mass_core_t, dp
      class(mass_solver_t), intent(in) :: self
      type(mass_core_t), intent(in) :: c
      real(dp), intent(in) :: v(:,:)
      real(dp), intent(inout) :: mv(:,:)
    end subroutine apply_i

    !> The end-of-run line of the log about the solves ('' for none).
    function report_i(self, c) result(line)
      import :: mass_solver_t, mass_core_t
      class(mass_solver_t), intent(in) :: self
      type(mass_core_t), intent(in) :: c
      character(len=:), allocatable :: line
    end function report_i
  end interface

contains

  !> Whether `step` folds the updates of a step into the solve (by default not).
  pure logical function never_fused(self)
    class(mass_solver_t), intent(in) :: self
    never_fused = .false.
  end function never_fused

  !> The step with the solve folded in (`mass_step`), for the solvers whose `fused` is true:
  !! with kf = K u, v <- v - dt M^-1 kf and u_next <- u + dt v. Other solvers stop here.
  subroutine no_step(self, c, kf, dt, u, v, u_next)
    class(mass_solver_t), intent(inout) :: self
    type(mass_core_t), intent(in) :: c
    real(dp), intent(in) :: kf(:,:), dt, u(:,:)
    real(dp), intent(inout) :: v(:,:), u_next(:,:)
    call fatal('mass_step', 'this mass solver does not fold the step into its solve')
  end subroutine no_step

  subroutine consistent_apply(self, c, v, mv)
    class(consistent_solver_t), intent(in) :: self
    type(mass_core_t), intent(in) :: c
    real(dp), intent(in) :: v(:,:)
    real(dp), intent(inout) :: mv(:,:)
    call csr_matvec(c%nn, self%m%g%row_ptr, self%m%g%col, self%m%val, v, mv, size(v, 1))
  end subroutine consistent_apply

  !> What the set-up of every consistent solver starts with: s%m <- m (this rank's rows), and
  !! c%free, c%inv_diag from the diagonal of m or, with `row_sums`, its row sums.
  subroutine consistent_setup(s, c, m, fixed, row_sums)
    class(consistent_solver_t), intent(inout) :: s
    type(mass_core_t), intent(inout) :: c
    type(csr_t), intent(in) :: m
    logical, intent(in) :: fixed(:,:)
    logical, intent(in), optional :: row_sums
    real(dp), allocatable :: d(:)
    logical :: sums
    sums = .false.
    if (present(row_sums)) sums = row_sums
    allocate(d(c%nn))
    call csr_copy(s%m, m)
    if (sums) then
      call csr_row_sums(m, d)
    else
      call csr_diagonal(m, d)
    end if
    call core_diagonal(c, d, fixed)
  end subroutine consistent_setup

  !> c%free and c%inv_diag from the dofs `fixed(ndm, nlocal)` and the diagonal d (owned nodes)
  !! that the solver divides by: a dof is free when not fixed and its node has d > 0.
  subroutine core_diagonal(c, d, fixed)
    type(mass_core_t), intent(inout) :: c
    real(dp), intent(in) :: d(:)
    logical, intent(in) :: fixed(:,:)
    integer :: i, k
    do i = 1, c%nlocal
      do k = 1, size(fixed, 1)
        c%free(k, i) = merge(0.0_dp, 1.0_dp, fixed(k, i))
      end do
    end do
    do i = 1, c%nn
      do k = 1, size(fixed, 1)
        if (fixed(k, i) .or. .not. d(i) > 0.0_dp) then
          c%free(k, i) = 0.0_dp
          c%inv_diag(k, i) = 0.0_dp
        else
          c%inv_diag(k, i) = 1.0_dp/d(i)
        end if
      end do
    end do
  end subroutine core_diagonal
end module ictus_solver_mass_solver
