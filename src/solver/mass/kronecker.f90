!> MASS SOLVER=KRONECKER of the mass operator (ictus_solver_mass_solver): exact solves by 1D
!! banded factors along the lattice directions of NURBS patches and rectangular Q4/Q8/Q9
!! grids (ictus_solver_tensor_types and the tensor_*.f90 files). Like the Cholesky factor it
!! runs on every rank on the gathered f (ictus_solver_mass_gathered), so the bits do not
!! depend on the number of ranks; its memory is a few vectors. On one rank the owned nodes
!! are the global ones, in order: the solve reads f and writes a directly, and `step` folds
!! the velocity and displacement updates of a step into the solve.
module ictus_solver_mass_kronecker
  use ictus_core_kinds, only: dp
  use ictus_core_logger, only: log_info
  use ictus_core_strings, only: str
  use ictus_core_timer, only: wall_time
  use ictus_parallel_env, only: env_size
  use ictus_solver_sparse, only: csr_t
  use ictus_solver_domain, only: domain_t
  use ictus_solver_tensor_types, only: tensor_layout_t, tensor_mass_t
  use ictus_solver_tensor_setup, only: tensor_mass_setup, tensor_mass_renumber, &
      tensor_mass_describe
  use ictus_solver_tensor_solve, only: tensor_mass_solve, tensor_mass_step
  use ictus_solver_mass_solver, only: mass_core_t, mass_solver_t, consistent_solver_t, &
      consistent_setup
  use ictus_solver_mass_gathered, only: gathered_mass_t, gathered_t, gather_mass, &
      gathered_setup, gathered_loads
  implicit none
  private
  public :: kronecker_init

  !> The solver on the lattices and, on several ranks, the gathered loads and solution.
  type, extends(consistent_solver_t) :: kronecker_solver_t
    type(tensor_mass_t) :: tm
    type(gathered_t) :: g
  contains
    procedure :: solve => kronecker_solve
    procedure :: report => kronecker_report
    procedure :: fused => kronecker_fused
    procedure :: step => kronecker_step
  end type kronecker_solver_t

contains

  !> The Kronecker solver of the consistent mass m (this rank's rows) with the dofs
  !! `fixed(2, nlocal)` on the lattices `layout` of the model; gm is the gathered mass, made
  !! here unless another solver's set-up made it. err = 1 with `msg` when the layout is
  !! absent or the mass is not what the lattices promise.
  subroutine kronecker_init(s, c, dom, m, fixed, gm, err, msg, layout)
    class(mass_solver_t), allocatable, intent(out) :: s
    type(mass_core_t), intent(inout) :: c
    type(domain_t), intent(in) :: dom
    type(csr_t), intent(in) :: m
    logical, intent(in) :: fixed(:,:)
    type(gathered_mass_t), intent(inout) :: gm
    integer, intent(out) :: err
    character(len=:), allocatable, intent(out) :: msg
    type(tensor_layout_t), intent(in), optional :: layout
    type(kronecker_solver_t), allocatable :: t
    allocate(t)
    call consistent_setup(t, c, m, fixed)
    call gather_mass(gm, c, dom, m, fixed)
    if (present(layout)) then
      call kronecker_setup(t, c, dom, layout, gm, err, msg)
    else
      err = 1
      msg = 'no lattice layout of the model was given'
    end if
    call move_alloc(t, s)
  end subroutine kronecker_init

  !> The solver of the gathered mass gm on every rank; on several ranks its node numbers are
  !! the positions in the gathered vectors. err = 1 with `msg` when the mass is not what the
  !! lattices promise.
  subroutine kronecker_setup(s, c, dom, layout, gm, err, msg)
    type(kronecker_solver_t), intent(inout) :: s
    type(mass_core_t), intent(in) :: c
    type(domain_t), intent(in) :: dom
    type(tensor_layout_t), intent(in) :: layout
    type(gathered_mass_t), intent(in) :: gm
    integer, intent(out) :: err
    character(len=:), allocatable, intent(out) :: msg
    integer, allocatable :: pos(:)
    integer :: q, ng, np
    real(dp) :: t0
    t0 = wall_time()
    ng = c%nglobal
    np = env_size()
    call tensor_mass_setup(s%tm, layout, ng, gm%row_ptr, gm%col, gm%val, gm%keep, err, msg)
    if (err /= 0) return
    if (np > 1) then
      ! read and write the gathered vectors: node g is at position pos(g)
      allocate(pos(ng))
      do q = 1, ng
        pos(gm%gid(q)) = q
      end do
      call tensor_mass_renumber(s%tm, pos)
      call gathered_setup(s%g, c, dom, gm%cnt)
    end if
    call log_info('consistent mass: solved along lattice directions (MASS SOLVER=KRONECKER) '// &
        'on '//tensor_mass_describe(s%tm)//', set-up and check '//str(wall_time() - t0, 3)// &
        ' s')
  end subroutine kronecker_setup

  subroutine kronecker_solve(self, c, dom, f, a, ierr)
    class(kronecker_solver_t), intent(inout) :: self
    type(mass_core_t), intent(inout) :: c
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: f(:,:)
    real(dp), intent(inout) :: a(:,:)
    integer, intent(out) :: ierr
    ierr = 0
    if (.not. allocated(self%g%fall)) then
      call tensor_mass_solve(self%tm, f, a)
      return
    end if
    call gathered_loads(self%g, c, f)
    call tensor_mass_solve(self%tm, self%g%fall, self%g%x)
    a(:, 1:c%nn) = self%g%x(:, self%g%offset + 1:self%g%offset + c%nn)
  end subroutine kronecker_solve

  !> The step can fold the solve on one rank (on several the solve runs on the gathered
  !! loads, and the step takes mass_solve and its updates).
  pure logical function kronecker_fused(self)
    class(kronecker_solver_t), intent(in) :: self
    kronecker_fused = .not. allocated(self%g%fall)
  end function kronecker_fused

  !> v <- v - dt M^-1 kf and u_next <- u + dt v, the same bits as the solve of -kf followed
  !! by v = v + dt a and u_next = u + dt v (ictus_solver_tensor_solve, tensor_mass_step).
  subroutine kronecker_step(self, c, kf, dt, u, v, u_next)
    class(kronecker_solver_t), intent(inout) :: self
    type(mass_core_t), intent(in) :: c
    real(dp), intent(in) :: kf(:,:), dt, u(:,:)
    real(dp), intent(inout) :: v(:,:), u_next(:,:)
    call tensor_mass_step(self%tm, kf, dt, u, v, u_next)
  end subroutine kronecker_step

  function kronecker_report(self, c) result(line)
    class(kronecker_solver_t), intent(in) :: self
    type(mass_core_t), intent(in) :: c
    character(len=:), allocatable :: line
    line = 'consistent mass: '//str(c%n_solves)//' solves along the lattice directions'
  end function kronecker_report
end module ictus_solver_mass_kronecker
