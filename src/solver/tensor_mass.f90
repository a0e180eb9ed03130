!> Exact consistent-mass solves on tensor-product lattices: MASS SOLVER=KRONECKER
!! (doc/theory.md §5.2).
!!
!! * **Kronecker blocks.** On a NURBS patch whose geometry and weights are separable (a
!!   rectangle refined in any way, graded knots included), and on a grid of Q4 or Q9 elements
!!   with axis-parallel sides, the consistent mass of each displacement component is a
!!   Kronecker product M = A1 (x) A2 of two banded 1D masses (half bandwidth p). Its inverse
!!   A1^-1 (x) A2^-1 is two sweeps of banded Cholesky solves, one along each lattice
!!   direction: O(n) work, no stored factor beyond the 1D ones (the structure Gao & Calo,
!!   CMAME 2014, use for explicit IGA). A1 and A2 are read off the assembled M.
!! * **Serendipity blocks.** On a grid of Q8 elements with axis-parallel sides the mass is not
!!   a Kronecker product, but the serendipity space is the biquadratic one without the
!!   bubble (x) bubble functions of the hierarchical basis (vertex hats V and element bubbles B
!!   in each direction): Q8 = span{V(x)V, V(x)B, B(x)V}. So its mass is the principal
!!   submatrix of the Q9 mass Â1 (x) Â2 (hierarchical 1D masses from the node coordinates)
!!   without the B x B rows. With S the Kronecker inverse and E the B x B selection, the
!!   capacitance formula gives the solve x = S g - S E (E^T S E)^-1 E^T S g, and
!!   E^T S E = (Â1^-1)_BB (x) (Â2^-1)_BB is again a Kronecker product whose factors have the
!!   Schur complements Â_BB - Â_BV Â_VV^-1 Â_VB as inverses (tridiagonal solves). One solve:
!!   two Kronecker solves, one Schur product on the element lattice, two basis changes.
!! * **Dirichlet conditions.** A lattice line fixed in a component becomes an identity row of
!!   that component's 1D matrix (for Q8 only vertex lines). Other fixed dofs (say the one
!!   point of a roller edge fixed along the edge) are up to `max_points` isolated points: a
!!   second capacitance correction with the responses to unit loads there, computed once.
!!
!! `tensor_layout` finds the lattices in the model; `tensor_mass_setup` builds the 1D matrices
!! and proves the result: M v for pseudo-random v must solve back to v within 1e-9 (relative),
!! so a mesh that only looks like a lattice (a distorted grid, a non-uniform density, weights
!! that are not separable) is refused with the reason, and the caller falls back to another
!! solver. The solve allocates nothing.
module ictus_solver_tensor_mass
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: str
  use ictus_core_memory, only: alloc_stream
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, ETYPE_IGA
  use ictus_solver_model, only: model_t
  implicit none
  private
  public :: tensor_layout_t, tensor_mass_t, tensor_layout, tensor_mass_setup, &
      tensor_mass_solve, tensor_mass_step, tensor_mass_renumber, tensor_mass_describe, &
      TENSOR_DIRECT, TENSOR_SERENDIPITY

  !> Block kinds: a Kronecker-product mass, or the Q8 mass inside the Q9 one.
  integer, parameter :: TENSOR_DIRECT = 1, TENSOR_SERENDIPITY = 2
  !> Most isolated fixed points per block and component (each costs one lattice-sized
  !! response vector and one pass per solve).
  integer, parameter :: max_points = 8
  !> Relative error of the set-up check M v -> v above which the lattice is refused.
  real(dp), parameter :: check_tol = 1.0e-9_dp
  !> Columns solved together along direction 1: their recurrences run as one vector of
  !! col_block lanes (4 AVX-512 registers), whose last kd values stay in registers.
  integer, parameter :: col_block = 32

  !> One lattice as found in the model: n(1) x n(2) points, the node at each (0: none, the
  !! centre of a Q8 element), and for Q8 the coordinate of each lattice line.
  type :: lattice_t
    integer :: kind = TENSOR_DIRECT
    integer :: n(2) = 0
    integer, allocatable :: node(:,:)
    real(dp), allocatable :: x1(:), x2(:)
    !> What the lattice is, for the log (e.g. "patch BODY", "Q8 grid").
    character(len=:), allocatable :: what
  end type lattice_t

  !> The lattices of a model (nblocks = 0 when it has none; `reason` says why).
  type :: tensor_layout_t
    integer :: nblocks = 0
    type(lattice_t), allocatable :: b(:)
    character(len=:), allocatable :: reason
  end type tensor_layout_t

  !> A symmetric band matrix a(k, i) = A(i, i - k), k = 0..kd, and its Cholesky factor
  !! l(0, i) = 1/L(i, i), l(k, i) = L(i, i - k).
  type :: band_t
    integer :: n = 0
    integer :: kd = 0
    real(dp), allocatable :: a(:,:), l(:,:)
  end type band_t

  !> A hierarchical 1D Q8 mass A (vertex v at 2v - 1, the bubble of element e at 2e) in
  !! condensed form: A_BB is diagonal (the bubbles of two elements do not overlap), so
  !! A^-1 y = expand(S^-1 condense(y)) with the tridiagonal vertex Schur complement
  !! S = A_VV - A_VB A_BB^-1 A_BV (its Cholesky factor in sv), condense(y)_v =
  !! y_v - pr(v-1) y_(bubble v-1) - pl(v) y_(bubble v), and the bubbles expanded as
  !! x_e = ab(e) y_e - pl(e) x_(vertex e) - pr(e) x_(vertex e+1), where ab = 1/A_BB and
  !! pl, pr are the bubble's couplings to its left and right vertex times ab. Half the lines
  !! and half the band of the banded factor of A.
  type :: cond_t
    type(band_t) :: sv
    real(dp), allocatable :: ab(:), pl(:), pr(:)
    !> The entries themselves, per bubble e (contiguous, for the Schur products): A_BB(e),
    !! and its couplings cl(e), cr(e) to its left and right vertex.
    real(dp), allocatable :: abb(:), cl(:), cr(:)
  end type cond_t

  !> One component of one block: the fixed lines of each direction (fix1, fix2; rows1 lists
  !! those of direction 1), the 1D matrices with the fixed lines as identity rows
  !! (hierarchical for Q8), the factor of their vertex parts and their condensed forms (Q8),
  !! and the isolated fixed points with their unit responses w(:, :, k), the lattice
  !! box(1:4, k) = i1, i2, j1, j2
  !! outside which |w(:, :, k)| < 1e-18 max |w(:, :, k)| (the inverse of a mass matrix decays
  !! exponentially away from the load), and the Cholesky factor h of the capacitance matrix
  !! H(l, k) = w(pts(l), k).
  type :: comp_t
    type(band_t) :: m(2)
    type(band_t) :: v(2)
    type(cond_t) :: q(2)
    logical, allocatable :: fix1(:), fix2(:)
    integer, allocatable :: rows1(:)
    integer :: npts = 0
    integer, allocatable :: pts(:,:), box(:,:)
    real(dp), allocatable :: w(:,:,:), h(:,:), beta(:)
  end type comp_t

  !> One block: its kind and lattice (with kfirst(j) the first node of column j when the
  !! nodes of that column are numbered one after the other, 0 otherwise), both components,
  !! and the work arrays of a solve: the lattice z(:, :, c) of each component, the B x B
  !! values r and the Schur work t (direction 2) and tv (direction 1) of Q8, and a ring of
  !! columns (Q8: the last loads of a forward block, the last back-substituted vertex
  !! columns), a block zb of bubble columns (their indices jb) and the work lt of
  !! `lines_solve`.
  type :: tblock_t
    integer :: kind = TENSOR_DIRECT
    integer :: n(2) = 0
    integer :: ne(2) = 0
    integer, allocatable :: node(:,:), kfirst(:)
    !> The columns in the boxes of the point corrections (stored once those are known).
    logical, allocatable :: defer(:)
    type(comp_t) :: c(2)
    real(dp), allocatable :: z(:,:,:), r(:,:,:), t(:,:), tv(:,:), ring(:,:), zb(:,:), lt(:,:)
    integer, allocatable :: jb(:)
    !> One column of nodal values on its way out of `store` (2, n(1)).
    real(dp), allocatable :: xc(:,:)
    character(len=:), allocatable :: what
  end type tblock_t

  !> The solver: its blocks and the nodes outside every block (massless: zero result).
  type :: tensor_mass_t
    integer :: nblocks = 0
    type(tblock_t), allocatable :: b(:)
    integer, allocatable :: outside(:)
  end type tensor_mass_t

