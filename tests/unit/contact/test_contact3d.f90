!> 3D contact kernels (doc/contact.md §9) against exact answers: surfaces of 4-, 8- and
!! 9-node quadrilateral faces built on node grids, no elements needed.
!!
!! * Flat interface: the top of a lower body (z = 0, 3 x 3 faces) and the bottom of an upper
!!   one (4 x 4 faces, non-matching) moved down by g. TWO HALF PASS: pressure eps g at every
!!   point, resultants -/+ eps g A along z, the consistent nodal loads eps g l_A on both
!!   surfaces, energy 1/2 eps g^2 A. A rigid wall under the upper body: resultant eps g A.
!! * Projection onto a curved surface that 9-node faces represent exactly (the paraboloid
!!   z = c (x^2 + y^2) over a bilinear (x, y) parametrisation): points put at a signed
!!   distance delta along the exact normal project back with d = delta (1e-11).
!! * A point beyond the surface's boundary and behind it is outside; a point over the fold
!!   between two faces at an angle gets their mean normal (a corner).
!! * Rational Bezier faces: a quarter cylinder of radius R from two exact quadratic arcs of
!!   45 degrees (middle weight cos 22.5 degrees) times a linear span along the axis: points at
!!   a signed distance delta along the radius project back with d = delta (1e-10), sum l_A is
!!   the area pi R L/2 (1e-10 with 8 x 8 Gauss points), the two faces are neighbours.
program test_contact3d
  use ictus_core_kinds, only: dp
  use ictus_test_check, only: checker_t
  use ictus_contact_face3d, only: surface3d_t, surface3d_init, projection3d_t, project3d, &
      face_bbox, P3_INTERIOR, P3_CORNER, P3_OUTSIDE
  use ictus_contact_search3d, only: grid3_t, grid3_init, grid3_build, grid3_query
  use ictus_contact_pair3d, only: pair3d_t, pair3d_setup, two_half_pass3d, wall3d
  implicit none
  type(checker_t) :: t
  real(dp), parameter :: eps = 1.0e5_dp, gap = 1.0e-3_dp, lx = 2.0_dp, ly = 1.5_dp
  call t%start("contact/contact3d")
  call flat(t, 4, 8, 'Q4 3x3 against Q8 4x4')
  call flat(t, 9, 4, 'Q9 3x3 against Q4 4x4')
  call paraboloid(t)
  call outside_and_fold(t)
  call cylinder(t)
  call t%finish()

