!> The small-strain guard: small-strain kinematics are not objective, so a rigid rotation of
!! a few tenths of a radian already shows as strain (a spun body grows). At output times a
!! small-strain run measures the largest infinitesimal rotation |du_y/dx - du_x/dy| / 2 of its
!! elements; above ROTATION_LIMIT the run warns once, naming the element and the time, and
!! points to NLGEOM=YES.
module ictus_solver_guard
  use ictus_core_kinds, only: dp
  use ictus_parallel_env, only: allreduce_max
  use ictus_elements_types, only: elem_shape_t, TASK_ROTATION
  use ictus_elements_library, only: element_routine, element_out_t
  use ictus_solver_model, only: model_t
  use ictus_solver_domain, only: domain_t, domain_owns
  use ictus_solver_assemble, only: element_shape, shape_cache_t
  implicit none
  private
  public :: largest_rotation, ROTATION_LIMIT

  !> Rotation (rad) above which small-strain kinematics are flagged.
  real(dp), parameter :: ROTATION_LIMIT = 0.1_dp

contains

  !> The largest infinitesimal rotation over the elements this rank owns and, on every rank,
  !! the global element e_at (the lowest index among the largest) where it occurs; u: local
  !! displacements (owned and ghosts, current).
  subroutine largest_rotation(model, dom, u, wmax, e_at)
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    real(dp), intent(in) :: u(:,:)
    real(dp), intent(out) :: wmax
    integer, intent(out) :: e_at
    type(shape_cache_t) :: cache
    type(elem_shape_t) :: shp
    type(element_out_t) :: out
    real(dp) :: wmine
    integer :: k, e, nen
    wmine = 0.0_dp
    e_at = 0
    do k = 1, dom%nelem
      e = dom%elem(k)
      if (.not. domain_owns(dom, k)) cycle
      nen = model%nen(e)
      call element_shape(model, e, model%gauss(:, e), cache, 1, shp)
      call element_routine(TASK_ROTATION, model%etype(e), shp, &
          model%x0(:, model%conn(1:nen, e)), model%materials(model%mat(e)), out, &
          u(:, dom%conn(1:nen, k)))
      if (out%ierr == 0 .and. out%scalar > wmine) then
        wmine = out%scalar
        e_at = e
      end if
    end do
    wmax = wmine
    call allreduce_max(wmax)
    if (wmine < wmax) e_at = 0
    e_at = -e_at
    if (e_at == 0) e_at = -huge(1)
    call allreduce_max(e_at)
    e_at = -e_at
  end subroutine largest_rotation
end module ictus_solver_guard
