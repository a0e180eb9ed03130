!> 3D isoparametric solid: 3 dof per node (x1, y1, z1, x2, ...), the material law at the
!! quadrature points, small strain or finite strain (NLGEOM, total Lagrangian).
!!
!! The routines mirror ictus_elements_solid2d without the thickness: every one takes the
!! shape data of the element (elem_shape_t: N and dN/d(xi, eta, zeta) at the quadrature points,
!! parent weights), so the same kernel serves C3D8, C3D20 and C3D27. Strains in B are
!! (eps_xx, eps_yy, eps_zz, gamma_xy, gamma_yz, gamma_zx) with engineering shears; stress and
!! strain output use the tensor components (xx, yy, zz, xy, yz, zx) of element_out_t.
module ictus_elements_solid3d
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: elem_shape_t
  use ictus_elements_solid_points, only: points_stress, point_mass, lowest_detj
  use ictus_materials_law, only: law_t, det3, adjugate3, tensor_of
  implicit none
  private
  public :: solid3d_stiffness, solid3d_mass, solid3d_stress, solid3d_min_detj, solid3d_volume, &
      solid3d_geometry, solid3d_force, solid3d_rotation

contains

  !> The deformation gradient F = I + grad.
  pure function deformation_gradient(grad) result(f)
    real(dp), intent(in) :: grad(3, 3)
    real(dp) :: f(3, 3)
    integer :: i
    f = grad
    do i = 1, 3
      f(i, i) = f(i, i) + 1.0_dp
    end do
  end function deformation_gradient

  !> Jacobian determinant and Cartesian derivatives dN/dx at quadrature point g.
  !! J(i, j) = d x_j / d xi_i; dnx(3, nen) = J^-1 dN/dxi. dnx is not set when detj <= 0.
  pure subroutine jacobian(nen, shp, xl, g, detj, dnx)
    integer, intent(in) :: nen, g
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(3, nen)
    real(dp), intent(out) :: detj, dnx(3, nen)
    real(dp) :: jac(3, 3)
    jac = matmul(shp%dn(:, :, g), transpose(xl))
    detj = det3(jac)
    if (.not. detj > 0.0_dp) then
      dnx = 0.0_dp
      return
    end if
    ! J^-1 = adj(J) / det J
    dnx = matmul(adjugate3(jac), shp%dn(:, :, g))/detj
  end subroutine jacobian

  !> Strain-displacement matrix b(6, 3*nen) from Cartesian derivatives dnx(3, nen).
  pure subroutine bmatrix(nen, dnx, b)
    integer, intent(in) :: nen
    real(dp), intent(in) :: dnx(3, nen)
    real(dp), intent(out) :: b(6, 3*nen)
    integer :: a, c
    b = 0.0_dp
    do a = 1, nen
      c = 3*(a - 1)
      b(1, c + 1) = dnx(1, a)
      b(2, c + 2) = dnx(2, a)
      b(3, c + 3) = dnx(3, a)
      b(4, c + 1) = dnx(2, a)
      b(4, c + 2) = dnx(1, a)
      b(5, c + 2) = dnx(3, a)
      b(5, c + 3) = dnx(2, a)
      b(6, c + 1) = dnx(3, a)
      b(6, c + 3) = dnx(1, a)
    end do
  end subroutine bmatrix

  !> Element stiffness ke = sum_g B^T D B det J w_g.
  !! nen: nodes; shp: shape data (shp%nen = nen); xl(3, nen): node coordinates; d(6, 6):
  !! constitutive matrix (xx, yy, zz, xy, yz, zx; engineering shears); ke(3*nen, 3*nen):
  !! stiffness, dof order x1, y1, z1, ...; ierr: 0, or the first quadrature point with
  !! det J <= 0 (ke is then incomplete).
  pure subroutine solid3d_stiffness(nen, shp, xl, d, ke, ierr)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(3, nen), d(6, 6)
    real(dp), intent(out) :: ke(3*nen, 3*nen)
    integer, intent(out) :: ierr
    real(dp) :: dnx(3, nen), b(6, 3*nen), db(6, 3*nen), detj
    integer :: g
    ke = 0.0_dp
    ierr = 0
    do g = 1, shp%ngp
      call jacobian(nen, shp, xl, g, detj, dnx)
      if (.not. detj > 0.0_dp) then
        ierr = g
        return
      end if
      call bmatrix(nen, dnx, b)
      db = matmul(d, b)*(detj*shp%w(g))
      ke = ke + matmul(transpose(b), db)
    end do
  end subroutine solid3d_stiffness

  !> Geometry of an element at its quadrature points, for the internal force of every later
  !! step: Cartesian derivatives dnx(3, nen, ngp) = J^-1 dN/dxi and volume weights
  !! dvol(ngp) = det J w_g. nen; shp; xl(3, nen); ierr: 0, or the first point with det J <= 0
  !! (dnx and dvol are then incomplete).
  pure subroutine solid3d_geometry(nen, shp, xl, dnx, dvol, ierr)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(3, nen)
    real(dp), intent(out) :: dnx(3, nen, shp%ngp), dvol(shp%ngp)
    integer, intent(out) :: ierr
    real(dp) :: detj
    integer :: g
    ierr = 0
    dvol = 0.0_dp
    do g = 1, shp%ngp
      call jacobian(nen, shp, xl, g, detj, dnx(:, :, g))
      if (.not. detj > 0.0_dp) then
        ierr = g
        return
      end if
      dvol(g) = detj*shp%w(g)
    end do
  end subroutine solid3d_geometry

  !> Scalar consistent mass me(A, B) = int rho N_A N_B dV (the same in x, y and z) and the
  !! element mass mass_e = int rho dV, both with the quadrature rule of shp.
  !! nen; shp; xl(3, nen); rho: density; me(nen, nen); mass_e;
  !! ierr: 0, or the first quadrature point with det J <= 0.
  pure subroutine solid3d_mass(nen, shp, xl, rho, me, mass_e, ierr)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(3, nen), rho
    real(dp), intent(out) :: me(nen, nen), mass_e
    integer, intent(out) :: ierr
    real(dp) :: dnx(3, nen, shp%ngp), dvol(shp%ngp)
    integer :: g
    me = 0.0_dp
    mass_e = 0.0_dp
    call solid3d_geometry(nen, shp, xl, dnx, dvol, ierr)
    if (ierr /= 0) return
    do g = 1, shp%ngp
      call point_mass(nen, shp%n(:, g), rho*dvol(g), me, mass_e)
    end do
  end subroutine solid3d_mass

  !> Displacement gradient grad(3, 3) = du_i/dx_j at one point.
  pure function gradient(nen, dnx, ul) result(grad)
    integer, intent(in) :: nen
    real(dp), intent(in) :: dnx(3, nen), ul(3, nen)
    real(dp) :: grad(3, 3)
    grad = matmul(ul, transpose(dnx))
  end function gradient

  !> Internal force of the material law and the stored energy, with the geometry of
  !! `solid3d_geometry`: in small strain f_a = sum_g (sigma . grad N_a) dvol_g; with NLGEOM
  !! (total Lagrangian) f_a = sum_g (P . grad_X N_a) dvol_g with the first Piola-Kirchhoff
  !! stress P = J sigma F^-T = sigma adj(F)^T of F = I + grad_X u. The energy is
  !! sum_g w_g dvol_g (w per unit reference volume).
  !! With `mean` (mean dilatation, doc/theory.md §2.1) the law sees the gradient of
  !! `mean_dilatation` instead, and the force is the variation of that energy (`mean_force`).
  !! nen; ngp; dnx(3, nen, ngp); dvol(ngp); ul(3, nen): displacements; law (with its
  !! kinematics); hist_old(:, ngp), hist_new(:, ngp): history per point (first dimension
  !! nhist, may be 0); f(3, nen); energy; ierr: 0, or the first point with det F <= 0 (an
  !! inverted element; f is then incomplete).
  pure subroutine solid3d_force(nen, ngp, dnx, dvol, ul, law, hist_old, hist_new, f, energy, &
      ierr, mean)
    integer, intent(in) :: nen, ngp
    real(dp), intent(in) :: dnx(3, nen, ngp), dvol(ngp), ul(3, nen)
    class(law_t), intent(in) :: law
    real(dp), intent(in) :: hist_old(:,:)
    real(dp), intent(out) :: hist_new(:,:)
    real(dp), intent(out) :: f(3, nen), energy
    integer, intent(out) :: ierr
    logical, intent(in), optional :: mean
    real(dp) :: sig(6), w, grad(3, 3), p(3, 3), fd(3, 3)
    integer :: g
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
      if (law%kin%nlgeom) then
        fd = deformation_gradient(grad)
        if (.not. det3(fd) > 0.0_dp) then
          ierr = g
          return
        end if
      end if
      call law%stress(grad, hist_old(:, g), hist_new(:, g), sig, w)
      energy = energy + w*dvol(g)
      p = tensor_of(sig)*dvol(g)
      if (law%kin%nlgeom) p = matmul(p, transpose(adjugate3(fd)))
      f = f + matmul(p, dnx(:, :, g))
    end do
  end subroutine solid3d_force

  !> The gradients grad(3, 3, ngp) made to share the element's mean dilatation (B-bar in
  !! small strain, F-bar with NLGEOM; doc/theory.md §2.1): small strain
  !! grad + (theta - tr grad)/3 I with theta = the volume mean of tr grad; finite strain
  !! F-bar = (theta/J)^(1/3) F with J = det F and theta = sum J dvol / sum dvol (current over
  !! reference volume). jac(ngp): J at the points (1 in small strain), theta; ierr: the first
  !! point with J <= 0.
  pure subroutine mean_dilatation(ngp, grad, dvol, nlgeom, jac, theta, ierr)
    integer, intent(in) :: ngp
    real(dp), intent(inout) :: grad(3, 3, ngp)
    real(dp), intent(in) :: dvol(ngp)
    logical, intent(in) :: nlgeom
    real(dp), intent(out) :: jac(ngp), theta
    integer, intent(out) :: ierr
    real(dp) :: c
    integer :: g, i
    ierr = 0
    do g = 1, ngp
      if (nlgeom) then
        jac(g) = det3(deformation_gradient(grad(:, :, g)))
        if (.not. jac(g) > 0.0_dp) then
          ierr = g
          return
        end if
      else
        jac(g) = grad(1, 1, g) + grad(2, 2, g) + grad(3, 3, g)
      end if
    end do
    theta = sum(jac*dvol)/sum(dvol)
    do g = 1, ngp
      if (nlgeom) then
        c = (theta/jac(g))**(1.0_dp/3.0_dp)
        grad(:, :, g) = c*deformation_gradient(grad(:, :, g))
        do i = 1, 3
          grad(i, i, g) = grad(i, i, g) - 1.0_dp
        end do
      else
        c = (theta - jac(g))/3.0_dp
        do i = 1, 3
          grad(i, i, g) = grad(i, i, g) + c
        end do
        jac(g) = 1.0_dp
      end if
    end do
  end subroutine mean_dilatation

  !> The internal force of the mean-dilatation element: the variation of sum_g w(grad-bar_g)
  !! dvol_g (doc/theory.md §2.1). With tau the Kirchhoff stress at grad-bar (J-bar sigma,
  !! J-bar = theta; sigma in small strain), its mean p = tr tau / 3 and
  !! grad_x N = F^-T grad_X N (grad_X N in small strain):
  !!     f_a = sum_g (tau - p I) grad_x N_a dvol_g + (sum_g p_g dvol_g)/(sum_g J_g dvol_g)
  !!           sum_g J_g grad_x N_a dvol_g.
  pure subroutine mean_force(nen, ngp, dnx, dvol, ul, law, hist_old, hist_new, f, energy, ierr)
    integer, intent(in) :: nen, ngp
    real(dp), intent(in) :: dnx(3, nen, ngp), dvol(ngp), ul(3, nen)
    class(law_t), intent(in) :: law
    real(dp), intent(in) :: hist_old(:,:)
    real(dp), intent(out) :: hist_new(:,:)
    real(dp), intent(out) :: f(3, nen), energy
    integer, intent(out) :: ierr
    real(dp) :: grad(3, 3, ngp), gbar(3, 3, ngp), jac(ngp), theta, sig(6), w, tau(3, 3), pm
    real(dp) :: ptot, dx(3, nen, ngp)
    integer :: g, i
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
      ! spatial derivatives grad_x N = F^-T grad_X N = adj(F)^T grad_X N / J (reference ones
      ! in small strain)
      if (law%kin%nlgeom) then
        dx(:, :, g) = matmul(transpose(adjugate3(deformation_gradient(grad(:, :, g)))), &
            dnx(:, :, g))/jac(g)
      else
        dx(:, :, g) = dnx(:, :, g)
      end if
      call law%stress(gbar(:, :, g), hist_old(:, g), hist_new(:, g), sig, w)
      energy = energy + w*dvol(g)
      tau = tensor_of(sig)
      if (law%kin%nlgeom) tau = theta*tau
      pm = (tau(1, 1) + tau(2, 2) + tau(3, 3))/3.0_dp
      ptot = ptot + pm*dvol(g)
      do i = 1, 3
        tau(i, i) = tau(i, i) - pm
      end do
      f = f + dvol(g)*matmul(tau, dx(:, :, g))
    end do
    ptot = ptot/sum(jac*dvol)
    do g = 1, ngp
      f = f + (ptot*jac(g)*dvol(g))*dx(:, :, g)
    end do
  end subroutine mean_force

  !> The displacement gradient grad(3, 3, ngp) at every quadrature point of shp; ierr: 0, or
  !! the first point with det J <= 0 (grad is then incomplete); dvol (optional): det J times
  !! the weight at the points.
  pure subroutine point_gradients(nen, shp, xl, ul, grad, ierr, dvol)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(3, nen), ul(3, nen)
    real(dp), intent(out) :: grad(3, 3, shp%ngp)
    integer, intent(out) :: ierr
    real(dp), intent(out), optional :: dvol(shp%ngp)
    real(dp) :: dnx(3, nen, shp%ngp), dv(shp%ngp)
    integer :: g
    grad = 0.0_dp
    call solid3d_geometry(nen, shp, xl, dnx, dv, ierr)
    if (ierr /= 0) return
    do g = 1, shp%ngp
      grad(:, :, g) = gradient(nen, dnx(:, :, g), ul)
    end do
    if (present(dvol)) dvol = dv
  end subroutine point_gradients

  !> Cauchy stress of the material law at the quadrature points of shp.
  !! eps (optional): the strain at the points (small strain, or the logarithmic strain with
  !! NLGEOM; strain_of of ictus_elements_solid_points).
  !! nen; shp; xl(3, nen); ul(3, nen): nodal displacements; law; hist(:, ngp): the history per
  !! point; sig(6, shp%ngp): (xx, yy, zz, xy, yz, zx) per point; ierr: 0, or the first point
  !! with det J <= 0 (or, with `mean` and NLGEOM, det F <= 0).
  pure subroutine solid3d_stress(nen, shp, xl, ul, law, hist, sig, ierr, eps, mean)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(3, nen), ul(3, nen)
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
  end subroutine solid3d_stress

  !> Largest infinitesimal rotation over the quadrature points of shp: the length of the axial
  !! vector of (grad - grad^T)/2 (the small-strain guard, as solid2d_rotation in the plane).
  !! nen; shp; xl(3, nen); ul(3, nen); wmax; ierr: 0, or the first point with det J <= 0.
  pure subroutine solid3d_rotation(nen, shp, xl, ul, wmax, ierr)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(3, nen), ul(3, nen)
    real(dp), intent(out) :: wmax
    integer, intent(out) :: ierr
    real(dp) :: grad(3, 3, shp%ngp), w(3)
    integer :: g
    wmax = 0.0_dp
    call point_gradients(nen, shp, xl, ul, grad, ierr)
    if (ierr /= 0) return
    do g = 1, shp%ngp
      w = 0.5_dp*[grad(3, 2, g) - grad(2, 3, g), grad(1, 3, g) - grad(3, 1, g), &
          grad(2, 1, g) - grad(1, 2, g)]
      wmax = max(wmax, sqrt(sum(w**2)))
    end do
  end subroutine solid3d_rotation

  !> Smallest Jacobian determinant over the quadrature points and where it occurs.
  !! nen; shp; xl(3, nen); detj_min: the minimum det J; igp: its quadrature point (a NaN or
  !! infinite det J, of coordinates too large to cube, is returned as it is, with its point).
  pure subroutine solid3d_min_detj(nen, shp, xl, detj_min, igp)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(3, nen)
    real(dp), intent(out) :: detj_min
    integer, intent(out) :: igp
    real(dp) :: detj(shp%ngp)
    integer :: g
    do g = 1, shp%ngp
      detj(g) = det3(matmul(shp%dn(:, :, g), transpose(xl)))
    end do
    call lowest_detj(shp%ngp, detj, detj_min, igp)
  end subroutine solid3d_min_detj

  !> Element volume sum_g det J w_g (signed: an inverted element gives a negative
  !! contribution). nen; shp; xl(3, nen); vol.
  pure subroutine solid3d_volume(nen, shp, xl, vol)
    integer, intent(in) :: nen
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(3, nen)
    real(dp), intent(out) :: vol
    integer :: g
    vol = 0.0_dp
    do g = 1, shp%ngp
      vol = vol + det3(matmul(shp%dn(:, :, g), transpose(xl)))*shp%w(g)
    end do
  end subroutine solid3d_volume
end module ictus_elements_solid3d
