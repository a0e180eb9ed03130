!> Compressible neo-Hookean hyperelasticity in the Abaqus form (*HYPERELASTIC, NEO HOOKE),
!! finite strain only (NLGEOM=YES):
!!
!!     W = C10 (I1bar - 3) + (J - 1)^2 / D1,   I1bar = J^(-2/3) tr b,  b = F F^T
!!     sigma = (2 C10 / J) dev(bbar) + (2 / D1) (J - 1) I,   bbar = J^(-2/3) b
!!
!! In the small-strain limit mu = 2 C10 and the bulk modulus K = 2/D1 (doc/theory.md §1).
module ictus_materials_neo_hooke
  use ictus_core_kinds, only: dp
  use ictus_materials_law, only: law_t, voigt_of, det3, stretch_measures, stress_norm
  use ictus_materials_elastic, only: elastic_dmat
  implicit none
  private
  public :: neo_hooke_t

  type, extends(law_t) :: neo_hooke_t
    real(dp) :: c10 = 0.0_dp
    real(dp) :: d1 = 0.0_dp
  contains
    procedure :: init => nh_init
    procedure :: stress => nh_stress
    procedure :: wave_speed => nh_wave_speed
    procedure :: wave_ratio => nh_wave_ratio
  end type neo_hooke_t

contains

  !> No history; not linear; the reference tangent of mu = 2 C10, K = 2/D1 (as E and nu).
  subroutine nh_init(this)
    class(neo_hooke_t), intent(inout) :: this
    real(dp) :: e, nu
    this%name = 'neo-Hookean'
    this%nhist = 0
    this%linear = .false.
    call small_strain_constants(this, e, nu)
    this%isochoric = 2.0_dp/this%d1 >= 50.0_dp*2.0_dp*this%c10
    call elastic_dmat(e, nu, .true., this%d2(:, :, 1))
    call elastic_dmat(e, nu, .false., this%d2(:, :, 2))
  end subroutine nh_init

  !> E and nu of the small-strain limit: mu = 2 C10, K = 2/D1.
  pure subroutine small_strain_constants(this, e, nu)
    class(neo_hooke_t), intent(in) :: this
    real(dp), intent(out) :: e, nu
    real(dp) :: mu, k
    mu = 2.0_dp*this%c10
    k = 2.0_dp/this%d1
    e = 9.0_dp*k*mu/(3.0_dp*k + mu)
    nu = (3.0_dp*k - 2.0_dp*mu)/(2.0_dp*(3.0_dp*k + mu))
  end subroutine small_strain_constants

  !> The Cauchy stress of the law at F = I + grad (a finite-strain law: the deck refuses it
  !! without NLGEOM); w = W per unit reference volume.
  pure subroutine nh_stress(this, grad, hist_old, hist_new, sig, w)
    class(neo_hooke_t), intent(in) :: this
    real(dp), intent(in) :: grad(3, 3), hist_old(:)
    real(dp), intent(out) :: hist_new(:), sig(6), w
    real(dp) :: f(3, 3), b(3, 3), detf, i1bar, s(3, 3), jm23
    integer :: i
    hist_new = hist_old
    f = grad
    do i = 1, 3
      f(i, i) = f(i, i) + 1.0_dp
    end do
    detf = det3(f)
    b = matmul(f, transpose(f))
    jm23 = detf**(-2.0_dp/3.0_dp)
    i1bar = jm23*(b(1, 1) + b(2, 2) + b(3, 3))
    s = (2.0_dp*this%c10/detf)*jm23*b
    do i = 1, 3
      s(i, i) = s(i, i) - (2.0_dp*this%c10/detf)*i1bar/3.0_dp + (2.0_dp/this%d1)*(detf - 1.0_dp)
    end do
    sig = voigt_of(s)
    w = this%c10*(i1bar - 3.0_dp) + (detf - 1.0_dp)**2/this%d1
  end subroutine nh_stress

  !> Dilatational wave speed of the small-strain limit, sqrt((K + 4 mu/3)/rho).
  pure real(dp) function nh_wave_speed(this, rho)
    class(neo_hooke_t), intent(in) :: this
    real(dp), intent(in) :: rho
    nh_wave_speed = sqrt((2.0_dp/this%d1 + 8.0_dp*this%c10/3.0_dp)/rho)
  end function nh_wave_speed

  !> c/c_0 in the current state (doc/theory.md §7.1): the dilatational modulus is at most
  !! M = K + (4/3) mu J^(-5/3) lam_max(b) + |sigma| (bulk part K, isochoric part of the
  !! stretched chains, geometric stiffness), against M_0 = K + (4/3) mu; c/c_0 = sqrt(J M/M_0).
  pure real(dp) function nh_wave_ratio(this, grad, hist) result(r)
    class(neo_hooke_t), intent(in) :: this
    real(dp), intent(in) :: grad(3, 3), hist(:)
    real(dp) :: detf, lmax, sig(6), w, hnew(size(hist)), k, mu, m
    mu = 2.0_dp*this%c10
    k = 2.0_dp/this%d1
    call stretch_measures(grad, detf, lmax)
    call this%stress(grad, hist, hnew, sig, w)
    m = k + 4.0_dp*mu/3.0_dp*detf**(-5.0_dp/3.0_dp)*lmax + stress_norm(sig)
    r = sqrt(detf*m/(k + 4.0_dp*mu/3.0_dp))
  end function nh_wave_ratio
end module ictus_materials_neo_hooke
