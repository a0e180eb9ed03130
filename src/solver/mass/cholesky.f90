!> Sparse Cholesky factorisation L L^T = P A P^T of a symmetric positive definite matrix, and
!! its triangular solves (used for the consistent mass, doc/theory.md §5: factorised once).
!!
!! Three stages, in the classic order of a direct solver:
!!
!! 1. `chol_analyse` (symbolic, from the pattern and a fill-reducing order such as METIS
!!    nested dissection): elimination tree, its postorder (same fill, and the columns of a
!!    supernode become consecutive), column counts by row subtrees, fundamental supernodes
!!    (consecutive columns with the same structure below the diagonal block), the sorted row
!!    structure of every supernode, and the sizes of the work arrays of stage 2.
!! 2. `chol_factor` (numeric, multifrontal): supernodes in postorder; the columns of a
!!    supernode are assembled from A and from the update matrices its children left on a
!!    stack, then factorised densely (diagonal block by `dense_cholesky`, the rows below by
!!    BLAS dtrsm) and its own update matrix (dsyrk) is pushed for its parent. Rows and columns
!!    marked `keep = .false.` are replaced by the identity, which is how fixed dofs get a zero
!!    solution without a second pattern.
!! 3. `chol_solve`: forward and backward substitution, supernode by supernode, reading the
!!    factor once each, for the two or three right-hand sides stored as x(nd, n) in pivot
!!    order (the displacement components, each with its factor).
!!
!! Every stage is sequential and has a fixed operation order, so a factor and a solve are the
!! same bits wherever they run; the caller decides which rank runs them (see
!! ictus_solver_mass_cholesky). `chol_solve` allocates nothing (the caller gives its work).
module ictus_solver_cholesky
  use ictus_core_kinds, only: dp, i8
  use ictus_parallel_partition, only: nested_dissection
  implicit none
  private
  public :: chol_t, chol_analyse, chol_factor, chol_solve, dense_cholesky, tail_order

  type :: chol_t
    !> Order of the matrix, number of supernodes, number of numeric factors held.
    integer :: n = 0
    integer :: nsup = 0
    integer :: nfac = 0
    !> Pivot order: pivot k is row order(k) of A; row i of A is pivot inv(i).
    integer, allocatable :: order(:), inv(:)
    !> Supernode s holds the pivots first(s)..first(s+1)-1 (nsup + 1).
    integer, allocatable :: first(:)
    !> Parent supernode (0 for a root) and number of children.
    integer, allocatable :: sparent(:), nchild(:)
    !> Rows (pivots) of supernode s, ascending: rix(rix_ptr(s):rix_ptr(s+1)-1); its own
    !! pivots come first.
    integer(i8), allocatable :: rix_ptr(:)
    integer, allocatable :: rix(:)
    !> Supernode s is the dense column-major block val(val_ptr(s)+1 : val_ptr(s+1), f) of
    !! nrows x ncols, for factor f = 1..nfac.
    integer(i8), allocatable :: val_ptr(:)
    real(dp), allocatable :: val(:,:)
    !> Non-zeros of L and flops of the numeric factorisation (from the symbolic stage).
    integer(i8) :: nnz = 0
    real(dp) :: flops = 0.0_dp
    !> Largest update matrix, peak of the update stack (entries) and deepest stack.
    integer(i8) :: w_size = 0
    integer(i8) :: stack_size = 0
    integer :: stack_depth = 0
    !> Most rows of a supernode (the solve's work vector).
    integer :: max_rows = 0
    !> Tail: the last ntail pivots form the last supernode, a dense block. With two sets of
    !! kept dofs that differ only there, the factor is shared up to the tail and the tail
    !! is factorised once per component: its Schur complement with the rows and columns not
    !! kept in that component replaced by the identity (component 1 in val, component 2 in
    !! tail2).
    integer :: ntail = 0
    real(dp), allocatable :: tail2(:,:)
    !> 1 where a tail dof is kept, 0 where it is not (ntail, 2): the forward sweep leaves
    !! -L_DI y_I on those rows, which must not enter the tail solve.
    real(dp), allocatable :: tail_keep(:,:)
  end type chol_t

  interface
    subroutine dtrsm(side, uplo, transa, diag, m, n, alpha, a, lda, b, ldb)
      import :: dp
      character, intent(in) :: side, uplo, transa, diag
      integer, intent(in) :: m, n, lda, ldb
      real(dp), intent(in) :: alpha, a(lda, *)
      real(dp), intent(inout) :: b(ldb, *)
    end subroutine dtrsm
    subroutine dsyrk(uplo, trans, n, k, alpha, a, lda, beta, c, ldc)
      import :: dp
      character, intent(in) :: uplo, trans
      integer, intent(in) :: n, k, lda, ldc
      real(dp), intent(in) :: alpha, beta, a(lda, *)
      real(dp), intent(inout) :: c(ldc, *)
    end subroutine dsyrk
  end interface

  !> Panel width of `dense_cholesky`.
  integer, parameter :: panel = 64
  !> Relaxed supernodes: most columns of a merged supernode, and its explicit zeros at most
  !! this fraction of its non-zeros (see `amalgamate`).
  integer, parameter :: relax_cols = 32
  real(dp), parameter :: relax_zeros = 0.25_dp

contains

  !> Symbolic factorisation of the n x n matrix whose pattern is given by full rows
  !! (row_ptr, col; both triangles, diagonal optional) in the pivot order `order`
  !! (order(k) = row of A eliminated k-th). Sets everything in `ch` but the values; `nfac`
  !! numeric factors (1 or 2) will share it. With `ntail` > 0, the last ntail pivots of
  !! `order` must be connected to each other in the pattern (a clique); they stay last and
  !! form one supernode (see chol_t%ntail). ierr = 1 when L has more than huge(0) supernodal
  !! row indices, 2 when the row lists do not come out at the counted lengths (a bug).
  subroutine chol_analyse(ch, n, row_ptr, col, order, nfac, ierr, ntail)
    type(chol_t), intent(out) :: ch
    integer, intent(in) :: n, nfac
    integer, intent(in) :: row_ptr(n + 1), col(*), order(n)
    integer, intent(out) :: ierr
    integer, intent(in), optional :: ntail
    integer, allocatable :: parent(:), anc(:), cc(:), nch(:), col2sup(:), smark(:), sizes(:)
    integer(i8), allocatable :: fillp(:)
    integer, allocatable :: snr(:)
    integer(i8) :: nr, nc, m, top, peak
    integer :: i, j, k, p, s, nst, nsup
    ierr = 0
    ch%n = n
    ch%nfac = nfac
    if (present(ntail)) ch%ntail = ntail
    allocate(ch%order(n), ch%inv(n), parent(n), anc(n))
    ch%order = order
    call invert(n, ch%order, ch%inv)

    call etree_postorder(ch, n, row_ptr, col, parent)

    ! column counts (diagonal included) by row subtrees: row k of L has its non-zeros on the
    ! tree paths from the pivots of row k of A up to k
    allocate(cc(n), nch(n))
    cc = 1
    nch = 0
    anc = 0
    do k = 1, n
      if (parent(k) > 0) nch(parent(k)) = nch(parent(k)) + 1
      anc(k) = k
      i = ch%order(k)
      do p = row_ptr(i), row_ptr(i + 1) - 1
        j = ch%inv(col(p))
        do while (j < k .and. anc(j) /= k)
          cc(j) = cc(j) + 1
          anc(j) = k
          j = parent(j)
        end do
      end do
    end do
    ch%nnz = sum(int(cc, i8))

    ! fundamental supernodes: j continues the supernode of j - 1 when j - 1 is its only child
    ! and column j has the structure of column j - 1 without the diagonal
    allocate(col2sup(n))
    nsup = 0
    do j = 1, n
      if (j > 1) then
        if ((parent(j - 1) == j .and. nch(j) == 1 .and. cc(j - 1) == cc(j) + 1 .and. &
            j /= n - ch%ntail + 1) .or. j > n - ch%ntail + 1) then
          col2sup(j) = nsup
          cycle
        end if
      end if
      nsup = nsup + 1
      col2sup(j) = nsup
    end do
    call amalgamate(n, ch%ntail, parent, cc, nsup, col2sup, snr)
    ch%nsup = nsup
    allocate(ch%first(nsup + 1), ch%sparent(nsup), ch%nchild(nsup), ch%rix_ptr(nsup + 1), &
        ch%val_ptr(nsup + 1))
    do j = n, 1, -1
      ch%first(col2sup(j)) = j
    end do
    ch%first(nsup + 1) = n + 1
    ch%nchild = 0
    ch%rix_ptr(1) = 1
    ch%val_ptr(1) = 0
    do s = 1, nsup
      j = ch%first(s + 1) - 1
      ch%sparent(s) = 0
      if (parent(j) > 0) ch%sparent(s) = col2sup(parent(j))
      if (ch%sparent(s) > 0) ch%nchild(ch%sparent(s)) = ch%nchild(ch%sparent(s)) + 1
      nr = snr(s)
      nc = ch%first(s + 1) - ch%first(s)
      ch%max_rows = max(ch%max_rows, int(nr))
      ch%rix_ptr(s + 1) = ch%rix_ptr(s) + nr
      ch%val_ptr(s + 1) = ch%val_ptr(s) + nr*nc
      ! flops: for each column of the supernode, sqrt + divisions + the rank-1 update below
      m = nr - nc
      ch%flops = ch%flops + real(nc, dp)**3/3.0_dp + real(m, dp)*real(nc, dp)**2 + &
          real(m, dp)**2*real(nc, dp)
    end do
    if (ch%rix_ptr(nsup + 1) - 1 > huge(0)) then
      ierr = 1
      return
    end if

    ! row structure of the supernodes: walk row k's subtree supernode by supernode; rows are
    ! appended in increasing k, so every list comes out sorted
    allocate(ch%rix(ch%rix_ptr(nsup + 1) - 1), fillp(nsup), smark(nsup))
    do s = 1, nsup
      nc = ch%first(s + 1) - ch%first(s)
      do k = 1, int(nc)
        ch%rix(ch%rix_ptr(s) + k - 1) = ch%first(s) + k - 1
      end do
      fillp(s) = ch%rix_ptr(s) + nc
    end do
    smark = 0
    do k = 1, n
      smark(col2sup(k)) = k
      i = ch%order(k)
      do p = row_ptr(i), row_ptr(i + 1) - 1
        j = ch%inv(col(p))
        if (j >= k) cycle
        s = col2sup(j)
        do while (smark(s) /= k)
          ch%rix(fillp(s)) = k
          fillp(s) = fillp(s) + 1
          smark(s) = k
          s = ch%sparent(s)
        end do
      end do
    end do
    if (any(fillp /= ch%rix_ptr(2:nsup + 1))) then
      ierr = 2
      return
    end if

    ! work sizes of the numeric stage: largest update matrix and the peak of the stack
    allocate(sizes(nsup))
    top = 0
    peak = 0
    nst = 0
    do s = 1, nsup
      m = (ch%rix_ptr(s + 1) - ch%rix_ptr(s)) - (ch%first(s + 1) - ch%first(s))
      ch%w_size = max(ch%w_size, m*m)
      do k = 1, ch%nchild(s)
        top = top - int(sizes(nst), i8)**2
        nst = nst - 1
      end do
      if (m > 0) then
        nst = nst + 1
        sizes(nst) = int(m)
        top = top + m*m
        peak = max(peak, top)
        ch%stack_depth = max(ch%stack_depth, nst)
      end if
    end do
    ch%stack_size = peak
  end subroutine chol_analyse

  !> The elimination tree of the pattern (row_ptr, col) in the pivot order ch%order (Liu,
  !! with path compression), then its postorder (children in ascending order, the same fill,
  !! and the columns of a supernode become consecutive): ch%order, ch%inv relabelled, and
  !! parent(k) the parent pivot of pivot k in the new order (0 for a root).
  subroutine etree_postorder(ch, n, row_ptr, col, parent)
    type(chol_t), intent(inout) :: ch
    integer, intent(in) :: n
    integer, intent(in) :: row_ptr(n + 1), col(*)
    integer, intent(out) :: parent(n)
    integer, allocatable :: anc(:), post(:), head(:), next(:), stack(:), relabel(:)
    integer :: i, j, jn, k, p, r, nst, cnt
    allocate(anc(n))
    parent = 0
    anc = 0
    do k = 1, n
      i = ch%order(k)
      do p = row_ptr(i), row_ptr(i + 1) - 1
        j = ch%inv(col(p))
        if (j >= k) cycle
        do
          jn = anc(j)
          if (jn == k) exit
          anc(j) = k
          if (jn == 0) then
            parent(j) = k
            exit
          end if
          j = jn
        end do
      end do
    end do

    ! postorder (children in ascending order), then relabel order, inv and parent
    allocate(head(n), next(n), stack(n), post(n), relabel(n))
    head = 0
    next = 0
    do k = n, 1, -1
      if (parent(k) > 0) then
        next(k) = head(parent(k))
        head(parent(k)) = k
      end if
    end do
    cnt = 0
    do r = 1, n
      if (parent(r) /= 0) cycle
      nst = 1
      stack(1) = r
      do while (nst > 0)
        j = stack(nst)
        if (head(j) /= 0) then
          k = head(j)
          head(j) = next(k)
          nst = nst + 1
          stack(nst) = k
        else
          nst = nst - 1
          cnt = cnt + 1
          post(cnt) = j
        end if
      end do
    end do
    do k = 1, n
      relabel(post(k)) = k
    end do
    anc = ch%order
    do k = 1, n
      ch%order(k) = anc(post(k))
    end do
    call invert(n, ch%order, ch%inv)
    anc = parent
    do k = 1, n
      parent(k) = 0
      if (anc(post(k)) > 0) parent(k) = relabel(anc(post(k)))
    end do
    deallocate(head, next, stack, post, relabel)
  end subroutine etree_postorder

  !> Relaxed supernodes: a supernode joins the group of the one before it when that one is
  !! its child (the child's rows below its diagonal block are then all rows of the parent)
  !! and the merged block stays small (at most relax_cols columns) with few explicit zeros
  !! (at most relax_zeros of its non-zeros). Fewer, larger dense blocks make the solve's
  !! per-supernode work (gathering and scattering rows of x) rarer. The tail is never
  !! merged. col2sup and nsup are renumbered; snr(s) = rows of merged supernode s.
  subroutine amalgamate(n, ntail, parent, cc, nsup, col2sup, snr)
    integer, intent(in) :: n, ntail, parent(n), cc(n)
    integer, intent(inout) :: nsup, col2sup(n)
    integer, allocatable, intent(out) :: snr(:)
    integer, allocatable :: first(:), fpar(:), newid(:)
    integer(i8) :: gnc, gnr, gtrue, ncs, nrs, trues, nc_new, nr_new, true_new, zeros
    integer :: s, j, g
    logical :: merge_it
    allocate(first(nsup + 1), fpar(nsup), newid(nsup), snr(nsup))
    do j = n, 1, -1
      first(col2sup(j)) = j
    end do
    first(nsup + 1) = n + 1
    do s = 1, nsup
      j = first(s + 1) - 1
      fpar(s) = 0
      if (parent(j) > 0) fpar(s) = col2sup(parent(j))
    end do
    g = 0
    gnc = 0
    gnr = 0
    gtrue = 0
    do s = 1, nsup
      ncs = first(s + 1) - first(s)
      nrs = cc(first(s))
      trues = ncs*nrs - ncs*(ncs - 1)/2
      merge_it = .false.
      if (s > 1) then
        if (fpar(s - 1) == s .and. .not. (ntail > 0 .and. s == nsup)) then
          nc_new = gnc + ncs
          nr_new = gnc + nrs
          true_new = gtrue + trues
          zeros = nr_new*nc_new - nc_new*(nc_new - 1)/2 - true_new
          merge_it = nc_new <= relax_cols .and. real(zeros, dp) <= relax_zeros*real(true_new, dp)
        end if
      end if
      if (merge_it) then
        gnc = nc_new
        gnr = nr_new
        gtrue = true_new
      else
        g = g + 1
        gnc = ncs
        gnr = nrs
        gtrue = trues
      end if
      newid(s) = g
      snr(g) = int(gnr)
    end do
    do j = 1, n
      col2sup(j) = newid(col2sup(j))
    end do
    nsup = g
  end subroutine amalgamate

  !> Numeric factorisation number `f` (1..nfac) of A (row_ptr, col, a: full rows, as given to
  !! chol_analyse), with the rows and columns where keep is .false. replaced by the identity.
  !! ierr = 0, or the row of A at which A is not positive definite, or -1 when the work arrays
  !! cannot be allocated. With a tail (ntail > 0), `keep` must be .true. on the tail and
  !! keep_tail(:, c) gives the kept dofs of component c there.
  subroutine chol_factor(ch, row_ptr, col, a, keep, f, ierr, keep_tail)
    type(chol_t), intent(inout) :: ch
    integer, intent(in) :: row_ptr(:), col(:), f
    real(dp), intent(in) :: a(:)
    logical, intent(in) :: keep(:)
    integer, intent(out) :: ierr
    logical, intent(in), optional :: keep_tail(:,:)
    real(dp), allocatable :: stack(:), w(:)
    integer(i8), allocatable :: soff(:)
    integer, allocatable :: ssup(:), pos(:)
    integer(i8) :: top, b, r0
    integer :: s, c, e, nst, nc, nr, m, st
    ierr = 0
    if (.not. allocated(ch%val)) then
      allocate(ch%val(ch%val_ptr(ch%nsup + 1), ch%nfac), stat=st)
      if (st /= 0) then
        ierr = -1
        return
      end if
    end if
    allocate(stack(max(ch%stack_size, 1_i8)), w(max(ch%w_size, 1_i8)), &
        soff(max(ch%stack_depth, 1)), ssup(max(ch%stack_depth, 1)), pos(ch%n), stat=st)
    if (st /= 0) then
      ierr = -1
      return
    end if
    nst = 0
    top = 0
    do s = 1, ch%nsup
      nc = ch%first(s + 1) - ch%first(s)
      r0 = ch%rix_ptr(s)
      nr = int(ch%rix_ptr(s + 1) - r0)
      m = nr - nc
      b = ch%val_ptr(s)
      do c = 1, nr
        pos(ch%rix(r0 + c - 1)) = c
      end do
      call assemble_columns(ch, s, nr, nc, row_ptr, col, a, keep, pos, ch%val(b + 1, f))
      w(1:int(m, i8)**2) = 0.0_dp
      do e = nst - ch%nchild(s) + 1, nst
        c = ssup(e)
        call extend_add(ch, c, pos, nr, nc, m, stack(soff(e) + 1), ch%val(b + 1, f), w)
      end do
      if (ch%nchild(s) > 0) then
        top = soff(nst - ch%nchild(s) + 1)
        nst = nst - ch%nchild(s)
      end if
      if (ch%ntail > 0 .and. s == ch%nsup) then
        ! the assembled tail is the Schur complement: one copy per component
        if (allocated(ch%tail2)) deallocate(ch%tail2, ch%tail_keep)
        allocate(ch%tail2(nc, nc), ch%tail_keep(nc, 2), stat=st)
        if (st /= 0) then
          ierr = -1
          return
        end if
        do c = 1, nc
          ch%tail_keep(c, :) = merge(1.0_dp, 0.0_dp, keep_tail(ch%order(ch%n - nc + c), :))
        end do
        ch%tail2 = reshape(ch%val(b + 1:b + int(nc, i8)**2, f), [nc, nc])
        call tail_identity(ch, nc, keep_tail(:, 2), ch%tail2)
        call dense_cholesky(nc, ch%tail2, nc, ierr)
        if (ierr /= 0) then
          ierr = ch%order(ch%first(s) + ierr - 1)
          return
        end if
        call tail_identity(ch, nc, keep_tail(:, 1), ch%val(b + 1, f))
      end if
      call dense_cholesky(nc, ch%val(b + 1, f), nr, ierr)
      if (ierr /= 0) then
        ierr = ch%order(ch%first(s) + ierr - 1)
        return
      end if
      if (m > 0) then
        call dtrsm('R', 'L', 'T', 'N', m, nc, 1.0_dp, ch%val(b + 1, f), nr, &
            ch%val(b + nc + 1, f), nr)
        call dsyrk('L', 'N', m, nc, -1.0_dp, ch%val(b + nc + 1, f), nr, 1.0_dp, w, m)
        nst = nst + 1
        ssup(nst) = s
        soff(nst) = top
        stack(top + 1:top + int(m, i8)**2) = w(1:int(m, i8)**2)
        top = top + int(m, i8)**2
      end if
    end do
  end subroutine chol_factor

  !> Rows and columns of the tail block t(nc, nc) whose dofs are not kept become identity.
  subroutine tail_identity(ch, nc, keep, t)
    type(chol_t), intent(in) :: ch
    integer, intent(in) :: nc
    logical, intent(in) :: keep(:)
    real(dp), intent(inout) :: t(nc, *)
    integer :: k
    do k = 1, nc
      if (keep(ch%order(ch%n - nc + k))) cycle
      t(k, 1:nc) = 0.0_dp
      t(1:nc, k) = 0.0_dp
      t(k, k) = 1.0_dp
    end do
  end subroutine tail_identity

  !> The entries of A in the columns of supernode s (rows >= the column, in pivot order) into
  !! its block l(nr, nc), which is zeroed first; identity on rows/columns not kept.
  subroutine assemble_columns(ch, s, nr, nc, row_ptr, col, a, keep, pos, l)
    type(chol_t), intent(in) :: ch
    integer, intent(in) :: s, nr, nc, row_ptr(:), col(:), pos(:)
    real(dp), intent(in) :: a(:)
    logical, intent(in) :: keep(:)
    real(dp), intent(out) :: l(nr, nc)
    integer :: jc, j, i, p, r
    l = 0.0_dp
    do jc = 1, nc
      j = ch%first(s) + jc - 1
      i = ch%order(j)
      if (.not. keep(i)) then
        l(jc, jc) = 1.0_dp
        cycle
      end if
      do p = row_ptr(i), row_ptr(i + 1) - 1
        r = ch%inv(col(p))
        if (r < j .or. .not. keep(col(p))) cycle
        l(pos(r), jc) = l(pos(r), jc) + a(p)
      end do
    end do
  end subroutine assemble_columns

  !> Adds the update matrix u (lower triangle, mc x mc) of child supernode c into the block
  !! l(nr, nc) of its parent and the parent's own update matrix w(m, m); pos maps a pivot to
  !! its row in the parent.
  subroutine extend_add(ch, c, pos, nr, nc, m, u, l, w)
    type(chol_t), intent(in) :: ch
    integer, intent(in) :: c, pos(:), nr, nc, m
    real(dp), intent(in) :: u(*)
    real(dp), intent(inout) :: l(nr, nc), w(m, *)
    integer :: mc, jj, ii, pj, pi
    integer(i8) :: r0, o
    r0 = ch%rix_ptr(c) + (ch%first(c + 1) - ch%first(c))
    mc = int(ch%rix_ptr(c + 1) - r0)
    do jj = 1, mc
      pj = pos(ch%rix(r0 + jj - 1))
      o = int(jj - 1, i8)*mc
      if (pj <= nc) then
        do ii = jj, mc
          pi = pos(ch%rix(r0 + ii - 1))
          l(pi, pj) = l(pi, pj) + u(o + ii)
        end do
      else
        do ii = jj, mc
          pi = pos(ch%rix(r0 + ii - 1))
          w(pi - nc, pj - nc) = w(pi - nc, pj - nc) + u(o + ii)
        end do
      end if
    end do
  end subroutine extend_add

  !> Dense Cholesky a = L L^T of the leading n x n block of a(lda, *), lower triangle, in
  !! panels of `panel` columns: each panel column by column, then the rows below it (dtrsm)
  !! and the trailing block (dsyrk). ierr = the column with a non-positive pivot, else 0.
  !! (Not LAPACK's dpotrf: its blocking may depend on the number of BLAS threads.)
  subroutine dense_cholesky(n, a, lda, ierr)
    integer, intent(in) :: n, lda
    real(dp), intent(inout) :: a(lda, *)
    integer, intent(out) :: ierr
    integer :: k0, nb, j, i, k
    real(dp) :: d
    ierr = 0
    do k0 = 1, n, panel
      nb = min(panel, n - k0 + 1)
      do j = k0, k0 + nb - 1
        d = a(j, j)
        do k = k0, j - 1
          d = d - a(j, k)**2
        end do
        if (.not. d > 0.0_dp) then
          ierr = j
          return
        end if
        a(j, j) = sqrt(d)
        do i = j + 1, k0 + nb - 1
          d = a(i, j)
          do k = k0, j - 1
            d = d - a(i, k)*a(j, k)
          end do
          a(i, j) = d/a(j, j)
        end do
      end do
      if (k0 + nb <= n) then
        call dtrsm('R', 'L', 'T', 'N', n - k0 - nb + 1, nb, 1.0_dp, a(k0, k0), lda, &
            a(k0 + nb, k0), lda)
        call dsyrk('L', 'N', n - k0 - nb + 1, nb, -1.0_dp, a(k0 + nb, k0), lda, 1.0_dp, &
            a(k0 + nb, k0 + nb), lda)
      end if
    end do
  end subroutine dense_cholesky

  !> Solves L L^T x = b in place for x(nd, n) in pivot order (nd = 2 or 3 components):
  !! component c with factor fac(c), one sweep for each run of consecutive components that
  !! share a factor (the same bits as one sweep per component). With a tail (2 components
  !! only), the shared factor and one tail factor per component. xl(max_rows, nd) is work
  !! space.
  subroutine chol_solve(ch, fac, x, xl)
    type(chol_t), intent(in) :: ch
    integer, intent(in) :: fac(:)
    real(dp), intent(inout), contiguous :: x(:,:), xl(:,:)
    integer :: s, k, ld, nd, c1, c2
    s = ch%nsup
    k = ch%ntail
    ld = size(xl, 1)
    nd = size(x, 1)
    if (k > 0) then
      ! shared factor up to the tail, one tail factor per component
      call substitute(ch, ch%val(1, 1), x, xl, ld, nd, 1, 2, s - 1, .false.)
      xl(1:k, 1) = x(1, ch%n - k + 1:ch%n)*ch%tail_keep(:, 1)
      xl(1:k, 2) = x(2, ch%n - k + 1:ch%n)*ch%tail_keep(:, 2)
      call tail_solve(k, ch%val(ch%val_ptr(s) + 1, 1), xl(1:k, 1))
      call tail_solve(k, ch%tail2, xl(1:k, 2))
      x(1, ch%n - k + 1:ch%n) = xl(1:k, 1)
      x(2, ch%n - k + 1:ch%n) = xl(1:k, 2)
      call substitute(ch, ch%val(1, 1), x, xl, ld, nd, 1, 2, s - 1, .true.)
      return
    end if
    c1 = 1
    do while (c1 <= nd)
      c2 = c1
      do while (c2 < nd)
        if (fac(c2 + 1) /= fac(c1)) exit
        c2 = c2 + 1
      end do
      call substitute(ch, ch%val(1, fac(c1)), x, xl, ld, nd, c1, c2, s, .false.)
      call substitute(ch, ch%val(1, fac(c1)), x, xl, ld, nd, c1, c2, s, .true.)
      c1 = c2 + 1
    end do
  end subroutine chol_solve

  !> L L^T x = b in place for a dense lower factor l(n, n) (the tail).
  subroutine tail_solve(n, l, x)
    integer, intent(in) :: n
    real(dp), intent(in) :: l(n, *)
    real(dp), intent(inout) :: x(n)
    integer :: j, i
    real(dp) :: t
    do j = 1, n
      x(j) = x(j)/l(j, j)
      do i = j + 1, n
        x(i) = x(i) - l(i, j)*x(j)
      end do
    end do
    do j = n, 1, -1
      t = 0.0_dp
      do i = j + 1, n
        t = t + l(i, j)*x(i)
      end do
      x(j) = (x(j) - t)/l(j, j)
    end do
  end subroutine tail_solve

  !> The triangular solves for components c1..c2 of x on supernodes 1..last: L y = b
  !! (`transposed` false: supernodes and columns in increasing order) or L^T x = y (true:
  !! in decreasing order). Per supernode, its rows of x are gathered into the dense columns
  !! xl(1:nr, c), so the inner loops are contiguous and vectorised:
  !! - forward: the diagonal block is solved and the rows below updated column by column,
  !!   then all nr rows are scattered back;
  !! - backward: each column's dot product with the rows below runs in four lanes (a fixed
  !!   order, so the same bits on any machine that rounds IEEE doubles) that the compiler
  !!   maps to one vector register; only the supernode's own nc rows change.
  subroutine substitute(ch, val, x, xl, ld, nd, c1, c2, last, transposed)
    type(chol_t), intent(in) :: ch
    real(dp), intent(in) :: val(*)
    integer, intent(in) :: ld, nd, c1, c2, last
    real(dp), intent(inout) :: x(nd, *), xl(ld, nd)
    logical, intent(in) :: transposed
    integer(i8) :: r0, o
    integer :: k, s, nc, nr, jc, ii, c
    real(dp) :: y, t(4)
    do k = 1, last
      s = merge(last + 1 - k, k, transposed)
      call gather_rows(ch, s, x, xl, ld, nd, c1, c2, nc, nr, r0)
      if (.not. transposed) then
        o = ch%val_ptr(s)
        do jc = 1, nc
          do c = c1, c2
            y = xl(jc, c)/val(o + jc)
            xl(jc, c) = y
            do ii = jc + 1, nr
              xl(ii, c) = xl(ii, c) - val(o + ii)*y
            end do
          end do
          o = o + nr
        end do
        call scatter_rows(ch, r0, nr, x, xl, ld, nd, c1, c2)
      else
        do jc = nc, 1, -1
          o = ch%val_ptr(s) + int(jc - 1, i8)*nr
          do c = c1, c2
            t = 0.0_dp
            ii = jc + 1
            do while (ii + 3 <= nr)
              t = t + val(o + ii:o + ii + 3)*xl(ii:ii + 3, c)
              ii = ii + 4
            end do
            do while (ii <= nr)
              t(1) = t(1) + val(o + ii)*xl(ii, c)
              ii = ii + 1
            end do
            xl(jc, c) = (xl(jc, c) - ((t(1) + t(2)) + (t(3) + t(4))))/val(o + jc)
          end do
        end do
        call scatter_rows(ch, r0, nc, x, xl, ld, nd, c1, c2)
      end if
    end do
  end subroutine substitute

  !> Supernode s of the solves: its number of columns nc and rows nr, the offset r0 of its row
  !! list, and its rows of x (components c1..c2) gathered into xl(1:nr, c).
  subroutine gather_rows(ch, s, x, xl, ld, nd, c1, c2, nc, nr, r0)
    type(chol_t), intent(in) :: ch
    integer, intent(in) :: s, ld, nd, c1, c2
    real(dp), intent(in) :: x(nd, *)
    real(dp), intent(inout) :: xl(ld, nd)
    integer, intent(out) :: nc, nr
    integer(i8), intent(out) :: r0
    integer :: ii
    nc = ch%first(s + 1) - ch%first(s)
    r0 = ch%rix_ptr(s) - 1
    nr = int(ch%rix_ptr(s + 1) - 1 - r0)
    do ii = 1, nr
      xl(ii, c1:c2) = x(c1:c2, ch%rix(r0 + ii))
    end do
  end subroutine gather_rows

  !> The first n gathered rows xl(1:n, c) back into x (components c1..c2).
  subroutine scatter_rows(ch, r0, n, x, xl, ld, nd, c1, c2)
    type(chol_t), intent(in) :: ch
    integer(i8), intent(in) :: r0
    integer, intent(in) :: n, ld, nd, c1, c2
    real(dp), intent(inout) :: x(nd, *)
    real(dp), intent(in) :: xl(ld, nd)
    integer :: ii
    do ii = 1, n
      x(c1:c2, ch%rix(r0 + ii)) = xl(ii, c1:c2)
    end do
  end subroutine scatter_rows

  !> The pivot order with the nodes `last` at the end: METIS nested dissection of the graph
  !! of the other nodes, then those nodes in ascending order; and the pattern with the last
  !! nodes made a clique (row_ptr, col augmented), as chol_analyse needs for a tail.
  subroutine tail_order(n, row_ptr, col, last, order, rp_aug, col_aug, err)
    integer, intent(in) :: n, row_ptr(n + 1), col(:)
    logical, intent(in) :: last(n)
    integer, allocatable, intent(out) :: order(:), rp_aug(:), col_aug(:)
    integer, intent(out) :: err
    integer, allocatable :: sub_of(:), nodes(:), rp(:), cl(:), sub_order(:), tail(:), mark(:)
    integer :: ni, nt, i, p, k
    ni = count(.not. last)
    nt = n - ni
    allocate(sub_of(n), nodes(ni), tail(nt), order(n), rp(ni + 1), sub_order(ni), mark(n))
    ni = 0
    nt = 0
    do i = 1, n
      if (last(i)) then
        nt = nt + 1
        tail(nt) = i
        sub_of(i) = 0
      else
        ni = ni + 1
        nodes(ni) = i
        sub_of(i) = ni
      end if
    end do
    ! the graph of the other nodes, then its order
    rp(1) = 1
    do k = 1, ni
      i = nodes(k)
      rp(k + 1) = rp(k) + count(sub_of(col(row_ptr(i):row_ptr(i + 1) - 1)) > 0)
    end do
    allocate(cl(rp(ni + 1) - 1))
    do k = 1, ni
      i = nodes(k)
      cl(rp(k):rp(k + 1) - 1) = pack(sub_of(col(row_ptr(i):row_ptr(i + 1) - 1)), &
          sub_of(col(row_ptr(i):row_ptr(i + 1) - 1)) > 0)
    end do
    call nested_dissection(ni, rp, cl, sub_order, err)
    if (err /= 0) return
    order(1:ni) = nodes(sub_order)
    order(ni + 1:n) = tail
    ! the pattern with the tail as a clique
    allocate(rp_aug(n + 1), col_aug(row_ptr(n + 1) - 1 + nt*nt))
    mark = 0
    rp_aug(1) = 1
    do i = 1, n
      k = rp_aug(i)
      do p = row_ptr(i), row_ptr(i + 1) - 1
        col_aug(k) = col(p)
        mark(col(p)) = i
        k = k + 1
      end do
      if (last(i)) then
        do p = 1, nt
          if (mark(tail(p)) == i) cycle
          col_aug(k) = tail(p)
          k = k + 1
        end do
      end if
      rp_aug(i + 1) = k
    end do
  end subroutine tail_order

  !> inv(order(k)) = k.
  pure subroutine invert(n, order, inv)
    integer, intent(in) :: n, order(n)
    integer, intent(out) :: inv(n)
    integer :: k
    do k = 1, n
      inv(order(k)) = k
    end do
  end subroutine invert
end module ictus_solver_cholesky
