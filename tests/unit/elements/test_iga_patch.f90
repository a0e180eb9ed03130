!> IGA patch tests on a distorted NURBS patch (doc/reference.md §5), assembled here from
!! iga_shape_data, solid2d_stiffness and solid2d_stress and the patch routines.
!!
!! A square patch, refined to 4 x 4 spans (p = 2) or elevated to p = 3 and refined to 3 x 3
!! spans (k-refinement), with every interior control point moved by a deterministic
!! pseudo-random offset and weights between 0.75 and 1.25 on all control points. Since the
!! NURBS basis has sum R_A = 1 and sum R_A x_A = x for any weights, the linear field
!! u = a + B x, imposed on the boundary control points with the interior solved from
!! K_II u_I = -K_IB u_B, must be reproduced at the interior control points with constant
!! stress D eps(B) (1e-10); rigid translation and infinitesimal rotation give K u = 0.
program test_iga_patch
  use ictus_core_kinds, only: dp
  use ictus_geometry_patch, only: patch_t, patch_elevate, patch_refine, patch_elem_ij
  use ictus_elements_types, only: elem_shape_t
  use ictus_elements_iga, only: iga_shape_data
  use ictus_elements_solid2d, only: solid2d_stiffness, solid2d_stress
  use ictus_materials_elastic, only: elastic_dmat
  use ictus_materials_law, only: kinematics_t, ANALYSIS_PLANE_STRAIN, ANALYSIS_PLANE_STRESS
  use ictus_materials_linear_elastic, only: linear_elastic_t
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t

  call t%start("elements/iga_patch")
  ! B-spline weights (all 1): the production rule (p+1 Gauss points) is exact
  call case_patch(t, 2, 4, .true., 0.0_dp, 3)
  call case_patch(t, 3, 3, .true., 0.0_dp, 4)
  call case_patch(t, 2, 4, .false., 0.0_dp, 3)
  ! weights 1 +- 25 %: the basis is rational, Gauss quadrature is exact only in the limit
  ! (about 2e-5 with p+1 points, 1e-15 with 12); the rigid-body checks hold for any rule
  call case_patch(t, 2, 4, .true., 0.25_dp, 12)
  call case_patch(t, 3, 3, .true., 0.25_dp, 12)
  call case_patch(t, 3, 3, .false., 0.25_dp, 4)
  call t%finish()

