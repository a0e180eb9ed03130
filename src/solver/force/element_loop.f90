!> The internal force as a loop over the elements that calls the material law at every
!! quadrature point: f_a = sum_e int sigma(grad u, history) . grad N_a dV. What nonlinear laws
!! and finite strain use; on a linear model it agrees with the assembled K u to round-off.
!!
!! Each rank loops over the elements that hold one of its owned nodes (domain_t%elem, in
!! global order) and keeps the force of its owned rows: every row is summed over the same
!! elements in the same order on any number of ranks, so the bits do not depend on the
!! partition. The Cartesian shape derivatives and volume weights of every quadrature point are
!! computed once (`element_geometry`) and stored: 8 (ndm nen + 1) bytes per point.
module ictus_solver_force_element
  use ictus_core_kinds, only: dp
  use ictus_parallel_repro, only: repro_sum
  use ictus_elements_types, only: elem_shape_t
  use ictus_elements_library, only: element_geometry, element_force
  use ictus_materials_material, only: material_t
  use ictus_materials_eigen, only: sym_eigen3
  use ictus_solver_model, only: model_t
  use ictus_solver_domain, only: domain_t, domain_owns
  use ictus_solver_assemble, only: element_shape, shape_cache_t
  implicit none
  private
  public :: element_force_t, element_loop_init, element_loop_apply, element_loop_energy, &
      element_loop_bytes, element_loop_dissipation, element_loop_stable, element_loop_geometry, &
      element_loop_stiffness

  type :: element_force_t
    !> Elements of this rank (domain_t%elem order), their types, nodes, quadrature points and
    !! materials; local connectivity (nen_max, nelem); whether the element is this rank's own
    !! (counted in the energy).
    integer :: nelem = 0
    integer :: nglobal = 0
    !> The first element (global index) and step at which det F <= 0 at a quadrature point
    !! (0: none): an inverted element stops the run.
    integer :: inverted = 0
    integer, allocatable :: etype(:), nen(:), ngp(:), mat(:), elem(:)
    integer, allocatable :: conn(:,:)
    logical, allocatable :: own(:)
    !> Whether the element shares its mean dilatation (B-bar / F-bar).
    logical, allocatable :: mean(:)
    !> Geometry per quadrature point: dnx(ndm, nen_max, ngp_max, nelem), dvol(ngp_max, nelem).
    real(dp), allocatable :: dnx(:,:,:,:), dvol(:,:)
    !> The materials (copied from the model).
    type(material_t), allocatable :: materials(:)
    !> History variables per point (nhist_max, ngp_max, nelem) and the largest nhist.
    integer :: nhist = 0
    !> Stored energy and dissipated energy (the laws' dissipation history integrated) of each
    !! element at the last apply, and a work array for this rank's own elements.
    real(dp), allocatable :: energy(:), dissipated(:), eown(:)
    !> Whether any law dissipates.
    logical :: dissipates = .false.
    !> Work arrays of one element.
    real(dp), allocatable :: ul(:,:), fe(:,:), hnew(:,:)
  end type element_force_t

contains

  !> Sets up the loop over this rank's elements: shape data, geometry, materials. ierr: 0, or
  !! the global index of an element with det J <= 0 (checked before, so not expected).
  subroutine element_loop_init(el, model, dom, ierr)
    type(element_force_t), intent(out) :: el
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    integer, intent(out) :: ierr
    integer :: k, e, ngp_max, nen_max, m
    el%nelem = dom%nelem
    el%nglobal = model%nel
    el%materials = model%materials
    nen_max = model%nen_max
    ngp_max = maxval(product(model%gauss, dim=1))
    el%nhist = 0
    do m = 1, model%nmat
      el%nhist = max(el%nhist, model%materials(m)%law%nhist)
    end do
    allocate(el%etype(el%nelem), el%nen(el%nelem), el%ngp(el%nelem), el%mat(el%nelem), &
        el%own(el%nelem), el%energy(el%nelem), el%dissipated(el%nelem))
    el%energy = 0.0_dp
    el%dissipated = 0.0_dp
    el%dissipates = any([(model%materials(m)%law%hist_dissipation > 0, m = 1, model%nmat)])
    el%conn = dom%conn
    el%elem = dom%elem(1:dom%nelem)
    allocate(el%mean(el%nelem), source=.false.)
    if (allocated(model%mean_dil)) el%mean = model%mean_dil(el%elem)
    allocate(el%dnx(model%ndm, nen_max, ngp_max, el%nelem), el%dvol(ngp_max, el%nelem), &
        source=0.0_dp)
    allocate(el%ul(model%ndm, nen_max), el%fe(model%ndm, nen_max), el%hnew(el%nhist, ngp_max))
    do k = 1, el%nelem
      e = dom%elem(k)
      el%etype(k) = model%etype(e)
      el%nen(k) = model%nen(e)
      el%mat(k) = model%mat(e)
      el%own(k) = domain_owns(dom, k)
    end do
    call element_loop_geometry(el, model, ierr)
    allocate(el%eown(count(el%own)), source=0.0_dp)
  end subroutine element_loop_init

  !> The shape derivatives and volume weights of every quadrature point of the loop's
  !! elements (el%dnx, el%dvol, el%ngp), from the reference geometry: what the loop stores
  !! once. The benchmark times it as the cost a loop that recomputed them every step would
  !! pay (doc/performance.md §2.2). ierr: 0, or the global index of an element whose
  !! geometry fails.
  subroutine element_loop_geometry(el, model, ierr)
    type(element_force_t), intent(inout) :: el
    type(model_t), intent(in) :: model
    integer, intent(out) :: ierr
    type(shape_cache_t) :: cache
    type(elem_shape_t) :: shp
    integer :: k, e, nen, ngp_max, g
    ierr = 0
    ngp_max = size(el%dvol, 1)
    do k = 1, el%nelem
      e = el%elem(k)
      nen = el%nen(k)
      call element_shape(model, e, model%gauss(:, e), cache, 1, shp)
      ! a rule has at most the points of the tensor Gauss rule of the same n
      if (shp%ngp > ngp_max) then
        if (ierr == 0) ierr = e
        cycle
      end if
      el%ngp(k) = shp%ngp
      call element_geometry(model%etype(e), shp, model%x0(:, model%conn(1:nen, e)), &
          el%dnx(:, 1:nen, 1:shp%ngp, k), el%dvol(1:shp%ngp, k), g)
      if (g /= 0 .and. ierr == 0) ierr = e
    end do
  end subroutine element_loop_geometry

  !> Memory of the stored geometry, bytes.
  pure real(dp) function element_loop_bytes(el)
    type(element_force_t), intent(in) :: el
    element_loop_bytes = 8.0_dp*(real(size(el%dnx), dp) + real(size(el%dvol), dp))
  end function element_loop_bytes

  !> f = f_int(u) on the nn owned rows (u: owned and ghost values, current), with the history
  !! hist(nhist, ngp_max, nelem) of the start of the step replaced by that of its end.
  subroutine element_loop_apply(el, nn, u, f, hist)
    type(element_force_t), intent(inout) :: el
    integer, intent(in) :: nn
    real(dp), intent(in) :: u(:,:)
    real(dp), intent(inout) :: f(:,:)
    real(dp), intent(inout) :: hist(:,:,:)
    integer :: k, a, i, nen, ngp, ierr
    f(:, 1:nn) = 0.0_dp
    do k = 1, el%nelem
      nen = el%nen(k)
      ngp = el%ngp(k)
      do a = 1, nen
        el%ul(:, a) = u(:, el%conn(a, k))
      end do
      associate (law => el%materials(el%mat(k))%law)
        call element_force(el%etype(k), nen, ngp, el%dnx(:, 1:nen, 1:ngp, k), &
            el%dvol(1:ngp, k), el%ul(:, 1:nen), law, hist(:, 1:ngp, k), &
            el%hnew(:, 1:ngp), el%fe(:, 1:nen), el%energy(k), ierr, el%mean(k))
      end associate
      if (ierr /= 0 .and. el%inverted == 0) el%inverted = el%elem(k)
      if (el%nhist > 0) hist(:, 1:ngp, k) = el%hnew(:, 1:ngp)
      if (el%dissipates) then
        associate (idx => el%materials(el%mat(k))%law%hist_dissipation)
          el%dissipated(k) = 0.0_dp
          if (idx > 0) el%dissipated(k) = dot_product(hist(idx, 1:ngp, k), el%dvol(1:ngp, k))
        end associate
      end if
      do a = 1, nen
        i = el%conn(a, k)
        if (i <= nn) f(:, i) = f(:, i) + el%fe(:, a)
      end do
    end do
  end subroutine element_loop_apply

  !> The stable-step factor of the current state (doc/theory.md §7.1): the smallest over
  !! this rank's elements and their quadrature points of s = sigma_min(F)/(c/c_0), where
  !! sigma_min(F) = sqrt(lam_min(F^T F)) is how much the element has shrunk in its most
  !! compressed direction and c/c_0 the law's `wave_ratio`; 1 in the reference state.
  !! kmin: the global index of the element that gives it (the first one in this rank's order).
  !! The history is that of the start of the next step (hist as element_loop_apply leaves it).
  subroutine element_loop_stable(el, u, hist, smin, kmin)
    type(element_force_t), intent(inout) :: el
    real(dp), intent(in) :: u(:,:)
    real(dp), intent(in) :: hist(:,:,:)
    real(dp), intent(out) :: smin
    integer, intent(out) :: kmin
    real(dp) :: grad(3, 3), f(3, 3), lam(3), v(3, 3), s
    integer :: k, a, g, i, nen, nd
    nd = size(el%dnx, 1)
    smin = huge(1.0_dp)
    kmin = 0
    do k = 1, el%nelem
      nen = el%nen(k)
      do a = 1, nen
        el%ul(:, a) = u(:, el%conn(a, k))
      end do
      do g = 1, el%ngp(k)
        grad = 0.0_dp
        grad(1:nd, 1:nd) = matmul(el%ul(:, 1:nen), transpose(el%dnx(:, 1:nen, g, k)))
        f = grad
        do i = 1, 3
          f(i, i) = f(i, i) + 1.0_dp
        end do
        call sym_eigen3(matmul(transpose(f), f), lam, v)
        s = sqrt(max(minval(lam), 0.0_dp))/ &
            el%materials(el%mat(k))%law%wave_ratio(grad, hist(:, g, k))
        if (s < smin) then
          smin = s
          kmin = el%elem(k)
        end if
      end do
    end do
  end subroutine element_loop_stable

  !> kq = K q on the nn owned rows of a 3D model (q: owned and ghost values), with K the
  !! stiffness of the laws' reference tangents (tangent_3d), the K of the element routine's
  !! TASK_STIFFNESS, without assembling it: kq_a = sum_g B_a^T D B q dV from the stored
  !! geometry. The stable step's frequency estimate of a 3D model (ictus_solver_timestep)
  !! takes it, one product per iteration. Rows are summed over the elements in global order,
  !! so the bits do not depend on the partition.
  subroutine element_loop_stiffness(el, nn, q, kq)
    type(element_force_t), intent(inout) :: el
    integer, intent(in) :: nn
    real(dp), intent(in) :: q(:,:)
    real(dp), intent(inout) :: kq(:,:)
    real(dp) :: d(6, 6, size(el%materials)), grad(3, 3), eps(6), sig(6), s(3, 3)
    integer :: k, a, g, i, m, nen
    do m = 1, size(el%materials)
      call el%materials(m)%law%tangent_3d(d(:, :, m))
    end do
    kq(:, 1:nn) = 0.0_dp
    do k = 1, el%nelem
      nen = el%nen(k)
      do a = 1, nen
        el%ul(:, a) = q(:, el%conn(a, k))
      end do
      el%fe(:, 1:nen) = 0.0_dp
      do g = 1, el%ngp(k)
        grad = matmul(el%ul(:, 1:nen), transpose(el%dnx(:, 1:nen, g, k)))
        eps = [grad(1, 1), grad(2, 2), grad(3, 3), grad(1, 2) + grad(2, 1), &
            grad(2, 3) + grad(3, 2), grad(3, 1) + grad(1, 3)]
        sig = matmul(d(:, :, el%mat(k)), eps)*el%dvol(g, k)
        s = reshape([sig(1), sig(4), sig(6), sig(4), sig(2), sig(5), sig(6), sig(5), sig(3)], &
            [3, 3])
        el%fe(:, 1:nen) = el%fe(:, 1:nen) + matmul(s, el%dnx(:, 1:nen, g, k))
      end do
      do a = 1, nen
        i = el%conn(a, k)
        if (i <= nn) kq(:, i) = kq(:, i) + el%fe(:, a)
      end do
    end do
  end subroutine element_loop_stiffness

  !> Stored energy at the last apply: the sum over this rank's own elements, reproducible.
  function element_loop_energy(el) result(e)
    type(element_force_t), intent(inout) :: el
    real(dp) :: e
    e = own_sum(el, el%energy)
  end function element_loop_energy

  !> Energy dissipated by the laws up to the last apply (0 where no law dissipates).
  function element_loop_dissipation(el) result(e)
    type(element_force_t), intent(inout) :: el
    real(dp) :: e
    e = 0.0_dp
    if (el%dissipates) e = own_sum(el, el%dissipated)
  end function element_loop_dissipation

  !> The reproducible sum of v over this rank's own elements (each element counted once).
  function own_sum(el, v) result(e)
    type(element_force_t), intent(inout) :: el
    real(dp), intent(in) :: v(:)
    real(dp) :: e
    integer :: k, j
    j = 0
    do k = 1, el%nelem
      if (.not. el%own(k)) cycle
      j = j + 1
      el%eown(j) = v(k)
    end do
    e = repro_sum(j, el%eown, el%nglobal)
  end function own_sum
end module ictus_solver_force_element
