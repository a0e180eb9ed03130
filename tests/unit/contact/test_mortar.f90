!> MORTAR contact (doc/contact.md §4) through the public API, against exact answers.
!!
!! * Contact patch test on non-matching meshes (ratios 8:11 = 1:1.375 and 10:21 = 1:2.1; Q8
!!   against Q8, NURBS against NURBS, Q8 against NURBS): a uniform penetration g of a flat
!!   interface of length L gives the pressure eps g at every slave node, the consistent nodal
!!   loads eps g l_A of that pressure on both surfaces (l_A = int N_A dGamma of each
!!   surface's own basis), resultants -+eps g L and the energy 1/2 eps g^2 L.
!!   NODE TO SEGMENT is shown failing it (its master loads are not the consistent ones);
!!   TWO HALF PASS passes it (each half-pass loads its own surface consistently).
!! * Action = reaction on a curved, non-matching interface (a non-uniform gap): the two
!!   resultants of MORTAR cancel to round-off; TWO HALF PASS's do not.
!! * The forces are the gradient of the energy: central differences of the energy (exact
!!   for a quadratic energy) under slave node motions and a rigid master motion.
!! * The stability ratio equals l_s/m_s + l_m/m_m where l/m is uniform on each side.
!! * Outside points: slave points behind the master but beyond its end are counted.
!! * Lost points (doc/contact.md §3): points in contact that then lie beyond the search radius
!!   inside the other body (tunnelling) are counted as outside points, for every algorithm;
!!   once found open they are not.
!! * *TIE (doc/contact.md §4b) on coincident non-matching surfaces: a uniform relative
!!   displacement d of the upper body gives the traction eps d at every slave node (tension
!!   and shear alike) and its consistent loads on both surfaces; a rigid motion of both
!!   bodies (translation and rotation) gives no force.
program test_mortar
  use ictus_core_kinds, only: dp
  use ictus_test_check, only: checker_t
  use ictus_test_contact, only: q8_row, q8_surface, nurbs_surface
  use ictus_geometry_sides, only: SIDE_ETA0, SIDE_ETA1
  use ictus_contact_contact, only: contact_t, contact_init, contact_define_pair, &
      contact_setup, contact_forces, contact_stability, contact_failures, &
      PAIR_TWO_HALF_PASS, PAIR_NODE_TO_SEGMENT, PAIR_MORTAR, PAIR_TIE
  implicit none
  type(checker_t) :: t
  real(dp), parameter :: eps = 1.0e5_dp, gap = 1.0e-3_dp, len = 2.0_dp
  integer, parameter :: Q8 = 1, NURBS = 2
  call t%start("contact/mortar")
  call patch_test(t, Q8, 8, Q8, 11, 'Q8 8 vs 11')
  call patch_test(t, Q8, 10, Q8, 21, 'Q8 10 vs 21')
  call patch_test(t, NURBS, 8, NURBS, 11, 'NURBS 8 vs 11')
  call patch_test(t, NURBS, 10, NURBS, 21, 'NURBS 10 vs 21')
  call patch_test(t, Q8, 8, NURBS, 11, 'Q8 8 vs NURBS 11')
  call patch_test(t, NURBS, 21, Q8, 10, 'NURBS 21 vs Q8 10')
  call others_on_patch_test(t)
  call curved_balance(t)
  call energy_gradient(t, NURBS, 'NURBS slave')
  call energy_gradient(t, Q8, 'Q8 slave')
  call stability(t)
  call outside(t)
  call tunnelling(t, PAIR_MORTAR, 'lost, MORTAR')
  call tunnelling(t, PAIR_TWO_HALF_PASS, 'lost, TWO HALF PASS')
  call tunnelling(t, PAIR_NODE_TO_SEGMENT, 'lost, NODE TO SEGMENT')
  call tie(t, Q8, 8, NURBS, 11, 'tie Q8 8 vs NURBS 11')
  call tie(t, NURBS, 10, Q8, 21, 'tie NURBS 10 vs Q8 21')
  call t%finish()

contains

  !> Two bodies meeting on y = 0: the lower (first surface: its top, the slave) with n1
  !! elements or spans, the upper (second: its bottom) with n2, moved down by gap; pair 1 of
  !! `kind`. Returns nn, the coordinates and (optional) the lower body's node count.
  subroutine two_bodies(c, k1, n1, k2, n2, kind, x, nn, nlow)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: k1, n1, k2, n2, kind
    real(dp), intent(inout) :: x(:,:)
    integer, intent(out) :: nn
    integer, intent(out), optional :: nlow
    integer :: e1(8, n1), e2(8, n2), ierr
    nn = 0
    call contact_init(c, 2, 1)
    if (k1 == Q8) then
      call q8_row(n1, 0.0_dp, -1.0_dp, len/n1, 1.0_dp, x, nn, e1)
      call q8_surface(c, 1, 'LOW', e1, 3, x(:, 1:nn))
    else
      call nurbs_surface(c, 1, 'LOW', 0.0_dp, -1.0_dp, len, n1, SIDE_ETA1, x, nn, ierr)
      call t%equal_int(ierr, 0, 'LOW side')
    end if
    if (present(nlow)) nlow = nn
    if (k2 == Q8) then
      call q8_row(n2, 0.0_dp, -gap, len/n2, 1.0_dp, x, nn, e2)
      call q8_surface(c, 2, 'UP', e2, 1, x(:, 1:nn))
    else
      call nurbs_surface(c, 2, 'UP', 0.0_dp, -gap, len, n2, SIDE_ETA0, x, nn, ierr)
      call t%equal_int(ierr, 0, 'UP side')
    end if
    call contact_define_pair(c, 1, 'flat', kind, eps, 1, 2)
    call contact_setup(c)
  end subroutine two_bodies

  !> The contact patch test of MORTAR on one pair of meshes (see the top).
  subroutine patch_test(t, k1, n1, k2, n2, label)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: k1, n1, k2, n2
    character(len=*), intent(in) :: label
    type(contact_t) :: c
    real(dp) :: x(2, 600), fc(2, 600), energy, f1(2), f2(2)
    integer :: nn, k
    call two_bodies(c, k1, n1, k2, n2, PAIR_MORTAR, x, nn)
    fc(:, 1:nn) = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    associate (p => c%pairs(1), s1 => c%surfaces(1), s2 => c%surfaces(2))
      call t%equal_int(contact_failures(c), 0, label//': no projection failures')
      call t%close(p%force_first(2), -eps*gap*len, 1.0e-12_dp, label//': resultant on slave')
      call t%close(p%force_second(2), eps*gap*len, 1.0e-12_dp, label//': resultant on master')
      call t%close_abs(p%force_first(1), 0.0_dp, 1.0e-12_dp*eps*gap, label//': no shear')
      call t%close_abs(p%force_first(2) + p%force_second(2), 0.0_dp, &
          1.0e-13_dp*eps*gap*len, label//': action = reaction')
      call t%close(energy, 0.5_dp*eps*gap**2*len, 1.0e-12_dp, label//': energy')
      call t%equal_int(p%npoints, s1%nsn, label//': a point per slave node')
      call t%equal_int(p%active_points, s1%nsn, label//': every slave node active')
      do k = 1, s1%nsn
        call t%close(p%pressure(k), eps*gap, 1.0e-12_dp, label//': uniform pressure')
      end do
      f1 = 0.0_dp
      do k = 1, s1%nsn
        call t%close(fc(2, s1%nodes(k)), -eps*gap*s1%ell(k), 1.0e-11_dp, &
            label//': consistent load on the slave')
        f1 = f1 + fc(:, s1%nodes(k))
      end do
      f2 = 0.0_dp
      do k = 1, s2%nsn
        call t%close(fc(2, s2%nodes(k)), eps*gap*s2%ell(k), 1.0e-11_dp, &
            label//': consistent load on the master')
        f2 = f2 + fc(:, s2%nodes(k))
      end do
      call t%close(f1(2), p%force_first(2), 1.0e-12_dp, label//': slave nodal forces sum')
      call t%close(f2(2), p%force_second(2), 1.0e-12_dp, label//': master nodal forces sum')
    end associate
  end subroutine patch_test

  !> The largest relative error of the master nodal loads against eps g l_C, for `kind`.
  real(dp) function master_load_error(kind, k1, n1, k2, n2) result(err)
    integer, intent(in) :: kind, k1, n1, k2, n2
    type(contact_t) :: c
    real(dp) :: x(2, 600), fc(2, 600), energy
    integer :: nn, k
    call two_bodies(c, k1, n1, k2, n2, kind, x, nn)
    fc(:, 1:nn) = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    err = 0.0_dp
    associate (s2 => c%surfaces(2))
      do k = 1, s2%nsn
        err = max(err, abs(fc(2, s2%nodes(k)) - eps*gap*s2%ell(k))/(eps*gap*s2%ell(k)))
      end do
    end associate
  end function master_load_error

  !> The patch test with the other algorithms: NODE TO SEGMENT fails it on non-matching
  !! meshes (its master loads are the slave loads interpolated at the closest points);
  !! TWO HALF PASS passes it.
  subroutine others_on_patch_test(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: e
    e = master_load_error(PAIR_NODE_TO_SEGMENT, Q8, 8, Q8, 11)
    print '(a, es10.3)', '  NODE TO SEGMENT, Q8 8 vs 11: largest master load error ', e
    call t%true(e > 0.05_dp, 'NODE TO SEGMENT fails the patch test on 8 vs 11 (> 5 %)')
    e = master_load_error(PAIR_NODE_TO_SEGMENT, NURBS, 10, NURBS, 21)
    print '(a, es10.3)', '  NODE TO SEGMENT, NURBS 10 vs 21: largest master load error ', e
    call t%true(e > 0.05_dp, 'NODE TO SEGMENT fails the patch test on 10 vs 21 (> 5 %)')
    e = master_load_error(PAIR_TWO_HALF_PASS, Q8, 8, Q8, 11)
    print '(a, es10.3)', '  TWO HALF PASS, Q8 8 vs 11: largest master load error ', e
    call t%true(e < 1.0e-11_dp, 'TWO HALF PASS passes the flat patch test')
  end subroutine others_on_patch_test

  !> Curved non-matching interface: both bodies (Q8 8 below, NURBS 11 above, pressed
  !! together by gap) mapped by y -> y + 0.1 sin(1.3 x); the two discretisations of the
  !! curve differ, so the gap varies along it.
  subroutine curved_balance(t)
    type(checker_t), intent(inout) :: t
    type(contact_t) :: c
    real(dp) :: x(2, 600), fc(2, 600), energy, bal(2), f
    integer :: nn, kind
    do kind = 1, 2
      call two_bodies(c, Q8, 8, NURBS, 11, merge(PAIR_MORTAR, PAIR_TWO_HALF_PASS, kind == 1), &
          x, nn)
      x(2, 1:nn) = x(2, 1:nn) + 0.1_dp*sin(1.3_dp*x(1, 1:nn))
      fc(:, 1:nn) = 0.0_dp
      call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
      associate (p => c%pairs(1))
        bal = p%force_first + p%force_second
        f = norm2(p%force_first)
        if (kind == 1) then
          print '(a, es10.3)', '  curved 8 vs 11, MORTAR: |F1 + F2|/|F1| = ', norm2(bal)/f
          call t%true(f > 0.5_dp*eps*gap*len, 'curved: in contact')
          call t%true(norm2(bal) <= 1.0e-13_dp*f, 'curved: MORTAR action = reaction')
          call t%true(maxval(p%pressure) > 1.01_dp*minval(p%pressure, p%pressure > 0.0_dp), &
              'curved: the pressure varies')
        else
          print '(a, es10.3)', '  curved 8 vs 11, TWO HALF PASS: |F1 + F2|/|F1| = ', &
              norm2(bal)/f
          call t%true(norm2(bal) > 1.0e-6_dp*f, 'curved: TWO HALF PASS is out of balance')
        end if
      end associate
    end do
  end subroutine curved_balance

  !> Penalty energy of pair 1 on x.
  real(dp) function energy_at(c, nn, x) result(energy)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: nn
    real(dp), intent(in) :: x(:,:)
    real(dp) :: fc(2, nn)
    fc = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc, energy)
  end function energy_at

  !> f = -dW/dx: a tilted master (Q8 11 above NURBS 8 or Q8 8, penetration from gap to
  !! gap/2 along the interface; on Q8 the mortar weights are not the shape functions); central differences of the energy in y at every slave node and for a
  !! rigid y motion of the master.
  subroutine energy_gradient(t, k1, label)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: k1
    character(len=*), intent(in) :: label
    type(contact_t) :: c
    real(dp) :: x(2, 600), xp(2, 600), fc(2, 600), energy, h, dw, fm
    integer :: nn, k, g, nlow
    call two_bodies(c, k1, 8, Q8, 11, PAIR_MORTAR, x, nn, nlow)
    ! the upper body tilted: y + gap x/(2 len); the lower one shrunk to [0.1, 1.9] along x,
    ! so that no slave point is near a master end (where the overlap length would move)
    x(2, nlow + 1:nn) = x(2, nlow + 1:nn) + 0.5_dp*gap*x(1, nlow + 1:nn)/len
    x(1, 1:nlow) = 1.0_dp + 0.9_dp*(x(1, 1:nlow) - 1.0_dp)
    fc(:, 1:nn) = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    h = 1.0e-3_dp*gap
    associate (s1 => c%surfaces(1), s2 => c%surfaces(2))
      do k = 1, s1%nsn
        g = s1%nodes(k)
        xp(:, 1:nn) = x(:, 1:nn)
        xp(2, g) = x(2, g) + h
        dw = energy_at(c, nn, xp)
        xp(2, g) = x(2, g) - h
        dw = (dw - energy_at(c, nn, xp))/(2.0_dp*h)
        call t%close_abs(-dw, fc(2, g), 1.0e-7_dp*eps*gap*len/s1%nsn, &
            label//': slave node force = -dW/dy')
      end do
      fm = 0.0_dp
      do k = 1, s2%nsn
        fm = fm + fc(2, s2%nodes(k))
      end do
      xp(:, 1:nn) = x(:, 1:nn)
      xp(2, s2%nodes) = x(2, s2%nodes) + h
      dw = energy_at(c, nn, xp)
      xp(2, s2%nodes) = x(2, s2%nodes) - h
      dw = (dw - energy_at(c, nn, xp))/(2.0_dp*h)
      call t%close(-dw, fm, 1.0e-7_dp, label//': master resultant = -dW/dY (rigid motion)')
    end associate
  end subroutine energy_gradient

  !> Stability ratio with l/m = 1/c1 on every slave node and 1/c2 on every master node:
  !! r = dt^2 eps (1/c1 + 1/c2) on matching and non-matching meshes.
  subroutine stability(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: c1 = 0.3_dp, c2 = 0.7_dp, dt = 1.0e-4_dp
    type(contact_t) :: c
    real(dp) :: x(2, 600), m(600), r
    character(len=128) :: where
    integer :: nn, k, n2
    do n2 = 8, 11, 3
      call two_bodies(c, NURBS, 8, NURBS, n2, PAIR_MORTAR, x, nn)
      m(1:nn) = 1.0_dp
      do k = 1, c%surfaces(1)%nsn
        m(c%surfaces(1)%nodes(k)) = c1*c%surfaces(1)%ell(k)
      end do
      do k = 1, c%surfaces(2)%nsn
        m(c%surfaces(2)%nodes(k)) = c2*c%surfaces(2)%ell(k)
      end do
      call contact_stability(c, nn, x(:, 1:nn), m(1:nn), dt, r, where)
      call t%close(r, dt*dt*eps*(1.0_dp/c1 + 1.0_dp/c2), 1.0e-12_dp, &
          'stability: r = dt^2 eps (l_s/m_s + l_m/m_m)')
      call t%true(index(where, 'flat: node') == 1, 'stability: names the node')
    end do
    m(c%surfaces(2)%nodes(3)) = 0.0_dp
    call contact_stability(c, nn, x(:, 1:nn), m(1:nn), dt, r, where)
    call t%true(r >= huge(1.0_dp), 'stability: a zero mass gives r = huge')
  end subroutine stability

  !> A slave twice as long as the master: LOW [0, 2] (Q8 8) under UP [0, 1] (Q8 4), both
  !! penetrating by gap; the slave points over (1, 1 + search radius] lie behind the
  !! master's end tangent and project beyond it. The mortar weights of the quadratic edges are
  !! the Bernstein polynomials (each integrates to h/3 over an edge), so the corner node at
  !! x = 1 has l = 2h/3, half of it under the master: p = eps g/2. Resultant: eps g (1 - h/3)
  !! from the nodes with all their support under the master, plus eps g/2 times h/3 from
  !! the node at x = 1: eps g (1 - h/6), h = 0.25.
  subroutine outside(t)
    type(checker_t), intent(inout) :: t
    type(contact_t) :: c
    real(dp) :: x(2, 600), fc(2, 600), energy
    integer :: nn, e1(8, 8), e2(8, 4)
    nn = 0
    call contact_init(c, 2, 1)
    call q8_row(8, 0.0_dp, -1.0_dp, 0.25_dp, 1.0_dp, x, nn, e1)
    call q8_surface(c, 1, 'LOW', e1, 3, x(:, 1:nn))
    call q8_row(4, 0.0_dp, -gap, 0.25_dp, 1.0_dp, x, nn, e2)
    call q8_surface(c, 2, 'UP', e2, 1, x(:, 1:nn))
    call contact_define_pair(c, 1, 'half', PAIR_MORTAR, eps, 1, 2)
    call contact_setup(c)
    fc(:, 1:nn) = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    associate (p => c%pairs(1))
      call t%true(p%outside_points > 0, 'outside: counted')
      call t%equal_int(p%outside_surf, 1, 'outside: on the slave')
      call t%true(p%outside_x(1) > 1.0_dp, 'outside: the first one lies beyond x = 1')
      call t%close(p%force_second(2), eps*gap*(1.0_dp - 0.25_dp/6.0_dp), 1.0e-12_dp, &
          'outside: the resultant of the overlap')
      call t%close_abs(p%force_first(2) + p%force_second(2), 0.0_dp, 1.0e-10_dp, &
          'outside: action = reaction')
    end associate
  end subroutine outside

  !> Tunnelling: Q8 8 under Q8 11, penetrating by gap (all points in contact); the upper body
  !! then moved down by 1 (twice the segment length beyond the search radius: no point has a
  !! candidate), then back above the lower one (open).
  subroutine tunnelling(t, kind, label)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: kind
    character(len=*), intent(in) :: label
    type(contact_t) :: c
    real(dp) :: x(2, 600), fc(2, 600), energy
    integer :: nn, nlow
    call two_bodies(c, Q8, 8, Q8, 11, kind, x, nn, nlow)
    fc(:, 1:nn) = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    call t%equal_int(c%pairs(1)%outside_points, 0, label//': in contact, none lost')
    call t%true(c%pairs(1)%active_points > 0, label//': in contact')
    x(2, nlow + 1:nn) = x(2, nlow + 1:nn) - 1.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    call t%true(c%pairs(1)%outside_points > 0, label//': deep inside, counted')
    call t%equal_int(c%pairs(1)%active_points, 0, label//': deep inside, no force')
    call t%equal_int(c%pairs(1)%outside_surf, 1, label//': the first on the first surface')
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    call t%equal_int(c%pairs(1)%outside_points, size(c%pairs(1)%inside), &
        label//': still counted, every point')
    x(2, nlow + 1:nn) = x(2, nlow + 1:nn) + 1.0_dp + 2.0_dp*gap
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    call t%equal_int(c%pairs(1)%outside_points, 0, label//': open again, none')
    x(2, nlow + 1:nn) = x(2, nlow + 1:nn) - 3.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    call t%equal_int(c%pairs(1)%outside_points, 0, label//': far away from open: none')
  end subroutine tunnelling

  !> A tie between the lower body's top (slave) and the upper body's bottom, both on y = 0.
  subroutine tie(t, k1, n1, k2, n2, label)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: k1, n1, k2, n2
    character(len=*), intent(in) :: label
    real(dp), parameter :: d(2) = [3.0e-4_dp, -5.0e-4_dp], th = 0.2_dp
    type(contact_t) :: c
    real(dp) :: x(2, 600), x0(2, 600), fc(2, 600), energy, rot(2, 2)
    integer :: nn, nlow, k
    call two_bodies(c, k1, n1, k2, n2, PAIR_MORTAR, x, nn, nlow)
    ! the upper body back onto y = 0: the surfaces coincide
    x(2, nlow + 1:nn) = x(2, nlow + 1:nn) + gap
    x0(:, 1:nn) = x(:, 1:nn)
    c%pairs(1)%kind = PAIR_TIE
    call contact_setup(c, x0(:, 1:nn))
    call t%true(c%pairs(1)%mo%n > 0 .and. c%pairs(1)%mo%untied == 0, label//': all tied')
    x(:, nlow + 1:nn) = x(:, nlow + 1:nn) + spread(d, 2, nn - nlow)
    fc(:, 1:nn) = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    associate (p => c%pairs(1), s1 => c%surfaces(1), s2 => c%surfaces(2))
      do k = 1, s1%nsn
        call t%close(fc(1, s1%nodes(k)), eps*d(1)*s1%ell(k), 1.0e-11_dp, &
            label//': consistent x load on the slave')
        call t%close(fc(2, s1%nodes(k)), eps*d(2)*s1%ell(k), 1.0e-11_dp, &
            label//': consistent y load on the slave')
      end do
      do k = 1, s2%nsn
        call t%close(fc(1, s2%nodes(k)), -eps*d(1)*s2%ell(k), 1.0e-11_dp, &
            label//': consistent x load on the master')
        call t%close(fc(2, s2%nodes(k)), -eps*d(2)*s2%ell(k), 1.0e-11_dp, &
            label//': consistent y load on the master')
      end do
      call t%close(p%force_first(1), eps*d(1)*len, 1.0e-12_dp, label//': shear resultant')
      call t%close(p%force_first(2), eps*d(2)*len, 1.0e-12_dp, label//': tension resultant')
      call t%close_abs(norm2(p%force_first + p%force_second), 0.0_dp, 1.0e-13_dp*eps* &
          norm2(d)*len, label//': action = reaction')
      call t%close(energy, 0.5_dp*eps*dot_product(d, d)*len, 1.0e-12_dp, label//': energy')
    end associate
    ! both bodies moved rigidly: turned by th about (0.3, -0.2) and shifted
    rot = reshape([cos(th), sin(th), -sin(th), cos(th)], [2, 2])
    do k = 1, nn
      x(:, k) = matmul(rot, x0(:, k) - [0.3_dp, -0.2_dp]) + [0.3_dp, -0.2_dp] + d
    end do
    fc(:, 1:nn) = 0.0_dp
    call contact_forces(c, nn, x(:, 1:nn), fc(:, 1:nn), energy)
    call t%close_abs(maxval(abs(fc(:, 1:nn))), 0.0_dp, 1.0e-9_dp*eps*norm2(d), &
        label//': a rigid motion gives no force')
  end subroutine tie
end program test_mortar
