!> Contact surfaces: chains of segments, each a 2- or 3-node Lagrange edge of a finite element
!! or a rational Bezier segment (one knot span of a NURBS patch side).
!!
!! Every segment has a local parameter t in [0, 1] and stores its global nodes (or control
!! points) in order of increasing t, oriented counter-clockwise around its body: the body lies
!! on the left of the tangent x'(t), and the outward normal is n = (t_y, -t_x) with
!! t = x'/|x'|. Shape functions R_A(t):
!! * Lagrange, 2 nodes at t = 0, 1: (1 - t, t);
!! * Lagrange, 3 nodes at t = 0, 1/2, 1: ((1-t)(1-2t), 4t(1-t), t(2t-1));
!! * rational Bezier of degree p: N_A = sum_j C(A, j) B_j(t) (Bernstein B_j, extraction
!!   operator C of the span), R_A = w_A N_A / sum_B w_B N_B.
!! Gauss points and the nodal weights l_A = int R_A dGamma are set up on the reference
!! configuration.
module ictus_contact_surface
  use ictus_core_kinds, only: dp, str_len
  use ictus_elements_quadrature, only: gauss_legendre
  use ictus_elements_types, only: element_kind_t
  use ictus_elements_library, only: element_kind
  use ictus_geometry_patch, only: patch_t, patch_point, patch_side_elements, patch_elem_ij
  use ictus_geometry_bezier, only: bernstein_d2, de_casteljau, BEZIER_MAX_DEGREE
  use ictus_core_errors, only: input_error
  implicit none
  private
  public :: contact_surface_t, SEG_LAGRANGE, SEG_BEZIER, surface_init, surface_free, &
      segment_shape, segment_geometry, segment_bbox, face_segment, element_area, &
      patch_side_segments, reverse_segment, MAX_SEG_NODES, segment_curve_t, segment_curve, &
      surface_curves, curve_point, curve_geometry, CURVE_SAMPLES

  !> Largest number of nodes of a segment (degree 15, the most the Bezier evaluation of
  !! ictus_geometry_bezier takes): the size of the fixed local arrays of the contact kernels,
  !! so that a contact step allocates nothing.
  integer, parameter :: MAX_SEG_NODES = BEZIER_MAX_DEGREE + 1

  !> A segment curve keeps its points at t_k = k/CURVE_SAMPLES, k = 0..CURVE_SAMPLES: the
  !! closest-point projection starts at the nearest of them.
  integer, parameter :: CURVE_SAMPLES = 4

  !> Segment kinds.
  integer, parameter :: SEG_LAGRANGE = 1, SEG_BEZIER = 2

  !> One segment on given coordinates in Bezier form, for many evaluations at fixed
  !! positions: x(t) = x_0 + A(t)/W(t), (A, W)(t) = sum_j B_j(t) h_j, with the Bernstein
  !! polynomials B_j of degree p and the homogeneous Bezier points
  !! h_j = sum_A C(A, j) w_A (x_A - x_0, 1). A Lagrange edge is a polynomial Bezier curve
  !! (W = 1): h = x_1, x_2 for 2 nodes; x_1, 2 x_mid - (x_1 + x_3)/2, x_3 for 3 nodes (less
  !! x_0). The origin x_0 is the segment's first node: relative to it the Bezier points are of
  !! the size of the segment, so the derivatives lose no digits to the size of the
  !! coordinates (x_A W' and A' cancel in x' = (A' - W' x)/W). The contact kernels build the
  !! curves of a master surface once per force evaluation (`surface_curves`); its
  !! closest-point projections then evaluate the segments many times per point without the
  !! extraction operator, the weights and the gather of the nodes, and one pass gives the
  !! point and both derivatives. Same curve as `segment_geometry`, to round-off.
  !! No default initialisation: a local curve costs nothing until it is built.
  type :: segment_curve_t
    !> Degree, and whether W varies (Bezier segments) or is 1 (Lagrange edges).
    integer :: p
    logical :: rational
    !> Origin x_0 (2) and homogeneous Bezier points (w x, w y, w) relative to it, (3, p + 1)
    !! used.
    real(dp) :: x0(2)
    real(dp) :: h(3, MAX_SEG_NODES)
    !> Points at t_k = k/CURVE_SAMPLES, (2, 0:CURVE_SAMPLES): evaluated once with the curve,
    !! not for every point projected onto it.
    real(dp) :: xk(2, 0:CURVE_SAMPLES)
  end type segment_curve_t

  !> A contact surface: segments, their nodes, neighbours, Gauss points and nodal weights.
  type :: contact_surface_t
    !> Surface name (upper case, as in the deck).
    character(len=str_len) :: name = ''
    !> Number of segments, largest number of nodes per segment.
    integer :: nseg = 0
    integer :: nen_max = 0
    !> Kind (SEG_*), nodes per segment (nseg).
    integer, allocatable :: kind(:)
    integer, allocatable :: nen(:)
    !> Global nodes of each segment in order of increasing t, (nen_max, nseg).
    integer, allocatable :: conn(:,:)
    !> NURBS weights (nen_max, nseg) and extraction operators (nen_max, nen_max, nseg) of the
    !! Bezier segments (1 and identity for Lagrange segments).
    real(dp), allocatable :: wgt(:,:)
    real(dp), allocatable :: ext(:,:,:)
    !> Neighbour segment before t = 0 and after t = 1 (0 at an end of the surface), (nseg).
    integer, allocatable :: prev(:), next(:)
    !> Model element of each segment (for messages), (nseg).
    integer, allocatable :: elem(:)
    !> Reference length of each segment (nseg) and the largest one.
    real(dp), allocatable :: seg_len(:)
    real(dp) :: hmax = 0.0_dp
    !> Distinct global nodes of the surface (nsn), and the position in `nodes` of each
    !! segment node, (nen_max, nseg).
    integer :: nsn = 0
    integer, allocatable :: nodes(:)
    integer, allocatable :: lnode(:,:)
    !> Nodal weights l_A = int R_A dGamma on the reference configuration, (nsn).
    real(dp), allocatable :: ell(:)
    !> Gauss points: segment, parameter t, weight w_q J_q (reference), shape values
    !! (nen_max, ngp).
    integer :: ngp = 0
    integer, allocatable :: gp_seg(:)
    real(dp), allocatable :: gp_t(:)
    real(dp), allocatable :: gp_wj(:)
    real(dp), allocatable :: gp_r(:,:)
    !> The segments on the reference coordinates (nseg): the mortar integrals take their
    !! length measure from them.
    type(segment_curve_t), allocatable :: ref(:)
  end type contact_surface_t


contains

  !> Sets up a surface from its segments (calls surface_free first).
  !! @param this the surface; @param name its name; @param kinds SEG_* (nseg);
  !! @param nens nodes per segment (nseg); @param conn global nodes (:, nseg), oriented;
  !! @param x0 reference coordinates (2, nn); @param wgt NURBS weights (:, nseg), optional;
  !! @param ext extraction operators (:, :, nseg), optional (identity);
  !! @param ngauss Gauss points per segment (nseg), optional (2 linear, 3 quadratic, p+1);
  !! @param elem model element per segment (nseg), optional
  subroutine surface_init(this, name, kinds, nens, conn, x0, wgt, ext, ngauss, elem)
    type(contact_surface_t), intent(inout) :: this
    character(len=*), intent(in) :: name
    integer, intent(in) :: kinds(:), nens(:), conn(:,:)
    real(dp), intent(in) :: x0(:,:)
    real(dp), intent(in), optional :: wgt(:,:), ext(:,:,:)
    integer, intent(in), optional :: ngauss(:), elem(:)
    integer :: ns, nm, s, a
    call surface_free(this)
    ns = size(kinds)
    nm = max(1, maxval([nens, 1]))
    this%name = name
    this%nseg = ns
    this%nen_max = nm
    if (nm > MAX_SEG_NODES) call input_error('*SURFACE '//trim(name), 'contact segments '// &
        'of more than 16 nodes (degree > 15) are not supported')
    this%kind = kinds
    this%nen = nens
    allocate(this%conn(nm, ns), this%wgt(nm, ns), this%ext(nm, nm, ns), this%elem(ns))
    this%conn = 0
    this%wgt = 1.0_dp
    this%ext = 0.0_dp
    this%elem = 0
    do s = 1, ns
      this%conn(1:nens(s), s) = conn(1:nens(s), s)
      do a = 1, nm
        this%ext(a, a, s) = 1.0_dp
      end do
      if (present(wgt)) this%wgt(1:nens(s), s) = wgt(1:nens(s), s)
      if (present(ext)) this%ext(1:nens(s), 1:nens(s), s) = ext(1:nens(s), 1:nens(s), s)
    end do
    if (present(elem)) this%elem = elem
    call collect_nodes(this, size(x0, 2))
    call link_neighbours(this, x0)
    call setup_gauss(this, x0, ngauss)
    allocate(this%ref(ns))
    call surface_curves(this, x0, this%ref)
  end subroutine surface_init

  !> Releases everything a surface holds.
  subroutine surface_free(this)
    type(contact_surface_t), intent(inout) :: this
    type(contact_surface_t) :: empty
    this = empty
  end subroutine surface_free

  !> Distinct nodes of the surface and the local-to-surface node map.
  subroutine collect_nodes(this, nn)
    type(contact_surface_t), intent(inout) :: this
    integer, intent(in) :: nn
    integer, allocatable :: pos(:)
    integer :: s, a, g
    allocate(pos(nn), this%lnode(this%nen_max, this%nseg))
    pos = 0
    this%lnode = 0
    this%nsn = 0
    allocate(this%nodes(this%nen_max*this%nseg))
    do s = 1, this%nseg
      do a = 1, this%nen(s)
        g = this%conn(a, s)
        if (pos(g) == 0) then
          this%nsn = this%nsn + 1
          pos(g) = this%nsn
          this%nodes(this%nsn) = g
        end if
        this%lnode(a, s) = pos(g)
      end do
    end do
    this%nodes = this%nodes(1:this%nsn)
  end subroutine collect_nodes

  !> Neighbours: Lagrange segments by shared end nodes; Bezier segments (the spans of one
  !! patch side, given in order along the side) by coinciding end points of list neighbours.
  subroutine link_neighbours(this, x0)
    type(contact_surface_t), intent(inout) :: this
    real(dp), intent(in) :: x0(:,:)
    integer, allocatable :: first_of(:)
    real(dp), allocatable :: xe(:,:,:)
    integer :: s, s2, k, g
    real(dp) :: tol
    allocate(this%prev(this%nseg), this%next(this%nseg))
    this%prev = 0
    this%next = 0
    allocate(first_of(size(x0, 2)), xe(2, 2, this%nseg))
    first_of = 0
    do s = 1, this%nseg
      if (this%kind(s) == SEG_LAGRANGE) then
        g = this%conn(1, s)
        if (first_of(g) == 0) first_of(g) = s
      end if
      call end_points(this, s, x0, xe(:, :, s))
    end do
    do s = 1, this%nseg
      if (this%kind(s) /= SEG_LAGRANGE) cycle
      s2 = first_of(this%conn(this%nen(s), s))
      if (s2 > 0 .and. s2 /= s) then
        this%next(s) = s2
        if (this%prev(s2) == 0) this%prev(s2) = s
      end if
    end do
    do k = 1, this%nseg
      s = k
      s2 = mod(k, this%nseg) + 1
      if (s2 == s .or. this%kind(s) /= SEG_BEZIER .or. this%kind(s2) /= SEG_BEZIER) cycle
      tol = 1.0e-8_dp*max(norm2(xe(:, 2, s) - xe(:, 1, s)), norm2(xe(:, 2, s2) - xe(:, 1, s2)))
      if (norm2(xe(:, 2, s) - xe(:, 1, s2)) <= tol) then
        this%next(s) = s2
        this%prev(s2) = s
      else if (norm2(xe(:, 1, s) - xe(:, 2, s2)) <= tol) then
        this%next(s2) = s
        this%prev(s) = s2
      end if
    end do
    ! the sides of several patches of one merged body, in any order: a side that ends where
    ! another begins shares its end control point (a node) with it
    first_of = 0
    do s = 1, this%nseg
      if (this%kind(s) == SEG_BEZIER .and. this%prev(s) == 0) first_of(this%conn(1, s)) = s
    end do
    do s = 1, this%nseg
      if (this%kind(s) /= SEG_BEZIER .or. this%next(s) /= 0) cycle
      s2 = first_of(this%conn(this%nen(s), s))
      if (s2 == 0 .or. s2 == s) cycle
      if (this%prev(s2) /= 0) cycle
      tol = 1.0e-8_dp*max(norm2(xe(:, 2, s) - xe(:, 1, s)), norm2(xe(:, 2, s2) - xe(:, 1, s2)))
      if (norm2(xe(:, 2, s) - xe(:, 1, s2)) <= tol) then
        this%next(s) = s2
        this%prev(s2) = s
      end if
    end do
  end subroutine link_neighbours

  !> Reference end points (2, 2) (t = 0, t = 1) of segment s.
  subroutine end_points(this, s, x0, xe)
    type(contact_surface_t), intent(in) :: this
    integer, intent(in) :: s
    real(dp), intent(in) :: x0(:,:)
    real(dp), intent(out) :: xe(2, 2)
    real(dp) :: x1(2), x2(2), r(MAX_SEG_NODES)
    call segment_geometry(this, s, x0, 0.0_dp, xe(:, 1), x1, x2, r)
    call segment_geometry(this, s, x0, 1.0_dp, xe(:, 2), x1, x2, r)
  end subroutine end_points

  !> Gauss points with reference weights w_q J_q, the nodal weights l_A and segment lengths.
  subroutine setup_gauss(this, x0, ngauss)
    type(contact_surface_t), intent(inout) :: this
    real(dp), intent(in) :: x0(:,:)
    integer, intent(in), optional :: ngauss(:)
    integer :: ng(this%nseg), s, q, m, a
    real(dp) :: xi(32), w(32), xq(2), x1(2), x2(2), r(MAX_SEG_NODES), wj
    do s = 1, this%nseg
      ! default: 2 points on a linear edge, 3 on a quadratic one, p + 1 on a Bezier span
      ng(s) = this%nen(s)
      if (present(ngauss)) ng(s) = ngauss(s)
      ng(s) = min(max(ng(s), 1), 32)
    end do
    this%ngp = sum(ng)
    allocate(this%gp_seg(this%ngp), this%gp_t(this%ngp), this%gp_wj(this%ngp), &
        this%gp_r(this%nen_max, this%ngp), this%ell(this%nsn), this%seg_len(this%nseg))
    this%ell = 0.0_dp
    this%gp_r = 0.0_dp
    this%seg_len = 0.0_dp
    m = 0
    do s = 1, this%nseg
      call gauss_legendre(ng(s), xi(1:ng(s)), w(1:ng(s)))
      do q = 1, ng(s)
        m = m + 1
        this%gp_seg(m) = s
        this%gp_t(m) = 0.5_dp*(1.0_dp + xi(q))
        call segment_geometry(this, s, x0, this%gp_t(m), xq, x1, x2, r)
        wj = 0.5_dp*w(q)*norm2(x1)
        this%gp_wj(m) = wj
        this%gp_r(1:this%nen(s), m) = r(1:this%nen(s))
        this%seg_len(s) = this%seg_len(s) + wj
        do a = 1, this%nen(s)
          this%ell(this%lnode(a, s)) = this%ell(this%lnode(a, s)) + r(a)*wj
        end do
      end do
    end do
    this%hmax = 0.0_dp
    if (this%nseg > 0) this%hmax = maxval(this%seg_len)
  end subroutine setup_gauss

  !> Shape functions of segment s at t and their first and second derivatives d/dt.
  !! @param this surface; @param s segment; @param t in [0, 1];
  !! @param r, dr, ddr values and derivatives (nen(s) used)
  pure subroutine segment_shape(this, s, t, r, dr, ddr)
    type(contact_surface_t), intent(in) :: this
    integer, intent(in) :: s
    real(dp), intent(in) :: t
    real(dp), intent(out) :: r(:), dr(:), ddr(:)
    integer :: n
    n = this%nen(s)
    if (this%kind(s) == SEG_LAGRANGE) then
      call lagrange_1d(n, t, r, dr, ddr)
    else
      call rational_bezier(this%nen_max, n - 1, this%ext(:, :, s), this%wgt(:, s), t, r, dr, &
          ddr)
    end if
  end subroutine segment_shape

  !> Point, first and second derivative d/dt and shape values of segment s at t.
  !! @param x coordinates (2, nn); @param xp point (2); @param x1, x2 derivatives (2);
  !! @param r shape values (nen_max; nen(s) used)
  pure subroutine segment_geometry(this, s, x, t, xp, x1, x2, r)
    type(contact_surface_t), intent(in) :: this
    integer, intent(in) :: s
    real(dp), intent(in) :: x(:,:), t
    real(dp), intent(out) :: xp(2), x1(2), x2(2), r(:)
    real(dp) :: dr(MAX_SEG_NODES), ddr(MAX_SEG_NODES)
    integer :: a, g
    call segment_shape(this, s, t, r, dr, ddr)
    xp = 0.0_dp
    x1 = 0.0_dp
    x2 = 0.0_dp
    do a = 1, this%nen(s)
      g = this%conn(a, s)
      xp = xp + r(a)*x(:, g)
      x1 = x1 + dr(a)*x(:, g)
      x2 = x2 + ddr(a)*x(:, g)
    end do
  end subroutine segment_geometry

  !> Segment s on the coordinates x in Bezier form (see segment_curve_t).
  !! @param this surface; @param s segment; @param x coordinates (2, nn); @param c the curve
  pure subroutine segment_curve(this, s, x, c)
    type(contact_surface_t), intent(in) :: this
    integer, intent(in) :: s
    real(dp), intent(in) :: x(:,:)
    type(segment_curve_t), intent(out) :: c
    real(dp) :: hw(3)
    integer :: a, j, n, g, k
    n = this%nen(s)
    c%p = n - 1
    c%rational = this%kind(s) /= SEG_LAGRANGE
    c%x0 = x(:, this%conn(1, s))
    if (.not. c%rational) then
      do a = 1, n
        g = this%conn(a, s)
        c%h(1, a) = x(1, g) - c%x0(1)
        c%h(2, a) = x(2, g) - c%x0(2)
        c%h(3, a) = 1.0_dp
      end do
      if (n == 3) c%h(1:2, 2) = 2.0_dp*c%h(1:2, 2) - 0.5_dp*(c%h(1:2, 1) + c%h(1:2, 3))
    else
      c%h(:, 1:n) = 0.0_dp
      do a = 1, n
        g = this%conn(a, s)
        hw(3) = this%wgt(a, s)
        hw(1) = hw(3)*(x(1, g) - c%x0(1))
        hw(2) = hw(3)*(x(2, g) - c%x0(2))
        do j = 1, n
          c%h(:, j) = c%h(:, j) + this%ext(a, j, s)*hw
        end do
      end do
    end if
    do k = 0, CURVE_SAMPLES
      call curve_point(c, real(k, dp)/real(CURVE_SAMPLES, dp), c%xk(:, k))
    end do
  end subroutine segment_curve

  !> All segments of a surface on the coordinates x in Bezier form.
  !! @param this surface; @param x coordinates (2, nn); @param curves (nseg)
  pure subroutine surface_curves(this, x, curves)
    type(contact_surface_t), intent(in) :: this
    real(dp), intent(in) :: x(:,:)
    type(segment_curve_t), intent(inout) :: curves(:)
    integer :: s
    do s = 1, this%nseg
      call segment_curve(this, s, x, curves(s))
    end do
  end subroutine surface_curves

  !> Point of a segment curve at t.
  !! @param c curve; @param t parameter; @param xp point (2)
  pure subroutine curve_point(c, t, xp)
    type(segment_curve_t), intent(in) :: c
    real(dp), intent(in) :: t
    real(dp), intent(out) :: xp(2)
    real(dp) :: h0(3), b0, b1, b2, u
    u = 1.0_dp - t
    select case (c%p)
    case (1)
      h0 = u*c%h(:, 1) + t*c%h(:, 2)
    case (2)
      b0 = u*u
      b1 = 2.0_dp*u*t
      b2 = t*t
      h0 = b0*c%h(:, 1) + b1*c%h(:, 2) + b2*c%h(:, 3)
    case default
      call de_casteljau(c%p, c%h, t, h0)
    end select
    if (c%rational) then
      xp = c%x0 + h0(1:2)/h0(3)
    else
      xp = c%x0 + h0(1:2)
    end if
  end subroutine curve_point

  !> Point and first and second derivatives d/dt of a segment curve at t, in one pass: of
  !! the homogeneous curve (A, W) directly for degrees 1 and 2, by de Casteljau's recursion
  !! (de_casteljau of ictus_geometry_bezier) for higher degrees; then with y = A/W = x - x_0,
  !! x' = (A' - W' y)/W, x'' = (A'' - 2 W' x' - W'' y)/W.
  !! @param c curve; @param t parameter; @param xp point (2); @param x1, x2 derivatives (2)
  pure subroutine curve_geometry(c, t, xp, x1, x2)
    type(segment_curve_t), intent(in) :: c
    real(dp), intent(in) :: t
    real(dp), intent(out) :: xp(2), x1(2), x2(2)
    real(dp) :: h0(3), h1(3), h2(3), d1(3), d2(3), y(2), u, rw
    u = 1.0_dp - t
    select case (c%p)
    case (1)
      h0 = u*c%h(:, 1) + t*c%h(:, 2)
      h1 = c%h(:, 2) - c%h(:, 1)
      h2 = 0.0_dp
    case (2)
      d1 = c%h(:, 2) - c%h(:, 1)
      d2 = c%h(:, 3) - c%h(:, 2)
      h0 = u*u*c%h(:, 1) + 2.0_dp*u*t*c%h(:, 2) + t*t*c%h(:, 3)
      h1 = 2.0_dp*(u*d1 + t*d2)
      h2 = 2.0_dp*(d2 - d1)
    case default
      call de_casteljau(c%p, c%h, t, h0, h1, h2)
    end select
    if (c%rational) then
      rw = 1.0_dp/h0(3)
      y = h0(1:2)*rw
      x1 = (h1(1:2) - h1(3)*y)*rw
      x2 = (h2(1:2) - 2.0_dp*h1(3)*x1 - h2(3)*y)*rw
      xp = c%x0 + y
    else
      xp = c%x0 + h0(1:2)
      x1 = h1(1:2)
      x2 = h2(1:2)
    end if
  end subroutine curve_geometry

  !> Bounding box (xmin, ymin, xmax, ymax) of segment s for coordinates x, grown by `grow`.
  !! Bezier segments lie in the hull of their Bezier points (positive weights); a quadratic
  !! Lagrange edge in the hull of its end nodes and 2 x_mid - (x_1 + x_3)/2.
  pure subroutine segment_bbox(this, s, x, grow, box)
    type(contact_surface_t), intent(in) :: this
    integer, intent(in) :: s
    real(dp), intent(in) :: x(:,:), grow
    real(dp), intent(out) :: box(4)
    real(dp) :: p(2)
    integer :: a, n
    n = this%nen(s)
    box(1:2) = x(:, this%conn(1, s))
    box(3:4) = box(1:2)
    do a = 2, n
      p = x(:, this%conn(a, s))
      if (this%kind(s) == SEG_LAGRANGE .and. n == 3 .and. a == 2) then
        p = 2.0_dp*p - 0.5_dp*(x(:, this%conn(1, s)) + x(:, this%conn(3, s)))
      end if
      box(1:2) = min(box(1:2), p)
      box(3:4) = max(box(3:4), p)
    end do
    ! a B-spline span lies in the hull of its own control points (convex-hull property)
    box(1:2) = box(1:2) - grow
    box(3:4) = box(3:4) + grow
  end subroutine segment_bbox

  !> Lagrange shape functions on t in [0, 1], nodes equally spaced (2 or 3 nodes).
  pure subroutine lagrange_1d(n, t, r, dr, ddr)
    integer, intent(in) :: n
    real(dp), intent(in) :: t
    real(dp), intent(out) :: r(:), dr(:), ddr(:)
    if (n == 2) then
      r(1:2) = [1.0_dp - t, t]
      dr(1:2) = [-1.0_dp, 1.0_dp]
      ddr(1:2) = 0.0_dp
    else
      r(1:3) = [(1.0_dp - t)*(1.0_dp - 2.0_dp*t), 4.0_dp*t*(1.0_dp - t), &
          t*(2.0_dp*t - 1.0_dp)]
      dr(1:3) = [4.0_dp*t - 3.0_dp, 4.0_dp - 8.0_dp*t, 4.0_dp*t - 1.0_dp]
      ddr(1:3) = [4.0_dp, -8.0_dp, 4.0_dp]
    end if
  end subroutine lagrange_1d

  !> Rational B-spline functions of one span through its extraction operator c and weights
  !! w, with first and second derivatives in t in [0, 1].
  !! @param ld leading dimension of c and w; @param p degree (p + 1 <= ld);
  !! @param c extraction operator (ld, ld), used (p+1, p+1); @param w weights (ld);
  !! @param t parameter; @param r, dr, ddr values and derivatives (p+1 used)
  pure subroutine rational_bezier(ld, p, c, w, t, r, dr, ddr)
    integer, intent(in) :: ld, p
    real(dp), intent(in) :: c(ld, ld), w(ld), t
    real(dp), intent(out) :: r(:), dr(:), ddr(:)
    real(dp) :: b(MAX_SEG_NODES), db(MAX_SEG_NODES), ddb(MAX_SEG_NODES), n0, n1, n2
    real(dp) :: ww, w1, w2
    integer :: a, j
    call bernstein_d2(p, t, b, db, ddb)
    ww = 0.0_dp
    w1 = 0.0_dp
    w2 = 0.0_dp
    do a = 1, p + 1
      n0 = 0.0_dp
      n1 = 0.0_dp
      n2 = 0.0_dp
      do j = 1, p + 1
        n0 = n0 + c(a, j)*b(j)
        n1 = n1 + c(a, j)*db(j)
        n2 = n2 + c(a, j)*ddb(j)
      end do
      r(a) = w(a)*n0
      dr(a) = w(a)*n1
      ddr(a) = w(a)*n2
      ww = ww + r(a)
      w1 = w1 + dr(a)
      w2 = w2 + ddr(a)
    end do
    do a = 1, p + 1
      r(a) = r(a)/ww
      dr(a) = (dr(a) - r(a)*w1)/ww
      ddr(a) = (ddr(a) - 2.0_dp*dr(a)*w1 - r(a)*w2)/ww
    end do
  end subroutine rational_bezier

  !> Global nodes of face `face` of an element in order along the face (corner k, [midside],
  !! corner k+1; element_kind_t%face): a counter-clockwise element's face runs
  !! counter-clockwise.
  !! @param etype element type; @param enodes global nodes of the element (nen);
  !! @param conn segment nodes (3; 2 or 3 used); @param nen 2, 3, or 0 if invalid
  subroutine face_segment(etype, enodes, face, conn, nen)
    integer, intent(in) :: etype, enodes(:), face
    integer, intent(out) :: conn(3), nen
    type(element_kind_t) :: k
    integer :: a
    k = element_kind(etype)
    conn = 0
    nen = 0
    if (face < 1 .or. face > k%nface .or. k%nen == 0) return
    nen = k%nfn
    do a = 1, nen
      conn(a) = enodes(k%face(a, face))
    end do
  end subroutine face_segment

  !> Signed area of an element from its boundary nodes in boundary order (the faces' nodes,
  !! each face's last node being the next face's first); positive when the nodes run
  !! counter-clockwise; 0 for a type without fixed nodes (NURBS).
  !! @param etype element type; @param xl nodal coordinates (2, nen)
  real(dp) function element_area(etype, xl) result(area)
    integer, intent(in) :: etype
    real(dp), intent(in) :: xl(:,:)
    type(element_kind_t) :: kd
    integer, allocatable :: ring(:)
    integer :: nr, k, a, b
    kd = element_kind(etype)
    area = 0.0_dp
    if (kd%nen == 0 .or. kd%nface == 0) return
    ring = reshape(kd%face(1:kd%nfn - 1, :), [(kd%nfn - 1)*kd%nface])
    nr = size(ring)
    do k = 1, nr
      a = ring(k)
      b = ring(mod(k, nr) + 1)
      area = area + 0.5_dp*(xl(1, a)*xl(2, b) - xl(1, b)*xl(2, a))
    end do
  end function element_area

  !> Reverses a segment's direction: node order, weights, and the extraction operator
  !! (B_j(t) = B_{p+2-j}(1-t), so C is reversed in both indices).
  !! @param nen nodes; @param conn (nen); @param wgt (nen); @param ext (nen, nen)
  pure subroutine reverse_segment(nen, conn, wgt, ext)
    integer, intent(in) :: nen
    integer, intent(inout) :: conn(:)
    real(dp), intent(inout) :: wgt(:), ext(:,:)
    conn(1:nen) = conn(nen:1:-1)
    wgt(1:nen) = wgt(nen:1:-1)
    ext(1:nen, 1:nen) = ext(nen:1:-1, nen:1:-1)
  end subroutine reverse_segment

  !> Rational Bezier segments of one side of a patch, oriented counter-clockwise around the
  !! patch. Orientation per span from the sign of t x (inward direction) at the span middle,
  !! where t = dx/d(side parameter); this sign is that of det J, which may be negative.
  !! @param patch the patch; @param offset global index of its first control point minus 1;
  !! @param side SIDE_*; @param nseg number of segments; @param nens nodes per segment
  !! (nseg); @param conn (p+1, nseg) global nodes; @param wgt (p+1, nseg);
  !! @param ext (p+1, p+1, nseg); @param elem patch element (nseg);
  !! @param ierr 0, 1 if the side is unknown, 2 if det J vanishes or changes sign on the side;
  !! @param node global node of each control point (n1*n2), optional: then `offset` is unused
  !! (a patch whose control points are merged with other patches')
  subroutine patch_side_segments(patch, offset, side, nseg, nens, conn, wgt, ext, elem, ierr, &
      node)
    type(patch_t), intent(in) :: patch
    integer, intent(in) :: offset, side
    integer, intent(in), optional :: node(:)
    integer, intent(out) :: nseg
    integer, allocatable, intent(out) :: nens(:), conn(:,:), elem(:)
    real(dp), allocatable, intent(out) :: wgt(:,:), ext(:,:,:)
    integer, intent(out) :: ierr
    integer, allocatable :: elems(:), faces(:)
    integer :: k, a, ij(2), p, loc, p1, nsign(2)
    real(dp) :: u(2), xp(2), du(2), dv(2), tang(2), inward(2), cr
    logical, allocatable :: flip(:)
    ierr = 0
    call patch_side_elements(patch, side, elems, faces, nseg)
    if (nseg == 0) then
      ierr = 1
      allocate(nens(0), conn(0, 0), wgt(0, 0), ext(0, 0, 0), elem(0))
      return
    end if
    p = maxval(patch%p)
    p1 = patch%p(1)
    allocate(nens(nseg), conn(p+1, nseg), wgt(p+1, nseg), ext(p+1, p+1, nseg), elem(nseg), &
        flip(nseg))
    conn = 0
    wgt = 1.0_dp
    ext = 0.0_dp
    nsign = 0
    do k = 1, nseg
      ij = patch_elem_ij(patch, elems(k))
      elem(k) = elems(k)
      u = [0.5_dp*(patch%span_lo1(ij(1)) + patch%span_hi1(ij(1))), &
          0.5_dp*(patch%span_lo2(ij(2)) + patch%span_hi2(ij(2)))]
      select case (faces(k))
      case (1, 3)
        nens(k) = p1 + 1
        if (faces(k) == 1) u(2) = patch%knots2(1)
        if (faces(k) == 3) u(2) = patch%knots2(size(patch%knots2))
        ext(1:p1+1, 1:p1+1, k) = patch%c1(:, :, ij(1))
        do a = 0, p1
          loc = 1 + a
          if (faces(k) == 3) loc = loc + patch%p(2)*(p1 + 1)
          conn(a+1, k) = patch%ien(loc, elems(k))
        end do
      case default
        nens(k) = patch%p(2) + 1
        if (faces(k) == 4) u(1) = patch%knots1(1)
        if (faces(k) == 2) u(1) = patch%knots1(size(patch%knots1))
        ext(1:patch%p(2)+1, 1:patch%p(2)+1, k) = patch%c2(:, :, ij(2))
        do a = 0, patch%p(2)
          loc = 1 + a*(p1 + 1)
          if (faces(k) == 2) loc = loc + p1
          conn(a+1, k) = patch%ien(loc, elems(k))
        end do
      end select
      call patch_point(patch, u, xp, du, dv)
      select case (faces(k))
      case (1)
        tang = du
        inward = dv
      case (3)
        tang = du
        inward = -dv
      case (2)
        tang = dv
        inward = -du
      case default
        tang = dv
        inward = du
      end select
      cr = tang(1)*inward(2) - tang(2)*inward(1)
      if (cr > 0.0_dp) then
        nsign(1) = nsign(1) + 1
      else if (cr < 0.0_dp) then
        nsign(2) = nsign(2) + 1
      end if
      flip(k) = cr < 0.0_dp
    end do
    if (nsign(1) + nsign(2) < nseg .or. (nsign(1) > 0 .and. nsign(2) > 0)) ierr = 2
    do k = 1, nseg
      do loc = 1, nens(k)
        wgt(loc, k) = patch%cp(3, conn(loc, k))
        if (present(node)) then
          conn(loc, k) = node(conn(loc, k))
        else
          conn(loc, k) = offset + conn(loc, k)
        end if
      end do
      if (flip(k)) call reverse_segment(nens(k), conn(:, k), wgt(:, k), ext(:, :, k))
    end do
  end subroutine patch_side_segments
end module ictus_contact_surface
