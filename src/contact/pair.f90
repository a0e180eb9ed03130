!> Contact pairs and rigid walls: definition, results, and the penalty force algorithms
!! TWO HALF PASS and NODE TO SEGMENT (doc/contact.md §3-5).
!!
!! * TWO HALF PASS: the Gauss points of each surface are projected onto the other; a point
!!   with penetration gp > 0 gets the traction eps gp n (n: outward normal of the other
!!   surface), distributed onto its own surface's nodes with its own shape functions and
!!   weights w_q J_q. Nothing is put on the other surface in that half-pass.
!! * NODE TO SEGMENT: each node (control point) s of the first surface, weighted by
!!   l_s = int N_s dGamma, against the second: +eps gp l_s n on s, -eps gp l_s R_A n on the
!!   master nodes A of the closest point.
!! * Coulomb friction (doc/contact.md §4a), when the pair has mu > 0: each contact point adds
!!   the tangential traction t tau (tau = (-n_y, n_x), the master's tangent), t from the
!!   penalty-regularised stick t_trial = t_old - eps_T dg_T and the return to the cone
!!   |t| <= mu p on slip; dg_T is the point's tangential displacement relative to the master
!!   since the last committed evaluation (contact_commit).
module ictus_contact_pair
  use ictus_core_kinds, only: dp, i8, str_len
  use ictus_contact_surface, only: contact_surface_t, MAX_SEG_NODES, segment_bbox, &
      segment_shape, segment_curve_t, surface_curves
  use ictus_contact_search, only: search_grid_t, grid_init, grid_build, grid_query
  use ictus_contact_projection, only: projection_t, project_point, PROJ_INTERIOR, &
      PROJ_CORNER, PROJ_OUTSIDE, PROJ_NONE
  implicit none
  private
  public :: contact_pair_t, PAIR_TWO_HALF_PASS, PAIR_NODE_TO_SEGMENT, PAIR_WALL, &
      pair_setup, pair_reset_results, update_grid, closest_point, half_pass, &
      two_half_pass_forces, node_to_segment_forces, friction_t, coulomb, pair_commit, &
      PAIR_MORTAR, PAIR_TIE, mortar_t, point_increment, mortar_resize, track

  !> Pair kinds.
  integer, parameter :: PAIR_TWO_HALF_PASS = 1, PAIR_NODE_TO_SEGMENT = 2, PAIR_WALL = 3, &
      PAIR_MORTAR = 4, PAIR_TIE = 5

  !> Coulomb friction of a pair (doc/contact.md §4a): the coefficient, the tangential
  !! penalty, the tangential traction of every contact point (committed: of the last
  !! accepted step; trial: of the last force evaluation), the tangential resultant on the
  !! first surface, the frictional work of the last evaluation's increment and the
  !! committed total.
  type :: friction_t
    !> On when mu > 0 (then the arrays below are allocated).
    logical :: on = .false.
    real(dp) :: mu = 0.0_dp
    real(dp) :: eps_t = 0.0_dp
    !> Points: Gauss points of the first surface, then (TWO HALF PASS) of the second; nodes
    !! of the first surface for NODE TO SEGMENT.
    integer :: npts = 0
    real(dp), allocatable :: t_old(:)
    real(dp), allocatable :: t_new(:)
    real(dp) :: force(2) = 0.0_dp
    real(dp) :: dwork = 0.0_dp
    real(dp) :: work = 0.0_dp
  end type friction_t

  !> The integration points of a MORTAR pair (src/contact/mortar.f90) on the slave (first)
  !! surface: each slave segment cut where the ends of the master segments project onto it,
  !! Gauss points on every piece. Per point: slave segment and parameter, reference weight
  !! w J, and the closest point on the master (PROJ_* status, segment, parameter, outward
  !! normal, signed distance d). Per slave node: the weight l_A = sum N_A w J, the weighted
  !! gap g_A = sum N_A d w J over the projected points, the pressure p_A and the tangential
  !! traction t_A. Sized by pair_setup, grown (rarely) by the mortar kernel.
  !! A tie (src/contact/tie.f90) keeps the points of the reference configuration that face
  !! the master, each with its reference offset `off` (2, n) = X_slave - X_master, and
  !! uses gap and slip for the x and y components of its weighted gap vector, p and t for
  !! those of its traction; `untied` counts the slave points left out.
  type :: mortar_t
    integer :: n = 0
    integer, allocatable :: sseg(:), mseg(:), status(:)
    real(dp), allocatable :: ts(:), tm(:), wj(:), d(:), normal(:,:)
    real(dp), allocatable :: ell(:), gap(:), p(:), slip(:), t(:)
    real(dp), allocatable :: off(:,:)
    integer :: untied = 0
  end type mortar_t

  !> One *CONTACT PAIR or *RIGID WALL with its results of the last force evaluation.
  type :: contact_pair_t
    !> Name in lower case (as used in the results file).
    character(len=str_len) :: name = ''
    !> PAIR_* kind, penalty eps_N, bipenalty mass penalty from the deck (< 0: none,
    !! 0: AUTO, > 0: eps_m), and the mass penalty eps_m in use (0: none; set by the time
    !! step from mass_penalty, doc/contact.md §6a).
    integer :: kind = PAIR_TWO_HALF_PASS
    real(dp) :: penalty = 0.0_dp
    real(dp) :: mass_penalty = -1.0_dp
    real(dp) :: eps_m = 0.0_dp
    !> Surface indices (in contact_t%surfaces) of the first and second surface (0: wall).
    integer :: first = 0
    integer :: second = 0
    !> Rigid wall: a point of the plane and the unit normal into the allowed side.
    real(dp) :: wall_point(2) = 0.0_dp
    real(dp) :: wall_normal(2) = 0.0_dp
    !> Search radius (box growth) of the global search.
    real(dp) :: radius = 0.0_dp
    !> Results: resultant force on the first and on the second surface (for a wall: the
    !! force on the wall, i.e. minus force_first), largest pressure and penetration, number
    !! of contact points in contact, contact energy, projection failures in the last call
    !! and in all calls.
    real(dp) :: force_first(2) = 0.0_dp
    real(dp) :: force_second(2) = 0.0_dp
    real(dp) :: max_pressure = 0.0_dp
    real(dp) :: max_penetration = 0.0_dp
    integer :: active_points = 0
    real(dp) :: energy = 0.0_dp
    integer :: failures = 0
    integer(i8) :: failures_total = 0
    !> Outside points (doc/contact.md §3): contact points that lie behind the other surface
    !! (d < 0 on the inner side of its end tangent) but project beyond one of its ends, so
    !! get no force; in the last call, in all calls, and the first one of the last call:
    !! its coordinates, the surface it belongs to (1 first, 2 second) and its nearest node.
    integer :: outside_points = 0
    integer(i8) :: outside_total = 0
    real(dp) :: outside_x(2) = 0.0_dp
    integer :: outside_surf = 0
    integer :: outside_node = 0
    !> Contact points of the first surface (Gauss points, or nodes for NODE TO SEGMENT):
    !! current coordinates (2, npoints) and pressure eps gp (npoints), 0 where open.
    integer :: npoints = 0
    real(dp), allocatable :: x(:,:)
    real(dp), allocatable :: pressure(:)
    !> Lost points: 1 for each contact point (TWO HALF PASS: the Gauss points of the first
    !! surface, then of the second; NODE TO SEGMENT and MORTAR: the slave nodes) that
    !! penetrated at its last evaluation with a closest point, 0 once it is found open. A
    !! point marked 1 that has no candidate segment at all (it left the search radius while
    !! inside the other body: tunnelling) is counted as an outside point. Kept in
    !! checkpoints.
    integer, allocatable :: inside(:)
    !> Search grids with the first / the second surface as master, candidate work array.
    type(search_grid_t) :: grid_first, grid_second
    !> The segments of the first / the second surface as curves on the coordinates of the
    !! grids (nseg each), built with them: the projections evaluate these.
    type(segment_curve_t), allocatable :: curves_first(:), curves_second(:)
    integer, allocatable :: cand(:)
    !> Coulomb friction (off unless set by contact_define_friction).
    type(friction_t) :: fr
    !> MORTAR: the integration points and nodal values.
    type(mortar_t) :: mo
  end type contact_pair_t

contains

  !> Sizes the work arrays of a pair and sets its search radius (the largest reference
  !! segment length of its surfaces, unless radius > 0 is already set).
  !! @param pair the pair; @param s1 first surface; @param s2 second surface (ignored for a
  !! wall)
  subroutine pair_setup(pair, s1, s2)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: s1, s2
    integer :: ncand
    if (pair%kind == PAIR_NODE_TO_SEGMENT .or. pair%kind == PAIR_MORTAR .or. &
        pair%kind == PAIR_TIE) then
      pair%npoints = s1%nsn
    else
      pair%npoints = s1%ngp
    end if
    if (allocated(pair%x)) deallocate(pair%x)
    if (allocated(pair%pressure)) deallocate(pair%pressure)
    if (allocated(pair%cand)) deallocate(pair%cand)
    allocate(pair%x(2, pair%npoints), pair%pressure(pair%npoints))
    pair%x = 0.0_dp
    pair%pressure = 0.0_dp
    ncand = s1%nseg
    if (pair%kind /= PAIR_WALL) then
      ncand = max(ncand, s2%nseg)
      if (pair%radius <= 0.0_dp) pair%radius = max(s1%hmax, s2%hmax)
      call grid_init(pair%grid_first, s1%nseg)
      call grid_init(pair%grid_second, s2%nseg)
    end if
    if (allocated(pair%curves_first)) deallocate(pair%curves_first)
    if (allocated(pair%curves_second)) deallocate(pair%curves_second)
    if (pair%kind /= PAIR_WALL) then
      allocate(pair%curves_first(s1%nseg), pair%curves_second(s2%nseg))
    else
      allocate(pair%curves_first(0), pair%curves_second(0))
    end if
    allocate(pair%cand(max(ncand, 1)))
    if (allocated(pair%inside)) deallocate(pair%inside)
    select case (pair%kind)
    case (PAIR_TWO_HALF_PASS)
      allocate(pair%inside(s1%ngp + s2%ngp), source=0)
    case (PAIR_NODE_TO_SEGMENT, PAIR_MORTAR)
      allocate(pair%inside(s1%nsn), source=0)
    case default
      allocate(pair%inside(0))
    end select
    if (pair%kind == PAIR_MORTAR .or. pair%kind == PAIR_TIE) call mortar_setup(pair%mo, s1, s2)
    if (pair%fr%on) then
      pair%fr%npts = pair%npoints
      if (pair%kind == PAIR_TWO_HALF_PASS) pair%fr%npts = s1%ngp + s2%ngp
      if (allocated(pair%fr%t_old)) deallocate(pair%fr%t_old)
      if (allocated(pair%fr%t_new)) deallocate(pair%fr%t_new)
      allocate(pair%fr%t_old(pair%fr%npts), pair%fr%t_new(pair%fr%npts), source=0.0_dp)
    end if
    call pair_reset_results(pair)
  end subroutine pair_setup

  !> Sizes the mortar points of a pair: max(p_s, p_m) + 1 Gauss points on each piece, at
  !! most nseg_s + 4 nseg_m + 4 pieces (each master segment end cuts at most two slave
  !! segments).
  subroutine mortar_setup(mo, s1, s2)
    type(mortar_t), intent(inout) :: mo
    type(contact_surface_t), intent(in) :: s1, s2
    integer :: cap
    cap = max(s1%nen_max, s2%nen_max)*(s1%nseg + 4*s2%nseg + 4)
    call mortar_resize(mo, cap)
    mo%n = 0
    if (allocated(mo%ell)) deallocate(mo%ell, mo%gap, mo%p, mo%slip, mo%t)
    allocate(mo%ell(s1%nsn), mo%gap(s1%nsn), mo%p(s1%nsn), mo%slip(s1%nsn), mo%t(s1%nsn), &
        source=0.0_dp)
  end subroutine mortar_setup

  !> (Re)allocates the point arrays of a mortar pair for cap points (contents lost).
  subroutine mortar_resize(mo, cap)
    type(mortar_t), intent(inout) :: mo
    integer, intent(in) :: cap
    if (allocated(mo%sseg)) deallocate(mo%sseg, mo%mseg, mo%status, mo%ts, mo%tm, mo%wj, &
        mo%d, mo%normal)
    allocate(mo%sseg(cap), mo%mseg(cap), mo%status(cap), mo%ts(cap), mo%tm(cap), &
        mo%wj(cap), mo%d(cap), mo%normal(2, cap))
  end subroutine mortar_resize

  !> Accepts the friction state of the last force evaluation (the end of a step): the trial
  !! tractions become the committed ones and the increment of frictional work is added.
  pure subroutine pair_commit(pair)
    type(contact_pair_t), intent(inout) :: pair
    if (.not. pair%fr%on) return
    pair%fr%t_old = pair%fr%t_new
    pair%fr%work = pair%fr%work + pair%fr%dwork
  end subroutine pair_commit

  !> Coulomb friction at one contact point (doc/contact.md §4a). Trial (stick) traction
  !! t_trial = t_old - eps_t dg; kept if |t_trial| <= mu p, else returned to the cone,
  !! t = mu p sign(t_trial). dw is the frictional work per unit weight of the increment,
  !! |t| times the slip (|t_trial| - mu p)/eps_t (0 in stick); et the elastic tangential
  !! energy t^2/(2 eps_t) per unit weight.
  !! @param t_old committed traction; @param dg tangential relative displacement increment;
  !! @param p normal pressure (>= 0); @param mu, eps_t coefficient and tangential penalty
  pure subroutine coulomb(t_old, dg, p, mu, eps_t, t, dw, et)
    real(dp), intent(in) :: t_old, dg, p, mu, eps_t
    real(dp), intent(out) :: t, dw, et
    real(dp) :: tt, lim
    tt = t_old - eps_t*dg
    lim = mu*p
    if (abs(tt) <= lim) then
      t = tt
      dw = 0.0_dp
    else
      t = sign(lim, tt)
      dw = lim*(abs(tt) - lim)/eps_t
    end if
    et = 0.5_dp*t*t/eps_t
  end subroutine coulomb

  !> Tangential displacement increment along tau of a point with shape values r(1:n) on
  !! nodes conn(1:n), x - xprev of its nodes interpolated.
  pure real(dp) function point_increment(n, r, conn, x, xprev, tau) result(dg)
    integer, intent(in) :: n, conn(:)
    real(dp), intent(in) :: r(:), x(:,:), xprev(:,:), tau(2)
    integer :: a
    dg = 0.0_dp
    do a = 1, n
      dg = dg + r(a)*dot_product(x(:, conn(a)) - xprev(:, conn(a)), tau)
    end do
  end function point_increment

  !> The lost-point state of one contact point after its projection pr (penetration gp):
  !! with no candidate segment at all (PROJ_NONE) a point that was inside stays inside and
  !! is lost; with a closest point it is inside while it penetrates; a failed projection
  !! leaves the state.
  pure subroutine track(inside, pr, gp, lost)
    integer, intent(inout) :: inside
    type(projection_t), intent(in) :: pr
    real(dp), intent(in) :: gp
    logical, intent(out) :: lost
    lost = .false.
    select case (pr%status)
    case (PROJ_NONE)
      lost = inside == 1
    case (PROJ_INTERIOR, PROJ_CORNER)
      inside = merge(1, 0, gp > 0.0_dp)
    case (PROJ_OUTSIDE)
      inside = 0
    end select
  end subroutine track

  !> Zeroes the per-call results of a pair.
  pure subroutine pair_reset_results(pair)
    type(contact_pair_t), intent(inout) :: pair
    pair%force_first = 0.0_dp
    pair%force_second = 0.0_dp
    pair%max_pressure = 0.0_dp
    pair%max_penetration = 0.0_dp
    pair%active_points = 0
    pair%energy = 0.0_dp
    pair%failures = 0
    pair%fr%force = 0.0_dp
    pair%fr%dwork = 0.0_dp
    pair%outside_points = 0
    pair%outside_surf = 0
    pair%outside_node = 0
  end subroutine pair_reset_results

  !> Rebuilds a search grid over the current bounding boxes of a master surface's segments,
  !! grown by radius, and the segments' curves on the current coordinates.
  !! @param surf master surface; @param x coordinates (2, nn); @param radius growth;
  !! @param grid its grid (from grid_init with surf%nseg boxes); @param curves (nseg)
  subroutine update_grid(surf, x, radius, grid, curves)
    type(contact_surface_t), intent(in) :: surf
    real(dp), intent(in) :: x(:,:), radius
    type(search_grid_t), intent(inout) :: grid
    type(segment_curve_t), intent(inout) :: curves(:)
    integer :: s
    do s = 1, surf%nseg
      call segment_bbox(surf, s, x, radius, grid%box(:, s))
    end do
    call grid_build(grid)
    call surface_curves(surf, x, curves)
  end subroutine update_grid

  !> Closest point of a master surface to xs: global search in its grid, then projection.
  !! @param master surface; @param grid its built grid; @param curves its segments' curves
  !! (nseg, from update_grid); @param xs point (2); @param cand work (>= master%nseg);
  !! @param res projection; @param nfail 1 if a projection failed
  pure subroutine closest_point(master, grid, curves, xs, cand, res, nfail)
    type(contact_surface_t), intent(in) :: master
    type(search_grid_t), intent(in) :: grid
    type(segment_curve_t), intent(in) :: curves(:)
    real(dp), intent(in) :: xs(2)
    integer, intent(inout) :: cand(:)
    type(projection_t), intent(out) :: res
    integer, intent(out) :: nfail
    integer :: ncand
    call grid_query(grid, xs, cand, ncand)
    call project_point(master, curves, xs, cand, ncand, res, nfail)
  end subroutine closest_point

  !> One half-pass: the Gauss points of `slave` against `master` (grid built); forces on
  !! the slave's nodes only.
  !! @param slave, master surfaces; @param grid master's grid; @param curves master's
  !! segment curves (from update_grid); @param x (2, nn);
  !! @param eps penalty; @param cand work; @param fc forces (2, nn), accumulated;
  !! @param force resultant on the slave (2), accumulated; @param energy sum 1/2 eps gp^2 wJ,
  !! accumulated; @param pmax, gmax max pressure/penetration; @param nact active points;
  !! @param nfail failed projections; @param xout, pout optional point output (2, ngp), (ngp);
  !! @param eps_m, dm optional bipenalty: mass penalty and the added nodal masses (nn),
  !! accumulated on the slave nodes: eps_m wJ |R_a| (sum|R_slave| + sum|R_master|), the
  !! absolute row sum of the slave rows of eps_m wJ C^T C, C = [R_slave, -R_master]
  !! @param fr, off, xprev optional Coulomb friction: the pair's friction state, the offset
  !! of this half-pass's points in it (0: the first surface, whose tangential resultant goes
  !! to fr%force) and the committed coordinates (2, nn); the frictional work of the points is
  !! added to fr%dwork and their elastic tangential energy to `energy`
  !! @param nout optional: outside points (behind the master, projected beyond its end),
  !! accumulated; @param out_x, out_g: the first one's coordinates and nearest slave node,
  !! set when nout goes from 0 to 1
  pure subroutine half_pass(slave, master, grid, curves, x, eps, cand, fc, force, energy, &
      pmax, gmax, nact, nfail, xout, pout, eps_m, dm, fr, off, xprev, nout, out_x, out_g, &
      inside)
    type(contact_surface_t), intent(in) :: slave, master
    type(search_grid_t), intent(in) :: grid
    type(segment_curve_t), intent(in) :: curves(:)
    real(dp), intent(in) :: x(:,:), eps
    integer, intent(inout) :: cand(:)
    real(dp), intent(inout) :: fc(:,:), force(2), energy, pmax, gmax
    integer, intent(inout) :: nact, nfail
    real(dp), intent(inout), optional :: xout(:,:), pout(:)
    real(dp), intent(in), optional :: eps_m
    real(dp), intent(inout), optional :: dm(:)
    type(friction_t), intent(inout), optional :: fr
    integer, intent(in), optional :: off
    real(dp), intent(in), optional :: xprev(:,:)
    integer, intent(inout), optional :: nout, out_g
    real(dp), intent(inout), optional :: out_x(2)
    integer, intent(inout), optional :: inside(:)
    type(projection_t) :: pr
    real(dp) :: xq(2), gp, tr(2), wj, sm, tau(2), dg, tt, dw, et
    logical :: lost
    real(dp) :: rm(MAX_SEG_NODES), dr(MAX_SEG_NODES), ddr(MAX_SEG_NODES)
    integer :: q, s, a, g, nf
    logical :: fric
    fric = .false.
    if (present(fr)) fric = fr%on
    do q = 1, slave%ngp
      s = slave%gp_seg(q)
      xq = 0.0_dp
      do a = 1, slave%nen(s)
        xq = xq + slave%gp_r(a, q)*x(:, slave%conn(a, s))
      end do
      call closest_point(master, grid, curves, xq, cand, pr, nf)
      nfail = nfail + nf
      gp = 0.0_dp
      if (pr%status == PROJ_INTERIOR .or. pr%status == PROJ_CORNER) gp = max(0.0_dp, -pr%d)
      if (present(xout)) xout(:, q) = xq
      if (present(pout)) pout(q) = eps*gp
      if (fric) fr%t_new(off + q) = 0.0_dp
      lost = .false.
      if (present(inside)) call track(inside(q), pr, gp, lost)
      if ((lost .or. (pr%status == PROJ_OUTSIDE .and. pr%d < 0.0_dp)) .and. present(nout)) then
        nout = nout + 1
        if (nout == 1 .and. present(out_x) .and. present(out_g)) then
          out_x = xq
          out_g = slave%conn(maxloc(slave%gp_r(1:slave%nen(s), q), 1), s)
        end if
      end if
      if (gp <= 0.0_dp) cycle
      wj = slave%gp_wj(q)
      tr = eps*gp*pr%normal
      if (fric) then
        ! slip of the slave point relative to the master point along the master's tangent
        tau = [-pr%normal(2), pr%normal(1)]
        call segment_shape(master, pr%seg, pr%t, rm, dr, ddr)
        dg = point_increment(slave%nen(s), slave%gp_r(:, q), slave%conn(:, s), x, xprev, &
            tau) - point_increment(master%nen(pr%seg), rm, master%conn(:, pr%seg), x, &
            xprev, tau)
        call coulomb(fr%t_old(off + q), dg, eps*gp, fr%mu, fr%eps_t, tt, dw, et)
        fr%t_new(off + q) = tt
        fr%dwork = fr%dwork + dw*wj
        energy = energy + et*wj
        tr = tr + tt*tau
        if (off == 0) fr%force = fr%force + wj*tt*tau
      end if
      do a = 1, slave%nen(s)
        g = slave%conn(a, s)
        fc(:, g) = fc(:, g) + slave%gp_r(a, q)*wj*tr
      end do
      if (present(dm) .and. present(eps_m)) then
        call segment_shape(master, pr%seg, pr%t, rm, dr, ddr)
        sm = sum(abs(slave%gp_r(1:slave%nen(s), q))) + sum(abs(rm(1:master%nen(pr%seg))))
        do a = 1, slave%nen(s)
          g = slave%conn(a, s)
          dm(g) = dm(g) + eps_m*wj*abs(slave%gp_r(a, q))*sm
        end do
      end if
      force = force + wj*tr
      energy = energy + 0.5_dp*eps*gp*gp*wj
      pmax = max(pmax, eps*gp)
      gmax = max(gmax, gp)
      nact = nact + 1
    end do
  end subroutine half_pass

  !> TWO HALF PASS forces of one pair. The pair's energy is the mean of the two half-passes
  !! (each half-pass alone carries the whole penalty energy of the interface).
  !! @param pair the pair (results updated); @param s1, s2 its surfaces; @param x (2, nn);
  !! @param fc forces (2, nn), accumulated; @param dm optional bipenalty added nodal masses
  !! (nn), accumulated when pair%eps_m > 0; @param xprev committed coordinates (2, nn) of
  !! the friction increments (not used without friction)
  subroutine two_half_pass_forces(pair, s1, s2, x, fc, xprev, dm)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: s1, s2
    real(dp), intent(in) :: x(:,:), xprev(:,:)
    real(dp), intent(inout) :: fc(:,:)
    real(dp), intent(inout), optional :: dm(:)
    real(dp) :: e1, e2, x2(2)
    integer :: n1, n2, g1, g2
    call pair_reset_results(pair)
    n1 = 0
    n2 = 0
    g1 = 0
    g2 = 0
    x2 = 0.0_dp
    call update_grid(s1, x, pair%radius, pair%grid_first, pair%curves_first)
    call update_grid(s2, x, pair%radius, pair%grid_second, pair%curves_second)
    e1 = 0.0_dp
    e2 = 0.0_dp
    if (pair%fr%on) then
      ! each half-pass alone carries the whole interface: the frictional work is the mean
      if (present(dm) .and. pair%eps_m > 0.0_dp) then
        call half_pass(s1, s2, pair%grid_second, pair%curves_second, x, pair%penalty, &
            pair%cand, fc, pair%force_first, e1, pair%max_pressure, pair%max_penetration, &
            pair%active_points, pair%failures, pair%x, pair%pressure, pair%eps_m, dm, &
            pair%fr, 0, xprev, nout=n1, out_x=pair%outside_x, out_g=g1, &
            inside=pair%inside(1:s1%ngp))
        call half_pass(s2, s1, pair%grid_first, pair%curves_first, x, pair%penalty, &
            pair%cand, fc, pair%force_second, e2, pair%max_pressure, pair%max_penetration, &
            pair%active_points, pair%failures, eps_m=pair%eps_m, dm=dm, fr=pair%fr, &
            off=s1%ngp, xprev=xprev, nout=n2, out_x=x2, out_g=g2, &
            inside=pair%inside(s1%ngp + 1:))
      else
        call half_pass(s1, s2, pair%grid_second, pair%curves_second, x, pair%penalty, &
            pair%cand, fc, pair%force_first, e1, pair%max_pressure, pair%max_penetration, &
            pair%active_points, pair%failures, pair%x, pair%pressure, fr=pair%fr, off=0, &
            xprev=xprev, nout=n1, out_x=pair%outside_x, out_g=g1, &
            inside=pair%inside(1:s1%ngp))
        call half_pass(s2, s1, pair%grid_first, pair%curves_first, x, pair%penalty, &
            pair%cand, fc, pair%force_second, e2, pair%max_pressure, pair%max_penetration, &
            pair%active_points, pair%failures, fr=pair%fr, off=s1%ngp, xprev=xprev, &
            nout=n2, out_x=x2, out_g=g2, &
            inside=pair%inside(s1%ngp + 1:))
      end if
      pair%fr%dwork = 0.5_dp*pair%fr%dwork
    else if (present(dm) .and. pair%eps_m > 0.0_dp) then
      call half_pass(s1, s2, pair%grid_second, pair%curves_second, x, pair%penalty, &
          pair%cand, fc, pair%force_first, e1, pair%max_pressure, pair%max_penetration, &
          pair%active_points, pair%failures, pair%x, pair%pressure, pair%eps_m, dm, &
          nout=n1, out_x=pair%outside_x, out_g=g1, &
          inside=pair%inside(1:s1%ngp))
      call half_pass(s2, s1, pair%grid_first, pair%curves_first, x, pair%penalty, &
          pair%cand, fc, pair%force_second, e2, pair%max_pressure, pair%max_penetration, &
          pair%active_points, pair%failures, eps_m=pair%eps_m, dm=dm, nout=n2, out_x=x2, &
          out_g=g2, &
          inside=pair%inside(s1%ngp + 1:))
    else
      call half_pass(s1, s2, pair%grid_second, pair%curves_second, x, pair%penalty, &
          pair%cand, fc, pair%force_first, e1, pair%max_pressure, pair%max_penetration, &
          pair%active_points, pair%failures, pair%x, pair%pressure, nout=n1, &
          out_x=pair%outside_x, out_g=g1, &
          inside=pair%inside(1:s1%ngp))
      call half_pass(s2, s1, pair%grid_first, pair%curves_first, x, pair%penalty, &
          pair%cand, fc, pair%force_second, e2, pair%max_pressure, pair%max_penetration, &
          pair%active_points, pair%failures, nout=n2, out_x=x2, out_g=g2, &
          inside=pair%inside(s1%ngp + 1:))
    end if
    call note_outside(pair, n1, n2, g1, g2, x2)
    pair%energy = 0.5_dp*(e1 + e2)
    pair%failures_total = pair%failures_total + pair%failures
  end subroutine two_half_pass_forces

  !> NODE TO SEGMENT forces of one pair: nodes of s1 (slave) against s2 (master).
  !! @param pair the pair (results updated); @param s1 slave, s2 master; @param x (2, nn);
  !! @param fc forces (2, nn), accumulated; @param dm optional bipenalty added nodal masses
  !! (nn), accumulated when pair%eps_m > 0: eps_m l_s (1 + sum|R|) on the slave node and
  !! eps_m l_s |R_A| (1 + sum|R|) on master node A (the rows of eps_m l_s C^T C,
  !! C = [1, -R_A], made diagonal by their absolute row sums); @param xprev committed
  !! coordinates (2, nn) of the friction increments (not used without friction)
  subroutine node_to_segment_forces(pair, s1, s2, x, fc, xprev, dm)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: s1, s2
    real(dp), intent(in) :: x(:,:), xprev(:,:)
    real(dp), intent(inout) :: fc(:,:)
    real(dp), intent(inout), optional :: dm(:)
    type(projection_t) :: pr
    real(dp) :: xs(2), gp, fs(2), r(MAX_SEG_NODES), dr(MAX_SEG_NODES), ddr(MAX_SEG_NODES), sm
    real(dp) :: tau(2), dg, tt, dw, et
    integer :: k, g, a, nf
    logical :: lost
    call pair_reset_results(pair)
    call update_grid(s2, x, pair%radius, pair%grid_second, pair%curves_second)
    do k = 1, s1%nsn
      g = s1%nodes(k)
      xs = x(:, g)
      call closest_point(s2, pair%grid_second, pair%curves_second, xs, pair%cand, pr, nf)
      pair%failures = pair%failures + nf
      gp = 0.0_dp
      if (pr%status == PROJ_INTERIOR .or. pr%status == PROJ_CORNER) gp = max(0.0_dp, -pr%d)
      pair%x(:, k) = xs
      pair%pressure(k) = pair%penalty*gp
      if (pair%fr%on) pair%fr%t_new(k) = 0.0_dp
      call track(pair%inside(k), pr, gp, lost)
      if (lost .or. (pr%status == PROJ_OUTSIDE .and. pr%d < 0.0_dp)) then
        pair%outside_points = pair%outside_points + 1
        if (pair%outside_points == 1) then
          pair%outside_x = xs
          pair%outside_surf = 1
          pair%outside_node = g
        end if
      end if
      if (gp <= 0.0_dp) cycle
      fs = pair%penalty*gp*s1%ell(k)*pr%normal
      call segment_shape(s2, pr%seg, pr%t, r, dr, ddr)
      if (pair%fr%on) then
        ! slip of the slave node relative to the master point along the master's tangent
        tau = [-pr%normal(2), pr%normal(1)]
        dg = dot_product(x(:, g) - xprev(:, g), tau) - point_increment(s2%nen(pr%seg), r, &
            s2%conn(:, pr%seg), x, xprev, tau)
        call coulomb(pair%fr%t_old(k), dg, pair%penalty*gp, pair%fr%mu, pair%fr%eps_t, tt, &
            dw, et)
        pair%fr%t_new(k) = tt
        pair%fr%dwork = pair%fr%dwork + dw*s1%ell(k)
        pair%energy = pair%energy + et*s1%ell(k)
        fs = fs + tt*s1%ell(k)*tau
        pair%fr%force = pair%fr%force + tt*s1%ell(k)*tau
      end if
      fc(:, g) = fc(:, g) + fs
      do a = 1, s2%nen(pr%seg)
        fc(:, s2%conn(a, pr%seg)) = fc(:, s2%conn(a, pr%seg)) - r(a)*fs
      end do
      if (present(dm) .and. pair%eps_m > 0.0_dp) then
        sm = pair%eps_m*s1%ell(k)*(1.0_dp + sum(abs(r(1:s2%nen(pr%seg)))))
        dm(g) = dm(g) + sm
        do a = 1, s2%nen(pr%seg)
          dm(s2%conn(a, pr%seg)) = dm(s2%conn(a, pr%seg)) + abs(r(a))*sm
        end do
      end if
      pair%force_first = pair%force_first + fs
      pair%force_second = pair%force_second - fs
      pair%energy = pair%energy + 0.5_dp*pair%penalty*gp*gp*s1%ell(k)
      pair%max_pressure = max(pair%max_pressure, pair%penalty*gp)
      pair%max_penetration = max(pair%max_penetration, gp)
      pair%active_points = pair%active_points + 1
    end do
    pair%failures_total = pair%failures_total + pair%failures
    pair%outside_total = pair%outside_total + pair%outside_points
  end subroutine node_to_segment_forces

  !> Sets the outside-point results of a pair from its two half-passes: n1, n2 points of the
  !! first and second surface, g1, g2 their first points' nearest nodes; the first point of
  !! the first surface (coordinates already in pair%outside_x) is named before that of the
  !! second (x2). Adds the count to the run total (TWO HALF PASS; NODE TO SEGMENT counts
  !! its nodes itself).
  pure subroutine note_outside(pair, n1, n2, g1, g2, x2)
    type(contact_pair_t), intent(inout) :: pair
    integer, intent(in) :: n1, n2, g1, g2
    real(dp), intent(in) :: x2(2)
    pair%outside_points = n1 + n2
    if (n1 > 0) then
      pair%outside_surf = 1
      pair%outside_node = g1
    else if (n2 > 0) then
      pair%outside_surf = 2
      pair%outside_node = g2
      pair%outside_x = x2
    end if
    pair%outside_total = pair%outside_total + pair%outside_points
  end subroutine note_outside
end module ictus_contact_pair
