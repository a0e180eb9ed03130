!> Viewing samples of NURBS elements for the XDMF sidecar.
!!
!! Viewers draw straight-sided cells with values at their corners, while a NURBS field lives
!! on control points that do not lie on the body. Each Bezier element (IGA element of the
!! model) is therefore sampled on an s x s grid of parent points (s x s x s for the elements
!! of a trivariate patch in 3D), by default s = 2 p_max + 1 (p_max the largest of its patch's
!! degrees; `*OUTPUT, FIELD, SAMPLES=s` sets s for all patches), and the grid is cut into
!! (s-1)^2 linear quads ((s-1)^3 linear hexahedra in 3D).
!!
!! A value at a sample point is sum_a R_a u_a over the element's control points a, with the
!! rational basis R_a = w_a N1_a1 N2_a2 [N3_a3] / sum_b w_b N1_b1 N2_b2 [N3_b3]. The B-spline
!! values N1 at the s sample parameters of a span depend only on the span of direction 1 (N2,
!! N3 likewise), so they are kept per patch and span, (p+1) x s numbers per span and
!! direction, and the sample
!! values are formed when a field is written. This keeps the memory of the samples
!! negligible: a row of basis values and indices per sample point would take several times
!! the element's share of the stiffness (doc/iga.md §7).
!! The same formulas map the reference control-point coordinates to the sample points and
!! control-point displacements to the displacement at the sample points.
!!
!! Ordering: elements in model order (only NURBS elements); within an element the sample
!! points run direction-1 fastest, at parent coordinates xi~ = -1 + 2 i/(s-1), i = 0..s-1
!! (the same in directions 2 and 3). Sample points on element edges are repeated per element (each
!! element's cells are independent), so a field that jumps across elements would also show.
module ictus_io_iga_viz
  use ictus_core_kinds, only: dp, i8
  use ictus_elements_types, only: etype_is_nurbs
  use ictus_geometry_bezier, only: bernstein
  use ictus_geometry_patch, only: patch_elem_ij
  use ictus_geometry_volume, only: volume_elem_ijk
  use ictus_solver_model, only: model_t, patch_pmax, element_cp_weight
  implicit none
  private
  public :: iga_viz_t, iga_viz_init, iga_viz_eval, iga_viz_points, iga_viz_cells, &
      iga_viz_free, iga_viz_count, iga_viz_samples

  !> B-spline values of one patch at the sample parameters of each span.
  type :: viz_patch_t
    !> Samples per direction.
    integer :: s = 0
    !> Degrees (p(3) = 0 for a bivariate patch).
    integer :: p(3) = 0
    !> n1(a1, i, j1): B-spline a1 of span j1 of direction 1 at sample i (1..s); n2, n3
    !! likewise (a bivariate patch: n3 = 1, one sample).
    real(dp), allocatable :: n1(:,:,:), n2(:,:,:), n3(:,:,:)
  end type viz_patch_t

  !> Sample points and linear cells (quads in 2D, hexahedra in 3D) of all IGA elements of a
  !! model.
  type :: iga_viz_t
    !> Dimension of the model (2 or 3): samples s^ndm and cells (s-1)^ndm of 2^ndm corners
    !! per element.
    integer :: ndm = 2
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
    integer(i8) :: ne
    ns = 0
    ncells = 0
    do ip = 1, model%npatch
      s = iga_viz_samples(model, ip, samples)
      if (model%ndm == 3) then
        ne = product(int(model%volumes(ip)%nel, i8))
      else
        ne = product(int(model%patches(ip)%nel, i8))
      end if
      ns = ns + int(s, i8)**model%ndm*ne
      ncells = ncells + int(s - 1, i8)**model%ndm*ne
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
    integer :: e, s, ip, smp
    call iga_viz_free(viz)
    viz%ndm = model%ndm
    smp = 0
    if (present(samples)) smp = samples
    allocate(viz%patches(model%npatch))
    do ip = 1, model%npatch
      associate (vp => viz%patches(ip))
        s = iga_viz_samples(model, ip, smp)
        vp%s = s
        if (model%ndm == 3) then
          associate (v => model%volumes(ip))
            vp%p = v%p
            call span_table(v%p(1), v%c1, s, vp%n1)
            call span_table(v%p(2), v%c2, s, vp%n2)
            call span_table(v%p(3), v%c3, s, vp%n3)
          end associate
        else
          associate (pt => model%patches(ip))
            vp%p(1:2) = pt%p
            call span_table(pt%p(1), pt%c1, s, vp%n1)
            call span_table(pt%p(2), pt%c2, s, vp%n2)
            allocate(vp%n3(1, 1, 1), source=1.0_dp)
          end associate
        end if
      end associate
    end do
    allocate(viz%first_point(model%nel), viz%first_cell(model%nel))
    viz%first_point = -1
    viz%first_cell = -1
    viz%nen_max = 0
    do e = 1, model%nel
      if (.not. etype_is_nurbs(model%etype(e))) cycle
      s = viz%patches(model%patch(e))%s
      viz%first_point(e) = viz%ns
      viz%first_cell(e) = viz%ncells
      viz%ns = viz%ns + s**viz%ndm
      viz%ncells = viz%ncells + (s - 1)**viz%ndm
      viz%nen_max = max(viz%nen_max, model%nen(e))
    end do
  end subroutine iga_viz_init

  !> The B-splines of every span of one direction (degree p, extraction operators c(p+1,
  !! p+1, nel)) at the s sample parameters: tab(p+1, s, nel).
  subroutine span_table(p, c, s, tab)
    integer, intent(in) :: p, s
    real(dp), intent(in) :: c(:,:,:)
    real(dp), allocatable, intent(out) :: tab(:,:,:)
    ! degrees are at most 10 (the deck's limit)
    real(dp) :: xi, b(11), db(11)
    integer :: i, j
    allocate(tab(p + 1, s, size(c, 3)))
    do i = 1, s
      xi = -1.0_dp + 2.0_dp*real(i - 1, dp)/real(s - 1, dp)
      call bernstein(p, 0.5_dp*(xi + 1.0_dp), b(1:p + 1), db(1:p + 1))
      do j = 1, size(c, 3)
        tab(:, i, j) = matmul(c(:, :, j), b(1:p + 1))
      end do
    end do
  end subroutine span_table

  !> Control-point values to the sample-point values of the elements `elems`, in their order
  !! (each element's s^ndm points, direction 1 fastest). No allocation.
  !! @param uc control-point (node) vectors (ndm, :), node i at column map(i) (a rank's local
  !! numbering, or the identity); @param us (ndm, points of elems)
  pure subroutine iga_viz_eval(viz, model, elems, uc, us, map)
    type(iga_viz_t), intent(in) :: viz
    type(model_t), intent(in) :: model
    integer, intent(in) :: elems(:)
    real(dp), intent(in) :: uc(:,:)
    real(dp), intent(out) :: us(:,:)
    integer, intent(in) :: map(:)
    integer :: q, e, k, ijk(3), i1, i2, i3, a1, a2, a3, a, nen, nd, s3
    real(dp) :: r(viz%nen_max), ww
    nd = viz%ndm
    k = 0
    do q = 1, size(elems)
      e = elems(q)
      nen = model%nen(e)
      ijk = 1
      if (nd == 3) then
        ijk = volume_elem_ijk(model%volumes(model%patch(e)), model%patch_elem(e))
      else
        ijk(1:2) = patch_elem_ij(model%patches(model%patch(e)), model%patch_elem(e))
      end if
      associate (vp => viz%patches(model%patch(e)))
        s3 = merge(vp%s, 1, nd == 3)
        do i3 = 1, s3
          do i2 = 1, vp%s
            do i1 = 1, vp%s
              k = k + 1
              ! the rational basis as iga_basis_at forms it (n3 = 1 for a bivariate patch)
              ww = 0.0_dp
              a = 0
              do a3 = 1, vp%p(3) + 1
                do a2 = 1, vp%p(2) + 1
                  do a1 = 1, vp%p(1) + 1
                    a = a + 1
                    r(a) = element_cp_weight(model, e, a)*vp%n1(a1, i1, ijk(1))* &
                        vp%n2(a2, i2, ijk(2))*vp%n3(a3, i3, ijk(3))
                    ww = ww + r(a)
                  end do
                end do
              end do
              us(1:nd, k) = 0.0_dp
              do a = 1, nen
                us(1:nd, k) = us(1:nd, k) + (r(a)/ww)*uc(1:nd, map(model%conn(a, e)))
              end do
            end do
          end do
        end do
      end associate
    end do
  end subroutine iga_viz_eval

  !> Reference coordinates of all sample points, (ndm, ns).
  pure subroutine iga_viz_points(viz, model, points)
    type(iga_viz_t), intent(in) :: viz
    type(model_t), intent(in) :: model
    real(dp), intent(out) :: points(:,:)
    integer :: e, i
    call iga_viz_eval(viz, model, pack([(e, e = 1, model%nel)], viz%first_point >= 0), &
        model%x0, points, [(i, i = 1, model%nn)])
  end subroutine iga_viz_points

  !> Linear cells (2^ndm, ncells), 0-based sample point numbers: quads counter-clockwise in
  !! the parameter plane (counter-clockwise in x when det J > 0); in 3D hexahedra, the quad
  !! at the lower direction-3 sample then the one above it (the VTK and XDMF corner order,
  !! positive volume when det J > 0).
  pure subroutine iga_viz_cells(viz, model, cells)
    type(iga_viz_t), intent(in) :: viz
    type(model_t), intent(in) :: model
    integer, intent(out) :: cells(:,:)
    integer :: e, s, i1, i2, i3, k0, c, s3, lo, up
    do e = 1, model%nel
      if (viz%first_point(e) < 0) cycle
      s = viz%patches(model%patch(e))%s
      s3 = merge(s - 1, 1, viz%ndm == 3)
      k0 = viz%first_point(e)
      c = viz%first_cell(e)
      do i3 = 0, s3 - 1
        ! the sample layers i3 and i3 + 1 (3D)
        lo = k0 + i3*s*s
        up = lo + s*s
        ! corners (i1, i2), (i1+1, i2), (i1+1, i2+1), (i1, i2+1)
        do i2 = 0, s - 2
          do i1 = 0, s - 2
            c = c + 1
            cells(1, c) = lo + i1 + i2*s
            cells(2, c) = lo + i1 + 1 + i2*s
            cells(3, c) = lo + i1 + 1 + (i2 + 1)*s
            cells(4, c) = lo + i1 + (i2 + 1)*s
            if (viz%ndm == 3) cells(5:8, c) = cells(1:4, c) + (up - lo)
          end do
        end do
      end do
    end do
  end subroutine iga_viz_cells

  !> Samples per direction of patch ip: `samples` (SAMPLES=) when > 0, else 2 p_max + 1.
  pure integer function iga_viz_samples(model, ip, samples) result(s)
    type(model_t), intent(in) :: model
    integer, intent(in) :: ip, samples
    s = samples
    if (s <= 0) s = 2*patch_pmax(model, ip) + 1
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
