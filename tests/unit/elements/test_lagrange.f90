!> Q4/Q8/Q9 shape functions: partition of unity, Kronecker delta, derivatives against finite
!! differences, polynomial reproduction, linear completeness on a curved element, faces.
program test_lagrange
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, elem_shape_t, element_kind_t
  use ictus_elements_library, only: etype_name, etype_nen, element_kind
  use ictus_elements_lagrange, only: lagrange_shape, lagrange_shape_data, lagrange_face_nodes
  use ictus_test_check, only: checker_t
  use ictus_test_elements, only: check_shape_functions
  implicit none
  type(checker_t) :: t
  integer, parameter :: types(3) = [ETYPE_Q4, ETYPE_Q8, ETYPE_Q9]
  !> Parent coordinates of the nodes in deck order (corners ccw, midsides 5..8, centre 9).
  real(dp), parameter :: xnode(2, 9) = reshape([-1.0_dp, -1.0_dp, 1.0_dp, -1.0_dp, &
      1.0_dp, 1.0_dp, -1.0_dp, 1.0_dp, 0.0_dp, -1.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, &
      -1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], [2, 9])
  !> Test points inside the parent square (and two on its boundary).
  real(dp), parameter :: pts(2, 6) = reshape([0.13_dp, -0.71_dp, -0.52_dp, 0.33_dp, &
      0.91_dp, 0.87_dp, -0.05_dp, 0.0_dp, 1.0_dp, 0.4_dp, -0.3_dp, -1.0_dp], [2, 6])
  type(element_kind_t) :: kd
  integer :: k
  call t%start("elements/lagrange")
  do k = 1, 3
    kd = element_kind(types(k))
    call check_shape_functions(t, etype_name(types(k)), kd%shape, xnode(:, 1:kd%nen), pts)
    call case_reproduction(t, types(k))
    call case_curved_linear(t, types(k))
    call case_shape_data(t, types(k))
  end do
  call case_faces(t)
  call t%finish()

