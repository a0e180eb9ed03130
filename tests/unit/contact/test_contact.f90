!> Contact forces and stability through the public API (contact_t): flat interfaces between
!! straight Q8 meshes and NURBS patches with a uniform penetration g (doc/contact.md §4-5,
!! doc/reference.md §4), a rigid wall, node-to-segment, and the stability ratio of
!! doc/contact.md §6.
!!
!! Exact answers for a flat interface of length L with penetration g: pressure eps g at every
!! contact point, resultant eps g L on each body (equal and opposite), penalty energy
!! 1/2 eps g^2 L, nodal forces eps g l_A.
program test_contact
  use ictus_core_kinds, only: dp
  use ictus_test_check, only: checker_t
  use ictus_elements_types, only: ETYPE_Q8
  use ictus_geometry_patch, only: patch_t, patch_refine
  use ictus_geometry_sides, only: SIDE_ETA0, SIDE_ETA1
  use ictus_contact_surface, only: surface_init, face_segment, element_area, &
      patch_side_segments, SEG_LAGRANGE, SEG_BEZIER
  use ictus_test_contact, only: q8_row, q8_surface, nurbs_surface
  use ictus_contact_contact, only: contact_t, contact_init, contact_define_pair, &
      contact_define_wall, contact_setup, contact_forces, contact_stability, &
      contact_failures, PAIR_TWO_HALF_PASS, PAIR_NODE_TO_SEGMENT, PAIR_WALL, &
      contact_define_friction, contact_commit, PAIR_MORTAR
  implicit none
  type(checker_t) :: t
  real(dp), parameter :: eps = 1.0e5_dp, gap = 1.0e-3_dp, len = 2.0_dp
  call t%start("contact/contact")
  call q8_two_half_pass(t, 4, 4, 'Q8 matching')
  call q8_two_half_pass(t, 4, 5, 'Q8 4 vs 5')
  call nurbs_two_half_pass(t, .false., 'NURBS')
  call nurbs_two_half_pass(t, .true., 'Q8 vs NURBS')
  call q8_node_to_segment(t)
  call q8_rigid_wall(t)
  call q8_stability(t)
  call hertz_mirror(t)
  call friction_steps(t, PAIR_WALL, 'friction, wall')
  call friction_steps(t, PAIR_NODE_TO_SEGMENT, 'friction, NTS')
  call friction_steps(t, PAIR_TWO_HALF_PASS, 'friction, THP')
  call friction_steps(t, PAIR_MORTAR, 'friction, MORTAR')
  call outside_points(t)
  call t%finish()

