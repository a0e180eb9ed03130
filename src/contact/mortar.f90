!> MORTAR segment-to-segment penalty contact (doc/contact.md §4): the first surface is the
!! slave (its basis weights the gap), the second the master.
!!
!! * Integration: each slave segment is cut at the parameters where the end points of the
!!   master segments project onto it (closest point on the slave curve), so that every piece
!!   faces one master segment and the integrand is smooth on it; each piece gets
!!   max(p_s, p_m) + 1 Gauss points (exact for the product of two bases of degree p where
!!   the projection is affine: the patch test), weighted by the slave's reference length.
!!   Each point is projected onto the master (closest point, as the other algorithms):
!!   signed distance d, outward master normal n, master shape values M_C.
!! * Weighted gap and pressure of slave node A, with positive weights phi_A that sum to 1
!!   (the slave's shape functions N_A, except on 3-node Lagrange edges: `mortar_weights`):
!!   l_A = int phi_A dGamma, g_A = int phi_A d dGamma over the points with a closest point,
!!   p_A = eps max(0, -g_A)/l_A; energy W = sum_A 1/2 eps max(0, -g_A)^2/l_A.
!! * Forces from the same integrals on both sides: with lambda = sum_A phi_A p_A at a point,
!!   f_B = int N_B lambda n dGamma on slave node B and f_C = -int M_C lambda n dGamma on
!!   master node C (for a fixed normal, f = -dW/dx). Both bases are partitions of unity, so the two resultants are equal and
!!   opposite to round-off, on any pair of meshes; a uniform gap gives a uniform pressure
!!   and the consistent nodal loads of it on both sides (the contact patch test).
!! * Coulomb friction (doc/contact.md §4a) per slave node: the weighted slip
!!   s_A = int phi_A (du_s - du_m).tau dGamma / l_A (tau the master tangent), the traction
!!   t_A from `coulomb`, and the forces int N_B (sum_A phi_A t_A) tau dGamma like the normal
!!   ones.
module ictus_contact_mortar
  use ictus_core_kinds, only: dp
  use ictus_core_sort, only: sort
  use ictus_elements_quadrature, only: gauss_legendre
  use ictus_contact_surface, only: contact_surface_t, MAX_SEG_NODES, segment_shape, &
      surface_curves, curve_point, curve_geometry, CURVE_SAMPLES, SEG_LAGRANGE
  use ictus_contact_pair, only: contact_pair_t, mortar_t, pair_reset_results, update_grid, &
      closest_point, coulomb, point_increment, PAIR_TIE
  use ictus_contact_projection, only: projection_t, project_on_curve, project_point, &
      PROJ_INTERIOR, PROJ_CORNER, PROJ_OUTSIDE, SEG_INTERIOR, PROJ_NONE
  use ictus_contact_search, only: grid_query
  implicit none
  private
  public :: mortar_forces, mortar_ratio, mortar_points, mortar_weights, projected, distribute

  !> Most cuts of one slave segment (master segment ends projecting into it); more are
  !! ignored (the pieces are then integrated across a master segment end, less exactly).
  integer, parameter :: MAX_CUTS = 64
  !> Pieces shorter than this (in the slave parameter) are skipped.
  real(dp), parameter :: min_piece = 1.0e-12_dp
  !> Cuts closer than this to a segment end (in the slave parameter) are dropped: a sliver
  !! that thin carries less than 1e-3 of the segment and is integrated with the piece beside
  !! it.
  real(dp), parameter :: end_cut = 1.0e-3_dp
  !> Where both surfaces end together (at a symmetry plane, say) the deformed ends do not
  !! line up exactly, and the slave points within a hair of the slave's own end may lie
  !! just beyond the master's end. Such a point, within this fraction of the parameter of
  !! the slave's end segment from the slave surface's end, is not an outside point: the
  !! surfaces end there by design. It gets no force, like every point beyond the master.
  real(dp), parameter :: end_reach = 0.05_dp

contains

  !> The integration points of a mortar pair on the coordinates x (2, nn): pair%mo%n points
  !! with their closest points on the master; builds the master's grid and curves and the
  !! slave's curves. Projection failures are added to pair%failures; points that lie behind
  !! the master (d < 0) but project beyond its end are counted in pair%outside_points (the
  !! first one's coordinates and nearest slave node kept), except next to the slave's own
  !! end (end_reach).
  subroutine mortar_points(pair, s1, s2, x)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: s1, s2
    real(dp), intent(in) :: x(:,:)
    type(projection_t) :: pr
    real(dp) :: cut(0:MAX_CUTS + 1), xi(2*MAX_SEG_NODES), w(2*MAX_SEG_NODES)
    real(dp) :: t, h, xq(2), xr(2), x1(2), x2(2), r(MAX_SEG_NODES), dr(MAX_SEG_NODES), &
        ddr(MAX_SEG_NODES)
    integer :: s, k, q, ng, nc, nf, i
    call update_grid(s2, x, pair%radius, pair%grid_second, pair%curves_second)
    call surface_curves(s1, x, pair%curves_first)
    associate (mo => pair%mo)
      mo%n = 0
      do s = 1, s1%nseg
        call slave_cuts(pair, s1, s, cut, nc)
        ng = min(max(s1%nen(s), s2%nen_max), size(xi))
        call gauss_legendre(ng, xi(1:ng), w(1:ng))
        do k = 0, nc
          h = cut(k + 1) - cut(k)
          if (h <= min_piece) cycle
          do q = 1, ng
            if (mo%n == size(mo%sseg)) call grow(mo)
            mo%n = mo%n + 1
            i = mo%n
            t = cut(k) + 0.5_dp*h*(1.0_dp + xi(q))
            call curve_geometry(s1%ref(s), t, xr, x1, x2)
            call curve_point(pair%curves_first(s), t, xq)
            ! the points of a piece face one master segment: from the second point on,
            ! the previous point's segment (and a walk to its neighbours) is the candidate;
            ! the global search where that does not give an interior point
            nf = 0
            pr%status = PROJ_NONE
            if (q > 1 .and. mo%status(i - 1) == PROJ_INTERIOR) call project_point(s2, &
                pair%curves_second, xq, [mo%mseg(i - 1)], 1, pr, nf)
            if (pr%status /= PROJ_INTERIOR) call closest_point(s2, pair%grid_second, &
                pair%curves_second, xq, pair%cand, pr, nf)
            pair%failures = pair%failures + nf
            mo%sseg(i) = s
            mo%ts(i) = t
            mo%wj(i) = 0.5_dp*h*w(q)*norm2(x1)
            mo%status(i) = pr%status
            mo%mseg(i) = pr%seg
            mo%tm(i) = pr%t
            mo%normal(:, i) = pr%normal
            mo%d(i) = pr%d
            if (pr%status == PROJ_OUTSIDE .and. pr%d < 0.0_dp .and. .not. &
                at_slave_end(s1, s, t)) then
              pair%outside_points = pair%outside_points + 1
              if (pair%outside_points == 1) then
                call segment_shape(s1, s, t, r, dr, ddr)
                pair%outside_x = xq
                pair%outside_surf = 1
                pair%outside_node = s1%conn(maxloc(r(1:s1%nen(s)), 1), s)
              end if
            end if
          end do
        end do
      end do
    end associate
  end subroutine mortar_points

  !> The cuts of slave segment s: 0, the sorted parameters where master segment ends near
  !! the segment (the master grid's candidates at its ends and middle) project into its
  !! interior, 1; cut(0:nc+1).
  subroutine slave_cuts(pair, s1, s, cut, nc)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: s1
    integer, intent(in) :: s
    real(dp), intent(out) :: cut(0:)
    integer, intent(out) :: nc
    real(dp) :: xp(2), xe(2), t
    integer :: j, k, e, m, ncand, st, it, nseen, seen(MAX_CUTS)
    nc = 0
    nseen = 0
    do j = 0, 2
      call curve_point(pair%curves_first(s), 0.5_dp*real(j, dp), xp)
      call grid_query(pair%grid_second, xp, pair%cand, ncand)
      do k = 1, ncand
        m = pair%cand(k)
        ! the three queries mostly return the same segments: each is looked at once
        if (any(seen(1:nseen) == m)) cycle
        if (nseen < MAX_CUTS) then
          nseen = nseen + 1
          seen(nseen) = m
        end if
        do e = 0, 1
          xe = pair%curves_second(m)%xk(:, e*CURVE_SAMPLES)
          call project_on_curve(pair%curves_first(s), s1%seg_len(s), xe, t, st, it)
          if (st /= SEG_INTERIOR .or. nc >= MAX_CUTS) cycle
          if (t <= end_cut .or. t >= 1.0_dp - end_cut) cycle
          if (any(abs(cut(1:nc) - t) <= min_piece)) cycle
          nc = nc + 1
          cut(nc) = t
        end do
      end do
    end do
    call sort(cut(1:nc))
    cut(0) = 0.0_dp
    cut(nc + 1) = 1.0_dp
  end subroutine slave_cuts

  !> Whether parameter t of slave segment s lies within end_reach of an end of the surface.
  pure logical function at_slave_end(s1, s, t)
    type(contact_surface_t), intent(in) :: s1
    integer, intent(in) :: s
    real(dp), intent(in) :: t
    at_slave_end = (s1%prev(s) == 0 .and. t <= end_reach) .or. &
        (s1%next(s) == 0 .and. t >= 1.0_dp - end_reach)
  end function at_slave_end

  !> Doubles the point capacity of a mortar pair, keeping the points.
  subroutine grow(mo)
    type(mortar_t), intent(inout) :: mo
    integer, allocatable :: ia(:)
    real(dp), allocatable :: ra(:), rb(:,:)
    integer :: n, cap
    n = mo%n
    cap = max(2*size(mo%sseg), 64)
    allocate(ia(cap)); ia(1:n) = mo%sseg(1:n); call move_alloc(ia, mo%sseg)
    allocate(ia(cap)); ia(1:n) = mo%mseg(1:n); call move_alloc(ia, mo%mseg)
    allocate(ia(cap)); ia(1:n) = mo%status(1:n); call move_alloc(ia, mo%status)
    allocate(ra(cap)); ra(1:n) = mo%ts(1:n); call move_alloc(ra, mo%ts)
    allocate(ra(cap)); ra(1:n) = mo%tm(1:n); call move_alloc(ra, mo%tm)
    allocate(ra(cap)); ra(1:n) = mo%wj(1:n); call move_alloc(ra, mo%wj)
    allocate(ra(cap)); ra(1:n) = mo%d(1:n); call move_alloc(ra, mo%d)
    allocate(rb(2, cap)); rb(:, 1:n) = mo%normal(:, 1:n); call move_alloc(rb, mo%normal)
  end subroutine grow

  !> The mortar weights phi_A of the slave nodes of segment s at t (r: its shape values):
  !! the shape functions themselves where they are positive (linear edges, NURBS), the
  !! quadratic Bernstein polynomials (1-t)^2, 2t(1-t), t^2 on a 3-node Lagrange edge (nodes at
  !! t = 0, 1/2, 1). Those span the same quadratics and sum to 1, but are positive: with the
  !! Lagrange functions themselves the corner weights are negative on half the edge, so a
  !! corner's weighted gap can close while the edge is open, and its pressure then pulls
  !! (the Hertz run with Q8 faces gained 12 % energy; Puso, Laursen & Solberg, CMAME 197
  !! (2008) 555-566, change the quadratic basis of the weighted gap for the same reason).
  pure subroutine mortar_weights(s1, s, t, r, phi)
    type(contact_surface_t), intent(in) :: s1
    integer, intent(in) :: s
    real(dp), intent(in) :: t, r(:)
    real(dp), intent(out) :: phi(:)
    if (s1%kind(s) == SEG_LAGRANGE .and. s1%nen(s) == 3) then
      phi(1) = (1.0_dp - t)**2
      phi(2) = 2.0_dp*t*(1.0_dp - t)
      phi(3) = t*t
    else
      phi(1:s1%nen(s)) = r(1:s1%nen(s))
    end if
  end subroutine mortar_weights

  !> Whether mortar point i has a closest point on the master.
  pure logical function projected(mo, i)
    type(mortar_t), intent(in) :: mo
    integer, intent(in) :: i
    projected = mo%status(i) == PROJ_INTERIOR .or. mo%status(i) == PROJ_CORNER
  end function projected

  !> MORTAR forces of one pair: slave s1 (first surface) against master s2.
  !! @param pair the pair (results updated); @param s1, s2 its surfaces; @param x (2, nn);
  !! @param fc forces (2, nn), accumulated; @param xprev committed coordinates (2, nn) of
  !! the friction increments (not used without friction)
  subroutine mortar_forces(pair, s1, s2, x, fc, xprev)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: s1, s2
    real(dp), intent(in) :: x(:,:), xprev(:,:)
    real(dp), intent(inout) :: fc(:,:)
    real(dp) :: r(MAX_SEG_NODES), rm(MAX_SEG_NODES), dr(MAX_SEG_NODES), ddr(MAX_SEG_NODES)
    real(dp) :: tau(2), dg, tt, dw, et, gn, phi(MAX_SEG_NODES)
    integer :: i, s, a, la
    logical :: fric, seen(s1%nsn)
    call pair_reset_results(pair)
    call mortar_points(pair, s1, s2, x)
    fric = pair%fr%on
    associate (mo => pair%mo)
      mo%ell = 0.0_dp
      mo%gap = 0.0_dp
      mo%slip = 0.0_dp
      seen = .false.
      ! nodal weights, weighted gaps and (friction) weighted slips
      do i = 1, mo%n
        s = mo%sseg(i)
        call segment_shape(s1, s, mo%ts(i), r, dr, ddr)
        call mortar_weights(s1, s, mo%ts(i), r, phi)
        do a = 1, s1%nen(s)
          la = s1%lnode(a, s)
          mo%ell(la) = mo%ell(la) + phi(a)*mo%wj(i)
          if (mo%status(i) /= PROJ_NONE) seen(la) = .true.
        end do
        if (.not. projected(mo, i)) cycle
        do a = 1, s1%nen(s)
          la = s1%lnode(a, s)
          mo%gap(la) = mo%gap(la) + phi(a)*mo%d(i)*mo%wj(i)
        end do
        if (fric) then
          tau = [-mo%normal(2, i), mo%normal(1, i)]
          call segment_shape(s2, mo%mseg(i), mo%tm(i), rm, dr, ddr)
          dg = point_increment(s1%nen(s), r, s1%conn(:, s), x, xprev, tau) - &
              point_increment(s2%nen(mo%mseg(i)), rm, s2%conn(:, mo%mseg(i)), x, xprev, tau)
          do a = 1, s1%nen(s)
            la = s1%lnode(a, s)
            mo%slip(la) = mo%slip(la) + phi(a)*dg*mo%wj(i)
          end do
        end if
      end do
      ! nodal pressures and tractions, energy, results
      do la = 1, s1%nsn
        mo%p(la) = 0.0_dp
        mo%t(la) = 0.0_dp
        gn = 0.0_dp
        if (mo%ell(la) > 0.0_dp) gn = max(0.0_dp, -mo%gap(la))/mo%ell(la)
        mo%p(la) = pair%penalty*gn
        if (fric) then
          pair%fr%t_new(la) = 0.0_dp
          if (mo%ell(la) > 0.0_dp) then
            call coulomb(pair%fr%t_old(la), mo%slip(la)/mo%ell(la), mo%p(la), pair%fr%mu, &
                pair%fr%eps_t, tt, dw, et)
            mo%t(la) = tt
            pair%fr%t_new(la) = tt
            pair%fr%dwork = pair%fr%dwork + dw*mo%ell(la)
            pair%energy = pair%energy + et*mo%ell(la)
          end if
        end if
        pair%x(:, la) = x(:, s1%nodes(la))
        pair%pressure(la) = mo%p(la)
        call track_node(pair, la, seen(la), gn, x(:, s1%nodes(la)), s1%nodes(la))
        if (gn <= 0.0_dp) cycle
        pair%energy = pair%energy + 0.5_dp*mo%p(la)*gn*mo%ell(la)
        pair%max_pressure = max(pair%max_pressure, mo%p(la))
        pair%max_penetration = max(pair%max_penetration, gn)
        pair%active_points = pair%active_points + 1
      end do
      call apply_forces(pair, s1, s2, fc)
    end associate
    pair%failures_total = pair%failures_total + pair%failures
    pair%outside_total = pair%outside_total + pair%outside_points
  end subroutine mortar_forces

  !> The lost-point state of slave node la (pair%inside, ictus_contact_pair's `track`): a
  !! node none of whose mortar points has a candidate master segment (seen false) and that
  !! was in contact is lost, counted as an outside point (the first one's coordinates xa and
  !! node g kept); otherwise it is inside while its weighted gap penetrates (gn > 0).
  pure subroutine track_node(pair, la, seen, gn, xa, g)
    type(contact_pair_t), intent(inout) :: pair
    integer, intent(in) :: la, g
    logical, intent(in) :: seen
    real(dp), intent(in) :: gn, xa(2)
    if (seen) then
      pair%inside(la) = merge(1, 0, gn > 0.0_dp)
    else if (pair%inside(la) == 1) then
      pair%outside_points = pair%outside_points + 1
      if (pair%outside_points == 1) then
        pair%outside_x = xa
        pair%outside_surf = 1
        pair%outside_node = g
      end if
    end if
  end subroutine track_node

  !> The nodal forces of the pressures and tractions of pair%mo on both surfaces, from the
  !! same point values: lambda n + theta tau times w J, with lambda = sum_A phi_A p_A and
  !! theta = sum_A phi_A t_A, onto N_B (slave) and -M_C (master); the two resultants are
  !! summed from the nodal contributions separately.
  subroutine apply_forces(pair, s1, s2, fc)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: s1, s2
    real(dp), intent(inout) :: fc(:,:)
    real(dp) :: r(MAX_SEG_NODES), dr(MAX_SEG_NODES), ddr(MAX_SEG_NODES)
    real(dp) :: lam, theta, tau(2), tr(2), phi(MAX_SEG_NODES)
    integer :: i, s, a
    associate (mo => pair%mo)
      do i = 1, mo%n
        if (.not. projected(mo, i)) cycle
        s = mo%sseg(i)
        call segment_shape(s1, s, mo%ts(i), r, dr, ddr)
        call mortar_weights(s1, s, mo%ts(i), r, phi)
        lam = 0.0_dp
        theta = 0.0_dp
        do a = 1, s1%nen(s)
          lam = lam + phi(a)*mo%p(s1%lnode(a, s))
          theta = theta + phi(a)*mo%t(s1%lnode(a, s))
        end do
        if (lam == 0.0_dp .and. theta == 0.0_dp) cycle
        tau = [-mo%normal(2, i), mo%normal(1, i)]
        tr = (lam*mo%normal(:, i) + theta*tau)*mo%wj(i)
        if (theta /= 0.0_dp) pair%fr%force = pair%fr%force + theta*tau*mo%wj(i)
        call distribute(pair, s1, s2, i, r, tr, fc)
      end do
    end associate
  end subroutine apply_forces

  !> The force tr (2) of mortar point i onto the slave nodes of its segment (shape values r)
  !! and, with the opposite sign, onto the master nodes of its closest point; the resultants
  !! force_first and force_second summed from the nodal contributions.
  subroutine distribute(pair, s1, s2, i, r, tr, fc)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: s1, s2
    integer, intent(in) :: i
    real(dp), intent(in) :: r(:), tr(2)
    real(dp), intent(inout) :: fc(:,:)
    real(dp) :: rm(MAX_SEG_NODES), dr(MAX_SEG_NODES), ddr(MAX_SEG_NODES), f(2)
    integer :: s, m, a, g
    s = pair%mo%sseg(i)
    do a = 1, s1%nen(s)
      g = s1%conn(a, s)
      f = r(a)*tr
      fc(:, g) = fc(:, g) + f
      pair%force_first = pair%force_first + f
    end do
    m = pair%mo%mseg(i)
    call segment_shape(s2, m, pair%mo%tm(i), rm, dr, ddr)
    do a = 1, s2%nen(m)
      g = s2%conn(a, m)
      f = rm(a)*tr
      fc(:, g) = fc(:, g) - f
      pair%force_second = pair%force_second - f
    end do
  end subroutine distribute

  !> The largest MORTAR stability term of a pair (doc/contact.md §6): for each slave node A,
  !! q_A = <l/m>_slave + <l/m>_master, the means of l_B/m_B over the slave nodes and of
  !! l_C/m_C over the master nodes coupled to A, weighted by the mortar products
  !! int |phi_A N_B| dGamma and int |phi_A M_C| dGamma (the master mean is the largest l_C/m_C
  !! of the master where A has no closest point); r = dt^2 eps q_A. For matching meshes
  !! with uniform l/m this is l_s/m_s + l_m/m_m, the estimate of the other algorithms.
  !! @param pair the pair; @param s1, s2 slave and master; @param x (2, nn);
  !! @param m_diag lumped masses (nn); @param q_max largest q_A (huge, naming the node, if
  !! a mass of either surface is not positive); @param g_slave its slave node; @param g_master the master node most coupled to
  !! it (0 if none)
  subroutine mortar_ratio(pair, s1, s2, x, m_diag, q_max, g_slave, g_master)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: s1, s2
    real(dp), intent(in) :: x(:,:), m_diag(:)
    real(dp), intent(out) :: q_max
    integer, intent(out) :: g_slave, g_master
    real(dp) :: r(MAX_SEG_NODES), rm(MAX_SEG_NODES), dr(MAX_SEG_NODES), ddr(MAX_SEG_NODES)
    real(dp) :: ws(s1%nsn), ss(s1%nsn), wm(s1%nsn), sm(s1%nsn), best(s1%nsn), q, lm_all, &
        phi(MAX_SEG_NODES)
    integer :: near(s1%nsn), i, s, m, b, la, k
    q_max = 0.0_dp
    g_slave = 0
    g_master = 0
    do k = 1, s1%nsn + s2%nsn
      if (k <= s1%nsn) then
        b = s1%nodes(k)
      else
        b = s2%nodes(k - s1%nsn)
      end if
      if (m_diag(b) <= 0.0_dp) then
        q_max = huge(1.0_dp)
        g_slave = b
        return
      end if
    end do
    pair%failures = 0
    pair%outside_points = 0
    ! a tie keeps the points of its reference configuration
    if (pair%kind /= PAIR_TIE) call mortar_points(pair, s1, s2, x)
    ws = 0.0_dp
    ss = 0.0_dp
    wm = 0.0_dp
    sm = 0.0_dp
    best = -1.0_dp
    near = 0
    lm_all = 0.0_dp
    do k = 1, s2%nsn
      lm_all = max(lm_all, ell_over_m(s2%ell(k), m_diag(s2%nodes(k))))
    end do
    associate (mo => pair%mo)
      do i = 1, mo%n
        s = mo%sseg(i)
        call segment_shape(s1, s, mo%ts(i), r, dr, ddr)
        call mortar_weights(s1, s, mo%ts(i), r, phi)
        call couple(s1, s, phi, s1, s, r, mo%wj(i), m_diag, ws, ss)
        if (.not. projected(mo, i)) cycle
        m = mo%mseg(i)
        call segment_shape(s2, m, mo%tm(i), rm, dr, ddr)
        call couple(s1, s, phi, s2, m, rm, mo%wj(i), m_diag, wm, sm, best, near)
      end do
    end associate
    do la = 1, s1%nsn
      q = lm_all
      if (wm(la) > 0.0_dp) q = sm(la)/wm(la)
      if (ws(la) > 0.0_dp) q = q + ss(la)/ws(la)
      if (q > q_max .or. g_slave == 0) then
        q_max = q
        g_slave = s1%nodes(la)
        g_master = near(la)
      end if
    end do
  end subroutine mortar_ratio

  !> Adds the products c = |N_A R_B| wj of one point to w(A) and c l_B/m_B to sl(A), for the
  !! nodes A of segment s of `sa` (shape values ra) and B of segment m of `sb` (values rb);
  !! optional: the B with the largest c seen for each A (best, near).
  pure subroutine couple(sa, s, ra, sb, m, rb, wj, m_diag, w, sl, best, near)
    type(contact_surface_t), intent(in) :: sa, sb
    integer, intent(in) :: s, m
    real(dp), intent(in) :: ra(:), rb(:), wj, m_diag(:)
    real(dp), intent(inout) :: w(:), sl(:)
    real(dp), intent(inout), optional :: best(:)
    integer, intent(inout), optional :: near(:)
    real(dp) :: c
    integer :: a, b, la
    do a = 1, sa%nen(s)
      la = sa%lnode(a, s)
      do b = 1, sb%nen(m)
        c = abs(ra(a)*rb(b))*wj
        w(la) = w(la) + c
        sl(la) = sl(la) + c*ell_over_m(sb%ell(sb%lnode(b, m)), m_diag(sb%conn(b, m)))
        if (present(best)) then
          if (c > best(la)) then
            best(la) = c
            near(la) = sb%conn(b, m)
          end if
        end if
      end do
    end do
  end subroutine couple

  !> l/m (the masses are checked positive first).
  pure real(dp) function ell_over_m(ell, m)
    real(dp), intent(in) :: ell, m
    ell_over_m = ell/m
  end function ell_over_m
end module ictus_contact_mortar
