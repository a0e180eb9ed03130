!> The internal-force seam: f_int(u, history) and the strain energy, by one of two
!! implementations that the model chooses.
!!
!! - ASSEMBLED: f = K u with the constant stiffness (ictus_solver_force_assembled). Exact for
!!   linear laws in small strain, and the fastest: the step is then a memory-bound sparse
!!   product, and the linear lumped stepper fuses it with the updates.
!! - ELEMENT: a loop over the elements that calls the material law at every quadrature point
!!   (ictus_solver_force_element). What laws with history and finite strain need.
!!
!! `*DYNAMIC, EXPLICIT, INTERNAL FORCE=AUTO|ASSEMBLED|ELEMENT` chooses; AUTO takes ASSEMBLED
!! where every law has a constant tangent, in 3D only while K's 3 x 3 blocks take at most half
!! the memory available (ictus_solver_assemble). ELEMENT on a linear model is the check that
!! both agree (to round-off).
module ictus_solver_internal_force
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: str
  use ictus_solver_model, only: model_t, model_force_kind, FORCE_AUTO, FORCE_ASSEMBLED, &
      FORCE_ELEMENT
  use ictus_solver_assemble, only: operators_t
  use ictus_solver_domain, only: domain_t
  use ictus_solver_sparse, only: bsr_t
  use ictus_solver_force_assembled, only: assembled_force_t, assembled_init, assembled_apply, &
      assembled_energy
  use ictus_solver_force_element, only: element_force_t, element_loop_init, &
      element_loop_apply, element_loop_energy, element_loop_bytes, element_loop_dissipation, &
      element_loop_stable
  implicit none
  private
  public :: force_op_t, force_op_init, force_apply, force_energy, force_kind_name, &
      force_choice, force_hist_shape, force_dissipation, force_dissipates, force_stable, &
      force_choice_note, FORCE_ASSEMBLED, FORCE_ELEMENT

  type :: force_op_t
    !> FORCE_ASSEMBLED or FORCE_ELEMENT.
    integer :: kind = FORCE_ASSEMBLED
    !> Owned rows and the global number of nodes.
    integer :: nn = 0
    integer :: nglobal = 0
    type(assembled_force_t) :: asm
    type(element_force_t) :: el
  end type force_op_t

