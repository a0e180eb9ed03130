!> The lattices of a model for MASS SOLVER=KRONECKER (ictus_solver_tensor_types): one per
!! NURBS patch, or one per connected grid of Q4, Q8 or Q9 elements with axis-parallel sides.
module ictus_solver_tensor_layout
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: str
  use ictus_elements_types, only: ETYPE_IGA, element_kind_t
  use ictus_elements_library, only: element_kind
  use ictus_solver_model, only: model_t
  use ictus_solver_tensor_types, only: lattice_t, tensor_layout_t, TENSOR_DIRECT, &
      TENSOR_SERENDIPITY
  implicit none
  private
  public :: tensor_layout_t, tensor_layout

contains

  !> Finds the lattices of `model`: one per NURBS patch when all elements are patch spans,
  !! or one per connected group of elements when all are Q4, Q8 or Q9 elements whose nodes
  !! sit on a rectangular grid of lines (axis-parallel). Otherwise lay%nblocks = 0 and
  !! lay%reason says why.
  subroutine tensor_layout(model, lay)
    type(model_t), intent(in) :: model
    type(tensor_layout_t), intent(out) :: lay
    integer :: p, i, j, n1, n2, et
    if (model%nel == 0) then
      lay%reason = 'the model has no elements'
      return
    end if
    if (all(model%etype == ETYPE_IGA)) then
      if (model%nmerged > 0) then
        lay%reason = 'patches share control points (MERGE=YES), so the model is not a '// &
            'set of separate lattices'
        return
      end if
      allocate(lay%b(model%npatch))
      do p = 1, model%npatch
        n1 = model%patches(p)%n(1)
        n2 = model%patches(p)%n(2)
        lay%b(p)%kind = TENSOR_DIRECT
        lay%b(p)%n = [n1, n2]
        allocate(lay%b(p)%node(n1, n2))
        do j = 1, n2
          do i = 1, n1
            lay%b(p)%node(i, j) = model%patch_offset(p) + i + (j - 1)*n1
          end do
        end do
        lay%b(p)%what = 'patch '//trim(model%patches(p)%name)
      end do
      lay%nblocks = model%npatch
      return
    end if
    if (any(model%etype == ETYPE_IGA)) then
      lay%reason = 'finite elements and NURBS patches are mixed'
      return
    end if
    et = model%etype(1)
    if (any(model%etype /= et)) then
      lay%reason = 'the elements are of more than one type'
      return
    end if
    call fe_lattices(model, et, lay)
  end subroutine tensor_layout

  !> The lattices of a mesh of one finite-element type: connected groups of elements
  !! (through shared nodes), each checked to be a rectangular grid.
  subroutine fe_lattices(model, et, lay)
    type(model_t), intent(in) :: model
    integer, intent(in) :: et
    type(tensor_layout_t), intent(inout) :: lay
    integer, allocatable :: parent(:), group_of_el(:), group(:), el_order(:), first(:), next(:)
    integer :: e, a, r, s, ngroups, k, g
    type(lattice_t), allocatable :: tmp(:)
    character(len=:), allocatable :: why
    if (.not. lattice_quad(et)) then
      lay%reason = 'the elements are not Q4, Q8 or Q9'
      return
    end if
    ! union-find over the nodes of each element
    allocate(parent(model%nn))
    parent = [(a, a = 1, model%nn)]
    do e = 1, model%nel
      r = find_root(parent, model%conn(1, e))
      do a = 2, model%nen(e)
        s = find_root(parent, model%conn(a, e))
        if (s /= r) parent(max(r, s)) = min(r, s)
        r = min(r, s)
      end do
    end do
    ! the group of each element: its root's number in order of first appearance
    allocate(group_of_el(model%nel), group(model%nn), source=0)
    ngroups = 0
    do e = 1, model%nel
      r = find_root(parent, model%conn(1, e))
      if (group(r) == 0) then
        ngroups = ngroups + 1
        group(r) = ngroups
      end if
      group_of_el(e) = group(r)
    end do
    ! elements of each group, in element order
    allocate(first(ngroups + 1), source=0)
    do e = 1, model%nel
      first(group_of_el(e) + 1) = first(group_of_el(e) + 1) + 1
    end do
    first(1) = 1
    do g = 1, ngroups
      first(g + 1) = first(g) + first(g + 1)
    end do
    allocate(el_order(model%nel))
    next = first(1:ngroups)
    do e = 1, model%nel
      k = group_of_el(e)
      el_order(next(k)) = e
      next(k) = next(k) + 1
    end do
    allocate(tmp(ngroups))
    do g = 1, ngroups
      call grid_lattice(model, et, el_order(first(g):first(g + 1) - 1), tmp(g), why)
      if (len(why) > 0) then
        lay%reason = why
        return
      end if
    end do
    call move_alloc(tmp, lay%b)
    lay%nblocks = ngroups
  end subroutine fe_lattices

  !> Root of node i in the union-find forest (with path halving).
  integer function find_root(parent, i) result(r)
    integer, intent(inout) :: parent(:)
    integer, intent(in) :: i
    r = i
    do while (parent(r) /= r)
      parent(r) = parent(parent(r))
      r = parent(r)
    end do
  end function find_root

  !> The lattice of one connected group of elements `els` of type et, or `why` (non-empty)
  !! when they do not form a rectangular grid: node coordinates on n1 x lines and n2 y lines,
  !! every lattice point a node (Q8: except the element centres), every element one cell.
  subroutine grid_lattice(model, et, els, lat, why)
    type(model_t), intent(in) :: model
    integer, intent(in) :: et, els(:)
    type(lattice_t), intent(out) :: lat
    character(len=:), allocatable, intent(out) :: why
    integer, allocatable :: nodes(:), li(:), lj(:), cell(:,:)
    logical, allocatable :: seen(:)
    real(dp), allocatable :: xs(:), ys(:)
    real(dp) :: tol, ext
    integer :: e, a, k, n1, n2, step, i0, j0, i, j, nn, expected, ne1, ne2
    type(element_kind_t) :: kd
    logical :: serendipity
    why = ''
    allocate(seen(model%nn), source=.false.)
    do k = 1, size(els)
      seen(model%conn(1:model%nen(els(k)), els(k))) = .true.
    end do
    nodes = pack([(a, a = 1, model%nn)], seen)
    nn = size(nodes)
    ext = max(maxval(model%x0(1, nodes)) - minval(model%x0(1, nodes)), &
        maxval(model%x0(2, nodes)) - minval(model%x0(2, nodes)))
    tol = 1.0e-9_dp*ext
    xs = distinct(model%x0(1, nodes), tol)
    ys = distinct(model%x0(2, nodes), tol)
    n1 = size(xs)
    n2 = size(ys)
    kd = element_kind(et)
    step = kd%order
    ! serendipity: a quadratic quadrilateral without its centre node
    serendipity = kd%order == 2 .and. .not. kd%centre
    if (mod(n1 - 1, step) /= 0 .or. mod(n2 - 1, step) /= 0 .or. n1 < 2 .or. n2 < 2) then
      why = 'the nodes do not lie on a grid of lines parallel to the axes'
      return
    end if
    ne1 = (n1 - 1)/step
    ne2 = (n2 - 1)/step
    expected = n1*n2
    if (serendipity) expected = n1*n2 - ne1*ne2
    if (nn /= expected .or. size(els) /= ne1*ne2) then
      why = 'the nodes do not lie on a grid of lines parallel to the axes'
      return
    end if
    allocate(lat%node(n1, n2), source=0)
    allocate(li(model%nn), lj(model%nn), source=0)
    do k = 1, nn
      i = locate(xs, model%x0(1, nodes(k)), tol)
      j = locate(ys, model%x0(2, nodes(k)), tol)
      if (lat%node(i, j) /= 0 .or. (serendipity .and. mod(i, 2) == 0 .and. &
          mod(j, 2) == 0)) then
        why = 'the nodes do not lie on a grid of lines parallel to the axes'
        return
      end if
      lat%node(i, j) = nodes(k)
      li(nodes(k)) = i
      lj(nodes(k)) = j
    end do
    ! every element fills one cell of step x step lattice intervals, each cell once
    allocate(cell(ne1, ne2), source=0)
    do k = 1, size(els)
      e = els(k)
      associate (ii => li(model%conn(1:model%nen(e), e)), jj => lj(model%conn(1:model%nen(e), e)))
        i0 = minval(ii)
        j0 = minval(jj)
        if (maxval(ii) - i0 /= step .or. maxval(jj) - j0 /= step .or. mod(i0 - 1, step) /= 0 &
            .or. mod(j0 - 1, step) /= 0) then
          why = 'an element is not one cell of the grid of lines'
          return
        end if
        cell(1 + (i0 - 1)/step, 1 + (j0 - 1)/step) = cell(1 + (i0 - 1)/step, &
            1 + (j0 - 1)/step) + 1
      end associate
    end do
    if (any(cell /= 1)) then
      why = 'the elements do not cover the grid of lines once'
      return
    end if
    lat%kind = TENSOR_DIRECT
    if (serendipity) lat%kind = TENSOR_SERENDIPITY
    lat%n = [n1, n2]
    lat%x1 = xs
    lat%x2 = ys
    lat%what = trim(kd%name)//' grid of '//str(ne1)//' x '//str(ne2)//' elements'
  end subroutine grid_lattice

  !> Whether element type et is a Lagrange or serendipity quadrilateral of order 1 or 2 whose
  !! nodes can sit on a lattice (Q4, Q8, Q9: four corners, fixed nodes, 2D).
  logical function lattice_quad(et)
    integer, intent(in) :: et
    type(element_kind_t) :: kd
    kd = element_kind(et)
    lattice_quad = kd%ndm == 2 .and. kd%ncorner == 4 .and. kd%nen == (kd%order + 1)**2 - &
        merge(1, 0, kd%order == 2 .and. .not. kd%centre) .and. kd%order >= 1 .and. kd%order <= 2
  end function lattice_quad

  !> The distinct values of v (ascending; values closer than tol are one).
  function distinct(v, tol) result(d)
    real(dp), intent(in) :: v(:), tol
    real(dp), allocatable :: d(:), s(:)
    integer :: i, k
    allocate(s, source=v)
    call heap_sort(s)
    allocate(d(size(s)))
    k = 0
    do i = 1, size(s)
      if (k > 0) then
        if (s(i) - d(k) <= tol) cycle
      end if
      k = k + 1
      d(k) = s(i)
    end do
    d = d(1:k)
  end function distinct

  !> Index of the entry of the ascending list d within tol of x (bisection; 1..size(d)).
  pure integer function locate(d, x, tol) result(k)
    real(dp), intent(in) :: d(:), x, tol
    integer :: lo, hi, mid
    lo = 1
    hi = size(d)
    do while (lo < hi)
      mid = (lo + hi)/2
      if (d(mid) < x - tol) then
        lo = mid + 1
      else
        hi = mid
      end if
    end do
    k = lo
  end function locate

  !> In-place ascending heap sort (n log n; the coordinate lists have millions of entries).
  pure subroutine heap_sort(v)
    real(dp), intent(inout) :: v(:)
    integer :: n, i
    real(dp) :: t
    n = size(v)
    do i = n/2, 1, -1
      call sift(v, i, n)
    end do
    do i = n, 2, -1
      t = v(1)
      v(1) = v(i)
      v(i) = t
      call sift(v, 1, i - 1)
    end do
  end subroutine heap_sort

  pure subroutine sift(v, start, last)
    real(dp), intent(inout) :: v(:)
    integer, intent(in) :: start, last
    integer :: root, child
    real(dp) :: t
    root = start
    do while (2*root <= last)
      child = 2*root
      if (child < last) then
        if (v(child + 1) > v(child)) child = child + 1
      end if
      if (v(root) >= v(child)) return
      t = v(root)
      v(root) = v(child)
      v(child) = t
      root = child
    end do
  end subroutine sift
end module ictus_solver_tensor_layout
