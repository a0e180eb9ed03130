!> Shape functions of the Lagrange/serendipity quadrilaterals Q4, Q8 (serendipity) and Q9.
!!
!! Local node order (doc/user-guide.md §4, *ELEMENT): corners counter-clockwise at (-1,-1), (1,-1),
!! (1,1), (-1,1); then midsides 5 (on 1-2), 6 (on 2-3), 7 (on 3-4), 8 (on 4-1); then the
!! centre 9 (Q9 only). Face k runs from corner k to corner k+1 (corner 4 to corner 1 for k = 4).
module ictus_elements_lagrange
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, elem_shape_t, element_kind_t, &
      KERNEL_SOLID2D, add_alias
  use ictus_elements_quadrature, only: gauss_rule_2d
  use ictus_materials_law, only: ANALYSIS_PLANE_STRAIN, ANALYSIS_PLANE_STRESS
  implicit none
  private
  public :: lagrange_shape, lagrange_shape_data, lagrange_face_nodes, lagrange_node_xi, &
      q4_kind, q8_kind, q9_kind, quad_1d

  !> Parent coordinates of the 9 possible nodes, (2, 9).
  real(dp), parameter :: node_xi(2, 9) = reshape([ &
      -1.0_dp, -1.0_dp, 1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, 1.0_dp, &
      0.0_dp, -1.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, -1.0_dp, 0.0_dp, &
      0.0_dp, 0.0_dp], [2, 9])