contains

  !> The implementation a model gets: the deck's choice, or for FORCE_AUTO the assembled K
  !! where every material law is linear, the strain small and no element shares its mean
  !! dilatation (`model_force_kind`). With `k` (the assembled operators' stiffness), a 3D model
  !! whose K was not assembled (AUTO short of memory: ictus_solver_assemble) takes the element
  !! loop.
  integer function force_choice(model, k)
    type(model_t), intent(in) :: model
    type(bsr_t), intent(in), optional :: k
    force_choice = model_force_kind(model)
    if (.not. present(k) .or. force_choice /= FORCE_ASSEMBLED) return
    if (.not. allocated(k%val)) force_choice = FORCE_ELEMENT
  end function force_choice

  !> Why a 3D model under INTERNAL FORCE=AUTO got the operator `kind`, for the log ('' in 2D,
  !! where it follows the laws alone, and where the deck chose): the bytes of K's 3 x 3 blocks
  !! against the memory available.
  function force_choice_note(kind, model, ops) result(s)
    integer, intent(in) :: kind
    type(model_t), intent(in) :: model
    type(operators_t), intent(in) :: ops
    character(len=:), allocatable :: s
    character(len=:), allocatable :: avail
    s = ''
    if (model%ndm /= 3 .or. model%force_kind /= FORCE_AUTO) return
    if (model_force_kind(model) /= FORCE_ASSEMBLED) then
      s = 'AUTO: the element loop (a law with history or finite strain)'
      return
    end if
    avail = 'an unknown amount of memory available'
    if (ops%k_avail >= 0.0_dp) avail = str(ops%k_avail/1.0e6_dp, 4)//' MB available'
    if (kind == FORCE_ASSEMBLED) then
      s = 'AUTO: the assembled K, whose 3 x 3 blocks take '//str(ops%k_bytes/1.0e6_dp, 4)// &
          ' MB (at most half of the '//avail//' on every node)'
    else
      s = 'AUTO: the element loop, as the assembled K would take '// &
          str(ops%k_bytes/1.0e6_dp, 4)//' MB, more than half of the '//avail// &
          ' (per node, with its ranks)'
    end if
  end function force_choice_note

  !> Sets up the operator of `kind` (FORCE_ASSEMBLED or FORCE_ELEMENT) for this rank's part;
  !! k: the assembled stiffness (kept alive by the caller; the assembled operator points to
  !! it); ordered: a consistent mass (the assembled product in column order). ierr: 0, or the
  !! global index of an element whose geometry fails.
  subroutine force_op_init(fop, kind, model, dom, k, ordered, ierr)
    type(force_op_t), intent(out) :: fop
    integer, intent(in) :: kind
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    type(bsr_t), target, intent(in) :: k
    logical, intent(in) :: ordered
    integer, intent(out) :: ierr
    ierr = 0
    fop%kind = kind
    fop%nn = dom%nowned
    fop%nglobal = dom%nn_global
    if (kind == FORCE_ELEMENT) then
      call element_loop_init(fop%el, model, dom, ierr)
    else
      ! the column-order product of a consistent mass has 2 x 2 blocks; a 3D K takes its one
      ! product, whose bits do not depend on the partition either
      call assembled_init(fop%asm, k, ordered .and. size(k%val, 1) == 2)
    end if
  end subroutine force_op_init

  !> f = f_int(u) on the owned rows (u: owned and ghost values); hist: the quadrature-point
  !! history (nhist, ngp, elements) of the element loop, updated to the end of the step.
  subroutine force_apply(fop, u, f, hist)
    type(force_op_t), intent(inout) :: fop
    real(dp), intent(in) :: u(:,:)
    real(dp), intent(inout) :: f(:,:)
    real(dp), intent(inout) :: hist(:,:,:)
    if (fop%kind == FORCE_ELEMENT) then
      call element_loop_apply(fop%el, fop%nn, u, f, hist)
    else
      call assembled_apply(fop%asm, fop%nn, u, f)
    end if
  end subroutine force_apply

  !> Strain energy at u, where r = -f_int(u) is the nodal force of the last `force_apply`:
  !! 1/2 u . K u for the assembled K, the integral of the laws' energy density for the element
  !! loop.
  function force_energy(fop, u, r) result(e)
    type(force_op_t), intent(inout) :: fop
    real(dp), intent(in) :: u(:,:), r(:,:)
    real(dp) :: e
    if (fop%kind == FORCE_ELEMENT) then
      e = element_loop_energy(fop%el)
    else
      e = assembled_energy(fop%nn, u, r, fop%nglobal)
    end if
  end function force_energy

  !> Energy the material laws have dissipated up to the last `force_apply` (plastic work);
  !! 0 for the assembled K.
  function force_dissipation(fop) result(e)
    type(force_op_t), intent(inout) :: fop
    real(dp) :: e
    e = 0.0_dp
    if (fop%kind == FORCE_ELEMENT) e = element_loop_dissipation(fop%el)
  end function force_dissipation

  !> This rank's stable-step factor of the current state (ictus_solver_force_element's
  !! element_loop_stable) and the global index of the element that gives it; 1 and 0 for the
  !! assembled K (a linear model in small strain keeps its start-up step).
  subroutine force_stable(fop, u, hist, smin, kmin)
    type(force_op_t), intent(inout) :: fop
    real(dp), intent(in) :: u(:,:)
    real(dp), intent(in) :: hist(:,:,:)
    real(dp), intent(out) :: smin
    integer, intent(out) :: kmin
    smin = 1.0_dp
    kmin = 0
    if (fop%kind == FORCE_ELEMENT) call element_loop_stable(fop%el, u, hist, smin, kmin)
  end subroutine force_stable

  !> Whether any material law dissipates energy (then the energy balance has a plastic-work
  !! term).
  pure logical function force_dissipates(fop)
    type(force_op_t), intent(in) :: fop
    force_dissipates = fop%kind == FORCE_ELEMENT .and. fop%el%dissipates
  end function force_dissipates

  !> Shape of the history array of the state, (nhist, quadrature points, elements); zero
  !! extents for the assembled K (which keeps none; the element loop sizes it even with
  !! nhist = 0, so that its slices stay valid).
  function force_hist_shape(fop) result(hs)
    type(force_op_t), intent(in) :: fop
    integer :: hs(3)
    hs = 0
    if (fop%kind == FORCE_ELEMENT) &
        hs = [fop%el%nhist, size(fop%el%dvol, 1), fop%el%nelem]
  end function force_hist_shape

  !> How the internal force is formed, for the log.
  function force_kind_name(fop) result(s)
    type(force_op_t), intent(in) :: fop
    character(len=:), allocatable :: s
    character(len=32) :: mb
    if (fop%kind == FORCE_ELEMENT) then
      write(mb, '(f0.1)') element_loop_bytes(fop%el)/1.0e6_dp
      s = 'element loop over the material laws ('//trim(mb)//' MB of stored geometry)'
    else
      write(mb, '(f0.1)') (8.0_dp*real(size(fop%asm%k%val), dp) + &
          4.0_dp*real(size(fop%asm%k%g%col), dp))/1.0e6_dp
      s = 'assembled stiffness, f = K u ('//str(size(fop%asm%k%val, 1))//' x '// &
          str(size(fop%asm%k%val, 1))//' blocks, '//trim(mb)//' MB on this rank)'
    end if
  end function force_kind_name
end module ictus_solver_internal_force
