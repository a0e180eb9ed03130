!> The 3D isoparametric solid kernel (ictus_elements_solid3d) through the element routine, for
!! C3D8, C3D20 (3x3x3 and the C3D20R 2x2x2 rule) and C3D27; expected values from theory only.
!!
!! - Patch test on one distorted element (curved edges for C3D20/C3D27): nodal values of a
!!   linear field u = a + B x give sigma = D eps(B) at every Gauss point (1e-10 relative), and
!!   the internal force (law route) equals K u (stiffness route).
!! - Patch test on a 2x2x2 mesh of distorted elements (a smooth nonlinear map of [0, 2]^3, so
!!   quadratic elements have curved edges, interior nodes moved off-centre): K assembled, the
!!   boundary nodes given the linear field, the interior solved; the interior displacements
!!   equal the linear field and every Gauss point of every element has sigma = D eps(B)
!!   (1e-10); rigid translations and infinitesimal rotations u = w x X give K u = 0 (1e-10 of
!!   |K| |u|); a stretch does not.
!! - Finite strain (NLGEOM, total Lagrangian): a finite rigid rotation R (70 degrees about an
!!   oblique axis) plus a translation gives zero internal force for St. Venant-Kirchhoff and
!!   the neo-Hookean law, with and without the mean dilatation (1e-12 of |K| |X|), and a
!!   homogeneous F gives SVK's sigma = F S F^T / J at every point; the internal force is the
!!   variation of the element energy (central differences) for SVK, neo-Hooke and, in small
!!   strain, B-bar.
!! - Consistent mass: sum = element mass = rho V, with V of the distorted trilinear hexahedron
!!   from the divergence theorem, V = (1/3) sum_faces int x . n dA, each face the bilinear
!!   surface of its four corners (the integrand is biquadratic, so 2x2 Gauss on a face is
!!   exact); the volume routine gives V too.
!! - omega_max of a free unit cube, one C3D8 element, 2x2x2 Gauss, lumped mass m/8 per node:
!!   the dilatational mode u_A = X_A - X_c has the constant strain eps = I, so
!!   f_A = (3 lambda + 2 mu) int grad N_A dV = (3 lambda + 2 mu) (h^2/4) xi_A (the integrand is
!!   linear in each direction: 2x2x2 Gauss is exact), and u_A = (h/2) xi_A; hence
!!   K u = (3 lambda + 2 mu)(h/2) u and omega^2 = (3 lambda + 2 mu)(h/2)/(rho h^3/8)
!!   = 12 K_bulk/(rho h^2) = 4 E/((1 - 2 nu) rho h^2). The other eigenvalues of the element
!!   (from its K built symbolically: exactly at nu = 0, 1/4, 1/3, 2/5, 49/100, and numerically
!!   at 500 values of nu in [0, 0.499]) all lie at or below it (at nu = 0 six tie with it),
!!   so it is omega_max; the test's dsyev confirms it at nu = 0.3: for E = 1000, rho = 1,
!!   h = 1, omega_max = sqrt(10000) = 100; for h = 2.5, 40.
!! - Inverted element (corners 1-4 and 5-8 swapped): det J = -h^3/8 < 0, ierr = 1.
!! - The small-strain guard: an infinitesimal rotation w gives the largest rotation |w|.
program test_solid3d
  use ictus_core_kinds, only: dp, pi
  use ictus_elements_types, only: ETYPE_C3D8, ETYPE_C3D20, ETYPE_C3D27, elem_shape_t, &
      TASK_MASS, TASK_FORCE, TASK_STIFFNESS, TASK_STRESS, TASK_JACOBIAN, TASK_ROTATION
  use ictus_elements_library, only: element_shape_data, element_routine, element_out_t, &
      etype_name, etype_nen
  use ictus_elements_hexahedra, only: hexahedra_node_xi
  use ictus_elements_solid3d, only: solid3d_volume
  use ictus_materials_law, only: kinematics_t, ANALYSIS_3D, voigt_of, det3
  use ictus_materials_material, only: material_t, material_make_law
  use ictus_test_check, only: checker_t
  use ictus_test_elements, only: element_omega_max, solve_dense, cross3, svk_cauchy
  implicit none

  !> The 2x2x2 patch lives on a 5x5x5 grid of potential nodes (id = i + 5 j + 25 k + 1).
  integer, parameter :: ngrid = 5, nnode = ngrid**3, ndof = 3*nnode
  real(dp), parameter :: e_mod = 1000.0_dp, nu = 0.3_dp
  !> A linear field u = a0 + bm x (bm not symmetric: strain and rotation).
  real(dp), parameter :: a0(3) = [0.3_dp, -0.2_dp, 0.1_dp]
  real(dp), parameter :: bm(3, 3) = reshape([0.02_dp, 0.007_dp, -0.011_dp, -0.013_dp, &
      0.031_dp, 0.004_dp, 0.009_dp, -0.006_dp, -0.017_dp], [3, 3])
  type(checker_t) :: t
  type(material_t) :: lin, svk, nh
  integer :: k
  integer, parameter :: types(4) = [ETYPE_C3D8, ETYPE_C3D20, ETYPE_C3D20, ETYPE_C3D27]
  integer, parameter :: rules(4) = [2, 3, 2, 3]
  character(len=6), parameter :: labels(4) = [character(len=6) :: 'C3D8', 'C3D20', &
      'C3D20R', 'C3D27']

  call t%start("elements/solid3d")
  call material_make_law('LINEAR ELASTIC', [e_mod, nu], kinematics_t(ANALYSIS_3D, .false.), &
      lin%law)
  call material_make_law('LINEAR ELASTIC', [e_mod, nu], kinematics_t(ANALYSIS_3D, .true.), &
      svk%law)
  call material_make_law('NEO HOOKE', [25.0_dp, 0.02_dp], kinematics_t(ANALYSIS_3D, .true.), &
      nh%law)
  lin%density = 1.0_dp
  svk%density = 1.0_dp
  nh%density = 1.0_dp
  do k = 1, 4
    call case_element_patch(t, types(k), rules(k), trim(labels(k)))
    call case_patch(t, types(k), rules(k), trim(labels(k)))
    call case_finite_rotation(t, types(k), rules(k), trim(labels(k)))
    call case_variation(t, types(k), rules(k), trim(labels(k)))
  end do
  do k = 1, 3
    call case_mass(t, types(k + merge(1, 0, k == 3)))
    call case_inverted(t, types(k + merge(1, 0, k == 3)))
  end do
  call case_omega_cube(t)
  call case_rotation_guard(t)
  call t%finish()

