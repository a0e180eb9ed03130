!> Isotropic linear elasticity as a material law (small strain): sigma = lambda tr(eps) I +
!! 2 mu eps, with sigma_zz from the plane-strain or plane-stress condition in 2D.
!!
!! The constant tangent is the constitutive matrix of ictus_materials_elastic, so the
!! assembled stiffness and the element loop over this law compute the same internal force.
module ictus_materials_linear_elastic
  use ictus_core_kinds, only: dp
  use ictus_materials_law, only: law_t, ANALYSIS_PLANE_STRESS, voigt_strain
  use ictus_materials_elastic, only: elastic_dmat, wave_speed_p
  implicit none
  private
  public :: linear_elastic_t

  type, extends(law_t) :: linear_elastic_t
    !> Young's modulus and Poisson's ratio.
    real(dp) :: e = 0.0_dp
    real(dp) :: nu = 0.0_dp
  contains
    procedure :: init => le_init
    procedure :: stress => le_stress
    procedure :: wave_speed => le_wave_speed
  end type linear_elastic_t

contains

  !> No history; linear, with the tangent of plane strain and plane stress.
  subroutine le_init(this)
    class(linear_elastic_t), intent(inout) :: this
    this%name = 'linear elastic'
    this%nhist = 0
    this%linear = .true.
    call elastic_dmat(this%e, this%nu, .true., this%d2(:, :, 1))
    call elastic_dmat(this%e, this%nu, .false., this%d2(:, :, 2))
  end subroutine le_init

  !> sigma = D eps in 3D; plane stress sets sigma_zz = 0 through eps_zz = -nu/(1 - nu)
  !! (eps_xx + eps_yy), plane strain takes eps_zz = 0 as given. w = sigma : eps / 2.
  pure subroutine le_stress(this, analysis, grad, hist_old, hist_new, sig, w)
    class(linear_elastic_t), intent(in) :: this
    integer, intent(in) :: analysis
    real(dp), intent(in) :: grad(3, 3), hist_old(:)
    real(dp), intent(out) :: hist_new(:), sig(6), w
    real(dp) :: eps(6), lam, mu, tr
    hist_new = hist_old
    eps = voigt_strain(grad)
    mu = this%e/(2.0_dp*(1.0_dp + this%nu))
    lam = this%e*this%nu/((1.0_dp + this%nu)*(1.0_dp - 2.0_dp*this%nu))
    if (analysis == ANALYSIS_PLANE_STRESS) eps(3) = -this%nu/(1.0_dp - this%nu)*(eps(1) + eps(2))
    tr = eps(1) + eps(2) + eps(3)
    sig(1:3) = lam*tr + 2.0_dp*mu*eps(1:3)
    sig(4:6) = mu*eps(4:6)
    if (analysis == ANALYSIS_PLANE_STRESS) sig(3) = 0.0_dp
    w = 0.5_dp*dot_product(sig, eps)
  end subroutine le_stress

  pure real(dp) function le_wave_speed(this, rho, analysis)
    class(linear_elastic_t), intent(in) :: this
    real(dp), intent(in) :: rho
    integer, intent(in) :: analysis
    le_wave_speed = wave_speed_p(this%e, this%nu, rho, analysis /= ANALYSIS_PLANE_STRESS)
  end function le_wave_speed
end module ictus_materials_linear_elastic
