!> *TIE: two surfaces glued by a MORTAR tie (doc/contact.md §4b); the first surface is the
!! slave, the second the master.
!!
!! * Set-up, on the reference coordinates: the mortar points of the pair (the slave segments
!!   cut where the master segment ends project, Gauss points on each piece; ictus_contact_
!!   mortar) and their closest points on the master. A point is tied when it lies within
!!   5 % of the longest segment of the two surfaces from the master; the pairing (slave
!!   point, master segment and parameter) and the reference offset o = X_s - X_m of each
!!   tied point are kept for the whole run.
!! * Weighted gap vector of slave node A, with the mortar weights phi_A (positive, sum 1):
!!   l_A = int phi_A dGamma over all slave points, G_A = int phi_A (x_s - x_m - o) dGamma
!!   over the tied points; traction P_A = -eps G_A/l_A in both directions (a bilateral
!!   penalty: tension, compression and shear); energy sum_A 1/2 eps |G_A|^2/l_A.
!! * Forces from the same integrals on both sides, with lambda = sum_A phi_A P_A at a point:
!!   f_B = int N_B lambda dGamma on slave node B, f_C = -int M_C lambda dGamma on master
!!   node C: action equals reaction to round-off, and a uniform relative displacement gives
!!   a uniform traction and its consistent nodal loads on both surfaces (a non-matching tied
!!   interface passes the patch test).
!! * The offset is not rotated with the bodies: where the two surfaces coincide (o = 0, the
!!   usual glued mesh) a rigid rotation gives no force; a gap o across the tie is held fixed
!!   in space, so keep tied surfaces on top of each other.
module ictus_contact_tie
  use ictus_core_kinds, only: dp
  use ictus_contact_surface, only: contact_surface_t, MAX_SEG_NODES, segment_shape
  use ictus_contact_pair, only: contact_pair_t, pair_reset_results
  use ictus_contact_mortar, only: mortar_points, mortar_weights, projected, distribute
  implicit none
  private
  public :: tie_setup, tie_forces

  !> A point is tied when its distance to the master is at most this fraction of the
  !! longest reference segment of the two surfaces.
  real(dp), parameter :: tie_reach = 0.05_dp

