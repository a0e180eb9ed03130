!> The toy law of doc/architecture.md "Adding a material law", defined here in tests/ only:
!! isotropic small-strain elasticity in Lame form, sigma = lambda tr(eps) I + 2 mu eps, not
!! declared linear (so AUTO takes the element loop) and with one history variable per point,
!! the largest strain-energy density reached so far.
module toy_law
  use ictus_core_kinds, only: dp
  use ictus_materials_law, only: law_t, voigt_strain, ANALYSIS_PLANE_STRESS
  implicit none
  private
  public :: lame_law_t

  type, extends(law_t) :: lame_law_t
    real(dp) :: lambda = 0.0_dp
    real(dp) :: mu = 0.0_dp
  contains
    procedure :: init => lame_init
    procedure :: stress => lame_stress
    procedure :: wave_speed => lame_wave_speed
  end type lame_law_t

contains

  subroutine lame_init(this)
    class(lame_law_t), intent(inout) :: this
    this%name = 'toy Lame'
    this%nhist = 1
    this%linear = .false.
    ! the reference tangent (plane strain, plane stress), for the stable-step estimate
    this%d2 = 0.0_dp
    this%d2(1:2, 1:2, 1) = this%lambda
    this%d2(1, 1, 1) = this%lambda + 2.0_dp*this%mu
    this%d2(2, 2, 1) = this%lambda + 2.0_dp*this%mu
    this%d2(3, 3, :) = this%mu
    this%d2(1:2, 1:2, 2) = 2.0_dp*this%mu*this%lambda/(this%lambda + 2.0_dp*this%mu)
    this%d2(1, 1, 2) = this%d2(1, 1, 2) + 2.0_dp*this%mu
    this%d2(2, 2, 2) = this%d2(2, 2, 2) + 2.0_dp*this%mu
  end subroutine lame_init

  !> Small strain only (the tests use plane strain: eps_zz = 0); hist(1) = max(hist(1), w).
  pure subroutine lame_stress(this, grad, hist_old, hist_new, sig, w)
    class(lame_law_t), intent(in) :: this
    real(dp), intent(in) :: grad(3, 3), hist_old(:)
    real(dp), intent(out) :: hist_new(:), sig(6), w
    real(dp) :: eps(6), tr
    eps = voigt_strain(grad)
    tr = eps(1) + eps(2) + eps(3)
    sig(1:3) = this%lambda*tr + 2.0_dp*this%mu*eps(1:3)
    sig(4:6) = this%mu*eps(4:6)
    if (this%kin%analysis == ANALYSIS_PLANE_STRESS) sig(3) = 0.0_dp
    w = 0.5_dp*dot_product(sig, eps)
    hist_new(1) = max(hist_old(1), w)
  end subroutine lame_stress

  pure real(dp) function lame_wave_speed(this, rho)
    class(lame_law_t), intent(in) :: this
    real(dp), intent(in) :: rho
    lame_wave_speed = sqrt((this%lambda + 2.0_dp*this%mu)/rho)
    if (this%kin%analysis == ANALYSIS_PLANE_STRESS) lame_wave_speed = &
        sqrt(4.0_dp*this%mu*(this%lambda + this%mu)/((this%lambda + 2.0_dp*this%mu)*rho))
  end function lame_wave_speed
end module toy_law
