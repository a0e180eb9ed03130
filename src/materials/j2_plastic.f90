!> J2 (von Mises) plasticity with piecewise-linear isotropic hardening (*ELASTIC + *PLASTIC):
!!
!! - small strain: sigma = lambda tr(eps - eps_p) I + 2 mu (eps - eps_p), yield
!!   f = sqrt(3/2) |s| - sigma_y(epbar) <= 0, radial return;
!! - finite strain (NLGEOM): the same return on the logarithmic elastic strain
!!   eps_e = ln(V_e) of the elastic left Cauchy-Green tensor b_e = F C_p^-1 F^T, with the
!!   Kirchhoff stress tau (the exponential-map algorithm of Simo 1992), sigma = tau/J.
!!
!! sigma_y(epbar) interpolates the table (sigma_y_k, epbar_k), epbar_1 = 0, linearly and stays
!! at its last value beyond the table. Plane strain and 3D only (plane stress needs a
!! different return; the deck refuses it). History per point (8): the plastic strain eps_p
!! (small strain) or C_p^-1 - I (finite strain) as 6 Voigt components (xx, yy, zz, xy, yz, zx,
!! tensor components), epbar, and the plastic work per unit reference volume (the integral
!! of sigma_eq d epbar: the dissipation of the energy balance).
module ictus_materials_j2_plastic
  use ictus_core_kinds, only: dp
  use ictus_materials_law, only: law_t, voigt_of, tensor_of, det3, adjugate3, stress_norm
  use ictus_materials_elastic, only: elastic_dmat, wave_speed_p
  use ictus_materials_eigen, only: sym_eigen3
  implicit none
  private
  public :: j2_plastic_t, j2_plastic, yield_stress, J2_HIST

  !> History variables per point, and where the equivalent plastic strain and the plastic
  !! work sit in them.
  integer, parameter :: J2_HIST = 8, J2_EPBAR = 7, J2_WP = 8

  type, extends(law_t) :: j2_plastic_t
    real(dp) :: e = 0.0_dp
    real(dp) :: nu = 0.0_dp
    !> Hardening table: yield stress and equivalent plastic strain, (npts).
    real(dp), allocatable :: sy(:), ep(:)
  contains
    procedure :: init => j2_init
    procedure :: stress => j2_stress
    procedure :: wave_speed => j2_wave_speed
    procedure :: wave_ratio => j2_wave_ratio
  end type j2_plastic_t