contains

  !> The tied points of pair (kind PAIR_TIE, pair_setup done) on the reference
  !! coordinates x0 (2, nn): pair%mo%n points with their offsets, the weights l_A of all
  !! slave points, and mo%untied (slave points beyond tie_reach).
  subroutine tie_setup(pair, s1, s2, x0)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: s1, s2
    real(dp), intent(in) :: x0(:,:)
    real(dp) :: r(MAX_SEG_NODES), dr(MAX_SEG_NODES), ddr(MAX_SEG_NODES), phi(MAX_SEG_NODES)
    real(dp) :: reach
    integer :: i, k, s, a
    call mortar_points(pair, s1, s2, x0)
    reach = tie_reach*max(s1%hmax, s2%hmax)
    associate (mo => pair%mo)
      if (allocated(mo%off)) deallocate(mo%off)
      allocate(mo%off(2, mo%n))
      mo%ell = 0.0_dp
      k = 0
      do i = 1, mo%n
        s = mo%sseg(i)
        call segment_shape(s1, s, mo%ts(i), r, dr, ddr)
        call mortar_weights(s1, s, mo%ts(i), r, phi)
        do a = 1, s1%nen(s)
          mo%ell(s1%lnode(a, s)) = mo%ell(s1%lnode(a, s)) + phi(a)*mo%wj(i)
        end do
        if (.not. projected(mo, i)) cycle
        if (abs(mo%d(i)) > reach) cycle
        k = k + 1
        mo%sseg(k) = mo%sseg(i)
        mo%ts(k) = mo%ts(i)
        mo%wj(k) = mo%wj(i)
        mo%status(k) = mo%status(i)
        mo%mseg(k) = mo%mseg(i)
        mo%tm(k) = mo%tm(i)
        mo%normal(:, k) = mo%normal(:, i)
        mo%d(k) = mo%d(i)
        mo%off(:, k) = relative(s1, s2, mo%sseg(k), mo%ts(k), mo%mseg(k), mo%tm(k), x0)
      end do
      mo%untied = mo%n - k
      mo%n = k
    end associate
    pair%outside_points = 0
    pair%failures = 0
  end subroutine tie_setup

  !> x_s - x_m at one point: slave segment s at t against master segment m at tm, on the
  !! coordinates x (2, nn).
  pure function relative(s1, s2, s, t, m, tm, x) result(g)
    type(contact_surface_t), intent(in) :: s1, s2
    integer, intent(in) :: s, m
    real(dp), intent(in) :: t, tm, x(:,:)
    real(dp) :: g(2)
    real(dp) :: r(MAX_SEG_NODES), dr(MAX_SEG_NODES), ddr(MAX_SEG_NODES)
    integer :: a
    g = 0.0_dp
    call segment_shape(s1, s, t, r, dr, ddr)
    do a = 1, s1%nen(s)
      g = g + r(a)*x(:, s1%conn(a, s))
    end do
    call segment_shape(s2, m, tm, r, dr, ddr)
    do a = 1, s2%nen(m)
      g = g - r(a)*x(:, s2%conn(a, m))
    end do
  end function relative

  !> Tie forces of one pair on the coordinates x (2, nn), accumulated into fc (2, nn);
  !! the results of the pair (force_first/second, energy; max_pressure: the largest |P_A|,
  !! max_penetration: the largest |G_A|/l_A; the point output: each slave node's |P_A|).
  subroutine tie_forces(pair, s1, s2, x, fc)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: s1, s2
    real(dp), intent(in) :: x(:,:)
    real(dp), intent(inout) :: fc(:,:)
    real(dp) :: r(MAX_SEG_NODES), dr(MAX_SEG_NODES), ddr(MAX_SEG_NODES), phi(MAX_SEG_NODES)
    real(dp) :: g(2), gn
    integer :: i, s, a, la
    call pair_reset_results(pair)
    associate (mo => pair%mo)
      mo%gap = 0.0_dp
      mo%slip = 0.0_dp
      do i = 1, mo%n
        s = mo%sseg(i)
        call segment_shape(s1, s, mo%ts(i), r, dr, ddr)
        call mortar_weights(s1, s, mo%ts(i), r, phi)
        g = relative(s1, s2, s, mo%ts(i), mo%mseg(i), mo%tm(i), x) - mo%off(:, i)
        do a = 1, s1%nen(s)
          la = s1%lnode(a, s)
          mo%gap(la) = mo%gap(la) + phi(a)*g(1)*mo%wj(i)
          mo%slip(la) = mo%slip(la) + phi(a)*g(2)*mo%wj(i)
        end do
      end do
      do la = 1, s1%nsn
        mo%p(la) = 0.0_dp
        mo%t(la) = 0.0_dp
        if (mo%ell(la) > 0.0_dp) then
          mo%p(la) = -pair%penalty*mo%gap(la)/mo%ell(la)
          mo%t(la) = -pair%penalty*mo%slip(la)/mo%ell(la)
        end if
        gn = hypot(mo%p(la), mo%t(la))
        pair%x(:, la) = x(:, s1%nodes(la))
        pair%pressure(la) = gn
        if (gn <= 0.0_dp) cycle
        pair%energy = pair%energy + 0.5_dp*gn*gn/pair%penalty*mo%ell(la)
        pair%max_pressure = max(pair%max_pressure, gn)
        pair%max_penetration = max(pair%max_penetration, gn/pair%penalty)
        pair%active_points = pair%active_points + 1
      end do
      call tie_apply(pair, s1, s2, fc)
    end associate
  end subroutine tie_forces

  !> The nodal forces of the tractions (p, t) of pair%mo on both surfaces: lambda w J, with
  !! lambda = sum_A phi_A (p_A, t_A), onto N_B (slave) and -M_C (master); the two resultants
  !! summed from the nodal contributions separately.
  subroutine tie_apply(pair, s1, s2, fc)
    type(contact_pair_t), intent(inout) :: pair
    type(contact_surface_t), intent(in) :: s1, s2
    real(dp), intent(inout) :: fc(:,:)
    real(dp) :: r(MAX_SEG_NODES), dr(MAX_SEG_NODES), ddr(MAX_SEG_NODES), phi(MAX_SEG_NODES)
    real(dp) :: tr(2)
    integer :: i, s, a
    associate (mo => pair%mo)
      do i = 1, mo%n
        s = mo%sseg(i)
        call segment_shape(s1, s, mo%ts(i), r, dr, ddr)
        call mortar_weights(s1, s, mo%ts(i), r, phi)
        tr = 0.0_dp
        do a = 1, s1%nen(s)
          tr = tr + phi(a)*[mo%p(s1%lnode(a, s)), mo%t(s1%lnode(a, s))]
        end do
        call distribute(pair, s1, s2, i, r, tr*mo%wj(i), fc)
      end do
    end associate
  end subroutine tie_apply
end module ictus_contact_tie
