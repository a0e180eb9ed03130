!> Shape data of a Bezier-extracted NURBS element (one non-empty knot-span rectangle).
!!
!! On the element, N = (C2 (x) C1) B with B the tensor-product Bernstein polynomials of the
!! local variables t_i = (xi~_i + 1)/2, and R_A = w_A N_A / W, W = sum w_B N_B = w_b . B with
!! w_b = C^T w (doc/iga.md §3). Derivatives are taken with respect to the parent
!! coordinates (xi~, eta~) in [-1, 1]^2, so the standard solid element routine
!! (J = sum dR/dxi~ x_A) integrates over the physical span exactly.
module ictus_elements_iga
  use ictus_core_kinds, only: dp
  use ictus_geometry_bezier, only: bernstein
  use ictus_elements_types, only: elem_shape_t, element_kind_t, KERNEL_SOLID2D, KERNEL_SOLID3D
  use ictus_elements_quadrature, only: gauss_legendre
  implicit none
  private
  public :: iga_shape_data, iga_basis_at, iga_kind, iga3_kind, iga3_shape_data, iga3_basis_at

contains

  !> The NURBS span as an element type, for the dispatcher (ictus_elements_library): its nodes,
  !! Gauss rule and shape functions follow from the patch's degrees, span by span. Its four
  !! faces are the sides of the span; results show it on viewing cells (quadrilaterals).
  function iga_kind() result(k)
    type(element_kind_t) :: k
    k%name = 'IGA'
    k%xdmf = 'Quadrilateral'
    k%ndm = 2
    k%ncorner = 4
    k%nface = 4
    k%kernel = KERNEL_SOLID2D
  end function iga_kind

  !> The span of a trivariate patch as an element type: the 3D solid kernel (as the
  !! hexahedra), nodes, Gauss rule and shape functions from the patch's degrees span by span
  !! (iga3_shape_data); its six faces are the faces of the span box; results show it on
  !! viewing cells (hexahedra).
  function iga3_kind() result(k)
    type(element_kind_t) :: k
    k%name = 'IGA'
    k%xdmf = 'Hexahedron'
    k%ndm = 3
    k%ncorner = 8
    k%nface = 6
    k%kernel = KERNEL_SOLID3D
  end function iga3_kind

  !> NURBS basis and parent derivatives at all Gauss points of one element.
  !! @param p degrees (2); @param c1e extraction operator of direction 1 (p1+1, p1+1);
  !! @param c2e extraction operator of direction 2 (p2+1, p2+1); @param wl weights of the
  !! element's control points (nen), direction 1 fastest; @param ngauss Gauss points per
  !! direction (2); @param shp filled: nen, ngp = ngauss1*ngauss2 (direction 1 fastest),
  !! n(nen, ngp), dn(2, nen, ngp), w(ngp) (parent weights, sum 4)
  subroutine iga_shape_data(p, c1e, c2e, wl, ngauss, shp)
    integer, intent(in) :: p(2), ngauss(2)
    real(dp), intent(in) :: c1e(:,:), c2e(:,:), wl(:)
    type(elem_shape_t), intent(inout) :: shp
    real(dp) :: x1(ngauss(1)), w1(ngauss(1)), x2(ngauss(2)), w2(ngauss(2))
    integer :: nen, g1, g2, g
    nen = (p(1) + 1)*(p(2) + 1)
    call gauss_legendre(ngauss(1), x1, w1)
    call gauss_legendre(ngauss(2), x2, w2)
    shp%nen = nen
    shp%ngp = ngauss(1)*ngauss(2)
    if (allocated(shp%n)) deallocate(shp%n)
    if (allocated(shp%dn)) deallocate(shp%dn)
    if (allocated(shp%w)) deallocate(shp%w)
    allocate(shp%n(nen, shp%ngp), shp%dn(2, nen, shp%ngp), shp%w(shp%ngp))
    g = 0
    do g2 = 1, ngauss(2)
      do g1 = 1, ngauss(1)
        g = g + 1
        call iga_basis_at(p, c1e, c2e, wl, [x1(g1), x2(g2)], shp%n(:, g), shp%dn(:, :, g))
        shp%w(g) = w1(g1)*w2(g2)
      end do
    end do
  end subroutine iga_shape_data

  !> NURBS basis of one element at parent coordinates xi(2) in [-1, 1]^2.
  !! @param p degrees (2); @param c1e (p1+1, p1+1); @param c2e (p2+1, p2+1);
  !! @param wl weights (nen), direction 1 fastest; @param xi parent coordinates (2);
  !! @param r R_A (nen); @param dr dR_A/d(xi~, eta~) (2, nen)
  pure subroutine iga_basis_at(p, c1e, c2e, wl, xi, r, dr)
    integer, intent(in) :: p(2)
    real(dp), intent(in) :: c1e(:,:), c2e(:,:), wl(:), xi(2)
    real(dp), intent(out) :: r(:), dr(:,:)
    real(dp) :: b1(p(1)+1), db1(p(1)+1), b2(p(2)+1), db2(p(2)+1)
    real(dp) :: n1(p(1)+1), dn1(p(1)+1), n2(p(2)+1), dn2(p(2)+1)
    real(dp) :: ww, dw(2), nn, dnn(2)
    integer :: a1, a2, k
    call bernstein(p(1), 0.5_dp*(xi(1) + 1.0_dp), b1, db1)
    call bernstein(p(2), 0.5_dp*(xi(2) + 1.0_dp), b2, db2)
    ! B-splines on the span; d/dxi~ = (1/2) d/dt
    n1 = matmul(c1e, b1)
    dn1 = 0.5_dp*matmul(c1e, db1)
    n2 = matmul(c2e, b2)
    dn2 = 0.5_dp*matmul(c2e, db2)
    ww = 0.0_dp
    dw = 0.0_dp
    k = 0
    do a2 = 1, p(2) + 1
      do a1 = 1, p(1) + 1
        k = k + 1
        r(k) = wl(k)*n1(a1)*n2(a2)
        dr(1, k) = wl(k)*dn1(a1)*n2(a2)
        dr(2, k) = wl(k)*n1(a1)*dn2(a2)
        ww = ww + r(k)
        dw = dw + dr(:, k)
      end do
    end do
    do k = 1, (p(1) + 1)*(p(2) + 1)
      nn = r(k)
      dnn = dr(:, k)
      r(k) = nn/ww
      dr(:, k) = (dnn*ww - nn*dw)/ww**2
    end do
  end subroutine iga_basis_at

  !> NURBS basis and parent derivatives at all Gauss points (ngauss(3) per direction) of one
  !! element of a trivariate patch (ictus_geometry_volume): degrees p(3), extraction operators
  !! c1e, c2e, c3e of its spans, weights wl of its control points (direction 1 fastest).
  subroutine iga3_shape_data(p, c1e, c2e, c3e, wl, ngauss, shp)
    integer, intent(in) :: p(3), ngauss(3)
    real(dp), intent(in) :: c1e(:,:), c2e(:,:), c3e(:,:), wl(:)
    type(elem_shape_t), intent(inout) :: shp
    real(dp) :: x1(ngauss(1)), w1(ngauss(1)), x2(ngauss(2)), w2(ngauss(2)), x3(ngauss(3)), &
        w3(ngauss(3))
    integer :: g1, g2, g3, g
    call gauss_legendre(ngauss(1), x1, w1)
    call gauss_legendre(ngauss(2), x2, w2)
    call gauss_legendre(ngauss(3), x3, w3)
    shp%nen = product(p + 1)
    shp%ngp = product(ngauss)
    if (allocated(shp%n)) deallocate(shp%n)
    if (allocated(shp%dn)) deallocate(shp%dn)
    if (allocated(shp%w)) deallocate(shp%w)
    allocate(shp%n(shp%nen, shp%ngp), shp%dn(3, shp%nen, shp%ngp), shp%w(shp%ngp))
    g = 0
    do g3 = 1, ngauss(3)
      do g2 = 1, ngauss(2)
        do g1 = 1, ngauss(1)
          g = g + 1
          call iga3_basis_at(p, c1e, c2e, c3e, wl, [x1(g1), x2(g2), x3(g3)], shp%n(:, g), &
              shp%dn(:, :, g))
          shp%w(g) = w1(g1)*w2(g2)*w3(g3)
        end do
      end do
    end do
  end subroutine iga3_shape_data

  !> NURBS basis r(nen) and parent derivatives dr(3, nen) of one trivariate element at
  !! xi(3) in [-1, 1]^3: R_A = w_A N_A / sum_B w_B N_B with N_(a1,a2,a3) the products of the
  !! span B-splines sum_j C(a, j) B_j of each direction.
  pure subroutine iga3_basis_at(p, c1e, c2e, c3e, wl, xi, r, dr)
    integer, intent(in) :: p(3)
    real(dp), intent(in) :: c1e(:,:), c2e(:,:), c3e(:,:), wl(:), xi(3)
    real(dp), intent(out) :: r(:), dr(:,:)
    real(dp) :: n(maxval(p) + 1, 3), dn(maxval(p) + 1, 3), ww, dw(3)
    integer :: a1, a2, a3, k
    call span_basis(p(1), c1e, xi(1), n(:, 1), dn(:, 1))
    call span_basis(p(2), c2e, xi(2), n(:, 2), dn(:, 2))
    call span_basis(p(3), c3e, xi(3), n(:, 3), dn(:, 3))
    ww = 0.0_dp
    dw = 0.0_dp
    k = 0
    do a3 = 1, p(3) + 1
      do a2 = 1, p(2) + 1
        do a1 = 1, p(1) + 1
          k = k + 1
          r(k) = wl(k)*n(a1, 1)*n(a2, 2)*n(a3, 3)
          dr(1, k) = wl(k)*dn(a1, 1)*n(a2, 2)*n(a3, 3)
          dr(2, k) = wl(k)*n(a1, 1)*dn(a2, 2)*n(a3, 3)
          dr(3, k) = wl(k)*n(a1, 1)*n(a2, 2)*dn(a3, 3)
          ww = ww + r(k)
          dw = dw + dr(:, k)
        end do
      end do
    end do
    do k = 1, product(p + 1)
      dr(:, k) = (dr(:, k)*ww - r(k)*dw)/ww**2
      r(k) = r(k)/ww
    end do
  end subroutine iga3_basis_at

  !> B-splines n(p+1) of one span (extraction operator c) and their derivatives d/dxi at
  !! xi in [-1, 1].
  pure subroutine span_basis(p, c, xi, n, dn)
    integer, intent(in) :: p
    real(dp), intent(in) :: c(:,:), xi
    real(dp), intent(out) :: n(:), dn(:)
    real(dp) :: b(p + 1), db(p + 1)
    call bernstein(p, 0.5_dp*(xi + 1.0_dp), b, db)
    n(1:p + 1) = matmul(c(1:p + 1, 1:p + 1), b)
    dn(1:p + 1) = 0.5_dp*matmul(c(1:p + 1, 1:p + 1), db)
  end subroutine span_basis
end module ictus_elements_iga
