!> The set-up of MASS SOLVER=KRONECKER (ictus_solver_tensor_types): the 1D matrices of every
!! block read off the assembled mass, the fixed lines and points, the banded factors, and
!! the check that the result solves the mass; the renumbering for gathered vectors and the
!! description for the log.
module ictus_solver_tensor_setup
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: str
  use ictus_core_memory, only: alloc_stream
  use ictus_solver_tensor_types, only: lattice_t, tensor_layout_t, band_t, cond_t, comp_t, &
      tblock_t, tensor_mass_t, TENSOR_DIRECT, TENSOR_SERENDIPITY, max_points, check_tol, &
      col_block
  use ictus_solver_tensor_solve, only: tensor_mass_solve, base_solve, nodal_value
  implicit none
  private
  public :: tensor_mass_setup, tensor_mass_renumber, tensor_mass_describe

contains

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
end module ictus_solver_tensor_setup
