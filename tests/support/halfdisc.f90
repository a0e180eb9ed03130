!> The half-disc patch of doc/iga.md §10.4 (R = 4 by default), shared by the geometry and
!! element tests.
module ictus_test_halfdisc
  use ictus_core_kinds, only: dp, pi
  use ictus_geometry_patch, only: patch_t
  implicit none
  private
  public :: half_disc

contains

  !> One biquadratic patch for the half-disc x >= 0 centred at the origin, in the (xi, eta)
  !! order of the doc/iga.md §10.4 table (det J < 0 in that order).
  subroutine half_disc(patch, radius)
    type(patch_t), intent(inout) :: patch
    real(dp), intent(in), optional :: radius
    real(dp) :: cp(3, 9), k(6), c, tn, rr, s2
    rr = 4.0_dp
    if (present(radius)) rr = radius
    s2 = sqrt(2.0_dp)/2.0_dp
    c = cos(pi/8.0_dp)
    tn = tan(pi/8.0_dp)
    k = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    cp(:, 1) = [0.0_dp, -rr, 1.0_dp]
    cp(:, 2) = [0.0_dp, 0.0_dp, 1.0_dp]
    cp(:, 3) = [0.0_dp, rr, 1.0_dp]
    cp(:, 4) = [rr*tn, -rr, c]
    cp(:, 5) = [rr/2.0_dp, 0.0_dp, 1.0_dp]
    cp(:, 6) = [rr*tn, rr, c]
    cp(:, 7) = [rr*s2, -rr*s2, 1.0_dp]
    cp(:, 8) = [2.0_dp*rr*s2, 0.0_dp, s2]
    cp(:, 9) = [rr*s2, rr*s2, 1.0_dp]
    call patch%init('HALF', [2, 2], [3, 3], k, k, cp)
  end subroutine half_disc
end module ictus_test_halfdisc