contains

  !> The isotropic D (6, 6) of e_mod, nu (engineering shears).
  function dmat() result(d)
    real(dp) :: d(6, 6)
    real(dp) :: lam, mu
    integer :: i
    mu = e_mod/(2.0_dp*(1.0_dp + nu))
    lam = e_mod*nu/((1.0_dp + nu)*(1.0_dp - 2.0_dp*nu))
    d = 0.0_dp
    d(1:3, 1:3) = lam
    do i = 1, 3
      d(i, i) = lam + 2.0_dp*mu
      d(i + 3, i + 3) = mu
    end do
  end function dmat

  !> The exact stress (xx, yy, zz, xy, yz, zx) of the linear field: D eps(bm).
  function sigma_exact() result(sig)
    real(dp) :: sig(6)
    real(dp) :: eps(6), d(6, 6)
    eps = [bm(1, 1), bm(2, 2), bm(3, 3), bm(1, 2) + bm(2, 1), bm(2, 3) + bm(3, 2), &
        bm(3, 1) + bm(1, 3)]
    d = dmat()
    sig = matmul(d, eps)
  end function sigma_exact

  !> A distorted element of type et: the corners of a skewed box, midsides off their chords,
  !! face centres and the centre off their places (so C3D20 and C3D27 are curved).
  subroutine distorted(et, xl)
    integer, intent(in) :: et
    real(dp), intent(out) :: xl(:,:)
    real(dp) :: xa(3)
    integer :: a
    do a = 1, etype_nen(et)
      call hexahedra_node_xi(a, xa)
      xl(:, a) = [1.1_dp*xa(1) + 0.15_dp*xa(2) + 0.05_dp*xa(2)*xa(3), &
          0.9_dp*xa(2) - 0.1_dp*xa(3) + 0.07_dp*xa(1)*xa(2), &
          0.8_dp*xa(3) + 0.12_dp*xa(1) - 0.06_dp*xa(1)*xa(3)] + [2.0_dp, -1.0_dp, 0.5_dp]
      if (a > 8) xl(:, a) = xl(:, a) + 0.04_dp*[sin(1.3_dp*a), cos(0.7_dp*a), sin(2.1_dp*a)]
    end do
  end subroutine distorted

  subroutine case_element_patch(t, et, ng, lab)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et, ng
    character(len=*), intent(in) :: lab
    type(elem_shape_t) :: shp
    type(element_out_t) :: out, kout
    real(dp) :: xl(3, 27), ul(3, 27), sig(6), fk(81)
    integer :: nen, a, g
    nen = etype_nen(et)
    call element_shape_data(et, ng, shp)
    call distorted(et, xl)
    do a = 1, nen
      ul(:, a) = a0 + matmul(bm, xl(:, a))
    end do
    call element_routine(TASK_STRESS, et, shp, xl(:, 1:nen), lin, out, ul(:, 1:nen))
    call t%equal_int(out%ierr, 0, lab//' element patch: stress ierr')
    sig = sigma_exact()
    do g = 1, shp%ngp
      call t%close_abs(maxval(abs(out%sig(:, g) - sig)), 0.0_dp, 1.0e-10_dp*maxval(abs(sig)), &
          lab//' element patch: sigma = D eps at the Gauss point')
      call t%close_abs(maxval(abs(out%eps(:, g) - voigt_of(0.5_dp*(bm + transpose(bm))))), &
          0.0_dp, 1.0e-12_dp, lab//' element patch: strain output')
    end do
    call element_routine(TASK_FORCE, et, shp, xl(:, 1:nen), lin, out, ul(:, 1:nen))
    call element_routine(TASK_STIFFNESS, et, shp, xl(:, 1:nen), lin, kout)
    call t%true(size(kout%s, 1) == 3*nen .and. size(out%p, 1) == 3, lab//' 3 dof per node')
    fk(1:3*nen) = matmul(kout%s, reshape(ul(:, 1:nen), [3*nen]))
    call t%close_abs(maxval(abs(reshape(out%p, [3*nen]) - fk(1:3*nen))), 0.0_dp, &
        1.0e-12_dp*maxval(abs(fk(1:3*nen))), lab//' law force = K u')
    call t%close_abs(maxval(abs(kout%s - transpose(kout%s))), 0.0_dp, &
        1.0e-13_dp*maxval(abs(kout%s)), lab//' K symmetric')
  end subroutine case_element_patch

  !> Node coordinates of the patch: a smooth nonlinear map of [0, 2]^3 plus off-centre moves
  !! of the interior nodes.
  subroutine patch_coordinates(x)
    real(dp), intent(out) :: x(3, nnode)
    integer :: i, j, k
    real(dp) :: s, r, q
    do k = 0, ngrid - 1
      do j = 0, ngrid - 1
        do i = 0, ngrid - 1
          s = 0.5_dp*real(i, dp)
          r = 0.5_dp*real(j, dp)
          q = 0.5_dp*real(k, dp)
          x(:, node(i, j, k)) = [s + 0.06_dp*r*r - 0.04_dp*s*q, r + 0.08_dp*s*s - &
              0.03_dp*q*r, q + 0.05_dp*s*r - 0.04_dp*r*r]
          if (all([i, j, k] > 0 .and. [i, j, k] < ngrid - 1)) x(:, node(i, j, k)) = &
              x(:, node(i, j, k)) + 0.05_dp*[sin(real(i + 2*j + 3*k, dp)), &
              cos(real(3*i + j + k, dp)), sin(real(i + j + 5*k, dp))]
        end do
      end do
    end do
    ! the interior corner node well off-centre
    x(:, node(2, 2, 2)) = x(:, node(2, 2, 2)) + [0.12_dp, -0.09_dp, 0.07_dp]
  end subroutine patch_coordinates

  pure integer function node(i, j, k)
    integer, intent(in) :: i, j, k
    node = i + ngrid*j + ngrid*ngrid*k + 1
  end function node

  !> Connectivity ix(nen) of element (ex, ey, ez), each 0..1: local node a at parent point
  !! xi_a sits on grid point 2 e + 1 + xi_a.
  subroutine connectivity(et, ex, ey, ez, ix)
    integer, intent(in) :: et, ex, ey, ez
    integer, intent(out) :: ix(:)
    real(dp) :: xa(3)
    integer :: a
    do a = 1, etype_nen(et)
      call hexahedra_node_xi(a, xa)
      ix(a) = node(2*ex + 1 + nint(xa(1)), 2*ey + 1 + nint(xa(2)), 2*ez + 1 + nint(xa(3)))
    end do
  end subroutine connectivity

  !> Assembles the global K of the 2x2x2 patch; used(A) marks the nodes of the mesh.
  subroutine assemble(et, shp, x, kg, used)
    integer, intent(in) :: et
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: x(3, nnode)
    real(dp), intent(out) :: kg(ndof, ndof)
    logical, intent(out) :: used(nnode)
    type(element_out_t) :: out
    integer :: ix(27), nen, ex, ey, ez, a, b, dofs(81)
    nen = etype_nen(et)
    kg = 0.0_dp
    used = .false.
    do ez = 0, 1
      do ey = 0, 1
        do ex = 0, 1
          call connectivity(et, ex, ey, ez, ix)
          call element_routine(TASK_STIFFNESS, et, shp, x(:, ix(1:nen)), lin, out)
          call t%equal_int(out%ierr, 0, etype_name(et)//' patch element valid')
          do a = 1, nen
            dofs(3*a - 2:3*a) = 3*(ix(a) - 1) + [1, 2, 3]
          end do
          do b = 1, 3*nen
            do a = 1, 3*nen
              kg(dofs(a), dofs(b)) = kg(dofs(a), dofs(b)) + out%s(a, b)
            end do
          end do
          used(ix(1:nen)) = .true.
        end do
      end do
    end do
  end subroutine assemble

  subroutine case_patch(t, et, ng, lab)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et, ng
    character(len=*), intent(in) :: lab
    type(elem_shape_t) :: shp
    type(element_out_t) :: out
    real(dp), allocatable :: kg(:,:), kff(:,:), rhs(:)
    real(dp) :: x(3, nnode), u(ndof), uex(ndof), sig(6), knorm, w(3), ul(3, 27)
    logical :: used(nnode), bnd(nnode)
    integer, allocatable :: free(:)
    integer :: nen, a, i, j, k, nf, info, ex, ey, ez, ix(27), g
    nen = etype_nen(et)
    allocate(kg(ndof, ndof))
    call element_shape_data(et, ng, shp)
    call patch_coordinates(x)
    call assemble(et, shp, x, kg, used)
    do k = 0, ngrid - 1
      do j = 0, ngrid - 1
        do i = 0, ngrid - 1
          bnd(node(i, j, k)) = any([i, j, k] == 0 .or. [i, j, k] == ngrid - 1)
        end do
      end do
    end do
    do a = 1, nnode
      uex(3*a - 2:3*a) = a0 + matmul(bm, x(:, a))
    end do
    allocate(free(ndof))
    nf = 0
    do a = 1, nnode
      if (used(a) .and. .not. bnd(a)) then
        free(nf + 1:nf + 3) = 3*(a - 1) + [1, 2, 3]
        nf = nf + 3
      end if
    end do
    free = free(1:nf)
    call t%equal_int(nf, 3*merge(1, merge(7, 27, et == ETYPE_C3D20), et == ETYPE_C3D8), &
        lab//' patch interior dofs')
    u = uex
    u(free) = 0.0_dp
    kff = kg(free, free)
    rhs = -matmul(kg(free, :), u)
    call solve_dense(nf, kff, rhs, info)
    call t%equal_int(info, 0, lab//' patch dgesv')
    u(free) = rhs
    call t%close_abs(maxval(abs(u(free) - uex(free))), 0.0_dp, 1.0e-10_dp*maxval(abs(uex)), &
        lab//' patch interior displacements = the linear field')
    sig = sigma_exact()
    do ez = 0, 1
      do ey = 0, 1
        do ex = 0, 1
          call connectivity(et, ex, ey, ez, ix)
          do a = 1, nen
            ul(:, a) = u(3*ix(a) - 2:3*ix(a))
          end do
          call element_routine(TASK_STRESS, et, shp, x(:, ix(1:nen)), lin, out, ul(:, 1:nen))
          do g = 1, shp%ngp
            call t%close_abs(maxval(abs(out%sig(:, g) - sig)), 0.0_dp, &
                1.0e-10_dp*maxval(abs(sig)), lab//' patch: sigma = D eps at every Gauss point')
          end do
        end do
      end do
    end do
    ! rigid translation and infinitesimal rotation: K u = 0; a stretch is not a zero mode
    knorm = sqrt(sum(kg**2))
    w = [0.3_dp, -0.5_dp, 0.4_dp]*1.0e-3_dp
    do a = 1, nnode
      u(3*a - 2:3*a) = merge([0.7_dp, -1.1_dp, 0.4_dp], 0.0_dp, used(a))
    end do
    call t%true(sqrt(sum(matmul(kg, u)**2)) < 1.0e-10_dp*knorm*sqrt(sum(u**2)), &
        lab//' translation K u = 0')
    do a = 1, nnode
      u(3*a - 2:3*a) = merge(cross3(w, x(:, a)), [0.0_dp, 0.0_dp, 0.0_dp], used(a))
    end do
    call t%true(sqrt(sum(matmul(kg, u)**2)) < 1.0e-10_dp*knorm*sqrt(sum(u**2)), &
        lab//' infinitesimal rotation K u = 0')
    do a = 1, nnode
      u(3*a - 2:3*a) = merge([x(1, a), 0.0_dp, 0.0_dp], [0.0_dp, 0.0_dp, 0.0_dp], used(a))
    end do
    call t%true(sqrt(sum(matmul(kg, u)**2)) > 1.0e-3_dp*knorm*sqrt(sum(u**2)), &
        lab//' stretch K u /= 0')
  end subroutine case_patch

  !> The rotation by angle th about the unit axis n (Rodrigues).
  function rotation(n, th) result(r)
    real(dp), intent(in) :: n(3), th
    real(dp) :: r(3, 3)
    real(dp) :: w(3, 3)
    integer :: i
    w = reshape([0.0_dp, n(3), -n(2), -n(3), 0.0_dp, n(1), n(2), -n(1), 0.0_dp], [3, 3])
    r = sin(th)*w + (1.0_dp - cos(th))*matmul(w, w)
    do i = 1, 3
      r(i, i) = r(i, i) + 1.0_dp
    end do
  end function rotation

  !> Finite rigid motion: zero force (SVK, neo-Hooke; with and without F-bar); homogeneous F:
  !! SVK's closed-form Cauchy stress at every point.
  subroutine case_finite_rotation(t, et, ng, lab)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et, ng
    character(len=*), intent(in) :: lab
    type(elem_shape_t) :: shp
    type(element_out_t) :: out, kout
    real(dp) :: xl(3, 27), ul(3, 27), r(3, 3), f(3, 3), sig(6), scale, lam, mu
    integer :: nen, a, g, im
    logical :: mean
    nen = etype_nen(et)
    call element_shape_data(et, ng, shp)
    call distorted(et, xl)
    r = rotation([1.0_dp, 2.0_dp, 2.0_dp]/3.0_dp, 70.0_dp*pi/180.0_dp)
    do a = 1, nen
      ul(:, a) = matmul(r, xl(:, a)) - xl(:, a) + [0.4_dp, -0.3_dp, 0.2_dp]
    end do
    call element_routine(TASK_STIFFNESS, et, shp, xl(:, 1:nen), lin, kout)
    scale = 1.0e-12_dp*maxval(abs(kout%s))*maxval(abs(xl(:, 1:nen)))
    do im = 1, 2
      mean = im == 2
      call element_routine(TASK_FORCE, et, shp, xl(:, 1:nen), svk, out, ul(:, 1:nen), &
          mean=mean)
      call t%close_abs(maxval(abs(out%p)), 0.0_dp, scale, lab//' SVK finite rotation f = 0')
      call element_routine(TASK_FORCE, et, shp, xl(:, 1:nen), nh, out, ul(:, 1:nen), &
          mean=mean)
      call t%close_abs(maxval(abs(out%p)), 0.0_dp, scale, lab//' neo-Hooke finite rotation f = 0')
    end do
    ! homogeneous F: sigma = F S F^T / J, S = lambda tr(E) I + 2 mu E
    f = reshape([1.1_dp, 0.05_dp, -0.08_dp, 0.12_dp, 0.93_dp, 0.04_dp, -0.03_dp, 0.07_dp, &
        1.05_dp], [3, 3])
    do a = 1, nen
      ul(:, a) = matmul(f, xl(:, a)) - xl(:, a)
    end do
    mu = e_mod/(2.0_dp*(1.0_dp + nu))
    lam = e_mod*nu/((1.0_dp + nu)*(1.0_dp - 2.0_dp*nu))
    sig = voigt_of(svk_cauchy(lam, mu, f, det3(f)))
    do im = 1, 2
      call element_routine(TASK_STRESS, et, shp, xl(:, 1:nen), svk, out, ul(:, 1:nen), &
          mean=im == 2)
      do g = 1, shp%ngp
        call t%close_abs(maxval(abs(out%sig(:, g) - sig)), 0.0_dp, &
            1.0e-11_dp*maxval(abs(sig)), lab//' SVK homogeneous F: sigma at every point')
      end do
    end do
  end subroutine case_finite_rotation

  !> f_a = dW/du_a by central differences (step 1e-6) on a non-homogeneous field, for SVK and
  !! neo-Hooke (with and without F-bar) and small-strain B-bar.
  subroutine case_variation(t, et, ng, lab)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et, ng
    character(len=*), intent(in) :: lab
    type(elem_shape_t) :: shp
    real(dp) :: xl(3, 27), ul(3, 27)
    integer :: nen, a
    nen = etype_nen(et)
    call element_shape_data(et, ng, shp)
    call distorted(et, xl)
    do a = 1, nen
      ul(:, a) = 0.05_dp*[sin(xl(2, a) + 0.3_dp*a), cos(xl(3, a) - 0.2_dp*a), &
          sin(xl(1, a)*xl(2, a))]
    end do
    call variation(t, et, shp, xl(:, 1:nen), ul(:, 1:nen), svk, .false., lab//' SVK')
    call variation(t, et, shp, xl(:, 1:nen), ul(:, 1:nen), svk, .true., lab//' SVK F-bar')
    call variation(t, et, shp, xl(:, 1:nen), ul(:, 1:nen), nh, .false., lab//' neo-Hooke')
    call variation(t, et, shp, xl(:, 1:nen), ul(:, 1:nen), nh, .true., &
        lab//' neo-Hooke F-bar')
    call variation(t, et, shp, xl(:, 1:nen), ul(:, 1:nen), lin, .true., lab//' B-bar')
  end subroutine case_variation

  subroutine variation(t, et, shp, xl, ul, mat, mean, lab)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(:,:), ul(:,:)
    type(material_t), intent(in) :: mat
    logical, intent(in) :: mean
    character(len=*), intent(in) :: lab
    real(dp), parameter :: h = 1.0e-6_dp
    type(element_out_t) :: out, op, om
    real(dp) :: up(3, size(ul, 2)), err
    integer :: a, i
    call element_routine(TASK_FORCE, et, shp, xl, mat, out, ul, mean=mean)
    err = 0.0_dp
    do a = 1, size(ul, 2)
      do i = 1, 3
        up = ul
        up(i, a) = ul(i, a) + h
        call element_routine(TASK_FORCE, et, shp, xl, mat, op, up, mean=mean)
        up(i, a) = ul(i, a) - h
        call element_routine(TASK_FORCE, et, shp, xl, mat, om, up, mean=mean)
        err = max(err, abs((op%scalar - om%scalar)/(2.0_dp*h) - out%p(i, a)))
      end do
    end do
    call t%close_abs(err, 0.0_dp, 1.0e-6_dp*maxval(abs(out%p)), lab//': f = dW/du')
  end subroutine variation

  !> V of the trilinear hexahedron of corners xc(3, 8) (Abaqus order) by the divergence theorem.
  function hex_volume(xc) result(v)
    real(dp), intent(in) :: xc(3, 8)
    real(dp) :: v
    integer, parameter :: faces(4, 6) = reshape([1, 4, 3, 2, 5, 6, 7, 8, 1, 2, 6, 5, 2, 3, 7, &
        6, 3, 4, 8, 7, 4, 1, 5, 8], [4, 6])
    real(dp) :: p(3, 4), s, r, n(4), ds(4), dr(4), g(2)
    integer :: f, i, j
    g = [-1.0_dp, 1.0_dp]/sqrt(3.0_dp)
    v = 0.0_dp
    do f = 1, 6
      p = xc(:, faces(:, f))
      do j = 1, 2
        do i = 1, 2
          s = g(i)
          r = g(j)
          n = 0.25_dp*[(1 - s)*(1 - r), (1 + s)*(1 - r), (1 + s)*(1 + r), (1 - s)*(1 + r)]
          ds = 0.25_dp*[-(1 - r), 1 - r, 1 + r, -(1 + r)]
          dr = 0.25_dp*[-(1 - s), -(1 + s), 1 + s, 1 - s]
          v = v + dot_product(matmul(p, n), cross3(matmul(p, ds), matmul(p, dr)))/3.0_dp
        end do
      end do
    end do
  end function hex_volume

  !> Consistent mass of a distorted straight-edged element (midsides, face centres and centre
  !! on the trilinear map of the corners, so all three types have the same trilinear
  !! geometry): sum me = mass_e = rho V, the volume routine V, symmetry.
  subroutine case_mass(t, et)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    type(elem_shape_t) :: shp
    type(element_out_t) :: out
    type(material_t) :: dense
    real(dp) :: xl(3, 27), xa(3), xc(3, 8), n8(8), v, vol
    integer :: nen, a
    nen = etype_nen(et)
    call element_shape_data(et, merge(2, 3, et == ETYPE_C3D8), shp)
    call distorted(ETYPE_C3D8, xc)
    do a = 1, nen
      call hexahedra_node_xi(a, xa)
      n8 = 0.125_dp*[(1 - xa(1))*(1 - xa(2))*(1 - xa(3)), (1 + xa(1))*(1 - xa(2))*(1 - xa(3)), &
          (1 + xa(1))*(1 + xa(2))*(1 - xa(3)), (1 - xa(1))*(1 + xa(2))*(1 - xa(3)), &
          (1 - xa(1))*(1 - xa(2))*(1 + xa(3)), (1 + xa(1))*(1 - xa(2))*(1 + xa(3)), &
          (1 + xa(1))*(1 + xa(2))*(1 + xa(3)), (1 - xa(1))*(1 + xa(2))*(1 + xa(3))]
      xl(:, a) = matmul(xc, n8)
    end do
    v = hex_volume(xc)
    dense%density = 2.5_dp
    call material_make_law('LINEAR ELASTIC', [e_mod, nu], kinematics_t(ANALYSIS_3D, .false.), &
        dense%law)
    call element_routine(TASK_MASS, et, shp, xl(:, 1:nen), dense, out)
    call t%equal_int(out%ierr, 0, etype_name(et)//' mass ierr')
    call t%close(sum(out%s), 2.5_dp*v, 1.0e-13_dp, etype_name(et)//' sum me = rho V')
    call t%close(out%scalar, 2.5_dp*v, 1.0e-13_dp, etype_name(et)//' mass_e = rho V')
    call t%close_abs(maxval(abs(out%s - transpose(out%s))), 0.0_dp, 1.0e-15_dp, &
        etype_name(et)//' me symmetric')
    call solid3d_volume(nen, shp, xl(:, 1:nen), vol)
    call t%close(vol, v, 1.0e-13_dp, etype_name(et)//' volume routine = V')
  end subroutine case_mass

  !> Corners 1-4 and 5-8 swapped on the cube of side 1 (a mirror image): det J = -1/8 at
  !! every point; ierr = 1 for the stiffness, mass and stress; the Jacobian task finds -1/8.
  subroutine case_inverted(t, et)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    type(elem_shape_t) :: shp
    type(element_out_t) :: out
    real(dp) :: xl(3, 27), ul(3, 27), xa(3)
    integer :: nen, a
    nen = etype_nen(et)
    call element_shape_data(et, merge(2, 3, et == ETYPE_C3D8), shp)
    do a = 1, nen
      call hexahedra_node_xi(a, xa)
      xl(:, a) = 0.5_dp*([xa(1), xa(2), -xa(3)] + 1.0_dp)
    end do
    ul = 0.0_dp
    call element_routine(TASK_STIFFNESS, et, shp, xl(:, 1:nen), lin, out)
    call t%equal_int(out%ierr, 1, etype_name(et)//' inverted: stiffness ierr')
    call element_routine(TASK_MASS, et, shp, xl(:, 1:nen), lin, out)
    call t%equal_int(out%ierr, 1, etype_name(et)//' inverted: mass ierr')
    call element_routine(TASK_STRESS, et, shp, xl(:, 1:nen), lin, out, ul(:, 1:nen))
    call t%equal_int(out%ierr, 1, etype_name(et)//' inverted: stress ierr')
    call element_routine(TASK_FORCE, et, shp, xl(:, 1:nen), lin, out, ul(:, 1:nen))
    call t%equal_int(out%ierr, 1, etype_name(et)//' inverted: force ierr')
    call element_routine(TASK_JACOBIAN, et, shp, xl(:, 1:nen), lin, out)
    call t%close(out%scalar, -0.125_dp, 1.0e-14_dp, etype_name(et)//' inverted: det J = -1/8')
  end subroutine case_inverted

  !> omega_max of the free lumped cube (header), with the lumped masses m/8 (row sums).
  subroutine case_omega_cube(t)
    type(checker_t), intent(inout) :: t
    type(elem_shape_t) :: shp
    type(element_out_t) :: kout, mout
    real(dp) :: xl(3, 8), xa(3), h, want, u(24), ml(8, 8), omega
    integer :: i, info, k
    call element_shape_data(ETYPE_C3D8, 2, shp)
    do k = 1, 2
      h = merge(1.0_dp, 2.5_dp, k == 1)
      do i = 1, 8
        call hexahedra_node_xi(i, xa)
        xl(:, i) = 0.5_dp*h*(xa + 1.0_dp) + [0.3_dp, -0.7_dp, 1.1_dp]
      end do
      call element_routine(TASK_STIFFNESS, ETYPE_C3D8, shp, xl, lin, kout)
      call element_routine(TASK_MASS, ETYPE_C3D8, shp, xl, lin, mout)
      ml = 0.0_dp
      do i = 1, 8
        ml(i, i) = sum(mout%s(i, :))
      end do
      call t%close_abs(maxval(abs(sum(ml, dim=2)/mout%scalar - 0.125_dp)), 0.0_dp, 1.0e-15_dp, &
          'C3D8 cube: row-sum m/8 per node')
      call element_omega_max(8, kout%s, ml, .true., omega, info, ndm=3)
      call t%equal_int(info, 0, 'C3D8 cube: omega info')
      want = sqrt(4.0_dp*e_mod/((1.0_dp - 2.0_dp*nu)*lin%density*h*h))
      call t%close(omega, want, 1.0e-12_dp, &
          'C3D8 cube: omega_max = sqrt(4 E/((1 - 2 nu) rho h^2))')
      ! the dilatational mode is its eigenvector: K u = omega^2 M u
      do i = 1, 8
        u(3*i - 2:3*i) = xl(:, i) - sum(xl, dim=2)/8.0_dp
      end do
      call t%close_abs(maxval(abs(matmul(kout%s, u) - want**2*mout%scalar/8.0_dp*u)), &
          0.0_dp, 1.0e-12_dp*want**2*mout%scalar*h, 'C3D8 cube: dilatation K u = omega^2 M u')
    end do
    call t%close(want, 40.0_dp, 1.0e-12_dp, 'C3D8 cube: h = 2.5 gives 40')
  end subroutine case_omega_cube

  !> The largest infinitesimal rotation of u = w x X is |w| at every point.
  subroutine case_rotation_guard(t)
    type(checker_t), intent(inout) :: t
    type(elem_shape_t) :: shp
    type(element_out_t) :: out
    real(dp) :: xl(3, 27), ul(3, 27), w(3)
    integer :: a
    call element_shape_data(ETYPE_C3D20, 3, shp)
    call distorted(ETYPE_C3D20, xl)
    w = [0.002_dp, -0.003_dp, 0.006_dp]
    do a = 1, 20
      ul(:, a) = cross3(w, xl(:, a))
    end do
    call element_routine(TASK_ROTATION, ETYPE_C3D20, shp, xl(:, 1:20), lin, out, ul(:, 1:20))
    call t%close(out%scalar, 0.007_dp, 1.0e-12_dp, 'C3D20 rotation guard = |w|')
  end subroutine case_rotation_guard
end program test_solid3d
