!> Viewing samples of NURBS elements for the XDMF sidecar.
!!
!! Viewers draw straight-sided cells with values at their corners, while a NURBS field lives
!! on control points that do not lie on the body. Each Bezier element (IGA element of the
!! model) is therefore sampled on an s x s grid of parent points, s = 2 p_max + 1 (p_max the
!! larger of the element's two degrees), and the grid is cut into (s-1)^2 linear quads.
!!
!! A value at sample point k is sum_j val(j, k) * u(idx(j, k)) over the element's control
!! points (a sparse interpolation matrix, row k), so the same matrix maps the reference
!! control-point coordinates to the sample points and control-point displacements to the
!! displacement at the sample points.
!!
!! Ordering: elements in model order (only ETYPE_IGA elements); within an element the sample
!! points run direction-1 fastest, at parent coordinates xi~ = -1 + 2 i/(s-1), i = 0..s-1
!! (the same in direction 2). Sample points on element edges are repeated per element (each
!! element's cells are independent), so a field that jumps across elements would also show.
module ictus_io_iga_viz
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_IGA
  use ictus_elements_iga, only: iga_basis_at
  use ictus_geometry_patch, only: patch_elem_ij
  use ictus_solver_model, only: model_t
  implicit none
  private
  public :: iga_viz_t, iga_viz_init, iga_viz_eval, iga_viz_free

  !> Sample points and linear-quad cells of all IGA elements of a model.
  type :: iga_viz_t
    !> Number of sample points and of cells.
    integer :: ns = 0
    integer :: ncells = 0
    !> Largest number of control points per element (rows of idx and val).
    integer :: nen_max = 0
    !> Global control-point indices (1..nn) of each sample point's element, (nen_max, ns);
    !! 0 in unused rows (elements with fewer control points).
    integer, allocatable :: idx(:,:)
    !> NURBS basis values at each sample point, (nen_max, ns); 0 in unused rows.
    real(dp), allocatable :: val(:,:)
    !> Reference coordinates of the sample points, (2, ns).
    real(dp), allocatable :: points(:,:)
    !> Linear-quad cells (4, ncells), 0-based sample point indices, counter-clockwise in the
    !! parameter plane (counter-clockwise in x when det J > 0).
    integer, allocatable :: cells(:,:)
    !> Model element of each sample point, (ns).
    integer, allocatable :: elem(:)
  end type iga_viz_t

contains

  !> Builds the sample points, interpolation matrix and cells of all IGA elements of `model`.
  !! @param model the model (patches as refined, conn, patch, patch_elem, x0, weight);
  !! @param viz filled (any previous content is released)
  subroutine iga_viz_init(model, viz)
    type(model_t), intent(in) :: model
    type(iga_viz_t), intent(inout) :: viz
    integer :: e, s, ns, nc, nen, ip, ie, ij(2), i1, i2, k, k0, c
    real(dp) :: xi(2)
    call iga_viz_free(viz)
    ns = 0
    nc = 0
    viz%nen_max = 0
    do e = 1, model%nel
      if (model%etype(e) /= ETYPE_IGA) cycle
      s = samples_per_direction(model, e)
      ns = ns + s*s
      nc = nc + (s - 1)**2
      viz%nen_max = max(viz%nen_max, model%nen(e))
    end do
    viz%ns = ns
    viz%ncells = nc
    allocate(viz%idx(viz%nen_max, ns), viz%val(viz%nen_max, ns), viz%points(2, ns), &
        viz%cells(4, nc), viz%elem(ns))
    viz%idx = 0
    viz%val = 0.0_dp
    k = 0
    c = 0
    do e = 1, model%nel
      if (model%etype(e) /= ETYPE_IGA) cycle
      s = samples_per_direction(model, e)
      nen = model%nen(e)
      ip = model%patch(e)
      ie = model%patch_elem(e)
      k0 = k
      associate (pt => model%patches(ip))
        ij = patch_elem_ij(pt, ie)
        do i2 = 0, s - 1
          do i1 = 0, s - 1
            k = k + 1
            xi = [-1.0_dp + 2.0_dp*real(i1, dp)/real(s - 1, dp), &
                -1.0_dp + 2.0_dp*real(i2, dp)/real(s - 1, dp)]
            call basis_values(pt%p, pt%c1(:, :, ij(1)), pt%c2(:, :, ij(2)), &
                model%weight(model%conn(1:nen, e)), xi, viz%val(1:nen, k))
            viz%idx(1:nen, k) = model%conn(1:nen, e)
            viz%elem(k) = e
          end do
        end do
      end associate
      ! cells: corners (i1, i2), (i1+1, i2), (i1+1, i2+1), (i1, i2+1), 0-based point numbers
      do i2 = 0, s - 2
        do i1 = 0, s - 2
          c = c + 1
          viz%cells(1, c) = k0 + i1 + i2*s
          viz%cells(2, c) = k0 + i1 + 1 + i2*s
          viz%cells(3, c) = k0 + i1 + 1 + (i2 + 1)*s
          viz%cells(4, c) = k0 + i1 + (i2 + 1)*s
        end do
      end do
    end do
    call iga_viz_eval(viz, model%x0, viz%points)
  end subroutine iga_viz_init

  !> Samples per direction of IGA element e: 2 p_max + 1.
  pure integer function samples_per_direction(model, e) result(s)
    type(model_t), intent(in) :: model
    integer, intent(in) :: e
    s = 2*maxval(model%patches(model%patch(e))%p) + 1
  end function samples_per_direction

  !> NURBS basis values of one element at parent point xi (derivatives discarded).
  pure subroutine basis_values(p, c1e, c2e, wl, xi, r)
    integer, intent(in) :: p(2)
    real(dp), intent(in) :: c1e(:,:), c2e(:,:), wl(:), xi(2)
    real(dp), intent(out) :: r(:)
    real(dp) :: dr(2, size(r))
    call iga_basis_at(p, c1e, c2e, wl, xi, r, dr)
  end subroutine basis_values

  !> Control-point values to sample-point values: us(:, k) = sum_j val(j, k) uc(:, idx(j, k)).
  !! No allocation. @param viz from iga_viz_init; @param uc control-point (node) vectors
  !! (2, nn), global numbering; @param us sample-point vectors (2, viz%ns)
  pure subroutine iga_viz_eval(viz, uc, us)
    type(iga_viz_t), intent(in) :: viz
    real(dp), intent(in) :: uc(:,:)
    real(dp), intent(out) :: us(:,:)
    integer :: k, j
    do k = 1, viz%ns
      us(1:2, k) = 0.0_dp
      do j = 1, viz%nen_max
        if (viz%idx(j, k) == 0) exit
        us(1:2, k) = us(1:2, k) + viz%val(j, k)*uc(1:2, viz%idx(j, k))
      end do
    end do
  end subroutine iga_viz_eval

  !> Releases everything.
  !! @param viz the samples
  subroutine iga_viz_free(viz)
    type(iga_viz_t), intent(inout) :: viz
    viz%ns = 0
    viz%ncells = 0
    viz%nen_max = 0
    if (allocated(viz%idx)) deallocate(viz%idx)
    if (allocated(viz%val)) deallocate(viz%val)
    if (allocated(viz%points)) deallocate(viz%points)
    if (allocated(viz%cells)) deallocate(viz%cells)
    if (allocated(viz%elem)) deallocate(viz%elem)
  end subroutine iga_viz_free
end module ictus_io_iga_viz
