!> The material-law interface: what the element routines ask of a constitutive law at one
!! quadrature point.
!!
!! A law is a type that extends `law_t`. Its point routine `stress` is pure: the displacement
!! gradient (small strain), or with NLGEOM the deformation gradient F = I + grad, and the
!! history variables at the start of the step go in; the Cauchy stress, the history at the end
!! of the step and the stored-energy density come out. The element keeps
!! no state of its own, so a law with history stores it in the state of the run (and so in
!! checkpoints) through `nhist`. `wave_speed` gives the dilatational wave speed that bounds
!! the stable time step at the start, `wave_ratio` how much faster the waves run in the
!! current state (finite strain: the stable step follows it during the run), and `tangent_2d` the small-strain tangent at the reference state (`tangent_3d` its 3D form); a
!! `linear` law's tangent is exact everywhere, so its internal force may be the assembled
!! product K u (doc/theory.md).
!!
!! Tensors are 3 x 3 in every dimension: a 2D analysis has zero out-of-plane gradients, and the
!! stress comes back in Voigt order (xx, yy, zz, xy, yz, zx).
module ictus_materials_law
  use ictus_core_kinds, only: dp
  use ictus_materials_eigen, only: sym_eigen3
  implicit none
  private
  public :: law_t, kinematics_t, ANALYSIS_PLANE_STRAIN, ANALYSIS_PLANE_STRESS, ANALYSIS_3D, &
      voigt_strain, voigt_of, tensor_of, det3, adjugate3, stretch_measures, stress_norm

  !> The kinematic idealisation a law is evaluated in.
  integer, parameter :: ANALYSIS_PLANE_STRAIN = 1, ANALYSIS_PLANE_STRESS = 2, ANALYSIS_3D = 3

  !> How a law is evaluated: the 2D idealisation (or 3D), and small strain (grad is the
  !! small-strain displacement gradient) or finite strain (F = I + grad, NLGEOM=YES).
  type :: kinematics_t
    integer :: analysis = ANALYSIS_PLANE_STRAIN
    logical :: nlgeom = .false.
  end type kinematics_t

  type, abstract :: law_t
    !> Name of the law as the log and the results file show it.
    character(len=32) :: name = ''
    !> How the law is evaluated (set before `init` by whoever makes the law).
    type(kinematics_t) :: kin
    !> History variables per quadrature point (0 for an elastic law), and which of them holds
    !! the dissipated energy per unit reference volume (0: the law dissipates nothing).
    integer :: nhist = 0
    integer :: hist_dissipation = 0
    !> Which history variable is the equivalent plastic strain (0: none), for the output.
    integer :: hist_peeq = 0
    !> Whether the law's deformations are (nearly) isochoric, so that fully integrated
    !! elements lock: plastic flow, or a bulk modulus of at least 50 shear moduli (nu >= 0.49).
    !! Elements of such a law share their mean dilatation by default (doc/theory.md §2.1).
    logical :: isochoric = .false.
    !> The small-strain tangent at the reference state in 2D Voigt order (xx, yy, xy;
    !! engineering shear): (:, :, 1) plane strain, (:, :, 2) plane stress; set by every law's
    !! `init`. It gives the stiffness of the stable-step estimate at the start, and, for a
    !! linear law (`linear`: the tangent is exact at every state, f_int = K u), the internal
    !! force itself.
    logical :: linear = .false.
    real(dp) :: d2(3, 3, 2) = 0.0_dp
  contains
    !> Sets the components above from the law's properties and `kin`; called once by
    !! `material_make_law` (and by whoever builds a law by hand, after setting `kin`).
    procedure(law_init_i), deferred :: init
    !> The point routine.
    procedure(law_stress_i), deferred :: stress
    !> Dilatational wave speed (for the stable time step).
    procedure(law_wave_i), deferred :: wave_speed
    !> The tangent at the reference state in 2D Voigt order.
    procedure :: tangent_2d => law_tangent_2d
    !> The tangent at the reference state in 3D Voigt order (from d2: isotropic laws).
    procedure :: tangent_3d => law_tangent_3d
    !> c/c_0: the current dilatational wave speed (current density) over that of the
    !! reference state, for the stable step during a finite-strain run. The default
    !! holds for a law whose second Piola-Kirchhoff stress has a constant tangent (St.
    !! Venant-Kirchhoff); a law with another tangent overrides it.
    procedure :: wave_ratio => law_wave_ratio
  end type law_t

  abstract interface
    subroutine law_init_i(this)
      import :: law_t
      class(law_t), intent(inout) :: this
    end subroutine law_init_i

    !> grad(3, 3): displacement gradient du_i/dX_j (F = I + grad with this%kin%nlgeom);
    !! hist_old(nhist): history at the start of the step; hist_new(nhist): at its end;
    !! sig(6): Cauchy stress (xx, yy, zz, xy, yz, zx); w: stored (elastic) energy density per
    !! unit reference volume.
    pure subroutine law_stress_i(this, grad, hist_old, hist_new, sig, w)
      import :: law_t, dp
      class(law_t), intent(in) :: this
      real(dp), intent(in) :: grad(3, 3), hist_old(:)
      real(dp), intent(out) :: hist_new(:), sig(6), w
    end subroutine law_stress_i

    !> rho: density.
    pure real(dp) function law_wave_i(this, rho)
      import :: law_t, dp
      class(law_t), intent(in) :: this
      real(dp), intent(in) :: rho
    end function law_wave_i
  end interface

