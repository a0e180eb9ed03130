!> Rigid wall: the plane through a point with unit normal n pointing into the allowed side.
!! The Gauss points x_q of the surface have d = (x_q - x_wall).n and penetration
!! gp = max(0, -d); the traction eps gp n is distributed with the surface's shape functions
!! and weights w_q J_q. With Coulomb friction (doc/contact.md §4a) the point also gets the
!! tangential traction t tau, tau = (-n_y, n_x) the wall's direction, from the point's
!! displacement along tau since the committed coordinates (the wall does not move).
module ictus_contact_wall
  use ictus_core_kinds, only: dp
  use ictus_contact_surface, only: contact_surface_t
  use ictus_contact_pair, only: contact_pair_t, pair_reset_results, coulomb
  implicit none
  private
  public :: wall_forces, wall_point_gap

contains

  !> Signed distance of point xp from the wall plane (positive on the allowed side).
  !! @param point a point of the plane (2); @param normal unit normal (2); @param xp (2)
  pure real(dp) function wall_point_gap(point, normal, xp) result(d)
    real(dp), intent(in) :: point(2), normal(2), xp(2)
    d = dot_product(xp - point, normal)
  end function wall_point_gap

  !> Forces of a rigid wall on its surface. force_first is the resultant on the surface,
  !! force_second = -force_first the force on the wall.
  !! @param pair the wall (kind PAIR_WALL; results updated); @param surf its surface;
  !! @param x coordinates (2, nn); @param fc forces (2, nn), accumulated; @param xprev
  !! committed coordinates (2, nn) of the friction increments (not used without friction)
  pure subroutine wall_forces(pair, surf, x, fc, xprev)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: surf
    real(dp), intent(in) :: x(:,:), xprev(:,:)
    real(dp), intent(inout) :: fc(:,:)
    real(dp) :: xq(2), gp, tr(2), wj, tau(2), dg, tt, dw, et
    integer :: q, s, a, g
    call pair_reset_results(pair)
    tau = [-pair%wall_normal(2), pair%wall_normal(1)]
    do q = 1, surf%ngp
      s = surf%gp_seg(q)
      xq = 0.0_dp
      do a = 1, surf%nen(s)
        xq = xq + surf%gp_r(a, q)*x(:, surf%conn(a, s))
      end do
      gp = max(0.0_dp, -wall_point_gap(pair%wall_point, pair%wall_normal, xq))
      pair%x(:, q) = xq
      pair%pressure(q) = pair%penalty*gp
      if (pair%fr%on) pair%fr%t_new(q) = 0.0_dp
      if (gp <= 0.0_dp) cycle
      wj = surf%gp_wj(q)
      tr = pair%penalty*gp*pair%wall_normal
      if (pair%fr%on) then
        dg = 0.0_dp
        do a = 1, surf%nen(s)
          g = surf%conn(a, s)
          dg = dg + surf%gp_r(a, q)*dot_product(x(:, g) - xprev(:, g), tau)
        end do
        call coulomb(pair%fr%t_old(q), dg, pair%penalty*gp, pair%fr%mu, pair%fr%eps_t, tt, &
            dw, et)
        pair%fr%t_new(q) = tt
        pair%fr%dwork = pair%fr%dwork + dw*wj
        pair%energy = pair%energy + et*wj
        tr = tr + tt*tau
        pair%fr%force = pair%fr%force + wj*tt*tau
      end if
      do a = 1, surf%nen(s)
        g = surf%conn(a, s)
        fc(:, g) = fc(:, g) + surf%gp_r(a, q)*wj*tr
      end do
      pair%force_first = pair%force_first + wj*tr
      pair%energy = pair%energy + 0.5_dp*pair%penalty*gp*gp*wj
      pair%max_pressure = max(pair%max_pressure, pair%penalty*gp)
      pair%max_penetration = max(pair%max_penetration, gp)
      pair%active_points = pair%active_points + 1
    end do
    pair%force_second = -pair%force_first
  end subroutine wall_forces
end module ictus_contact_wall
