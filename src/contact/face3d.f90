!> Contact surfaces in 3D: quadrilateral faces of hexahedra (4-node bilinear, 8-node
!! serendipity, 9-node Lagrange; the face lists of element_kind_t%face, corners ordered so
!! that the right-hand rule gives the outward normal) and rational Bezier faces (one knot span
!! of a NURBS surface: degrees p1, p2, its 1D extraction operators and weights), their Gauss
!! points and nodal weights, and the closest-point projection of a point onto them
!! (doc/contact.md §9).
!!
!! A face is parametrised on [-1, 1]^2: a Lagrange face with the shape functions of the
!! quadrilaterals Q4, Q8, Q9 (ictus_elements_lagrange: corners, then the midsides of the sides
!! 1-2, 2-3, 3-4, 4-1, then the centre); a Bezier face with R_A = w_A N_A / sum_B w_B N_B,
!! N_(i,j) = sum_k C1(i, k) B_k(u) sum_l C2(j, l) B_l(v), u = (1 + xi)/2, v = (1 + eta)/2,
!! control points i fastest. Its outward normal is n = a1 x a2/|a1 x a2|, a_i = dx/dxi_i (the
!! Bezier faces of a surface must be oriented so).
!!
!! Projection onto one face: minimise |x_s - x(xi)|^2 by Gauss-Newton steps on
!! f_i = (x_s - x).a_i = 0 with H_ij = a_i.a_j (the Hessian without the curvature term
!! (x_s - x).x_,ij, which is of the size of the gap times the curvature: near the surface,
!! where contact points are, the iteration is nearly quadratic), steps halved while the
!! distance grows beyond round-off, xi clamped to the square. Several candidate faces: the interior
!! projection of least distance. A point whose best projection is clamped to a side shared
!! with another face of the surface lies over a fold between faces: it takes the mean normal
!! of the two faces there (a "corner", as in 2D); clamped to a side of the surface's
!! boundary, it is beyond the surface (outside).
module ictus_contact_face3d
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9
  use ictus_elements_lagrange, only: lagrange_shape
  use ictus_elements_quadrature, only: gauss_legendre
  use ictus_elements_iga, only: iga_basis_at
  implicit none
  private
  public :: surface3d_t, surface3d_init, face_shape, face_geometry, face_bbox, &
      projection3d_t, project3d, P3_NONE, P3_INTERIOR, P3_CORNER, P3_OUTSIDE, MAX_FACE_NODES

  !> Most nodes of a face: a bicubic Bezier face.
  integer, parameter :: MAX_FACE_NODES = 16

  !> Outcome of a projection: no candidate, interior point of a face, on a fold between two
  !! faces, beyond the surface's boundary.
  integer, parameter :: P3_NONE = 0, P3_INTERIOR = 1, P3_CORNER = 2, P3_OUTSIDE = 3

  !> Newton iterations, halvings, tolerance on xi.
  integer, parameter :: max_iter = 40, max_halvings = 8
  real(dp), parameter :: tol = 1.0e-13_dp
  !> How far past a side of its face (in the face's parameter, width 2) a projection may
  !! fall and still be on the face.
  real(dp), parameter :: edge_tol = 0.05_dp

  type :: surface3d_t
    !> Faces: nodes per face (Lagrange 4, 8 or 9; Bezier (p1 + 1)(p2 + 1)), global nodes
    !! (MAX_FACE_NODES, nface).
    integer :: nface = 0
    integer, allocatable :: nen(:)
    integer, allocatable :: conn(:,:)
    !> Bezier faces: degrees (2, nface; 0 for Lagrange faces), 1D extraction operators
    !! (4, 4, nface) in each direction and weights (MAX_FACE_NODES, nface).
    integer, allocatable :: deg(:,:)
    real(dp), allocatable :: ext1(:,:,:), ext2(:,:,:), wgt(:,:)
    !> Neighbour face across each side (4, nface; 0 on the boundary of the surface).
    integer, allocatable :: nbr(:,:)
    !> Distinct nodes (nsn) and each face node's position in them (MAX_FACE_NODES, nface).
    integer :: nsn = 0
    integer, allocatable :: nodes(:), lnode(:,:)
    !> Gauss points: face, parent point (2), reference weight w J, shape values
    !! (MAX_FACE_NODES).
    integer :: ngp = 0
    integer, allocatable :: gp_face(:)
    real(dp), allocatable :: gp_xi(:,:), gp_wj(:), gp_r(:,:)
    !> Nodal weights l_A = int N_A dA (reference), their row-sum bound
    !! l_row_A = int |N_A| sum_B |N_B| dA (the Gershgorin row sum of the penalty stiffness
    !! of a flat contact per unit penalty: > 0 also at the corners of 8-node faces, where
    !! l_A < 0), the nodal areas of NODE TO SEGMENT a_A (each face's area shared in the
    !! proportions of int N_A^2 dA, as HRZ shares an element's mass: > 0, summing to the
    !! area), the largest face diameter.
    real(dp), allocatable :: ell(:), ell_row(:), area(:)
    real(dp) :: hmax = 0.0_dp
  end type surface3d_t

  !> The closest point of a surface to a point.
  type :: projection3d_t
    integer :: status = P3_NONE
    integer :: face = 0
    real(dp) :: xi(2) = 0.0_dp
    real(dp) :: xbar(3) = 0.0_dp
    real(dp) :: normal(3) = 0.0_dp
    !> Signed distance (x_s - xbar).normal and distance.
    real(dp) :: d = 0.0_dp
    real(dp) :: dist = 0.0_dp
  end type projection3d_t

contains

  !> The element type whose quadrilateral has nen nodes.
  pure integer function quad_type(nen)
    integer, intent(in) :: nen
    quad_type = ETYPE_Q4
    if (nen == 8) quad_type = ETYPE_Q8
    if (nen == 9) quad_type = ETYPE_Q9
  end function quad_type

  !> Shape values r(nen) and parent derivatives dr(2, nen) of face f of s at xi: the
  !! quadrilateral's (Lagrange faces) or the NURBS span's (Bezier faces, ictus_elements_iga).
  pure subroutine face_shape(s, f, xi, r, dr)
    type(surface3d_t), intent(in) :: s
    integer, intent(in) :: f
    real(dp), intent(in) :: xi(2)
    real(dp), intent(out) :: r(:), dr(:,:)
    integer :: p(2)
    if (s%deg(1, f) == 0) then
      call lagrange_shape(quad_type(s%nen(f)), xi, r, dr)
    else
      p = s%deg(:, f)
      call iga_basis_at(p, s%ext1(1:p(1) + 1, 1:p(1) + 1, f), s%ext2(1:p(2) + 1, &
          1:p(2) + 1, f), s%wgt(1:s%nen(f), f), xi, r, dr)
    end if
  end subroutine face_shape

  !> Point xp, tangents a(3, 2) and unit normal n of face f at xi on the coordinates x (3, nn);
  !! jac = |a1 x a2|.
  pure subroutine face_geometry(s, f, x, xi, xp, a, n, jac)
    type(surface3d_t), intent(in) :: s
    integer, intent(in) :: f
    real(dp), intent(in) :: x(:,:), xi(2)
    real(dp), intent(out) :: xp(3), a(3, 2), n(3), jac
    real(dp) :: r(MAX_FACE_NODES), dr(2, MAX_FACE_NODES)
    integer :: k, g
    call face_shape(s, f, xi, r, dr)
    xp = 0.0_dp
    a = 0.0_dp
    do k = 1, s%nen(f)
      g = s%conn(k, f)
      xp = xp + r(k)*x(:, g)
      a(:, 1) = a(:, 1) + dr(1, k)*x(:, g)
      a(:, 2) = a(:, 2) + dr(2, k)*x(:, g)
    end do
    n = cross(a(:, 1), a(:, 2))
    jac = norm2(n)
    if (jac > 0.0_dp) n = n/jac
  end subroutine face_geometry

  pure function cross(u, v) result(w)
    real(dp), intent(in) :: u(3), v(3)
    real(dp) :: w(3)
    w = [u(2)*v(3) - u(3)*v(2), u(3)*v(1) - u(1)*v(3), u(1)*v(2) - u(2)*v(1)]
  end function cross

  !> Bounding box (6) of face f on x, grown by `grow` (the hull of its nodes, widened by a
  !! quarter of the box for the bulge of a quadratic face).
  pure subroutine face_bbox(s, f, x, grow, box)
    type(surface3d_t), intent(in) :: s
    integer, intent(in) :: f
    real(dp), intent(in) :: x(:,:), grow
    real(dp), intent(out) :: box(6)
    real(dp) :: ext(3)
    integer :: k
    box(1:3) = x(:, s%conn(1, f))
    box(4:6) = box(1:3)
    do k = 2, s%nen(f)
      box(1:3) = min(box(1:3), x(:, s%conn(k, f)))
      box(4:6) = max(box(4:6), x(:, s%conn(k, f)))
    end do
    ! a Bezier face lies in the hull of its control points (positive weights); a quadratic
    ! Lagrange face may bulge beyond its nodes
    ext = 0.0_dp
    if (s%deg(1, f) == 0 .and. s%nen(f) > 4) ext = 0.25_dp*(box(4:6) - box(1:3))
    box(1:3) = box(1:3) - ext - grow
    box(4:6) = box(4:6) + ext + grow
  end subroutine face_bbox

  !> Sets up a surface from faces: nodes per face nens(nface), global nodes conn(:, nface)
  !! (Lagrange faces: outward corner order), reference coordinates x0 (3, nn); ng Gauss
  !! points per direction (default: 2 on 4-node faces, 3 on 8- and 9-node faces, p + 1 on
  !! Bezier faces). Bezier faces (optional, all faces): degrees deg(2, nface), 1D extraction
  !! operators ext1, ext2 (:, :, nface) and weights wgt(:, nface).
  subroutine surface3d_init(s, nens, conn, x0, ng, deg, ext1, ext2, wgt)
    type(surface3d_t), intent(out) :: s
    integer, intent(in) :: nens(:), conn(:,:)
    real(dp), intent(in) :: x0(:,:)
    integer, intent(in), optional :: ng, deg(:,:)
    real(dp), intent(in), optional :: ext1(:,:,:), ext2(:,:,:), wgt(:,:)
    integer, allocatable :: pos(:)
    integer :: f, k, g, nm
    s%nface = size(nens)
    s%nen = nens
    nm = MAX_FACE_NODES
    allocate(s%conn(nm, s%nface), s%lnode(nm, s%nface), s%nodes(nm*s%nface))
    allocate(s%deg(2, s%nface), source=0)
    allocate(s%ext1(4, 4, s%nface), s%ext2(4, 4, s%nface), s%wgt(nm, s%nface), source=0.0_dp)
    if (present(deg)) then
      s%deg = deg
      do f = 1, s%nface
        s%ext1(1:deg(1, f) + 1, 1:deg(1, f) + 1, f) = ext1(1:deg(1, f) + 1, 1:deg(1, f) + 1, f)
        s%ext2(1:deg(2, f) + 1, 1:deg(2, f) + 1, f) = ext2(1:deg(2, f) + 1, 1:deg(2, f) + 1, f)
        s%wgt(1:nens(f), f) = wgt(1:nens(f), f)
      end do
    end if
    s%conn = 0
    s%lnode = 0
    allocate(pos(size(x0, 2)), source=0)
    do f = 1, s%nface
      s%conn(1:nens(f), f) = conn(1:nens(f), f)
      do k = 1, nens(f)
        g = conn(k, f)
        if (pos(g) == 0) then
          s%nsn = s%nsn + 1
          pos(g) = s%nsn
          s%nodes(s%nsn) = g
        end if
        s%lnode(k, f) = pos(g)
      end do
    end do
    s%nodes = s%nodes(1:s%nsn)
    call link_faces(s, x0)
    call setup_gauss(s, x0, ng)
  end subroutine surface3d_init

  !> The corner points (3, 4) of face f on x, at xi = (-1,-1), (1,-1), (1,1), (-1,1): side c
  !! runs from corner c to corner c + 1.
  pure subroutine face_corners(s, f, x, xc)
    type(surface3d_t), intent(in) :: s
    integer, intent(in) :: f
    real(dp), intent(in) :: x(:,:)
    real(dp), intent(out) :: xc(3, 4)
    real(dp), parameter :: xi(2, 4) = reshape([-1.0_dp, -1.0_dp, 1.0_dp, -1.0_dp, 1.0_dp, &
        1.0_dp, -1.0_dp, 1.0_dp], [2, 4])
    real(dp) :: a(3, 2), n(3), jac
    integer :: c
    do c = 1, 4
      call face_geometry(s, f, x, xi(:, c), xc(:, c), a, n, jac)
    end do
  end subroutine face_corners

  !> Neighbours across the sides: two faces share a side when its two end points coincide
  !! (to 1e-8 of the face sizes; the corner points of Bezier faces are not control points).
  subroutine link_faces(s, x0)
    type(surface3d_t), intent(inout) :: s
    real(dp), intent(in) :: x0(:,:)
    real(dp), allocatable :: xc(:,:,:)
    real(dp) :: tol, p1(3), p2(3), q1(3), q2(3)
    integer :: f, e, f2, e2
    allocate(s%nbr(4, s%nface), source=0)
    allocate(xc(3, 4, s%nface))
    do f = 1, s%nface
      call face_corners(s, f, x0, xc(:, :, f))
      s%hmax = max(s%hmax, norm2(xc(:, 3, f) - xc(:, 1, f)), norm2(xc(:, 4, f) - xc(:, 2, f)))
    end do
    tol = 1.0e-8_dp*s%hmax
    do f = 1, s%nface
      do e = 1, 4
        p1 = xc(:, e, f)
        p2 = xc(:, mod(e, 4) + 1, f)
        do f2 = 1, s%nface
          if (f2 == f) cycle
          do e2 = 1, 4
            q1 = xc(:, e2, f2)
            q2 = xc(:, mod(e2, 4) + 1, f2)
            if ((norm2(p1 - q2) <= tol .and. norm2(p2 - q1) <= tol) .or. &
                (norm2(p1 - q1) <= tol .and. norm2(p2 - q2) <= tol)) s%nbr(e, f) = f2
          end do
        end do
      end do
    end do
  end subroutine link_faces

  !> Gauss points with reference weights and the nodal weights l_A.
  subroutine setup_gauss(s, x0, ng)
    type(surface3d_t), intent(inout) :: s
    real(dp), intent(in) :: x0(:,:)
    integer, intent(in), optional :: ng
    real(dp) :: gx(8), gw(8), xp(3), a(3, 2), n(3), jac, r(MAX_FACE_NODES), &
        dr(2, MAX_FACE_NODES), diag(MAX_FACE_NODES), af
    integer :: f, i, j, m, q, k
    s%ngp = 0
    do f = 1, s%nface
      s%ngp = s%ngp + nrule(s, f, ng)**2
    end do
    allocate(s%gp_face(s%ngp), s%gp_xi(2, s%ngp), s%gp_wj(s%ngp), &
        s%gp_r(MAX_FACE_NODES, s%ngp))
    allocate(s%ell(s%nsn), s%ell_row(s%nsn), s%area(s%nsn), source=0.0_dp)
    s%gp_r = 0.0_dp
    q = 0
    do f = 1, s%nface
      m = nrule(s, f, ng)
      call gauss_legendre(m, gx(1:m), gw(1:m))
      diag = 0.0_dp
      af = 0.0_dp
      do j = 1, m
        do i = 1, m
          q = q + 1
          s%gp_face(q) = f
          s%gp_xi(:, q) = [gx(i), gx(j)]
          call face_geometry(s, f, x0, s%gp_xi(:, q), xp, a, n, jac)
          s%gp_wj(q) = gw(i)*gw(j)*jac
          call face_shape(s, f, s%gp_xi(:, q), r, dr)
          s%gp_r(1:s%nen(f), q) = r(1:s%nen(f))
          do k = 1, s%nen(f)
            s%ell(s%lnode(k, f)) = s%ell(s%lnode(k, f)) + r(k)*s%gp_wj(q)
            s%ell_row(s%lnode(k, f)) = s%ell_row(s%lnode(k, f)) + abs(r(k))* &
                sum(abs(r(1:s%nen(f))))*s%gp_wj(q)
            diag(k) = diag(k) + r(k)**2*s%gp_wj(q)
          end do
          af = af + s%gp_wj(q)
        end do
      end do
      do k = 1, s%nen(f)
        s%area(s%lnode(k, f)) = s%area(s%lnode(k, f)) + af*diag(k)/sum(diag(1:s%nen(f)))
      end do
    end do
  end subroutine setup_gauss

  !> Gauss points per direction of face f (ng if given): 2 on 4-node faces, 3 on 8- and
  !! 9-node faces, the larger degree + 1 on Bezier faces.
  pure integer function nrule(s, f, ng)
    type(surface3d_t), intent(in) :: s
    integer, intent(in) :: f
    integer, intent(in), optional :: ng
    nrule = merge(2, 3, s%nen(f) == 4)
    if (s%deg(1, f) > 0) nrule = maxval(s%deg(:, f)) + 1
    if (present(ng)) nrule = min(max(ng, 1), 8)
  end function nrule

  !> Closest point of face f to xs on x: xi (clamped to the square), point, normal, and
  !! whether xi lies on the square's boundary (clamped: the side 1..4 it lies on, else 0).
  pure subroutine project_face(s, f, x, xs, xi, xp, n, side)
    type(surface3d_t), intent(in) :: s
    integer, intent(in) :: f
    real(dp), intent(in) :: x(:,:), xs(3)
    real(dp), intent(out) :: xi(2), xp(3), n(3)
    integer, intent(out) :: side
    real(dp) :: a(3, 2), jac, h(2, 2), g(2), dxi(2), xt(2), xq(3), dist, dnew, det, scale, pull
    integer :: it, m, c, k
    xi = 0.0_dp
    call face_geometry(s, f, x, xi, xp, a, n, jac)
    dist = norm2(xs - xp)
    scale = max(norm2(a(:, 1)), norm2(a(:, 2)), tiny(1.0_dp))
    do it = 1, max_iter
      g = [dot_product(xs - xp, a(:, 1)), dot_product(xs - xp, a(:, 2))]
      h(1, 1) = dot_product(a(:, 1), a(:, 1))
      h(2, 2) = dot_product(a(:, 2), a(:, 2))
      h(1, 2) = dot_product(a(:, 1), a(:, 2))
      h(2, 1) = h(1, 2)
      det = h(1, 1)*h(2, 2) - h(1, 2)**2
      if (.not. det > 0.0_dp) exit
      dxi = [h(2, 2)*g(1) - h(1, 2)*g(2), h(1, 1)*g(2) - h(2, 1)*g(1)]/det
      do m = 0, max_halvings
        xt = min(max(xi + dxi, -1.0_dp), 1.0_dp)
        call face_geometry(s, f, x, xt, xq, a, n, jac)
        dnew = norm2(xs - xq)
        if (dnew <= dist*(1.0_dp + 1.0e-14_dp) + 1.0e-15_dp*scale) exit
        dxi = 0.5_dp*dxi
      end do
      dxi = xt - xi
      xi = xt
      xp = xq
      dist = dnew
      if (maxval(abs(dxi)) <= tol) exit
      ! a point far in front of the face (beyond an eighth of its size, within 60 degrees of
      ! its normal) gets no force from it whatever its exact closest point: stop there. The
      ! steps contract by about the distance times the curvature, so such points would take
      ! the most iterations; points near or behind the face converge to tol.
      if (it >= 4 .and. dist > 0.25_dp*scale .and. dot_product(xs - xp, n) > 0.5_dp*dist) exit
    end do
    call face_geometry(s, f, x, xi, xp, a, n, jac)
    ! on a side of the square the point is beyond the face where it pulls outward by more
    ! than an edge tolerance: the free Gauss-Newton step across that side,
    ! (xs - xp).a_k/|a_k|^2, above 0.05 (2.5 % of the face's width). A point whose closest
    ! point lies on the side, or just past it because the interpolated surface's tangent at
    ! the side is not that of the geometry (a node on a symmetry plane, where a quarter
    ! model's surface ends), is on the face.
    side = 0
    do c = 1, 4
      if (.not. on_side(xi, c)) cycle
      k = merge(2, 1, c == 1 .or. c == 3)
      pull = dot_product(xs - xp, a(:, k))*merge(1.0_dp, -1.0_dp, c == 2 .or. c == 3)
      if (pull > edge_tol*dot_product(a(:, k), a(:, k))) side = c
    end do
  end subroutine project_face

  !> Whether xi lies on side c (1: eta = -1, 2: xi = 1, 3: eta = 1, 4: xi = -1) of the
  !! square; the sides are those of the corners c, c+1 of the Q4 order.
  pure logical function on_side(xi, c)
    real(dp), intent(in) :: xi(2)
    integer, intent(in) :: c
    select case (c)
    case (1)
      on_side = xi(2) <= -1.0_dp
    case (2)
      on_side = xi(1) >= 1.0_dp
    case (3)
      on_side = xi(2) >= 1.0_dp
    case default
      on_side = xi(1) <= -1.0_dp
    end select
  end function on_side

  !> Closest point of surface s on the coordinates x to xs among the candidate faces cand
  !! (1:ncand): the interior projection of least distance; else the clamped one of least
  !! distance, a corner (mean normal of the two faces) if its side is shared, outside if it
  !! lies on the surface's boundary. Failures of Gauss-Newton (a degenerate face) leave the
  !! face's last iterate, which the distance comparison then judges.
  pure subroutine project3d(s, x, xs, cand, ncand, res)
    type(surface3d_t), intent(in) :: s
    real(dp), intent(in) :: x(:,:), xs(3)
    integer, intent(in) :: cand(:), ncand
    type(projection3d_t), intent(out) :: res
    real(dp) :: xi(2), xp(3), n(3), dist, best_in, best_cl, n2(3), a(3, 2), jac, xq(3), xi2(2)
    integer :: k, f, side, f_cl, side_cl, f2, s2
    real(dp) :: xi_cl(2), xp_cl(3), n_cl(3), lb(ncand), box(6), t
    integer :: order(ncand), j, i
    best_in = huge(1.0_dp)
    best_cl = huge(1.0_dp)
    f_cl = 0
    side_cl = 0
    xi_cl = 0.0_dp
    xp_cl = 0.0_dp
    n_cl = 0.0_dp
    ! the faces in the order of a lower bound of their distance (to their box, which holds
    ! the face): once an interior projection is found, a face whose bound is not below its
    ! distance cannot give a closer one and is not projected (most candidates of a search
    ! radius of a face size are such)
    do k = 1, ncand
      call face_bbox(s, cand(k), x, 0.0_dp, box)
      lb(k) = norm2(max(box(1:3) - xs, 0.0_dp, xs - box(4:6)))
      order(k) = k
    end do
    do k = 2, ncand
      i = order(k)
      t = lb(i)
      j = k - 1
      do while (j >= 1)
        if (lb(order(j)) <= t) exit
        order(j + 1) = order(j)
        j = j - 1
      end do
      order(j + 1) = i
    end do
    do k = 1, ncand
      if (lb(order(k)) >= best_in) exit
      f = cand(order(k))
      call project_face(s, f, x, xs, xi, xp, n, side)
      dist = norm2(xs - xp)
      if (side == 0) then
        if (dist < best_in) then
          best_in = dist
          res%status = P3_INTERIOR
          res%face = f
          res%xi = xi
          res%xbar = xp
          res%normal = n
        end if
      else if (dist < best_cl) then
        best_cl = dist
        f_cl = f
        side_cl = side
        xi_cl = xi
        xp_cl = xp
        n_cl = n
      end if
    end do
    if (res%status /= P3_INTERIOR .and. f_cl > 0) then
      res%face = f_cl
      res%xi = xi_cl
      res%xbar = xp_cl
      f2 = s%nbr(side_cl, f_cl)
      if (f2 > 0) then
        ! over the fold between f_cl and f2: the mean of their normals at the shared point
        call project_face(s, f2, x, xs, xi2, xq, n2, s2)
        call face_geometry(s, f2, x, xi2, xq, a, n2, jac)
        res%status = P3_CORNER
        n = n_cl + n2
        res%normal = n/max(norm2(n), tiny(1.0_dp))
      else
        res%status = P3_OUTSIDE
        res%normal = n_cl
      end if
    end if
    if (res%status /= P3_NONE) then
      res%d = dot_product(xs - res%xbar, res%normal)
      res%dist = norm2(xs - res%xbar)
    end if
  end subroutine project3d
end module ictus_contact_face3d
