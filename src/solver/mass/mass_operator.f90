!> The mass operator of the time loop: a = M^-1 f on the free dofs, and v -> M v.
!!
!! Lumped mass: a division by the nodal mass (ictus_solver_mass_lumped). Consistent mass, by
!! the solver the deck names (MASS SOLVER), each an implementation of `mass_solver_t`
!! (ictus_solver_mass_solver) in a file of its own in this folder:
!!
!! * MASS_SOLVER_AUTO (the default of the deck) resolves at set-up to KRONECKER when the model
!!   is made of tensor-product lattices whose mass that solver proves it solves exactly, and
!!   to CHOLESKY otherwise (the log says which, and why).
!! * MASS_SOLVER_KRONECKER: exact solves along the lattice directions (kronecker.f90).
!! * MASS_SOLVER_CHOLESKY: the sparse Cholesky factor of M (cholesky_solver.f90).
!! * MASS_SOLVER_CG: a Jacobi-preconditioned conjugate gradient (cg.f90).
!! * MASS_SOLVER_CORRECTOR: a fixed number of row-sum-preconditioned passes (corrector.f90).
!!
!! `mass_op_init` sets up the shared data and calls the set-up of the solver (one line per
!! solver); the other routines dispatch to it once per call. All work arrays are allocated
!! once in `mass_op_init`; a solve allocates nothing.
module ictus_solver_mass_operator
  use ictus_core_kinds, only: dp
  use ictus_core_memory, only: alloc_stream
  use ictus_core_errors, only: fatal
  use ictus_core_logger, only: log_info
  use ictus_parallel_env, only: allreduce_max
  use ictus_solver_sparse, only: csr_t
  use ictus_solver_domain, only: domain_t
  use ictus_solver_model, only: MASS_SOLVER_CG, MASS_SOLVER_CHOLESKY, MASS_SOLVER_CORRECTOR, &
      MASS_SOLVER_KRONECKER, MASS_SOLVER_AUTO
  use ictus_solver_tensor_types, only: tensor_layout_t
  use ictus_solver_mass_solver, only: mass_core_t, mass_solver_t
  use ictus_solver_mass_gathered, only: gathered_mass_t
  use ictus_solver_mass_lumped, only: lumped_init
  use ictus_solver_mass_cg, only: cg_init
  use ictus_solver_mass_corrector, only: corrector_init, mass_min_entry
  use ictus_solver_mass_cholesky, only: cholesky_init
  use ictus_solver_mass_kronecker, only: kronecker_init
  implicit none
  private
  public :: mass_op_t, mass_op_init, mass_solve, mass_apply, mass_set_added, mass_step, &
      mass_steps_fused, mass_op_report, &
      mass_min_entry, MASS_SOLVER_CG, MASS_SOLVER_CHOLESKY, MASS_SOLVER_CORRECTOR, &
      MASS_SOLVER_KRONECKER, MASS_SOLVER_AUTO

  !> The shared data (mass_core_t: sizes, lumped masses, inv_diag, free, statistics, set-up
  !! message), the solver taken and its implementation.
  type, extends(mass_core_t) :: mass_op_t
    !> Consistent-mass solver (MASS_SOLVER_*; AUTO is resolved by mass_op_init).
    integer :: solver = MASS_SOLVER_CG
    class(mass_solver_t), allocatable :: impl
  end type mass_op_t

