!> Sparse matrices of the explicit solver.
!!
!! The stiffness is stored in block CSR with 2x2 node blocks in 2D, 3x3 in 3D (`bsr_t`): it
!! moves the fewest bytes per product, and the product is the memory-bound kernel of every
!! step. The consistent mass, the same for every displacement component, is a scalar CSR
!! matrix (`csr_t`) on the same node graph. Both are assembled once from element matrices.
module ictus_solver_sparse
  use ictus_core_kinds, only: dp, i8
  use ictus_core_memory, only: alloc_stream, available_memory
  use, intrinsic :: iso_c_binding, only: c_int, c_double
  implicit none
  private
  public :: graph_t, bsr_t, csr_t, graph_from_elements, bsr_init, csr_init, bsr_add_element, &
      csr_add_element, bsr_matvec, csr_matvec, csr_diagonal, csr_row_sums, find_col, &
      graph_copy, csr_copy, fused_lumped_step, fused_lumped_rows, bsr_upper_t, bsr_upper_init, &
      bsr_matvec_ordered, bsr_upper_matvec, bsr3_matvec, bsr_product, fused_lumped_rows3

  !> Node adjacency graph in CSR form (every node is its own neighbour). Rows exist for the
  !! first `n` (owned) nodes; columns are local node indices 1..ncol, sorted in each row by
  !! `key` (the global node index), so that sums over a row run in the same order whatever
  !! the partition.
  type :: graph_t
    integer :: n = 0
    integer :: ncol = 0
    integer, allocatable :: row_ptr(:)
    integer, allocatable :: col(:)
    integer, allocatable :: key(:)
  end type graph_t

  !> Block CSR matrix with nb x nb node blocks (2 in 2D, 3 in 3D), val(nb, nb, nnz_blocks).
  type :: bsr_t
    type(graph_t) :: g
    real(dp), allocatable :: val(:,:,:)
  end type bsr_t

  !> The blocks on and above the diagonal of a symmetric `bsr_t` whose rows are all on this
  !! rank, numbered in global order (`bsr_upper_init`): the storage of `bsr_upper_matvec`.
  !! Each row starts with its diagonal block; n = 0 when the matrix does not qualify, or
  !! (`short_of_memory`) when the storage would take more than half the memory available.
  type :: bsr_upper_t
    integer :: n = 0
    logical :: short_of_memory = .false.
    integer, allocatable :: row_ptr(:), col(:)
    real(dp), allocatable :: val(:,:,:)
  end type bsr_upper_t

  !> Scalar CSR matrix, val(nnz).
  type :: csr_t
    type(graph_t) :: g
    real(dp), allocatable :: val(:)
  end type csr_t

  !> The row loops of bsr_kernel.c (1-based row_ptr and col, as here): y = A x on n rows.
  abstract interface
    subroutine c_row_loop(n, row_ptr, col, val, x, y) bind(c)
      import :: c_int, c_double
      integer(c_int), value :: n
      integer(c_int), intent(in) :: row_ptr(*), col(*)
      real(c_double), intent(in) :: val(*), x(*)
      real(c_double), intent(inout) :: y(*)
    end subroutine c_row_loop
  end interface
  procedure(c_row_loop), bind(c, name='ictus_bsr_matvec') :: c_bsr_matvec
  procedure(c_row_loop), bind(c, name='ictus_bsr_matvec_ordered') :: c_bsr_matvec_ordered
  procedure(c_row_loop), bind(c, name='ictus_bsr_symv') :: c_bsr_symv
  procedure(c_row_loop), bind(c, name='ictus_bsr3_matvec') :: c_bsr3_matvec