contains

  !> The law of Young's modulus e, Poisson's ratio nu and the hardening table
  !! table = (sigma_y_1, epbar_1, sigma_y_2, epbar_2, ...).
  function j2_plastic(e, nu, table) result(law)
    real(dp), intent(in) :: e, nu, table(:)
    type(j2_plastic_t) :: law
    integer :: n, k
    n = size(table)/2
    law%e = e
    law%nu = nu
    allocate(law%sy(n), law%ep(n))
    do k = 1, n
      law%sy(k) = table(2*k - 1)
      law%ep(k) = table(2*k)
    end do
  end function j2_plastic

  subroutine j2_init(this)
    class(j2_plastic_t), intent(inout) :: this
    this%name = 'J2 plasticity'
    this%nhist = J2_HIST
    this%hist_dissipation = J2_WP
    this%hist_peeq = J2_EPBAR
    this%isochoric = .true.
    this%linear = .false.
    call elastic_dmat(this%e, this%nu, .true., this%d2(:, :, 1))
    call elastic_dmat(this%e, this%nu, .false., this%d2(:, :, 2))
  end subroutine j2_init

  !> Yield stress at equivalent plastic strain epbar and its slope H (0 beyond the table).
  pure subroutine yield_stress(sy, ep, epbar, s, h)
    real(dp), intent(in) :: sy(:), ep(:), epbar
    real(dp), intent(out) :: s, h
    integer :: k, n
    n = size(sy)
    s = sy(n)
    h = 0.0_dp
    do k = 1, n - 1
      if (epbar < ep(k + 1)) then
        h = (sy(k + 1) - sy(k))/(ep(k + 1) - ep(k))
        s = sy(k) + h*(epbar - ep(k))
        return
      end if
    end do
  end subroutine yield_stress

  !> The plastic multiplier dg of the return from a trial equivalent stress q_trial at
  !! epbar: q_trial - 3 mu dg = sigma_y(epbar + dg), solved segment by segment of the table
  !! (exact for a piecewise-linear hardening).
  pure real(dp) function return_multiplier(this, mu, q_trial, epbar) result(dg)
    class(j2_plastic_t), intent(in) :: this
    real(dp), intent(in) :: mu, q_trial, epbar
    real(dp) :: s, h, r
    integer :: it
    dg = 0.0_dp
    do it = 1, size(this%sy) + 2
      call yield_stress(this%sy, this%ep, epbar + dg, s, h)
      r = q_trial - 3.0_dp*mu*dg - s
      dg = dg + r/(3.0_dp*mu + h)
      call yield_stress(this%sy, this%ep, epbar + dg, s, h)
      if (abs(q_trial - 3.0_dp*mu*dg - s) <= 1.0e-13_dp*q_trial) exit
    end do
  end function return_multiplier

  !> Radial return of a trial stress tr (3 x 3, from the elastic strain ee): the stress,
  !! the plastic strain increment (tensor) and the new epbar and plastic work.
  pure subroutine radial_return(this, mu, lam, ee, hist_old, sig, dep, epbar, wp)
    class(j2_plastic_t), intent(in) :: this
    real(dp), intent(in) :: mu, lam, ee(3, 3), hist_old(:)
    real(dp), intent(out) :: sig(3, 3), dep(3, 3), epbar, wp
    real(dp) :: s(3, 3), q, p, sy, h, dg, sy1
    integer :: i
    p = (lam + 2.0_dp*mu/3.0_dp)*(ee(1, 1) + ee(2, 2) + ee(3, 3))
    s = 2.0_dp*mu*ee
    do i = 1, 3
      s(i, i) = s(i, i) - 2.0_dp*mu*(ee(1, 1) + ee(2, 2) + ee(3, 3))/3.0_dp
    end do
    q = sqrt(1.5_dp*sum(s*s))
    epbar = hist_old(J2_EPBAR)
    wp = hist_old(J2_WP)
    dep = 0.0_dp
    call yield_stress(this%sy, this%ep, epbar, sy, h)
    if (q > sy) then
      dg = return_multiplier(this, mu, q, epbar)
      dep = (1.5_dp*dg/q)*s
      s = s*(1.0_dp - 3.0_dp*mu*dg/q)
      epbar = epbar + dg
      ! the plastic work int sigma_y d epbar over the increment (trapezoidal: exact for a
      ! piecewise-linear hardening within one segment)
      call yield_stress(this%sy, this%ep, epbar, sy1, h)
      wp = wp + 0.5_dp*(sy + sy1)*dg
    end if
    sig = s
    do i = 1, 3
      sig(i, i) = sig(i, i) + p
    end do
  end subroutine radial_return

  pure subroutine j2_stress(this, grad, hist_old, hist_new, sig, w)
    class(j2_plastic_t), intent(in) :: this
    real(dp), intent(in) :: grad(3, 3), hist_old(:)
    real(dp), intent(out) :: hist_new(:), sig(6), w
    real(dp) :: mu, lam, eps(3, 3), ee(3, 3), s3(3, 3), dep(3, 3), epbar, wp
    mu = this%e/(2.0_dp*(1.0_dp + this%nu))
    lam = this%e*this%nu/((1.0_dp + this%nu)*(1.0_dp - 2.0_dp*this%nu))
    if (this%kin%nlgeom) then
      call finite_return(this, mu, lam, grad, hist_old, hist_new, sig, w)
      return
    end if
    eps = 0.5_dp*(grad + transpose(grad))
    ee = eps - tensor_of(hist_old(1:6))
    call radial_return(this, mu, lam, ee, hist_old, s3, dep, epbar, wp)
    ee = ee - dep
    hist_new(1:6) = hist_old(1:6) + voigt_of(dep)
    hist_new(J2_EPBAR) = epbar
    hist_new(J2_WP) = wp
    sig = voigt_of(s3)
    w = 0.5_dp*sum(s3*ee)
  end subroutine j2_stress

  !> The finite-strain return: b_e trial = F C_p^-1 F^T, principal logarithmic strains,
  !! radial return on the Kirchhoff stress, b_e = exp(2 eps_e) in the same principal
  !! directions, C_p^-1 = F^-1 b_e F^-T.
  pure subroutine finite_return(this, mu, lam, grad, hist_old, hist_new, sig, w)
    class(j2_plastic_t), intent(in) :: this
    real(dp), intent(in) :: mu, lam, grad(3, 3), hist_old(:)
    real(dp), intent(out) :: hist_new(:), sig(6), w
    real(dp) :: f(3, 3), finv(3, 3), cpi(3, 3), be(3, 3), lam2(3), nv(3, 3), ee(3, 3)
    real(dp) :: tau(3, 3), dep(3, 3), epbar, wp, detf, ln(3), c
    integer :: i, k
    f = grad
    cpi = tensor_of(hist_old(1:6))
    do i = 1, 3
      f(i, i) = f(i, i) + 1.0_dp
      cpi(i, i) = cpi(i, i) + 1.0_dp
    end do
    detf = det3(f)
    be = matmul(matmul(f, cpi), transpose(f))
    call sym_eigen3(be, lam2, nv)
    ln = 0.5_dp*log(lam2)
    ! the elastic log strain in its principal frame (diagonal)
    ee = 0.0_dp
    do i = 1, 3
      ee(i, i) = ln(i)
    end do
    call radial_return(this, mu, lam, ee, hist_old, tau, dep, epbar, wp)
    ee = ee - dep
    w = 0.5_dp*sum(tau*ee)
    ! back to the spatial frame: b_e = N exp(2 eps_e) N^T, tau = N tau' N^T
    be = 0.0_dp
    do i = 1, 3
      c = exp(2.0_dp*ee(i, i))
      do k = 1, 3
        be(:, k) = be(:, k) + c*nv(k, i)*nv(:, i)
      end do
    end do
    tau = matmul(matmul(nv, tau), transpose(nv))
    finv = inverse3(f, detf)
    cpi = matmul(matmul(finv, be), transpose(finv))
    do i = 1, 3
      cpi(i, i) = cpi(i, i) - 1.0_dp
    end do
    hist_new(1:6) = voigt_of(cpi)
    hist_new(J2_EPBAR) = epbar
    hist_new(J2_WP) = wp
    sig = voigt_of(tau)/detf
  end subroutine finite_return

  !> The inverse of a 3 x 3 matrix with determinant d (the adjugate over d).
  pure function inverse3(a, d) result(b)
    real(dp), intent(in) :: a(3, 3), d
    real(dp) :: b(3, 3)
    b = adjugate3(a)/d
  end function inverse3

  !> The elastic dilatational wave speed (plasticity only softens).
  pure real(dp) function j2_wave_speed(this, rho)
    class(j2_plastic_t), intent(in) :: this
    real(dp), intent(in) :: rho
    j2_wave_speed = wave_speed_p(this%e, this%nu, rho, .true.)
  end function j2_wave_speed

  !> c/c_0 in the current state (doc/theory.md §7.1): the Kirchhoff stress is linear in the
  !! logarithmic elastic strain with the elastic moduli, so the elastic dilatational modulus
  !! of the Cauchy stress is at most M = (lambda + 2 mu)/J + |sigma| (plastic flow only
  !! softens); c/c_0 = sqrt(J M/(lambda + 2 mu)). 1 in small strain.
  pure real(dp) function j2_wave_ratio(this, grad, hist) result(r)
    class(j2_plastic_t), intent(in) :: this
    real(dp), intent(in) :: grad(3, 3), hist(:)
    real(dp) :: sig(6), w, hnew(size(hist)), m0, f(3, 3), detf
    integer :: i
    r = 1.0_dp
    if (.not. this%kin%nlgeom) return
    f = grad
    do i = 1, 3
      f(i, i) = f(i, i) + 1.0_dp
    end do
    detf = det3(f)
    call this%stress(grad, hist, hnew, sig, w)
    m0 = this%d2(1, 1, 1)
    r = sqrt(1.0_dp + detf*stress_norm(sig)/m0)
  end function j2_wave_ratio
end module ictus_materials_j2_plastic