contains

  !> Sets up the operator for the rows of `dom`. `m` is used only when `consistent`;
  !! `fixed(ndm, nlocal)` marks Dirichlet dofs, whose accelerations are zero; `rtol` is the
  !! relative residual at which the conjugate gradient stops (default 1e-12); `solver` is a
  !! MASS_SOLVER_* (default CG); `passes` the corrector's k (default 2). `ierr` (when
  !! present) is 0, or 1 when the Cholesky factor cannot be made (see
  !! ictus_solver_mass_cholesky) or the corrector meets a negative entry of M; without it such
  !! a failure is fatal. `layout` (the model's lattices, ictus_solver_tensor_layout) is needed
  !! by MASS_SOLVER_KRONECKER and AUTO; without it they are refused (AUTO: the Cholesky
  !! factor).
  subroutine mass_op_init(op, dom, consistent, m, m_diag, fixed, rtol, solver, ierr, passes, &
      layout)
    type(mass_op_t), intent(out) :: op
    type(domain_t), intent(in) :: dom
    logical, intent(in) :: consistent
    type(csr_t), intent(in) :: m
    real(dp), intent(in) :: m_diag(:)
    logical, intent(in) :: fixed(:,:)
    real(dp), intent(in), optional :: rtol
    integer, intent(in), optional :: solver
    integer, intent(out), optional :: ierr
    integer, intent(in), optional :: passes
    type(tensor_layout_t), intent(in), optional :: layout
    type(gathered_mass_t) :: gm
    integer :: err, e
    character(len=:), allocatable :: msg
    op%nn = dom%nowned
    op%nlocal = dom%nlocal
    op%nglobal = dom%nn_global
    op%consistent = consistent
    if (present(solver)) op%solver = solver
    if (present(ierr)) ierr = 0
    op%m_diag = m_diag(1:op%nn)
    call alloc_stream(op%inv_diag, size(fixed, 1), op%nn, 0.0_dp)
    call alloc_stream(op%free, size(fixed, 1), dom%nlocal, 0.0_dp)
    if (.not. consistent) then
      call lumped_init(op%impl, op%mass_core_t, fixed)
      return
    end if
    err = 0
    select case (op%solver)
    case (MASS_SOLVER_CG)
      call cg_init(op%impl, op%mass_core_t, m, fixed, rtol)
    case (MASS_SOLVER_CORRECTOR)
      call corrector_init(op%impl, op%mass_core_t, m, fixed, passes, err, msg)
    case (MASS_SOLVER_CHOLESKY)
      call cholesky_init(op%impl, op%mass_core_t, dom, m, fixed, gm, err, msg)
    case (MASS_SOLVER_KRONECKER, MASS_SOLVER_AUTO)
      call kronecker_init(op%impl, op%mass_core_t, dom, m, fixed, gm, err, msg, layout)
      if (err == 0) then
        op%solver = MASS_SOLVER_KRONECKER
      else if (op%solver == MASS_SOLVER_AUTO) then
        call log_info('consistent mass: not solved along lattice directions ('//msg// &
            '); Cholesky factor instead')
        op%setup_msg = msg
        op%solver = MASS_SOLVER_CHOLESKY
        call cholesky_init(op%impl, op%mass_core_t, dom, m, fixed, gm, err, msg)
      else
        msg = 'MASS SOLVER=KRONECKER: '//msg
      end if
    case default
      call fatal('consistent mass', 'unknown MASS SOLVER', 1)
    end select
    ! one decision for all ranks (a rank alone must not stop)
    e = merge(1, 0, err /= 0)
    call allreduce_max(e)
    if (e /= 0) then
      if (err == 0) msg = 'the set-up of the mass solve failed on another rank'
      op%setup_msg = msg
      if (.not. present(ierr)) call fatal('consistent mass', msg, 1)
      ierr = 1
      call log_info('consistent mass: '//msg)
    end if
  end subroutine mass_op_init

  !> Lumped mass only: owned node i gets the added mass dm >= 0 in the solve a = M^-1 f
  !! (bipenalty, doc/contact.md §6a): inv_diag = 1/(m_i + dm) on its free dofs; dm = 0 restores
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
    call op%impl%apply(op%mass_core_t, v, mv)
  end subroutine mass_apply

  !> Solves M a = f on the free owned dofs (a = 0 on fixed ones); f and a are (2, >= nn).
  !! For a consistent mass, `a` holds the start value on entry (e.g. the previous step's
  !! acceleration), and the solve is counted. `ierr` = 1 when the conjugate gradient did not
  !! converge.
  subroutine mass_solve(op, dom, f, a, ierr)
    type(mass_op_t), intent(inout) :: op
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: f(:,:)
    real(dp), intent(inout) :: a(:,:)
    integer, intent(out) :: ierr
    if (op%consistent) then
      op%n_solves = op%n_solves + 1
      op%last_iter = 0
    end if
    call op%impl%solve(op%mass_core_t, dom, f, a, ierr)
  end subroutine mass_solve

  !> Whether `mass_step` can fold the velocity and displacement updates of a step into the
  !! solve (a consistent mass solved along the lattice directions on one rank).
  pure logical function mass_steps_fused(op)
    type(mass_op_t), intent(in) :: op
    mass_steps_fused = .false.
    if (op%consistent) mass_steps_fused = op%impl%fused()
  end function mass_steps_fused

  !> The undamped step's updates with the solve folded in (needs mass_steps_fused): with
  !! kf = K u on the owned nodes, v <- v - dt M^-1 kf and u_next <- u + dt v, the same bits
  !! as mass_solve of -kf followed by v = v + dt a and u_next = u + dt v, without the passes
  !! over the acceleration (which is not stored).
  subroutine mass_step(op, kf, dt, u, v, u_next)
    type(mass_op_t), intent(inout) :: op
    real(dp), intent(in) :: kf(:,:), dt, u(:,:)
    real(dp), intent(inout) :: v(:,:), u_next(:,:)
    op%n_solves = op%n_solves + 1
    op%last_iter = 0
    call op%impl%step(op%mass_core_t, kf, dt, u, v, u_next)
  end subroutine mass_step

  !> The end-of-run line of the log about the mass solves ('' for a lumped mass), e.g.
  !! 'consistent mass: 100 solves with the Cholesky factor'.
  function mass_op_report(op) result(line)
    type(mass_op_t), intent(in) :: op
    character(len=:), allocatable :: line
    line = op%impl%report(op%mass_core_t)
  end function mass_op_report
end module ictus_solver_mass_operator
