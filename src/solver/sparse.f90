!> Sparse matrices of the explicit solver.
!!
!! The stiffness is stored in block CSR with 2x2 node blocks (`bsr_t`): it moves the fewest
!! bytes per product, and the product is the memory-bound kernel of every step. The consistent
!! mass, the same for both displacement components, is a scalar CSR matrix (`csr_t`) on the
!! same node graph. Both are assembled once from element matrices.
module ictus_solver_sparse
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: graph_t, bsr_t, csr_t, graph_from_elements, bsr_init, csr_init, bsr_add_element, &
      csr_add_element, bsr_matvec, csr_matvec, csr_diagonal, csr_row_sums, find_col

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

  !> Block CSR matrix with 2x2 blocks, val(2, 2, nnz_blocks).
  type :: bsr_t
    type(graph_t) :: g
    real(dp), allocatable :: val(:,:,:)
  end type bsr_t

  !> Scalar CSR matrix, val(nnz).
  type :: csr_t
    type(graph_t) :: g
    real(dp), allocatable :: val(:)
  end type csr_t

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
    allocate(g%col(g%row_ptr(nrows + 1) - 1))
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

  !> Zero block matrix on graph `g`.
  subroutine bsr_init(a, g)
    type(bsr_t), intent(out) :: a
    type(graph_t), intent(in) :: g
    a%g = g
    allocate(a%val(2, 2, size(g%col)), source=0.0_dp)
  end subroutine bsr_init

  !> Zero scalar matrix on graph `g`.
  subroutine csr_init(a, g)
    type(csr_t), intent(out) :: a
    type(graph_t), intent(in) :: g
    a%g = g
    allocate(a%val(size(g%col)), source=0.0_dp)
  end subroutine csr_init

  !> Adds an element stiffness ke(2*nen, 2*nen) (dofs x1,y1,x2,y2,...) on nodes `nodes`
  !! (local indices); only the rows of nodes that have rows (owned nodes) are added.
  subroutine bsr_add_element(a, nen, nodes, ke)
    type(bsr_t), intent(inout) :: a
    integer, intent(in) :: nen
    integer, intent(in) :: nodes(nen)
    real(dp), intent(in) :: ke(2*nen, 2*nen)
    integer :: p, q, pos
    do p = 1, nen
      if (nodes(p) > a%g%n) cycle
      do q = 1, nen
        pos = find_col(a%g, nodes(p), nodes(q))
        a%val(:, :, pos) = a%val(:, :, pos) + ke(2*p - 1:2*p, 2*q - 1:2*q)
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
  subroutine bsr_matvec(n, row_ptr, col, val, x, y)
    integer, intent(in) :: n
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(2, 2, *), x(2, *)
    real(dp), intent(inout) :: y(2, *)
    integer :: i, k, j
    real(dp) :: s1, s2
    do i = 1, n
      s1 = 0.0_dp
      s2 = 0.0_dp
      do k = row_ptr(i), row_ptr(i + 1) - 1
        j = col(k)
        s1 = s1 + val(1, 1, k)*x(1, j) + val(1, 2, k)*x(2, j)
        s2 = s2 + val(2, 1, k)*x(1, j) + val(2, 2, k)*x(2, j)
      end do
      y(1, i) = s1
      y(2, i) = s2
    end do
  end subroutine bsr_matvec

  !> y = (A ⊗ I2) x for the scalar matrix acting on both components, on its n rows.
  subroutine csr_matvec(n, row_ptr, col, val, x, y)
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
  end subroutine csr_matvec

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