contains

  !> Builds the node graph of a mesh: nodes i and j are neighbours when an element holds both.
  !! conn(nen_max, nel) with nen(e) valid entries per element, in local indices 1..ncol; rows
  !! are made for nodes 1..nrows only; key(ncol) orders the columns (global indices).
  subroutine graph_from_elements(nrows, ncol, nel, nen_max, nen, conn, key, g)
    integer, intent(in) :: nrows, ncol, nel, nen_max
    integer, intent(in) :: nen(nel), conn(nen_max, nel), key(ncol)
    type(graph_t), intent(out) :: g
    integer, allocatable :: node_ptr(:), node_el(:), mark(:), cnt(:)
    integer :: e, a, b, i, k, j, pos
    ! node -> elements map for the row nodes
    allocate(cnt(ncol + 1), source=0)
    do e = 1, nel
      do a = 1, nen(e)
        cnt(conn(a, e)) = cnt(conn(a, e)) + 1
      end do
    end do
    allocate(node_ptr(ncol + 1))
    node_ptr(1) = 1
    do i = 1, ncol
      node_ptr(i + 1) = node_ptr(i) + cnt(i)
    end do
    allocate(node_el(node_ptr(ncol + 1) - 1))
    cnt = 0
    do e = 1, nel
      do a = 1, nen(e)
        i = conn(a, e)
        node_el(node_ptr(i) + cnt(i)) = e
        cnt(i) = cnt(i) + 1
      end do
    end do
    ! count distinct neighbours, then fill
    allocate(mark(ncol), source=0)
    g%n = nrows
    g%ncol = ncol
    g%key = key
    allocate(g%row_ptr(nrows + 1))
    g%row_ptr(1) = 1
    do i = 1, nrows
      k = 0
      do j = node_ptr(i), node_ptr(i + 1) - 1
        e = node_el(j)
        do b = 1, nen(e)
          if (mark(conn(b, e)) /= i) then
            mark(conn(b, e)) = i
            k = k + 1
          end if
        end do
      end do
      if (k == 0) k = 1
      g%row_ptr(i + 1) = g%row_ptr(i) + k
    end do
    call alloc_stream(g%col, g%row_ptr(nrows + 1) - 1, 0)
    mark = 0
    do i = 1, nrows
      pos = g%row_ptr(i)
      if (node_ptr(i + 1) == node_ptr(i)) then
        ! a node without elements keeps its diagonal entry only
        g%col(pos) = i
        cycle
      end if
      do j = node_ptr(i), node_ptr(i + 1) - 1
        e = node_el(j)
        do b = 1, nen(e)
          if (mark(conn(b, e)) /= i) then
            mark(conn(b, e)) = i
            g%col(pos) = conn(b, e)
            pos = pos + 1
          end if
        end do
      end do
      call sort_by_key(g%col(g%row_ptr(i):g%row_ptr(i + 1) - 1), key)
    end do
  end subroutine graph_from_elements

  !> Insertion sort of local indices by their key (rows are short).
  pure subroutine sort_by_key(v, key)
    integer, intent(inout) :: v(:)
    integer, intent(in) :: key(:)
    integer :: i, j, x
    do i = 2, size(v)
      x = v(i)
      j = i - 1
      do while (j >= 1)
        if (key(v(j)) <= key(x)) exit
        v(j + 1) = v(j)
        j = j - 1
      end do
      v(j + 1) = x
    end do
  end subroutine sort_by_key

  !> Position of column `j` in row `i` (0 if absent), by bisection on the keys.
  pure integer function find_col(g, i, j) result(pos)
    type(graph_t), intent(in) :: g
    integer, intent(in) :: i, j
    integer :: lo, hi, mid, kj
    lo = g%row_ptr(i)
    hi = g%row_ptr(i + 1) - 1
    kj = g%key(j)
    pos = 0
    do while (lo <= hi)
      mid = (lo + hi)/2
      if (g%key(g%col(mid)) == kj) then
        pos = mid
        return
      else if (g%key(g%col(mid)) < kj) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
  end function find_col

  !> dst = src, with the column array (streamed by every product) in huge pages.
  subroutine graph_copy(dst, src)
    type(graph_t), intent(out) :: dst
    type(graph_t), intent(in) :: src
    dst%n = src%n
    dst%ncol = src%ncol
    dst%row_ptr = src%row_ptr
    dst%key = src%key
    call alloc_stream(dst%col, size(src%col), 0)
    dst%col(:) = src%col
  end subroutine graph_copy

  !> dst = src for a scalar matrix (graph and values in huge pages, see graph_copy).
  subroutine csr_copy(dst, src)
    type(csr_t), intent(out) :: dst
    type(csr_t), intent(in) :: src
    call graph_copy(dst%g, src%g)
    call alloc_stream(dst%val, size(src%val), 0.0_dp)
    dst%val(:) = src%val
  end subroutine csr_copy

  !> Zero block matrix on graph `g` with nb x nb blocks (default 2).
  subroutine bsr_init(a, g, nb)
    type(bsr_t), intent(out) :: a
    type(graph_t), intent(in) :: g
    integer, intent(in), optional :: nb
    integer :: m
    m = 2
    if (present(nb)) m = nb
    call graph_copy(a%g, g)
    call alloc_stream(a%val, m, m, size(g%col), 0.0_dp)
  end subroutine bsr_init

  !> Zero scalar matrix on graph `g`.
  subroutine csr_init(a, g)
    type(csr_t), intent(out) :: a
    type(graph_t), intent(in) :: g
    call graph_copy(a%g, g)
    call alloc_stream(a%val, size(g%col), 0.0_dp)
  end subroutine csr_init

  !> Adds an element stiffness ke(nb*nen, nb*nen) (dofs x1, y1[, z1], x2, ...) on nodes
  !! `nodes` (local indices); only the rows of nodes that have rows (owned nodes) are added.
  subroutine bsr_add_element(a, nen, nodes, ke)
    type(bsr_t), intent(inout) :: a
    integer, intent(in) :: nen
    integer, intent(in) :: nodes(nen)
    real(dp), intent(in) :: ke(:,:)
    integer :: p, q, pos, nb
    nb = size(a%val, 1)
    do p = 1, nen
      if (nodes(p) > a%g%n) cycle
      do q = 1, nen
        pos = find_col(a%g, nodes(p), nodes(q))
        a%val(:, :, pos) = a%val(:, :, pos) + ke(nb*(p - 1) + 1:nb*p, nb*(q - 1) + 1:nb*q)
      end do
    end do
  end subroutine bsr_add_element

  !> Adds a scalar element matrix me(nen, nen) on nodes `nodes`.
  subroutine csr_add_element(a, nen, nodes, me)
    type(csr_t), intent(inout) :: a
    integer, intent(in) :: nen
    integer, intent(in) :: nodes(nen)
    real(dp), intent(in) :: me(nen, nen)
    integer :: p, q, pos
    do p = 1, nen
      if (nodes(p) > a%g%n) cycle
      do q = 1, nen
        pos = find_col(a%g, nodes(p), nodes(q))
        a%val(pos) = a%val(pos) + me(p, q)
      end do
    end do
  end subroutine csr_add_element

  !> y = A x for the block matrix on its n rows; x(2, *) holds owned and ghost values.
  !! Each block's two products are added first; the blocks of a row go alternately into two
  !! partial sums (odd and even positions), added at the end. The two chains of dependent
  !! additions run in parallel (measured: doc/performance-history.md §3.1); the order is a fixed
  !! function of the row, whose columns are sorted by global index, so the bits do not
  !! depend on the partition. `fused_lumped_step` sums in the same order. The row loop is
  !! `ictus_bsr_matvec` (bsr_kernel.c): the same operations, plus a software prefetch of the
  !! block stream, which Fortran cannot express (it keeps the stream in flight beyond the
  !! caches; see doc/performance.md §3.1).
  subroutine bsr_matvec(n, row_ptr, col, val, x, y)
    integer, intent(in) :: n
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(2, 2, *), x(2, *)
    real(dp), intent(inout) :: y(2, *)
    call c_bsr_matvec(n, row_ptr, col, val, x, y)
  end subroutine bsr_matvec

  !> y = A x for a matrix of 3x3 blocks (3D) on its n rows; x(3, *) holds owned and ghost
  !! values. The order of bsr_matvec with three components: each block's three products in
  !! column order, the blocks alternately into two partial sums (`ictus_bsr3_matvec`,
  !! bsr_kernel.c).
  subroutine bsr3_matvec(n, row_ptr, col, val, x, y)
    integer, intent(in) :: n
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(3, 3, *), x(3, *)
    real(dp), intent(inout) :: y(3, *)
    call c_bsr3_matvec(n, row_ptr, col, val, x, y)
  end subroutine bsr3_matvec

  !> y = A x on the n rows of `a` by the block size's product (bsr_matvec for 2 x 2 blocks,
  !! bsr3_matvec for 3 x 3); x and y hold nb components per node, node after node.
  subroutine bsr_product(a, n, x, y)
    type(bsr_t), intent(in) :: a
    integer, intent(in) :: n
    real(dp), intent(in) :: x(*)
    real(dp), intent(inout) :: y(*)
    if (size(a%val, 1) == 3) then
      call bsr3_matvec(n, a%g%row_ptr, a%g%col, a%val, x, y)
    else
      call bsr_matvec(n, a%g%row_ptr, a%g%col, a%val, x, y)
    end if
  end subroutine bsr_product

  !> y = A x summed in column order: each row one chain over its blocks in the order of their
  !! columns (global indices), y_i = ((0 + t_1) + t_2) + ..., with t_k = A_ik(:, 1) x_k1 +
  !! A_ik(:, 2) x_k2 (`ictus_bsr_matvec_ordered`, bsr_kernel.c). The product of the
  !! consistent-mass step on any partition: `bsr_upper_matvec` gives the same bits from half
  !! the storage where one rank holds all rows. Fixed order, so the bits do not depend on the
  !! partition.
  subroutine bsr_matvec_ordered(n, row_ptr, col, val, x, y)
    integer, intent(in) :: n
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(2, 2, *), x(2, *)
    real(dp), intent(inout) :: y(2, *)
    call c_bsr_matvec_ordered(n, row_ptr, col, val, x, y)
  end subroutine bsr_matvec_ordered

  !> The upper storage of `a` (its diagonal and the blocks to its right) for
  !! `bsr_upper_matvec`, when `a` qualifies: no ghost columns (one rank holds all rows), the
  !! local numbering in global order (key increasing), a diagonal block in every row that has
  !! blocks, and A symmetric bit for bit (A_ji = A_ij^T, as `assemble_operators` builds K).
  !! Otherwise up%n = 0 and nothing is kept (callers take `bsr_matvec_ordered`, the same
  !! bits). About half the memory of `a`; not kept either when that is more than half the
  !! memory available (`available_memory`; up%short_of_memory).
  subroutine bsr_upper_init(a, up)
    type(bsr_t), intent(in) :: a
    type(bsr_upper_t), intent(out) :: up
    integer :: i, k, nb, n, j, kt
    integer(i8) :: avail
    n = a%g%n
    if (n == 0 .or. a%g%ncol /= n) return
    do i = 2, n
      if (a%g%key(i) <= a%g%key(i - 1)) return
    end do
    nb = 0
    do i = 1, n
      do k = a%g%row_ptr(i), a%g%row_ptr(i + 1) - 1
        j = a%g%col(k)
        if (j < i) then
          ! the mirror block A_ji must be the transpose, bit for bit
          kt = find_col(a%g, j, i)
          if (kt == 0) return
          if (any(a%val(:, :, k) /= transpose(a%val(:, :, kt)))) return
        else
          nb = nb + 1
        end if
      end do
      if (a%g%row_ptr(i + 1) > a%g%row_ptr(i)) then
        if (a%g%col(a%g%row_ptr(i)) > i) return
      end if
    end do
    avail = available_memory()
    if (avail >= 0 .and. 2_i8*(36_i8*nb + 4_i8*(n + 1)) > avail) then
      up%short_of_memory = .true.
      return
    end if
    allocate(up%row_ptr(n + 1), up%col(nb))
    call alloc_stream(up%val, 2, 2, nb, 0.0_dp)
    nb = 0
    up%row_ptr(1) = 1
    do i = 1, n
      do k = a%g%row_ptr(i), a%g%row_ptr(i + 1) - 1
        if (a%g%col(k) < i) cycle
        nb = nb + 1
        up%col(nb) = a%g%col(k)
        up%val(:, :, nb) = a%val(:, :, k)
      end do
      up%row_ptr(i + 1) = nb + 1
      ! the diagonal first (columns are sorted; a row with blocks holds its own node)
      if (up%row_ptr(i + 1) > up%row_ptr(i)) then
        if (up%col(up%row_ptr(i)) /= i) then
          deallocate(up%row_ptr, up%col, up%val)
          return
        end if
      end if
    end do
    up%n = n
  end subroutine bsr_upper_init

  !> y = A x from the upper storage (`bsr_upper_init`, up%n > 0): the bits of
  !! `bsr_matvec_ordered` on the full rows, reading about half the bytes
  !! (`ictus_bsr_symv`, bsr_kernel.c: the terms of the blocks left of the diagonal are added
  !! to y_j from row i < j, in the order of i).
  subroutine bsr_upper_matvec(up, x, y)
    type(bsr_upper_t), intent(in) :: up
    real(dp), intent(in) :: x(2, *)
    real(dp), intent(inout) :: y(2, *)
    call c_bsr_symv(up%n, up%row_ptr, up%col, up%val, x, y)
  end subroutine bsr_upper_matvec

  !> The undamped lumped-mass predictor and the displacement update in one pass over memory:
  !! for each owned node i, f_i = -(K u)_i, a_i = f_i/m_i, v_i = v_i + dt a_i,
  !! u_next_i = u_i + dt v_i. The rows go in chunks of `chunk`: K u of a chunk lands in a
  !! small buffer that stays in the L1 cache, then the chunk's updates run. The same
  !! operations in the same order as the separate passes, so the bits are the same; u_next
  !! must not alias u (rows read neighbours' u).
  subroutine fused_lumped_step(n, row_ptr, col, val, inv_m, dt, u, v, u_next)
    integer, intent(in) :: n
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(2, 2, *), inv_m(2, n), dt
    real(dp), intent(in) :: u(2, *)
    real(dp), intent(inout) :: v(2, *)
    real(dp), intent(inout) :: u_next(2, *)
    call fused_lumped_rows(1, n, row_ptr, col, val, inv_m, dt, u, v, u_next)
  end subroutine fused_lumped_step

  !> The fused lumped step on rows lo .. lo + len - 1 only (`fused_lumped_step` for all rows;
  !! the sweeps of ictus_solver_sweep run it on runs of rows): v += dt (-K x_in)/m,
  !! x_out = x_in + dt v, in chunks whose K x_in stays in the L1 cache. With `alpha`, `m_pos`
  !! and `pw` the damped step of `damped_update` instead.
  subroutine fused_lumped_rows(lo, len, row_ptr, col, val, inv_m, dt, x_in, v, x_out, alpha, &
      m_pos, pw)
    integer, intent(in) :: lo, len
    integer, intent(in) :: row_ptr(*), col(*)
    real(dp), intent(in) :: val(2, 2, *), inv_m(2, *), dt
    real(dp), intent(in) :: x_in(2, *)
    real(dp), intent(inout) :: v(2, *), x_out(2, *)
    real(dp), intent(in), optional :: alpha(*), m_pos(*)
    real(dp), intent(inout), optional :: pw(2, *)
    integer, parameter :: chunk = 512
    real(dp) :: ku(2, chunk), v1, v2
    integer :: i0, m, l, i
    do i0 = lo, lo + len - 1, chunk
      m = min(chunk, lo + len - i0)
      call bsr_matvec(m, row_ptr(i0), col, val, x_in, ku)
      if (present(pw)) then
        call damped_update(i0, m, ku, inv_m, alpha, m_pos, dt, x_in, v, x_out, pw)
        cycle
      end if
      do l = 1, m
        i = i0 + l - 1
        v1 = v(1, i) + dt*((-ku(1, l))*inv_m(1, i))
        v2 = v(2, i) + dt*((-ku(2, l))*inv_m(2, i))
        v(1, i) = v1
        v(2, i) = v2
        x_out(1, i) = x_in(1, i) + dt*v1
        x_out(2, i) = x_in(2, i) + dt*v2
      end do
    end do
  end subroutine fused_lumped_rows

  !> The update of rows i0 .. i0 + m - 1 of the damped lumped-mass step (the mass-proportional
  !! damping of ictus_solver_explicit) from ku = K x_in of those rows: a = -ku/m,
  !! h = alpha dt/2, v_new = ((1 - h) v + dt a)/(1 + h), x_out = x_in + dt v_new, and the
  !! terms of the damping power at t_n, pw(c, i) = (-(alpha m_pos) v_mid) v_mid in
  !! component c with v_mid = (v + v_new)/2 (their sum over all nodes and components is the
  !! power). alpha and m_pos: the node's damping coefficient and positive lumped mass. The
  !! operations of the unfused damped step in the same order, so the same bits.
  subroutine damped_update(i0, m, ku, inv_m, alpha, m_pos, dt, x_in, v, x_out, pw)
    integer, intent(in) :: i0, m
    real(dp), intent(in) :: ku(2, m), inv_m(2, *), alpha(*), m_pos(*), dt, x_in(2, *)
    real(dp), intent(inout) :: v(2, *), x_out(2, *), pw(2, *)
    real(dp) :: h, am, vn1, vn2, vm1, vm2
    integer :: l, i
    do l = 1, m
      i = i0 + l - 1
      h = 0.5_dp*alpha(i)*dt
      vn1 = ((1.0_dp - h)*v(1, i) + dt*((-ku(1, l))*inv_m(1, i)))/(1.0_dp + h)
      vn2 = ((1.0_dp - h)*v(2, i) + dt*((-ku(2, l))*inv_m(2, i)))/(1.0_dp + h)
      vm1 = 0.5_dp*(v(1, i) + vn1)
      vm2 = 0.5_dp*(v(2, i) + vn2)
      am = alpha(i)*m_pos(i)
      pw(1, i) = (-(am*vm1))*vm1
      pw(2, i) = (-(am*vm2))*vm2
      v(:, i) = [vn1, vn2]
      x_out(:, i) = [x_in(1, i) + dt*vn1, x_in(2, i) + dt*vn2]
    end do
  end subroutine damped_update

  !> `fused_lumped_rows` for 3 x 3 blocks (3D): rows lo .. lo + len - 1 of
  !! v += dt (-K x_in)/m, x_out = x_in + dt v in chunks of K x_in (bsr3_matvec) that stay in
  !! the L1 cache; with `alpha`, `m_pos` and `pw` the damped update of `damped_update` on three
  !! components. Per component the operations of the unfused 3D step, so the same bits.
  subroutine fused_lumped_rows3(lo, len, row_ptr, col, val, inv_m, dt, x_in, v, x_out, alpha, &
      m_pos, pw)
    integer, intent(in) :: lo, len
    integer, intent(in) :: row_ptr(*), col(*)
    real(dp), intent(in) :: val(3, 3, *), inv_m(3, *), dt
    real(dp), intent(in) :: x_in(3, *)
    real(dp), intent(inout) :: v(3, *), x_out(3, *)
    real(dp), intent(in), optional :: alpha(*), m_pos(*)
    real(dp), intent(inout), optional :: pw(3, *)
    integer, parameter :: chunk = 512
    real(dp) :: ku(3, chunk), vn(3), vm(3), h, am
    integer :: i0, m, l, i
    do i0 = lo, lo + len - 1, chunk
      m = min(chunk, lo + len - i0)
      call bsr3_matvec(m, row_ptr(i0), col, val, x_in, ku)
      if (present(pw)) then
        do l = 1, m
          i = i0 + l - 1
          h = 0.5_dp*alpha(i)*dt
          vn = ((1.0_dp - h)*v(:, i) + dt*((-ku(:, l))*inv_m(:, i)))/(1.0_dp + h)
          vm = 0.5_dp*(v(:, i) + vn)
          am = alpha(i)*m_pos(i)
          pw(:, i) = (-(am*vm))*vm
          v(:, i) = vn
          x_out(:, i) = x_in(:, i) + dt*vn
        end do
        cycle
      end if
      do l = 1, m
        i = i0 + l - 1
        vn = v(:, i) + dt*((-ku(:, l))*inv_m(:, i))
        v(:, i) = vn
        x_out(:, i) = x_in(:, i) + dt*vn
      end do
    end do
  end subroutine fused_lumped_rows3

  !> y = (A ⊗ I) x for the scalar matrix acting on every component, on its n rows; x and y
  !! hold `nc` components per node (default 2; 3 in 3D), node after node.
  subroutine csr_matvec(n, row_ptr, col, val, x, y, nc)
    integer, intent(in) :: n
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(*), x(*)
    real(dp), intent(inout) :: y(*)
    integer, intent(in), optional :: nc
    integer :: m
    m = 2
    if (present(nc)) m = nc
    if (m == 2) then
      call csr_rows2(n, row_ptr, col, val, x, y)
    else
      call csr_rows(m, n, row_ptr, col, val, x, y)
    end if
  end subroutine csr_matvec

  !> The rows of csr_matvec for two components.
  subroutine csr_rows2(n, row_ptr, col, val, x, y)
    integer, intent(in) :: n
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(*), x(2, *)
    real(dp), intent(inout) :: y(2, *)
    integer :: i, k, j
    real(dp) :: s1, s2
    do i = 1, n
      s1 = 0.0_dp
      s2 = 0.0_dp
      do k = row_ptr(i), row_ptr(i + 1) - 1
        j = col(k)
        s1 = s1 + val(k)*x(1, j)
        s2 = s2 + val(k)*x(2, j)
      end do
      y(1, i) = s1
      y(2, i) = s2
    end do
  end subroutine csr_rows2

  !> The rows of csr_matvec for nc components (each summed in the same order as csr_rows2).
  subroutine csr_rows(nc, n, row_ptr, col, val, x, y)
    integer, intent(in) :: nc, n
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(*), x(nc, *)
    real(dp), intent(inout) :: y(nc, *)
    integer :: i, k, j
    real(dp) :: s(nc)
    do i = 1, n
      s = 0.0_dp
      do k = row_ptr(i), row_ptr(i + 1) - 1
        j = col(k)
        s = s + val(k)*x(:, j)
      end do
      y(:, i) = s
    end do
  end subroutine csr_rows

  !> Diagonal of a scalar CSR matrix.
  subroutine csr_diagonal(a, d)
    type(csr_t), intent(in) :: a
    real(dp), intent(out) :: d(:)
    integer :: i
    do i = 1, a%g%n
      d(i) = a%val(find_col(a%g, i, i))
    end do
  end subroutine csr_diagonal

  !> Row sums of a scalar CSR matrix.
  subroutine csr_row_sums(a, s)
    type(csr_t), intent(in) :: a
    real(dp), intent(out) :: s(:)
    integer :: i
    do i = 1, a%g%n
      s(i) = sum(a%val(a%g%row_ptr(i):a%g%row_ptr(i + 1) - 1))
    end do
  end subroutine csr_row_sums
end module ictus_solver_sparse