contains

  !> A deterministic pseudo-random number in [-1, 1] from two integers.
  pure real(dp) function hash(i, j)
    integer, intent(in) :: i, j
    real(dp) :: s
    s = sin(12.9898_dp*real(i, dp) + 78.233_dp*real(j, dp))*43758.5453_dp
    hash = 2.0_dp*(s - floor(s)) - 1.0_dp
  end function hash

  !> The distorted patch: [0, 2] x [0, 1.5] biquadratic single span, elevated to degree p,
  !! refined into k x k spans; interior control points moved by up to 0.3 of the control
  !! net spacing, all weights in [0.75, 1.25].
  subroutine distorted_patch(p, k, wamp, q)
    integer, intent(in) :: p, k
    real(dp), intent(in) :: wamp
    type(patch_t), intent(inout) :: q
    real(dp) :: cp(3, 9), kn(6), hx, hy
    integer :: i, j, a
    kn = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    do j = 0, 2
      do i = 0, 2
        cp(:, 1 + i + 3*j) = [1.0_dp*i, 0.75_dp*j, 1.0_dp]
      end do
    end do
    call q%init('SQUARE', [2, 2], [3, 3], kn, kn, cp)
    if (p > 2) call patch_elevate(q, [p, p])
    call patch_refine(q, [k, k])
    hx = 2.0_dp/real(q%n(1) - 1, dp)
    hy = 1.5_dp/real(q%n(2) - 1, dp)
    do j = 1, q%n(2)
      do i = 1, q%n(1)
        a = i + (j - 1)*q%n(1)
        q%cp(3, a) = q%cp(3, a)*(1.0_dp + wamp*hash(3*i + 1, 7*j + 2))
        if (i == 1 .or. j == 1 .or. i == q%n(1) .or. j == q%n(2)) cycle
        q%cp(1, a) = q%cp(1, a) + 0.3_dp*hx*hash(i, j)
        q%cp(2, a) = q%cp(2, a) + 0.3_dp*hy*hash(j + 11, i + 5)
      end do
    end do
  end subroutine distorted_patch

  !> Shape data of element e (ng Gauss points per direction).
  subroutine element_shape(q, e, ng, shp)
    type(patch_t), intent(in) :: q
    integer, intent(in) :: e, ng
    type(elem_shape_t), intent(inout) :: shp
    integer :: ij(2)
    ij = patch_elem_ij(q, e)
    call iga_shape_data(q%p, q%c1(:, :, ij(1)), q%c2(:, :, ij(2)), q%cp(3, q%ien(:, e)), &
        [ng, ng], shp)
  end subroutine element_shape

  !> Dense global stiffness (2 ncp, 2 ncp), dofs x1, y1, x2, ...
  subroutine assemble_k(q, d, ng, kg, ierr)
    type(patch_t), intent(in) :: q
    real(dp), intent(in) :: d(3, 3)
    integer, intent(in) :: ng
    real(dp), intent(out) :: kg(:,:)
    integer, intent(out) :: ierr
    type(elem_shape_t) :: shp
    real(dp), allocatable :: ke(:,:)
    integer, allocatable :: dof(:)
    integer :: e, a, nen
    nen = q%nen
    allocate(ke(2*nen, 2*nen), dof(2*nen))
    kg = 0.0_dp
    ierr = 0
    do e = 1, q%nel(1)*q%nel(2)
      call element_shape(q, e, ng, shp)
      call solid2d_stiffness(nen, shp, q%cp(1:2, q%ien(:, e)), d, 1.0_dp, ke, ierr)
      if (ierr /= 0) return
      do a = 1, nen
        dof(2*a - 1) = 2*q%ien(a, e) - 1
        dof(2*a) = 2*q%ien(a, e)
      end do
      kg(dof, dof) = kg(dof, dof) + ke
    end do
  end subroutine assemble_k

  !> Rigid translation and infinitesimal rotation (any rule), and the linear-field patch test
  !! (skipped for weights /= 1 with fewer than 12 points) for degree p with k x k spans;
  !! plane strain or plane stress; weights 1 +- wamp; ng Gauss points per direction.
  subroutine case_patch(t, p, k, plane_strain, wamp, ng)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: p, k
    logical, intent(in) :: plane_strain
    real(dp), intent(in) :: wamp
    integer, intent(in) :: ng
    type(patch_t) :: q
    type(elem_shape_t) :: shp
    real(dp) :: d(3, 3), a0(2), bm(2, 2), sig_exact(3), kscale, err_u, err_s
    real(dp), allocatable :: kg(:,:), u(:), f(:), kii(:,:), rhs(:,:), sig(:,:), ul(:,:)
    integer, allocatable :: interior(:), ipiv(:)
    logical, allocatable :: bnd(:)
    integer :: ncp, ndof, i, j, a, e, ierr, ni, info
    character(len=40) :: tag
    type(linear_elastic_t) :: law
    real(dp) :: nohist(0, 100)
    write(tag, '(a,i0,a,i0,a,i0,a,l1)') 'p = ', p, ', ', k, ' x ', k, ' spans, strain ', &
        plane_strain
    call distorted_patch(p, k, wamp, q)
    ncp = q%n(1)*q%n(2)
    ndof = 2*ncp
    call elastic_dmat(1000.0_dp, 0.2_dp, plane_strain, d)
    law = linear_elastic_t(e=1000.0_dp, nu=0.2_dp)
    law%kin = kinematics_t(merge(ANALYSIS_PLANE_STRAIN, ANALYSIS_PLANE_STRESS, plane_strain), &
        .false.)
    call law%init()
    allocate(kg(ndof, ndof), u(ndof), f(ndof))
    call assemble_k(q, d, ng, kg, ierr)
    call t%equal_int(ierr, 0, "positive det J on the distorted patch, "//trim(tag))
    kscale = maxval(abs(kg))

    ! rigid translation and infinitesimal rotation: K u = 0
    do a = 1, ncp
      u(2*a - 1) = 0.7_dp
      u(2*a) = -0.4_dp
    end do
    f = matmul(kg, u)
    call t%true(maxval(abs(f)) < 1.0e-10_dp*kscale*maxval(abs(u)), &
        "K u = 0 for a rigid translation, "//trim(tag))
    do a = 1, ncp
      u(2*a - 1) = -1.0e-3_dp*q%cp(2, a)
      u(2*a) = 1.0e-3_dp*q%cp(1, a)
    end do
    f = matmul(kg, u)
    call t%true(maxval(abs(f)) < 1.0e-10_dp*kscale*maxval(abs(u)), &
        "K u = 0 for an infinitesimal rotation, "//trim(tag))

    ! linear field on the boundary control points, interior solved by dgesv (exact only when
    ! the quadrature is: polynomial basis, or rational with many points)
    if (wamp > 0.0_dp .and. ng < 12) return
    a0 = [0.01_dp, -0.02_dp]
    bm = reshape([1.0e-3_dp, -2.0e-3_dp, 3.0e-3_dp, 0.5e-3_dp], [2, 2])
    allocate(bnd(ncp))
    do j = 1, q%n(2)
      do i = 1, q%n(1)
        bnd(i + (j - 1)*q%n(1)) = i == 1 .or. j == 1 .or. i == q%n(1) .or. j == q%n(2)
      end do
    end do
    ni = count(.not. bnd)
    allocate(interior(2*ni))
    j = 0
    do a = 1, ncp
      u(2*a - 1:2*a) = a0 + matmul(bm, q%cp(1:2, a))
      if (bnd(a)) cycle
      interior(j + 1:j + 2) = [2*a - 1, 2*a]
      j = j + 2
    end do
    f = u
    do a = 1, size(interior)
      u(interior(a)) = 0.0_dp
    end do
    allocate(kii(2*ni, 2*ni), rhs(2*ni, 1), ipiv(2*ni))
    kii = kg(interior, interior)
    rhs(:, 1) = -matmul(kg(interior, :), u)
    call dgesv(2*ni, 1, kii, 2*ni, ipiv, rhs, 2*ni, info)
    call t%equal_int(info, 0, "dgesv on K_II, "//trim(tag))
    u(interior) = rhs(:, 1)
    err_u = maxval(abs(u - f))/maxval(abs(f))
    call t%true(err_u < 1.0e-10_dp, "linear field reproduced at the interior control "// &
        "points, "//trim(tag))
    ! constant stress D eps(B) at every Gauss point of every element
    sig_exact = matmul(d, [bm(1, 1), bm(2, 2), bm(1, 2) + bm(2, 1)])
    err_s = 0.0_dp
    do e = 1, q%nel(1)*q%nel(2)
      call element_shape(q, e, ng, shp)
      if (allocated(sig)) deallocate(sig)
      allocate(sig(6, shp%ngp))
      if (allocated(ul)) deallocate(ul)
      allocate(ul(2, q%nen))
      do a = 1, q%nen
        ul(:, a) = u(2*q%ien(a, e) - 1:2*q%ien(a, e))
      end do
      call solid2d_stress(q%nen, shp, q%cp(1:2, q%ien(:, e)), ul, law, nohist, sig, ierr)
      do a = 1, shp%ngp
        err_s = max(err_s, maxval(abs(sig([1, 2, 4], a) - sig_exact)))
      end do
    end do
    call t%true(err_s < 1.0e-10_dp*maxval(abs(sig_exact)), "constant stress D eps(B) at "// &
        "all Gauss points, "//trim(tag))
  end subroutine case_patch
end program test_iga_patch
