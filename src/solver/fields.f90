!> Element fields for output: the Cauchy stress, the strain, the von Mises stress and the
!! equivalent plastic strain of every element (the mean over its quadrature points), and the
!! stress and von Mises stress averaged at the nodes for viewing (doc/results.md).
!!
!! Each rank evaluates the elements it assembles (domain_t%elem, global order) with the state's
!! history, keeps those it owns for the per-element datasets, and averages at its owned nodes
!! over every element that holds them, in global element order: the same bits on any number of
!! ranks.
module ictus_solver_fields
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: elem_shape_t, TASK_STRESS
  use ictus_elements_library, only: element_routine, element_out_t
  use ictus_solver_model, only: model_t
  use ictus_solver_domain, only: domain_t, domain_owns
  use ictus_solver_assemble, only: element_shape, shape_cache_t
  implicit none
  private
  public :: element_fields_t, element_fields

  !> The fields of this rank: per own element (global ids `elem`) stress and strain
  !! (4, nown: xx, yy, xy, zz in 2D; 6, nown: xx, yy, zz, xy, yz, zx in 3D), von Mises stress
  !! and equivalent plastic strain (nown); per owned node the averaged stress (4 or 6, nowned)
  !! and von Mises stress (nowned).
  type :: element_fields_t
    integer, allocatable :: elem(:)
    real(dp), allocatable :: stress(:,:), strain(:,:), mises(:), peeq(:)
    real(dp), allocatable :: nodal_stress(:,:), nodal_mises(:)
  end type element_fields_t

contains

  !> Whether element e shares its mean dilatation (false where the model does not say).
  pure logical function mean_dilatation(model, e)
    type(model_t), intent(in) :: model
    integer, intent(in) :: e
    mean_dilatation = .false.
    if (allocated(model%mean_dil)) mean_dilatation = model%mean_dil(e)
  end function mean_dilatation

  !> The fields at the displacements u (local: owned and ghosts) with the quadrature-point
  !! history hist(nhist, ngp, local elements) of the state (empty: no history).
  subroutine element_fields(model, dom, u, hist, ef)
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    real(dp), intent(in) :: u(:,:), hist(:,:,:)
    type(element_fields_t), intent(inout) :: ef
    type(shape_cache_t) :: cache
    type(elem_shape_t) :: shp
    type(element_out_t) :: out
    real(dp), allocatable :: h0(:,:), acc(:,:), cnt(:)
    real(dp) :: s_mean(6), e_mean(6), mises, peeq
    integer :: k, e, nen, j, g, ip, a, i, nc
    integer, allocatable :: comp(:)
    if (allocated(ef%elem)) deallocate(ef%elem, ef%stress, ef%strain, ef%mises, ef%peeq, &
        ef%nodal_stress, ef%nodal_mises)
    ! the components written: xx, yy, xy, zz in 2D; xx, yy, zz, xy, yz, zx in 3D
    if (model%ndm == 3) then
      comp = [1, 2, 3, 4, 5, 6]
    else
      comp = [1, 2, 4, 3]
    end if
    nc = size(comp)
    j = count([(domain_owns(dom, k), k = 1, dom%nelem)])
    allocate(ef%elem(j), ef%stress(nc, j), ef%strain(nc, j), ef%mises(j), ef%peeq(j))
    allocate(acc(nc + 1, dom%nlocal), cnt(dom%nlocal), source=0.0_dp)
    j = 0
    do k = 1, dom%nelem
      e = dom%elem(k)
      nen = model%nen(e)
      call element_shape(model, e, model%gauss(:, e), cache, 1, shp)
      associate (law => model%materials(model%mat(e))%law)
        if (size(hist) > 0) then
          h0 = hist(:, 1:shp%ngp, k)
        else
          if (allocated(h0)) deallocate(h0)
          allocate(h0(law%nhist, shp%ngp), source=0.0_dp)
        end if
        call element_routine(TASK_STRESS, model%etype(e), shp, model%x0(:, model%conn(1:nen, e)), &
            model%materials(model%mat(e)), out, u(:, dom%conn(1:nen, k)), h0, &
            mean=mean_dilatation(model, e))
        ip = law%hist_peeq
      end associate
      s_mean = 0.0_dp
      e_mean = 0.0_dp
      mises = 0.0_dp
      peeq = 0.0_dp
      do g = 1, shp%ngp
        s_mean(1:nc) = s_mean(1:nc) + out%sig(comp, g)
        e_mean(1:nc) = e_mean(1:nc) + out%eps(comp, g)
        mises = mises + von_mises(out%sig(:, g))
        if (ip > 0) peeq = peeq + h0(ip, g)
      end do
      s_mean = s_mean/shp%ngp
      e_mean = e_mean/shp%ngp
      mises = mises/shp%ngp
      peeq = peeq/shp%ngp
      do a = 1, nen
        i = dom%conn(a, k)
        acc(1:nc, i) = acc(1:nc, i) + s_mean(1:nc)
        acc(nc + 1, i) = acc(nc + 1, i) + mises
        cnt(i) = cnt(i) + 1.0_dp
      end do
      if (.not. domain_owns(dom, k)) cycle
      j = j + 1
      ef%elem(j) = e
      ef%stress(:, j) = s_mean(1:nc)
      ef%strain(:, j) = e_mean(1:nc)
      ef%mises(j) = mises
      ef%peeq(j) = peeq
    end do
    allocate(ef%nodal_stress(nc, dom%nowned), ef%nodal_mises(dom%nowned), source=0.0_dp)
    do i = 1, dom%nowned
      if (cnt(i) == 0.0_dp) cycle
      ef%nodal_stress(:, i) = acc(1:nc, i)/cnt(i)
      ef%nodal_mises(i) = acc(nc + 1, i)/cnt(i)
    end do
  end subroutine element_fields

  !> von Mises stress of sig (xx, yy, zz, xy, yz, zx).
  pure real(dp) function von_mises(sig)
    real(dp), intent(in) :: sig(6)
    von_mises = sqrt(0.5_dp*((sig(1) - sig(2))**2 + (sig(2) - sig(3))**2 + &
        (sig(3) - sig(1))**2) + 3.0_dp*(sig(4)**2 + sig(5)**2 + sig(6)**2))
  end function von_mises
end module ictus_solver_fields
