!> h- and p-refinement of NURBS curves and surfaces that leave the geometry unchanged.
!!
!! Knot refinement is Piegl & Tiller A5.4 (RefineKnotVectCurve), degree elevation A5.9
!! (DegreeElevateCurve); both work in homogeneous coordinates (w x, w y, w). Control points
!! are passed and returned as cp(d + 1, :) = (x, y[, z], w): the curve routines take any
!! number of coordinates (the first dimension of cp less one). Surface versions apply the curve
!! algorithm to every row (dir = 1) or column (dir = 2) of the control net (direction 1
!! fastest). Internally the algorithms use 0-based arrays exactly as printed in the book.
module ictus_geometry_refine
  use ictus_core_kinds, only: dp
  use ictus_geometry_bspline, only: find_span
  implicit none
  private
  public :: refine_knot_vector, surface_refine, degree_elevate_curve, degree_elevate_surface

contains

  !> Inserts the knots `x_new` (non-decreasing, inside the parameter range) into a NURBS curve.
  !! @param n control points; @param p degree; @param knots (n+p+1);
  !! @param cp (d + 1, n): (x, y[, z], w);
  !! @param x_new knots to insert (any number, may be 0); @param n_out n + size(x_new);
  !! @param knots_out (n_out+p+1); @param cp_out (d + 1, n_out)
  pure subroutine refine_knot_vector(n, p, knots, cp, x_new, n_out, knots_out, cp_out)
    integer, intent(in) :: n, p
    real(dp), intent(in) :: knots(:), cp(:,:), x_new(:)
    integer, intent(out) :: n_out
    real(dp), allocatable, intent(out) :: knots_out(:), cp_out(:,:)
    real(dp) :: pw(size(cp, 1), 0:n-1), qw(size(cp, 1), 0:n+size(x_new)-1)
    real(dp) :: u(0:n+p), ub(0:n+p+size(x_new)), x(0:size(x_new)-1), alfa
    integer :: m, r, a, b, i, j, k, l, ind, nl, nw
    nw = size(cp, 1)
    nl = n - 1
    r = size(x_new) - 1
    n_out = n + size(x_new)
    allocate(knots_out(n_out+p+1), cp_out(nw, n_out))
    if (r < 0) then
      knots_out = knots(1:n+p+1)
      cp_out = cp(:, 1:n)
      return
    end if
    m = nl + p + 1
    u = knots(1:n+p+1)
    x = x_new
    do j = 0, nl
      pw(1:nw-1, j) = cp(1:nw-1, j+1)*cp(nw, j+1)
      pw(nw, j) = cp(nw, j+1)
    end do
    a = find_span(n, p, x(0), knots) - 1
    b = find_span(n, p, x(r), knots) - 1 + 1
    do j = 0, a - p
      qw(:, j) = pw(:, j)
    end do
    do j = b - 1, nl
      qw(:, j+r+1) = pw(:, j)
    end do
    do j = 0, a
      ub(j) = u(j)
    end do
    do j = b + p, m
      ub(j+r+1) = u(j)
    end do
    i = b + p - 1
    k = b + p + r
    do j = r, 0, -1
      do while (x(j) <= u(i) .and. i > a)
        qw(:, k-p-1) = pw(:, i-p-1)
        ub(k) = u(i)
        k = k - 1
        i = i - 1
      end do
      qw(:, k-p-1) = qw(:, k-p)
      do l = 1, p
        ind = k - p + l
        alfa = ub(k+l) - x(j)
        if (abs(alfa) == 0.0_dp) then
          qw(:, ind-1) = qw(:, ind)
        else
          alfa = alfa/(ub(k+l) - u(i-p+l))
          qw(:, ind-1) = alfa*qw(:, ind-1) + (1.0_dp - alfa)*qw(:, ind)
        end if
      end do
      ub(k) = x(j)
      k = k - 1
    end do
    knots_out = ub
    do j = 0, n_out - 1
      cp_out(1:nw-1, j+1) = qw(1:nw-1, j)/qw(nw, j)
      cp_out(nw, j+1) = qw(nw, j)
    end do
  end subroutine refine_knot_vector

  !> Knot refinement of a NURBS surface in direction `dir` (1 or 2).
  !! @param dir direction refined; @param n1, n2 control points per direction;
  !! @param p degree in direction dir; @param knots knot vector of direction dir;
  !! @param cp (3, n1*n2); @param x_new knots to insert; @param n_out new count in dir;
  !! @param knots_out new knot vector of dir; @param cp_out (3, new n1 * new n2)
  pure subroutine surface_refine(dir, n1, n2, p, knots, cp, x_new, n_out, knots_out, cp_out)
    integer, intent(in) :: dir, n1, n2, p
    real(dp), intent(in) :: knots(:), cp(:,:), x_new(:)
    integer, intent(out) :: n_out
    real(dp), allocatable, intent(out) :: knots_out(:), cp_out(:,:)
    real(dp), allocatable :: row(:,:), row_out(:,:)
    integer :: j, nrow, nlen, i
    if (dir == 1) then
      nlen = n1
      nrow = n2
    else
      nlen = n2
      nrow = n1
    end if
    n_out = nlen + size(x_new)
    allocate(row(3, nlen), cp_out(3, n_out*nrow))
    do j = 1, nrow
      do i = 1, nlen
        row(:, i) = cp(:, net_index(dir, i, j, n1))
      end do
      call refine_knot_vector(nlen, p, knots, row, x_new, n_out, knots_out, row_out)
      do i = 1, n_out
        cp_out(:, net_index(dir, i, j, merge(n_out, n1, dir == 1))) = row_out(:, i)
      end do
    end do
  end subroutine surface_refine

  !> Elevates the degree of a NURBS curve from p to p+t (A5.9); interior knot
  !! multiplicities rise by t, the curve is unchanged.
  !! @param n control points; @param p degree; @param knots (n+p+1);
  !! @param cp (d + 1, n): (x, y[, z], w);
  !! @param t elevation (>= 0); @param n_out new number of control points;
  !! @param knots_out (n_out+p+t+1); @param cp_out (d + 1, n_out)
  pure subroutine degree_elevate_curve(n, p, knots, cp, t, n_out, knots_out, cp_out)
    integer, intent(in) :: n, p, t
    real(dp), intent(in) :: knots(:), cp(:,:)
    integer, intent(out) :: n_out
    real(dp), allocatable, intent(out) :: knots_out(:), cp_out(:,:)
    real(dp) :: pw(size(cp, 1), 0:n-1), u(0:n+p), bezalfs(0:p+t, 0:p)
    real(dp) :: bpts(size(cp, 1), 0:p), ebpts(size(cp, 1), 0:p+t), &
        nextbpts(size(cp, 1), 0:max(p-1, 0)), alfs(0:max(p-1, 0))
    real(dp), allocatable :: qw(:,:), uh(:)
    real(dp) :: inv, ua, ub, numer, den, bet, alf, gam
    integer :: m, ph, ph2, i, j, k, mpi, mh, kind, r, a, b, cind, mul, oldr, lbz, rbz
    integer :: save_, s, first, last, tr, kj, nspan, nw
    nw = size(cp, 1)
    if (t <= 0) then
      n_out = n
      knots_out = knots(1:n+p+1)
      cp_out = cp(:, 1:n)
      return
    end if
    m = n + p
    u = knots(1:n+p+1)
    do j = 0, n - 1
      pw(1:nw-1, j) = cp(1:nw-1, j+1)*cp(nw, j+1)
      pw(nw, j) = cp(nw, j+1)
    end do
    ! upper bound of the output sizes: every distinct knot gains t copies
    nspan = 1
    do j = 1, m
      if (u(j) /= u(j-1)) nspan = nspan + 1
    end do
    allocate(qw(nw, 0:n+nspan*t), uh(0:m+1+nspan*t))
    ph = p + t
    ph2 = ph/2
    bezalfs = 0.0_dp
    bezalfs(0, 0) = 1.0_dp
    bezalfs(ph, p) = 1.0_dp
    do i = 1, ph2
      inv = 1.0_dp/binomial(ph, i)
      mpi = min(p, i)
      do j = max(0, i-t), mpi
        bezalfs(i, j) = inv*binomial(p, j)*binomial(t, i-j)
      end do
    end do
    do i = ph2 + 1, ph - 1
      mpi = min(p, i)
      do j = max(0, i-t), mpi
        bezalfs(i, j) = bezalfs(ph-i, p-j)
      end do
    end do
    mh = ph
    kind = ph + 1
    r = -1
    a = p
    b = p + 1
    cind = 1
    ua = u(0)
    qw(:, 0) = pw(:, 0)
    uh(0:ph) = ua
    bpts = pw(:, 0:p)
    ub = ua
    do while (b < m)
      i = b
      do while (b < m)
        if (u(b) /= u(b+1)) exit
        b = b + 1
      end do
      mul = b - i + 1
      mh = mh + mul + t
      ub = u(b)
      oldr = r
      r = p - mul
      lbz = 1
      if (oldr > 0) lbz = (oldr + 2)/2
      rbz = ph
      if (r > 0) rbz = ph - (r + 1)/2
      if (r > 0) then
        ! insert knot ub r times to get the Bezier segment
        numer = ub - ua
        do k = p, mul + 1, -1
          alfs(k-mul-1) = numer/(u(a+k) - ua)
        end do
        do j = 1, r
          save_ = r - j
          s = mul + j
          do k = p, s, -1
            bpts(:, k) = alfs(k-s)*bpts(:, k) + (1.0_dp - alfs(k-s))*bpts(:, k-1)
          end do
          nextbpts(:, save_) = bpts(:, p)
        end do
      end if
      ! degree-elevate the Bezier segment
      do i = lbz, ph
        ebpts(:, i) = 0.0_dp
        mpi = min(p, i)
        do j = max(0, i-t), mpi
          ebpts(:, i) = ebpts(:, i) + bezalfs(i, j)*bpts(:, j)
        end do
      end do
      if (oldr > 1) then
        ! remove knot ua oldr times
        first = kind - 2
        last = kind
        den = ub - ua
        bet = (ub - uh(kind-1))/den
        do tr = 1, oldr - 1
          i = first
          j = last
          kj = j - kind + 1
          do while (j - i > tr)
            if (i < cind) then
              alf = (ub - uh(i))/(ua - uh(i))
              qw(:, i) = alf*qw(:, i) + (1.0_dp - alf)*qw(:, i-1)
            end if
            if (j >= lbz) then
              if (j - tr <= kind - ph + oldr) then
                gam = (ub - uh(j-tr))/den
                ebpts(:, kj) = gam*ebpts(:, kj) + (1.0_dp - gam)*ebpts(:, kj+1)
              else
                ebpts(:, kj) = bet*ebpts(:, kj) + (1.0_dp - bet)*ebpts(:, kj+1)
              end if
            end if
            i = i + 1
            j = j - 1
            kj = kj - 1
          end do
          first = first - 1
          last = last + 1
        end do
      end if
      if (a /= p) then
        do i = 0, ph - oldr - 1
          uh(kind) = ua
          kind = kind + 1
        end do
      end if
      do j = lbz, rbz
        qw(:, cind) = ebpts(:, j)
        cind = cind + 1
      end do
      if (b < m) then
        bpts(:, 0:r-1) = nextbpts(:, 0:r-1)
        do j = r, p
          bpts(:, j) = pw(:, b-p+j)
        end do
        a = b
        b = b + 1
        ua = ub
      end if
    end do
    uh(kind:kind+ph) = ub
    n_out = mh - ph
    allocate(knots_out(n_out+ph+1), cp_out(nw, n_out))
    knots_out = uh(0:n_out+ph)
    do j = 0, n_out - 1
      cp_out(1:nw-1, j+1) = qw(1:nw-1, j)/qw(nw, j)
      cp_out(nw, j+1) = qw(nw, j)
    end do
  end subroutine degree_elevate_curve

  !> Degree elevation of a NURBS surface by t in direction `dir` (1 or 2).
  !! @param dir direction; @param n1, n2 control points per direction; @param p degree in
  !! dir; @param knots knot vector of dir; @param cp (3, n1*n2); @param t elevation;
  !! @param n_out new count in dir; @param knots_out new knot vector of dir;
  !! @param cp_out (3, new n1 * new n2)
  pure subroutine degree_elevate_surface(dir, n1, n2, p, knots, cp, t, n_out, knots_out, &
      cp_out)
    integer, intent(in) :: dir, n1, n2, p, t
    real(dp), intent(in) :: knots(:), cp(:,:)
    integer, intent(out) :: n_out
    real(dp), allocatable, intent(out) :: knots_out(:), cp_out(:,:)
    real(dp), allocatable :: row(:,:), row_out(:,:)
    integer :: j, nrow, nlen, i
    if (dir == 1) then
      nlen = n1
      nrow = n2
    else
      nlen = n2
      nrow = n1
    end if
    allocate(row(3, nlen))
    do j = 1, nrow
      do i = 1, nlen
        row(:, i) = cp(:, net_index(dir, i, j, n1))
      end do
      call degree_elevate_curve(nlen, p, knots, row, t, n_out, knots_out, row_out)
      if (j == 1) allocate(cp_out(3, n_out*nrow))
      do i = 1, n_out
        cp_out(:, net_index(dir, i, j, merge(n_out, n1, dir == 1))) = row_out(:, i)
      end do
    end do
  end subroutine degree_elevate_surface

  !> Index in a control net of point i along direction `dir` in row j across it; `nd1` is
  !! the net's number of points in direction 1.
  pure integer function net_index(dir, i, j, nd1) result(idx)
    integer, intent(in) :: dir, i, j, nd1
    if (dir == 1) then
      idx = i + (j - 1)*nd1
    else
      idx = j + (i - 1)*nd1
    end if
  end function net_index

  !> Binomial coefficient as a real number.
  pure real(dp) function binomial(n, k)
    integer, intent(in) :: n, k
    integer :: j
    binomial = 1.0_dp
    do j = 1, k
      binomial = binomial*real(n + 1 - j, dp)/real(j, dp)
    end do
  end function binomial
end module ictus_geometry_refine
