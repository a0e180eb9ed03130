!> Penalty contact in 3D (doc/contact.md §9): TWO HALF PASS between two surfaces of
!! quadrilateral faces and a rigid plane, the 3D forms of the 2D algorithms of
!! ictus_contact_pair and ictus_contact_wall.
!!
!! * TWO HALF PASS: every Gauss point x_q of each surface is projected onto the other
!!   (bucket search over the other surface's face boxes grown by the search radius, then
!!   the closest point, ictus_contact_face3d); with penetration gp = max(0, -d) > 0 it gets
!!   the traction eps gp n (n the other surface's outward normal), spread on its own face's
!!   nodes with N_A w J. The energy is the mean of the two half-passes.
!! * Rigid wall: d = (x_q - x_0).n for the plane through x_0 with unit normal n into the
!!   allowed side; the same traction.
!! Points behind the other surface that project onto its boundary are counted as outside
!! points, as in 2D.
module ictus_contact_pair3d
  use ictus_core_kinds, only: dp
  use ictus_contact_face3d, only: surface3d_t, face_bbox, projection3d_t, project3d, &
      P3_INTERIOR, P3_CORNER, P3_OUTSIDE, face_shape, MAX_FACE_NODES
  use ictus_contact_search3d, only: grid3_t, grid3_init, grid3_build, grid3_query
  implicit none
  private
  public :: pair3d_t, pair3d_setup, pair3d_grids, two_half_pass3d, wall3d, node_to_surface3d

  type :: pair3d_t
    !> Surface indices of the first and second surface in their owner's list (second = 0
    !! for a rigid wall); not used by the routines here, which take the surfaces. nts: NODE
    !! TO SEGMENT (the first surface's nodes against the second) instead of TWO HALF PASS.
    integer :: first = 0
    integer :: second = 0
    logical :: nts = .false.
    !> Normal penalty, search radius (0: the largest face of the two surfaces).
    real(dp) :: penalty = 0.0_dp
    real(dp) :: radius = 0.0_dp
    !> Rigid wall: a point and the unit normal into the allowed side.
    real(dp) :: wall_point(3) = 0.0_dp
    real(dp) :: wall_normal(3) = 0.0_dp
    !> Search grids of the first and second surface's faces, candidate work array.
    type(grid3_t) :: grid_first, grid_second
    integer, allocatable :: cand(:)
    !> Results of the last evaluation: resultants on the first and the second surface,
    !! energy, largest pressure and penetration, active and outside points.
    real(dp) :: force_first(3) = 0.0_dp
    real(dp) :: force_second(3) = 0.0_dp
    real(dp) :: energy = 0.0_dp
    real(dp) :: max_pressure = 0.0_dp
    real(dp) :: max_penetration = 0.0_dp
    integer :: active_points = 0
    integer :: outside_points = 0
    !> The first outside point of the last evaluation: its coordinates, its surface (1 the
    !! first, 2 the second) and the node of its face with the largest shape function.
    real(dp) :: outside_x(3) = 0.0_dp
    integer :: outside_surf = 0
    integer :: outside_node = 0
  end type pair3d_t

contains

  !> Sizes the grids of a pair of surfaces s1, s2 (s2 ignored for a wall: wall = .true.).
  subroutine pair3d_setup(p, s1, s2, wall)
    type(pair3d_t), intent(inout) :: p
    type(surface3d_t), intent(in) :: s1, s2
    logical, intent(in) :: wall
    if (wall) then
      p%wall_normal = p%wall_normal/norm2(p%wall_normal)
      return
    end if
    if (p%radius <= 0.0_dp) p%radius = max(s1%hmax, s2%hmax)
    call grid3_init(p%grid_first, s1%nface)
    call grid3_init(p%grid_second, s2%nface)
    allocate(p%cand(max(s1%nface, s2%nface, 1)))
  end subroutine pair3d_setup

  !> The grid of surface s's faces on x.
  subroutine build_grid(s, x, radius, g)
    type(surface3d_t), intent(in) :: s
    real(dp), intent(in) :: x(:,:), radius
    type(grid3_t), intent(inout) :: g
    integer :: f
    do f = 1, s%nface
      call face_bbox(s, f, x, radius, g%box(:, f))
    end do
    call grid3_build(g)
  end subroutine build_grid

  !> Zeroes the results.
  pure subroutine reset(p)
    type(pair3d_t), intent(inout) :: p
    p%force_first = 0.0_dp
    p%force_second = 0.0_dp
    p%energy = 0.0_dp
    p%max_pressure = 0.0_dp
    p%max_penetration = 0.0_dp
    p%active_points = 0
    p%outside_points = 0
  end subroutine reset

  !> The search grids of both surfaces on the coordinates x (3, nn).
  subroutine pair3d_grids(p, s1, s2, x)
    type(pair3d_t), intent(inout) :: p
    type(surface3d_t), intent(in) :: s1, s2
    real(dp), intent(in) :: x(:,:)
    call build_grid(s1, x, p%radius, p%grid_first)
    call build_grid(s2, x, p%radius, p%grid_second)
  end subroutine pair3d_grids

  !> TWO HALF PASS forces on the coordinates x (3, nn), accumulated into fc (3, nn).
  !! Optional xs (3, s1%ngp) and ps (s1%ngp): the current Gauss points of the first surface
  !! and their pressure eps gp (0 where open).
  subroutine two_half_pass3d(p, s1, s2, x, fc, xs, ps)
    type(pair3d_t), intent(inout) :: p
    type(surface3d_t), intent(in) :: s1, s2
    real(dp), intent(in) :: x(:,:)
    real(dp), intent(inout) :: fc(:,:)
    real(dp), intent(inout), optional :: xs(:,:), ps(:)
    real(dp) :: e1, e2
    call reset(p)
    call pair3d_grids(p, s1, s2, x)
    e1 = 0.0_dp
    e2 = 0.0_dp
    call half_pass(p, s1, s2, p%grid_second, x, fc, p%force_first, e1, 1, xs, ps)
    call half_pass(p, s2, s1, p%grid_first, x, fc, p%force_second, e2, 2)
    p%energy = 0.5_dp*(e1 + e2)
  end subroutine two_half_pass3d

  !> One half-pass: the Gauss points of `slave` against `master` (grid built); forces on
  !! the slave's nodes, its resultant and energy accumulated; xs, ps as in two_half_pass3d.
  subroutine half_pass(p, slave, master, grid, x, fc, force, energy, side, xs, ps)
    type(pair3d_t), intent(inout) :: p
    type(surface3d_t), intent(in) :: slave, master
    type(grid3_t), intent(in) :: grid
    real(dp), intent(in) :: x(:,:)
    real(dp), intent(inout) :: fc(:,:), force(3), energy
    integer, intent(in) :: side
    real(dp), intent(inout), optional :: xs(:,:), ps(:)
    type(projection3d_t) :: pr
    real(dp) :: xq(3), gp, tr(3)
    integer :: q, f, k, ncand
    do q = 1, slave%ngp
      f = slave%gp_face(q)
      xq = 0.0_dp
      do k = 1, slave%nen(f)
        xq = xq + slave%gp_r(k, q)*x(:, slave%conn(k, f))
      end do
      if (present(xs)) xs(:, q) = xq
      if (present(ps)) ps(q) = 0.0_dp
      call grid3_query(grid, xq, p%cand, ncand)
      call project3d(master, x, xq, p%cand, ncand, pr)
      if (pr%status == P3_OUTSIDE .and. pr%d < 0.0_dp) call outside(p, xq, side, &
          slave%conn(maxloc(slave%gp_r(1:slave%nen(f), q), dim=1), f))
      if (pr%status /= P3_INTERIOR .and. pr%status /= P3_CORNER) cycle
      gp = max(0.0_dp, -pr%d)
      if (gp <= 0.0_dp) cycle
      if (present(ps)) ps(q) = p%penalty*gp
      tr = p%penalty*gp*pr%normal*slave%gp_wj(q)
      call spread(slave, f, q, tr, fc, force)
      energy = energy + 0.5_dp*p%penalty*gp*gp*slave%gp_wj(q)
      p%max_pressure = max(p%max_pressure, p%penalty*gp)
      p%max_penetration = max(p%max_penetration, gp)
      p%active_points = p%active_points + 1
    end do
  end subroutine half_pass

  !> Counts an outside point (at xq, of surface `side`, nearest node g); the first of an
  !! evaluation is kept.
  pure subroutine outside(p, xq, side, g)
    type(pair3d_t), intent(inout) :: p
    real(dp), intent(in) :: xq(3)
    integer, intent(in) :: side, g
    p%outside_points = p%outside_points + 1
    if (p%outside_points > 1) return
    p%outside_x = xq
    p%outside_surf = side
    p%outside_node = g
  end subroutine outside

  !> The force tr of Gauss point q of face f onto the face's nodes (N_A tr), accumulated
  !! into fc and the resultant.
  pure subroutine spread(s, f, q, tr, fc, force)
    type(surface3d_t), intent(in) :: s
    integer, intent(in) :: f, q
    real(dp), intent(in) :: tr(3)
    real(dp), intent(inout) :: fc(:,:), force(3)
    integer :: k, g
    do k = 1, s%nen(f)
      g = s%conn(k, f)
      fc(:, g) = fc(:, g) + s%gp_r(k, q)*tr
    end do
    force = force + tr
  end subroutine spread

  !> NODE TO SEGMENT in 3D (node to surface): every node A of the slave surface s1 is
  !! projected onto the master s2; with penetration gp = -d > 0 it gets eps gp a_A n (a_A its
  !! nodal area, n the master's outward normal at the closest point) and the master face's
  !! nodes get -eps gp a_A n N_B(xi). Action equals reaction node by node. Optional xs
  !! (3, s1%nsn), ps (s1%nsn): the slave nodes and their pressures eps gp.
  subroutine node_to_surface3d(p, s1, s2, x, fc, xs, ps)
    type(pair3d_t), intent(inout) :: p
    type(surface3d_t), intent(in) :: s1, s2
    real(dp), intent(in) :: x(:,:)
    real(dp), intent(inout) :: fc(:,:)
    real(dp), intent(inout), optional :: xs(:,:), ps(:)
    type(projection3d_t) :: pr
    real(dp) :: gp, tr(3), nr(MAX_FACE_NODES), dnr(2, MAX_FACE_NODES)
    integer :: a, g, b, ncand
    call reset(p)
    call build_grid(s2, x, p%radius, p%grid_second)
    do a = 1, s1%nsn
      g = s1%nodes(a)
      if (present(xs)) xs(:, a) = x(:, g)
      if (present(ps)) ps(a) = 0.0_dp
      call grid3_query(p%grid_second, x(:, g), p%cand, ncand)
      call project3d(s2, x, x(:, g), p%cand, ncand, pr)
      if (pr%status == P3_OUTSIDE .and. pr%d < 0.0_dp) call outside(p, x(:, g), 1, g)
      if (pr%status /= P3_INTERIOR .and. pr%status /= P3_CORNER) cycle
      gp = max(0.0_dp, -pr%d)
      if (gp <= 0.0_dp) cycle
      tr = p%penalty*gp*s1%area(a)*pr%normal
      fc(:, g) = fc(:, g) + tr
      p%force_first = p%force_first + tr
      call face_shape(s2, pr%face, pr%xi, nr, dnr)
      do b = 1, s2%nen(pr%face)
        fc(:, s2%conn(b, pr%face)) = fc(:, s2%conn(b, pr%face)) - nr(b)*tr
      end do
      p%force_second = p%force_second - tr
      if (present(ps)) ps(a) = p%penalty*gp
      p%energy = p%energy + 0.5_dp*p%penalty*gp*gp*s1%area(a)
      p%max_pressure = max(p%max_pressure, p%penalty*gp)
      p%max_penetration = max(p%max_penetration, gp)
      p%active_points = p%active_points + 1
    end do
  end subroutine node_to_surface3d

  !> Rigid-wall forces on surface s at the coordinates x (3, nn), accumulated into fc; the
  !! force on the wall is -force_first. Optional xs, ps as in two_half_pass3d.
  subroutine wall3d(p, s, x, fc, xs, ps)
    type(pair3d_t), intent(inout) :: p
    type(surface3d_t), intent(in) :: s
    real(dp), intent(in) :: x(:,:)
    real(dp), intent(inout) :: fc(:,:)
    real(dp), intent(inout), optional :: xs(:,:), ps(:)
    real(dp) :: xq(3), gp, tr(3)
    integer :: q, f, k
    call reset(p)
    do q = 1, s%ngp
      f = s%gp_face(q)
      xq = 0.0_dp
      do k = 1, s%nen(f)
        xq = xq + s%gp_r(k, q)*x(:, s%conn(k, f))
      end do
      gp = max(0.0_dp, -dot_product(xq - p%wall_point, p%wall_normal))
      if (present(xs)) xs(:, q) = xq
      if (present(ps)) ps(q) = p%penalty*gp
      if (gp <= 0.0_dp) cycle
      tr = p%penalty*gp*p%wall_normal*s%gp_wj(q)
      call spread(s, f, q, tr, fc, p%force_first)
      p%energy = p%energy + 0.5_dp*p%penalty*gp*gp*s%gp_wj(q)
      p%max_pressure = max(p%max_pressure, p%penalty*gp)
      p%max_penetration = max(p%max_penetration, gp)
      p%active_points = p%active_points + 1
    end do
    p%force_second = -p%force_first
  end subroutine wall3d
end module ictus_contact_pair3d