contains

  !> d(3, 3): the reference tangent of the law's 2D idealisation.
  pure subroutine law_tangent_2d(this, d)
    class(law_t), intent(in) :: this
    real(dp), intent(out) :: d(3, 3)
    d = this%d2(:, :, merge(2, 1, this%kin%analysis == ANALYSIS_PLANE_STRESS))
  end subroutine law_tangent_2d

  !> d(6, 6): the small-strain tangent at the reference state in 3D Voigt order (xx, yy, zz,
  !! xy, yz, zx; engineering shears): the isotropic tangent whose normal entries lambda + 2 mu
  !! and lambda and shear entry mu are those of the plane-strain tangent d2(:, :, 1). The
  !! plane-strain tangent is the 3D one on the in-plane components, so this is exact for every
  !! isotropic law (all of ictus's); an anisotropic law overrides it.
  pure subroutine law_tangent_3d(this, d)
    class(law_t), intent(in) :: this
    real(dp), intent(out) :: d(6, 6)
    integer :: i
    d = 0.0_dp
    d(1:3, 1:3) = this%d2(1, 2, 1)
    do i = 1, 3
      d(i, i) = this%d2(1, 1, 1)
      d(i + 3, i + 3) = this%d2(3, 3, 1)
    end do
  end subroutine law_tangent_3d

  !> c/c_0 of a law whose tangent dS/dE is constant (doc/theory.md §7.1): in the current
  !! state the dilatational modulus is at most M = M_0 lam_max(b)^2/J + |sigma| (M_0 the
  !! reference modulus lambda + 2 mu, b = F F^T, J = det F, |sigma| the Frobenius norm of
  !! the Cauchy stress, its geometric stiffness), and with the density rho_0/J,
  !! c/c_0 = sqrt(J M/M_0). 1 in small strain (the tangent does not change).
  pure real(dp) function law_wave_ratio(this, grad, hist) result(r)
    class(law_t), intent(in) :: this
    real(dp), intent(in) :: grad(3, 3), hist(:)
    real(dp) :: detf, lmax, sig(6), w, hnew(size(hist)), m0
    r = 1.0_dp
    if (.not. this%kin%nlgeom) return
    call stretch_measures(grad, detf, lmax)
    call this%stress(grad, hist, hnew, sig, w)
    m0 = this%d2(1, 1, 1)
    r = sqrt(detf*(m0*lmax**2/detf + stress_norm(sig))/m0)
  end function law_wave_ratio

  !> detf = det F and lmax_b the largest eigenvalue of b = F F^T, F = I + grad.
  pure subroutine stretch_measures(grad, detf, lmax_b)
    real(dp), intent(in) :: grad(3, 3)
    real(dp), intent(out) :: detf, lmax_b
    real(dp) :: f(3, 3), lam(3), v(3, 3)
    integer :: i
    f = grad
    do i = 1, 3
      f(i, i) = f(i, i) + 1.0_dp
    end do
    detf = det3(f)
    call sym_eigen3(matmul(f, transpose(f)), lam, v)
    lmax_b = maxval(lam)
  end subroutine stretch_measures

  !> The Frobenius norm of a symmetric tensor in Voigt order (xx, yy, zz, xy, yz, zx): an
  !! upper bound of its largest principal value.
  pure real(dp) function stress_norm(sig)
    real(dp), intent(in) :: sig(6)
    stress_norm = sqrt(sum(sig(1:3)**2) + 2.0_dp*sum(sig(4:6)**2))
  end function stress_norm

  !> Determinant of a 3 x 3 matrix.
  pure real(dp) function det3(a)
    real(dp), intent(in) :: a(3, 3)
    det3 = a(1, 1)*(a(2, 2)*a(3, 3) - a(2, 3)*a(3, 2)) - a(1, 2)*(a(2, 1)*a(3, 3) - &
        a(2, 3)*a(3, 1)) + a(1, 3)*(a(2, 1)*a(3, 2) - a(2, 2)*a(3, 1))
  end function det3

  !> The adjugate of a 3 x 3 matrix (the transposed cofactor matrix): adj(a) = det(a) a^-1.
  pure function adjugate3(a) result(b)
    real(dp), intent(in) :: a(3, 3)
    real(dp) :: b(3, 3)
    b(1, 1) = a(2, 2)*a(3, 3) - a(2, 3)*a(3, 2)
    b(1, 2) = a(1, 3)*a(3, 2) - a(1, 2)*a(3, 3)
    b(1, 3) = a(1, 2)*a(2, 3) - a(1, 3)*a(2, 2)
    b(2, 1) = a(2, 3)*a(3, 1) - a(2, 1)*a(3, 3)
    b(2, 2) = a(1, 1)*a(3, 3) - a(1, 3)*a(3, 1)
    b(2, 3) = a(1, 3)*a(2, 1) - a(1, 1)*a(2, 3)
    b(3, 1) = a(2, 1)*a(3, 2) - a(2, 2)*a(3, 1)
    b(3, 2) = a(1, 2)*a(3, 1) - a(1, 1)*a(3, 2)
    b(3, 3) = a(1, 1)*a(2, 2) - a(1, 2)*a(2, 1)
  end function adjugate3

  !> The symmetric 3 x 3 tensor a in Voigt order (xx, yy, zz, xy, yz, zx), no factor 2.
  pure function voigt_of(a) result(v)
    real(dp), intent(in) :: a(3, 3)
    real(dp) :: v(6)
    v = [a(1, 1), a(2, 2), a(3, 3), a(1, 2), a(2, 3), a(3, 1)]
  end function voigt_of

  !> The symmetric 3 x 3 tensor of Voigt components v (xx, yy, zz, xy, yz, zx).
  pure function tensor_of(v) result(a)
    real(dp), intent(in) :: v(6)
    real(dp) :: a(3, 3)
    a(1, 1) = v(1)
    a(2, 1) = v(4)
    a(3, 1) = v(6)
    a(1, 2) = v(4)
    a(2, 2) = v(2)
    a(3, 2) = v(5)
    a(1, 3) = v(6)
    a(2, 3) = v(5)
    a(3, 3) = v(3)
  end function tensor_of

  !> Small-strain tensor of a displacement gradient in Voigt order (xx, yy, zz, xy, yz, zx)
  !! with engineering shears: eps = (grad + grad^T)/2, gamma_ij = 2 eps_ij.
  pure function voigt_strain(grad) result(eps)
    real(dp), intent(in) :: grad(3, 3)
    real(dp) :: eps(6)
    eps = [grad(1, 1), grad(2, 2), grad(3, 3), grad(1, 2) + grad(2, 1), &
        grad(2, 3) + grad(3, 2), grad(3, 1) + grad(1, 3)]
  end function voigt_strain
end module ictus_materials_law
