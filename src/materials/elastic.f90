!> Isotropic linear elasticity in 2D: the constitutive matrix and the elastic wave speeds.
!!
!! Voigt order (xx, yy, xy) with the engineering shear strain gamma_xy = du/dy + dv/dx, so
!! sigma = D eps with eps = (eps_xx, eps_yy, gamma_xy). See doc/theory.md §1.
module ictus_materials_elastic
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: elastic_dmat, wave_speed_p, wave_speed_s

contains

  !> Constitutive matrix of an isotropic material in plane strain or plane stress.
  !! e: Young's modulus; nu: Poisson's ratio; plane_strain: .true. for plane strain,
  !! .false. for plane stress; d(3,3): the matrix, Voigt (xx, yy, xy), engineering shear.
  pure subroutine elastic_dmat(e, nu, plane_strain, d)
    real(dp), intent(in) :: e, nu
    logical, intent(in) :: plane_strain
    real(dp), intent(out) :: d(3,3)
    real(dp) :: c
    d = 0.0_dp
    if (plane_strain) then
      c = e/((1.0_dp + nu)*(1.0_dp - 2.0_dp*nu))
      d(1,1) = c*(1.0_dp - nu)
      d(2,2) = d(1,1)
      d(1,2) = c*nu
      d(2,1) = d(1,2)
      d(3,3) = c*(1.0_dp - 2.0_dp*nu)/2.0_dp
    else
      c = e/(1.0_dp - nu*nu)
      d(1,1) = c
      d(2,2) = c
      d(1,2) = c*nu
      d(2,1) = d(1,2)
      d(3,3) = c*(1.0_dp - nu)/2.0_dp
    end if
  end subroutine elastic_dmat

  !> Dilatational (P) wave speed: sqrt((lambda + 2 mu)/rho) in plane strain,
  !! sqrt(E/(rho (1 - nu^2))) in plane stress.
  !! e: Young's modulus; nu: Poisson's ratio; rho: density; plane_strain: the 2D idealisation.
  pure real(dp) function wave_speed_p(e, nu, rho, plane_strain)
    real(dp), intent(in) :: e, nu, rho
    logical, intent(in) :: plane_strain
    if (plane_strain) then
      wave_speed_p = sqrt(e*(1.0_dp - nu)/((1.0_dp + nu)*(1.0_dp - 2.0_dp*nu)*rho))
    else
      wave_speed_p = sqrt(e/(rho*(1.0_dp - nu*nu)))
    end if
  end function wave_speed_p

  !> Shear (S) wave speed sqrt(mu/rho), mu = E/(2 (1 + nu)).
  !! e: Young's modulus; nu: Poisson's ratio; rho: density.
  pure real(dp) function wave_speed_s(e, nu, rho)
    real(dp), intent(in) :: e, nu, rho
    wave_speed_s = sqrt(e/(2.0_dp*(1.0_dp + nu)*rho))
  end function wave_speed_s
end module ictus_materials_elastic