contains

  !> Faces of a node grid of ne x ne faces (nen nodes each: 4, 8 or 9) over [0, lx] x [0, ly]
  !! at height z, appended to x (3, nn); up = .true.: normals +z, else -z.
  subroutine grid_faces(ne, nen, z, up, x, nn, nens, conn, nf)
    integer, intent(in) :: ne, nen
    real(dp), intent(in) :: z
    logical, intent(in) :: up
    real(dp), intent(inout) :: x(:,:)
    integer, intent(inout) :: nn, nf
    integer, intent(inout) :: nens(:), conn(:,:)
    integer :: i, j, m, id(0:2*ne, 0:2*ne), c(9), k
    m = 2*ne
    do j = 0, m
      do i = 0, m
        id(i, j) = 0
        if (nen /= 9 .and. mod(i, 2) == 1 .and. mod(j, 2) == 1) cycle
        if (nen == 4 .and. (mod(i, 2) == 1 .or. mod(j, 2) == 1)) cycle
        nn = nn + 1
        id(i, j) = nn
        x(:, nn) = [lx*i/m, ly*j/m, z]
      end do
    end do
    do j = 0, m - 2, 2
      do i = 0, m - 2, 2
        nf = nf + 1
        ! corners counter-clockwise seen from +z, midsides of 1-2, 2-3, 3-4, 4-1, centre
        c = [id(i, j), id(i + 2, j), id(i + 2, j + 2), id(i, j + 2), id(i + 1, j), &
            id(i + 2, j + 1), id(i + 1, j + 2), id(i, j + 1), id(i + 1, j + 1)]
        if (.not. up) c = [c(1), c(4), c(3), c(2), c(8), c(7), c(6), c(5), c(9)]
        nens(nf) = nen
        conn(:, nf) = 0
        do k = 1, nen
          conn(k, nf) = c(k)
        end do
      end do
    end do
  end subroutine grid_faces

  subroutine flat(t, nen1, nen2, label)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: nen1, nen2
    character(len=*), intent(in) :: label
    type(surface3d_t) :: s1, s2
    type(pair3d_t) :: p, w
    real(dp) :: x(3, 400), fc(3, 400), area
    integer :: nn, n1, n2, nens1(16), conn1(9, 16), nens2(16), conn2(9, 16), k
    nn = 0
    n1 = 0
    n2 = 0
    call grid_faces(3, nen1, 0.0_dp, .true., x, nn, nens1, conn1, n1)
    call grid_faces(4, nen2, -gap, .false., x, nn, nens2, conn2, n2)
    call surface3d_init(s1, nens1(1:n1), conn1(:, 1:n1), x(:, 1:nn))
    call surface3d_init(s2, nens2(1:n2), conn2(:, 1:n2), x(:, 1:nn))
    area = lx*ly
    call t%close(sum(s1%ell), area, 1.0e-13_dp, label//': sum l_A = area')
    p%penalty = eps
    call pair3d_setup(p, s1, s2, .false.)
    fc(:, 1:nn) = 0.0_dp
    call two_half_pass3d(p, s1, s2, x(:, 1:nn), fc(:, 1:nn))
    call t%close(p%force_first(3), -eps*gap*area, 1.0e-12_dp, label//': resultant on the first')
    call t%close(p%force_second(3), eps*gap*area, 1.0e-12_dp, label//': resultant on the second')
    call t%close_abs(norm2(p%force_first(1:2)), 0.0_dp, 1.0e-9_dp, label//': no shear')
    call t%close(p%energy, 0.5_dp*eps*gap**2*area, 1.0e-12_dp, label//': energy')
    call t%close(p%max_pressure, eps*gap, 1.0e-9_dp, label//': pressure eps g')
    call t%equal_int(p%active_points, s1%ngp + s2%ngp, label//': every point active')
    call t%equal_int(p%outside_points, 0, label//': no outside point')
    do k = 1, s1%nsn
      call t%close(fc(3, s1%nodes(k)), -eps*gap*s1%ell(k), 1.0e-9_dp, &
          label//': consistent load on the first')
    end do
    do k = 1, s2%nsn
      call t%close(fc(3, s2%nodes(k)), eps*gap*s2%ell(k), 1.0e-9_dp, &
          label//': consistent load on the second')
    end do
    ! the upper surface on a rigid wall z = 0 (normal +z)
    w%penalty = eps
    w%wall_point = 0.0_dp
    w%wall_normal = [0.0_dp, 0.0_dp, 2.0_dp]
    call pair3d_setup(w, s2, s2, .true.)
    fc(:, 1:nn) = 0.0_dp
    call wall3d(w, s2, x(:, 1:nn), fc(:, 1:nn))
    call t%close(w%force_first(3), eps*gap*area, 1.0e-12_dp, label//': wall resultant')
    call t%close(w%energy, 0.5_dp*eps*gap**2*area, 1.0e-12_dp, label//': wall energy')
  end subroutine flat

  !> 9-node faces on z = c (x^2 + y^2): exact geometry, normal (-2cx, -2cy, 1)/|.|.
  subroutine paraboloid(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: c = 0.3_dp
    type(surface3d_t) :: s
    type(projection3d_t) :: pr
    type(grid3_t) :: g
    real(dp) :: x(3, 400), xs(3), n(3), delta, px, py
    integer :: nn, nf, nens(16), conn(9, 16), k, cand(16), ncand, i
    nn = 0
    nf = 0
    call grid_faces(4, 9, 0.0_dp, .true., x, nn, nens, conn, nf)
    x(3, 1:nn) = c*(x(1, 1:nn)**2 + x(2, 1:nn)**2)
    call surface3d_init(s, nens(1:nf), conn(:, 1:nf), x(:, 1:nn))
    call grid3_init(g, nf)
    do k = 1, nf
      call face_bbox(s, k, x(:, 1:nn), 0.5_dp, g%box(:, k))
    end do
    call grid3_build(g)
    do i = 1, 12
      px = 0.1_dp + 1.8_dp*modulo(0.618_dp*i, 1.0_dp)
      py = 0.1_dp + 1.3_dp*modulo(0.382_dp*i + 0.2_dp, 1.0_dp)
      n = [-2.0_dp*c*px, -2.0_dp*c*py, 1.0_dp]
      n = n/norm2(n)
      delta = 1.0e-2_dp*merge(1.0_dp, -1.0_dp, mod(i, 2) == 0)
      xs = [px, py, c*(px*px + py*py)] + delta*n
      call grid3_query(g, xs, cand, ncand)
      call t%true(ncand > 0, 'paraboloid: candidates found')
      call project3d(s, x(:, 1:nn), xs, cand, ncand, pr)
      call t%equal_int(pr%status, P3_INTERIOR, 'paraboloid: interior projection')
      call t%close(pr%d, delta, 1.0e-10_dp, 'paraboloid: signed distance = delta')
      call t%close_abs(norm2(pr%normal - n), 0.0_dp, 1.0e-10_dp, 'paraboloid: exact normal')
    end do
  end subroutine paraboloid

  !> Two Q4 faces folded along x = 1 (the second rises at 45 degrees); a point above the
  !! fold and one behind the surface beyond its boundary.
  subroutine outside_and_fold(t)
    type(checker_t), intent(inout) :: t
    type(surface3d_t) :: s
    type(projection3d_t) :: pr
    real(dp) :: x(3, 6), n(3)
    integer :: nens(2), conn(9, 2)
    x(:, 1) = [0.0_dp, 0.0_dp, 0.0_dp]
    x(:, 2) = [1.0_dp, 0.0_dp, 0.0_dp]
    x(:, 3) = [1.0_dp, 1.0_dp, 0.0_dp]
    x(:, 4) = [0.0_dp, 1.0_dp, 0.0_dp]
    x(:, 5) = [2.0_dp, 0.0_dp, -1.0_dp]
    x(:, 6) = [2.0_dp, 1.0_dp, -1.0_dp]
    nens = 4
    conn = 0
    conn(1:4, 1) = [1, 2, 3, 4]
    conn(1:4, 2) = [2, 5, 6, 3]
    call surface3d_init(s, nens, conn, x)
    call t%equal_int(s%nbr(2, 1), 2, 'fold: face 1 has face 2 across its side 2')
    call project3d(s, x, [1.1_dp, 0.5_dp, 0.3_dp], [1, 2], 2, pr)
    call t%equal_int(pr%status, P3_CORNER, 'fold: a point over the fold is a corner')
    n = [1.0_dp, 0.0_dp, 1.0_dp + sqrt(2.0_dp)]
    n = n/norm2(n)
    call t%close_abs(norm2(pr%normal - n), 0.0_dp, 1.0e-12_dp, 'fold: the mean normal')
    call project3d(s, x, [-0.2_dp, 0.5_dp, -0.05_dp], [1, 2], 2, pr)
    call t%equal_int(pr%status, P3_OUTSIDE, 'beyond the boundary: outside')
    call t%true(pr%d < 0.0_dp, 'beyond the boundary and behind: d < 0')
  end subroutine outside_and_fold

  !> Quarter cylinder x^2 + z^2 = R^2, x, z >= 0, 0 <= y <= L: two Bezier faces (arc 0..45
  !! and 45..90 degrees, quadratic rational) times a linear span in y, running from y = L to
  !! y = 0 so that a1 x a2 points outward.
  subroutine cylinder(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: rc = 2.0_dp, lc = 3.0_dp, pi = acos(-1.0_dp)
    type(surface3d_t) :: s
    type(projection3d_t) :: pr
    real(dp) :: x(3, 10), ext(4, 4, 2), wgt(16, 2), th, xs(3), delta, c45, yv
    integer :: nens(2), conn(16, 2), deg(2, 2), f, i, j, k
    c45 = cos(pi/8.0_dp)
    ! control points of the arcs in the x-z plane: angles 0, 22.5 (scaled 1/cos), 45, ...
    do j = 1, 2
      yv = merge(lc, 0.0_dp, j == 1)
      do i = 0, 4
        th = pi/8.0_dp*i
        x(:, i + 1 + 5*(j - 1)) = rc*[cos(th), 0.0_dp, sin(th)]/merge(c45, 1.0_dp, &
            mod(i, 2) == 1)
        x(2, i + 1 + 5*(j - 1)) = yv
      end do
    end do
    ext = 0.0_dp
    do k = 1, 4
      ext(k, k, :) = 1.0_dp
    end do
    deg(:, 1) = [2, 1]
    deg(:, 2) = [2, 1]
    nens = 6
    conn = 0
    wgt = 0.0_dp
    do f = 1, 2
      do j = 1, 2
        do i = 1, 3
          conn(i + 3*(j - 1), f) = 2*(f - 1) + i + 5*(j - 1)
          wgt(i + 3*(j - 1), f) = merge(c45, 1.0_dp, i == 2)
        end do
      end do
    end do
    call surface3d_init(s, nens, conn, x, ng=8, deg=deg, ext1=ext, ext2=ext, wgt=wgt)
    call t%close(sum(s%ell), 0.5_dp*pi*rc*lc, 1.0e-10_dp, 'cylinder: sum l_A = pi R L/2')
    call t%equal_int(s%nbr(2, 1), 2, 'cylinder: the faces are neighbours')
    do k = 1, 10
      th = 0.5_dp*pi*(0.05_dp + 0.09_dp*k)
      delta = 0.02_dp*merge(1.0_dp, -1.0_dp, mod(k, 3) == 0)
      xs = (rc + delta)*[cos(th), 0.0_dp, sin(th)]
      xs(2) = lc*(0.1_dp + 0.08_dp*k)
      call project3d(s, x, xs, [1, 2], 2, pr)
      call t%true(pr%status == P3_INTERIOR .or. pr%status == P3_CORNER, &
          'cylinder: projected')
      call t%close(pr%d, delta, 1.0e-10_dp, 'cylinder: signed distance = delta')
      call t%close_abs(norm2(pr%normal - [cos(th), 0.0_dp, sin(th)]), 0.0_dp, 1.0e-10_dp, &
          'cylinder: the radial normal')
    end do
  end subroutine cylinder
end program test_contact3d
