!> Merging of multi-patch NURBS bodies (*PATCH, MERGE=YES; doc/iga.md §1.1): control points
!! that two MERGE=YES patch sides share become one node, so that the patches form one body with
!! one mass and no internal seam.
!!
!! Two sides are glued when their end points coincide (in either direction). They must then
!! be the same curve in the same parametrisation: the same number of control points, the same
!! knot vector (scaled to [0, 1], reversed with the direction) and pairwise coincident control
!! points and weights. Anything else is refused, naming both patches and sides. Coincident
!! means within merge_tol times the larger patch's bounding-box diagonal (coordinates) and
!! merge_tol relative (weights). Merging runs on the refined patches (after every *REFINE and
!! *ELEVATE), so both patches must be refined alike along the shared side.
module ictus_app_merge_patches
  use ictus_core_kinds, only: dp
  use ictus_core_errors, only: input_error
  use ictus_core_strings, only: str
  use ictus_geometry_sides, only: SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, side_name
  use ictus_geometry_patch, only: patch_t, patch_side_points
  use ictus_geometry_volume, only: volume_t
  use ictus_app_id_map, only: merge_sort
  implicit none
  private
  public :: merge_patch_points, merge_tol, merge_volume_points, volume_merge_tol

  !> Relative tolerance of coincidence (coordinates against the patch size, and weights).
  real(dp), parameter :: merge_tol = 1.0e-9_dp

  !> Coincident control points of one trivariate patch: within this times its bounding-box
  !! diagonal (merge_volume_points).
  real(dp), parameter :: volume_merge_tol = 1.0e-10_dp

  !> Relative tolerance of equal knot vectors (scaled to [0, 1]).
  real(dp), parameter :: knot_tol = 1.0e-10_dp

