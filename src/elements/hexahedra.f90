!> Shape functions of the hexahedra C3D8 (trilinear), C3D20 (serendipity) and C3D27
!! (triquadratic), in the Abaqus node order (doc/elements3d.md).
!!
!! Parent cube [-1, 1]^3 with coordinates (xi, eta, zeta):
!!  - corners 1-4 on zeta = -1 counter-clockwise seen from +zeta: (-1,-1,-1), (1,-1,-1),
!!    (1,1,-1), (-1,1,-1); corners 5-8 above them on zeta = +1;
!!  - midsides (C3D20, C3D27) 9-12 on the edges 1-2, 2-3, 3-4, 4-1; 13-16 on 5-6, 6-7, 7-8,
!!    8-5; 17-20 on 1-5, 2-6, 3-7, 4-8;
!!  - (C3D27) the centre 21, then the face centres 22-27 on the faces S1..S6: the order in
!!    which gmsh writes C3D27 into Abaqus decks (checked against its export of a cube,
!!    tests/scripts/check_quarter_ball.py), so that gmsh meshes read as they are.
!!
!! Faces in the Abaqus numbering: S1 (corners 1-2-3-4, zeta = -1), S2 (5-8-7-6, zeta = 1),
!! S3 (1-5-6-2, eta = -1), S4 (2-6-7-3, xi = 1), S5 (3-7-8-4, eta = 1), S6 (4-8-5-1,
!! xi = -1). Abaqus lists them with the normal inward; the face lists of the element kind
!! (`element_kind_t%face`) run the other way round, so the right-hand rule gives the outward
!! normal: S1 = 1-4-3-2, S2 = 5-6-7-8, S3 = 1-2-6-5, S4 = 2-3-7-6, S5 = 3-4-8-7, S6 = 4-1-5-8,
!! followed by the midsides of their sides (corner 1-2, 2-3, 3-4, 4-1 of the list) and the
!! face centre.
!!
!! XDMF's Hexahedron_20 and Hexahedron_27 are VTK's quadratic and triquadratic hexahedra (the
!! XDMF library: "Xdmf element types ... have the same ordering as VTK"). Hexahedron_20 is the
!! C3D20 order; Hexahedron_27 has the face centres in the order xi = -1, xi = 1, eta = -1,
!! eta = 1, zeta = -1, zeta = 1 (S6, S4, S3, S5, S1, S2), kept in `xdmf_order`.
module ictus_elements_hexahedra
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: element_kind_t, KERNEL_SOLID3D, add_alias
  use ictus_elements_lagrange, only: quad_1d
  use ictus_materials_law, only: ANALYSIS_3D
  implicit none
  private
  public :: c3d8_kind, c3d20_kind, c3d27_kind, hexahedra_node_xi, shape_c3d8, shape_c3d20, &
      shape_c3d27

  !> Corner pairs of the edges carrying the midsides 9-20.
  integer, parameter :: edge_corners(2, 12) = reshape([1, 2, 2, 3, 3, 4, 4, 1, 5, 6, 6, 7, &
      7, 8, 8, 5, 1, 5, 2, 6, 3, 7, 4, 8], [2, 12])

  !> Corners of the faces S1..S6, ordered for the outward normal (right-hand rule).
  integer, parameter :: face_corners(4, 6) = reshape([1, 4, 3, 2, 5, 6, 7, 8, 1, 2, 6, 5, &
      2, 3, 7, 6, 3, 4, 8, 7, 4, 1, 5, 8], [4, 6])

  !> Parent coordinates of the corners, (3, 8).
  real(dp), parameter :: corner_xi(3, 8) = reshape([ &
      -1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, &
      -1.0_dp, 1.0_dp, -1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, 1.0_dp, &
      1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp], [3, 8])

  !> XDMF (VTK) order of the 27 nodes: XDMF node k is local node xdmf27(k).
  integer, parameter :: xdmf27(27) = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, &
      17, 18, 19, 20, 27, 25, 24, 26, 22, 23, 21]

