!> Isoparametric solid kernels: patch tests on distorted (and, for Q8/Q9, curved) 2x2 meshes
!! (doc/reference.md §5), rigid-body modes, consistent-mass totals, inverted elements.
program test_solid2d
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, elem_shape_t
  use ictus_elements_library, only: etype_name, etype_nen
  use ictus_elements_lagrange, only: lagrange_shape_data
  use ictus_elements_solid2d, only: solid2d_stiffness, solid2d_mass, solid2d_stress, &
      solid2d_min_detj, solid2d_volume
  use ictus_materials_elastic, only: elastic_dmat
  use ictus_materials_law, only: kinematics_t, ANALYSIS_PLANE_STRAIN
  use ictus_materials_linear_elastic, only: linear_elastic_t
  use ictus_test_check, only: checker_t
  implicit none

  interface
    subroutine dgesv(n, nrhs, a, lda, ipiv, b, ldb, info)
      import :: dp
      integer, intent(in) :: n, nrhs, lda, ldb
      real(dp), intent(inout) :: a(lda, *), b(ldb, *)
      integer, intent(out) :: ipiv(*), info
    end subroutine dgesv
  end interface

  !> The 2x2 patch lives on a 5x5 grid of potential nodes (id = i + 5 j + 1, i, j = 0..4).
  integer, parameter :: ngrid = 5, nnode = ngrid*ngrid, ndof = 2*nnode
  type(checker_t) :: t
  real(dp) :: d(3, 3)
  !> The law of d (E = 1000, nu = 0.2, plane strain), for the stress routine.
  type(linear_elastic_t) :: law
  real(dp) :: nohist(0, 9)
  integer :: k
  integer, parameter :: types(3) = [ETYPE_Q4, ETYPE_Q8, ETYPE_Q9]

  call t%start("elements/solid2d")
  call elastic_dmat(1000.0_dp, 0.2_dp, .true., d)
  law = linear_elastic_t(e=1000.0_dp, nu=0.2_dp)
  law%kin = kinematics_t(ANALYSIS_PLANE_STRAIN, .false.)
  call law%init()
  do k = 1, 3
    call case_patch(t, types(k), d)
    call case_element_mass(t, types(k))
    call case_inverted(t, types(k), d)
  end do
  call t%finish()

