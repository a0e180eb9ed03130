!> The lumped mass of the mass operator (ictus_solver_mass_solver): a division by the nodal
!! mass. Its data are the shared m_diag and inv_diag (which the stepper and the contact also
!! read directly, and `mass_set_added` changes).
module ictus_solver_mass_lumped
  use ictus_core_kinds, only: dp
  use ictus_solver_domain, only: domain_t
  use ictus_solver_mass_solver, only: mass_core_t, mass_solver_t, core_diagonal
  implicit none
  private
  public :: lumped_init

  type, extends(mass_solver_t) :: lumped_solver_t
  contains
    procedure :: solve => lumped_solve
    procedure :: apply => lumped_apply
    procedure :: report => lumped_report
  end type lumped_solver_t

contains

  !> The lumped solver of the masses c%m_diag with the dofs `fixed(ndm, nlocal)`.
  subroutine lumped_init(s, c, fixed)
    class(mass_solver_t), allocatable, intent(out) :: s
    type(mass_core_t), intent(inout) :: c
    logical, intent(in) :: fixed(:,:)
    call core_diagonal(c, c%m_diag, fixed)
    allocate(lumped_solver_t :: s)
  end subroutine lumped_init

  subroutine lumped_solve(self, c, dom, f, a, ierr)
    class(lumped_solver_t), intent(inout) :: self
    type(mass_core_t), intent(inout) :: c
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: f(:,:)
    real(dp), intent(inout) :: a(:,:)
    integer, intent(out) :: ierr
    ierr = 0
    a(:, 1:c%nn) = f(:, 1:c%nn)*c%inv_diag
  end subroutine lumped_solve

  subroutine lumped_apply(self, c, v, mv)
    class(lumped_solver_t), intent(in) :: self
    type(mass_core_t), intent(in) :: c
    real(dp), intent(in) :: v(:,:)
    real(dp), intent(inout) :: mv(:,:)
    integer :: i
    do i = 1, c%nn
      mv(:, i) = c%m_diag(i)*v(:, i)
    end do
  end subroutine lumped_apply

  function lumped_report(self, c) result(line)
    class(lumped_solver_t), intent(in) :: self
    type(mass_core_t), intent(in) :: c
    character(len=:), allocatable :: line
    line = ''
  end function lumped_report
end module ictus_solver_mass_lumped