contains

  !> The element types of this file, for the dispatcher (ictus_elements_library).
  function q4_kind() result(k)
    type(element_kind_t) :: k
    k = quad_kind('Q4', 'Quadrilateral', 4, 2, 1, .false.)
    k%shape => shape_q4
    call add_alias(k, 'CPE4', ANALYSIS_PLANE_STRAIN, 0)
    call add_alias(k, 'CPS4', ANALYSIS_PLANE_STRESS, 0)
  end function q4_kind

  function q8_kind() result(k)
    type(element_kind_t) :: k
    k = quad_kind('Q8', 'Quadrilateral_8', 8, 3, 2, .false.)
    k%shape => shape_q8
    call add_alias(k, 'CPE8', ANALYSIS_PLANE_STRAIN, 0)
    call add_alias(k, 'CPS8', ANALYSIS_PLANE_STRESS, 0)
    call add_alias(k, 'CPE8R', ANALYSIS_PLANE_STRAIN, 2)
    call add_alias(k, 'CPS8R', ANALYSIS_PLANE_STRESS, 2)
  end function q8_kind

  function q9_kind() result(k)
    type(element_kind_t) :: k
    k = quad_kind('Q9', 'Quadrilateral_9', 9, 3, 2, .true.)
    k%shape => shape_q9
    call add_alias(k, 'CPE9', ANALYSIS_PLANE_STRAIN, 0)
    call add_alias(k, 'CPS9', ANALYSIS_PLANE_STRESS, 0)
    ! gmsh's name for its 9-node quadrilateral: a membrane in the plane, so plane stress.
    call add_alias(k, 'M3D9', ANALYSIS_PLANE_STRESS, 0)
  end function q9_kind

  !> The common part of the three quadrilaterals: 4 corners, 4 faces from corner k to k + 1
  !! (with midside k + 4 for the quadratic ones).
  function quad_kind(name, xdmf, nen, ngauss, order, centre) result(k)
    character(len=*), intent(in) :: name, xdmf
    integer, intent(in) :: nen, ngauss, order
    logical, intent(in) :: centre
    type(element_kind_t) :: k
    integer :: f
    k%name = name
    k%xdmf = xdmf
    k%ndm = 2
    k%nen = nen
    k%ncorner = 4
    k%ngauss = ngauss
    k%order = order
    k%centre = centre
    k%kernel = KERNEL_SOLID2D
    k%nface = 4
    k%nfn = order + 1
    allocate(k%face(k%nfn, 4))
    do f = 1, 4
      k%face(1, f) = f
      k%face(k%nfn, f) = mod(f, 4) + 1
      if (order == 2) k%face(2, f) = f + 4
    end do
  end function quad_kind

  !> Parent coordinates of local node a (1..9) in [-1, 1]^2; xa(2).
  pure subroutine lagrange_node_xi(a, xa)
    integer, intent(in) :: a
    real(dp), intent(out) :: xa(2)
    xa = node_xi(:, a)
  end subroutine lagrange_node_xi

  !> Shape functions and their parent derivatives at one point.
  !! etype: ETYPE_Q4, ETYPE_Q8 or ETYPE_Q9; xi(2): parent point (xi, eta);
  !! n(nen): N_A(xi); dn(2, nen): dN_A/dxi, dN_A/deta. Any other etype gives zeros.
  pure subroutine lagrange_shape(etype, xi, n, dn)
    integer, intent(in) :: etype
    real(dp), intent(in) :: xi(2)
    real(dp), intent(out) :: n(:), dn(:,:)
    n = 0.0_dp
    dn = 0.0_dp
    select case (etype)
    case (ETYPE_Q4)
      call shape_q4(xi, n(1:4), dn(:, 1:4))
    case (ETYPE_Q8)
      call shape_q8(xi, n(1:8), dn(:, 1:8))
    case (ETYPE_Q9)
      call shape_q9(xi, n(1:9), dn(:, 1:9))
    end select
  end subroutine lagrange_shape

  !> Bilinear: N_A = (1 + xi xi_A)(1 + eta eta_A)/4.
  pure subroutine shape_q4(xi, n, dn)
    real(dp), intent(in) :: xi(:)
    real(dp), intent(out) :: n(:), dn(:,:)
    integer :: a
    real(dp) :: s, t
    do a = 1, 4
      s = 1.0_dp + xi(1)*node_xi(1, a)
      t = 1.0_dp + xi(2)*node_xi(2, a)
      n(a) = 0.25_dp*s*t
      dn(1, a) = 0.25_dp*node_xi(1, a)*t
      dn(2, a) = 0.25_dp*s*node_xi(2, a)
    end do
  end subroutine shape_q4

  !> Serendipity: corners (1 + xi xi_A)(1 + eta eta_A)(xi xi_A + eta eta_A - 1)/4;
  !! midsides with xi_A = 0: (1 - xi^2)(1 + eta eta_A)/2; with eta_A = 0:
  !! (1 + xi xi_A)(1 - eta^2)/2.
  pure subroutine shape_q8(xi, n, dn)
    real(dp), intent(in) :: xi(:)
    real(dp), intent(out) :: n(:), dn(:,:)
    integer :: a
    real(dp) :: xa, ya, s, t, r
    do a = 1, 4
      xa = node_xi(1, a)
      ya = node_xi(2, a)
      s = 1.0_dp + xi(1)*xa
      t = 1.0_dp + xi(2)*ya
      r = xi(1)*xa + xi(2)*ya - 1.0_dp
      n(a) = 0.25_dp*s*t*r
      dn(1, a) = 0.25_dp*xa*t*(r + s)
      dn(2, a) = 0.25_dp*ya*s*(r + t)
    end do
    do a = 5, 8
      xa = node_xi(1, a)
      ya = node_xi(2, a)
      if (xa == 0.0_dp) then
        t = 1.0_dp + xi(2)*ya
        n(a) = 0.5_dp*(1.0_dp - xi(1)**2)*t
        dn(1, a) = -xi(1)*t
        dn(2, a) = 0.5_dp*(1.0_dp - xi(1)**2)*ya
      else
        s = 1.0_dp + xi(1)*xa
        n(a) = 0.5_dp*s*(1.0_dp - xi(2)**2)
        dn(1, a) = 0.5_dp*xa*(1.0_dp - xi(2)**2)
        dn(2, a) = -s*xi(2)
      end if
    end do
  end subroutine shape_q8

  !> Biquadratic Lagrange: tensor product of the 1D quadratics through -1, 0, 1.
  pure subroutine shape_q9(xi, n, dn)
    real(dp), intent(in) :: xi(:)
    real(dp), intent(out) :: n(:), dn(:,:)
    integer :: a
    real(dp) :: l1(3), d1(3), l2(3), d2(3)
    integer :: i, j
    call quad_1d(xi(1), l1, d1)
    call quad_1d(xi(2), l2, d2)
    do a = 1, 9
      ! 1D index 1, 2, 3 for the node coordinate -1, 0, 1
      i = nint(node_xi(1, a)) + 2
      j = nint(node_xi(2, a)) + 2
      n(a) = l1(i)*l2(j)
      dn(1, a) = d1(i)*l2(j)
      dn(2, a) = l1(i)*d2(j)
    end do
  end subroutine shape_q9

  !> 1D quadratic Lagrange polynomials through -1, 0, 1 and their derivatives.
  pure subroutine quad_1d(x, l, d)
    real(dp), intent(in) :: x
    real(dp), intent(out) :: l(3), d(3)
    l(1) = 0.5_dp*x*(x - 1.0_dp)
    l(2) = 1.0_dp - x*x
    l(3) = 0.5_dp*x*(x + 1.0_dp)
    d(1) = x - 0.5_dp
    d(2) = -2.0_dp*x
    d(3) = x + 0.5_dp
  end subroutine quad_1d

  !> Shape data of a Lagrange element type for an ngauss x ngauss Gauss rule.
  !! etype: ETYPE_Q4/Q8/Q9; ngauss: points per direction (1..10);
  !! shp: filled with nen, ngp = ngauss^2, n(nen, ngp), dn(2, nen, ngp), w(ngp) (allocated here;
  !! quadrature points ordered with xi running fastest).
  pure subroutine lagrange_shape_data(etype, ngauss, shp)
    integer, intent(in) :: etype, ngauss
    type(elem_shape_t), intent(out) :: shp
    real(dp), allocatable :: xg(:,:)
    integer :: g
    shp%nen = merge(4, merge(8, 9, etype == ETYPE_Q8), etype == ETYPE_Q4)
    shp%ngp = ngauss*ngauss
    allocate(shp%n(shp%nen, shp%ngp), shp%dn(2, shp%nen, shp%ngp), shp%w(shp%ngp))
    allocate(xg(2, shp%ngp))
    call gauss_rule_2d(ngauss, ngauss, xg, shp%w)
    do g = 1, shp%ngp
      call lagrange_shape(etype, xg(:, g), shp%n(:, g), shp%dn(:, :, g))
    end do
  end subroutine lagrange_shape_data

  !> Local node numbers of face 1..4 in order along the face: corner k, [midside k+4],
  !! corner k+1 (corner 1 after corner 4).
  !! etype: ETYPE_Q4/Q8/Q9; face: 1..4; nodes(nfn) (at least 3 long for Q8/Q9, 2 for Q4):
  !! local node numbers; nfn: 2 (Q4), 3 (Q8/Q9), 0 for an invalid etype or face.
  pure subroutine lagrange_face_nodes(etype, face, nodes, nfn)
    integer, intent(in) :: etype, face
    integer, intent(out) :: nodes(:)
    integer, intent(out) :: nfn
    nodes = 0
    nfn = 0
    if (face < 1 .or. face > 4) return
    select case (etype)
    case (ETYPE_Q4)
      nfn = 2
      nodes(1) = face
      nodes(2) = mod(face, 4) + 1
    case (ETYPE_Q8, ETYPE_Q9)
      nfn = 3
      nodes(1) = face
      nodes(2) = face + 4
      nodes(3) = mod(face, 4) + 1
    end select
  end subroutine lagrange_face_nodes
end module ictus_elements_lagrange