contains

  !> Node numbering after merging. Before merging, node u = 1..nn0 is an FE node (u <=
  !! offset(1)) or control point k of patch p (u = offset(p) + k). Glued sides join their
  !! control points; each group becomes one node, numbered in order of its first member, so
  !! cp_node(u) <= u and an unmerged model keeps its numbering.
  !! @param patches the refined patches; @param offset index of each patch's first control
  !! point minus one; @param merge MERGE=YES per patch; @param where "file:line" of each
  !! *PATCH card (for messages); @param nn0 nodes before merging; @param cp_node node of
  !! each u after merging (nn0); @param nn nodes after merging
  subroutine merge_patch_points(patches, offset, merge, where, nn0, cp_node, nn)
    type(patch_t), intent(in) :: patches(:)
    integer, intent(in) :: offset(:), nn0
    logical, intent(in) :: merge(:)
    character(len=*), intent(in) :: where(:)
    integer, allocatable, intent(out) :: cp_node(:)
    integer, intent(out) :: nn
    integer, parameter :: sides(4) = [SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1]
    integer, allocatable :: parent(:)
    real(dp), allocatable :: diag(:)
    integer :: np, a, b, sa, sb, u
    np = size(patches)
    allocate(parent(nn0), diag(np))
    parent = [(u, u = 1, nn0)]
    do a = 1, np
      associate (cp => patches(a)%cp)
        diag(a) = norm2(maxval(cp(1:2, :), dim=2) - minval(cp(1:2, :), dim=2))
      end associate
    end do
    do a = 1, np
      if (.not. merge(a)) cycle
      do b = a, np
        if (.not. merge(b)) cycle
        do sa = 1, 4
          do sb = 1, 4
            if (b == a .and. sb <= sa) cycle
            call glue_sides(a, sides(sa), b, sides(sb))
          end do
        end do
      end do
    end do
    call numbering(parent, cp_node, nn)

  contains

    !> Joins the control points of side sa of patch a and side sb of patch b when the sides
    !! meet at both ends; reports sides that meet but differ.
    subroutine glue_sides(a, sa, b, sb)
      integer, intent(in) :: a, sa, b, sb
      integer, allocatable :: ia(:), ib(:)
      real(dp), allocatable :: ka(:), kb(:)
      character(len=:), allocatable :: why
      integer :: na, nb, k, j
      real(dp) :: tol
      logical :: rev
      associate (pa => patches(a), pb => patches(b))
        call patch_side_points(pa, sa, ia, na)
        call patch_side_points(pb, sb, ib, nb)
        tol = merge_tol*max(diag(a), diag(b))
        ! a collapsed side (a degenerate patch corner) is glued to nothing
        if (dist(pa, ia(1), pa, ia(na)) <= tol .or. dist(pb, ib(1), pb, ib(nb)) <= tol) return
        if (dist(pa, ia(1), pb, ib(1)) <= tol .and. dist(pa, ia(na), pb, ib(nb)) <= tol) then
          rev = .false.
        else if (dist(pa, ia(1), pb, ib(nb)) <= tol .and. &
            dist(pa, ia(na), pb, ib(1)) <= tol) then
          rev = .true.
        else
          return
        end if
        why = ''
        ka = side_knots(pa, sa)
        kb = side_knots(pb, sb)
        if (rev) kb = 1.0_dp - kb(size(kb):1:-1)
        if (na /= nb) then
          why = str(na)//' and '//str(nb)//' control points along them'
        else if (size(ka) /= size(kb)) then
          why = 'different degrees along them'
        else if (any(abs(ka - kb) > knot_tol)) then
          why = 'different knot vectors along them'
        else
          do k = 1, na
            j = k
            if (rev) j = nb + 1 - k
            if (dist(pa, ia(k), pb, ib(j)) > tol .or. abs(pa%cp(3, ia(k)) - pb%cp(3, ib(j))) > &
                merge_tol*max(pa%cp(3, ia(k)), pb%cp(3, ib(j)))) then
              why = 'control point '//str(k)//' of the first side (x, y, w) = ('// &
                  str(pa%cp(1, ia(k)))//', '//str(pa%cp(2, ia(k)))//', '// &
                  str(pa%cp(3, ia(k)))//') differs from ('//str(pb%cp(1, ib(j)))//', '// &
                  str(pb%cp(2, ib(j)))//', '//str(pb%cp(3, ib(j)))//')'
              exit
            end if
          end do
        end if
        if (len(why) > 0) then
          call input_error(where(b), '*PATCH, MERGE=YES: side '//side_name(sa)// &
              ' of patch '//trim(pa%name)//' and side '//side_name(sb)//' of patch '// &
              trim(pb%name)//' meet at both ends but cannot be merged: '//why// &
              ' (merged sides must be the same curve with the same knots; refine both '// &
              'patches alike, *REFINE and *ELEVATE apply before merging)')
          return
        end if
        do k = 1, na
          j = k
          if (rev) j = nb + 1 - k
          call join(parent, offset(a) + ia(k), offset(b) + ib(j))
        end do
      end associate
    end subroutine glue_sides
  end subroutine merge_patch_points

  !> Node numbering of a 3D model after merging the coincident control points of each
  !! trivariate patch (the collapsed sides of a degenerate patch, as the quarter-ball's axis
  !! segment and centre: doc/iga.md §11), so that a body has no edge of zero length between
  !! separate nodes. Coincident: within volume_merge_tol times the patch's bounding-box
  !! diagonal. Each group becomes one node numbered in order of its first member (cp_node(u)
  !! <= u, as merge_patch_points); the weights may differ (each element keeps the weights of
  !! its own control points). The candidates are found by sorting the control points along a
  !! generic direction (cells of 1e-8 diagonals): the result depends on the coordinates
  !! only, the same on every rank.
  !! @param volumes the refined patches; @param offset index of each patch's first control
  !! point minus one; @param nn0 nodes before merging; @param cp_node node of each u after
  !! merging (nn0); @param nn nodes after merging
  subroutine merge_volume_points(volumes, offset, nn0, cp_node, nn)
    type(volume_t), intent(in) :: volumes(:)
    integer, intent(in) :: offset(:), nn0
    integer, allocatable, intent(out) :: cp_node(:)
    integer, intent(out) :: nn
    ! a direction along which no plane of a usual control net projects to one value
    real(dp), parameter :: dir(3) = [0.8017837257_dp, 0.5469001627_dp, 0.2358453154_dp]
    integer, allocatable :: parent(:), key(:), order(:)
    real(dp) :: diag, tol, cell
    integer :: a, i, j, m, u
    allocate(parent(nn0))
    parent = [(u, u = 1, nn0)]
    do a = 1, size(volumes)
      associate (cp => volumes(a)%cp)
        m = size(cp, 2)
        diag = norm2(maxval(cp(1:3, :), dim=2) - minval(cp(1:3, :), dim=2))
        tol = volume_merge_tol*diag
        cell = 1.0e-8_dp*diag
        if (.not. (cell > 0.0_dp)) cycle
        key = [(nint(dot_product(dir, cp(1:3, i) - cp(1:3, 1))/cell), i = 1, m)]
        order = [(i, i = 1, m)]
        call merge_sort(key, order)
        ! coincident points lie in the same or the next cell of the sorted keys
        do i = 1, m
          do j = i + 1, m
            if (key(j) > key(i) + 1) exit
            if (norm2(cp(1:3, order(i)) - cp(1:3, order(j))) <= tol) &
                call join(parent, offset(a) + order(i), offset(a) + order(j))
          end do
        end do
      end associate
    end do
    call numbering(parent, cp_node, nn)
  end subroutine merge_volume_points

  !> Distance between control point i of patch p and control point j of patch q.
  pure real(dp) function dist(p, i, q, j)
    type(patch_t), intent(in) :: p, q
    integer, intent(in) :: i, j
    dist = norm2(p%cp(1:2, i) - q%cp(1:2, j))
  end function dist

  !> Knot vector along a side (direction 2 for XI0/XI1, direction 1 for ETA0/ETA1), scaled
  !! to [0, 1].
  pure function side_knots(p, side) result(k)
    type(patch_t), intent(in) :: p
    integer, intent(in) :: side
    real(dp), allocatable :: k(:)
    if (side == SIDE_XI0 .or. side == SIDE_XI1) then
      k = p%knots2
    else
      k = p%knots1
    end if
    k = (k - k(1))/(k(size(k)) - k(1))
  end function side_knots

  !> One node per group of the union-find forest parent, numbered in order of its first
  !! member: cp_node(u) of each member u, nn nodes.
  pure subroutine numbering(parent, cp_node, nn)
    integer, intent(in) :: parent(:)
    integer, allocatable, intent(out) :: cp_node(:)
    integer, intent(out) :: nn
    integer :: u, r
    allocate(cp_node(size(parent)))
    nn = 0
    do u = 1, size(parent)
      r = find_root(parent, u)
      if (r == u) then
        nn = nn + 1
        cp_node(u) = nn
      else
        cp_node(u) = cp_node(r)
      end if
    end do
  end subroutine numbering

  !> Root of u in the union-find forest (the smallest member of its group).
  pure integer function find_root(parent, u) result(r)
    integer, intent(in) :: parent(:), u
    r = u
    do while (parent(r) /= r)
      r = parent(r)
    end do
  end function find_root

  !> Joins the groups of u and v; the smaller root becomes the root.
  pure subroutine join(parent, u, v)
    integer, intent(inout) :: parent(:)
    integer, intent(in) :: u, v
    integer :: ru, rv
    ru = find_root(parent, u)
    rv = find_root(parent, v)
    if (ru /= rv) parent(max(ru, rv)) = min(ru, rv)
  end subroutine join
end module ictus_app_merge_patches
