!> C3D8/C3D20/C3D27 shape functions (doc/elements3d.md): partition of unity, sum of the
!! derivatives, Kronecker delta at the nodes, derivatives against central differences,
!! reproduction of the monomials of each space (and C3D20 missing x^2 y^2), the shape data of
!! the library; the faces S1..S6 (their nodes on the face of the parent cube, corners ordered
!! so the right-hand rule gives the outward normal, midsides and centre where they belong);
!! the XDMF order of Hexahedron_27; the deck names.
program test_hexahedra
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_C3D8, ETYPE_C3D20, ETYPE_C3D27, ETYPE_Q8, &
      elem_shape_t, element_kind_t, KERNEL_SOLID3D
  use ictus_elements_library, only: element_kind, etype_name, etype_nen, etype_ndm, &
      element_shape_data, element_default_ngauss, element_type_named, element_abaqus_names, &
      element_types_named
  use ictus_elements_hexahedra, only: hexahedra_node_xi
  use ictus_materials_law, only: ANALYSIS_3D
  use ictus_test_check, only: checker_t
  use ictus_test_elements, only: check_shape_functions, cross3
  implicit none
  type(checker_t) :: t
  integer, parameter :: types(3) = [ETYPE_C3D8, ETYPE_C3D20, ETYPE_C3D27]
  !> Test points inside the parent cube (and two on its boundary).
  real(dp), parameter :: pts(3, 6) = reshape([0.13_dp, -0.71_dp, 0.42_dp, -0.52_dp, 0.33_dp, &
      -0.88_dp, 0.91_dp, 0.87_dp, 0.05_dp, -0.05_dp, 0.0_dp, 0.6_dp, 1.0_dp, 0.4_dp, -0.3_dp, &
      -0.3_dp, -1.0_dp, 0.77_dp], [3, 6])
  integer :: k
  call t%start("elements/hexahedra")
  do k = 1, 3
    call case_basics(t, types(k))
    call case_reproduction(t, types(k))
    call case_shape_data(t, types(k))
    call case_faces(t, types(k))
  end do
  call case_xdmf(t)
  call case_names(t)
  call t%finish()