contains

  ! ------------------------------------------------------------------ lattices of a model

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
    if (et /= ETYPE_Q4 .and. et /= ETYPE_Q8 .and. et /= ETYPE_Q9) then
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
    step = 1
    if (et /= ETYPE_Q4) step = 2
    if (mod(n1 - 1, step) /= 0 .or. mod(n2 - 1, step) /= 0 .or. n1 < 2 .or. n2 < 2) then
      why = 'the nodes do not lie on a grid of lines parallel to the axes'
      return
    end if
    ne1 = (n1 - 1)/step
    ne2 = (n2 - 1)/step
    expected = n1*n2
    if (et == ETYPE_Q8) expected = n1*n2 - ne1*ne2
    if (nn /= expected .or. size(els) /= ne1*ne2) then
      why = 'the nodes do not lie on a grid of lines parallel to the axes'
      return
    end if
    allocate(lat%node(n1, n2), source=0)
    allocate(li(model%nn), lj(model%nn), source=0)
    do k = 1, nn
      i = locate(xs, model%x0(1, nodes(k)), tol)
      j = locate(ys, model%x0(2, nodes(k)), tol)
      if (lat%node(i, j) /= 0 .or. (et == ETYPE_Q8 .and. mod(i, 2) == 0 .and. &
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
    if (et == ETYPE_Q8) lat%kind = TENSOR_SERENDIPITY
    lat%n = [n1, n2]
    lat%x1 = xs
    lat%x2 = ys
    select case (et)
    case (ETYPE_Q4)
      lat%what = 'Q4 grid'
    case (ETYPE_Q8)
      lat%what = 'Q8 grid'
    case default
      lat%what = 'Q9 grid'
    end select
    lat%what = lat%what//' of '//str(ne1)//' x '//str(ne2)//' elements'
  end subroutine grid_lattice

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

  ! ------------------------------------------------------------------ set-up

  !> Builds the solver for the lattices `lay` of the global consistent mass (ng rows,
  !! columns sorted, global node numbers) with keep(ng, 2) the solved dofs of each component.
  !! ierr = 0, or 1 with `reason` when the mass is not what the lattices promise.
  subroutine tensor_mass_setup(tm, lay, ng, row_ptr, col, val, keep, ierr, reason)
    type(tensor_mass_t), intent(out) :: tm
    type(tensor_layout_t), intent(in) :: lay
    integer, intent(in) :: ng, row_ptr(:), col(:)
    real(dp), intent(in) :: val(:)
    logical, intent(in) :: keep(:,:)
    integer, intent(out) :: ierr
    character(len=:), allocatable, intent(out) :: reason
    integer, allocatable :: blk(:), li(:), lj(:)
    integer :: ib, i, j, k, q, c, n1, n2, kd(2)
    real(dp) :: err
    ierr = 1
    reason = ''
    if (lay%nblocks == 0) then
      reason = lay%reason
      return
    end if
    ! where each node sits; the couplings must stay inside a block
    allocate(blk(ng), li(ng), lj(ng), source=0)
    do ib = 1, lay%nblocks
      do j = 1, lay%b(ib)%n(2)
        do i = 1, lay%b(ib)%n(1)
          k = lay%b(ib)%node(i, j)
          if (k == 0) cycle
          if (k > ng .or. blk(min(k, ng)) /= 0) then
            reason = 'a node belongs to two lattices'
            return
          end if
          blk(k) = ib
          li(k) = i
          lj(k) = j
        end do
      end do
    end do
    tm%nblocks = lay%nblocks
    allocate(tm%b(lay%nblocks))
    tm%outside = pack([(k, k = 1, ng)], blk == 0)
    do q = 1, size(tm%outside)
      if (keep(tm%outside(q), 1) .or. keep(tm%outside(q), 2)) then
        reason = 'a node with mass lies outside the lattices'
        return
      end if
    end do
    do ib = 1, lay%nblocks
      kd = 0
      do j = 1, lay%b(ib)%n(2)
        do i = 1, lay%b(ib)%n(1)
          k = lay%b(ib)%node(i, j)
          if (k == 0) cycle
          do q = row_ptr(k), row_ptr(k + 1) - 1
            if (blk(col(q)) /= ib) then
              reason = 'the mass couples two lattices'
              return
            end if
            kd(1) = max(kd(1), abs(li(col(q)) - i))
            kd(2) = max(kd(2), abs(lj(col(q)) - j))
          end do
        end do
      end do
      associate (b => tm%b(ib), l => lay%b(ib))
        b%kind = l%kind
        b%n = l%n
        b%node = l%node
        call find_runs(b)
        b%what = l%what
        n1 = l%n(1)
        n2 = l%n(2)
        b%ne = (l%n - 1)/2
        if (b%kind == TENSOR_DIRECT) then
          call fit_direct(l, kd, row_ptr, col, val, b%c(1)%m, ierr)
          if (ierr /= 0) then
            reason = 'the mass is not a Kronecker product on '//l%what
            return
          end if
          b%c(2)%m = b%c(1)%m
        else
          call serendipity_masses(l, ng, row_ptr, val, b%c(1)%m)
          b%c(2)%m = b%c(1)%m
        end if
        ! the lattice arrays in huge pages (streamed every step, read by columns)
        call alloc_stream(b%z, n1, n2, 2, 0.0_dp)
        allocate(b%xc(2, n1), b%lt(col_block, n1), source=0.0_dp)
        if (b%kind == TENSOR_SERENDIPITY) then
          call alloc_stream(b%tv, b%ne(1) + 1, b%ne(2), 0.0_dp)
          allocate(b%ring(n1, 2), b%zb(n1, col_block), b%jb(col_block))
          call alloc_stream(b%r, b%ne(1), b%ne(2), 2, 0.0_dp)
          call alloc_stream(b%t, b%ne(1), b%ne(2) + 1, 0.0_dp)
        end if
        do c = 1, 2
          call component_setup(b, c, keep(:, c), ierr, reason)
          if (ierr /= 0) then
            reason = reason//' on '//l%what
            return
          end if
        end do
        ! the plain columns again, now that the fixed points are known, and the columns
        ! of the point corrections
        call find_runs(b)
        allocate(b%defer(n2), source=.false.)
        do c = 1, 2
          do k = 1, b%c(c)%npts
            b%defer(b%c(c)%box(3, k):b%c(c)%box(4, k)) = .true.
          end do
        end do
      end associate
    end do
    ! the proof: M v solved back to v for two pseudo-random v on the solved dofs
    call self_check(tm, ng, row_ptr, col, val, keep, err)
    if (.not. err <= check_tol) then
      ierr = 1
      reason = 'the mass is not the tensor-product mass of the lattices (M v solved back '// &
          'with a relative error of '//str(err, 3)//')'
      return
    end if
    ierr = 0
  end subroutine tensor_mass_setup

  !> The 1D masses of a Kronecker block read off M: A1(i, k) = M((i, j0), (k, j0)),
  !! A2(j, l) = M((i0, j), (i0, l)) / M((i0, j0), (i0, j0)) at the middle lattice point.
  !! ierr = 1 when an entry is missing or the pivot is not positive.
  subroutine fit_direct(l, kd, row_ptr, col, val, m, ierr)
    type(lattice_t), intent(in) :: l
    integer, intent(in) :: kd(2), row_ptr(:), col(:)
    real(dp), intent(in) :: val(:)
    type(band_t), intent(out) :: m(2)
    integer, intent(out) :: ierr
    integer :: i0, j0, i, j, k
    real(dp) :: a0
    ierr = 1
    i0 = (l%n(1) + 1)/2
    j0 = (l%n(2) + 1)/2
    a0 = entry(l%node(i0, j0), l%node(i0, j0))
    if (.not. a0 > 0.0_dp) return
    call band_alloc(m(1), l%n(1), kd(1))
    call band_alloc(m(2), l%n(2), kd(2))
    do i = 1, l%n(1)
      do k = 0, min(kd(1), i - 1)
        m(1)%a(k, i) = entry(l%node(i, j0), l%node(i - k, j0))
      end do
    end do
    do j = 1, l%n(2)
      do k = 0, min(kd(2), j - 1)
        m(2)%a(k, j) = entry(l%node(i0, j), l%node(i0, j - k))/a0
      end do
    end do
    ierr = 0
  contains
    !> M(a, b) (0 when not stored), by bisection in the sorted row a.
    real(dp) function entry(a, b)
      integer, intent(in) :: a, b
      integer :: lo, hi, mid
      entry = 0.0_dp
      lo = row_ptr(a)
      hi = row_ptr(a + 1) - 1
      do while (lo <= hi)
        mid = (lo + hi)/2
        if (col(mid) == b) then
          entry = val(mid)
          return
        else if (col(mid) < b) then
          lo = mid + 1
        else
          hi = mid - 1
        end if
      end do
    end function entry
  end subroutine fit_direct

  !> The hierarchical 1D masses of a Q8 block: per element of length h the quadratic
  !! Lagrange mass h/30 [4 2 -1; 2 16 2; -1 2 4] in the basis (left hat, bubble, right hat),
  !! assembled along each direction; scaled so that their Kronecker product has the block's
  !! total mass (the sum of all entries of its rows of M: density x thickness x area).
  subroutine serendipity_masses(l, ng, row_ptr, val, m)
    type(lattice_t), intent(in) :: l
    integer, intent(in) :: ng, row_ptr(:)
    real(dp), intent(in) :: val(:)
    type(band_t), intent(out) :: m(2)
    real(dp), parameter :: lag(3, 3) = reshape([4.0_dp, 2.0_dp, -1.0_dp, 2.0_dp, 16.0_dp, &
        2.0_dp, -1.0_dp, 2.0_dp, 4.0_dp], [3, 3])/30.0_dp
    real(dp), parameter :: hmat(3, 3) = reshape([1.0_dp, 0.5_dp, 0.0_dp, 0.0_dp, 1.0_dp, &
        0.0_dp, 0.0_dp, 0.5_dp, 1.0_dp], [3, 3])
    real(dp) :: he(3, 3), total, s(2)
    integer :: d, e, a, b, i, j, k, n
    he = matmul(transpose(hmat), matmul(lag, hmat))
    do d = 1, 2
      n = l%n(d)
      call band_alloc(m(d), n, 2)
      do e = 1, (n - 1)/2
        do b = 1, 3
          do a = b, 3
            i = 2*e - 2 + a
            j = 2*e - 2 + b
            if (d == 1) then
              m(d)%a(i - j, i) = m(d)%a(i - j, i) + (l%x1(2*e + 1) - l%x1(2*e - 1))*he(a, b)
            else
              m(d)%a(i - j, i) = m(d)%a(i - j, i) + (l%x2(2*e + 1) - l%x2(2*e - 1))*he(a, b)
            end if
          end do
        end do
      end do
    end do
    ! the total mass of the block: all entries of its rows
    total = 0.0_dp
    do j = 1, l%n(2)
      do i = 1, l%n(1)
        k = l%node(i, j)
        if (k > 0 .and. k <= ng) total = total + sum(val(row_ptr(k):row_ptr(k + 1) - 1))
      end do
    end do
    s(1) = l%x1(l%n(1)) - l%x1(1)
    s(2) = l%x2(l%n(2)) - l%x2(1)
    m(1)%a = m(1)%a*(total/(s(1)*s(2)))
  end subroutine serendipity_masses

  !> One component of a block: the fixed lattice lines (whole lines of dofs not kept; for Q8
  !! vertex lines only), the isolated fixed points, the modified 1D matrices and their
  !! factors, and the unit responses of the points with their capacitance factor.
  subroutine component_setup(b, c, keep, ierr, reason)
    type(tblock_t), intent(inout) :: b
    integer, intent(in) :: c
    logical, intent(in) :: keep(:)
    integer, intent(out) :: ierr
    character(len=:), allocatable, intent(inout) :: reason
    integer :: i, j, k, l, n1, n2, np, step
    logical :: fixed_here
    associate (cp => b%c(c))
      n1 = b%n(1)
      n2 = b%n(2)
      step = 1
      if (b%kind == TENSOR_SERENDIPITY) step = 2
      allocate(cp%fix1(n1), cp%fix2(n2), source=.false.)
      do i = 1, n1, step
        cp%fix1(i) = .true.
        do j = 1, n2
          if (b%node(i, j) > 0) cp%fix1(i) = cp%fix1(i) .and. .not. keep(max(b%node(i, j), 1))
        end do
      end do
      do j = 1, n2, step
        cp%fix2(j) = .true.
        do i = 1, n1
          if (b%node(i, j) > 0) cp%fix2(j) = cp%fix2(j) .and. .not. keep(max(b%node(i, j), 1))
        end do
      end do
      cp%rows1 = pack([(i, i = 1, n1)], cp%fix1)
      ! the other fixed dofs: isolated points
      np = 0
      do j = 1, n2
        do i = 1, n1
          if (b%node(i, j) == 0) cycle
          fixed_here = .not. keep(b%node(i, j))
          if (fixed_here .and. .not. (cp%fix1(i) .or. cp%fix2(j))) np = np + 1
        end do
      end do
      if (np > max_points) then
        ierr = 1
        reason = str(np)//' fixed dofs of component '//str(c)//' are not on whole lattice '// &
            'lines (at most '//str(max_points)//' can be)'
        return
      end if
      cp%npts = np
      allocate(cp%pts(2, np), cp%box(4, np), cp%w(n1, n2, np), cp%h(np, np), cp%beta(np))
      np = 0
      do j = 1, n2
        do i = 1, n1
          if (b%node(i, j) == 0) cycle
          if (.not. keep(b%node(i, j)) .and. .not. (cp%fix1(i) .or. cp%fix2(j))) then
            np = np + 1
            cp%pts(:, np) = [i, j]
          end if
        end do
      end do
      call fix_lines(cp%m(1), cp%fix1)
      call fix_lines(cp%m(2), cp%fix2)
      do k = 1, 2
        call band_factor(cp%m(k), ierr)
        if (ierr /= 0) then
          reason = 'a 1D mass is not positive definite'
          return
        end if
        if (b%kind == TENSOR_SERENDIPITY) then
          call vertex_part(cp%m(k), cp%v(k))
          call band_factor(cp%v(k), ierr)
          if (ierr == 0) call condensed(cp%m(k), cp%q(k), ierr)
          if (ierr /= 0) then
            reason = 'a 1D vertex mass is not positive definite'
            return
          end if
        end if
      end do
      ! unit responses of the points (without the point correction) and the capacitance
      cp%w = 0.0_dp
      do k = 1, cp%npts
        call base_solve(b, c, c, unit=cp%pts(:, k))
        call nodal_lattice(b, c, cp%w(:, :, k))
        call response_box(cp%w(:, :, k), cp%box(:, k))
      end do
      do k = 1, cp%npts
        do l = 1, cp%npts
          cp%h(l, k) = cp%w(cp%pts(1, l), cp%pts(2, l), k)
        end do
      end do
      call small_cholesky(cp%npts, cp%h, ierr)
      if (ierr /= 0) then
        reason = 'the capacitance matrix of the fixed points is not positive definite'
        return
      end if
    end associate
    ierr = 0
  end subroutine component_setup

  !> The smallest lattice box i1:i2 x j1:j2 outside which |w| < 1e-18 max |w|: a point's
  !! correction beta w changes x there by less than the rounding of x, so it is applied in
  !! the box only (the response of a point decays exponentially with the distance).
  subroutine response_box(w, box)
    real(dp), intent(in) :: w(:,:)
    integer, intent(out) :: box(4)
    real(dp) :: cut
    integer :: i, j
    cut = 1.0e-18_dp*maxval(abs(w))
    box = [size(w, 1) + 1, 0, size(w, 2) + 1, 0]
    do j = 1, size(w, 2)
      do i = 1, size(w, 1)
        if (abs(w(i, j)) < cut) cycle
        box = [min(box(1), i), max(box(2), i), min(box(3), j), max(box(4), j)]
      end do
    end do
  end subroutine response_box

  !> Rows and columns of the fixed indices become identity rows.
  subroutine fix_lines(m, fix)
    type(band_t), intent(inout) :: m
    logical, intent(in) :: fix(:)
    integer :: i, k
    do i = 1, m%n
      if (.not. fix(i)) cycle
      m%a(:, i) = 0.0_dp
      m%a(0, i) = 1.0_dp
      do k = 1, min(m%kd, m%n - i)
        m%a(k, i + k) = 0.0_dp
      end do
    end do
  end subroutine fix_lines

  !> The vertex part of a hierarchical 1D mass (odd indices; tridiagonal).
  subroutine vertex_part(m, v)
    type(band_t), intent(in) :: m
    type(band_t), intent(out) :: v
    integer :: i
    call band_alloc(v, (m%n + 1)/2, 1)
    do i = 1, v%n
      v%a(0, i) = m%a(0, 2*i - 1)
      if (i > 1) v%a(1, i) = m%a(2, 2*i - 1)
    end do
  end subroutine vertex_part

  !> The condensed form of a hierarchical 1D mass m (type cond_t; fixed lines are identity
  !! rows, which leave their couplings 0); ierr /= 0 when the vertex Schur complement is not
  !! positive definite.
  subroutine condensed(m, q, ierr)
    type(band_t), intent(in) :: m
    type(cond_t), intent(out) :: q
    integer, intent(out) :: ierr
    integer :: e, v, ne
    ! entry A(i, j), i >= j, is m%a(i - j, i)
    ne = (m%n - 1)/2
    allocate(q%ab(ne), q%pl(ne), q%pr(ne), q%abb(ne), q%cl(ne), q%cr(ne))
    do e = 1, ne
      q%abb(e) = m%a(0, 2*e)
      q%cl(e) = m%a(1, 2*e)
      q%cr(e) = m%a(1, 2*e + 1)
      q%ab(e) = 1.0_dp/m%a(0, 2*e)
      q%pl(e) = m%a(1, 2*e)*q%ab(e)
      q%pr(e) = m%a(1, 2*e + 1)*q%ab(e)
    end do
    call band_alloc(q%sv, ne + 1, 1)
    do v = 1, ne + 1
      q%sv%a(0, v) = m%a(0, 2*v - 1)
      if (v > 1) then
        q%sv%a(0, v) = q%sv%a(0, v) - m%a(1, 2*v - 1)*q%pr(v - 1)
        q%sv%a(1, v) = m%a(2, 2*v - 1) - m%a(1, 2*v - 1)*q%pl(v - 1)
      end if
      if (v <= ne) q%sv%a(0, v) = q%sv%a(0, v) - m%a(1, 2*v)*q%pl(v)
    end do
    call band_factor(q%sv, ierr)
  end subroutine condensed

  !> b%kfirst(j): the first node of lattice column j when the column is plain: its nodes
  !! (every lattice point, or for Q8 the odd ones of an even column) numbered one after the
  !! other in lattice order, and no isolated fixed point of either component on it (once
  !! those are known); 0 otherwise (then the solve goes through b%node).
  subroutine find_runs(b)
    type(tblock_t), intent(inout) :: b
    integer :: i, j, step, c
    if (.not. allocated(b%kfirst)) allocate(b%kfirst(b%n(2)))
    do j = 1, b%n(2)
      step = 1
      if (b%kind == TENSOR_SERENDIPITY .and. mod(j, 2) == 0) step = 2
      b%kfirst(j) = b%node(1, j)
      do i = 1 + step, b%n(1), step
        if (b%node(i, j) /= b%node(1, j) + (i - 1)/step) b%kfirst(j) = 0
      end do
      if (b%node(1, j) <= 0) b%kfirst(j) = 0
      do c = 1, 2
        if (.not. allocated(b%c(c)%pts)) cycle
        if (any(b%c(c)%pts(2, 1:b%c(c)%npts) == j)) b%kfirst(j) = 0
      end do
    end do
  end subroutine find_runs

  subroutine band_alloc(m, n, kd)
    type(band_t), intent(out) :: m
    integer, intent(in) :: n, kd
    m%n = n
    m%kd = kd
    allocate(m%a(0:kd, n), m%l(0:kd, n), source=0.0_dp)
  end subroutine band_alloc

  !> Banded Cholesky factor A = L L^T; ierr = i when pivot i is not positive.
  subroutine band_factor(m, ierr)
    type(band_t), intent(inout) :: m
    integer, intent(out) :: ierr
    integer :: i, j, k, kd
    real(dp) :: s
    kd = m%kd
    m%l = 0.0_dp
    ierr = 0
    do i = 1, m%n
      do j = max(1, i - kd), i - 1
        s = m%a(i - j, i)
        do k = max(1, i - kd), j - 1
          s = s - m%l(i - k, i)*m%l(j - k, j)
        end do
        m%l(i - j, i) = s*m%l(0, j)
      end do
      s = m%a(0, i)
      do k = max(1, i - kd), i - 1
        s = s - m%l(i - k, i)**2
      end do
      if (.not. s > 0.0_dp) then
        ierr = i
        return
      end if
      m%l(0, i) = 1.0_dp/sqrt(s)
    end do
  end subroutine band_factor

  !> Cholesky factor of a small dense SPD matrix in place (lower triangle; diagonal holds
  !! the inverse of L(i, i)); ierr = 1 when it is not positive definite.
  subroutine small_cholesky(n, h, ierr)
    integer, intent(in) :: n
    real(dp), intent(inout) :: h(n, n)
    integer, intent(out) :: ierr
    integer :: i, j, k
    real(dp) :: s
    ierr = 0
    do i = 1, n
      do j = 1, i - 1
        s = h(i, j)
        do k = 1, j - 1
          s = s - h(i, k)*h(j, k)
        end do
        h(i, j) = s*h(j, j)
      end do
      s = h(i, i)
      do k = 1, i - 1
        s = s - h(i, k)**2
      end do
      if (.not. s > 0.0_dp) then
        ierr = 1
        return
      end if
      h(i, i) = 1.0_dp/sqrt(s)
    end do
  end subroutine small_cholesky

  !> The set-up check: for two pseudo-random v (zero on the dofs not solved), f = M v and
  !! x = solve(f); err = max |x - v| / max |v|.
  subroutine self_check(tm, ng, row_ptr, col, val, keep, err)
    type(tensor_mass_t), intent(inout) :: tm
    integer, intent(in) :: ng, row_ptr(:), col(:)
    real(dp), intent(in) :: val(:)
    logical, intent(in) :: keep(:,:)
    real(dp), intent(out) :: err
    real(dp), allocatable :: v(:,:), f(:,:), x(:,:)
    integer :: trial, i, c, q
    integer :: seed
    allocate(v(2, ng), f(2, ng), x(2, ng))
    err = 0.0_dp
    seed = 12345
    do trial = 1, 2
      do i = 1, ng
        do c = 1, 2
          seed = modulo(1103515245*seed + 12345, 2147483647)
          v(c, i) = merge(real(seed, dp)/2147483647.0_dp - 0.5_dp, 0.0_dp, keep(i, c))
        end do
      end do
      do i = 1, ng
        f(:, i) = 0.0_dp
        do q = row_ptr(i), row_ptr(i + 1) - 1
          f(:, i) = f(:, i) + val(q)*v(:, col(q))
        end do
      end do
      call tensor_mass_solve(tm, f, x)
      err = max(err, maxval(abs(x - v))/max(maxval(abs(v)), tiny(1.0_dp)))
    end do
  end subroutine self_check

  !> w <- the nodal values of component c of b%z at every lattice point that is a node
  !! (0 elsewhere): the unit responses of the fixed points, the change of basis of `store`.
  subroutine nodal_lattice(b, c, w)
    type(tblock_t), intent(in) :: b
    integer, intent(in) :: c
    real(dp), intent(out) :: w(:,:)
    integer :: i, j
    w = 0.0_dp
    do j = 1, b%n(2)
      do i = 1, b%n(1)
        if (b%node(i, j) > 0) w(i, j) = nodal_value(b, c, i, j)
      end do
    end do
  end subroutine nodal_lattice

  !> Node numbers of the blocks replaced by map(node) (e.g. the positions of the nodes in a
  !! gathered vector), so that tensor_mass_solve reads and writes in that numbering.
  subroutine tensor_mass_renumber(tm, map)
    type(tensor_mass_t), intent(inout) :: tm
    integer, intent(in) :: map(:)
    integer :: ib, i, j
    do ib = 1, tm%nblocks
      do j = 1, tm%b(ib)%n(2)
        do i = 1, tm%b(ib)%n(1)
          if (tm%b(ib)%node(i, j) > 0) tm%b(ib)%node(i, j) = map(tm%b(ib)%node(i, j))
        end do
      end do
      call find_runs(tm%b(ib))
    end do
    if (size(tm%outside) > 0) tm%outside = map(tm%outside)
  end subroutine tensor_mass_renumber

  !> One line per block for the log: what it is, its lattice and its fixed lines and points.
  function tensor_mass_describe(tm) result(s)
    type(tensor_mass_t), intent(in) :: tm
    character(len=:), allocatable :: s
    integer :: ib
    s = ''
    do ib = 1, tm%nblocks
      associate (b => tm%b(ib))
        if (ib > 1) s = s//'; '
        s = s//b%what//' ('//str(b%n(1))//' x '//str(b%n(2))//' lattice, '// &
            merge('Kronecker  ', 'serendipity', b%kind == TENSOR_DIRECT)
        s = trim(s)//', fixed lines '//str(count(b%c(1)%fix1) + count(b%c(1)%fix2))//' + '// &
            str(count(b%c(2)%fix1) + count(b%c(2)%fix2))//', fixed points '// &
            str(b%c(1)%npts)//' + '//str(b%c(2)%npts)//')'
      end associate
    end do
  end function tensor_mass_describe

  ! ------------------------------------------------------------------ the solve

  !> x = M^-1 f on the solved dofs of every block (0 on fixed dofs and outside the blocks);
  !! f and x are (2, ng) in the node numbering of the blocks (a flat gathered vector of
  !! pairs will do). Allocates nothing.
  !!
  !! Both components go through each pass together. Passes over the lattice: Kronecker
  !! blocks 3 (load with the forward elimination along direction 2, the direction-1 solves
  !! of col_block columns at a time inside it; back substitution; store with the point
  !! correction), Q8 blocks 6 (load in the hierarchical basis; forward; back with the
  !! B x B values picked out; forward from g - E mu; back; store with the change to nodal
  !! values and the point correction).
  subroutine tensor_mass_solve(tm, f, x)
    type(tensor_mass_t), intent(inout) :: tm
    real(dp), intent(in) :: f(2, *)
    real(dp), intent(inout) :: x(2, *)
    integer :: ib, k
    do k = 1, size(tm%outside)
      x(:, tm%outside(k)) = 0.0_dp
    end do
    do ib = 1, tm%nblocks
      call solve_block(tm%b(ib), f, x=x)
    end do
  end subroutine tensor_mass_solve

  !> The velocity and displacement updates of a step with the solve folded in: with
  !! kf = K u (2, *), v <- v - dt M^-1 kf and u_next <- u + dt v on every node, the same
  !! bits as a = tensor_mass_solve(-kf), v = v + dt a, u_next = u + dt v (the solve is
  !! linear and rounding is symmetric in the sign). Saves the passes over a. Allocates
  !! nothing.
  subroutine tensor_mass_step(tm, kf, dt, u, v, u_next)
    type(tensor_mass_t), intent(inout) :: tm
    real(dp), intent(in) :: kf(2, *), dt, u(2, *)
    real(dp), intent(inout) :: v(2, *), u_next(2, *)
    integer :: ib, k, l
    do k = 1, size(tm%outside)
      l = tm%outside(k)
      u_next(:, l) = u(:, l) + dt*v(:, l)
    end do
    do ib = 1, tm%nblocks
      call solve_block(tm%b(ib), kf, dt=dt, u=u, v=v, u_next=u_next)
    end do
  end subroutine tensor_mass_step

  !> The solve of one block for the loads f, stored into x or (with dt) folded into the
  !! step (`emit_column`); a Q8 block stores each column as its last pass finishes it.
  subroutine solve_block(b, f, x, dt, u, v, u_next)
    type(tblock_t), intent(inout) :: b
    real(dp), intent(in) :: f(2, *)
    real(dp), intent(inout), optional :: x(2, *)
    real(dp), intent(in), optional :: dt, u(2, *)
    real(dp), intent(inout), optional :: v(2, *), u_next(2, *)
    if (b%kind == TENSOR_DIRECT) then
      call base_solve(b, 1, 2, f)
      call store(b, x, dt, u, v, u_next)
    else
      call q8_front(b, 1, 2, f)
      call q8_backward_store(b, x, dt, u, v, u_next)
    end if
  end subroutine solve_block

  !> b%z(:, :, c1:c2) <- the solve of those components without the point correction, for
  !! the nodal loads f (both components: c1 = 1, c2 = 2) or for a unit load at lattice point
  !! `unit`: the Kronecker inverse, or for Q8 the capacitance solve in the hierarchical basis
  !! (module header), which leaves hierarchical coefficients in z (`store` and `nodal_value`
  !! change them to nodal values).
  subroutine base_solve(b, c1, c2, f, unit)
    type(tblock_t), intent(inout) :: b
    integer, intent(in) :: c1, c2
    real(dp), intent(in), optional :: f(2, *)
    integer, intent(in), optional :: unit(2)
    if (b%kind == TENSOR_DIRECT) then
      call forward(b, c1, c2, f, unit)
      call backward(b, c1, c2)
      return
    end if
    call q8_front(b, c1, c2, f, unit)
    call q8_backward(b, c1, c2)
  end subroutine base_solve

  !> A Q8 solve up to its last back substitution: mu = (G1^-1 (x) G2^-1) (S g)_BB, then
  !! S (g - E mu) eliminated forward along direction 2 (g = (H1^T (x) H2^T) f, gathered
  !! again in the second forward pass).
  subroutine q8_front(b, c1, c2, f, unit)
    type(tblock_t), intent(inout) :: b
    integer, intent(in) :: c1, c2
    real(dp), intent(in), optional :: f(2, *)
    integer, intent(in), optional :: unit(2)
    integer :: c
    call q8_forward(b, c1, c2, .false., f, unit)
    call q8_back_pick(b, c1, c2)
    do c = c1, c2
      call schur_dim1(b%c(c)%q(1), b%c(c)%v(1), b%r(:, :, c), b%tv, b%lt)
      call schur_dim2(b%c(c)%q(2), b%c(c)%v(2), b%r(:, :, c), b%t)
    end do
    call q8_forward(b, c1, c2, .true., f, unit)
  end subroutine q8_front

  !> Column j of a unit load at lattice point `unit` (the responses of the fixed points).
  pure subroutine unit_column(j, col, unit)
    integer, intent(in) :: j, unit(2)
    real(dp), intent(out) :: col(:)
    col = 0.0_dp
    if (unit(2) == j) col(unit(1)) = 1.0_dp
  end subroutine unit_column

  !> Columns j of the loads of both components in one sweep over f: f at the nodes, 0 at
  !! Q8 centres, on fixed lines and at fixed points; for a Q8 block changed to the
  !! hierarchical basis along direction 1 (g(i) = f(i) + (f(i-1) + f(i+1))/2 at the odd
  !! points, the fixed rows 0 again). A plain column (b%kfirst(j) > 0: its nodes one range,
  !! no fixed point on it) is read as that range of f, the change of basis on the way.
  subroutine gather_pair(b, j, col1, col2, f)
    type(tblock_t), intent(in) :: b
    integer, intent(in) :: j
    real(dp), intent(out) :: col1(:), col2(:)
    real(dp), intent(in) :: f(2, *)
    integer :: i, k, k0, n1
    n1 = b%n(1)
    k0 = b%kfirst(j)
    if (k0 > 0 .and. b%kind == TENSOR_DIRECT) then
      call load_run(n1, f(1, k0), col1, col2)
    else if (k0 > 0 .and. mod(j, 2) == 1) then
      call load_run_q8(n1, f(1, k0), col1, col2)
    else if (k0 > 0) then
      call load_run_q8_centres(n1, f(1, k0), col1, col2)
    else
      do i = 1, n1
        k = b%node(i, j)
        col1(i) = 0.0_dp
        col2(i) = 0.0_dp
        if (k > 0) then
          col1(i) = f(1, k)
          col2(i) = f(2, k)
        end if
      end do
      call zero_fixed(b%c(1), j, col1)
      call zero_fixed(b%c(2), j, col2)
      if (b%kind == TENSOR_SERENDIPITY) then
        call hier_column(col1)
        call hier_column(col2)
      end if
    end if
    call zero_lines(b%c(1), j, col1)
    call zero_lines(b%c(2), j, col2)
  end subroutine gather_pair

  !> The loads of a lattice column from the pairs fl(1:2n) of its n nodes, numbered one after
  !! the other: the two components apart.
  pure subroutine load_run(n, fl, col1, col2)
    integer, intent(in) :: n
    real(dp), intent(in) :: fl(2*n)
    real(dp), intent(out) :: col1(n), col2(n)
    integer :: i
    do i = 1, n
      col1(i) = fl(2*i - 1)
      col2(i) = fl(2*i)
    end do
  end subroutine load_run

  !> The same for an odd column of a Q8 block (a node at every lattice point), changed to
  !! the hierarchical basis along the column (as `hier_column`).
  pure subroutine load_run_q8(n, fl, col1, col2)
    integer, intent(in) :: n
    real(dp), intent(in) :: fl(2*n)
    real(dp), intent(out) :: col1(n), col2(n)
    integer :: i
    col1(1) = fl(1) + 0.5_dp*fl(3)
    col2(1) = fl(2) + 0.5_dp*fl(4)
    ! points 2v (a midside node) and 2v + 1 (a vertex) of each pair
    do i = 2, n - 3, 2
      col1(i) = fl(2*i - 1)
      col2(i) = fl(2*i)
      col1(i + 1) = fl(2*i + 1) + 0.5_dp*(fl(2*i - 1) + fl(2*i + 3))
      col2(i + 1) = fl(2*i + 2) + 0.5_dp*(fl(2*i) + fl(2*i + 4))
    end do
    col1(n - 1) = fl(2*n - 3)
    col2(n - 1) = fl(2*n - 2)
    col1(n) = fl(2*n - 1) + 0.5_dp*fl(2*n - 3)
    col2(n) = fl(2*n) + 0.5_dp*fl(2*n - 2)
  end subroutine load_run_q8

  !> The same for an even column of a Q8 block: nodes at the odd lattice points only, the
  !! pairs fl(1:n+1) of its (n + 1)/2 nodes; 0 at the element centres (so the change of
  !! basis adds nothing).
  pure subroutine load_run_q8_centres(n, fl, col1, col2)
    integer, intent(in) :: n
    real(dp), intent(in) :: fl(n + 1)
    real(dp), intent(out) :: col1(n), col2(n)
    integer :: i
    do i = 1, n
      col1(i) = merge(fl(i), 0.0_dp, mod(i, 2) == 1)
      col2(i) = merge(fl(i + 1), 0.0_dp, mod(i, 2) == 1)
    end do
  end subroutine load_run_q8_centres

  !> A column of loads changed to the hierarchical basis along it: g(i) = f(i) +
  !! (f(i-1) + f(i+1))/2 at the odd (vertex) points.
  pure subroutine hier_column(g)
    real(dp), intent(inout) :: g(:)
    integer :: i, n
    n = size(g)
    g(1) = g(1) + 0.5_dp*g(2)
    do i = 3, n - 2, 2
      g(i) = g(i) + 0.5_dp*(g(i - 1) + g(i + 1))
    end do
    g(n) = g(n) + 0.5_dp*g(n - 1)
  end subroutine hier_column

  !> The fixed lines of column j of one component's loads set to 0 (a fixed column, the
  !! fixed rows).
  pure subroutine zero_lines(cp, j, col)
    type(comp_t), intent(in) :: cp
    integer, intent(in) :: j
    real(dp), intent(inout) :: col(:)
    integer :: k
    if (cp%fix2(j)) then
      col = 0.0_dp
      return
    end if
    do k = 1, size(cp%rows1)
      col(cp%rows1(k)) = 0.0_dp
    end do
  end subroutine zero_lines

  !> The fixed dofs of column j of one component's loads set to 0: its fixed lines and its
  !! isolated fixed points.
  pure subroutine zero_fixed(cp, j, col)
    type(comp_t), intent(in) :: cp
    integer, intent(in) :: j
    real(dp), intent(inout) :: col(:)
    integer :: p
    call zero_lines(cp, j, col)
    do p = 1, cp%npts
      if (cp%pts(2, p) == j) col(cp%pts(1, p)) = 0.0_dp
    end do
  end subroutine zero_fixed

  !> Forward elimination of the Kronecker solve of a direct block, col_block columns at a
  !! time: the columns are gathered (or set to the unit load), solved along direction 1
  !! together (`lines_solve`: one recurrence whose lanes are the columns), and eliminated
  !! along direction 2 one after the other, while the block is still in the cache.
  subroutine forward(b, c1, c2, f, unit)
    type(tblock_t), intent(inout) :: b
    integer, intent(in) :: c1, c2
    real(dp), intent(in), optional :: f(2, *)
    integer, intent(in), optional :: unit(2)
    integer :: j0, j1, j, k, n2, c
    real(dp) :: l0, l1, l2
    n2 = b%n(2)
    associate (z => b%z)
      do j0 = 1, n2, col_block
        j1 = min(j0 + col_block - 1, n2)
        do j = j0, j1
          if (present(unit)) then
            do c = c1, c2
              call unit_column(j, z(:, j, c), unit)
            end do
          else
            call gather_pair(b, j, z(:, j, 1), z(:, j, 2), f)
          end if
        end do
        do c = c1, c2
          call lines_solve(b%c(c)%m(1), z(:, j0:j1, c), b%lt)
          associate (m2 => b%c(c)%m(2))
            do j = j0, j1
              l0 = m2%l(0, j)
              if (m2%kd == 2 .and. j > 2) then
                l1 = m2%l(1, j)
                l2 = m2%l(2, j)
                z(:, j, c) = ((z(:, j, c) - l2*z(:, j - 2, c)) - l1*z(:, j - 1, c))*l0
              else
                do k = min(m2%kd, j - 1), 1, -1
                  z(:, j, c) = z(:, j, c) - m2%l(k, j)*z(:, j - k, c)
                end do
                z(:, j, c) = z(:, j, c)*l0
              end if
            end do
          end associate
        end do
      end do
    end associate
  end subroutine forward

  !> x(i, :) <- A^-1 applied along i (A of order m%n) to every column of x (at most
  !! col_block) at once: one recurrence whose lanes are the columns. For half bandwidths 1
  !! and 2 the last values stay in registers (a chain through memory would cost a
  !! store-to-load round trip per step), and the forward sweep writes its results to the
  !! work lt(col_block, m%n) with the lanes side by side, which the backward sweep reads:
  !! one strided gather and one strided store per value instead of two each; wider bands
  !! take the plain loops.
  subroutine lines_solve(m, x, lt)
    type(band_t), intent(in) :: m
    real(dp), intent(inout) :: x(:,:), lt(:,:)
    real(dp) :: y(col_block), y1(col_block), y2(col_block)
    integer :: n, i, k, nb
    n = m%n
    nb = size(x, 2)
    if (m%kd == 2 .and. n >= 2) then
      y2(1:nb) = x(1, :)*m%l(0, 1)
      lt(1:nb, 1) = y2(1:nb)
      y1(1:nb) = (x(2, :) - m%l(1, 2)*y2(1:nb))*m%l(0, 2)
      lt(1:nb, 2) = y1(1:nb)
      do i = 3, n
        y(1:nb) = ((x(i, :) - m%l(2, i)*y2(1:nb)) - m%l(1, i)*y1(1:nb))*m%l(0, i)
        lt(1:nb, i) = y(1:nb)
        y2(1:nb) = y1(1:nb)
        y1(1:nb) = y(1:nb)
      end do
      y2(1:nb) = lt(1:nb, n)*m%l(0, n)
      x(n, :) = y2(1:nb)
      y1(1:nb) = (lt(1:nb, n - 1) - m%l(1, n)*y2(1:nb))*m%l(0, n - 1)
      x(n - 1, :) = y1(1:nb)
      do i = n - 2, 1, -1
        y(1:nb) = ((lt(1:nb, i) - m%l(2, i + 2)*y2(1:nb)) - m%l(1, i + 1)*y1(1:nb))*m%l(0, i)
        x(i, :) = y(1:nb)
        y2(1:nb) = y1(1:nb)
        y1(1:nb) = y(1:nb)
      end do
    else if (m%kd == 1) then
      y1(1:nb) = x(1, :)*m%l(0, 1)
      lt(1:nb, 1) = y1(1:nb)
      do i = 2, n
        y1(1:nb) = (x(i, :) - m%l(1, i)*y1(1:nb))*m%l(0, i)
        lt(1:nb, i) = y1(1:nb)
      end do
      y1(1:nb) = lt(1:nb, n)*m%l(0, n)
      x(n, :) = y1(1:nb)
      do i = n - 1, 1, -1
        y1(1:nb) = (lt(1:nb, i) - m%l(1, i + 1)*y1(1:nb))*m%l(0, i)
        x(i, :) = y1(1:nb)
      end do
    else
      do i = 1, n
        do k = min(m%kd, i - 1), 1, -1
          x(i, :) = x(i, :) - m%l(k, i)*x(i - k, :)
        end do
        x(i, :) = x(i, :)*m%l(0, i)
      end do
      do i = n, 1, -1
        do k = min(m%kd, n - i), 1, -1
          x(i, :) = x(i, :) - m%l(k, i + k)*x(i + k, :)
        end do
        x(i, :) = x(i, :)*m%l(0, i)
      end do
    end if
  end subroutine lines_solve

  !> Back substitution along direction 2 (direct blocks).
  subroutine backward(b, c1, c2)
    type(tblock_t), intent(inout) :: b
    integer, intent(in) :: c1, c2
    integer :: j, k, n2, c
    real(dp) :: l0, l1, l2
    n2 = b%n(2)
    associate (z => b%z)
      do j = n2, 1, -1
        do c = c1, c2
          associate (m2 => b%c(c)%m(2))
            l0 = m2%l(0, j)
            if (m2%kd == 2 .and. j < n2 - 1) then
              l1 = m2%l(1, j + 1)
              l2 = m2%l(2, j + 2)
              z(:, j, c) = ((z(:, j, c) - l2*z(:, j + 2, c)) - l1*z(:, j + 1, c))*l0
            else
              do k = min(m2%kd, n2 - j), 1, -1
                z(:, j, c) = z(:, j, c) - m2%l(k, j + k)*z(:, j + k, c)
              end do
              z(:, j, c) = z(:, j, c)*l0
            end if
          end associate
        end do
      end do
    end associate
  end subroutine backward

  ! ------------------------------------------------------------------ Q8 blocks
  ! The Kronecker solves of a Q8 block work on the hierarchical 1D masses in their condensed
  ! form (type cond_t): A^-1 y = condense, a tridiagonal solve on the vertex lines, expand.
  ! Along direction 2 the lines are lattice columns (whole vectors), along direction 1 the
  ! lattice rows (vertex rows solved col_block columns at a time by `lines_solve`).

  !> The forward pass of a Q8 Kronecker solve, col_block columns at a time (col_block is
  !! even, so a block ends on an even column and each of its odd columns has both
  !! neighbours loaded): the nodal loads (or the unit load) of each column changed to the
  !! hierarchical basis along direction 1 (`gather_pair`); the odd (vertex) columns along
  !! direction 2 (g = (H1^T (x) H2^T) f, the fixed lines set to 0); then the vertex columns
  !! condensed and eliminated along direction 2. The even columns keep their values. First
  !! solve: each vertex column in one pass (`q8_first_vertex`). Second (`second`): g - E mu,
  !! solved along direction 1 block by block before direction 2 (`q8_vertex_forward`);
  !! b%ring(:, c) carries the last even column of a block's loads to the next block.
  subroutine q8_forward(b, c1, c2, second, f, unit)
    type(tblock_t), intent(inout) :: b
    integer, intent(in) :: c1, c2
    logical, intent(in) :: second
    real(dp), intent(in), optional :: f(2, *)
    integer, intent(in), optional :: unit(2)
    integer :: j0, j1, j, n2, c
    n2 = b%n(2)
    associate (z => b%z)
      do j0 = 1, n2, col_block
        j1 = min(j0 + col_block - 1, n2)
        do j = j0, j1
          call load_column(b, j, c1, c2, z(:, j, 1), z(:, j, 2), f, unit)
        end do
        do c = c1, c2
          if (.not. second) then
            do j = j0, j1, 2
              call q8_first_vertex(b, c, j, z(:, :, c))
            end do
            cycle
          end if
          do j = j0, j1, 2
            if (j == j0 .and. j > 1) then
              call vertex_hier(b, c, j, z(:, :, c), b%ring(:, c))
            else if (j > 1) then
              call vertex_hier(b, c, j, z(:, :, c), z(:, j - 1, c))
            else
              call vertex_hier(b, c, j, z(:, :, c), z(:, j, c))
            end if
          end do
          if (j1 < n2) b%ring(:, c) = z(:, j1, c)
          do j = j0 + 1, j1, 2
            call subtract_centres(b%ne(1), b%r(:, j/2, c), z(:, j, c))
          end do
          call q8_lines(b%c(c)%q(1), z(:, j0:j1, c), b%lt)
          call q8_vertex_forward(b%c(c)%q(2), z(:, :, c), j0, j1)
        end do
      end do
    end associate
  end subroutine q8_forward

  !> The loads of column j, changed to the hierarchical basis along it, into col1, col2 (the
  !! components c1..c2 of a unit load at lattice point `unit`, or both components of f).
  subroutine load_column(b, j, c1, c2, col1, col2, f, unit)
    type(tblock_t), intent(in) :: b
    integer, intent(in) :: j, c1, c2
    real(dp), intent(out) :: col1(:), col2(:)
    real(dp), intent(in), optional :: f(2, *)
    integer, intent(in), optional :: unit(2)
    if (.not. present(unit)) then
      call gather_pair(b, j, col1, col2, f)
      return
    end if
    if (c1 == 1) then
      call unit_column(j, col1, unit)
      call hier_column(col1)
      call zero_lines(b%c(1), j, col1)
    end if
    if (c2 == 2) then
      call unit_column(j, col2, unit)
      call hier_column(col2)
      call zero_lines(b%c(2), j, col2)
    end if
  end subroutine load_column

  !> Vertex column j of component c changed to the hierarchical basis along direction 2:
  !! z(:, j) + (gl + z(:, j + 1))/2 with gl the loads of the even column before it (both
  !! neighbours changed along direction 1 only), 0 on a fixed column.
  subroutine vertex_hier(b, c, j, z, gl)
    type(tblock_t), intent(in) :: b
    integer, intent(in) :: c, j
    real(dp), intent(inout) :: z(:,:)
    real(dp), intent(in) :: gl(:)
    integer :: n1, n2
    n1 = b%n(1)
    n2 = b%n(2)
    if (b%c(c)%fix2(j)) then
      z(:, j) = 0.0_dp
    else if (j > 1 .and. j < n2) then
      call add_halves(n1, z(:, j), gl, z(:, j + 1))
    else if (j > 1) then
      z(:, j) = z(:, j) + 0.5_dp*gl
    else
      z(:, j) = z(:, j) + 0.5_dp*z(:, j + 1)
    end if
  end subroutine vertex_hier

  !> y <- (y + a/2) + b/2.
  pure subroutine add_halves(n, y, a, b)
    integer, intent(in) :: n
    real(dp), intent(inout) :: y(n)
    real(dp), intent(in) :: a(n), b(n)
    integer :: i
    do i = 1, n
      y(i) = (y(i) + 0.5_dp*a(i)) + 0.5_dp*b(i)
    end do
  end subroutine add_halves

  !> The loads at the element centres of an even column less E mu: y(2i) <- y(2i) - mu(i).
  pure subroutine subtract_centres(ne, mu, y)
    integer, intent(in) :: ne
    real(dp), intent(in) :: mu(ne)
    real(dp), intent(inout) :: y(2*ne + 1)
    integer :: i
    do i = 1, ne
      y(2*i) = y(2*i) - mu(i)
    end do
  end subroutine subtract_centres

  !> Vertex column j of component c in the first forward pass, in one pass over it: changed
  !! to the hierarchical basis along direction 2 (`vertex_hier`), condensed and eliminated
  !! (the operations of `q8_vertex_forward`). Its neighbours hold their loads (changed along
  !! direction 1 only), as this pass leaves the even columns.
  subroutine q8_first_vertex(b, c, j, z)
    type(tblock_t), intent(in) :: b
    integer, intent(in) :: c, j
    real(dp), intent(inout) :: z(:,:)
    integer :: v, n2
    n2 = b%n(2)
    v = (j + 1)/2
    associate (q => b%c(c)%q(2))
      if (b%c(c)%fix2(j)) then
        z(:, j) = 0.0_dp
      else if (j > 1 .and. j < n2) then
        call first_vertex_run(b%n(1), q%pr(v - 1), q%pl(v), q%sv%l(1, v), q%sv%l(0, v), &
            z(:, j - 1), z(:, j + 1), z(:, j - 2), z(:, j))
      else if (j == 1) then
        z(:, j) = z(:, j) + 0.5_dp*z(:, j + 1)
        z(:, j) = (z(:, j) - q%pl(v)*z(:, j + 1))*q%sv%l(0, v)
      else
        z(:, j) = z(:, j) + 0.5_dp*z(:, j - 1)
        z(:, j) = ((z(:, j) - q%pr(v - 1)*z(:, j - 1)) - q%sv%l(1, v)*z(:, j - 2))*q%sv%l(0, v)
      end if
    end associate
  end subroutine q8_first_vertex

  !> An interior vertex column of the first forward pass: y <- ((((y + gl/2) + gr/2) -
  !! pr gl) - pl gr - l1 y2) l0 (y2: the vertex column before, eliminated).
  pure subroutine first_vertex_run(n, pr, pl, l1, l0, gl, gr, y2, y)
    integer, intent(in) :: n
    real(dp), intent(in) :: pr, pl, l1, l0, gl(n), gr(n), y2(n)
    real(dp), intent(inout) :: y(n)
    integer :: i
    do i = 1, n
      y(i) = ((((y(i) + 0.5_dp*gl(i)) + 0.5_dp*gr(i)) - pr*gl(i)) - pl*gr(i) - l1*y2(i))*l0
    end do
  end subroutine first_vertex_run

  !> Direction 2, forward, on the vertex columns j0, j0 + 2, .., j1 of z (j0 odd): condensed
  !! (y_v -= pr(v-1) z_(bubble v-1) + pl(v) z_(bubble v)) and eliminated with the factor of
  !! the vertex Schur complement.
  subroutine q8_vertex_forward(q, z, j0, j1)
    type(cond_t), intent(in) :: q
    real(dp), intent(inout) :: z(:,:)
    integer, intent(in) :: j0, j1
    integer :: j, v, n2
    real(dp) :: pr, pl, l1, l0
    n2 = size(z, 2)
    do j = j0, j1, 2
      v = (j + 1)/2
      l0 = q%sv%l(0, v)
      if (j > 1 .and. j < n2) then
        pr = q%pr(v - 1)
        pl = q%pl(v)
        l1 = q%sv%l(1, v)
        z(:, j) = (((z(:, j) - pr*z(:, j - 1)) - pl*z(:, j + 1)) - l1*z(:, j - 2))*l0
      else if (j == 1) then
        z(:, j) = (z(:, j) - q%pl(v)*z(:, j + 1))*l0
      else
        z(:, j) = ((z(:, j) - q%pr(v - 1)*z(:, j - 1)) - q%sv%l(1, v)*z(:, j - 2))*l0
      end if
    end do
  end subroutine q8_vertex_forward

  !> The condensed solve along direction 1 of every column of x (at most col_block): each
  !! column condensed on its vertex rows, the vertex rows solved together (`lines_solve`
  !! with the tridiagonal factor), the bubble rows expanded.
  subroutine q8_lines(q, x, lt)
    type(cond_t), intent(in) :: q
    real(dp), intent(inout) :: x(:,:), lt(:,:)
    integer :: j
    do j = 1, size(x, 2)
      call q8_condense(q, x(:, j))
    end do
    call lines_solve(q%sv, x(1::2, :), lt)
    do j = 1, size(x, 2)
      call q8_expand(q, x(:, j))
    end do
  end subroutine q8_lines

  !> y(2v-1) <- y(2v-1) - pr(v-1) y(2v-2) - pl(v) y(2v): the load of the vertex Schur
  !! complement.
  pure subroutine q8_condense(q, y)
    type(cond_t), intent(in) :: q
    real(dp), intent(inout) :: y(:)
    call condense_line(q%sv%n, q%pl, q%pr, y)
  end subroutine q8_condense

  !> q8_condense on a line of nv vertices (explicit shapes: a loop the compiler vectorises;
  !! each bubble value is written back unchanged next to its vertex, so that the stores
  !! are contiguous).
  pure subroutine condense_line(nv, pl, pr, y)
    integer, intent(in) :: nv
    real(dp), intent(in) :: pl(nv - 1), pr(nv - 1)
    real(dp), intent(inout) :: y(2*nv - 1)
    real(dp) :: b
    integer :: v
    y(1) = y(1) - pl(1)*y(2)
    do v = 2, nv - 1
      b = y(2*v - 2)
      y(2*v - 1) = (y(2*v - 1) - pr(v - 1)*b) - pl(v)*y(2*v)
      y(2*v - 2) = b
    end do
    y(2*nv - 1) = y(2*nv - 1) - pr(nv - 1)*y(2*nv - 2)
  end subroutine condense_line

  !> x(2e) <- ab(e) y(2e) - pl(e) x(2e-1) - pr(e) x(2e+1): the bubbles from the solved
  !! vertices.
  pure subroutine q8_expand(q, x)
    type(cond_t), intent(in) :: q
    real(dp), intent(inout) :: x(:)
    call expand_line(size(q%ab), q%ab, q%pl, q%pr, x)
  end subroutine q8_expand

  !> q8_expand on a line of ne bubbles (explicit shapes; the vertex values written back
  !! unchanged next to their bubbles, as in condense_line).
  pure subroutine expand_line(ne, ab, pl, pr, x)
    integer, intent(in) :: ne
    real(dp), intent(in) :: ab(ne), pl(ne), pr(ne)
    real(dp), intent(inout) :: x(2*ne + 1)
    real(dp) :: a
    integer :: e
    do e = 1, ne
      a = x(2*e - 1)
      x(2*e) = (ab(e)*x(2*e) - pl(e)*a) - pr(e)*x(2*e + 1)
      x(2*e - 1) = a
    end do
  end subroutine expand_line

  !> The backward pass of the first Q8 solve, which only needs its B x B values: the vertex
  !! columns back-substituted along direction 2 into a ring of two columns (z is not
  !! written), each even column expanded from its neighbours into zb; every col_block of
  !! them are solved along direction 1 together and their bubble rows go to r.
  subroutine q8_back_pick(b, c1, c2)
    type(tblock_t), intent(inout) :: b
    integer, intent(in) :: c1, c2
    integer :: j, c, nb, v, n2, s, q, i
    n2 = b%n(2)
    do c = c1, c2
      associate (q2 => b%c(c)%q(2), z => b%z(:, :, c), ring => b%ring)
        nb = 0
        do j = n2, 1, -2
          v = (j + 1)/2
          s = mod(v, 2) + 1
          if (j < n2) then
            nb = nb + 1
            call back_pick_run(b%n(1), q2%sv%l(1, v + 1), q2%sv%l(0, v), q2%ab(v), q2%pl(v), &
                q2%pr(v), z(:, j), z(:, j + 1), ring(:, 3 - s), ring(:, s), b%zb(:, nb))
            b%jb(nb) = j + 1
            if (nb == col_block .or. j == 1) then
              ! direction 1 on these columns, bubble rows into r
              do q = 1, nb
                call q8_condense(b%c(c)%q(1), b%zb(:, q))
              end do
              call lines_solve(b%c(c)%q(1)%sv, b%zb(1::2, 1:nb), b%lt)
              associate (q1 => b%c(c)%q(1))
                do q = 1, nb
                  do i = 1, b%ne(1)
                    b%r(i, b%jb(q)/2, c) = (q1%ab(i)*b%zb(2*i, q) - q1%pl(i)*b%zb(2*i - 1, q)) &
                        - q1%pr(i)*b%zb(2*i + 1, q)
                  end do
                end do
              end associate
              nb = 0
            end if
          else
            ring(:, s) = z(:, j)*q2%sv%l(0, v)
          end if
        end do
      end associate
    end do
  end subroutine q8_back_pick

  !> One step of `q8_back_pick` in one pass: the vertex column x = (y - l1 xr) l0 from its
  !! eliminated loads y and the vertex column after it (xr), and the even column between
  !! them expanded, zb = (ab g - pl x) - pr xr.
  pure subroutine back_pick_run(n, l1, l0, ab, pl, pr, y, g, xr, x, zb)
    integer, intent(in) :: n
    real(dp), intent(in) :: l1, l0, ab, pl, pr, y(n), g(n), xr(n)
    real(dp), intent(out) :: x(n), zb(n)
    integer :: i
    do i = 1, n
      x(i) = (y(i) - l1*xr(i))*l0
      zb(i) = (ab*g(i) - pl*x(i)) - pr*xr(i)
    end do
  end subroutine back_pick_run

  !> The backward pass of the second Q8 solve: the vertex columns back-substituted along
  !! direction 2, each even column expanded from its neighbours at its nodes (odd rows; the
  !! centres are not needed).
  subroutine q8_backward(b, c1, c2)
    type(tblock_t), intent(inout) :: b
    integer, intent(in) :: c1, c2
    integer :: j, c
    do c = c1, c2
      call q8_back_column(b, c, b%n(2))
    end do
    do j = b%n(2) - 2, 1, -2
      do c = c1, c2
        call q8_back_column(b, c, j)
      end do
    end do
  end subroutine q8_backward

  !> Vertex column j of component c back-substituted along direction 2 and the even column
  !! after it expanded at its nodes (odd rows), in b%z.
  subroutine q8_back_column(b, c, j)
    type(tblock_t), intent(inout) :: b
    integer, intent(in) :: c, j
    integer :: v
    v = (j + 1)/2
    associate (q2 => b%c(c)%q(2), z => b%z(:, :, c))
      if (j == b%n(2)) then
        z(:, j) = z(:, j)*q2%sv%l(0, v)
        return
      end if
      call back_run(b%n(1), q2%sv%l(1, v + 1), q2%sv%l(0, v), q2%ab(v), q2%pl(v), q2%pr(v), &
          z(:, j + 2), z(:, j), z(:, j + 1))
    end associate
  end subroutine q8_back_column

  !> One step of the Q8 back substitution in one pass: the vertex column x <- (x - l1 xr) l0
  !! (xr: the vertex column after it), and at the odd points of the even column between
  !! them g <- (ab g - pl x) - pr xr.
  pure subroutine back_run(n, l1, l0, ab, pl, pr, xr, x, g)
    integer, intent(in) :: n
    real(dp), intent(in) :: l1, l0, ab, pl, pr, xr(n)
    real(dp), intent(inout) :: x(n), g(n)
    integer :: i
    do i = 1, n - 1, 2
      x(i) = (x(i) - l1*xr(i))*l0
      x(i + 1) = (x(i + 1) - l1*xr(i + 1))*l0
      g(i) = (ab*g(i) - pl*x(i)) - pr*xr(i)
    end do
    x(n) = (x(n) - l1*xr(n))*l0
    g(n) = (ab*g(n) - pl*x(n)) - pr*xr(n)
  end subroutine back_run

  !> `q8_backward` with the store (`emit_column`) of each column as soon as it is final,
  !! while it is in the cache; the columns in the boxes of the point corrections (b%defer)
  !! go out at the end, once the corrections are known.
  subroutine q8_backward_store(b, x, dt, u, v, u_next)
    type(tblock_t), intent(inout) :: b
    real(dp), intent(inout), optional :: x(2, *)
    real(dp), intent(in), optional :: dt, u(2, *)
    real(dp), intent(inout), optional :: v(2, *), u_next(2, *)
    integer :: j, c, n2
    n2 = b%n(2)
    do c = 1, 2
      call q8_back_column(b, c, n2)
    end do
    if (.not. b%defer(n2)) call emit_column(b, n2, x, dt, u, v, u_next)
    do j = n2 - 2, 1, -2
      do c = 1, 2
        call q8_back_column(b, c, j)
      end do
      if (.not. b%defer(j + 1)) call emit_column(b, j + 1, x, dt, u, v, u_next)
      if (.not. b%defer(j)) call emit_column(b, j, x, dt, u, v, u_next)
    end do
    call point_betas(b)
    do j = 1, n2
      if (b%defer(j)) call emit_column(b, j, x, dt, u, v, u_next)
    end do
  end subroutine q8_backward_store

  !> x(:, node) for every node of the block from the solve in b%z, or (with dt) the updates
  !! of the fused step: `emit_column` for every column, once the point corrections are known.
  subroutine store(b, x, dt, u, v, u_next)
    type(tblock_t), intent(inout) :: b
    real(dp), intent(inout), optional :: x(2, *)
    real(dp), intent(in), optional :: dt, u(2, *)
    real(dp), intent(inout), optional :: v(2, *), u_next(2, *)
    integer :: j
    call point_betas(b)
    do j = 1, b%n(2)
      call emit_column(b, j, x, dt, u, v, u_next)
    end do
  end subroutine store

  !> The coefficients beta = H^-1 u(pts) of the point corrections, per component, from the
  !! solve in b%z.
  subroutine point_betas(b)
    type(tblock_t), intent(inout) :: b
    integer :: c, p
    do c = 1, 2
      associate (cp => b%c(c))
        do p = 1, cp%npts
          cp%beta(p) = nodal_value(b, c, cp%pts(1, p), cp%pts(2, p))
        end do
        if (cp%npts > 0) call small_solve(cp%npts, cp%h, cp%beta)
      end associate
    end do
  end subroutine point_betas

  !> Column j of the solve in b%z out to its nodes: the nodal values (for Q8 the change
  !! from the hierarchical basis, u(2e) = z(2e) + (z(2e-1) + z(2e+1))/2 along each
  !! direction; no node reads a B x B value), minus the point correction sum_p beta_p w_p
  !! (b%c(:)%beta known when the column lies in a box, b%defer), into x(:, node); or with
  !! `dt` (and u, v, u_next) taken as the solve for -f and folded into the step:
  !! v <- v - dt x, u_next <- u + dt v, node by node (the same operations, so the same bits,
  !! as a = x(-f), v = v + dt a, u_next = u + dt v). Through b%xc, which holds the column's
  !! nodes in lattice order (for an even Q8 column its odd points); a plain column
  !! (b%kfirst) is written as one range of nodes.
  subroutine emit_column(b, j, x, dt, u, v, u_next)
    type(tblock_t), intent(inout) :: b
    integer, intent(in) :: j
    real(dp), intent(inout), optional :: x(2, *)
    real(dp), intent(in), optional :: dt, u(2, *)
    real(dp), intent(inout), optional :: v(2, *), u_next(2, *)
    integer :: i, p, n1, c, k, m, nm, k0
    logical :: centres
    n1 = b%n(1)
    centres = b%kind == TENSOR_SERENDIPITY .and. mod(j, 2) == 0
    nm = n1
    if (b%kind == TENSOR_DIRECT) then
      call nodal_direct(n1, b%z(:, j, 1), b%z(:, j, 2), b%xc)
    else if (.not. centres) then
      call nodal_q8(n1, b%z(:, j, 1), b%z(:, j, 2), b%xc)
    else
      nm = (n1 + 1)/2
      call nodal_q8_centres(n1, b%z(:, j - 1:j + 1, 1), b%z(:, j - 1:j + 1, 2), b%xc)
    end if
    ! the point corrections, in the boxes of their responses (cp%w is 0 at Q8 centres)
    do c = 1, 2
      associate (cp => b%c(c))
        do p = 1, cp%npts
          if (j < cp%box(3, p) .or. j > cp%box(4, p)) cycle
          do i = cp%box(1, p), cp%box(2, p)
            if (b%node(i, j) == 0) cycle
            m = merge((i + 1)/2, i, centres)
            b%xc(c, m) = b%xc(c, m) - cp%beta(p)*cp%w(i, j, p)
          end do
        end do
        do p = 1, cp%npts
          if (cp%pts(2, p) == j) b%xc(c, merge((cp%pts(1, p) + 1)/2, cp%pts(1, p), &
              centres)) = 0.0_dp
        end do
      end associate
    end do
    k0 = b%kfirst(j)
    if (k0 > 0 .and. present(dt)) then
      call step_run(2*nm, b%xc, dt, u(1, k0), v(1, k0), u_next(1, k0))
    else if (k0 > 0) then
      x(:, k0:k0 + nm - 1) = b%xc(:, 1:nm)
    else
      do m = 1, nm
        k = b%node(merge(2*m - 1, m, centres), j)
        if (k == 0) cycle
        if (present(dt)) then
          v(1, k) = v(1, k) - dt*b%xc(1, m)
          v(2, k) = v(2, k) - dt*b%xc(2, m)
          u_next(1, k) = u(1, k) + dt*v(1, k)
          u_next(2, k) = u(2, k) + dt*v(2, k)
        else
          x(1, k) = b%xc(1, m)
          x(2, k) = b%xc(2, m)
        end if
      end do
    end if
  end subroutine emit_column

  !> The nodal values of a lattice column of a direct block, both components side by side:
  !! xc(:, i) = (z1(i), z2(i)).
  pure subroutine nodal_direct(n, z1, z2, xc)
    integer, intent(in) :: n
    real(dp), intent(in) :: z1(n), z2(n)
    real(dp), intent(out) :: xc(2, n)
    integer :: i
    do i = 1, n
      xc(1, i) = z1(i)
      xc(2, i) = z2(i)
    end do
  end subroutine nodal_direct

  !> The same for an odd column of a Q8 block: the hierarchical coefficients changed to nodal
  !! values along the column, u(2e) = z(2e) + (z(2e-1) + z(2e+1))/2.
  pure subroutine nodal_q8(n, z1, z2, xc)
    integer, intent(in) :: n
    real(dp), intent(in) :: z1(n), z2(n)
    real(dp), intent(out) :: xc(2, n)
    integer :: i
    xc(1, 1) = z1(1)
    xc(2, 1) = z2(1)
    do i = 2, n - 1, 2
      xc(1, i) = z1(i) + 0.5_dp*(z1(i - 1) + z1(i + 1))
      xc(2, i) = z2(i) + 0.5_dp*(z2(i - 1) + z2(i + 1))
      xc(1, i + 1) = z1(i + 1)
      xc(2, i + 1) = z2(i + 1)
    end do
  end subroutine nodal_q8

  !> The same for an even column of a Q8 block (z1, z2: the column with its neighbours):
  !! nodes at its odd points, u = z + (z_left + z_right)/2, into xc(:, 1:(n + 1)/2).
  pure subroutine nodal_q8_centres(n, z1, z2, xc)
    integer, intent(in) :: n
    real(dp), intent(in) :: z1(n, 3), z2(n, 3)
    real(dp), intent(out) :: xc(2, *)
    integer :: m
    do m = 1, (n + 1)/2
      xc(1, m) = z1(2*m - 1, 2) + 0.5_dp*(z1(2*m - 1, 1) + z1(2*m - 1, 3))
      xc(2, m) = z2(2*m - 1, 2) + 0.5_dp*(z2(2*m - 1, 1) + z2(2*m - 1, 3))
    end do
  end subroutine nodal_q8_centres

  !> The updates of the fused step on a range of n values (the pairs of consecutive nodes):
  !! v <- v - dt x, u_next <- u + dt v.
  pure subroutine step_run(n, x, dt, u, v, u_next)
    integer, intent(in) :: n
    real(dp), intent(in) :: x(n), dt, u(n)
    real(dp), intent(inout) :: v(n), u_next(n)
    integer :: q
    do q = 1, n
      v(q) = v(q) - dt*x(q)
      u_next(q) = u(q) + dt*v(q)
    end do
  end subroutine step_run

  !> The nodal value of component c of b%z at lattice point (i, j) (a node).
  pure real(dp) function nodal_value(b, c, i, j) result(u)
    type(tblock_t), intent(in) :: b
    integer, intent(in) :: c, i, j
    u = b%z(i, j, c)
    if (b%kind == TENSOR_DIRECT) return
    if (mod(i, 2) == 0) then
      u = u + 0.5_dp*(b%z(i - 1, j, c) + b%z(i + 1, j, c))
    else if (mod(j, 2) == 0) then
      u = u + 0.5_dp*(b%z(i, j - 1, c) + b%z(i, j + 1, c))
    end if
  end function nodal_value

  !> r(:, j) <- (A_BB - A_BV A_VV^-1 A_VB) r(:, j) for every column j: the inverse of
  !! (A^-1)_BB along direction 1 (q: the entries of A, v: the factor of A_VV). w(ne + 1, :)
  !! takes A_VB r column by column, the tridiagonal solves run col_block columns at a time
  !! (`lines_solve`, work lt), and r is updated column by column.
  subroutine schur_dim1(q, v, r, w, lt)
    type(cond_t), intent(in) :: q
    type(band_t), intent(in) :: v
    real(dp), intent(inout) :: r(:,:), w(:,:), lt(:,:)
    integer :: ne, j0, j1, j
    ne = size(r, 1)
    do j0 = 1, size(r, 2), col_block
      j1 = min(j0 + col_block - 1, size(r, 2))
      ! w = A_VB r: vertex k touches bubbles k - 1 (its right vertex) and k (its left)
      do j = j0, j1
        call vertex_load(ne, q%cl, q%cr, r(:, j), w(:, j))
      end do
      call lines_solve(v, w(:, j0:j1), lt)
      do j = j0, j1
        call schur_update(ne, q%abb, q%cl, q%cr, w(:, j), r(:, j))
      end do
    end do
  end subroutine schur_dim1

  !> w = A_VB r along one line of ne bubbles: vertex k touches bubbles k - 1 (its right
  !! vertex, cr) and k (its left, cl).
  pure subroutine vertex_load(ne, cl, cr, r, w)
    integer, intent(in) :: ne
    real(dp), intent(in) :: cl(ne), cr(ne), r(ne)
    real(dp), intent(out) :: w(ne + 1)
    integer :: k
    w(1) = cl(1)*r(1)
    do k = 2, ne
      w(k) = cr(k - 1)*r(k - 1) + cl(k)*r(k)
    end do
    w(ne + 1) = cr(ne)*r(ne)
  end subroutine vertex_load

  !> r <- A_BB r - A_BV w along one line (w = A_VV^-1 A_VB r).
  pure subroutine schur_update(ne, abb, cl, cr, w, r)
    integer, intent(in) :: ne
    real(dp), intent(in) :: abb(ne), cl(ne), cr(ne), w(ne + 1)
    real(dp), intent(inout) :: r(ne)
    integer :: e
    do e = 1, ne
      r(e) = abb(e)*r(e) - cl(e)*w(e) - cr(e)*w(e + 1)
    end do
  end subroutine schur_update

  !> The same along direction 2, for all rows at once (w holds ne(2) + 1 vertex columns):
  !! A_VB r with the forward elimination in one sweep, the back substitution with the update
  !! of r in the other.
  subroutine schur_dim2(q, v, r, w)
    type(cond_t), intent(in) :: q
    type(band_t), intent(in) :: v
    real(dp), intent(inout) :: r(:,:)
    real(dp), intent(inout) :: w(:,:)
    integer :: ne, k
    ne = size(r, 2)
    w(:, 1) = (q%cl(1)*r(:, 1))*v%l(0, 1)
    do k = 2, ne
      w(:, k) = ((q%cr(k - 1)*r(:, k - 1) + q%cl(k)*r(:, k)) - v%l(1, k)*w(:, k - 1))*v%l(0, k)
    end do
    w(:, ne + 1) = (q%cr(ne)*r(:, ne) - v%l(1, ne + 1)*w(:, ne))*v%l(0, ne + 1)
    w(:, ne + 1) = w(:, ne + 1)*v%l(0, ne + 1)
    do k = ne, 1, -1
      w(:, k) = (w(:, k) - v%l(1, k + 1)*w(:, k + 1))*v%l(0, k)
      r(:, k) = q%abb(k)*r(:, k) - q%cl(k)*w(:, k) - q%cr(k)*w(:, k + 1)
    end do
  end subroutine schur_dim2

  !> y <- H^-1 y with the factor of small_cholesky.
  pure subroutine small_solve(n, h, y)
    integer, intent(in) :: n
    real(dp), intent(in) :: h(n, n)
    real(dp), intent(inout) :: y(n)
    integer :: i, k
    do i = 1, n
      do k = 1, i - 1
        y(i) = y(i) - h(i, k)*y(k)
      end do
      y(i) = y(i)*h(i, i)
    end do
    do i = n, 1, -1
      do k = i + 1, n
        y(i) = y(i) - h(k, i)*y(k)
      end do
      y(i) = y(i)*h(i, i)
    end do
  end subroutine small_solve
end module ictus_solver_tensor_mass
