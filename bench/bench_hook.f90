!> The contact correction between the predictor and the update of the benchmark's steps, in
!! the form the sweeps of the linear lumped stepper call it (ictus_solver_explicit's
!! between_steps_t).
module ictus_bench_hook
  use ictus_core_kinds, only: dp
  use ictus_solver_explicit, only: state_t, between_steps_t
  use ictus_solver_mass_operator, only: mass_op_t
  use ictus_solver_domain, only: domain_t
  use ictus_solver_contact_step, only: contact_step_t, contact_correct
  use ictus_contact_contact, only: contact_t
  implicit none
  private
  public :: bench_hook_t

  !> What the correction acts on, kept by the benchmark program.
  type, extends(between_steps_t) :: bench_hook_t
    type(contact_step_t), pointer :: cs => null()
    type(contact_t), pointer :: contact => null()
    type(state_t), pointer :: s => null()
    type(mass_op_t), pointer :: mop => null()
    type(domain_t), pointer :: dom => null()
    real(dp), pointer :: x0(:,:) => null()
  contains
    procedure :: run => hook_run
  end type bench_hook_t

contains

  !> The contact correction of the current step (none without contact pairs).
  subroutine hook_run(this)
    class(bench_hook_t), intent(inout) :: this
    if (this%contact%npairs > 0) call contact_correct(this%cs, this%contact, this%s, this%mop, &
        this%dom, this%x0)
  end subroutine hook_run
end module ictus_bench_hook
