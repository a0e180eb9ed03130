!> The material-law interface: what the element routines ask of a constitutive law at one
!! quadrature point.
!!
!! A law is a type that extends `law_t`. Its point routine `stress` is pure: the displacement
!! gradient and the history variables at the start of the step go in; the Cauchy stress, the
!! history at the end of the step and the strain-energy density come out. The element keeps
!! no state of its own, so a law with history stores it in the state of the run (and so in
!! checkpoints) through `nhist`. `wave_speed` gives the dilatational wave speed that bounds
!! the stable time step, and `tangent_2d` the small-strain tangent at the reference state; a
!! `linear` law's tangent is exact everywhere, so its internal force may be the assembled
!! product K u (doc/theory.md).
!!
!! Tensors are 3 x 3 in every dimension: a 2D analysis has zero out-of-plane gradients, and the
!! stress comes back in Voigt order (xx, yy, zz, xy, yz, zx).
module ictus_materials_law
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: law_t, ANALYSIS_PLANE_STRAIN, ANALYSIS_PLANE_STRESS, ANALYSIS_3D, voigt_strain

  !> The kinematic idealisation a law is evaluated in.
  integer, parameter :: ANALYSIS_PLANE_STRAIN = 1, ANALYSIS_PLANE_STRESS = 2, ANALYSIS_3D = 3

  type, abstract :: law_t
    !> Name of the law as the log and the results file show it.
    character(len=32) :: name = ''
    !> History variables per quadrature point (0 for an elastic law).
    integer :: nhist = 0
    !> The small-strain tangent at the reference state in 2D Voigt order (xx, yy, xy;
    !! engineering shear): (:, :, 1) plane strain, (:, :, 2) plane stress; set by every law's
    !! `init`. It gives the stiffness of the stable-step estimate at the start, and, for a
    !! linear law (`linear`: the tangent is exact at every state, f_int = K u), the internal
    !! force itself.
    logical :: linear = .false.
    real(dp) :: d2(3, 3, 2) = 0.0_dp
  contains
    !> Sets the components above from the law's properties; called once by
    !! `material_make_law` (and by whoever builds a law by hand).
    procedure(law_init_i), deferred :: init
    !> The point routine.
    procedure(law_stress_i), deferred :: stress
    !> Dilatational wave speed (for the stable time step).
    procedure(law_wave_i), deferred :: wave_speed
    !> The tangent at the reference state in 2D Voigt order.
    procedure :: tangent_2d => law_tangent_2d
  end type law_t

  abstract interface
    subroutine law_init_i(this)
      import :: law_t
      class(law_t), intent(inout) :: this
    end subroutine law_init_i

    !> analysis: ANALYSIS_*; grad(3, 3): displacement gradient du_i/dX_j; hist_old(nhist):
    !! history at the start of the step; hist_new(nhist): at its end; sig(6): Cauchy stress
    !! (xx, yy, zz, xy, yz, zx); w: strain-energy density per unit reference volume.
    pure subroutine law_stress_i(this, analysis, grad, hist_old, hist_new, sig, w)
      import :: law_t, dp
      class(law_t), intent(in) :: this
      integer, intent(in) :: analysis
      real(dp), intent(in) :: grad(3, 3), hist_old(:)
      real(dp), intent(out) :: hist_new(:), sig(6), w
    end subroutine law_stress_i

    !> rho: density; analysis: ANALYSIS_*.
    pure real(dp) function law_wave_i(this, rho, analysis)
      import :: law_t, dp
      class(law_t), intent(in) :: this
      real(dp), intent(in) :: rho
      integer, intent(in) :: analysis
    end function law_wave_i
  end interface

contains

  !> d(3, 3): the reference tangent of the 2D idealisation `analysis`.
  pure subroutine law_tangent_2d(this, analysis, d)
    class(law_t), intent(in) :: this
    integer, intent(in) :: analysis
    real(dp), intent(out) :: d(3, 3)
    d = this%d2(:, :, merge(2, 1, analysis == ANALYSIS_PLANE_STRESS))
  end subroutine law_tangent_2d

  !> Small-strain tensor of a displacement gradient in Voigt order (xx, yy, zz, xy, yz, zx)
  !! with engineering shears: eps = (grad + grad^T)/2, gamma_ij = 2 eps_ij.
  pure function voigt_strain(grad) result(eps)
    real(dp), intent(in) :: grad(3, 3)
    real(dp) :: eps(6)
    eps = [grad(1, 1), grad(2, 2), grad(3, 3), grad(1, 2) + grad(2, 1), &
        grad(2, 3) + grad(3, 2), grad(3, 1) + grad(1, 3)]
  end function voigt_strain
end module ictus_materials_law
