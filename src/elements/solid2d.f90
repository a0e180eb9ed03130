!> 2D isoparametric solid: small-strain linear elasticity, 2 dof per node (x1, y1, x2, y2, ...).
!!
!! Every routine takes the shape data of the element (elem_shape_t: N and dN/d(xi, eta) at the
!! quadrature points, parent weights), so the same kernels serve Q4/Q8/Q9 and Bezier-extracted
!! NURBS spans. Strains are (eps_xx, eps_yy, gamma_xy) with engineering shear.
module ictus_elements_solid2d
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: elem_shape_t
  use ictus_materials_law, only: law_t
  use ictus_elements_solid_points, only: points_stress, point_mass, lowest_detj
  implicit none
  private
  public :: solid2d_stiffness, solid2d_mass, solid2d_stress, solid2d_min_detj, solid2d_volume, &
      solid2d_geometry, solid2d_force, solid2d_rotation

contains

  !> Jacobian determinant and Cartesian derivatives dN/dx at quadrature point g.
  !! J(i, j) = d x_j / d xi_i; dnx(2, nen) = J^{-1} dN/dxi. dnx is not set when detj <= 0.
  pure subroutine jacobian(nen, shp, xl, g, detj, dnx)
    integer, intent(in) :: nen, g
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(2, nen)
    real(dp), intent(out) :: detj, dnx(2, nen)
    real(dp) :: jac(2, 2), jinv(2, 2)
    jac = matmul(shp%dn(:, :, g), transpose(xl))
    detj = jac(1, 1)*jac(2, 2) - jac(1, 2)*jac(2, 1)
    if (detj <= 0.0_dp) then
      dnx = 0.0_dp
      return
    end if
    jinv(1, 1) = jac(2, 2)/detj
    jinv(2, 2) = jac(1, 1)/detj
    jinv(1, 2) = -jac(1, 2)/detj
    jinv(2, 1) = -jac(2, 1)/detj
    dnx = matmul(jinv, shp%dn(:, :, g))
  end subroutine jacobian

  !> Strain-displacement matrix b(3, 2*nen) from Cartesian derivatives dnx(2, nen).
  pure subroutine bmatrix(nen, dnx, b)
    integer, intent(in) :: nen
    real(dp), intent(in) :: dnx(2, nen)
    real(dp), intent(out) :: b(3, 2*nen)
    integer :: a
    b = 0.0_dp
    do a = 1, nen
      b(1, 2*a - 1) = dnx(1, a)
      b(2, 2*a) = dnx(2, a)
      b(3, 2*a - 1) = dnx(2, a)
      b(3, 2*a) = dnx(1, a)
    end do
  end subroutine bmatrix

  !> Element stiffness ke = sum_g B^T D B det J w_g thick.
  !! nen: nodes; shp: shape data (shp%nen = nen); xl(2, nen): node coordinates; d(3, 3):
  !! constitutive matrix; thick: thickness; ke(2*nen, 2*nen): stiffness, dof order x1, y1, ...;
  !! ierr: 0, or the first quadrature point with det J <= 0 (ke is then incomplete).
  pure subroutine solid2d_stiffness(nen, shp, xl, d, thick, ke, ierr)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(2, nen), d(3, 3), thick
    real(dp), intent(out) :: ke(2*nen, 2*nen)
    integer, intent(out) :: ierr
    real(dp) :: dnx(2, nen), b(3, 2*nen), db(3, 2*nen), detj
    integer :: g
    ke = 0.0_dp
    ierr = 0
    do g = 1, shp%ngp
      call jacobian(nen, shp, xl, g, detj, dnx)
      if (detj <= 0.0_dp) then
        ierr = g
        return
      end if
      call bmatrix(nen, dnx, b)
      db = matmul(d, b)*(detj*shp%w(g)*thick)
      ke = ke + matmul(transpose(b), db)
    end do
  end subroutine solid2d_stiffness

  !> Scalar consistent mass me(A, B) = int rho N_A N_B thick dA (the same for x and y) and the
  !! element mass mass_e = int rho thick dA, both with the quadrature rule of shp.
  !! nen; shp; xl(2, nen); rho: density; thick: thickness; me(nen, nen); mass_e;
  !! ierr: 0, or the first quadrature point with det J <= 0.
  pure subroutine solid2d_mass(nen, shp, xl, rho, thick, me, mass_e, ierr)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(2, nen), rho, thick
    real(dp), intent(out) :: me(nen, nen), mass_e
    integer, intent(out) :: ierr
    real(dp) :: dnx(2, nen), detj
    integer :: g
    me = 0.0_dp
    mass_e = 0.0_dp
    ierr = 0
    do g = 1, shp%ngp
      call jacobian(nen, shp, xl, g, detj, dnx)
      if (detj <= 0.0_dp) then
        ierr = g
        return
      end if
      call point_mass(nen, shp%n(:, g), rho*thick*detj*shp%w(g), me, mass_e)
    end do
  end subroutine solid2d_mass

  !> Geometry of an element at its quadrature points, for the internal force of every later
  !! step: Cartesian derivatives dnx(2, nen, ngp) = J^-1 dN/dxi and volume weights
  !! dvol(ngp) = det J w_g thick. nen; shp; xl(2, nen); thick; ierr: 0, or the first point with
  !! det J <= 0 (dnx and dvol are then incomplete).
  pure subroutine solid2d_geometry(nen, shp, xl, thick, dnx, dvol, ierr)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(2, nen), thick
    real(dp), intent(out) :: dnx(2, nen, shp%ngp), dvol(shp%ngp)
    integer, intent(out) :: ierr
    real(dp) :: detj
    integer :: g
    ierr = 0
    dvol = 0.0_dp
    do g = 1, shp%ngp
      call jacobian(nen, shp, xl, g, detj, dnx(:, :, g))
      if (detj <= 0.0_dp) then
        ierr = g
        return
      end if
      dvol(g) = detj*shp%w(g)*thick
    end do
  end subroutine solid2d_geometry

  !> Displacement gradient grad(3, 3) (du_i/dx_j, zero out of plane) at one point.
  pure function gradient(nen, dnx, ul) result(grad)
    integer, intent(in) :: nen
    real(dp), intent(in) :: dnx(2, nen), ul(2, nen)
    real(dp) :: grad(3, 3)
    integer :: a
    grad = 0.0_dp
    do a = 1, nen
      grad(1, 1) = grad(1, 1) + ul(1, a)*dnx(1, a)
      grad(1, 2) = grad(1, 2) + ul(1, a)*dnx(2, a)
      grad(2, 1) = grad(2, 1) + ul(2, a)*dnx(1, a)
      grad(2, 2) = grad(2, 2) + ul(2, a)*dnx(2, a)
    end do
  end function gradient

  !> Internal force of the material law and the stored energy, with the geometry of
  !! `solid2d_geometry`: in small strain f_a = sum_g (sigma . grad N_a) dvol_g; with NLGEOM
  !! (total Lagrangian) f_a = sum_g (P . grad_X N_a) dvol_g with the first Piola-Kirchhoff
  !! stress P = J sigma F^-T of the deformation gradient F = I + grad_X u (F_33 = 1 in 2D).
  !! The energy is sum_g w_g dvol_g (per unit reference volume).
  !! With `mean` (mean dilatation, doc/theory.md §2.1) the law sees the gradient of
  !! `mean_dilatation` instead, and the force is the variation of that energy (`mean_force`).
  !! nen; ngp; dnx(2, nen, ngp); dvol(ngp); ul(2, nen): displacements; law (with its
  !! kinematics);
  !! hist_old(:, ngp), hist_new(:, ngp): history per point (first dimension nhist, may be 0);
  !! f(2, nen); energy; ierr: 0, or the first point with det F <= 0 (an inverted element; f is
  !! then incomplete).
  pure subroutine solid2d_force(nen, ngp, dnx, dvol, ul, law, hist_old, hist_new, f, energy, &
      ierr, mean)
    integer, intent(in) :: nen, ngp
    real(dp), intent(in) :: dnx(2, nen, ngp), dvol(ngp), ul(2, nen)
    class(law_t), intent(in) :: law
    real(dp), intent(in) :: hist_old(:,:)
    real(dp), intent(out) :: hist_new(:,:)
    real(dp), intent(out) :: f(2, nen), energy
    integer, intent(out) :: ierr
    logical, intent(in), optional :: mean
    real(dp) :: sig(6), w, grad(3, 3), p(2, 2), detf, finv(2, 2), s2(2, 2)
    integer :: g, a
    if (present(mean)) then
      if (mean) then
        call mean_force(nen, ngp, dnx, dvol, ul, law, hist_old, hist_new, f, energy, ierr)
        return
      end if
    end if
    f = 0.0_dp
    energy = 0.0_dp
    ierr = 0
    do g = 1, ngp
      grad = gradient(nen, dnx(:, :, g), ul)
      call law%stress(grad, hist_old(:, g), hist_new(:, g), sig, w)
      energy = energy + w*dvol(g)
      if (.not. law%kin%nlgeom) then
        sig = sig*dvol(g)
        do a = 1, nen
          f(1, a) = f(1, a) + sig(1)*dnx(1, a, g) + sig(4)*dnx(2, a, g)
          f(2, a) = f(2, a) + sig(4)*dnx(1, a, g) + sig(2)*dnx(2, a, g)
        end do
        cycle
      end if
      ! in-plane F = I + grad and its inverse; P = J sigma F^-T, J = det F (F_33 = 1)
      detf = (1.0_dp + grad(1, 1))*(1.0_dp + grad(2, 2)) - grad(1, 2)*grad(2, 1)
      if (.not. detf > 0.0_dp) then
        ierr = g
        return
      end if
      finv(1, 1) = (1.0_dp + grad(2, 2))/detf
      finv(2, 2) = (1.0_dp + grad(1, 1))/detf
      finv(1, 2) = -grad(1, 2)/detf
      finv(2, 1) = -grad(2, 1)/detf
      s2 = tensor_of2(sig)
      ! P dvol = J sigma F^-T dvol, written out
      p(1, 1) = detf*dvol(g)*(s2(1, 1)*finv(1, 1) + s2(1, 2)*finv(1, 2))
      p(1, 2) = detf*dvol(g)*(s2(1, 1)*finv(2, 1) + s2(1, 2)*finv(2, 2))
      p(2, 1) = detf*dvol(g)*(s2(2, 1)*finv(1, 1) + s2(2, 2)*finv(1, 2))
      p(2, 2) = detf*dvol(g)*(s2(2, 1)*finv(2, 1) + s2(2, 2)*finv(2, 2))
      do a = 1, nen
        f(1, a) = f(1, a) + p(1, 1)*dnx(1, a, g) + p(1, 2)*dnx(2, a, g)
        f(2, a) = f(2, a) + p(2, 1)*dnx(1, a, g) + p(2, 2)*dnx(2, a, g)
      end do
    end do
  end subroutine solid2d_force

  !> The gradients grad(3, 3, ngp) made to share the element's mean dilatation (B-bar in
  !! small strain, F-bar with NLGEOM; doc/theory.md §2.1): small strain
  !! grad + (theta - tr grad)/2 I with theta = the volume mean of tr grad; finite strain
  !! F-bar = (theta/J)^(1/2) F with J = det F and theta = sum J dvol / sum dvol (current over
  !! reference area). In-plane only: the out-of-plane stretch stays 1 in plane strain.
  !! jac(ngp): J at the points (1 in small strain), theta; ierr: the first point with J <= 0.
  pure subroutine mean_dilatation(ngp, grad, dvol, nlgeom, jac, theta, ierr)
    integer, intent(in) :: ngp
    real(dp), intent(inout) :: grad(3, 3, ngp)
    real(dp), intent(in) :: dvol(ngp)
    logical, intent(in) :: nlgeom
    real(dp), intent(out) :: jac(ngp), theta
    integer, intent(out) :: ierr
    real(dp) :: f(2, 2), c
    integer :: g
    ierr = 0
    do g = 1, ngp
      if (nlgeom) then
        jac(g) = (1.0_dp + grad(1, 1, g))*(1.0_dp + grad(2, 2, g)) - grad(1, 2, g)*grad(2, 1, g)
        if (.not. jac(g) > 0.0_dp) then
          ierr = g
          return
        end if
      else
        jac(g) = grad(1, 1, g) + grad(2, 2, g)
      end if
    end do
    theta = sum(jac*dvol)/sum(dvol)
    do g = 1, ngp
      if (nlgeom) then
        c = sqrt(theta/jac(g))
        f = grad(1:2, 1:2, g)
        f(1, 1) = f(1, 1) + 1.0_dp
        f(2, 2) = f(2, 2) + 1.0_dp
        f = c*f
        f(1, 1) = f(1, 1) - 1.0_dp
        f(2, 2) = f(2, 2) - 1.0_dp
        grad(1:2, 1:2, g) = f
      else
        c = 0.5_dp*(theta - jac(g))
        grad(1, 1, g) = grad(1, 1, g) + c
        grad(2, 2, g) = grad(2, 2, g) + c
        jac(g) = 1.0_dp
      end if
    end do
  end subroutine mean_dilatation

  !> The internal force of the mean-dilatation element: the variation of sum_g w(grad-bar_g)
  !! dvol_g (doc/theory.md §2.1). With tau the Kirchhoff stress at grad-bar (J-bar sigma,
  !! J-bar = theta; sigma in small strain), its in-plane mean p = tr tau / 2 and
  !! grad_x N = F^-T grad_X N (grad_X N in small strain):
  !!     f_a = sum_g (tau - p I) grad_x N_a dvol_g + (sum_g p_g dvol_g)/(sum_g J_g dvol_g)
  !!           sum_g J_g grad_x N_a dvol_g.
  pure subroutine mean_force(nen, ngp, dnx, dvol, ul, law, hist_old, hist_new, f, energy, ierr)
    integer, intent(in) :: nen, ngp
    real(dp), intent(in) :: dnx(2, nen, ngp), dvol(ngp), ul(2, nen)
    class(law_t), intent(in) :: law
    real(dp), intent(in) :: hist_old(:,:)
    real(dp), intent(out) :: hist_new(:,:)
    real(dp), intent(out) :: f(2, nen), energy
    integer, intent(out) :: ierr
    real(dp) :: grad(3, 3, ngp), gbar(3, 3, ngp), jac(ngp), theta, sig(6), w, tau(2, 2), pm
    real(dp) :: ptot, dx(2, nen, ngp), finv(2, 2), dj
    integer :: g, a
    f = 0.0_dp
    energy = 0.0_dp
    do g = 1, ngp
      grad(:, :, g) = gradient(nen, dnx(:, :, g), ul)
    end do
    gbar = grad
    call mean_dilatation(ngp, gbar, dvol, law%kin%nlgeom, jac, theta, ierr)
    if (ierr /= 0) return
    ptot = 0.0_dp
    do g = 1, ngp
      ! spatial derivatives grad_x N = F^-T grad_X N (the reference ones in small strain)
      if (law%kin%nlgeom) then
        dj = jac(g)
        finv(1, 1) = (1.0_dp + grad(2, 2, g))/dj
        finv(2, 2) = (1.0_dp + grad(1, 1, g))/dj
        finv(1, 2) = -grad(1, 2, g)/dj
        finv(2, 1) = -grad(2, 1, g)/dj
        dx(:, :, g) = matmul(transpose(finv), dnx(:, :, g))
      else
        dx(:, :, g) = dnx(:, :, g)
      end if
      call law%stress(gbar(:, :, g), hist_old(:, g), hist_new(:, g), sig, w)
      energy = energy + w*dvol(g)
      tau = tensor_of2(sig)
      if (law%kin%nlgeom) tau = theta*tau
      pm = 0.5_dp*(tau(1, 1) + tau(2, 2))
      ptot = ptot + pm*dvol(g)
      tau(1, 1) = tau(1, 1) - pm
      tau(2, 2) = tau(2, 2) - pm
      do a = 1, nen
        f(:, a) = f(:, a) + dvol(g)*matmul(tau, dx(:, a, g))
      end do
    end do
    ptot = ptot/sum(jac*dvol)
    do g = 1, ngp
      do a = 1, nen
        f(:, a) = f(:, a) + ptot*jac(g)*dvol(g)*dx(:, a, g)
      end do
    end do
  end subroutine mean_force

  !> The in-plane part (2, 2) of the symmetric tensor of Voigt components v.
  pure function tensor_of2(v) result(a)
    real(dp), intent(in) :: v(6)
    real(dp) :: a(2, 2)
    a(1, 1) = v(1)
    a(2, 1) = v(4)
    a(1, 2) = v(4)
    a(2, 2) = v(2)
  end function tensor_of2

  !> Cauchy stress of the material law at the quadrature points of shp.
  !! eps (optional): the strain at the points (strain_of of ictus_elements_solid_points).
  !! nen; shp; xl(2, nen); ul(2, nen): nodal displacements; law; hist(:, ngp): the
  !! history per point; sig(6, shp%ngp): (xx, yy, zz, xy, yz, zx) per point; ierr: 0, or the
  !! first point with det J <= 0.
  pure subroutine solid2d_stress(nen, shp, xl, ul, law, hist, sig, ierr, eps, mean)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(2, nen), ul(2, nen)
    class(law_t), intent(in) :: law
    real(dp), intent(in) :: hist(:,:)
    real(dp), intent(out) :: sig(6, shp%ngp)
    integer, intent(out) :: ierr
    real(dp), intent(out), optional :: eps(6, shp%ngp)
    logical, intent(in), optional :: mean
    real(dp) :: grad(3, 3, shp%ngp), dvol(shp%ngp)
    sig = 0.0_dp
    call point_gradients(nen, shp, xl, ul, grad, ierr, dvol)
    if (ierr /= 0) return
    call points_stress(shp%ngp, grad, dvol, law, hist, sig, ierr, mean_dilatation, eps, mean)
  end subroutine solid2d_stress

  !> The displacement gradient grad(3, 3, ngp) at every quadrature point of shp; ierr: 0, or
  !! the first point with det J <= 0 (grad is then incomplete); dvol (optional): det J times
  !! the weight at the points.
  pure subroutine point_gradients(nen, shp, xl, ul, grad, ierr, dvol)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(2, nen), ul(2, nen)
    real(dp), intent(out) :: grad(3, 3, shp%ngp)
    integer, intent(out) :: ierr
    real(dp), intent(out), optional :: dvol(shp%ngp)
    real(dp) :: dnx(2, nen), detj
    integer :: g
    ierr = 0
    grad = 0.0_dp
    do g = 1, shp%ngp
      call jacobian(nen, shp, xl, g, detj, dnx)
      if (detj <= 0.0_dp) then
        ierr = g
        return
      end if
      grad(:, :, g) = gradient(nen, dnx, ul)
      if (present(dvol)) dvol(g) = detj*shp%w(g)
    end do
  end subroutine point_gradients

  !> Largest infinitesimal rotation |du_y/dx - du_x/dy| / 2 over the quadrature points of shp
  !! (what small-strain kinematics mistake for strain when it grows: the small-strain guard).
  !! nen; shp; xl(2, nen); ul(2, nen); wmax; ierr: 0, or the first point with det J <= 0.
  pure subroutine solid2d_rotation(nen, shp, xl, ul, wmax, ierr)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(2, nen), ul(2, nen)
    real(dp), intent(out) :: wmax
    integer, intent(out) :: ierr
    real(dp) :: grad(3, 3, shp%ngp)
    integer :: g
    wmax = 0.0_dp
    call point_gradients(nen, shp, xl, ul, grad, ierr)
    if (ierr /= 0) return
    do g = 1, shp%ngp
      wmax = max(wmax, 0.5_dp*abs(grad(2, 1, g) - grad(1, 2, g)))
    end do
  end subroutine solid2d_rotation

  !> Smallest Jacobian determinant over the quadrature points and where it occurs.
  !! nen; shp; xl(2, nen); detj_min: the minimum det J; igp: its quadrature point.
  pure subroutine solid2d_min_detj(nen, shp, xl, detj_min, igp)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(2, nen)
    real(dp), intent(out) :: detj_min
    integer, intent(out) :: igp
    real(dp) :: dnx(2, nen), detj(shp%ngp)
    integer :: g
    do g = 1, shp%ngp
      call jacobian(nen, shp, xl, g, detj(g), dnx)
    end do
    ! a NaN or infinite det J (coordinates too large to square) is returned as it is
    call lowest_detj(shp%ngp, detj, detj_min, igp)
  end subroutine solid2d_min_detj

  !> Element volume: area times thickness, sum_g det J w_g thick (signed: an inverted element
  !! gives a negative contribution). nen; shp; xl(2, nen); thick; vol.
  pure subroutine solid2d_volume(nen, shp, xl, thick, vol)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(2, nen), thick
    real(dp), intent(out) :: vol
    real(dp) :: jac(2, 2)
    integer :: g
    vol = 0.0_dp
    do g = 1, shp%ngp
      jac = matmul(shp%dn(:, :, g), transpose(xl))
      vol = vol + (jac(1, 1)*jac(2, 2) - jac(1, 2)*jac(2, 1))*shp%w(g)*thick
    end do
  end subroutine solid2d_volume
end module ictus_elements_solid2d