contains

  !> The element types of this file, for the dispatcher (ictus_elements_library). Their
  !! Abaqus names imply a 3D analysis; C3D20R is C3D20 with the reduced 2x2x2 Gauss rule.
  function c3d8_kind() result(k)
    type(element_kind_t) :: k
    k = hex_kind('C3D8', 'Hexahedron', 8, 2, 1, .false.)
    k%shape => shape_c3d8
  end function c3d8_kind

  function c3d20_kind() result(k)
    type(element_kind_t) :: k
    k = hex_kind('C3D20', 'Hexahedron_20', 20, 3, 2, .false.)
    k%shape => shape_c3d20
    call add_alias(k, 'C3D20R', ANALYSIS_3D, 2)
  end function c3d20_kind

  function c3d27_kind() result(k)
    type(element_kind_t) :: k
    k = hex_kind('C3D27', 'Hexahedron_27', 27, 3, 2, .true.)
    k%shape => shape_c3d27
    k%xdmf_order = xdmf27
  end function c3d27_kind

  !> The common part of the three hexahedra: 8 corners, 6 faces S1..S6 of nfn = 4, 8 or 9
  !! nodes (corners for the outward normal, midsides of their sides, centre).
  function hex_kind(name, xdmf, nen, ngauss, order, centre) result(k)
    character(len=*), intent(in) :: name, xdmf
    integer, intent(in) :: nen, ngauss, order
    logical, intent(in) :: centre
    type(element_kind_t) :: k
    integer :: f, i
    k = element_kind_t(name=name, xdmf=xdmf, ndm=3, nen=nen, ncorner=8, ngauss=ngauss, &
        nface=6, nfn=merge(4, merge(9, 8, centre), order == 1), order=order, centre=centre, &
        kernel=KERNEL_SOLID3D)
    allocate(k%face(k%nfn, 6))
    do f = 1, 6
      k%face(1:4, f) = face_corners(:, f)
      if (order == 1) cycle
      do i = 1, 4
        k%face(4 + i, f) = edge_node(face_corners(i, f), face_corners(mod(i, 4) + 1, f))
      end do
      if (centre) k%face(9, f) = 21 + f
    end do
  end function hex_kind

  !> The midside node (9..20) of the edge between corners c1 and c2 (0 if none).
  pure integer function edge_node(c1, c2)
    integer, intent(in) :: c1, c2
    integer :: e
    edge_node = 0
    do e = 1, 12
      if (all(edge_corners(:, e) == [c1, c2]) .or. all(edge_corners(:, e) == [c2, c1])) then
        edge_node = 8 + e
        return
      end if
    end do
  end function edge_node

  !> Parent coordinates of local node a (1..27) in [-1, 1]^3; xa(3).
  pure subroutine hexahedra_node_xi(a, xa)
    integer, intent(in) :: a
    real(dp), intent(out) :: xa(3)
    integer :: f, i
    if (a <= 8) then
      xa = corner_xi(:, a)
    else if (a <= 20) then
      xa = 0.5_dp*(corner_xi(:, edge_corners(1, a - 8)) + corner_xi(:, edge_corners(2, a - 8)))
    else if (a >= 22) then
      f = a - 21
      xa = 0.0_dp
      do i = 1, 4
        xa = xa + 0.25_dp*corner_xi(:, face_corners(i, f))
      end do
    else
      xa = 0.0_dp
    end if
  end subroutine hexahedra_node_xi

  !> Trilinear: N_A = (1 + xi xi_A)(1 + eta eta_A)(1 + zeta zeta_A)/8.
  pure subroutine shape_c3d8(xi, n, dn)
    real(dp), intent(in) :: xi(:)
    real(dp), intent(out) :: n(:), dn(:,:)
    integer :: a
    real(dp) :: s(3)
    do a = 1, 8
      s = 1.0_dp + xi(1:3)*corner_xi(:, a)
      n(a) = 0.125_dp*s(1)*s(2)*s(3)
      dn(1, a) = 0.125_dp*corner_xi(1, a)*s(2)*s(3)
      dn(2, a) = 0.125_dp*corner_xi(2, a)*s(1)*s(3)
      dn(3, a) = 0.125_dp*corner_xi(3, a)*s(1)*s(2)
    end do
  end subroutine shape_c3d8

  !> Serendipity: corners (1 + xi xi_A)(1 + eta eta_A)(1 + zeta zeta_A)
  !! (xi xi_A + eta eta_A + zeta zeta_A - 2)/8; a midside with xi_A = 0:
  !! (1 - xi^2)(1 + eta eta_A)(1 + zeta zeta_A)/4 (and likewise in the other directions).
  pure subroutine shape_c3d20(xi, n, dn)
    real(dp), intent(in) :: xi(:)
    real(dp), intent(out) :: n(:), dn(:,:)
    integer :: a, i
    real(dp) :: xa(3), s(3), ds(3), r
    do a = 1, 8
      xa = corner_xi(:, a)
      s = 1.0_dp + xi(1:3)*xa
      r = dot_product(xi(1:3), xa) - 2.0_dp
      n(a) = 0.125_dp*s(1)*s(2)*s(3)*r
      dn(1, a) = 0.125_dp*xa(1)*s(2)*s(3)*(r + s(1))
      dn(2, a) = 0.125_dp*xa(2)*s(1)*s(3)*(r + s(2))
      dn(3, a) = 0.125_dp*xa(3)*s(1)*s(2)*(r + s(3))
    end do
    do a = 9, 20
      call hexahedra_node_xi(a, xa)
      ! the factor of each direction and its derivative: 1 - xi^2 along the edge, else linear
      do i = 1, 3
        if (xa(i) == 0.0_dp) then
          s(i) = 1.0_dp - xi(i)**2
          ds(i) = -2.0_dp*xi(i)
        else
          s(i) = 1.0_dp + xi(i)*xa(i)
          ds(i) = xa(i)
        end if
      end do
      n(a) = 0.25_dp*s(1)*s(2)*s(3)
      dn(1, a) = 0.25_dp*ds(1)*s(2)*s(3)
      dn(2, a) = 0.25_dp*s(1)*ds(2)*s(3)
      dn(3, a) = 0.25_dp*s(1)*s(2)*ds(3)
    end do
  end subroutine shape_c3d20

  !> Triquadratic Lagrange: tensor product of the 1D quadratics through -1, 0, 1.
  pure subroutine shape_c3d27(xi, n, dn)
    real(dp), intent(in) :: xi(:)
    real(dp), intent(out) :: n(:), dn(:,:)
    real(dp) :: l(3, 3), d(3, 3), xa(3)
    integer :: a, i, j, k
    do i = 1, 3
      call quad_1d(xi(i), l(:, i), d(:, i))
    end do
    do a = 1, 27
      call hexahedra_node_xi(a, xa)
      ! 1D index 1, 2, 3 for the node coordinate -1, 0, 1
      i = nint(xa(1)) + 2
      j = nint(xa(2)) + 2
      k = nint(xa(3)) + 2
      n(a) = l(i, 1)*l(j, 2)*l(k, 3)
      dn(1, a) = d(i, 1)*l(j, 2)*l(k, 3)
      dn(2, a) = l(i, 1)*d(j, 2)*l(k, 3)
      dn(3, a) = l(i, 1)*l(j, 2)*d(k, 3)
    end do
  end subroutine shape_c3d27
end module ictus_elements_hexahedra