contains

  !> N and dN/dxi of type et at the parent point x (the kind's shape function).
  subroutine shape(et, x, n, dn)
    integer, intent(in) :: et
    real(dp), intent(in) :: x(3)
    real(dp), intent(out) :: n(:), dn(:,:)
    type(element_kind_t) :: kd
    kd = element_kind(et)
    call kd%shape(x, n, dn)
  end subroutine shape

  !> The shape-function checks of ictus_test_elements at pts and the nodes.
  subroutine case_basics(t, et)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    type(element_kind_t) :: kd
    real(dp) :: xnode(3, 27)
    integer :: a
    kd = element_kind(et)
    do a = 1, kd%nen
      call hexahedra_node_xi(a, xnode(:, a))
    end do
    call check_shape_functions(t, etype_name(et), kd%shape, xnode(:, 1:kd%nen), pts)
  end subroutine case_basics

  !> The exponents (3, nmono) of the monomials xi^a eta^b zeta^c of the element's space:
  !! C3D27 all with a, b, c <= 2; C3D8 those with a, b, c <= 1; C3D20 those with at most one
  !! exponent 2 and total degree at most 3 after counting the 2 as 1 (the 20 serendipity
  !! monomials: 1, xi, ..., xi eta zeta, xi^2, ..., xi^2 eta, ..., xi^2 eta zeta, ...).
  subroutine monomials(et, pw, nmono)
    integer, intent(in) :: et
    integer, intent(out) :: pw(3, 27), nmono
    integer :: a, b, c
    logical :: keep
    nmono = 0
    do c = 0, 2
      do b = 0, 2
        do a = 0, 2
          select case (et)
          case (ETYPE_C3D8)
            keep = max(a, b, c) <= 1
          case (ETYPE_C3D20)
            keep = count([a, b, c] == 2) <= 1
          case default
            keep = .true.
          end select
          if (.not. keep) cycle
          nmono = nmono + 1
          pw(:, nmono) = [a, b, c]
        end do
      end do
    end do
  end subroutine monomials

  !> Each element interpolates exactly the monomials of its space, with their derivatives;
  !! C3D20 must not reproduce xi^2 eta^2.
  subroutine case_reproduction(t, et)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    real(dp) :: n(27), dn(3, 27), f(27), x(3), xa(3), dwant(3), fx
    integer :: pw(3, 27), nen, nmono, m, p, a, i, e(3)
    nen = etype_nen(et)
    call monomials(et, pw, nmono)
    call t%equal_int(nmono, nen, etype_name(et)//' space dimension = nen')
    do m = 1, nmono
      do a = 1, nen
        call hexahedra_node_xi(a, xa)
        f(a) = product(xa**pw(:, m))
      end do
      do p = 1, size(pts, 2)
        x = pts(:, p)
        call shape(et, x, n(1:nen), dn(:, 1:nen))
        fx = product(x**pw(:, m))
        do i = 1, 3
          e = pw(:, m)
          e(i) = max(e(i) - 1, 0)
          dwant(i) = real(pw(i, m), dp)*product(x**e)
        end do
        call t%close_abs(sum(n(1:nen)*f(1:nen)), fx, 1.0e-14_dp, &
            etype_name(et)//' reproduces monomial')
        do i = 1, 3
          call t%close_abs(sum(dn(i, 1:nen)*f(1:nen)), dwant(i), 1.0e-14_dp, &
              etype_name(et)//' reproduces its derivative')
        end do
      end do
    end do
    if (et /= ETYPE_C3D20) return
    do a = 1, nen
      call hexahedra_node_xi(a, xa)
      f(a) = xa(1)**2*xa(2)**2
    end do
    x = [0.5_dp, 0.5_dp, 0.0_dp]
    call shape(et, x, n(1:nen), dn(:, 1:nen))
    call t%true(abs(sum(n(1:nen)*f(1:nen)) - 0.0625_dp) > 0.01_dp, &
        'C3D20 does not reproduce xi^2 eta^2')
  end subroutine case_reproduction

  !> The library's shape data: the full rule (2^3 or 3^3 points), weights summing to the
  !! parent volume 8, point 2 of the rule at (0, -sqrt(3/5), -sqrt(3/5)) for 3x3x3 (xi fastest);
  !! C3D20R's 2x2x2 rule.
  subroutine case_shape_data(t, et)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    type(elem_shape_t) :: shp
    real(dp) :: n(27), dn(3, 27), q
    integer :: nen, ng
    nen = etype_nen(et)
    ng = element_default_ngauss(et)
    call t%equal_int(ng, merge(2, 3, et == ETYPE_C3D8), etype_name(et)//' full rule')
    call t%equal_int(etype_ndm(et), 3, etype_name(et)//' ndm = 3')
    call element_shape_data(et, ng, shp)
    call t%equal_int(shp%nen, nen, etype_name(et)//' shape data nen')
    call t%equal_int(shp%ngp, ng**3, etype_name(et)//' shape data ngp')
    call t%true(size(shp%dn, 1) == 3 .and. size(shp%dn, 2) == nen, &
        etype_name(et)//' shape data dn(3, nen, ngp)')
    call t%close(sum(shp%w), 8.0_dp, 1.0e-14_dp, etype_name(et)//' weights sum 8')
    q = merge(1.0_dp/sqrt(3.0_dp), sqrt(0.6_dp), ng == 2)
    call shape(et, [merge(q, 0.0_dp, ng == 2), -q, -q], n(1:nen), dn(:, 1:nen))
    call t%close_abs(maxval(abs(shp%n(:, 2) - n(1:nen))), 0.0_dp, 1.0e-15_dp, &
        etype_name(et)//' shape data point 2')
    call t%close_abs(maxval(abs(shp%dn(:, :, 2) - dn(:, 1:nen))), 0.0_dp, 1.0e-15_dp, &
        etype_name(et)//' shape data point 2 derivatives')
    if (et /= ETYPE_C3D20) return
    call element_shape_data(et, 2, shp)
    call t%true(shp%ngp == 8 .and. abs(sum(shp%w) - 8.0_dp) < 1.0e-14_dp, 'C3D20R: 2x2x2 rule')
  end subroutine case_shape_data

  !> Faces S1..S6: nfn nodes, all on the plane of the face (S1 zeta = -1, S2 zeta = 1,
  !! S3 eta = -1, S4 xi = 1, S5 eta = 1, S6 xi = -1), and every element node on that plane in
  !! the list; the right-hand rule of corners 1, 2, 3 (and 3, 4, 1) gives the outward normal;
  !! node 4 + i is the midside of corners i and i + 1, node 9 the face centre.
  subroutine case_faces(t, et)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    integer, parameter :: axis(6) = [3, 3, 2, 1, 2, 1]
    real(dp), parameter :: side(6) = [-1.0_dp, 1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp]
    type(element_kind_t) :: kd
    real(dp) :: xf(3, 9), xa(3), nrm(3), out(3)
    integer :: f, i, a, nfn, on
    kd = element_kind(et)
    nfn = merge(4, merge(8, 9, et == ETYPE_C3D20), et == ETYPE_C3D8)
    call t%equal_int(kd%nface, 6, etype_name(et)//' 6 faces')
    call t%equal_int(kd%nfn, nfn, etype_name(et)//' nodes per face')
    if (kd%nfn /= nfn .or. kd%nface /= 6) return
    do f = 1, 6
      do i = 1, nfn
        call hexahedra_node_xi(kd%face(i, f), xf(:, i))
      end do
      call t%true(all(xf(axis(f), 1:nfn) == side(f)), etype_name(et)//' face nodes on the face')
      on = 0
      do a = 1, etype_nen(et)
        call hexahedra_node_xi(a, xa)
        if (xa(axis(f)) == side(f)) on = on + 1
      end do
      call t%equal_int(on, nfn, etype_name(et)//' face lists every node of its plane')
      out = 0.0_dp
      out(axis(f)) = side(f)
      nrm = cross3(xf(:, 2) - xf(:, 1), xf(:, 3) - xf(:, 2))
      call t%close(dot_product(nrm, out), 4.0_dp, 0.0_dp, etype_name(et)//' 1-2-3 normal outward')
      nrm = cross3(xf(:, 4) - xf(:, 3), xf(:, 1) - xf(:, 4))
      call t%close(dot_product(nrm, out), 4.0_dp, 0.0_dp, etype_name(et)//' 3-4-1 normal outward')
      if (nfn == 4) cycle
      do i = 1, 4
        call t%true(all(xf(:, 4 + i) == 0.5_dp*(xf(:, i) + xf(:, mod(i, 4) + 1))), &
            etype_name(et)//' face midside between its corners')
      end do
      if (nfn == 9) call t%true(all(xf(:, 9) == out), etype_name(et)//' face centre')
    end do
  end subroutine case_faces

  !> XDMF topologies; Hexahedron_27 (VTK order) has its face centres at xi = -1, xi = 1,
  !! eta = -1, eta = 1, zeta = -1, zeta = 1, then the centre: xdmf_order must put them there.
  subroutine case_xdmf(t)
    type(checker_t), intent(inout) :: t
    type(element_kind_t) :: kd
    real(dp) :: xa(3), want(3)
    integer :: k, a, i
    kd = element_kind(ETYPE_C3D8)
    call t%true(trim(kd%xdmf) == 'Hexahedron' .and. .not. allocated(kd%xdmf_order), &
        'C3D8: Hexahedron, same order')
    kd = element_kind(ETYPE_C3D20)
    call t%true(trim(kd%xdmf) == 'Hexahedron_20' .and. .not. allocated(kd%xdmf_order), &
        'C3D20: Hexahedron_20, same order')
    kd = element_kind(ETYPE_C3D27)
    call t%true(trim(kd%xdmf) == 'Hexahedron_27' .and. allocated(kd%xdmf_order), &
        'C3D27: Hexahedron_27 with its order')
    if (.not. allocated(kd%xdmf_order)) return
    do a = 1, 27
      call t%equal_int(count(kd%xdmf_order == a), 1, 'C3D27 xdmf_order is a permutation')
    end do
    call t%true(all(kd%xdmf_order(1:20) == [(k, k = 1, 20)]), 'C3D27 xdmf corners, midsides')
    do k = 21, 27
      call hexahedra_node_xi(kd%xdmf_order(k), xa)
      want = 0.0_dp
      if (k < 27) then
        i = (k - 19)/2
        want(i) = merge(-1.0_dp, 1.0_dp, mod(k, 2) == 1)
      end if
      call t%true(all(xa == want), 'C3D27 xdmf face centres in VTK order')
    end do
  end subroutine case_xdmf

  !> Deck names: the type names, C3D20R for C3D20 with 2x2x2 Gauss; the 2D lists unchanged.
  subroutine case_names(t)
    type(checker_t), intent(inout) :: t
    integer :: et, an, ng
    type(element_kind_t) :: kd
    call element_type_named('c3d8', et, an, ng)
    call t%true(et == ETYPE_C3D8 .and. ng == 0, 'C3D8 by name')
    call element_type_named('C3D20', et, an, ng)
    call t%true(et == ETYPE_C3D20 .and. ng == 0, 'C3D20 by name')
    call element_type_named('C3D20R', et, an, ng)
    call t%true(et == ETYPE_C3D20 .and. an == ANALYSIS_3D .and. ng == 2, &
        'C3D20R = C3D20, 3D, 2x2x2 Gauss')
    call element_type_named('C3D27', et, an, ng)
    call t%true(et == ETYPE_C3D27 .and. ng == 0, 'C3D27 by name')
    call element_type_named('C3D8R', et, an, ng)
    call t%equal_int(et, 0, 'C3D8R (one point, hourglass) is not a type')
    call t%true(index(element_abaqus_names(), 'C3D20R (C3D20)') > 0, 'Abaqus names list C3D20R')
    call t%true(element_types_named(2) == 'Q4, Q8, Q9', '2D type names unchanged')
    call t%true(index(element_types_named(), 'C3D8, C3D20, C3D27') > 0, 'all type names')
    call t%true(index(element_abaqus_names(2), 'C3D') == 0, '2D Abaqus names without C3D')
    kd = element_kind(ETYPE_C3D27)
    call t%true(kd%kernel == KERNEL_SOLID3D .and. kd%ncorner == 8 .and. kd%order == 2 .and. &
        kd%centre, 'C3D27 description')
    call t%equal_int(etype_ndm(ETYPE_Q8), 2, 'Q8 ndm = 2')
  end subroutine case_names
end program test_hexahedra
