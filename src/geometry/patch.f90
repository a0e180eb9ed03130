!> A two-parameter NURBS patch: geometry, refinement, Bezier elements and sides.
!!
!! Control points cp(3, n1*n2) = (x, y, w), direction-1 index fastest. Elements are the
!! non-empty knot-span rectangles, numbered e = i1 + (i2-1)*nel1; the local control points of
!! an element run direction-1 fastest. Element parent coordinates (xi~, eta~) in [-1, 1]^2
!! map linearly onto the span rectangle [span_lo1, span_hi1] x [span_lo2, span_hi2].
module ictus_geometry_patch
  use ictus_core_kinds, only: dp, str_len
  use ictus_core_errors, only: input_error
  use ictus_core_strings, only: str
  use ictus_geometry_sides, only: SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ALL
  use ictus_geometry_nurbs, only: nurbs_surface_point
  use ictus_geometry_refine, only: surface_refine, degree_elevate_surface
  use ictus_geometry_bezier, only: bezier_extraction_1d
  implicit none
  private
  public :: patch_t, patch_elevate, patch_refine, patch_build_elements, patch_point, &
      patch_side_points, patch_side_elements, patch_elem_ij, new_knots, span_ranges

  !> A NURBS patch with its Bezier-extracted elements.
  type :: patch_t
    !> Patch name from the deck.
    character(len=str_len) :: name = ''
    !> Degrees per direction.
    integer :: p(2) = 0
    !> Control points per direction.
    integer :: n(2) = 0
    !> Knot vectors of directions 1 and 2 (n(i)+p(i)+1 entries).
    real(dp), allocatable :: knots1(:), knots2(:)
    !> Control points (3, n1*n2): x, y, weight (not homogeneous); direction 1 fastest.
    real(dp), allocatable :: cp(:,:)
    !> Number of non-empty knot spans (elements) per direction.
    integer :: nel(2) = 0
    !> Control points per element, (p1+1)*(p2+1).
    integer :: nen = 0
    !> Extraction operators per direction: (p1+1, p1+1, nel1) and (p2+1, p2+1, nel2).
    real(dp), allocatable :: c1(:,:,:), c2(:,:,:)
    !> Parameter range of each element span per direction (nel1) and (nel2).
    real(dp), allocatable :: span_lo1(:), span_hi1(:), span_lo2(:), span_hi2(:)
    !> Knot span index (find_span convention, 1-based) of each element span, (nel1), (nel2).
    integer, allocatable :: span1(:), span2(:)
    !> Local control-point indices (1..n1*n2) of each element, (nen, nel1*nel2).
    integer, allocatable :: ien(:,:)
  contains
    procedure :: init => patch_init
    procedure :: free => patch_free
  end type patch_t

