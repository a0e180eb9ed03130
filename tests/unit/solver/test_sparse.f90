!> Sparse assembly and products against dense matrices built from the same element matrices,
!! and the stiffness product on partitions of a grid against the single-rank one.
program test_sparse
  use ictus_core_kinds, only: dp
  use ictus_solver_sparse, only: graph_t, bsr_t, csr_t, graph_from_elements, bsr_init, &
      csr_init, bsr_add_element, csr_add_element, bsr_matvec, csr_matvec, csr_row_sums, &
      bsr3_matvec, &
      csr_diagonal, find_col, fused_lumped_step, bsr_upper_t, bsr_upper_init, &
      bsr_matvec_ordered, bsr_upper_matvec
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  call t%start("solver/sparse")
  call test_assembly_and_products(t)
  call test_blocks3(t)
  call test_partitions(t)
  call test_summation_order(t)
  call test_column_order(t)
  call t%finish()
contains

  !> Three overlapping "elements" on 6 nodes with pseudo-random element matrices.
  subroutine test_assembly_and_products(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: nn = 6, nel = 3, nen = 4
    integer :: conn(nen, nel), nenv(nel), e, a, b, i, j
    real(dp) :: ke(2*nen, 2*nen, nel), me(nen, nen, nel), kd(2*nn, 2*nn), md(nn, nn)
    real(dp) :: x(2, nn), y(2, nn), yd(2*nn), s(nn), d(nn)
    type(graph_t) :: g
    type(bsr_t) :: k
    type(csr_t) :: m
    conn(:, 1) = [1, 2, 5, 4]
    conn(:, 2) = [2, 3, 6, 5]
    conn(:, 3) = [4, 5, 6, 1]
    nenv = nen
    do e = 1, nel
      do j = 1, 2*nen
        do i = 1, 2*nen
          ke(i, j, e) = sin(real(i + 3*j + 7*e, dp))
        end do
      end do
      do j = 1, nen
        do i = 1, nen
          me(i, j, e) = cos(real(2*i + j + 5*e, dp))
        end do
      end do
    end do
    call graph_from_elements(nn, nn, nel, nen, nenv, conn, [(i, i = 1, nn)], g)
    ! neighbours: node 1: 5, node 2: 6, node 3: 4 (not 1 and 4), node 4: 5, nodes 5 and 6: 6
    call t%equal_int(g%row_ptr(nn + 1) - 1, 32, "graph: 32 node pairs share an element")
    call t%true(find_col(g, 3, 4) == 0, "nodes 3 and 4 share no element")
    call t%true(find_col(g, 1, 6) > 0, "find_col finds (1, 6) (element 3)")
    call bsr_init(k, g)
    call csr_init(m, g)
    kd = 0.0_dp
    md = 0.0_dp
    do e = 1, nel
      call bsr_add_element(k, nen, conn(:, e), ke(:, :, e))
      call csr_add_element(m, nen, conn(:, e), me(:, :, e))
      do a = 1, nen
        do b = 1, nen
          kd(2*conn(a, e) - 1:2*conn(a, e), 2*conn(b, e) - 1:2*conn(b, e)) = &
              kd(2*conn(a, e) - 1:2*conn(a, e), 2*conn(b, e) - 1:2*conn(b, e)) &
              + ke(2*a - 1:2*a, 2*b - 1:2*b, e)
          md(conn(a, e), conn(b, e)) = md(conn(a, e), conn(b, e)) + me(a, b, e)
        end do
      end do
    end do
    do i = 1, nn
      x(:, i) = [real(i, dp), 1.0_dp/real(i, dp)]
    end do
    call bsr_matvec(nn, k%g%row_ptr, k%g%col, k%val, x, y)
    yd = matmul(kd, reshape(x, [2*nn]))
    call t%close_abs(maxval(abs(reshape(y, [2*nn]) - yd)), 0.0_dp, 1e-12_dp, "K x = dense K x")
    call csr_matvec(nn, m%g%row_ptr, m%g%col, m%val, x, y)
    call t%close_abs(maxval(abs(y(1, :) - matmul(md, x(1, :)))), 0.0_dp, 1e-12_dp, &
        "M x (component 1) = dense")
    call t%close_abs(maxval(abs(y(2, :) - matmul(md, x(2, :)))), 0.0_dp, 1e-12_dp, &
        "M x (component 2) = dense")
    call csr_row_sums(m, s)
    call t%close_abs(maxval(abs(s - sum(md, dim=2))), 0.0_dp, 1e-12_dp, "row sums")
    call csr_diagonal(m, d)
    call t%close_abs(maxval(abs(d - [(md(i, i), i = 1, nn)])), 0.0_dp, 1e-14_dp, "diagonal")
  end subroutine test_assembly_and_products

  !> 3x3 blocks (3D): the same mesh assembled with ke(3 nen, 3 nen); bsr3_matvec against the
  !! dense product (1e-12) and against the documented order of its sums, bit for bit: per row
  !! the blocks alternately into two partial sums, each block's three products added in
  !! column order, the two sums added at the end.
  subroutine test_blocks3(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: nn = 6, nel = 3, nen = 4
    integer :: conn(nen, nel), nenv(nel), e, a, b, i, j, q, c
    real(dp) :: ke(3*nen, 3*nen, nel), kd(3*nn, 3*nn), x(3, nn), y(3, nn), yd(3*nn), &
        sa(3), sb(3), tk(3)
    type(graph_t) :: g
    type(bsr_t) :: k
    conn(:, 1) = [1, 2, 5, 4]
    conn(:, 2) = [2, 3, 6, 5]
    conn(:, 3) = [4, 5, 6, 1]
    nenv = nen
    do e = 1, nel
      do j = 1, 3*nen
        do i = 1, 3*nen
          ke(i, j, e) = sin(real(i + 3*j + 7*e, dp))
        end do
      end do
    end do
    call graph_from_elements(nn, nn, nel, nen, nenv, conn, [(i, i = 1, nn)], g)
    call bsr_init(k, g, 3)
    call t%equal_int(size(k%val, 1), 3, 'blocks 3x3')
    kd = 0.0_dp
    do e = 1, nel
      call bsr_add_element(k, nen, conn(:, e), ke(:, :, e))
      do a = 1, nen
        do b = 1, nen
          kd(3*conn(a, e) - 2:3*conn(a, e), 3*conn(b, e) - 2:3*conn(b, e)) = &
              kd(3*conn(a, e) - 2:3*conn(a, e), 3*conn(b, e) - 2:3*conn(b, e)) &
              + ke(3*a - 2:3*a, 3*b - 2:3*b, e)
        end do
      end do
    end do
    do i = 1, nn
      x(:, i) = [real(i, dp), 1.0_dp/real(i, dp), sqrt(real(i, dp))]
    end do
    call bsr3_matvec(nn, k%g%row_ptr, k%g%col, k%val, x, y)
    yd = matmul(kd, reshape(x, [3*nn]))
    call t%close_abs(maxval(abs(reshape(y, [3*nn]) - yd)), 0.0_dp, 1.0e-12_dp, &
        '3x3 blocks: K x = dense K x')
    do i = 1, nn
      sa = 0.0_dp
      sb = 0.0_dp
      do q = k%g%row_ptr(i), k%g%row_ptr(i + 1) - 1
        j = k%g%col(q)
        do c = 1, 3
          tk(c) = (k%val(c, 1, q)*x(1, j) + k%val(c, 2, q)*x(2, j)) + k%val(c, 3, q)*x(3, j)
        end do
        if (mod(q - k%g%row_ptr(i), 2) == 0) then
          sa = sa + tk
        else
          sb = sb + tk
        end if
      end do
      call t%true(all(y(:, i) == sa + sb), '3x3 blocks: the documented order, bit for bit')
    end do
  end subroutine test_blocks3
  !> A 7 x 5 grid of 4-node elements with pseudo-random element matrices, cut into parts as
  !! METIS would (by element). Each part builds its rows as a rank does (owned nodes in
  !! increasing global index, ghosts after them in another order);
  !! K x on its owned nodes must be the single-rank result bit for bit, for the plain product
  !! and for the fused lumped step.
  subroutine test_partitions(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: ex = 7, ey = 5, nel = ex*ey, nn = (ex + 1)*(ey + 1), nen = 4
    integer :: conn(nen, nel), part(nel), gid(nn), e, i, j, a, b, np, p, k, nown, nloc
    real(dp) :: ke(2*nen, 2*nen, nel), xg(2, nn), yg(2, nn), vg(2, nn), ung(2, nn)
    real(dp) :: inv_m(2, nn), dt, yl(2, nn), unl(2, nn)
    real(dp), allocatable :: kd(:,:)
    logical :: same_k, same_fused
    do j = 1, ey
      do i = 1, ex
        e = i + (j - 1)*ex
        a = i + (j - 1)*(ex + 1)
        conn(:, e) = [a, a + 1, a + ex + 2, a + ex + 1]
        do b = 1, 2*nen
          do a = 1, 2*nen
            ke(a, b, e) = sin(real(a + 3*b + 7*e, dp)) + merge(4.0_dp, 0.0_dp, a == b)
          end do
        end do
      end do
    end do
    do i = 1, nn
      xg(:, i) = [cos(real(3*i, dp)), sin(real(5*i, dp))]
      vg(:, i) = [sin(real(2*i, dp)), cos(real(i, dp))]
      inv_m(:, i) = 1.0_dp/(1.0_dp + real(mod(i, 3), dp))
    end do
    dt = 0.01_dp
    ! single rank: the reference, and a check against the dense symmetric matrix
    part = 0
    call part_product(conn, ke, part, 0, xg, vg, inv_m, dt, yg, ung, gid, nown, nloc)
    allocate(kd(2*nn, 2*nn), source=0.0_dp)
    do e = 1, nel
      do a = 1, nen
        do b = 1, nen
          kd(2*conn(a, e) - 1:2*conn(a, e), 2*conn(b, e) - 1:2*conn(b, e)) = &
              kd(2*conn(a, e) - 1:2*conn(a, e), 2*conn(b, e) - 1:2*conn(b, e)) &
              + ke(2*a - 1:2*a, 2*b - 1:2*b, e)
        end do
      end do
    end do
    call t%close_abs(maxval(abs(reshape(yg, [2*nn]) - matmul(kd, reshape(xg, [2*nn])))), &
        0.0_dp, 1e-12_dp, "grid: K x (one part) = dense K x")
    ! 2, 3 and 4 parts: vertical strips, a checkerboard, stripes across the numbering
    do np = 2, 4
      call grid_parts(np, ex, part)
      same_k = .true.
      same_fused = .true.
      do p = 0, np - 1
        call part_product(conn, ke, part, p, xg, vg, inv_m, dt, yl, unl, gid, nown, nloc)
        do k = 1, nown
          if (any(yl(:, k) /= yg(:, gid(k)))) same_k = .false.
          if (any(unl(:, k) /= ung(:, gid(k)))) same_fused = .false.
        end do
      end do
      call t%true(same_k, "grid: K x on every part of " // char(48 + np) // &
          " = one part, bit for bit")
      call t%true(same_fused, "grid: fused lumped step on every part of " // char(48 + np) &
          // " = one part, bit for bit")
    end do
  end subroutine test_partitions

  !> The elements of a grid ex elements wide cut into np = 2, 3 or 4 parts: vertical strips,
  !! a checkerboard, stripes across the numbering.
  pure subroutine grid_parts(np, ex, part)
    integer, intent(in) :: np, ex
    integer, intent(out) :: part(:)
    integer :: e, i, j
    do e = 1, size(part)
      i = mod(e - 1, ex) + 1
      j = (e - 1)/ex + 1
      select case (np)
      case (2)
        part(e) = merge(0, 1, i <= 3)
      case (3)
        part(e) = mod(i/2 + j/2, 3)
      case default
        part(e) = count(j > [2, 3, 4])
      end select
    end do
  end subroutine grid_parts

  !> K x and the fused lumped step's u_next on the nodes of part p, built as a rank builds
  !! them: owned nodes (lowest part of their elements) by increasing global index, then the
  !! ghosts, here by decreasing global index; the elements that hold an owned node. gid(k) is
  !! the global index of local node k. u_next is returned huge when the fused step's
  !! velocities differ from the separate passes'.
  subroutine part_product(conn, ke, part, p, xg, vg, inv_m, dt, y, u_next, gid, nown, nloc, &
      yo, yu)
    integer, intent(in) :: conn(:,:), part(:), p
    real(dp), intent(in) :: ke(:,:,:), xg(:,:), vg(:,:), inv_m(:,:), dt
    real(dp), intent(out) :: y(:,:), u_next(:,:)
    integer, intent(out) :: gid(:), nown, nloc
    real(dp), intent(out), optional :: yo(:,:), yu(:,:)
    type(bsr_upper_t) :: up
    integer :: own(size(xg, 2)), g2l(size(xg, 2)), lconn(size(conn, 1), size(conn, 2))
    integer :: nenv(size(conn, 2)), elems(size(conn, 2)), nn, nen, nell, g, k, e
    logical :: needed(size(xg, 2))
    type(graph_t) :: gr
    type(bsr_t) :: kf
    real(dp), allocatable :: xl(:,:), vl(:,:), fl(:,:), iml(:,:), un(:,:)
    nn = size(xg, 2)
    nen = size(conn, 1)
    own = huge(1)
    do e = 1, size(conn, 2)
      own(conn(:, e)) = min(own(conn(:, e)), part(e))
    end do
    needed = .false.
    nell = 0
    do e = 1, size(conn, 2)
      if (any(own(conn(:, e)) == p)) then
        nell = nell + 1
        elems(nell) = e
        needed(conn(:, e)) = .true.
      end if
    end do
    nown = 0
    do g = 1, nn
      if (own(g) == p) then
        nown = nown + 1
        gid(nown) = g
      end if
    end do
    nloc = nown
    do g = nn, 1, -1
      if (needed(g) .and. own(g) /= p) then
        nloc = nloc + 1
        gid(nloc) = g
      end if
    end do
    g2l = 0
    do k = 1, nloc
      g2l(gid(k)) = k
    end do
    do k = 1, nell
      lconn(:, k) = g2l(conn(:, elems(k)))
    end do
    nenv = nen
    call graph_from_elements(nown, nloc, nell, nen, nenv(1:nell), lconn(:, 1:nell), &
        gid(1:nloc), gr)
    call bsr_init(kf, gr)
    do k = 1, nell
      call bsr_add_element(kf, nen, lconn(:, k), ke(:, :, elems(k)))
    end do
    allocate(xl(2, nloc), vl(2, nloc), iml(2, nloc), fl(2, nloc))
    xl(:, :) = xg(:, gid(1:nloc))
    vl(:, :) = vg(:, gid(1:nloc))
    iml(:, :) = inv_m(:, gid(1:nloc))
    fl = 1.0e300_dp
    if (present(yo)) then
      ! the products in column order: full rows, and the upper blocks where they qualify
      ! (huge where they do not)
      call bsr_matvec_ordered(nown, kf%g%row_ptr, kf%g%col, kf%val, xl, fl)
      yo = 0.0_dp
      yo(:, 1:nloc) = fl
      call bsr_upper_init(kf, up)
      yu = huge(1.0_dp)
      if (up%n == nown) then
        fl = 1.0e300_dp
        call bsr_upper_matvec(up, xl, fl)
        yu = 0.0_dp
        yu(:, 1:nloc) = fl
      end if
      fl = 1.0e300_dp
    end if
    call bsr_matvec(nown, kf%g%row_ptr, kf%g%col, kf%val, xl, fl)
    y = 0.0_dp
    y(:, 1:nloc) = fl
    allocate(un(2, nloc))
    un = 7.0_dp
    call fused_lumped_step(nown, kf%g%row_ptr, kf%g%col, kf%val, iml, dt, xl, vl, un)
    u_next = 0.0_dp
    u_next(:, 1:nloc) = un
    ! the fused step is the separate passes in the same order: the same bits
    if (any(vl(:, 1:nown) /= vg(:, gid(1:nown)) + dt*((-y(:, 1:nown))*iml(:, 1:nown)))) &
        u_next = huge(1.0_dp)
  end subroutine part_product

  !> bsr_matvec sums each row in the documented order, bit for bit: each block's two
  !! products first, then the blocks alternately into two partial sums (odd and even
  !! positions), added at the end. The reproducible results across ranks rest on this order,
  !! and the kernel is C (bsr_kernel.c), so the order is written out here in Fortran again.
  !! Rows of 1 to 40 blocks (odd and even counts), scattered columns, values of mixed signs
  !! and magnitudes (so that another order would change the bits); the whole matrix at once
  !! and in chunks of rows as the fused step calls it; the arrays are exactly as long as the
  !! matrix, so the prefetch runs past their end (it must not fault).
  subroutine test_summation_order(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: n = 400, ncol = 997
    integer :: row_ptr(n + 1), i, k, j, i0, nbad
    integer, allocatable :: col(:)
    real(dp), allocatable :: val(:,:,:)
    real(dp) :: x(2, ncol), y(2, n), yc(2, n), a1, a2, b1, b2, p1, p2
    call random_rows(n, ncol, row_ptr, col, val, x)
    call bsr_matvec(n, row_ptr, col, val, x, y)
    nbad = 0
    do i = 1, n
      a1 = 0.0_dp
      a2 = 0.0_dp
      b1 = 0.0_dp
      b2 = 0.0_dp
      do k = row_ptr(i), row_ptr(i + 1) - 1
        j = col(k)
        p1 = val(1, 1, k)*x(1, j) + val(1, 2, k)*x(2, j)
        p2 = val(2, 1, k)*x(1, j) + val(2, 2, k)*x(2, j)
        if (mod(k - row_ptr(i), 2) == 0) then
          a1 = a1 + p1
          a2 = a2 + p2
        else
          b1 = b1 + p1
          b2 = b2 + p2
        end if
      end do
      if (y(1, i) /= a1 + b1 .or. y(2, i) /= a2 + b2) nbad = nbad + 1
    end do
    call t%equal_int(nbad, 0, "bsr_matvec: rows of 1-40 blocks summed in the documented order")
    yc = huge(1.0_dp)
    do i0 = 1, n, 37
      call bsr_matvec(min(37, n - i0 + 1), row_ptr(i0), col, val, x, yc(1, i0))
    end do
    call t%true(all(yc == y), "bsr_matvec: in chunks of 37 rows, the same bits")
  end subroutine test_summation_order

  !> n rows of 1 to 40 blocks ((1 + mod(7 i, 40)), odd and even counts) with scattered
  !! columns among ncol, values of mixed signs and magnitudes (so that another order of a
  !! sum would change its bits), and x(2, ncol) alike.
  subroutine random_rows(n, ncol, row_ptr, col, val, x)
    integer, intent(in) :: n, ncol
    integer, intent(out) :: row_ptr(n + 1)
    integer, allocatable, intent(out) :: col(:)
    real(dp), allocatable, intent(out) :: val(:,:,:)
    real(dp), intent(out) :: x(2, ncol)
    integer :: i, k, m, j
    row_ptr(1) = 1
    do i = 1, n
      row_ptr(i + 1) = row_ptr(i) + 1 + mod(7*i, 40)
    end do
    m = row_ptr(n + 1) - 1
    allocate(col(m), val(2, 2, m))
    do k = 1, m
      col(k) = 1 + mod(37*k + k*k, ncol)
      val(:, 1, k) = [sin(1.3_dp*k)*10.0_dp**mod(k, 7), cos(0.7_dp*k)]
      val(:, 2, k) = [-sin(2.1_dp*k)*10.0_dp**(-mod(k, 5)), cos(3.1_dp*k)*1.0e3_dp]
    end do
    do j = 1, ncol
      x(:, j) = [sin(0.37_dp*j)*10.0_dp**mod(j, 4), -cos(0.91_dp*j)]
    end do
  end subroutine random_rows

  !> The product of the consistent-mass step, summed in column order: each row one chain over
  !! its blocks in column order, y_i = ((0 + t_1) + t_2) + ..., t_k = A_ik(:, 1) x_k1 +
  !! A_ik(:, 2) x_k2, written out here in Fortran (the kernels are C) on the rows of 1-40
  !! blocks of `test_summation_order`; then on the 7 x 5 grid of `test_partitions` with
  !! symmetric element matrices: the upper blocks qualify on one part and give the bits of
  !! the full rows; every part of 2-4 gives the one-part bits with the full rows; the upper
  !! storage is refused where a part has ghosts, and where K is not symmetric bit for bit.
  subroutine test_column_order(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: n = 400, ncol = 997
    integer, parameter :: ex = 7, ey = 5, nel = ex*ey, nn = (ex + 1)*(ey + 1), nen = 4
    integer :: row_ptr(n + 1), i, k, j, nbad, e, a, b, np, p, nown, nloc
    integer :: conn(nen, nel), part(nel), gid(nn)
    integer, allocatable :: col(:)
    real(dp), allocatable :: val(:,:,:)
    real(dp) :: x(2, ncol), y(2, n), a1, a2
    real(dp) :: ke(2*nen, 2*nen, nel), xg(2, nn), vg(2, nn), inv_m(2, nn), yg(2, nn), ung(2, nn)
    real(dp) :: yo1(2, nn), yu1(2, nn), yl(2, nn), unl(2, nn), yo(2, nn), yu(2, nn)
    logical :: same, refused
    call random_rows(n, ncol, row_ptr, col, val, x)
    call bsr_matvec_ordered(n, row_ptr, col, val, x, y)
    nbad = 0
    do i = 1, n
      a1 = 0.0_dp
      a2 = 0.0_dp
      do k = row_ptr(i), row_ptr(i + 1) - 1
        j = col(k)
        a1 = a1 + (val(1, 1, k)*x(1, j) + val(1, 2, k)*x(2, j))
        a2 = a2 + (val(2, 1, k)*x(1, j) + val(2, 2, k)*x(2, j))
      end do
      if (y(1, i) /= a1 .or. y(2, i) /= a2) nbad = nbad + 1
    end do
    call t%equal_int(nbad, 0, "bsr_matvec_ordered: rows of 1-40 blocks in column order")
    ! the grid, element matrices symmetric bit for bit (upper triangle mirrored)
    do j = 1, ey
      do i = 1, ex
        e = i + (j - 1)*ex
        a = i + (j - 1)*(ex + 1)
        conn(:, e) = [a, a + 1, a + ex + 2, a + ex + 1]
        do b = 1, 2*nen
          do a = 1, b
            ke(a, b, e) = sin(real(a + 3*b + 7*e, dp))*10.0_dp**mod(a + b, 5) &
                + merge(4.0_dp, 0.0_dp, a == b)
            ke(b, a, e) = ke(a, b, e)
          end do
        end do
      end do
    end do
    do i = 1, nn
      xg(:, i) = [cos(real(3*i, dp))*10.0_dp**mod(i, 3), sin(real(5*i, dp))]
      vg(:, i) = 0.0_dp
      inv_m(:, i) = 1.0_dp
    end do
    part = 0
    call part_product(conn, ke, part, 0, xg, vg, inv_m, 0.01_dp, yg, ung, gid, nown, nloc, &
        yo1, yu1)
    call t%true(all(yu1 /= huge(1.0_dp)), "one part: the upper blocks qualify")
    call t%true(all(yu1 == yo1), "one part: upper blocks give the bits of the full rows")
    call t%close_abs(maxval(abs(yo1 - yg))/maxval(abs(yg)), 0.0_dp, 1e-14_dp, &
        "one part: column order = the two-chain product to round-off")
    do np = 2, 4
      call grid_parts(np, ex, part)
      same = .true.
      refused = .true.
      do p = 0, np - 1
        call part_product(conn, ke, part, p, xg, vg, inv_m, 0.01_dp, yl, unl, gid, nown, &
            nloc, yo, yu)
        do k = 1, nown
          if (any(yo(:, k) /= yo1(:, gid(k)))) same = .false.
        end do
        if (nloc > nown .and. any(yu /= huge(1.0_dp))) refused = .false.
      end do
      call t%true(same, "grid: column order on every part of " // char(48 + np) // &
          " = one part, bit for bit")
      call t%true(refused, "grid: upper storage refused on the parts with ghosts (" // &
          char(48 + np) // " parts)")
    end do
    ! one entry not symmetric in its last bit (nodes 2 and 4 of an element: a pair no other
    ! element holds, so K holds that entry alone): the upper storage is refused
    ke(3, 8, 17) = nearest(ke(3, 8, 17), 1.0_dp)
    part = 0
    call part_product(conn, ke, part, 0, xg, vg, inv_m, 0.01_dp, yg, ung, gid, nown, nloc, &
        yo1, yu1)
    call t%true(all(yu1 == huge(1.0_dp)), "K not symmetric bit for bit: upper storage refused")
  end subroutine test_column_order
end program test_sparse
