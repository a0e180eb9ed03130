!> All contact of a model: surfaces, contact pairs and rigid walls, and the two calls the
!! time step makes: `contact_forces` (penalty forces on predicted coordinates) and
!! `contact_stability` (the predictor-corrector penalty stability ratio, doc/contact.md §6);
!! with Coulomb friction also `contact_commit` at the end of each step (doc/contact.md §4a).
!!
!! Set-up: `contact_init(c, nsurf, npairs)`, then `surface_init` on each c%surfaces(i),
!! `contact_define_pair` / `contact_define_wall` for each c%pairs(k), then `contact_setup(c)`.
!! `ictus_app_build_contact` does this from a deck.
module ictus_contact_contact
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: lower, str
  use ictus_contact_surface, only: contact_surface_t, segment_shape, segment_curve_t, &
      MAX_SEG_NODES
  use ictus_contact_pair, only: contact_pair_t, PAIR_TWO_HALF_PASS, PAIR_NODE_TO_SEGMENT, &
      PAIR_WALL, pair_setup, update_grid, closest_point, two_half_pass_forces, &
      node_to_segment_forces, pair_commit, PAIR_MORTAR, PAIR_TIE
  use ictus_contact_mortar, only: mortar_forces, mortar_ratio
  use ictus_contact_tie, only: tie_setup, tie_forces
  use ictus_contact_wall, only: wall_forces
  use ictus_contact_search, only: search_grid_t
  use ictus_contact_projection, only: projection_t, PROJ_INTERIOR, PROJ_CORNER
  use ictus_contact_contact3d, only: contact3d_t, contact3d_setup, contact3d_pair_forces, &
      contact3d_ratio
  implicit none
  private
  public :: contact_t, contact_init, contact_define_pair, contact_define_wall, contact_setup, &
      contact_forces, contact_stability, contact_failures, contact_free, contact_pair_t, &
      contact_surface_t, PAIR_TWO_HALF_PASS, PAIR_NODE_TO_SEGMENT, PAIR_WALL, PAIR_MORTAR, &
      PAIR_TIE, contact_define_friction, contact_commit, pair_stiffness, contact_init3d, &
      contact_node_mask, pair_resultant

  !> All pairs and walls of a model (walls after the pairs), their surfaces and results.
  type :: contact_t
    !> Number of contact pairs plus rigid walls, and each one with its results.
    integer :: npairs = 0
    type(contact_pair_t), allocatable :: pairs(:)
    !> Surfaces referred to by the pairs.
    integer :: nsurf = 0
    type(contact_surface_t), allocatable :: surfaces(:)
    !> User id of each global node (nn), for messages; unallocated: global index.
    integer, allocatable :: node_id(:)
    !> Projection failures in the last contact_forces call (all pairs).
    integer :: failures = 0
    !> Coulomb friction: whether a pair has it; the committed coordinates (2, nn) from which
    !! the tangential increments are measured (current on the surface nodes; allocated and
    !! set to the coordinates of the first contact_forces call, `started`); the frictional
    !! work of all pairs up to the last commit.
    logical :: friction = .false.
    logical :: started = .false.
    real(dp), allocatable :: x_prev(:,:)
    real(dp) :: friction_work = 0.0_dp
    !> Dimension of the model; in 3D (ndm = 3) the surfaces of faces and the geometry and
    !! results of each pair's 3D evaluation are in d3 (surfaces stays empty; pairs holds
    !! names, kinds, penalties and the results common to both).
    integer :: ndm = 2
    type(contact3d_t) :: d3
  end type contact_t

