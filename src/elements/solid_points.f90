!> What the 2D and 3D solid kernels (ictus_elements_solid2d, ictus_elements_solid3d) share at
!! the quadrature points, where nothing depends on the dimension: the law's stress and the
!! strain at given displacement gradients (3 x 3 in every dimension), a point's share of the
!! scalar consistent mass, and the smallest Jacobian determinant.
module ictus_elements_solid_points
  use ictus_core_kinds, only: dp
  use ictus_materials_law, only: law_t, voigt_of
  use ictus_materials_eigen, only: sym_eigen3
  implicit none
  private
  public :: points_stress, point_mass, lowest_detj, strain_of, mean_dilatation_i

  abstract interface
    !> A kernel's mean dilatation: makes the gradients grad(3, 3, ngp) share the element's
    !! mean dilatation, with the volume weights dvol(ngp); jac(ngp), theta; ierr: 0, or the
    !! first point with J <= 0.
    pure subroutine mean_dilatation_i(ngp, grad, dvol, nlgeom, jac, theta, ierr)
      import :: dp
      integer, intent(in) :: ngp
      real(dp), intent(inout) :: grad(3, 3, ngp)
      real(dp), intent(in) :: dvol(ngp)
      logical, intent(in) :: nlgeom
      real(dp), intent(out) :: jac(ngp), theta
      integer, intent(out) :: ierr
    end subroutine mean_dilatation_i
  end interface

contains

  !> Cauchy stress sig(6, ngp) (xx, yy, zz, xy, yz, zx) of the law at the displacement
  !! gradients grad(3, 3, ngp), with the history hist(:, ngp); eps (optional): the strain
  !! (strain_of). With `mean`, the gradients first share the element's mean dilatation by the
  !! kernel's mean_dil (volume weights dvol(ngp)); ierr: 0, or its first point with J <= 0.
  pure subroutine points_stress(ngp, grad, dvol, law, hist, sig, ierr, mean_dil, eps, mean)
    integer, intent(in) :: ngp
    real(dp), intent(inout) :: grad(3, 3, ngp)
    real(dp), intent(in) :: dvol(ngp)
    class(law_t), intent(in) :: law
    real(dp), intent(in) :: hist(:,:)
    real(dp), intent(inout) :: sig(6, ngp)
    integer, intent(out) :: ierr
    procedure(mean_dilatation_i) :: mean_dil
    real(dp), intent(out), optional :: eps(6, ngp)
    logical, intent(in), optional :: mean
    real(dp) :: w, hist_new(size(hist, 1)), jac(ngp), theta
    integer :: g
    ierr = 0
    if (present(mean)) then
      if (mean) call mean_dil(ngp, grad, dvol, law%kin%nlgeom, jac, theta, ierr)
      if (ierr /= 0) return
    end if
    do g = 1, ngp
      call law%stress(grad(:, :, g), hist(:, g), hist_new, sig(:, g), w)
      if (present(eps)) eps(:, g) = strain_of(grad(:, :, g), law%kin%nlgeom)
    end do
  end subroutine points_stress

  !> Adds one quadrature point to the scalar consistent mass: me(A, B) += f N_A N_B and
  !! mass_e += f, with f = rho dV of the point and n(nen) the shape functions there.
  pure subroutine point_mass(nen, n, f, me, mass_e)
    integer, intent(in) :: nen
    real(dp), intent(in) :: n(nen), f
    real(dp), intent(inout) :: me(nen, nen), mass_e
    integer :: a
    mass_e = mass_e + f
    do a = 1, nen
      me(:, a) = me(:, a) + f*n(a)*n(:)
    end do
  end subroutine point_mass

  !> The smallest of the Jacobian determinants detj(ngp) and its point igp; a NaN or infinite
  !! one (coordinates too large to multiply) is returned as it is, with its point.
  pure subroutine lowest_detj(ngp, detj, detj_min, igp)
    integer, intent(in) :: ngp
    real(dp), intent(in) :: detj(ngp)
    real(dp), intent(out) :: detj_min
    integer, intent(out) :: igp
    integer :: g
    detj_min = huge(1.0_dp)
    igp = 0
    do g = 1, ngp
      if (.not. abs(detj(g)) <= huge(1.0_dp)) then
        detj_min = detj(g)
        igp = g
        return
      end if
      if (detj(g) < detj_min) then
        detj_min = detj(g)
        igp = g
      end if
    end do
  end subroutine lowest_detj

  !> The strain tensor (xx, yy, zz, xy, yz, zx; tensor shears) of a displacement gradient:
  !! (grad + grad^T)/2 in small strain, the logarithmic strain ln V = ln(F F^T)/2 with NLGEOM.
  pure function strain_of(grad, nlgeom) result(eps)
    real(dp), intent(in) :: grad(3, 3)
    logical, intent(in) :: nlgeom
    real(dp) :: eps(6)
    real(dp) :: f(3, 3), b(3, 3), lam(3), v(3, 3), e(3, 3)
    integer :: i
    if (.not. nlgeom) then
      eps = voigt_of(0.5_dp*(grad + transpose(grad)))
      return
    end if
    f = grad
    do i = 1, 3
      f(i, i) = f(i, i) + 1.0_dp
    end do
    b = matmul(f, transpose(f))
    call sym_eigen3(b, lam, v)
    e = 0.0_dp
    do i = 1, 3
      e = e + 0.5_dp*log(lam(i))*spread(v(:, i), 2, 3)*spread(v(:, i), 1, 3)
    end do
    eps = voigt_of(e)
  end function strain_of
end module ictus_elements_solid_points
