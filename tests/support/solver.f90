!> Solver routines that only the tests use.
module ictus_test_solver
  use ictus_parallel_halo, only: halo_setup
  use ictus_solver_domain, only: domain_t
  implicit none
  private
  public :: domain_init_serial

contains

  !> A single-rank domain of nn nodes with no elements attached (for tests and tools that
  !! build operators by hand).
  subroutine domain_init_serial(dom, nn)
    type(domain_t), intent(out) :: dom
    integer, intent(in) :: nn
    integer :: i
    integer, allocatable :: none(:)
    dom%nn_global = nn
    allocate(dom%owner(nn), source=0)
    allocate(none(0))
    call halo_setup(dom%halo, [(i, i = 1, nn)], none, dom%owner)
    dom%nowned = nn
    dom%nlocal = nn
    dom%g2l = [(i, i = 1, nn)]
  end subroutine domain_init_serial
end module ictus_test_solver