contains

  !> Allocates nsurf surfaces and npairs pairs (calls contact_free first).
  !! @param c contact; @param nsurf surfaces; @param npairs pairs + walls
  subroutine contact_init(c, nsurf, npairs)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: nsurf, npairs
    call contact_free(c)
    c%nsurf = nsurf
    c%npairs = npairs
    allocate(c%surfaces(nsurf), c%pairs(npairs))
  end subroutine contact_init

  !> Allocates a 3D contact of nsurf surfaces of faces (c%d3%surfaces, to be set by
  !! surface3d_init) and npairs pairs + walls (calls contact_free first).
  subroutine contact_init3d(c, nsurf, npairs)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: nsurf, npairs
    call contact_init(c, 0, npairs)
    c%ndm = 3
    c%d3%nsurf = nsurf
    allocate(c%d3%surfaces(nsurf), c%d3%pairs(npairs), c%d3%names(nsurf))
    c%d3%names = ''
  end subroutine contact_init3d

  !> Releases everything.
  subroutine contact_free(c)
    type(contact_t), intent(inout) :: c
    type(contact_t) :: empty
    c = empty
  end subroutine contact_free

  !> Defines pair k: a contact pair between surfaces first and second.
  !! @param c contact; @param k pair index; @param name (stored in lower case);
  !! @param kind PAIR_TWO_HALF_PASS, PAIR_NODE_TO_SEGMENT or PAIR_MORTAR; @param penalty eps_N;
  !! @param first, second surface indices; @param radius search radius, optional
  !! (default: largest segment length of the two surfaces)
  subroutine contact_define_pair(c, k, name, kind, penalty, first, second, radius)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: k, kind, first, second
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: penalty
    real(dp), intent(in), optional :: radius
    c%pairs(k)%name = lower(trim(name))
    c%pairs(k)%kind = kind
    c%pairs(k)%penalty = penalty
    c%pairs(k)%first = first
    c%pairs(k)%second = second
    c%pairs(k)%radius = 0.0_dp
    if (present(radius)) c%pairs(k)%radius = radius
    if (c%ndm == 3) then
      c%d3%pairs(k)%first = first
      c%d3%pairs(k)%second = second
      c%d3%pairs(k)%radius = c%pairs(k)%radius
      c%d3%pairs(k)%nts = kind == PAIR_NODE_TO_SEGMENT
    end if
  end subroutine contact_define_pair

  !> Defines pair k as a rigid wall against surface `surf`.
  !! @param c contact; @param k pair index; @param name (lower case); @param point (ndm);
  !! @param normal (ndm), into the allowed side (normalised here; must be non-zero);
  !! @param penalty eps_N; @param surf surface index
  subroutine contact_define_wall(c, k, name, point, normal, penalty, surf)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: k, surf
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: point(:), normal(:), penalty
    real(dp) :: n(size(normal))
    c%pairs(k)%name = lower(trim(name))
    c%pairs(k)%kind = PAIR_WALL
    c%pairs(k)%penalty = penalty
    c%pairs(k)%first = surf
    c%pairs(k)%second = 0
    ! scaled by its largest component first: the squares of a normal of 1e-300 or 1e300 would
    ! leave the range of doubles, and any length names the same direction
    n = normal/maxval(abs(normal))
    if (c%ndm == 3) then
      c%d3%pairs(k)%first = surf
      c%d3%pairs(k)%second = 0
      c%d3%pairs(k)%wall_point = point(1:3)
      c%d3%pairs(k)%wall_normal = n(1:3)/norm2(n(1:3))
    else
      c%pairs(k)%wall_point = point(1:2)
      c%pairs(k)%wall_normal = n(1:2)/norm2(n(1:2))
    end if
  end subroutine contact_define_wall

  !> Whether each of the nn nodes is a node of a contact surface.
  function contact_node_mask(c, nn) result(mark)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: nn
    logical :: mark(nn)
    integer :: k
    mark = .false.
    do k = 1, c%nsurf
      mark(c%surfaces(k)%nodes(1:c%surfaces(k)%nsn)) = .true.
    end do
    do k = 1, c%d3%nsurf
      mark(c%d3%surfaces(k)%nodes(1:c%d3%surfaces(k)%nsn)) = .true.
    end do
  end function contact_node_mask

  !> The resultant force of pair k on its first (side 1) or second (side 2) surface (for a
  !! wall side 2 is the force on the wall), with z = 0 in 2D.
  pure function pair_resultant(c, k, side) result(f)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: k, side
    real(dp) :: f(3)
    if (c%ndm == 3) then
      f = c%d3%pairs(k)%force_first
      if (side == 2) f = c%d3%pairs(k)%force_second
    else
      f = [c%pairs(k)%force_first, 0.0_dp]
      if (side == 2) f = [c%pairs(k)%force_second, 0.0_dp]
    end if
  end function pair_resultant

  !> Gives pair k (defined) Coulomb friction (doc/contact.md §4a): coefficient mu (> 0;
  !! mu = 0 leaves the pair frictionless) and tangential penalty eps_t (<= 0: the normal
  !! penalty). Call before contact_setup.
  subroutine contact_define_friction(c, k, mu, eps_t)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: k
    real(dp), intent(in) :: mu, eps_t
    c%pairs(k)%fr%on = mu > 0.0_dp
    c%pairs(k)%fr%mu = mu
    c%pairs(k)%fr%eps_t = c%pairs(k)%penalty
    if (eps_t > 0.0_dp) c%pairs(k)%fr%eps_t = eps_t
    if (c%pairs(k)%fr%on) c%friction = .true.
  end subroutine contact_define_friction

  !> The penalty of a pair in the stability ratio: max(eps_N, eps_T) with friction (the
  !! tangential penalty acts on the tangential direction like eps_N on the normal one,
  !! doc/contact.md §6), else eps_N.
  pure real(dp) function pair_stiffness(p)
    type(contact_pair_t), intent(in) :: p
    pair_stiffness = p%penalty
    if (p%fr%on) pair_stiffness = max(p%penalty, p%fr%eps_t)
  end function pair_stiffness

  !> Accepts the friction state of the last contact_forces call on x (2, nn), the
  !! coordinates of the accepted step: tangential tractions, frictional work (summed over the
  !! pairs into c%friction_work) and the committed coordinates of the surface nodes. Nothing
  !! without friction.
  subroutine contact_commit(c, nn, x)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: nn
    real(dp), intent(in) :: x(:,:)
    integer :: k, i
    if (.not. c%friction) return
    c%friction_work = 0.0_dp
    do k = 1, c%npairs
      call pair_commit(c%pairs(k))
      c%friction_work = c%friction_work + c%pairs(k)%fr%work
    end do
    do k = 1, c%nsurf
      do i = 1, c%surfaces(k)%nsn
        c%x_prev(:, c%surfaces(k)%nodes(i)) = x(:, c%surfaces(k)%nodes(i))
      end do
    end do
  end subroutine contact_commit

  !> Sizes all work arrays (after surfaces and pairs are defined); ties (PAIR_TIE) find
  !! their tied points on the reference coordinates x0 (2, nn), which they need.
  subroutine contact_setup(c, x0)
    type(contact_t), intent(inout) :: c
    real(dp), intent(in), optional :: x0(:,:)
    integer :: k, s2
    if (c%ndm == 3) then
      call setup3d(c)
      return
    end if
    do k = 1, c%npairs
      s2 = c%pairs(k)%second
      if (s2 == 0) s2 = c%pairs(k)%first
      call pair_setup(c%pairs(k), c%surfaces(c%pairs(k)%first), c%surfaces(s2))
      if (c%pairs(k)%kind /= PAIR_TIE) cycle
      if (.not. present(x0)) error stop 'contact_setup: a tie needs the reference coordinates'
      call tie_setup(c%pairs(k), c%surfaces(c%pairs(k)%first), c%surfaces(s2), x0)
    end do
  end subroutine contact_setup

  !> contact_setup in 3D: the pairs' grids and their point output (the first surface's Gauss
  !! points).
  subroutine setup3d(c)
    type(contact_t), intent(inout) :: c
    integer :: k
    do k = 1, c%npairs
      c%d3%pairs(k)%penalty = c%pairs(k)%penalty
    end do
    call contact3d_setup(c%d3)
    do k = 1, c%npairs
      associate (p => c%pairs(k))
        p%npoints = c%d3%surfaces(c%d3%pairs(k)%first)%ngp
        if (c%d3%pairs(k)%nts) p%npoints = c%d3%surfaces(c%d3%pairs(k)%first)%nsn
        if (allocated(p%x)) deallocate(p%x)
        if (allocated(p%pressure)) deallocate(p%pressure)
        if (allocated(p%inside)) deallocate(p%inside)
        allocate(p%x(3, p%npoints), p%pressure(p%npoints), source=0.0_dp)
        allocate(p%inside(0))
      end associate
    end do
  end subroutine setup3d

  !> Contact forces of all pairs and walls on the current (predicted) coordinates.
  !! Does not allocate. Updates each pair's results and point output.
  !! @param c contact; @param nn number of nodes; @param x coordinates x0 + u_pre (ndm, nn);
  !! @param fc contact forces (ndm, nn): zeroed on the surface nodes, then accumulated (other
  !! entries are left untouched; zero the array once before the first call);
  !! @param energy penalty energy: sum over points of 1/2 eps gp^2 w J (TWO HALF PASS: the
  !! mean of its two half-passes; NODE TO SEGMENT: sum 1/2 eps gp^2 l_s);
  !! @param dm optional (nn): the bipenalty masses (doc/contact.md §6a) of the active points of
  !! the pairs with eps_m > 0, zeroed on the surface nodes and accumulated like fc
  subroutine contact_forces(c, nn, x, fc, energy, dm)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: nn
    real(dp), intent(in) :: x(:,:)
    real(dp), intent(inout) :: fc(:,:)
    real(dp), intent(out) :: energy
    real(dp), intent(inout), optional :: dm(:)
    integer :: k, i
    if (c%ndm == 3) then
      call forces3d(c, x, fc, energy)
      return
    end if
    ! only surface nodes receive contact forces: zero just those (cost of the surface)
    ! (loops, not vector subscripts: those make heap temporaries)
    do k = 1, c%nsurf
      do i = 1, c%surfaces(k)%nsn
        fc(:, c%surfaces(k)%nodes(i)) = 0.0_dp
      end do
      if (present(dm)) then
        do i = 1, c%surfaces(k)%nsn
          dm(c%surfaces(k)%nodes(i)) = 0.0_dp
        end do
      end if
    end do
    energy = 0.0_dp
    c%failures = 0
    if (c%friction) then
      ! the first call sets the committed coordinates (the only allocation)
      if (.not. c%started) then
        if (allocated(c%x_prev)) deallocate(c%x_prev)
        allocate(c%x_prev(2, nn), source=x)
        c%started = .true.
      end if
      call all_pairs(c, x, c%x_prev, fc, energy, dm)
    else
      call all_pairs(c, x, x, fc, energy, dm)
    end if
  end subroutine contact_forces

  !> contact_forces in 3D (frictionless pairs and walls, no bipenalty: refused by the
  !! reader): the pairs' results copied into c%pairs for the output.
  subroutine forces3d(c, x, fc, energy)
    type(contact_t), intent(inout) :: c
    real(dp), intent(in) :: x(:,:)
    real(dp), intent(inout) :: fc(:,:)
    real(dp), intent(out) :: energy
    integer :: k, i
    do k = 1, c%d3%nsurf
      do i = 1, c%d3%surfaces(k)%nsn
        fc(:, c%d3%surfaces(k)%nodes(i)) = 0.0_dp
      end do
    end do
    energy = 0.0_dp
    c%failures = 0
    do k = 1, c%npairs
      associate (p => c%pairs(k), q => c%d3%pairs(k))
        q%penalty = p%penalty
        call contact3d_pair_forces(c%d3, k, x, fc, p%x, p%pressure)
        p%energy = q%energy
        p%max_pressure = q%max_pressure
        p%max_penetration = q%max_penetration
        p%active_points = q%active_points
        p%outside_points = q%outside_points
        p%outside_total = p%outside_total + q%outside_points
        p%outside_x = q%outside_x(1:2)
        p%outside_surf = q%outside_surf
        p%outside_node = q%outside_node
        energy = energy + q%energy
      end associate
    end do
  end subroutine forces3d

  !> The forces of every pair (contact_forces), friction increments measured from xprev.
  subroutine all_pairs(c, x, xprev, fc, energy, dm)
    type(contact_t), intent(inout) :: c
    real(dp), intent(in) :: x(:,:), xprev(:,:)
    real(dp), intent(inout) :: fc(:,:), energy
    real(dp), intent(inout), optional :: dm(:)
    integer :: k
    do k = 1, c%npairs
      associate (p => c%pairs(k))
        select case (p%kind)
        case (PAIR_TWO_HALF_PASS)
          call two_half_pass_forces(p, c%surfaces(p%first), c%surfaces(p%second), x, fc, &
              xprev, dm)
        case (PAIR_NODE_TO_SEGMENT)
          call node_to_segment_forces(p, c%surfaces(p%first), c%surfaces(p%second), x, fc, &
              xprev, dm)
        case (PAIR_MORTAR)
          call mortar_forces(p, c%surfaces(p%first), c%surfaces(p%second), x, fc, xprev)
        case (PAIR_TIE)
          call tie_forces(p, c%surfaces(p%first), c%surfaces(p%second), x, fc)
        case (PAIR_WALL)
          call wall_forces(p, c%surfaces(p%first), x, fc, xprev)
        end select
        energy = energy + p%energy
        c%failures = c%failures + p%failures
      end associate
    end do
  end subroutine all_pairs

  !> Projection failures of the last contact_forces call, over all pairs.
  pure integer function contact_failures(c)
    type(contact_t), intent(in) :: c
    contact_failures = c%failures
  end function contact_failures

  !> Predictor-corrector penalty stability ratio r = dt^2 eps (l_s/m_s + l_m/m_m) over the
  !! nodes of the contact surfaces (doc/contact.md §6): l_s/m_s of the node, l_m/m_m the
  !! master's l/m interpolated as sum_A |R_A| l_A/m_A at the node's closest point (the largest
  !! master l/m when the node has no closest point within the search radius); a rigid wall
  !! has only the slave term. Both surfaces of a TWO HALF PASS pair act as slave in turn.
  !! The estimate asks for r <= 1 (r_s <= 1/2 for identical meshes). With friction eps is
  !! max(eps_N, eps_T) (pair_stiffness). A pair with a mass
  !! penalty eps_m > 0 (bipenalty) uses the masses m + 2 eps_m l of its fully active nodes
  !! (the lower bound of the added masses of contact_forces, whose Gershgorin factor is >= 2).
  !! @param c contact; @param nn nodes; @param x coordinates (2, nn); @param m_diag lumped
  !! nodal masses (nn); @param dt time step; @param r_max largest r (huge for a non-positive
  !! mass); @param where text naming the worst point (pair, node ids); @param r_pair
  !! optional (npairs): the largest r of each pair
  subroutine contact_stability(c, nn, x, m_diag, dt, r_max, where, r_pair)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: nn
    real(dp), intent(in) :: x(:,:), m_diag(nn), dt
    real(dp), intent(out) :: r_max
    character(len=*), intent(out) :: where
    real(dp), intent(out), optional :: r_pair(:)
    character(len=len(where)) :: at
    real(dp) :: r, q
    integer :: k, gs, gm
    r_max = 0.0_dp
    where = ''
    do k = 1, c%npairs
      ! the pair's own largest ratio (r, at), then kept if it is the largest so far
      r = 0.0_dp
      at = ''
      associate (p => c%pairs(k))
        if (c%ndm == 3) then
          call contact3d_ratio(c%d3, k, pair_stiffness(p), x, m_diag, dt, r, gs, gm)
          at = trim(p%name)//': node '//str(user_id(c, gs))
          if (gm > 0) at = trim(at)//' against node '//str(user_id(c, gm))
          if (r >= huge(1.0_dp)) at = trim(at)//' (non-positive lumped mass)'
        end if
        select case (merge(-1, p%kind, c%ndm == 3))
        case (-1)
          continue
        case (PAIR_WALL)
          call side_ratio(c, p%name, pair_stiffness(p), p%eps_m, c%surfaces(p%first), &
              c%surfaces(p%first), &
              p%grid_first, p%curves_first, .false., nn, x, m_diag, dt, r, at)
        case (PAIR_MORTAR, PAIR_TIE)
          call mortar_ratio(p, c%surfaces(p%first), c%surfaces(p%second), x, m_diag, q, gs, gm)
          r = huge(1.0_dp)
          if (q < huge(1.0_dp)) r = dt*dt*pair_stiffness(p)*q
          at = trim(p%name)//': node '//str(user_id(c, gs))
          if (gm > 0) at = trim(at)//' against node '//str(user_id(c, gm))
          if (r >= huge(1.0_dp)) at = trim(at)//' (non-positive lumped mass)'
        case (PAIR_NODE_TO_SEGMENT)
          call update_grid(c%surfaces(p%second), x, p%radius, p%grid_second, p%curves_second)
          call side_ratio(c, p%name, pair_stiffness(p), p%eps_m, c%surfaces(p%first), &
              c%surfaces(p%second), p%grid_second, p%curves_second, .true., nn, x, m_diag, &
              dt, r, at)
        case default
          call update_grid(c%surfaces(p%first), x, p%radius, p%grid_first, p%curves_first)
          call update_grid(c%surfaces(p%second), x, p%radius, p%grid_second, p%curves_second)
          call side_ratio(c, p%name, pair_stiffness(p), p%eps_m, c%surfaces(p%first), &
              c%surfaces(p%second), p%grid_second, p%curves_second, .true., nn, x, m_diag, &
              dt, r, at)
          call side_ratio(c, p%name, pair_stiffness(p), p%eps_m, c%surfaces(p%second), &
              c%surfaces(p%first), p%grid_first, p%curves_first, .true., nn, x, m_diag, dt, &
              r, at)
        end select
      end associate
      if (present(r_pair)) r_pair(k) = r
      if (r > r_max .or. len_trim(where) == 0) then
        r_max = r
        where = at
      end if
    end do
  end subroutine contact_stability

  !> Stability ratios of the nodes of `slave` against `master` (or a rigid wall when
  !! has_master is false); keeps the largest in r_max/where.
  subroutine side_ratio(c, name, penalty, eps_m, slave, master, grid, curves, has_master, nn, &
      x, m_diag, dt, r_max, where)
    type(contact_t), intent(in) :: c
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: penalty, eps_m
    type(contact_surface_t), intent(in) :: slave, master
    type(search_grid_t), intent(in) :: grid
    type(segment_curve_t), intent(in) :: curves(:)
    logical, intent(in) :: has_master
    integer, intent(in) :: nn
    real(dp), intent(in) :: x(2, nn), m_diag(nn), dt
    real(dp), intent(inout) :: r_max
    character(len=*), intent(inout) :: where
    type(projection_t) :: pr
    real(dp) :: rs, rm, rm_all, r
    integer :: k, g, gm, gm_all, nf, cand(max(master%nseg, 1))
    call largest_ratio(master, m_diag, eps_m, has_master, rm_all, gm_all)
    do k = 1, slave%nsn
      g = slave%nodes(k)
      rs = ell_over_m(slave%ell(k), m_diag(g), eps_m)
      rm = 0.0_dp
      gm = 0
      if (has_master) then
        call closest_point(master, grid, curves, x(:, g), cand, pr, nf)
        if (pr%status == PROJ_INTERIOR .or. pr%status == PROJ_CORNER) then
          call master_ratio(master, pr%seg, pr%t, m_diag, eps_m, rm, gm)
        else
          rm = rm_all
          gm = gm_all
        end if
      end if
      if (rs >= huge(1.0_dp) .or. rm >= huge(1.0_dp)) then
        r = huge(1.0_dp)
      else
        r = dt*dt*penalty*(rs + rm)
      end if
      if (r > r_max .or. len_trim(where) == 0) then
        r_max = r
        where = trim(name)//': node '//str(user_id(c, g))
        if (gm > 0) where = trim(where)//' against node '//str(user_id(c, gm))
        if (r >= huge(1.0_dp)) where = trim(where)//' (non-positive lumped mass)'
      end if
    end do
  end subroutine side_ratio

  !> Largest l_A/m_A over the nodes of a surface (0 if not wanted) and its node.
  pure subroutine largest_ratio(surf, m_diag, eps_m, wanted, rmax, gmax)
    type(contact_surface_t), intent(in) :: surf
    real(dp), intent(in) :: m_diag(:), eps_m
    logical, intent(in) :: wanted
    real(dp), intent(out) :: rmax
    integer, intent(out) :: gmax
    real(dp) :: ra
    integer :: k
    rmax = 0.0_dp
    gmax = 0
    if (.not. wanted) return
    do k = 1, surf%nsn
      ra = ell_over_m(surf%ell(k), m_diag(surf%nodes(k)), eps_m)
      if (ra > rmax .or. gmax == 0) then
        rmax = ra
        gmax = surf%nodes(k)
      end if
    end do
  end subroutine largest_ratio

  !> sum_A |R_A(t)| l_A/m_A on master segment s (huge if a mass is non-positive) and the
  !! node with the largest |R_A|.
  pure subroutine master_ratio(master, s, t, m_diag, eps_m, rm, gm)
    type(contact_surface_t), intent(in) :: master
    integer, intent(in) :: s
    real(dp), intent(in) :: t, m_diag(:), eps_m
    real(dp), intent(out) :: rm
    integer, intent(out) :: gm
    real(dp) :: rr(MAX_SEG_NODES), dr(MAX_SEG_NODES), ddr(MAX_SEG_NODES), ra, rbest
    integer :: a
    call segment_shape(master, s, t, rr, dr, ddr)
    rm = 0.0_dp
    gm = 0
    rbest = -1.0_dp
    do a = 1, master%nen(s)
      ra = ell_over_m(master%ell(master%lnode(a, s)), m_diag(master%conn(a, s)), eps_m)
      if (ra >= huge(1.0_dp)) then
        rm = ra
      else if (rm < huge(1.0_dp)) then
        rm = rm + abs(rr(a))*ra
      end if
      if (abs(rr(a)) > rbest) then
        rbest = abs(rr(a))
        gm = master%conn(a, s)
      end if
    end do
  end subroutine master_ratio

  !> l/(m + 2 eps_m l), or huge for a non-positive mass m.
  pure real(dp) function ell_over_m(ell, m, eps_m)
    real(dp), intent(in) :: ell, m, eps_m
    if (m <= 0.0_dp) then
      ell_over_m = huge(1.0_dp)
    else
      ell_over_m = ell/(m + 2.0_dp*eps_m*ell)
    end if
  end function ell_over_m

  !> User id of global node g.
  pure integer function user_id(c, g)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: g
    user_id = g
    if (allocated(c%node_id)) then
      if (g >= 1 .and. g <= size(c%node_id)) user_id = c%node_id(g)
    end if
  end function user_id
end module ictus_contact_contact
