!> A three-parameter (trivariate) NURBS patch: geometry, refinement, Bezier elements
!! (doc/iga.md §11). The 3D counterpart of ictus_geometry_patch.
!!
!! Control points cp(4, n1*n2*n3) = (x, y, z, w), direction 1 fastest, then 2, then 3 (the order
!! of a deck's *CONTROL POINTS). Elements are the non-empty knot-span boxes, numbered
!! e = i1 + nel1 (i2 - 1) + nel1 nel2 (i3 - 1); the local control points of an element run
!! direction 1 fastest. Element parent coordinates in [-1, 1]^3 map linearly onto the span box.
!! Knot insertion and degree elevation act on every line of control points along one
!! direction with the curve routines of ictus_geometry_refine, so the volume is unchanged.
module ictus_geometry_volume
  use ictus_core_kinds, only: dp, str_len
  use ictus_geometry_bezier, only: bezier_extraction_1d
  use ictus_geometry_refine, only: refine_knot_vector, degree_elevate_curve
  use ictus_geometry_patch, only: new_knots, span_ranges
  use ictus_geometry_sides, only: SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ZETA0, &
      SIDE_ZETA1, SIDE_ALL
  implicit none
  private
  public :: volume_t, volume_init, volume_refine, volume_elevate, volume_build_elements, &
      volume_side_points, volume_elem_ijk

  type :: volume_t
    character(len=str_len) :: name = ''
    !> Degrees and control points per direction.
    integer :: p(3) = 0
    integer :: n(3) = 0
    !> Knot vectors (n(d) + p(d) + 1 entries).
    real(dp), allocatable :: knots1(:), knots2(:), knots3(:)
    !> Control points (4, n1 n2 n3): x, y, z, w (not homogeneous).
    real(dp), allocatable :: cp(:,:)
    !> Elements per direction, control points per element.
    integer :: nel(3) = 0
    integer :: nen = 0
    !> Extraction operators per direction (p(d)+1, p(d)+1, nel(d)).
    real(dp), allocatable :: c1(:,:,:), c2(:,:,:), c3(:,:,:)
    !> Knot span index (1-based, find_span convention) and parameter range of each span.
    integer, allocatable :: span1(:), span2(:), span3(:)
    real(dp), allocatable :: lo1(:), hi1(:), lo2(:), hi2(:), lo3(:), hi3(:)
    !> Control points (1..n1 n2 n3) of each element, (nen, nel1 nel2 nel3).
    integer, allocatable :: ien(:,:)
  end type volume_t

contains

  !> Sets up a volume patch from degrees p(3), counts n(3), knot vectors and control points
  !! cp(4, n1 n2 n3), and builds its elements.
  subroutine volume_init(v, name, p, n, knots1, knots2, knots3, cp)
    type(volume_t), intent(out) :: v
    character(len=*), intent(in) :: name
    integer, intent(in) :: p(3), n(3)
    real(dp), intent(in) :: knots1(:), knots2(:), knots3(:), cp(:,:)
    v%name = name
    v%p = p
    v%n = n
    v%knots1 = knots1(1:n(1) + p(1) + 1)
    v%knots2 = knots2(1:n(2) + p(2) + 1)
    v%knots3 = knots3(1:n(3) + p(3) + 1)
    v%cp = cp(1:4, 1:product(n))
    call volume_build_elements(v)
  end subroutine volume_init

  !> Extraction operators, spans and element connectivity from p, n and the knots.
  subroutine volume_build_elements(v)
    type(volume_t), intent(inout) :: v
    integer :: i1, i2, i3, a1, a2, a3, e, k
    call bezier_extraction_1d(v%n(1), v%p(1), v%knots1, v%nel(1), v%c1)
    call bezier_extraction_1d(v%n(2), v%p(2), v%knots2, v%nel(2), v%c2)
    call bezier_extraction_1d(v%n(3), v%p(3), v%knots3, v%nel(3), v%c3)
    call span_ranges(v%n(1), v%p(1), v%knots1, v%span1, v%lo1, v%hi1)
    call span_ranges(v%n(2), v%p(2), v%knots2, v%span2, v%lo2, v%hi2)
    call span_ranges(v%n(3), v%p(3), v%knots3, v%span3, v%lo3, v%hi3)
    v%nen = product(v%p + 1)
    if (allocated(v%ien)) deallocate(v%ien)
    allocate(v%ien(v%nen, product(v%nel)))
    do i3 = 1, v%nel(3)
      do i2 = 1, v%nel(2)
        do i1 = 1, v%nel(1)
          e = i1 + v%nel(1)*(i2 - 1) + v%nel(1)*v%nel(2)*(i3 - 1)
          k = 0
          do a3 = 0, v%p(3)
            do a2 = 0, v%p(2)
              do a1 = 0, v%p(1)
                k = k + 1
                v%ien(k, e) = index3(v%n, v%span1(i1) - v%p(1) + a1, &
                    v%span2(i2) - v%p(2) + a2, v%span3(i3) - v%p(3) + a3)
              end do
            end do
          end do
        end do
      end do
    end do
  end subroutine volume_build_elements

  !> Control point (i1, i2, i3) (1-based per direction) of a net of n(3).
  pure integer function index3(n, i1, i2, i3)
    integer, intent(in) :: n(3), i1, i2, i3
    index3 = i1 + n(1)*(i2 - 1) + n(1)*n(2)*(i3 - 1)
  end function index3

  !> The span indices (i1, i2, i3) of element e (e = i1 + nel1 (i2 - 1) + nel1 nel2 (i3 - 1)).
  pure function volume_elem_ijk(v, e) result(ijk)
    type(volume_t), intent(in) :: v
    integer, intent(in) :: e
    integer :: ijk(3)
    ijk(1) = mod(e - 1, v%nel(1)) + 1
    ijk(2) = mod((e - 1)/v%nel(1), v%nel(2)) + 1
    ijk(3) = (e - 1)/(v%nel(1)*v%nel(2)) + 1
  end function volume_elem_ijk

  !> Control points (local indices, increasing) on a face of the volume: XI0/XI1 where the
  !! direction-1 index is first/last, ETA0/ETA1 for direction 2, ZETA0/ZETA1 for direction 3;
  !! SIDE_ALL gives every control point on the boundary once. nidx = 0 for any other side.
  subroutine volume_side_points(v, side, idx, nidx)
    type(volume_t), intent(in) :: v
    integer, intent(in) :: side
    integer, allocatable, intent(out) :: idx(:)
    integer, intent(out) :: nidx
    logical, allocatable :: on(:)
    integer :: i1, i2, i3, k
    allocate(on(product(v%n)), source=.false.)
    do i3 = 1, v%n(3)
      do i2 = 1, v%n(2)
        do i1 = 1, v%n(1)
          k = index3(v%n, i1, i2, i3)
          select case (side)
          case (SIDE_XI0)
            on(k) = i1 == 1
          case (SIDE_XI1)
            on(k) = i1 == v%n(1)
          case (SIDE_ETA0)
            on(k) = i2 == 1
          case (SIDE_ETA1)
            on(k) = i2 == v%n(2)
          case (SIDE_ZETA0)
            on(k) = i3 == 1
          case (SIDE_ZETA1)
            on(k) = i3 == v%n(3)
          case (SIDE_ALL)
            on(k) = i1 == 1 .or. i1 == v%n(1) .or. i2 == 1 .or. i2 == v%n(2) .or. &
                i3 == 1 .or. i3 == v%n(3)
          end select
        end do
      end do
    end do
    idx = pack([(k, k = 1, size(on))], on)
    nidx = size(idx)
  end subroutine volume_side_points

  !> Subdivides every non-empty knot span of each direction d into k(d) equal spans (knot
  !! insertion; k(d) = 1 leaves the direction), then rebuilds the elements.
  subroutine volume_refine(v, k)
    type(volume_t), intent(inout) :: v
    integer, intent(in) :: k(3)
    real(dp), allocatable :: x_new(:)
    integer :: d
    do d = 1, 3
      if (k(d) <= 1) cycle
      select case (d)
      case (1)
        call new_knots(v%knots1, k(d), x_new)
        call along(v, d, v%knots1, x_new=x_new)
      case (2)
        call new_knots(v%knots2, k(d), x_new)
        call along(v, d, v%knots2, x_new=x_new)
      case (3)
        call new_knots(v%knots3, k(d), x_new)
        call along(v, d, v%knots3, x_new=x_new)
      end select
    end do
    call volume_build_elements(v)
  end subroutine volume_refine

  !> Raises the degree of direction d by t(d) >= 0, then rebuilds the elements.
  subroutine volume_elevate(v, t)
    type(volume_t), intent(inout) :: v
    integer, intent(in) :: t(3)
    integer :: d
    do d = 1, 3
      if (t(d) <= 0) cycle
      select case (d)
      case (1)
        call along(v, d, v%knots1, t=t(d))
      case (2)
        call along(v, d, v%knots2, t=t(d))
      case (3)
        call along(v, d, v%knots3, t=t(d))
      end select
    end do
    call volume_build_elements(v)
  end subroutine volume_elevate

  !> Applies knot insertion (x_new) or degree elevation (t) to every line of control points
  !! along direction d, whose knot vector `knots` is replaced; n(d), p(d) and cp follow.
  subroutine along(v, d, knots, x_new, t)
    type(volume_t), intent(inout) :: v
    integer, intent(in) :: d
    real(dp), allocatable, intent(inout) :: knots(:)
    real(dp), intent(in), optional :: x_new(:)
    integer, intent(in), optional :: t
    real(dp), allocatable :: line(:,:), line_out(:,:), knots_out(:), cp_new(:,:)
    integer :: nn(3), m(3), i, j, l, n_out, idx(3), a, b
    nn = v%n
    allocate(line(4, nn(d)))
    ! the two other directions
    a = merge(2, 1, d == 1)
    b = merge(2, 3, d == 3)
    do j = 1, nn(b)
      do i = 1, nn(a)
        do l = 1, nn(d)
          idx(d) = l
          idx(a) = i
          idx(b) = j
          line(:, l) = v%cp(:, index3(nn, idx(1), idx(2), idx(3)))
        end do
        if (present(x_new)) then
          call refine_knot_vector(nn(d), v%p(d), knots, line, x_new, n_out, knots_out, &
              line_out)
        else
          call degree_elevate_curve(nn(d), v%p(d), knots, line, t, n_out, knots_out, &
              line_out)
        end if
        if (.not. allocated(cp_new)) then
          m = nn
          m(d) = n_out
          allocate(cp_new(4, product(m)))
        end if
        do l = 1, n_out
          idx(d) = l
          idx(a) = i
          idx(b) = j
          cp_new(:, index3(m, idx(1), idx(2), idx(3))) = line_out(:, l)
        end do
      end do
    end do
    v%n = m
    if (present(t)) v%p(d) = v%p(d) + t
    call move_alloc(knots_out, knots)
    call move_alloc(cp_new, v%cp)
  end subroutine along
end module ictus_geometry_volume
