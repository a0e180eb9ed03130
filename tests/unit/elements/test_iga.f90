!> Unit tests of ictus_elements_iga: NURBS element shape data from Bezier extraction.
program test_iga
  use ictus_core_kinds, only: dp, pi
  use ictus_geometry_patch, only: patch_t, patch_elevate, patch_refine, patch_point, &
      patch_elem_ij, patch_side_elements
  use ictus_geometry_sides, only: SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1
  use ictus_elements_types, only: elem_shape_t
  use ictus_elements_iga, only: iga_shape_data, iga_basis_at
  use ictus_elements_quadrature, only: gauss_legendre
  use ictus_test_check, only: checker_t
  use ictus_test_halfdisc, only: half_disc
  implicit none
  type(checker_t) :: t
  real(dp), parameter :: rr = 4.0_dp, s2 = sqrt(2.0_dp)/2.0_dp

  call t%start("elements/iga")
  call case_gauss(t)
  call case_half_disc_area(t)
  call case_patch_map(t)
  call case_basis_integrals(t)
  call case_side_faces(t)
  call t%finish()

contains


  !> Shape data of element e of a patch.
  subroutine element_shape(q, e, ng, shp)
    type(patch_t), intent(in) :: q
    integer, intent(in) :: e, ng(2)
    type(elem_shape_t), intent(inout) :: shp
    integer :: ij(2)
    ij = patch_elem_ij(q, e)
    call iga_shape_data(q%p, q%c1(:, :, ij(1)), q%c2(:, :, ij(2)), q%cp(3, q%ien(:, e)), ng, shp)
  end subroutine element_shape

  !> Jacobian J(i, j) = d x_i / d xi~_j at quadrature point g from shp%dn and the control points.
  pure function jacobian(q, e, shp, g) result(jac)
    type(patch_t), intent(in) :: q
    integer, intent(in) :: e, g
    type(elem_shape_t), intent(in) :: shp
    real(dp) :: jac(2, 2)
    integer :: a
    jac = 0.0_dp
    do a = 1, shp%nen
      jac(:, 1) = jac(:, 1) + shp%dn(1, a, g)*q%cp(1:2, q%ien(a, e))
      jac(:, 2) = jac(:, 2) + shp%dn(2, a, g)*q%cp(1:2, q%ien(a, e))
    end do
  end function jacobian

  !> Gauss-Legendre: weights sum to 2, exact for x^(2n-2), known 2- and 3-point rules.
  subroutine case_gauss(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: x(12), w(12)
    integer :: n
    call gauss_legendre(2, x(1:2), w(1:2))
    call t%close_abs(x(2), 1.0_dp/sqrt(3.0_dp), 1.0e-15_dp, "2-point abscissa")
    call gauss_legendre(3, x(1:3), w(1:3))
    call t%close_abs(x(3), sqrt(0.6_dp), 1.0e-15_dp, "3-point abscissa")
    call t%close_abs(w(2), 8.0_dp/9.0_dp, 1.0e-15_dp, "3-point centre weight")
    do n = 1, 12
      call gauss_legendre(n, x(1:n), w(1:n))
      call t%close_abs(sum(w(1:n)), 2.0_dp, 1.0e-14_dp, "Gauss weights sum")
      call t%close_abs(sum(w(1:n)*x(1:n)**(2*n-2)), 2.0_dp/real(2*n-1, dp), 1.0e-14_dp, &
          "Gauss exact for x^(2n-2)")
    end do
  end subroutine case_gauss

  !> Area of the half disc = 8 pi (R = 4) by sum w det J, det J of one sign (negative in
  !! this parameter order, doc/iga.md §10.4), before and after refinement and elevation.
  subroutine case_half_disc_area(t)
    type(checker_t), intent(inout) :: t
    type(patch_t) :: q
    type(elem_shape_t) :: shp
    real(dp) :: area, detj, jac(2, 2), dmax, dmin
    integer :: stage, e, g, ng(2)
    call half_disc(q)
    do stage = 1, 5
      select case (stage)
      case (2)
        call patch_refine(q, [2, 2])
      case (3)
        call patch_elevate(q, [3, 3])
      case (4)
        call patch_refine(q, [3, 2])
      case (5)
        call half_disc(q)
        call patch_elevate(q, [3, 4])
        call patch_refine(q, [16, 16])
      end select
      ng = [16, 16]
      if (stage == 5) ng = q%p + 2
      area = 0.0_dp
      dmax = -huge(1.0_dp)
      dmin = huge(1.0_dp)
      do e = 1, q%nel(1)*q%nel(2)
        call element_shape(q, e, ng, shp)
        do g = 1, shp%ngp
          jac = jacobian(q, e, shp, g)
          detj = jac(1, 1)*jac(2, 2) - jac(1, 2)*jac(2, 1)
          dmax = max(dmax, detj)
          dmin = min(dmin, detj)
          area = area + shp%w(g)*abs(detj)
        end do
      end do
      call t%close(area, 8.0_dp*pi, 1.0e-12_dp, "half disc area = 8 pi")
      call t%true(dmax < 0.0_dp, "det J negative at every quadrature point")
    end do
    call t%true(dmin < dmax, "det J varies")
  end subroutine case_half_disc_area

  !> Partition of unity at every quadrature point, sum R_A x_A = patch map, and
  !! sum dR_A/dxi~ x_A = dx/du (hi - lo)/2; iga_basis_at derivatives vs differences.
  subroutine case_patch_map(t)
    type(checker_t), intent(inout) :: t
    type(patch_t) :: q
    type(elem_shape_t) :: shp
    real(dp) :: x(2), xs(2), du(2), dv(2), u(2), xi(2), pu, ex, ed, neg, efd, jac(2, 2)
    real(dp) :: r(16), dr(2, 16), rp(16), rm(16), drp(2, 16), drm(2, 16)
    real(dp) :: gx(3), gw(3)
    real(dp), parameter :: h = 1.0e-6_dp
    integer :: e, g, g1, g2, ij(2), a, d
    call half_disc(q)
    call patch_elevate(q, [3, 2])
    call patch_refine(q, [3, 4])
    call gauss_legendre(3, gx, gw)
    pu = 0.0_dp
    ex = 0.0_dp
    ed = 0.0_dp
    neg = 0.0_dp
    efd = 0.0_dp
    do e = 1, q%nel(1)*q%nel(2)
      ij = patch_elem_ij(q, e)
      call element_shape(q, e, [3, 3], shp)
      call t%equal_int(shp%ngp, 9, "ngp")
      g = 0
      do g2 = 1, 3
        do g1 = 1, 3
          g = g + 1
          call t%close_abs(shp%w(g), gw(g1)*gw(g2), 1.0e-15_dp, "quadrature weight order")
          pu = max(pu, abs(sum(shp%n(:, g)) - 1.0_dp), maxval(abs(sum(shp%dn(:, :, g), 2))))
          neg = min(neg, minval(shp%n(:, g)))
          xs = matmul(q%cp(1:2, q%ien(:, e)), shp%n(:, g))
          u(1) = q%span_lo1(ij(1)) + 0.5_dp*(gx(g1) + 1.0_dp)*(q%span_hi1(ij(1)) &
              - q%span_lo1(ij(1)))
          u(2) = q%span_lo2(ij(2)) + 0.5_dp*(gx(g2) + 1.0_dp)*(q%span_hi2(ij(2)) &
              - q%span_lo2(ij(2)))
          call patch_point(q, u, x, du, dv)
          ex = max(ex, norm2(x - xs))
          jac = jacobian(q, e, shp, g)
          ed = max(ed, norm2(jac(:, 1) - 0.5_dp*du*(q%span_hi1(ij(1)) - q%span_lo1(ij(1)))), &
              norm2(jac(:, 2) - 0.5_dp*dv*(q%span_hi2(ij(2)) - q%span_lo2(ij(2)))))
        end do
      end do
      ! derivatives of iga_basis_at against central differences at an off-grid point
      xi = [0.3_dp, -0.55_dp]
      call iga_basis_at(q%p, q%c1(:, :, ij(1)), q%c2(:, :, ij(2)), q%cp(3, q%ien(:, e)), &
          xi, r(1:q%nen), dr(:, 1:q%nen))
      do d = 1, 2
        xi = [0.3_dp, -0.55_dp]
        xi(d) = xi(d) + h
        call iga_basis_at(q%p, q%c1(:, :, ij(1)), q%c2(:, :, ij(2)), q%cp(3, q%ien(:, e)), &
            xi, rp(1:q%nen), drp(:, 1:q%nen))
        xi(d) = xi(d) - 2*h
        call iga_basis_at(q%p, q%c1(:, :, ij(1)), q%c2(:, :, ij(2)), q%cp(3, q%ien(:, e)), &
            xi, rm(1:q%nen), drm(:, 1:q%nen))
        do a = 1, q%nen
          efd = max(efd, abs((rp(a) - rm(a))/(2*h) - dr(d, a)))
        end do
      end do
    end do
    call t%close_abs(pu, 0.0_dp, 1.0e-14_dp, "partition of unity at quadrature points")
    call t%true(neg >= 0.0_dp, "R non-negative")
    call t%close_abs(ex, 0.0_dp, 1.0e-13_dp, "sum R_A x_A = patch map")
    call t%close_abs(ed, 0.0_dp, 1.0e-12_dp, "parent derivatives = dx/du * span/2")
    call t%close_abs(efd, 0.0_dp, 1.0e-8_dp, "dR/dxi~ vs finite differences")
  end subroutine case_patch_map

  !> doc/iga.md §5: uniform open knots, p = 2, span h: integrals of the basis functions
  !! h/3, 2h/3, h, ..., h, 2h/3, h/3; in 2D on an affine patch they multiply.
  subroutine case_basis_integrals(t)
    type(checker_t), intent(inout) :: t
    type(patch_t) :: q
    type(elem_shape_t) :: shp
    real(dp), parameter :: l1 = 2.0_dp, l2 = 1.5_dp
    real(dp) :: k1(10), k2(8), cp(3, 7*5), jac(2, 2), m(7*5), h1, h2, i1(7), i2(5), err
    integer :: i, j, e, g, a
    k1 = [0.0_dp, 0.0_dp, 0.0_dp, 0.2_dp, 0.4_dp, 0.6_dp, 0.8_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    k2 = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp/3, 2.0_dp/3, 1.0_dp, 1.0_dp, 1.0_dp]
    ! control points at the Greville abscissae -> x = l1 u, y = l2 v (linear precision);
    ! weights all 2 (a constant weight leaves the rational basis equal to the B-splines)
    do j = 1, 5
      do i = 1, 7
        cp(:, i + (j-1)*7) = [l1*(k1(i+1) + k1(i+2))/2, l2*(k2(j+1) + k2(j+2))/2, 2.0_dp]
      end do
    end do
    call q%init('RECT', [2, 2], [7, 5], k1, k2, cp)
    m = 0.0_dp
    do e = 1, q%nel(1)*q%nel(2)
      call element_shape(q, e, [3, 3], shp)
      do g = 1, shp%ngp
        jac = jacobian(q, e, shp, g)
        do a = 1, shp%nen
          m(q%ien(a, e)) = m(q%ien(a, e)) + shp%w(g)*shp%n(a, g)* &
              (jac(1, 1)*jac(2, 2) - jac(1, 2)*jac(2, 1))
        end do
      end do
    end do
    h1 = l1/5
    h2 = l2/3
    i1 = h1*[1.0_dp/3, 2.0_dp/3, 1.0_dp, 1.0_dp, 1.0_dp, 2.0_dp/3, 1.0_dp/3]
    i2 = h2*[1.0_dp/3, 2.0_dp/3, 1.0_dp, 2.0_dp/3, 1.0_dp/3]
    err = 0.0_dp
    do j = 1, 5
      do i = 1, 7
        err = max(err, abs(m(i + (j-1)*7) - i1(i)*i2(j))/(i1(i)*i2(j)))
      end do
    end do
    call t%close_abs(err, 0.0_dp, 1.0e-14_dp, "integrals of R_A = products of h/3, 2h/3, h")
    call t%close(sum(m), l1*l2, 1.0e-14_dp, "integrals sum to the area")
    call t%close(m(1), h1*h2/9, 1.0e-14_dp, "corner rho h^2/9")
    call t%close(m(3), h1*h2/3, 1.0e-14_dp, "edge rho h^2/3")
  end subroutine case_basis_integrals

  !> The parent face reported by patch_side_elements maps onto the side: the face midpoint
  !! equals the patch point with the side's parameter fixed, on the refined half disc.
  subroutine case_side_faces(t)
    type(checker_t), intent(inout) :: t
    type(patch_t) :: q
    integer, allocatable :: el(:), fc(:)
    integer :: sides(4), s, k, nf, ij(2), e
    real(dp) :: xi(2), u(2), x(2), xs(2), r(16), dr(2, 16), err
    real(dp), parameter :: face_xi(2, 4) = reshape([0.0_dp, -1.0_dp, 1.0_dp, 0.0_dp, &
        0.0_dp, 1.0_dp, -1.0_dp, 0.0_dp], [2, 4])
    call half_disc(q)
    call patch_refine(q, [4, 3])
    sides = [SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1]
    err = 0.0_dp
    do s = 1, 4
      call patch_side_elements(q, sides(s), el, fc, nf)
      do k = 1, nf
        e = el(k)
        ij = patch_elem_ij(q, e)
        xi = face_xi(:, fc(k))
        call iga_basis_at(q%p, q%c1(:, :, ij(1)), q%c2(:, :, ij(2)), q%cp(3, q%ien(:, e)), &
            xi, r(1:q%nen), dr(:, 1:q%nen))
        xs = matmul(q%cp(1:2, q%ien(:, e)), r(1:q%nen))
        u(1) = 0.5_dp*(q%span_lo1(ij(1)) + q%span_hi1(ij(1)))
        u(2) = 0.5_dp*(q%span_lo2(ij(2)) + q%span_hi2(ij(2)))
        select case (sides(s))
        case (SIDE_XI0)
          u(1) = q%knots1(1)
        case (SIDE_XI1)
          u(1) = q%knots1(size(q%knots1))
        case (SIDE_ETA0)
          u(2) = q%knots2(1)
        case (SIDE_ETA1)
          u(2) = q%knots2(size(q%knots2))
        end select
        call patch_point(q, u, x)
        err = max(err, norm2(x - xs))
      end do
    end do
    call t%close_abs(err, 0.0_dp, 1.0e-13_dp, "side faces lie on the patch sides")
  end subroutine case_side_faces
end program test_iga