contains

  !> Sets up a patch from its data and builds its elements (calls free first).
  !! @param name patch name; @param p degrees (2); @param n control points per direction (2);
  !! @param knots1 (n1+p1+1); @param knots2 (n2+p2+1); @param cp (3, n1*n2)
  subroutine patch_init(this, name, p, n, knots1, knots2, cp)
    class(patch_t), intent(inout) :: this
    character(len=*), intent(in) :: name
    integer, intent(in) :: p(2), n(2)
    real(dp), intent(in) :: knots1(:), knots2(:), cp(:,:)
    call this%free()
    this%name = name
    this%p = p
    this%n = n
    this%knots1 = knots1(1:n(1)+p(1)+1)
    this%knots2 = knots2(1:n(2)+p(2)+1)
    this%cp = cp(1:3, 1:n(1)*n(2))
    call patch_build_elements(this)
  end subroutine patch_init

  !> Releases all arrays and resets the sizes.
  subroutine patch_free(this)
    class(patch_t), intent(inout) :: this
    this%name = ''
    this%p = 0
    this%n = 0
    this%nel = 0
    this%nen = 0
    if (allocated(this%knots1)) deallocate(this%knots1)
    if (allocated(this%knots2)) deallocate(this%knots2)
    if (allocated(this%cp)) deallocate(this%cp)
    if (allocated(this%c1)) deallocate(this%c1)
    if (allocated(this%c2)) deallocate(this%c2)
    if (allocated(this%span_lo1)) deallocate(this%span_lo1)
    if (allocated(this%span_hi1)) deallocate(this%span_hi1)
    if (allocated(this%span_lo2)) deallocate(this%span_lo2)
    if (allocated(this%span_hi2)) deallocate(this%span_hi2)
    if (allocated(this%span1)) deallocate(this%span1)
    if (allocated(this%span2)) deallocate(this%span2)
    if (allocated(this%ien)) deallocate(this%ien)
  end subroutine patch_free

  !> Raises the degrees to q (q >= p) without changing the geometry; rebuilds the elements.
  !! @param patch the patch; @param q new degrees (2)
  subroutine patch_elevate(patch, q)
    type(patch_t), intent(inout) :: patch
    integer, intent(in) :: q(2)
    real(dp), allocatable :: knots_out(:), cp_out(:,:)
    integer :: n_out
    if (any(q < patch%p)) then
      call input_error(trim(patch%name), 'ELEVATE: DEGREE='//str(q(1))//','//str(q(2)) &
          //' is below the patch degree '//str(patch%p(1))//','//str(patch%p(2)))
      return
    end if
    if (q(1) > patch%p(1)) then
      call degree_elevate_surface(1, patch%n(1), patch%n(2), patch%p(1), patch%knots1, &
          patch%cp, q(1) - patch%p(1), n_out, knots_out, cp_out)
      patch%n(1) = n_out
      patch%p(1) = q(1)
      call move_alloc(knots_out, patch%knots1)
      call move_alloc(cp_out, patch%cp)
    end if
    if (q(2) > patch%p(2)) then
      call degree_elevate_surface(2, patch%n(1), patch%n(2), patch%p(2), patch%knots2, &
          patch%cp, q(2) - patch%p(2), n_out, knots_out, cp_out)
      patch%n(2) = n_out
      patch%p(2) = q(2)
      call move_alloc(knots_out, patch%knots2)
      call move_alloc(cp_out, patch%cp)
    end if
    call patch_build_elements(patch)
  end subroutine patch_elevate

  !> Splits every non-empty knot span of direction i into k(i) equal spans by knot
  !! insertion (geometry unchanged); rebuilds the elements.
  !! @param patch the patch; @param k subdivisions per direction (2), k >= 1
  subroutine patch_refine(patch, k)
    type(patch_t), intent(inout) :: patch
    integer, intent(in) :: k(2)
    real(dp), allocatable :: knots_out(:), cp_out(:,:), x_new(:)
    integer :: n_out
    if (any(k < 1)) then
      call input_error(trim(patch%name), 'REFINE: SUBDIVIDE='//str(k(1))//','//str(k(2)) &
          //' must be at least 1')
      return
    end if
    if (k(1) > 1) then
      call new_knots(patch%knots1, k(1), x_new)
      call surface_refine(1, patch%n(1), patch%n(2), patch%p(1), patch%knots1, patch%cp, &
          x_new, n_out, knots_out, cp_out)
      patch%n(1) = n_out
      call move_alloc(knots_out, patch%knots1)
      call move_alloc(cp_out, patch%cp)
    end if
    if (k(2) > 1) then
      call new_knots(patch%knots2, k(2), x_new)
      call surface_refine(2, patch%n(1), patch%n(2), patch%p(2), patch%knots2, patch%cp, &
          x_new, n_out, knots_out, cp_out)
      patch%n(2) = n_out
      call move_alloc(knots_out, patch%knots2)
      call move_alloc(cp_out, patch%cp)
    end if
    call patch_build_elements(patch)
  end subroutine patch_refine

  !> Knots that split every non-empty span of `knots` into k equal parts, in order.
  pure subroutine new_knots(knots, k, x_new)
    real(dp), intent(in) :: knots(:)
    integer, intent(in) :: k
    real(dp), allocatable, intent(out) :: x_new(:)
    integer :: i, j, m
    m = 0
    do i = 1, size(knots) - 1
      if (knots(i+1) > knots(i)) m = m + 1
    end do
    allocate(x_new(m*(k-1)))
    m = 0
    do i = 1, size(knots) - 1
      if (knots(i+1) > knots(i)) then
        do j = 1, k - 1
          m = m + 1
          x_new(m) = knots(i) + (knots(i+1) - knots(i))*real(j, dp)/real(k, dp)
        end do
      end if
    end do
  end subroutine new_knots

  !> Fills nel, nen, the extraction operators, span ranges and ien from p, n, knots.
  !! @param patch the patch
  subroutine patch_build_elements(patch)
    type(patch_t), intent(inout) :: patch
    integer :: i1, i2, a1, a2, e, k, p1, p2, n1
    p1 = patch%p(1)
    p2 = patch%p(2)
    n1 = patch%n(1)
    call bezier_extraction_1d(n1, p1, patch%knots1, patch%nel(1), patch%c1)
    call bezier_extraction_1d(patch%n(2), p2, patch%knots2, patch%nel(2), patch%c2)
    call span_ranges(patch%n(1), p1, patch%knots1, patch%span1, patch%span_lo1, patch%span_hi1)
    call span_ranges(patch%n(2), p2, patch%knots2, patch%span2, patch%span_lo2, patch%span_hi2)
    patch%nen = (p1 + 1)*(p2 + 1)
    if (allocated(patch%ien)) deallocate(patch%ien)
    allocate(patch%ien(patch%nen, patch%nel(1)*patch%nel(2)))
    do i2 = 1, patch%nel(2)
      do i1 = 1, patch%nel(1)
        e = i1 + (i2 - 1)*patch%nel(1)
        k = 0
        do a2 = 0, p2
          do a1 = 0, p1
            k = k + 1
            patch%ien(k, e) = (patch%span1(i1) - p1 + a1) + (patch%span2(i2) - p2 + a2 - 1)*n1
          end do
        end do
      end do
    end do
  end subroutine patch_build_elements

  !> Knot span indices and parameter ranges of the non-empty spans of one direction.
  pure subroutine span_ranges(n, p, knots, span, lo, hi)
    integer, intent(in) :: n, p
    real(dp), intent(in) :: knots(:)
    integer, allocatable, intent(inout) :: span(:)
    real(dp), allocatable, intent(inout) :: lo(:), hi(:)
    integer :: i, m
    if (allocated(span)) deallocate(span)
    if (allocated(lo)) deallocate(lo)
    if (allocated(hi)) deallocate(hi)
    m = 0
    do i = p + 1, n
      if (knots(i+1) > knots(i)) m = m + 1
    end do
    allocate(span(m), lo(m), hi(m))
    m = 0
    do i = p + 1, n
      if (knots(i+1) > knots(i)) then
        m = m + 1
        span(m) = i
        lo(m) = knots(i)
        hi(m) = knots(i+1)
      end if
    end do
  end subroutine span_ranges

  !> Direction indices (i1, i2) of element e: e = i1 + (i2-1)*nel1.
  !! @param patch the patch; @param e element number; @return ij (2)
  pure function patch_elem_ij(patch, e) result(ij)
    type(patch_t), intent(in) :: patch
    integer, intent(in) :: e
    integer :: ij(2)
    ij(1) = mod(e - 1, patch%nel(1)) + 1
    ij(2) = (e - 1)/patch%nel(1) + 1
  end function patch_elem_ij

  !> Point of the patch at parameters u(2), optionally with dx/du1 and dx/du2.
  !! @param patch the patch; @param u parameters (2); @param x point (2);
  !! @param dxdu, dxdv derivatives (2), optional
  pure subroutine patch_point(patch, u, x, dxdu, dxdv)
    type(patch_t), intent(in) :: patch
    real(dp), intent(in) :: u(2)
    real(dp), intent(out) :: x(2)
    real(dp), intent(out), optional :: dxdu(2), dxdv(2)
    real(dp) :: d1(2), d2(2)
    call nurbs_surface_point(patch%n(1), patch%n(2), patch%p(1), patch%p(2), patch%knots1, &
        patch%knots2, patch%cp, u(1), u(2), x, d1, d2)
    if (present(dxdu)) dxdu = d1
    if (present(dxdv)) dxdv = d2
  end subroutine patch_point

  !> Control points on a side, in increasing parameter order along it. SIDE_ALL gives the
  !! whole boundary once, counter-clockwise in the parameter plane starting at (u1, u2) =
  !! (first, first): ETA0, XI1, ETA1 reversed, XI0 reversed.
  !! @param patch the patch; @param side SIDE_* code; @param idx local control point
  !! indices (nidx); @param nidx their number (0 for an unknown side)
  subroutine patch_side_points(patch, side, idx, nidx)
    type(patch_t), intent(in) :: patch
    integer, intent(in) :: side
    integer, allocatable, intent(out) :: idx(:)
    integer, intent(out) :: nidx
    integer :: n1, n2, i
    n1 = patch%n(1)
    n2 = patch%n(2)
    select case (side)
    case (SIDE_XI0)
      idx = [(1 + (i-1)*n1, i = 1, n2)]
    case (SIDE_XI1)
      idx = [(n1 + (i-1)*n1, i = 1, n2)]
    case (SIDE_ETA0)
      idx = [(i, i = 1, n1)]
    case (SIDE_ETA1)
      idx = [(i + (n2-1)*n1, i = 1, n1)]
    case (SIDE_ALL)
      idx = [[(i, i = 1, n1)], [(n1 + (i-1)*n1, i = 2, n2)], &
          [(i + (n2-1)*n1, i = n1-1, 1, -1)], [(1 + (i-1)*n1, i = n2-1, 2, -1)]]
    case default
      allocate(idx(0))
    end select
    nidx = size(idx)
  end subroutine patch_side_points

  !> Elements along a side and the parent face of each that lies on it (1: eta~ = -1,
  !! 2: xi~ = +1, 3: eta~ = +1, 4: xi~ = -1, as Q4 faces 1-2, 2-3, 3-4, 4-1). Elements come
  !! in increasing parameter order along the side; SIDE_ALL lists ETA0, XI1, ETA1 reversed,
  !! XI0 reversed (corner elements appear twice, with different faces).
  !! @param patch the patch; @param side SIDE_* code; @param elems elements (nf);
  !! @param faces parent faces (nf); @param nf number of element faces (0 if unknown side)
  subroutine patch_side_elements(patch, side, elems, faces, nf)
    type(patch_t), intent(in) :: patch
    integer, intent(in) :: side
    integer, allocatable, intent(out) :: elems(:), faces(:)
    integer, intent(out) :: nf
    integer :: ne1, ne2, i
    ne1 = patch%nel(1)
    ne2 = patch%nel(2)
    select case (side)
    case (SIDE_XI0)
      elems = [(1 + (i-1)*ne1, i = 1, ne2)]
      faces = [(4, i = 1, ne2)]
    case (SIDE_XI1)
      elems = [(ne1 + (i-1)*ne1, i = 1, ne2)]
      faces = [(2, i = 1, ne2)]
    case (SIDE_ETA0)
      elems = [(i, i = 1, ne1)]
      faces = [(1, i = 1, ne1)]
    case (SIDE_ETA1)
      elems = [(i + (ne2-1)*ne1, i = 1, ne1)]
      faces = [(3, i = 1, ne1)]
    case (SIDE_ALL)
      elems = [[(i, i = 1, ne1)], [(ne1 + (i-1)*ne1, i = 1, ne2)], &
          [(i + (ne2-1)*ne1, i = ne1, 1, -1)], [(1 + (i-1)*ne1, i = ne2, 1, -1)]]
      faces = [[(1, i = 1, ne1)], [(2, i = 1, ne2)], [(3, i = 1, ne1)], [(4, i = 1, ne2)]]
    case default
      allocate(elems(0), faces(0))
    end select
    nf = size(elems)
  end subroutine patch_side_elements
end module ictus_geometry_patch