contains

  !> Index in the 6-component stress of the 2D Voigt component i (xx, yy, xy).
  pure integer function voigt2(i)
    integer, intent(in) :: i
    voigt2 = merge(4, i, i == 3)
  end function voigt2

  !> Node coordinates of the patch: a smooth nonlinear map of [0, 2]^2 (so quadratic element
  !! sides are curved) plus off-centre moves of the interior nodes.
  subroutine patch_coordinates(x)
    real(dp), intent(out) :: x(2, nnode)
    integer :: i, j, id
    real(dp) :: s, r
    do j = 0, ngrid - 1
      do i = 0, ngrid - 1
        id = i + ngrid*j + 1
        s = 0.5_dp*real(i, dp)
        r = 0.5_dp*real(j, dp)
        x(1, id) = s + 0.06_dp*r*r - 0.04_dp*s*r
        x(2, id) = r + 0.08_dp*s*s - 0.03_dp*s*r
      end do
    end do
    ! interior corner node off-centre
    x(:, node(2, 2)) = x(:, node(2, 2)) + [0.13_dp, -0.09_dp]
    ! interior midside nodes off their chords
    x(:, node(2, 1)) = x(:, node(2, 1)) + [0.04_dp, 0.03_dp]
    x(:, node(1, 2)) = x(:, node(1, 2)) + [-0.03_dp, 0.05_dp]
    x(:, node(3, 2)) = x(:, node(3, 2)) + [0.05_dp, -0.04_dp]
    x(:, node(2, 3)) = x(:, node(2, 3)) + [-0.02_dp, -0.05_dp]
    ! element centres (used by Q9 only)
    x(:, node(1, 1)) = x(:, node(1, 1)) + [0.03_dp, 0.02_dp]
    x(:, node(3, 1)) = x(:, node(3, 1)) + [-0.04_dp, 0.03_dp]
    x(:, node(1, 3)) = x(:, node(1, 3)) + [0.02_dp, -0.03_dp]
    x(:, node(3, 3)) = x(:, node(3, 3)) + [-0.03_dp, -0.02_dp]
  end subroutine patch_coordinates

  pure integer function node(i, j)
    integer, intent(in) :: i, j
    node = i + ngrid*j + 1
  end function node

  !> Connectivity of element (ex, ey), ex, ey = 0..1, in deck order.
  subroutine connectivity(ex, ey, ix)
    integer, intent(in) :: ex, ey
    integer, intent(out) :: ix(9)
    integer :: i0, j0
    i0 = 2*ex
    j0 = 2*ey
    ix = [node(i0, j0), node(i0 + 2, j0), node(i0 + 2, j0 + 2), node(i0, j0 + 2), &
        node(i0 + 1, j0), node(i0 + 2, j0 + 1), node(i0 + 1, j0 + 2), node(i0, j0 + 1), &
        node(i0 + 1, j0 + 1)]
  end subroutine connectivity

  !> Assembles the global K of the 2x2 patch; used(A) marks nodes that belong to an element.
  subroutine assemble(et, shp, x, d, kg, used)
    integer, intent(in) :: et
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: x(2, nnode), d(3, 3)
    real(dp), intent(out) :: kg(ndof, ndof)
    logical, intent(out) :: used(nnode)
    real(dp) :: xl(2, 9)
    real(dp), allocatable :: ke(:,:)
    integer :: ix(9), nen, ex, ey, a, b, ierr, ga, gb
    nen = etype_nen(et)
    allocate(ke(2*nen, 2*nen))
    kg = 0.0_dp
    used = .false.
    do ey = 0, 1
      do ex = 0, 1
        call connectivity(ex, ey, ix)
        xl(:, 1:nen) = x(:, ix(1:nen))
        call solid2d_stiffness(nen, shp, xl(:, 1:nen), d, 0.5_dp, ke, ierr)
        call t%equal_int(ierr, 0, etype_name(et)//' patch element valid')
        do b = 1, 2*nen
          gb = 2*(ix((b + 1)/2) - 1) + 2 - mod(b, 2)
          do a = 1, 2*nen
            ga = 2*(ix((a + 1)/2) - 1) + 2 - mod(a, 2)
            kg(ga, gb) = kg(ga, gb) + ke(a, b)
          end do
        end do
        used(ix(1:nen)) = .true.
      end do
    end do
  end subroutine assemble

  subroutine case_patch(t, et, d)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    real(dp), intent(in) :: d(3, 3)
    real(dp), parameter :: a0(2) = [0.3_dp, -0.2_dp]
    real(dp), parameter :: bm(2, 2) = reshape([0.02_dp, 0.007_dp, -0.013_dp, 0.031_dp], [2, 2])
    type(elem_shape_t) :: shp
    real(dp) :: x(2, nnode), kg(ndof, ndof), u(ndof), uex(ndof), f(ndof), eps(3), sig_ex(3)
    real(dp), allocatable :: kff(:,:), rhs(:,:), sig(:,:)
    real(dp) :: xl(2, 9), ul(2, 9), knorm, unorm, detj_min
    logical :: used(nnode), bnd(nnode)
    integer, allocatable :: free(:), ipiv(:)
    integer :: nen, a, i, j, nf, info, ex, ey, ix(9), ierr, g, igp
    nen = etype_nen(et)
    call lagrange_shape_data(et, merge(2, 3, et == ETYPE_Q4), shp)
    call patch_coordinates(x)
    call assemble(et, shp, x, d, kg, used)
    ! boundary: grid lines i or j = 0 or 4
    do j = 0, ngrid - 1
      do i = 0, ngrid - 1
        bnd(node(i, j)) = i == 0 .or. j == 0 .or. i == ngrid - 1 .or. j == ngrid - 1
      end do
    end do
    ! exact linear field u = a0 + B x on every node
    do a = 1, nnode
      uex(2*a - 1:2*a) = a0 + matmul(bm, x(:, a))
    end do
    ! free dofs: interior nodes that belong to the mesh
    nf = 0
    allocate(free(ndof))
    do a = 1, nnode
      if (used(a) .and. .not. bnd(a)) then
        free(nf + 1:nf + 2) = [2*a - 1, 2*a]
        nf = nf + 2
      end if
    end do
    free = free(1:nf)
    call t%equal_int(nf, merge(2, merge(10, 18, et == ETYPE_Q8), et == ETYPE_Q4), &
        etype_name(et)//' patch interior dofs')
    u = uex
    u(free) = 0.0_dp
    allocate(kff(nf, nf), rhs(nf, 1), ipiv(nf))
    kff = kg(free, free)
    rhs(:, 1) = -matmul(kg(free, :), u)
    call dgesv(nf, 1, kff, nf, ipiv, rhs, nf, info)
    call t%equal_int(info, 0, etype_name(et)//' patch dgesv')
    u(free) = rhs(:, 1)
    unorm = maxval(abs(uex))
    do i = 1, nf
      call t%close_abs(u(free(i)), uex(free(i)), 1.0e-10_dp*unorm, &
          etype_name(et)//' patch interior displacement')
    end do
    ! stresses at every Gauss point equal D eps
    eps = [bm(1, 1), bm(2, 2), bm(1, 2) + bm(2, 1)]
    sig_ex = matmul(d, eps)
    allocate(sig(6, shp%ngp))
    do ey = 0, 1
      do ex = 0, 1
        call connectivity(ex, ey, ix)
        xl(:, 1:nen) = x(:, ix(1:nen))
        do a = 1, nen
          ul(:, a) = u(2*ix(a) - 1:2*ix(a))
        end do
        call solid2d_min_detj(nen, shp, xl(:, 1:nen), detj_min, igp)
        call t%true(detj_min > 0.0_dp .and. igp >= 1, etype_name(et)//' patch min det J > 0')
        call solid2d_stress(nen, shp, xl(:, 1:nen), ul(:, 1:nen), law, nohist, sig, ierr)
        call t%equal_int(ierr, 0, etype_name(et)//' patch stress ierr')
        do g = 1, shp%ngp
          do i = 1, 3
            call t%close_abs(sig(voigt2(i), g), sig_ex(i), 1.0e-10_dp*maxval(abs(sig_ex)), &
                etype_name(et)//' patch Gauss-point stress')
          end do
        end do
      end do
    end do
    ! rigid translation and infinitesimal rotation: K u = 0
    knorm = sqrt(sum(kg**2))
    do a = 1, nnode
      u(2*a - 1:2*a) = [0.7_dp, -1.1_dp]
    end do
    call rigid_check(t, kg, u, used, knorm, etype_name(et)//' translation K u = 0')
    do a = 1, nnode
      u(2*a - 1:2*a) = 1.0e-3_dp*[-x(2, a), x(1, a)]
    end do
    call rigid_check(t, kg, u, used, knorm, etype_name(et)//' rotation K u = 0')
    ! the check can fail: a stretch is not a zero-energy mode
    do a = 1, nnode
      u(2*a - 1:2*a) = merge([x(1, a), 0.0_dp], [0.0_dp, 0.0_dp], used(a))
    end do
    f = matmul(kg, u)
    call t%true(sqrt(sum(f**2)) > 1.0e-3_dp*knorm*sqrt(sum(u**2)), &
        etype_name(et)//' stretch K u /= 0')
    ! symmetry
    call t%close_abs(maxval(abs(kg - transpose(kg))), 0.0_dp, 1.0e-13_dp*knorm, &
        etype_name(et)//' K symmetric')
  end subroutine case_patch

  subroutine rigid_check(t, kg, u, used, knorm, label)
    type(checker_t), intent(inout) :: t
    real(dp), intent(in) :: kg(ndof, ndof), knorm
    real(dp), intent(inout) :: u(ndof)
    logical, intent(in) :: used(nnode)
    character(len=*), intent(in) :: label
    real(dp) :: f(ndof)
    integer :: a
    do a = 1, nnode
      if (.not. used(a)) u(2*a - 1:2*a) = 0.0_dp
    end do
    f = matmul(kg, u)
    call t%true(sqrt(sum(f**2)) < 1.0e-10_dp*knorm*sqrt(sum(u**2)), label)
  end subroutine rigid_check

  !> Sum of the consistent mass = rho t area. Straight-sided distorted quadrilateral (area by
  !! the shoelace formula), then (Q8, Q9) side 2-3 bulged outwards: a parabolic arc through the
  !! midside node displaced by delta normal to a chord of length L adds (2/3) L delta.
  subroutine case_element_mass(t, et)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    real(dp), parameter :: rho = 2.5_dp, thick = 0.4_dp, delta = 0.3_dp
    type(elem_shape_t) :: shp
    real(dp) :: xl(2, 9), mass_e, area, vol, chord(2), nrm(2), len23
    real(dp), allocatable :: me(:,:)
    integer :: nen, a, ierr
    nen = etype_nen(et)
    allocate(me(nen, nen))
    call lagrange_shape_data(et, merge(2, 3, et == ETYPE_Q4), shp)
    xl(:, 1) = [0.1_dp, -0.2_dp]
    xl(:, 2) = [2.3_dp, 0.4_dp]
    xl(:, 3) = [1.9_dp, 1.7_dp]
    xl(:, 4) = [-0.4_dp, 1.2_dp]
    do a = 5, 8
      xl(:, a) = 0.5_dp*(xl(:, a - 4) + xl(:, mod(a - 4, 4) + 1))
    end do
    xl(:, 9) = 0.25_dp*sum(xl(:, 1:4), dim=2)
    area = 0.0_dp
    do a = 1, 4
      area = area + 0.5_dp*(xl(1, a)*xl(2, mod(a, 4) + 1) - xl(1, mod(a, 4) + 1)*xl(2, a))
    end do
    call solid2d_mass(nen, shp, xl(:, 1:nen), rho, thick, me, mass_e, ierr)
    call t%equal_int(ierr, 0, etype_name(et)//' mass ierr')
    call t%close(sum(me), rho*thick*area, 1.0e-13_dp, &
        etype_name(et)//' sum me = rho t area')
    call t%close(mass_e, rho*thick*area, 1.0e-13_dp, etype_name(et)//' mass_e = rho t area')
    call t%close_abs(maxval(abs(me - transpose(me))), 0.0_dp, &
        1.0e-15_dp, etype_name(et)//' me symmetric')
    call solid2d_volume(nen, shp, xl(:, 1:nen), thick, vol)
    call t%close(vol, thick*area, 1.0e-13_dp, etype_name(et)//' volume = t area')
    if (et == ETYPE_Q4) return
    chord = xl(:, 3) - xl(:, 2)
    len23 = sqrt(sum(chord**2))
    nrm = [chord(2), -chord(1)]/len23
    xl(:, 6) = xl(:, 6) + delta*nrm
    area = area + 2.0_dp/3.0_dp*len23*delta
    call solid2d_mass(nen, shp, xl(:, 1:nen), rho, thick, me, mass_e, ierr)
    call t%close(sum(me), rho*thick*area, 1.0e-13_dp, &
        etype_name(et)//' curved: sum me = rho t area')
    call solid2d_volume(nen, shp, xl(:, 1:nen), thick, vol)
    call t%close(vol, thick*area, 1.0e-13_dp, etype_name(et)//' curved: volume')
  end subroutine case_element_mass

  !> Clockwise node order: det J < 0 at the first quadrature point, so ierr = 1.
  subroutine case_inverted(t, et, d)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    real(dp), intent(in) :: d(3, 3)
    type(elem_shape_t) :: shp
    real(dp) :: xl(2, 9), mass_e, detj_min, ul(2, 9)
    real(dp), allocatable :: sig(:,:), ke(:,:), me(:,:)
    integer :: nen, ierr, igp
    nen = etype_nen(et)
    allocate(ke(2*nen, 2*nen), me(nen, nen))
    call lagrange_shape_data(et, 3, shp)
    ! the unit square with the corners listed clockwise (1 and 3 kept, 2 and 4 swapped)
    xl(:, 1) = [0.0_dp, 0.0_dp]
    xl(:, 2) = [0.0_dp, 1.0_dp]
    xl(:, 3) = [1.0_dp, 1.0_dp]
    xl(:, 4) = [1.0_dp, 0.0_dp]
    xl(:, 5) = [0.0_dp, 0.5_dp]
    xl(:, 6) = [0.5_dp, 1.0_dp]
    xl(:, 7) = [1.0_dp, 0.5_dp]
    xl(:, 8) = [0.5_dp, 0.0_dp]
    xl(:, 9) = [0.5_dp, 0.5_dp]
    ul = 0.0_dp
    allocate(sig(6, shp%ngp))
    call solid2d_stiffness(nen, shp, xl(:, 1:nen), d, 1.0_dp, ke, ierr)
    call t%equal_int(ierr, 1, etype_name(et)//' inverted: stiffness ierr')
    call solid2d_mass(nen, shp, xl(:, 1:nen), 1.0_dp, 1.0_dp, me, mass_e, ierr)
    call t%equal_int(ierr, 1, etype_name(et)//' inverted: mass ierr')
    call solid2d_stress(nen, shp, xl(:, 1:nen), ul(:, 1:nen), law, nohist, sig, ierr)
    call t%equal_int(ierr, 1, etype_name(et)//' inverted: stress ierr')
    call solid2d_min_detj(nen, shp, xl(:, 1:nen), detj_min, igp)
    call t%close(detj_min, -0.25_dp, 1.0e-14_dp, etype_name(et)//' inverted: det J = -1/4')
    ! a bow-tie (corner 3 pulled across) is valid at some points only: ierr > 1 is allowed
    xl(:, 1) = [0.0_dp, 0.0_dp]
    xl(:, 2) = [1.0_dp, 0.0_dp]
    xl(:, 3) = [0.2_dp, 0.2_dp]
    xl(:, 4) = [0.0_dp, 1.0_dp]
    xl(:, 5) = [0.5_dp, 0.0_dp]
    xl(:, 6) = [0.6_dp, 0.1_dp]
    xl(:, 7) = [0.1_dp, 0.6_dp]
    xl(:, 8) = [0.0_dp, 0.5_dp]
    xl(:, 9) = [0.3_dp, 0.3_dp]
    call solid2d_stiffness(nen, shp, xl(:, 1:nen), d, 1.0_dp, ke, ierr)
    call t%true(ierr > 0, etype_name(et)//' re-entrant corner: ierr > 0')
  end subroutine case_inverted
end program test_solid2d