contains

  !> Each element interpolates exactly the monomials of its space: Q4 {1, xi, eta, xi eta};
  !! Q8 adds xi^2, eta^2, xi^2 eta, xi eta^2; Q9 adds xi^2 eta^2. The derivative of the
  !! interpolant equals the derivative of the monomial. Q8 must NOT reproduce xi^2 eta^2.
  subroutine case_reproduction(t, et)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    integer, parameter :: pw(2, 9) = reshape([0, 0, 1, 0, 0, 1, 1, 1, 2, 0, 0, 2, 2, 1, 1, 2, &
        2, 2], [2, 9])
    real(dp) :: n(9), dn(2, 9), f(9), x(2), want, dwant(2)
    integer :: nen, nmono, m, p, a
    nen = etype_nen(et)
    nmono = nen
    do m = 1, nmono
      do a = 1, nen
        f(a) = xnode(1, a)**pw(1, m)*xnode(2, a)**pw(2, m)
      end do
      do p = 1, size(pts, 2)
        x = pts(:, p)
        call lagrange_shape(et, x, n(1:nen), dn(:, 1:nen))
        want = x(1)**pw(1, m)*x(2)**pw(2, m)
        dwant(1) = real(pw(1, m), dp)*x(1)**max(pw(1, m) - 1, 0)*x(2)**pw(2, m)
        dwant(2) = real(pw(2, m), dp)*x(1)**pw(1, m)*x(2)**max(pw(2, m) - 1, 0)
        call t%close_abs(sum(n(1:nen)*f(1:nen)), want, 1.0e-14_dp, &
            etype_name(et)//' reproduces monomial')
        call t%close_abs(sum(dn(1, 1:nen)*f(1:nen)), dwant(1), 1.0e-14_dp, &
            etype_name(et)//' reproduces d/dxi')
        call t%close_abs(sum(dn(2, 1:nen)*f(1:nen)), dwant(2), 1.0e-14_dp, &
            etype_name(et)//' reproduces d/deta')
      end do
    end do
    if (et == ETYPE_Q8) then
      do a = 1, nen
        f(a) = xnode(1, a)**2*xnode(2, a)**2
      end do
      x = [0.5_dp, 0.5_dp]
      call lagrange_shape(et, x, n(1:nen), dn(:, 1:nen))
      call t%true(abs(sum(n(1:nen)*f(1:nen)) - 0.0625_dp) > 0.01_dp, &
          'Q8 does not reproduce xi^2 eta^2')
    end if
  end subroutine case_reproduction

  !> Curved, distorted element: nodal values of a linear field f = c + g.x interpolate to
  !! c + g.x(xi) with x(xi) = sum N_A x_A, and the Cartesian gradient of the interpolant is g.
  subroutine case_curved_linear(t, et)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    real(dp), parameter :: c = 0.7_dp, g(2) = [1.3_dp, -2.1_dp]
    real(dp) :: xl(2, 9), n(9), dn(2, 9), f(9), x(2), jac(2, 2), grad_xi(2), grad_x(2), detj
    integer :: nen, a, p
    nen = etype_nen(et)
    ! distorted quadrilateral ...
    xl(:, 1) = [0.0_dp, 0.0_dp]
    xl(:, 2) = [2.2_dp, 0.3_dp]
    xl(:, 3) = [2.5_dp, 1.9_dp]
    xl(:, 4) = [-0.2_dp, 1.6_dp]
    ! ... with midside nodes pushed off the chords (curved sides) and an off-centre centre
    xl(:, 5) = 0.5_dp*(xl(:, 1) + xl(:, 2)) + [0.05_dp, -0.2_dp]
    xl(:, 6) = 0.5_dp*(xl(:, 2) + xl(:, 3)) + [0.15_dp, 0.05_dp]
    xl(:, 7) = 0.5_dp*(xl(:, 3) + xl(:, 4)) + [0.1_dp, 0.12_dp]
    xl(:, 8) = 0.5_dp*(xl(:, 4) + xl(:, 1)) + [0.1_dp, 0.0_dp]
    xl(:, 9) = 0.25_dp*sum(xl(:, 1:4), dim=2) + [0.07_dp, -0.04_dp]
    do a = 1, nen
      f(a) = c + dot_product(g, xl(:, a))
    end do
    do p = 1, size(pts, 2)
      call lagrange_shape(et, pts(:, p), n(1:nen), dn(:, 1:nen))
      x = matmul(xl(:, 1:nen), n(1:nen))
      ! nine terms of order 1 with cancellation: a few ulps (Release builds sum differently)
      call t%close(sum(n(1:nen)*f(1:nen)), c + dot_product(g, x), 1.0e-13_dp, &
          etype_name(et)//' curved: linear field')
      jac = matmul(dn(:, 1:nen), transpose(xl(:, 1:nen)))
      detj = jac(1, 1)*jac(2, 2) - jac(1, 2)*jac(2, 1)
      call t%true(detj > 0.0_dp, etype_name(et)//' curved: det J > 0')
      grad_xi = matmul(dn(:, 1:nen), f(1:nen))
      ! solve J grad_x = grad_xi
      grad_x(1) = (jac(2, 2)*grad_xi(1) - jac(1, 2)*grad_xi(2))/detj
      grad_x(2) = (-jac(2, 1)*grad_xi(1) + jac(1, 1)*grad_xi(2))/detj
      call t%close(grad_x(1), g(1), 1.0e-13_dp, etype_name(et)//' curved: df/dx')
      call t%close(grad_x(2), g(2), 1.0e-13_dp, etype_name(et)//' curved: df/dy')
    end do
  end subroutine case_curved_linear

  subroutine case_shape_data(t, et)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    type(elem_shape_t) :: shp
    real(dp) :: n(9), dn(2, 9)
    integer :: nen
    nen = etype_nen(et)
    call lagrange_shape_data(et, 3, shp)
    call t%equal_int(shp%nen, nen, etype_name(et)//' shape data nen')
    call t%equal_int(shp%ngp, 9, etype_name(et)//' shape data ngp')
    call t%true(size(shp%n, 1) == nen .and. size(shp%n, 2) == 9 .and. &
        size(shp%dn, 2) == nen .and. size(shp%w) == 9, etype_name(et)//' shape data sizes')
    call t%close(sum(shp%w), 4.0_dp, 1.0e-14_dp, etype_name(et)//' shape data weights')
    ! point 2 of the 3x3 rule is (0, -sqrt(3/5)) (xi fastest)
    call lagrange_shape(et, [0.0_dp, -sqrt(0.6_dp)], n(1:nen), dn(:, 1:nen))
    call t%close_abs(maxval(abs(shp%n(:, 2) - n(1:nen))), 0.0_dp, 1.0e-15_dp, &
        etype_name(et)//' shape data point 2 values')
    call t%close_abs(maxval(abs(shp%dn(:, :, 2) - dn(:, 1:nen))), 0.0_dp, 1.0e-15_dp, &
        etype_name(et)//' shape data point 2 derivatives')
  end subroutine case_shape_data

  subroutine case_faces(t)
    type(checker_t), intent(inout) :: t
    integer :: nodes(3), nfn
    call lagrange_face_nodes(ETYPE_Q4, 4, nodes, nfn)
    call t%equal_int(nfn, 2, 'Q4 face nfn')
    call t%true(all(nodes(1:2) == [4, 1]), 'Q4 face 4 = (4, 1)')
    call lagrange_face_nodes(ETYPE_Q4, 2, nodes, nfn)
    call t%true(all(nodes(1:2) == [2, 3]), 'Q4 face 2 = (2, 3)')
    call lagrange_face_nodes(ETYPE_Q8, 1, nodes, nfn)
    call t%equal_int(nfn, 3, 'Q8 face nfn')
    call t%true(all(nodes == [1, 5, 2]), 'Q8 face 1 = (1, 5, 2)')
    call lagrange_face_nodes(ETYPE_Q9, 3, nodes, nfn)
    call t%true(all(nodes == [3, 7, 4]), 'Q9 face 3 = (3, 7, 4)')
    call lagrange_face_nodes(ETYPE_Q9, 4, nodes, nfn)
    call t%true(all(nodes == [4, 8, 1]), 'Q9 face 4 = (4, 8, 1)')
    call lagrange_face_nodes(ETYPE_Q8, 5, nodes, nfn)
    call t%equal_int(nfn, 0, 'invalid face')
  end subroutine case_faces
end program test_lagrange