contains

  !> Checks of a flat interface along y = 0 (first surface below, second above, pair 1).
  subroutine check_flat(t, c, nn, x, label)
    type(checker_t), intent(inout) :: t
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: nn
    real(dp), intent(in) :: x(:,:)
    character(len=*), intent(in) :: label
    real(dp) :: fc(2, nn), energy, integral, f1(2)
    integer :: q, k
    fc = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc, energy)
    associate (p => c%pairs(1), s1 => c%surfaces(1), s2 => c%surfaces(2))
      call t%close(p%force_first(2), -eps*gap*len, 1.0e-12_dp, label//': resultant first')
      call t%close(p%force_second(2), eps*gap*len, 1.0e-12_dp, label//': resultant second')
      call t%close_abs(p%force_first(1), 0.0_dp, 1.0e-9_dp, label//': no tangential force')
      call t%close_abs(p%force_first(2) + p%force_second(2), 0.0_dp, 1.0e-9_dp, &
          label//': momentum balance')
      call t%close(energy, 0.5_dp*eps*gap**2*len, 1.0e-10_dp, label//': energy')
      call t%close(p%max_pressure, eps*gap, 1.0e-9_dp, label//': max pressure')
      call t%close(p%max_penetration, gap, 1.0e-9_dp, label//': max penetration')
      call t%equal_int(p%active_points, s1%ngp + s2%ngp, label//': active points')
      call t%equal_int(contact_failures(c), 0, label//': no projection failures')
      call t%equal_int(p%npoints, s1%ngp, label//': output points')
      integral = 0.0_dp
      do q = 1, s1%ngp
        call t%close(p%pressure(q), eps*gap, 1.0e-9_dp, label//': pressure at a point')
        integral = integral + p%pressure(q)*s1%gp_wj(q)
      end do
      call t%close(integral, -p%force_first(2), 1.0e-12_dp, label//': int p = resultant')
      f1 = 0.0_dp
      do k = 1, s1%nsn
        f1 = f1 + fc(:, s1%nodes(k))
        call t%close(fc(2, s1%nodes(k)), -eps*gap*s1%ell(k), 1.0e-9_dp, &
            label//': nodal force eps g l_A')
      end do
      call t%close(f1(2), p%force_first(2), 1.0e-12_dp, label//': nodal forces sum')
    end associate
  end subroutine check_flat

  !> Two Q8 rows: below y = 0 (face S3, ne1 elements) and above y = -gap (face S1, ne2).
  subroutine q8_two_half_pass(t, ne1, ne2, label)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: ne1, ne2
    character(len=*), intent(in) :: label
    type(contact_t) :: c
    real(dp) :: x(2, 200)
    integer :: nn, e1(8, ne1), e2(8, ne2), e
    nn = 0
    call q8_row(ne1, 0.0_dp, -1.0_dp, len/ne1, 1.0_dp, x, nn, e1)
    call q8_row(ne2, 0.0_dp, -gap, len/ne2, 1.0_dp, x, nn, e2)
    do e = 1, ne1
      call t%true(element_area(ETYPE_Q8, x(:, e1(:, e))) > 0.0_dp, label//': area > 0')
    end do
    call contact_init(c, 2, 1)
    call q8_surface(c, 1, 'LOW', e1, 3, x(:, 1:nn))
    call q8_surface(c, 2, 'UP', e2, 1, x(:, 1:nn))
    call contact_define_pair(c, 1, 'Flat', PAIR_TWO_HALF_PASS, eps, 1, 2)
    call contact_setup(c)
    call t%true(c%pairs(1)%name == 'flat', label//': name in lower case')
    call check_flat(t, c, nn, x, label)
  end subroutine q8_two_half_pass

  !> Two NURBS patches (4 and 5 spans along the interface), or a Q8 row against a patch.
  subroutine nurbs_two_half_pass(t, q8_first, label)
    type(checker_t), intent(inout) :: t
    logical, intent(in) :: q8_first
    character(len=*), intent(in) :: label
    type(contact_t) :: c
    real(dp) :: x(2, 400)
    integer :: nn, e1(8, 3), ierr
    nn = 0
    call contact_init(c, 2, 1)
    if (q8_first) then
      call q8_row(3, 0.0_dp, -1.0_dp, len/3, 1.0_dp, x, nn, e1)
      call q8_surface(c, 1, 'LOW', e1, 3, x(:, 1:nn))
    else
      call nurbs_surface(c, 1, 'LOW', 0.0_dp, -1.0_dp, len, 4, SIDE_ETA1, x, nn, ierr)
      call t%equal_int(ierr, 0, 'LOW: side ok')
    end if
    call nurbs_surface(c, 2, 'UP', 0.0_dp, -gap, len, 5, SIDE_ETA0, x, nn, ierr)
    call t%equal_int(ierr, 0, 'UP: side ok')
    call contact_define_pair(c, 1, 'flat', PAIR_TWO_HALF_PASS, eps, 1, 2)
    call contact_setup(c)
    call check_flat(t, c, nn, x, label)
  end subroutine nurbs_two_half_pass

  !> NODE TO SEGMENT: nodes of the upper Q8 row's face (slave) against the lower row.
  subroutine q8_node_to_segment(t)
    type(checker_t), intent(inout) :: t
    type(contact_t) :: c
    real(dp) :: x(2, 200), fc(2, 200), energy, fsum(2)
    integer :: nn, e1(8, 4), e2(8, 5), k
    nn = 0
    call q8_row(4, 0.0_dp, -1.0_dp, len/4, 1.0_dp, x, nn, e1)
    call q8_row(5, 0.0_dp, -gap, len/5, 1.0_dp, x, nn, e2)
    call contact_init(c, 2, 1)
    call q8_surface(c, 1, 'UP', e2, 1, x(:, 1:nn))
    call q8_surface(c, 2, 'LOW', e1, 3, x(:, 1:nn))
    call contact_define_pair(c, 1, 'nts', PAIR_NODE_TO_SEGMENT, eps, 1, 2)
    call contact_setup(c)
    fc = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    associate (p => c%pairs(1), s1 => c%surfaces(1))
      call t%close(p%force_first(2), eps*gap*len, 1.0e-12_dp, 'NTS: resultant on slave')
      call t%close(p%force_second(2), -eps*gap*len, 1.0e-12_dp, 'NTS: resultant on master')
      call t%close(energy, 0.5_dp*eps*gap**2*len, 1.0e-10_dp, 'NTS: energy')
      call t%equal_int(p%npoints, s1%nsn, 'NTS: one output point per slave node')
      call t%equal_int(p%active_points, s1%nsn, 'NTS: all slave nodes active')
      do k = 1, s1%nsn
        call t%close(fc(2, s1%nodes(k)), eps*gap*s1%ell(k), 1.0e-9_dp, 'NTS: eps g l_s')
        call t%close(p%pressure(k), eps*gap, 1.0e-9_dp, 'NTS: pressure')
      end do
      fsum = sum(fc(:, 1:nn), dim=2)
      call t%close_abs(fsum(2), 0.0_dp, 1.0e-9_dp, 'NTS: forces balance')
    end associate
  end subroutine q8_node_to_segment

  !> Rigid wall y = 0 (normal (0, 1)) against the lower face of a Q8 row at y = -gap.
  subroutine q8_rigid_wall(t)
    type(checker_t), intent(inout) :: t
    type(contact_t) :: c
    real(dp) :: x(2, 100), fc(2, 100), energy
    integer :: nn, e2(8, 5), q
    nn = 0
    call q8_row(5, 0.0_dp, -gap, len/5, 1.0_dp, x, nn, e2)
    call contact_init(c, 1, 1)
    call q8_surface(c, 1, 'UP', e2, 1, x(:, 1:nn))
    call contact_define_wall(c, 1, 'Floor', [3.0_dp, 0.0_dp], [0.0_dp, 2.0_dp], eps, 1)
    call contact_setup(c)
    fc = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    associate (p => c%pairs(1), s1 => c%surfaces(1))
      call t%close(p%force_first(2), eps*gap*len, 1.0e-12_dp, 'wall: resultant on surface')
      call t%close(p%force_second(2), -eps*gap*len, 1.0e-12_dp, 'wall: force on the wall')
      call t%close(sum(fc(2, 1:nn)), eps*gap*len, 1.0e-12_dp, 'wall: nodal forces sum')
      call t%close(energy, 0.5_dp*eps*gap**2*len, 1.0e-10_dp, 'wall: energy')
      do q = 1, s1%ngp
        call t%close(p%pressure(q), eps*gap, 1.0e-9_dp, 'wall: pressure')
        call t%close(p%x(2, q), -gap, 1.0e-12_dp, 'wall: point y')
      end do
    end associate
    ! moved clear of the wall: no force
    x(2, 1:nn) = x(2, 1:nn) + 2.0_dp*gap
    fc = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    call t%close_abs(maxval(abs(fc(:, 1:nn))), 0.0_dp, 0.0_dp, 'wall: open, no force')
    call t%equal_int(c%pairs(1)%active_points, 0, 'wall: open, no active point')
  end subroutine q8_rigid_wall

  !> Stability ratio of a straight Q8 HRZ (2x2, corner 1/36, midside 8/36 of rho h^2) edge of
  !! square elements, doc/contact.md §6 with dt^2 eps/rho = 0.025: against a rigid wall the
  !! corner gives r_s = dt^2 eps (h/3)/(rho h^2/18) = 0.15/h; two identical meshes twice that.
  subroutine q8_stability(t)
    type(checker_t), intent(inout) :: t
    type(contact_t) :: c
    real(dp), parameter :: h = 0.5_dp, rho = 1.0_dp, dt = 5.0e-4_dp
    real(dp) :: x(2, 200), m(200), r, r_pair(2)
    integer :: nn, e1(8, 4), e2(8, 4), e, a
    character(len=200) :: where
    nn = 0
    call q8_row(4, 0.0_dp, -h, h, h, x, nn, e1)
    call q8_row(4, 0.0_dp, 0.0_dp, h, h, x, nn, e2)
    m = 0.0_dp
    do e = 1, 4
      do a = 1, 8
        if (a <= 4) then
          m(e1(a, e)) = m(e1(a, e)) + rho*h*h/36.0_dp
          m(e2(a, e)) = m(e2(a, e)) + rho*h*h/36.0_dp
        else
          m(e1(a, e)) = m(e1(a, e)) + 8.0_dp*rho*h*h/36.0_dp
          m(e2(a, e)) = m(e2(a, e)) + 8.0_dp*rho*h*h/36.0_dp
        end if
      end do
    end do
    call contact_init(c, 2, 2)
    call q8_surface(c, 1, 'LOW', e1, 3, x(:, 1:nn))
    call q8_surface(c, 2, 'UP', e2, 1, x(:, 1:nn))
    call t%close(c%surfaces(1)%ell(1), h/3.0_dp, 1.0e-12_dp, 'corner l_s = h/3')
    call contact_define_wall(c, 1, 'wall', [0.0_dp, 0.0_dp], [0.0_dp, -1.0_dp], 1.0e5_dp, 1)
    call contact_define_pair(c, 2, 'pair', PAIR_TWO_HALF_PASS, 1.0e5_dp, 1, 2)
    call contact_setup(c)
    ! the wall alone
    c%npairs = 1
    call contact_stability(c, nn, x(:, 1:nn), m(1:nn), dt, r, where)
    call t%close(r, 0.15_dp/h, 1.0e-10_dp, 'rigid wall: r = 0.15/h')
    call t%true(index(where, 'wall: node') == 1, 'rigid wall: where names the node')
    c%npairs = 2
    call contact_stability(c, nn, x(:, 1:nn), m(1:nn), dt, r, where)
    call t%close(r, 2.0_dp*0.15_dp/h, 1.0e-10_dp, 'two Q8 bodies: r = 2 x 0.15/h')
    call t%true(index(where, 'pair: node') == 1 .and. index(where, 'against node') > 0, &
        'two bodies: where names both nodes')
    call contact_stability(c, nn, x(:, 1:nn), m(1:nn), dt, r, where, r_pair)
    call t%close(r_pair(1), 0.15_dp/h, 1.0e-10_dp, 'per pair: the wall r = 0.15/h')
    call t%close(r_pair(2), 2.0_dp*0.15_dp/h, 1.0e-10_dp, 'per pair: the pair r = 0.3/h')
    call t%close(r, maxval(r_pair), 0.0_dp, 'per pair: r_max is the largest')
  end subroutine q8_stability

  !> The two half-discs of the benchmark (doc/iga.md §10.4, R = 4, refined 8 x 8), mirror
  !! images about y = 0 (the lower one has det J > 0, the upper det J < 0), pushed into each
  !! other by 2 delta; contact surfaces: the XI0 arcs, which end at the contact point (0, 0).
  !! Mirrored meshes: the y-forces are equal and opposite to round-off, the x-forces equal.
  subroutine hertz_mirror(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: r = 4.0_dp, delta = 0.01_dp
    type(contact_t) :: c
    type(patch_t) :: up, low
    real(dp) :: cp(3, 9), x(2, 200), fc(2, 200), energy, cw, tn
    integer :: nn, nseg, ierr, k
    integer, allocatable :: nens(:), conn(:,:), elem(:), kinds(:)
    real(dp), allocatable :: wgt(:,:), ext(:,:,:)
    cw = cos(acos(-1.0_dp)/8.0_dp)
    tn = tan(acos(-1.0_dp)/8.0_dp)
    cp = reshape([0.0_dp, -r, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, r, 1.0_dp, &
        r*tn, -r, cw, r/2, 0.0_dp, 1.0_dp, r*tn, r, cw, &
        r/sqrt(2.0_dp), -r/sqrt(2.0_dp), 1.0_dp, r*sqrt(2.0_dp), 0.0_dp, sqrt(0.5_dp), &
        r/sqrt(2.0_dp), r/sqrt(2.0_dp), 1.0_dp], [3, 9])
    cp(2, :) = cp(2, :) + r - delta
    call up%init('UP', [2, 2], [3, 3], [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], &
        [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], cp)
    cp(2, :) = -cp(2, :)
    call low%init('LOW', [2, 2], [3, 3], [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], &
        [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], cp)
    call patch_refine(up, [8, 8])
    call patch_refine(low, [8, 8])
    call contact_init(c, 2, 1)
    nn = 0
    do k = 1, 2
      if (k == 1) then
        x(:, nn+1:nn+up%n(1)*up%n(2)) = up%cp(1:2, :)
        call patch_side_segments(up, nn, 1, nseg, nens, conn, wgt, ext, elem, ierr)
        nn = nn + up%n(1)*up%n(2)
      else
        x(:, nn+1:nn+low%n(1)*low%n(2)) = low%cp(1:2, :)
        call patch_side_segments(low, nn, 1, nseg, nens, conn, wgt, ext, elem, ierr)
        nn = nn + low%n(1)*low%n(2)
      end if
      call t%equal_int(ierr, 0, 'hertz: side oriented')
      if (allocated(kinds)) deallocate(kinds)
      allocate(kinds(nseg))
      kinds = SEG_BEZIER
      call surface_init(c%surfaces(k), 'ARC', kinds, nens, conn, x(:, 1:nn), wgt=wgt, &
          ext=ext)
    end do
    call contact_define_pair(c, 1, 'hertz', PAIR_TWO_HALF_PASS, eps, 1, 2)
    call contact_setup(c)
    fc = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    associate (p => c%pairs(1))
      call t%true(p%force_first(2) > 0.0_dp, 'hertz: upper body pushed up')
      call t%close(p%force_first(2), -p%force_second(2), 1.0e-10_dp, 'hertz: P1 = P2')
      call t%close(p%force_first(1), p%force_second(1), 1.0e-10_dp, 'hertz: mirrored x')
      ! the Gauss points sit near, not at, the first contact point (0, 0) where gp = 2 delta
      call t%true(p%max_penetration < 2.0_dp*delta .and. p%max_penetration > 1.9_dp*delta, &
          'hertz: max gp just below 2 delta')
      call t%equal_int(p%failures, 0, 'hertz: no failed projections')
    end associate
  end subroutine hertz_mirror

  !> Coulomb friction (doc/contact.md §4a) on a flat interface of length L = len with
  !! penetration g: mu = 0.2, eps_T = eps/2, so the cone is mu eps g = 20 per unit length.
  !! The upper body (a Q8 row above a longer fixed row, or pressed onto the wall y = 0 from
  !! below) moves along x in committed steps: 1e-4 (stick: t = eps_T 1e-4 = 5, elastic energy
  !! t^2/(2 eps_T) L, no work), then 5e-4 (trial 30 > 20: slip, t = 20, slip (30 - 20)/eps_T,
  !! work 20 * 2e-4 L), then back by 2e-4 (trial 20 - 10 = 10: stick again). The friction force
  !! on the first surface is -t L along the motion; evaluating again without a commit gives
  !! the same; frictional work enters contact_t%friction_work only at the commits.
  subroutine friction_steps(t, kind, label)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: kind
    character(len=*), intent(in) :: label
    real(dp), parameter :: mu = 0.2_dp, eps_t = 0.5_dp*eps
    real(dp), parameter :: shift(3) = [1.0e-4_dp, 5.0e-4_dp, -2.0e-4_dp]
    real(dp), parameter :: trac(3) = [5.0_dp, 20.0_dp, 10.0_dp], work(3) = [0.0_dp, &
        20.0_dp*2.0e-4_dp*len, 0.0_dp]
    type(contact_t) :: c
    real(dp) :: x(2, 200), fc(2, 200), energy, e_n, f1(2)
    integer :: nn, nup, e1(8, 6), e2(8, 4), k
    nn = 0
    call q8_row(4, 0.0_dp, -gap, len/4, 1.0_dp, x, nn, e2)
    nup = nn
    if (kind == PAIR_WALL) then
      call contact_init(c, 1, 1)
      call q8_surface(c, 1, 'UP', e2, 1, x(:, 1:nn))
      call contact_define_wall(c, 1, 'floor', [0.0_dp, 0.0_dp], [0.0_dp, 1.0_dp], eps, 1)
    else
      call q8_row(6, -0.5_dp, -1.0_dp, len/4, 1.0_dp, x, nn, e1)
      call contact_init(c, 2, 1)
      call q8_surface(c, 1, 'UP', e2, 1, x(:, 1:nn))
      call q8_surface(c, 2, 'LOW', e1, 3, x(:, 1:nn))
      call contact_define_pair(c, 1, 'slide', kind, eps, 1, 2)
    end if
    call contact_define_friction(c, 1, mu, eps_t)
    call contact_setup(c)
    fc = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), e_n)
    call t%close_abs(c%pairs(1)%fr%force(1), 0.0_dp, 1.0e-12_dp, label//': no motion, no '// &
        'friction')
    call contact_commit(c, nn, x(:, 1:nn))
    do k = 1, 3
      x(1, 1:nup) = x(1, 1:nup) + shift(k)
      call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
      f1 = c%pairs(1)%fr%force
      call t%close(-f1(1), trac(k)*len, 1.0e-9_dp, label//': friction force')
      call t%close_abs(f1(2), 0.0_dp, 1.0e-9_dp, label//': friction force is tangential')
      call t%close(energy - e_n, 0.5_dp*trac(k)**2/eps_t*len, 1.0e-6_dp, &
          label//': elastic tangential energy')
      call t%close_abs(c%pairs(1)%fr%dwork, work(k), 1.0e-12_dp, label//': frictional work')
      call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
      call t%close(c%pairs(1)%fr%force(1), f1(1), 0.0_dp, label//': again the same '// &
          'without a commit')
      call contact_commit(c, nn, x(:, 1:nn))
    end do
    call t%close(c%friction_work, work(2), 1.0e-9_dp, label//': committed frictional work')
  end subroutine friction_steps

  !> Outside points (doc/contact.md §3): LOW = [0, 2h] x [0, h] (contact face its top, 2 Q8),
  !! UP = [1.4h, 3.4h] x [h - g, 2h - g] (its bottom face). The interfaces overlap on
  !! [1.4h, 2h]; beyond LOW's right end (x = 2h) UP's Gauss points lie below LOW's top line
  !! (behind its end tangent), and left of UP's left end LOW's lie above UP's bottom line.
  !! Gauss points of a quadratic edge at (1/2 -+ sqrt(3/5)/2) h and h/2 from its start:
  !! UP: 1.513h, 1.9h, 2.287h, 2.513h, 2.9h, 3.287h (4 beyond 2h, 2 in the overlap); LOW (face 3
  !! runs right to left, the same points): 0.113h, 0.5h, 0.887h, 1.113h, 1.5h, 1.887h (4 left
  !! of 1.4h, 2 in the overlap). The candidates are the segments whose boxes, grown by the
  !! search radius h, hold the point: UP's point at 3.287h is more than h beyond LOW's end
  !! (box [0, 3h]) and LOW's at 0.113h more than h before UP's start (box [0.4h, 3.4h]), so
  !! they have none and are not looked at (doc/contact.md §3, limits). So 3 + 3 = 6 outside
  !! points, 4 active ones, the first outside point on the first surface (UP); with a gap
  !! instead, none.
  subroutine outside_points(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: h = 0.5_dp, g = 1.0e-3_dp
    type(contact_t) :: c
    real(dp) :: x(2, 200), fc(2, 200), energy, sgn
    integer :: nn, e1(8, 2), e2(8, 2), k
    do k = 1, 2
      sgn = merge(1.0_dp, -1.0_dp, k == 1)
      nn = 0
      call q8_row(2, 0.0_dp, 0.0_dp, h, h, x, nn, e1)
      call q8_row(2, 1.4_dp*h, h - sgn*g, h, h, x, nn, e2)
      call contact_init(c, 2, 1)
      call q8_surface(c, 1, 'UP', e2, 1, x(:, 1:nn))
      call q8_surface(c, 2, 'LOW', e1, 3, x(:, 1:nn))
      call contact_define_pair(c, 1, 'pair', PAIR_TWO_HALF_PASS, eps, 1, 2)
      call contact_setup(c)
      fc = 0.0_dp
      call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
      associate (p => c%pairs(1))
        if (k == 1) then
          call t%equal_int(p%outside_points, 6, 'outside: 6 points behind the other end')
          call t%equal_int(p%active_points, 4, 'outside: 4 active points in the overlap')
          call t%equal_int(p%outside_surf, 1, 'outside: the first on the first surface')
          call t%true(p%outside_x(1) > 2.0_dp*h .and. abs(p%outside_x(2) - (h - g)) < &
              1.0e-12_dp, 'outside: the first point lies on UP beyond x = 2h')
          call t%true(p%outside_total == 6, 'outside: run total')
        else
          call t%equal_int(p%outside_points, 0, 'outside: none with a gap')
          call t%equal_int(p%active_points, 0, 'outside: none active with a gap')
        end if
      end associate
    end do
  end subroutine outside_points
end program test_contact
