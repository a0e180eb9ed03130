!> Viewing samples of NURBS elements for the XDMF sidecar.
!!
!! Viewers draw straight-sided cells with values at their corners, while a NURBS field lives
!! on control points that do not lie on the body. Each Bezier element (IGA element of the
!! model) is therefore sampled on an s x s grid of parent points, by default s = 2 p_max + 1
!! (p_max the larger of its patch's two degrees; `*OUTPUT, FIELD, SAMPLES=s` sets s for all
!! patches), and the grid is cut into (s-1)^2 linear quads.
!!
!! A value at a sample point is sum_a R_a u_a over the element's control points a, with the
!! rational basis R_a = w_a N1_a1 N2_a2 / sum_b w_b N1_b1 N2_b2. The B-spline values N1 at the
!! s sample parameters of a span depend only on the span of direction 1 (N2 likewise), so
!! they are kept per patch and span, (p+1) x s numbers per span and direction, and the sample
!! values are formed when a field is written. This keeps the memory of the samples
!! negligible: a row of basis values and indices per sample point would take several times
!! the element's share of the stiffness (doc/iga.md §7).
!! The same formulas map the reference control-point coordinates to the sample points and
!! control-point displacements to the displacement at the sample points.
!!
!! Ordering: elements in model order (only ETYPE_IGA elements); within an element the sample
!! points run direction-1 fastest, at parent coordinates xi~ = -1 + 2 i/(s-1), i = 0..s-1
!! (the same in direction 2). Sample points on element edges are repeated per element (each
!! element's cells are independent), so a field that jumps across elements would also show.
module ictus_io_iga_viz
  use ictus_core_kinds, only: dp, i8
  use ictus_elements_types, only: ETYPE_IGA
  use ictus_geometry_bezier, only: bernstein
  use ictus_geometry_patch, only: patch_elem_ij
  use ictus_solver_model, only: model_t
  implicit none
  private
  public :: iga_viz_t, iga_viz_init, iga_viz_eval, iga_viz_points, iga_viz_cells, &
      iga_viz_free, iga_viz_count, iga_viz_samples

  !> B-spline values of one patch at the sample parameters of each span.
  type :: viz_patch_t
    !> Samples per direction.
    integer :: s = 0
    !> n1(a1, i, j1): B-spline a1 of span j1 of direction 1 at sample i (1..s); n2 likewise.
    real(dp), allocatable :: n1(:,:,:), n2(:,:,:)
  end type viz_patch_t

  !> Sample points and linear-quad cells of all IGA elements of a model.
  type :: iga_viz_t
    !> Number of sample points and of cells.
    integer :: ns = 0
    integer :: ncells = 0
    !> Largest number of control points per element.
    integer :: nen_max = 0
    !> First sample point (0-based) and first cell (0-based) of each model element; -1 for
    !! elements that are not sampled.
    integer, allocatable :: first_point(:), first_cell(:)
    !> The patches' tables.
    type(viz_patch_t), allocatable :: patches(:)
  end type iga_viz_t

contains

  !> Sample points and cells of all IGA elements, without building anything: what the memory
  !! check needs before iga_viz_init. @param samples s for every patch, 0 = the default.
  subroutine iga_viz_count(model, samples, ns, ncells)
    type(model_t), intent(in) :: model
    integer, intent(in) :: samples
    integer(i8), intent(out) :: ns, ncells
    integer :: ip, s
    ns = 0
    ncells = 0
    do ip = 1, model%npatch
      s = iga_viz_samples(model, ip, samples)
      ns = ns + int(s, i8)**2*model%patches(ip)%nel(1)*model%patches(ip)%nel(2)
      ncells = ncells + int(s - 1, i8)**2*model%patches(ip)%nel(1)*model%patches(ip)%nel(2)
    end do
  end subroutine iga_viz_count

  !> Builds the sample numbering and the patches' B-spline tables.
  !! @param model the model (patches as refined, conn, patch, patch_elem);
  !! @param viz filled (any previous content is released);
  !! @param samples s for every patch, >= 2; 0 or absent = 2 p_max + 1 per patch
  subroutine iga_viz_init(model, viz, samples)
    type(model_t), intent(in) :: model
    type(iga_viz_t), intent(inout) :: viz
    integer, intent(in), optional :: samples
    integer :: e, s, ip, i, j, smp
    ! degrees are at most 10 (the deck's limit)
    real(dp) :: xi, b(11), db(11)
    call iga_viz_free(viz)
    smp = 0
    if (present(samples)) smp = samples
    allocate(viz%patches(model%npatch))
    do ip = 1, model%npatch
      associate (pt => model%patches(ip), vp => viz%patches(ip))
        s = iga_viz_samples(model, ip, smp)
        vp%s = s
        allocate(vp%n1(pt%p(1) + 1, s, pt%nel(1)), vp%n2(pt%p(2) + 1, s, pt%nel(2)))
        do i = 1, s
          xi = -1.0_dp + 2.0_dp*real(i - 1, dp)/real(s - 1, dp)
          call bernstein(pt%p(1), 0.5_dp*(xi + 1.0_dp), b(1:pt%p(1) + 1), db(1:pt%p(1) + 1))
          do j = 1, pt%nel(1)
            vp%n1(:, i, j) = matmul(pt%c1(:, :, j), b(1:pt%p(1) + 1))
          end do
          call bernstein(pt%p(2), 0.5_dp*(xi + 1.0_dp), b(1:pt%p(2) + 1), db(1:pt%p(2) + 1))
          do j = 1, pt%nel(2)
            vp%n2(:, i, j) = matmul(pt%c2(:, :, j), b(1:pt%p(2) + 1))
          end do
        end do
      end associate
    end do
    allocate(viz%first_point(model%nel), viz%first_cell(model%nel))
    viz%first_point = -1
    viz%first_cell = -1
    viz%nen_max = 0
    do e = 1, model%nel
      if (model%etype(e) /= ETYPE_IGA) cycle
      s = viz%patches(model%patch(e))%s
      viz%first_point(e) = viz%ns
      viz%first_cell(e) = viz%ncells
      viz%ns = viz%ns + s*s
      viz%ncells = viz%ncells + (s - 1)**2
      viz%nen_max = max(viz%nen_max, model%nen(e))
    end do
  end subroutine iga_viz_init

  !> Control-point values to the sample-point values of the elements `elems`, in their order
  !! (each element's s^2 points, direction 1 fastest). No allocation.
  !! @param uc control-point (node) vectors (2, :), node i at column map(i) (a rank's local
  !! numbering, or the identity); @param us (2, points of elems)
  pure subroutine iga_viz_eval(viz, model, elems, uc, us, map)
    type(iga_viz_t), intent(in) :: viz
    type(model_t), intent(in) :: model
    integer, intent(in) :: elems(:)
    real(dp), intent(in) :: uc(:,:)
    real(dp), intent(out) :: us(:,:)
    integer, intent(in) :: map(:)
    integer :: q, e, k, ij(2), i1, i2, a1, a2, a, nen
    real(dp) :: r(viz%nen_max), ww
    k = 0
    do q = 1, size(elems)
      e = elems(q)
      nen = model%nen(e)
      associate (pt => model%patches(model%patch(e)), vp => viz%patches(model%patch(e)))
        ij = patch_elem_ij(pt, model%patch_elem(e))
        do i2 = 1, vp%s
          do i1 = 1, vp%s
            k = k + 1
            ! the rational basis as iga_basis_at forms it
            ww = 0.0_dp
            a = 0
            do a2 = 1, pt%p(2) + 1
              do a1 = 1, pt%p(1) + 1
                a = a + 1
                r(a) = model%weight(model%conn(a, e))*vp%n1(a1, i1, ij(1))*vp%n2(a2, i2, ij(2))
                ww = ww + r(a)
              end do
            end do
            us(1:2, k) = 0.0_dp
            do a = 1, nen
              us(1:2, k) = us(1:2, k) + (r(a)/ww)*uc(1:2, map(model%conn(a, e)))
            end do
          end do
        end do
      end associate
    end do
  end subroutine iga_viz_eval

  !> Reference coordinates of all sample points, (2, ns).
  pure subroutine iga_viz_points(viz, model, points)
    type(iga_viz_t), intent(in) :: viz
    type(model_t), intent(in) :: model
    real(dp), intent(out) :: points(:,:)
    integer :: e, i
    call iga_viz_eval(viz, model, pack([(e, e = 1, model%nel)], viz%first_point >= 0), &
        model%x0, points, [(i, i = 1, model%nn)])
  end subroutine iga_viz_points

  !> Linear-quad cells (4, ncells), 0-based sample point numbers, counter-clockwise in the
  !! parameter plane (counter-clockwise in x when det J > 0).
  pure subroutine iga_viz_cells(viz, model, cells)
    type(iga_viz_t), intent(in) :: viz
    type(model_t), intent(in) :: model
    integer, intent(out) :: cells(:,:)
    integer :: e, s, i1, i2, k0, c
    do e = 1, model%nel
      if (viz%first_point(e) < 0) cycle
      s = viz%patches(model%patch(e))%s
      k0 = viz%first_point(e)
      c = viz%first_cell(e)
      ! corners (i1, i2), (i1+1, i2), (i1+1, i2+1), (i1, i2+1)
      do i2 = 0, s - 2
        do i1 = 0, s - 2
          c = c + 1
          cells(1, c) = k0 + i1 + i2*s
          cells(2, c) = k0 + i1 + 1 + i2*s
          cells(3, c) = k0 + i1 + 1 + (i2 + 1)*s
          cells(4, c) = k0 + i1 + (i2 + 1)*s
        end do
      end do
    end do
  end subroutine iga_viz_cells

  !> Samples per direction of patch ip: `samples` (SAMPLES=) when > 0, else 2 p_max + 1.
  pure integer function iga_viz_samples(model, ip, samples) result(s)
    type(model_t), intent(in) :: model
    integer, intent(in) :: ip, samples
    s = samples
    if (s <= 0) s = 2*maxval(model%patches(ip)%p) + 1
  end function iga_viz_samples

  !> Releases everything.
  !! @param viz the samples
  subroutine iga_viz_free(viz)
    type(iga_viz_t), intent(inout) :: viz
    viz%ns = 0
    viz%ncells = 0
    viz%nen_max = 0
    if (allocated(viz%first_point)) deallocate(viz%first_point)
    if (allocated(viz%first_cell)) deallocate(viz%first_cell)
    if (allocated(viz%patches)) deallocate(viz%patches)
  end subroutine iga_viz_free
end module ictus_io_iga_viz
