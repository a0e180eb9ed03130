!> Sparse Cholesky (ictus_solver_cholesky) against independent facts: the dense factor
!! reproduces A; the fill of a banded matrix in natural order is its band; nested dissection
!! fills less; solves of a bilinear-element mass matrix return the field that made the
!! right-hand side; fixed rows give zero and leave the rest of the system intact; a matrix
!! that is not positive definite is reported at its row.
program test_cholesky
  use ictus_core_kinds, only: dp, i8
  use ictus_solver_cholesky, only: chol_t, chol_analyse, chol_factor, chol_solve, &
      dense_cholesky, tail_order
  use ictus_parallel_partition, only: nested_dissection
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  call t%start("solver/cholesky")
  call test_dense(t)
  call test_fill(t)
  call test_mass_solves(t)
  call test_not_positive(t)
  call t%finish()
contains

  !> A = B B^T + n I (n = 150: three panels, so dtrsm and dsyrk run) is L L^T to round-off.
  subroutine test_dense(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: n = 150
    real(dp), allocatable :: b(:,:), a(:,:), l(:,:)
    real(dp) :: err
    integer :: i, j, ierr
    allocate(b(n, n))
    do j = 1, n
      do i = 1, n
        b(i, j) = sin(real(3*i + 7*j, dp))
      end do
    end do
    a = matmul(b, transpose(b))
    do i = 1, n
      a(i, i) = a(i, i) + n
    end do
    l = a
    call dense_cholesky(n, l, n, ierr)
    call t%equal_int(ierr, 0, "dense: B B^T + n I is positive definite")
    do j = 1, n
      l(1:j - 1, j) = 0.0_dp
    end do
    err = maxval(abs(matmul(l, transpose(l)) - a))/maxval(abs(a))
    call t%true(err < 1.0e-14_dp, "dense: L L^T = A to 1e-14 (got "//trim(rstr(err))//")")
  end subroutine test_dense

  !> Fill: for a 9-point grid pattern of nx x ny nodes numbered row by row, L fills the
  !! envelope exactly: row k of L runs from the first column of row k of A to k (every
  !! column in between is reached through lower-numbered nodes of the grid rows below).
  !! Nested dissection of a 40 x 40 grid must fill less.
  subroutine test_fill(t)
    type(checker_t), intent(inout) :: t
    integer, allocatable :: row_ptr(:), col(:), order(:)
    real(dp), allocatable :: val(:)
    type(chol_t) :: ch
    integer(i8) :: want
    integer :: n, j, ierr, nx, ny
    nx = 7
    ny = 9
    call grid_mass(nx, ny, row_ptr, col, val)
    n = nx*ny
    allocate(order(n))
    order = [(j, j = 1, n)]
    call chol_analyse(ch, n, row_ptr, col, order, 1, ierr)
    want = 0
    do j = 1, n
      want = want + j - minval(col(row_ptr(j):row_ptr(j + 1) - 1)) + 1
    end do
    call t%true(ch%nnz == want, "natural order fills the envelope: nnz(L) = "// &
        trim(istr(ch%nnz))//" (envelope: "//trim(istr(want))//")")
    call t%true(ch%rix_ptr(ch%nsup + 1) - 1 <= ch%nnz, "supernodal row lists are no longer than L")
    nx = 40
    ny = 40
    call grid_mass(nx, ny, row_ptr, col, val)
    n = nx*ny
    deallocate(order)
    allocate(order(n))
    order = [(j, j = 1, n)]
    call chol_analyse(ch, n, row_ptr, col, order, 1, ierr)
    want = ch%nnz
    call nested_dissection(n, row_ptr, col, order, ierr)
    call t%equal_int(ierr, 0, "METIS orders the 40 x 40 grid")
    call chol_analyse(ch, n, row_ptr, col, order, 1, ierr)
    call t%true(ch%nnz < want*7/10, "nested dissection fills less than the envelope: "// &
        trim(istr(ch%nnz))//" < 0.7 x "//trim(istr(want)))
    call t%true(all(ch%order > 0) .and. all(ch%inv(ch%order) == [(j, j = 1, n)]), &
        "the pivot order is a permutation")
  end subroutine test_fill

  !> M x = M x* returns x* (bilinear mass on a 23 x 17 grid: kappa <= 9 after the diagonal
  !! scaling, so x agrees to ~1e-13); with the left column fixed in component 1 only, the
  !! fixed dofs come out 0 and the free rows satisfy M_ff x_f = b_f, with two factors.
  subroutine test_mass_solves(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: nx = 23, ny = 17, n = nx*ny
    integer, allocatable :: row_ptr(:), col(:), order(:), rp_aug(:), col_aug(:)
    real(dp), allocatable :: val(:)
    real(dp) :: xs(2, n), b(2, n), x(2, n), r(2, n), err
    real(dp), allocatable :: work(:,:)
    logical :: keep(n, 2)
    type(chol_t) :: ch
    integer :: i, ierr, c
    call grid_mass(nx, ny, row_ptr, col, val)
    do i = 1, n
      xs(1, i) = cos(0.1_dp*i)
      xs(2, i) = 1.0_dp + sin(0.37_dp*i)
    end do
    call matvec(n, row_ptr, col, val, xs, b)
    allocate(order(n))
    call nested_dissection(n, row_ptr, col, order, ierr)
    keep = .true.
    call chol_analyse(ch, n, row_ptr, col, order, 1, ierr)
    call chol_factor(ch, row_ptr, col, val, keep(:, 1), 1, ierr)
    call t%equal_int(ierr, 0, "mass: factorised")
    allocate(work(ch%max_rows, 2))
    do i = 1, n
      x(:, ch%inv(i)) = b(:, i)
    end do
    call chol_solve(ch, [1, 1], x, work)
    x(:, :) = x(:, ch%inv)
    err = maxval(abs(x - xs))/maxval(abs(xs))
    call t%true(err < 1.0e-13_dp, "mass: M^-1 (M x*) = x* (rel. error "//trim(rstr(err))//")")

    ! component 1 fixed on the left column (x = 0): two factors
    do i = 1, n
      keep(i, 1) = mod(i - 1, nx) /= 0
    end do
    call chol_analyse(ch, n, row_ptr, col, order, 2, ierr)
    do c = 1, 2
      call chol_factor(ch, row_ptr, col, val, keep(:, c), c, ierr)
      call t%equal_int(ierr, 0, "mass with fixed dofs: factor "//char(48 + c))
    end do
    do i = 1, n
      x(1, ch%inv(i)) = merge(b(1, i), 0.0_dp, keep(i, 1))
      x(2, ch%inv(i)) = b(2, i)
    end do
    call chol_solve(ch, [1, 2], x, work)
    x(:, :) = x(:, ch%inv)
    call t%true(all(x(1, :) == 0.0_dp .or. keep(:, 1)), "fixed dofs: x = 0 exactly")
    call matvec(n, row_ptr, col, val, x, r)
    err = 0.0_dp
    do i = 1, n
      if (keep(i, 1)) err = max(err, abs(r(1, i) - b(1, i)))
    end do
    err = err/maxval(abs(b(1, :)))
    call t%true(err < 1.0e-14_dp, "fixed dofs: free rows solve M_ff x_f = b_f (residual "// &
        trim(rstr(err))//")")
    err = maxval(abs(x(2, :) - xs(2, :)))/maxval(abs(xs(2, :)))
    call t%true(err < 1.0e-13_dp, "second factor: component 2 unchanged (rel. error "// &
        trim(rstr(err))//")")

    ! the same with one shared factor and a dense tail: the left column in component 1 and
    ! the bottom row in component 2 are fixed; the corner node in both (an identity row)
    do i = 1, n
      keep(i, 1) = mod(i - 1, nx) /= 0
      keep(i, 2) = i > nx
    end do
    call tail_order(n, row_ptr, col, keep(:, 1) .neqv. keep(:, 2), order, rp_aug, col_aug, ierr)
    call chol_analyse(ch, n, rp_aug, col_aug, order, 1, ierr, count(keep(:, 1) .neqv. keep(:, 2)))
    call t%equal_int(ch%ntail, nx + ny - 2, "tail: the dofs fixed in one component only")
    call t%equal_int(ch%first(ch%nsup + 1) - ch%first(ch%nsup), ch%ntail, &
        "tail: the last supernode is the tail")
    call t%true(all(.not. (keep(ch%order(n - ch%ntail + 1:), 1) .eqv. &
        keep(ch%order(n - ch%ntail + 1:), 2))), "tail: its pivots are those dofs")
    call chol_factor(ch, row_ptr, col, val, keep(:, 1) .or. keep(:, 2), 1, ierr, keep)
    call t%equal_int(ierr, 0, "tail: factorised")
    deallocate(work)
    allocate(work(ch%max_rows, 2))
    do i = 1, n
      do c = 1, 2
        x(c, ch%inv(i)) = merge(b(c, i), 0.0_dp, keep(i, c))
      end do
    end do
    call chol_solve(ch, [1, 1], x, work)
    x(:, :) = x(:, ch%inv)
    call t%true(all(x(1, :) == 0.0_dp .or. keep(:, 1)) .and. &
        all(x(2, :) == 0.0_dp .or. keep(:, 2)), "tail: fixed dofs x = 0 exactly")
    call matvec(n, row_ptr, col, val, x, r)
    err = 0.0_dp
    do i = 1, n
      do c = 1, 2
        if (keep(i, c)) err = max(err, abs(r(c, i) - b(c, i))/maxval(abs(b(c, :))))
      end do
    end do
    call t%true(err < 1.0e-14_dp, "tail: free rows of both components solve M_ff x_f = b_f "// &
        "(residual "//trim(rstr(err))//")")
  end subroutine test_mass_solves

  !> A diagonal matrix with one negative entry is reported at that row.
  subroutine test_not_positive(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: n = 10
    integer :: row_ptr(n + 1), col(n), i, ierr
    real(dp) :: val(n)
    logical :: keep(n)
    type(chol_t) :: ch
    row_ptr = [(i, i = 1, n + 1)]
    col = [(i, i = 1, n)]
    val = 1.0_dp
    val(7) = -2.0_dp
    keep = .true.
    call chol_analyse(ch, n, row_ptr, col, [(n + 1 - i, i = 1, n)], 1, ierr)
    call chol_factor(ch, row_ptr, col, val, keep, 1, ierr)
    call t%equal_int(ierr, 7, "not positive definite: reported at row 7")
    keep(7) = .false.
    call chol_factor(ch, row_ptr, col, val, keep, 1, ierr)
    call t%equal_int(ierr, 0, "the same row not kept: factorised")
  end subroutine test_not_positive

  !> Consistent mass of bilinear elements (h = 1, rho = 1) on a grid of nx x ny nodes, full
  !! rows: element matrix (1/36) [4 2 1 2; 2 4 2 1; 1 2 4 2; 2 1 2 4].
  subroutine grid_mass(nx, ny, row_ptr, col, val)
    integer, intent(in) :: nx, ny
    integer, allocatable, intent(out) :: row_ptr(:), col(:)
    real(dp), allocatable, intent(out) :: val(:)
    real(dp), parameter :: me(4, 4) = reshape([4, 2, 1, 2, 2, 4, 2, 1, 1, 2, 4, 2, 2, 1, 2, &
        4]/36.0_dp, [4, 4])
    integer :: ix, iy, i, j, k, a, bb, e(4), n, p
    n = nx*ny
    allocate(row_ptr(n + 1))
    row_ptr(1) = 1
    do i = 1, n
      ix = mod(i - 1, nx)
      iy = (i - 1)/nx
      row_ptr(i + 1) = row_ptr(i) + (min(ix + 1, nx - 1) - max(ix - 1, 0) + 1)* &
          (min(iy + 1, ny - 1) - max(iy - 1, 0) + 1)
    end do
    allocate(col(row_ptr(n + 1) - 1), val(row_ptr(n + 1) - 1))
    do i = 1, n
      ix = mod(i - 1, nx)
      iy = (i - 1)/nx
      k = row_ptr(i)
      do j = max(iy - 1, 0), min(iy + 1, ny - 1)
        do a = max(ix - 1, 0), min(ix + 1, nx - 1)
          col(k) = j*nx + a + 1
          k = k + 1
        end do
      end do
    end do
    val = 0.0_dp
    do iy = 0, ny - 2
      do ix = 0, nx - 2
        e = [iy*nx + ix + 1, iy*nx + ix + 2, (iy + 1)*nx + ix + 2, (iy + 1)*nx + ix + 1]
        do a = 1, 4
          do bb = 1, 4
            do p = row_ptr(e(a)), row_ptr(e(a) + 1) - 1
              if (col(p) == e(bb)) val(p) = val(p) + me(a, bb)
            end do
          end do
        end do
      end do
    end do
  end subroutine grid_mass

  subroutine matvec(n, row_ptr, col, val, x, y)
    integer, intent(in) :: n, row_ptr(:), col(:)
    real(dp), intent(in) :: val(:), x(:,:)
    real(dp), intent(out) :: y(:,:)
    integer :: i, p
    y = 0.0_dp
    do i = 1, n
      do p = row_ptr(i), row_ptr(i + 1) - 1
        y(:, i) = y(:, i) + val(p)*x(:, col(p))
      end do
    end do
  end subroutine matvec

  function rstr(x) result(s)
    real(dp), intent(in) :: x
    character(len=16) :: s
    write(s, '(es10.2)') x
    s = adjustl(s)
  end function rstr

  function istr(i) result(s)
    integer(i8), intent(in) :: i
    character(len=20) :: s
    write(s, '(i0)') i
  end function istr
end program test_cholesky
