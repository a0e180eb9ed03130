!> Isotropic linear elasticity as a material law (*ELASTIC): in small strain
!! sigma = lambda tr(eps) I + 2 mu eps, with sigma_zz from the plane-strain or plane-stress
!! condition in 2D; with NLGEOM the St. Venant-Kirchhoff law, its finite-strain extension.
!!
!! The constant tangent is the constitutive matrix of ictus_materials_elastic, so the
!! assembled stiffness and the element loop over this law compute the same internal force.
module ictus_materials_linear_elastic
  use ictus_core_kinds, only: dp
  use ictus_materials_law, only: law_t, ANALYSIS_PLANE_STRESS, ANALYSIS_3D, voigt_strain, &
      voigt_of, det3
  use ictus_materials_elastic, only: elastic_dmat, wave_speed_p
  implicit none
  private
  public :: linear_elastic_t

  type, extends(law_t) :: linear_elastic_t
    !> Young's modulus and Poisson's ratio.
    real(dp) :: e = 0.0_dp
    real(dp) :: nu = 0.0_dp
    !> The Lame constants (set by init).
    real(dp) :: lam = 0.0_dp
    real(dp) :: mu = 0.0_dp
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
    this%mu = this%e/(2.0_dp*(1.0_dp + this%nu))
    this%lam = this%e*this%nu/((1.0_dp + this%nu)*(1.0_dp - 2.0_dp*this%nu))
    this%isochoric = this%nu >= 0.49_dp
    call elastic_dmat(this%e, this%nu, .true., this%d2(:, :, 1))
    call elastic_dmat(this%e, this%nu, .false., this%d2(:, :, 2))
  end subroutine le_init

  !> Small strain: sigma = D eps in 3D; plane stress sets sigma_zz = 0 through
  !! eps_zz = -nu/(1 - nu) (eps_xx + eps_yy), plane strain takes eps_zz = 0 as given;
  !! w = sigma : eps / 2. Finite strain (kin%nlgeom): St. Venant-Kirchhoff,
  !! S = lambda tr(E) I + 2 mu E with E = (F^T F - I)/2, sigma = F S F^T / J,
  !! w = lambda (tr E)^2 / 2 + mu E : E.
  pure subroutine le_stress(this, grad, hist_old, hist_new, sig, w)
    class(linear_elastic_t), intent(in) :: this
    real(dp), intent(in) :: grad(3, 3), hist_old(:)
    real(dp), intent(out) :: hist_new(:), sig(6), w
    real(dp) :: eps(6), lam, mu, tr, f(3, 3), e(3, 3), s(3, 3), detf
    integer :: i
    hist_new = hist_old
    mu = this%mu
    lam = this%lam
    if (this%kin%nlgeom .and. this%kin%analysis /= ANALYSIS_3D) then
      call svk_plane(lam, mu, grad, sig, w)
      return
    end if
    if (this%kin%nlgeom) then
      f = grad
      do i = 1, 3
        f(i, i) = f(i, i) + 1.0_dp
      end do
      e = 0.5_dp*(matmul(transpose(f), f))
      do i = 1, 3
        e(i, i) = e(i, i) - 0.5_dp
      end do
      tr = e(1, 1) + e(2, 2) + e(3, 3)
      s = 2.0_dp*mu*e
      do i = 1, 3
        s(i, i) = s(i, i) + lam*tr
      end do
      detf = det3(f)
      sig = voigt_of(matmul(matmul(f, s), transpose(f))/detf)
      w = 0.5_dp*lam*tr*tr + mu*sum(e*e)
      return
    end if
    eps = voigt_strain(grad)
    if (this%kin%analysis == ANALYSIS_PLANE_STRESS) eps(3) = -this%nu/(1.0_dp - this%nu)*(eps(1) + &
        eps(2))
    tr = eps(1) + eps(2) + eps(3)
    sig(1:3) = lam*tr + 2.0_dp*mu*eps(1:3)
    sig(4:6) = mu*eps(4:6)
    if (this%kin%analysis == ANALYSIS_PLANE_STRESS) sig(3) = 0.0_dp
    w = 0.5_dp*dot_product(sig, eps)
  end subroutine le_stress

  !> St. Venant-Kirchhoff in plane strain (grad has no out-of-plane terms, F_33 = 1): the
  !! in-plane 2 x 2 algebra of le_stress written out, E_33 = 0, S_33 = lambda tr E,
  !! sigma = F S F^T / J in the plane and sigma_zz = S_33 / J.
  pure subroutine svk_plane(lam, mu, grad, sig, w)
    real(dp), intent(in) :: lam, mu, grad(3, 3)
    real(dp), intent(out) :: sig(6), w
    real(dp) :: f11, f12, f21, f22, e11, e22, e12, tr, s11, s22, s12, detf, a11, a12, a21, a22
    f11 = 1.0_dp + grad(1, 1)
    f12 = grad(1, 2)
    f21 = grad(2, 1)
    f22 = 1.0_dp + grad(2, 2)
    e11 = 0.5_dp*(f11*f11 + f21*f21 - 1.0_dp)
    e22 = 0.5_dp*(f12*f12 + f22*f22 - 1.0_dp)
    e12 = 0.5_dp*(f11*f12 + f21*f22)
    tr = e11 + e22
    s11 = lam*tr + 2.0_dp*mu*e11
    s22 = lam*tr + 2.0_dp*mu*e22
    s12 = 2.0_dp*mu*e12
    detf = f11*f22 - f12*f21
    ! A = F S, sigma = A F^T / J
    a11 = f11*s11 + f12*s12
    a12 = f11*s12 + f12*s22
    a21 = f21*s11 + f22*s12
    a22 = f21*s12 + f22*s22
    sig(1) = (a11*f11 + a12*f12)/detf
    sig(2) = (a21*f21 + a22*f22)/detf
    sig(3) = lam*tr/detf
    sig(4) = (a11*f21 + a12*f22)/detf
    sig(5) = 0.0_dp
    sig(6) = 0.0_dp
    w = 0.5_dp*lam*tr*tr + mu*(e11*e11 + e22*e22 + 2.0_dp*e12*e12)
  end subroutine svk_plane

  pure real(dp) function le_wave_speed(this, rho)
    class(linear_elastic_t), intent(in) :: this
    real(dp), intent(in) :: rho
    le_wave_speed = wave_speed_p(this%e, this%nu, rho, this%kin%analysis /= ANALYSIS_PLANE_STRESS)
  end function le_wave_speed
end module ictus_materials_linear_elastic
