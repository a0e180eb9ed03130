!> Trivariate NURBS patches (ictus_geometry_volume) and their elements (iga3_basis_at):
!! the exact quarter-ball of scripts/mesh/quarter_ball.py, one quadratic patch of SIZE=3,5,3 in
!! spherical coordinates about the x axis (direction 1: the polar angle from +x to the plane
!! x = 0; direction 2: the azimuth from -z through +y to +z, two quarter circles; direction 3:
!! the radius), degenerate on the x-axis segment and at the centre.
!! * Its volume, by 14^3 Gauss points of det J per Bezier element, is pi R^3/3 to 1e-12,
!!   before and after knot insertion (2, 3, 2 spans per span) and degree elevation (+1 in each
!!   direction): refinement keeps the geometry.
!! * The basis is a partition of unity with derivatives summing to 0; points of the side
!!   zeta = 1 lie at radius R (1e-13).
program test_iga3d
  use ictus_core_kinds, only: dp, pi
  use ictus_test_check, only: checker_t
  use ictus_geometry_volume, only: volume_t, volume_init, volume_refine, volume_elevate, &
      volume_side_points, volume_elem_ijk
  use ictus_geometry_sides, only: SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ZETA0, &
      SIDE_ZETA1, SIDE_ALL
  use ictus_elements_iga, only: iga3_basis_at
  use ictus_elements_quadrature, only: gauss_legendre
  implicit none
  real(dp), parameter :: rb = 1.7_dp, c0(3) = [0.3_dp, -0.4_dp, 2.0_dp]
  type(checker_t) :: t
  type(volume_t) :: v
  call t%start("elements/iga3d")
  call quarter_ball(v)
  call check_volume(t, v, 'coarse 1 x 2 x 1 spans')
  call check_sides(t, v)
  call volume_refine(v, [2, 3, 2])
  call check_volume(t, v, 'refined 2 x 6 x 2')
  call volume_elevate(v, [1, 1, 1])
  call check_volume(t, v, 'elevated to p = 3')
  call t%equal_int(v%nel(2), 6, 'elevation keeps the spans')
  call t%true(all(v%p == 3), 'degrees 3')
  call t%finish()

contains

  subroutine quarter_ball(v)
    type(volume_t), intent(out) :: v
    real(dp), parameter :: s = sqrt(0.5_dp)
    ! polar profile (x, rho, w) and azimuth circle (y, z, w)
    real(dp), parameter :: prof(3, 3) = reshape([1.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, s, &
        0.0_dp, 1.0_dp, 1.0_dp], [3, 3])
    real(dp), parameter :: azi(3, 5) = reshape([0.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, s, &
        1.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, s, 0.0_dp, 1.0_dp, 1.0_dp], [3, 5])
    real(dp) :: cp(4, 45), r
    integer :: i, j, k, m
    m = 0
    do k = 1, 3
      r = rb*0.5_dp*real(k - 1, dp)
      do j = 1, 5
        do i = 1, 3
          m = m + 1
          cp(1:3, m) = c0 + r*[prof(1, i), prof(2, i)*azi(1, j), prof(2, i)*azi(2, j)]
          cp(4, m) = prof(3, i)*azi(3, j)
        end do
      end do
    end do
    call volume_init(v, 'BALL', [2, 2, 2], [3, 5, 3], [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, &
        1.0_dp, 1.0_dp], [0.0_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.5_dp, 1.0_dp, 1.0_dp, 1.0_dp], &
        [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], cp)
  end subroutine quarter_ball

  !> Volume by 14^3 Gauss points per element against pi R^3/3; partition of unity; points
  !! of the last elements' zeta = 1 faces at radius R.
  subroutine check_volume(t, v, label)
    type(checker_t), intent(inout) :: t
    type(volume_t), intent(in) :: v
    character(len=*), intent(in) :: label
    integer, parameter :: ng = 14
    real(dp) :: gx(ng), gw(ng), r(64), dr(3, 64), jm(3, 3), vol, xp(3), worst, wsum
    integer :: e, i1, i2, i3, g1, g2, g3, a
    call gauss_legendre(ng, gx, gw)
    vol = 0.0_dp
    worst = 0.0_dp
    wsum = 0.0_dp
    do i3 = 1, v%nel(3)
      do i2 = 1, v%nel(2)
        do i1 = 1, v%nel(1)
          e = i1 + v%nel(1)*(i2 - 1) + v%nel(1)*v%nel(2)*(i3 - 1)
          do g3 = 1, ng
            do g2 = 1, ng
              do g1 = 1, ng
                call iga3_basis_at(v%p, v%c1(:, :, i1), v%c2(:, :, i2), v%c3(:, :, i3), &
                    v%cp(4, v%ien(:, e)), [gx(g1), gx(g2), gx(g3)], r, dr)
                wsum = max(wsum, abs(sum(r(1:v%nen)) - 1.0_dp), &
                    maxval(abs(sum(dr(:, 1:v%nen), dim=2))))
                jm = 0.0_dp
                do a = 1, v%nen
                  jm = jm + spread(v%cp(1:3, v%ien(a, e)), 2, 3)*spread(dr(:, a), 1, 3)
                end do
                ! the derivatives are with respect to the parent cube: dV = det(dx/dxi) dxi
                vol = vol + gw(g1)*gw(g2)*gw(g3)*det3(jm)
              end do
            end do
          end do
          if (i3 == v%nel(3)) then
            do g2 = 1, ng
              do g1 = 1, ng
                call iga3_basis_at(v%p, v%c1(:, :, i1), v%c2(:, :, i2), v%c3(:, :, i3), &
                    v%cp(4, v%ien(:, e)), [gx(g1), gx(g2), 1.0_dp], r, dr)
                xp = matmul(v%cp(1:3, v%ien(:, e)), r(1:v%nen))
                worst = max(worst, abs(norm2(xp - c0) - rb))
              end do
            end do
          end if
        end do
      end do
    end do
    call t%close(vol, pi*rb**3/3.0_dp, 1.0e-12_dp, label//': volume pi R^3/3')
    call t%close_abs(worst, 0.0_dp, 1.0e-13_dp, label//': the zeta = 1 side on the sphere')
    call t%close_abs(wsum, 0.0_dp, 1.0e-13_dp, label//': partition of unity')
  end subroutine check_volume

  !> The faces of the coarse quarter-ball (3 x 5 x 3 control points): XI0 is the x axis
  !! segment and ZETA0 the centre (collapsed), XI1 lies in the plane x = cx, ZETA1 on the
  !! sphere; ALL is every control point but the 1 x 3 x 1 interior ones; and the span
  !! indices of the elements.
  subroutine check_sides(t, v)
    type(checker_t), intent(inout) :: t
    type(volume_t), intent(in) :: v
    integer, allocatable :: idx(:)
    integer :: n, k, counts(7)
    integer, parameter :: sides(7) = [SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ZETA0, &
        SIDE_ZETA1, SIDE_ALL]
    do k = 1, 7
      call volume_side_points(v, sides(k), idx, counts(k))
    end do
    call t%true(all(counts == [15, 15, 9, 9, 15, 15, 42]), 'sides: control points per face')
    call volume_side_points(v, SIDE_XI0, idx, n)
    call t%close_abs(maxval(abs(v%cp(2:3, idx) - spread(c0(2:3), 2, n))), 0.0_dp, 1.0e-15_dp, &
        'sides: XI0 on the x axis through the centre')
    call volume_side_points(v, SIDE_ZETA0, idx, n)
    call t%close_abs(maxval(abs(v%cp(1:3, idx) - spread(c0, 2, n))), 0.0_dp, 1.0e-15_dp, &
        'sides: ZETA0 at the centre')
    call volume_side_points(v, SIDE_XI1, idx, n)
    call t%close_abs(maxval(abs(v%cp(1, idx) - c0(1))), 0.0_dp, 1.0e-15_dp, &
        'sides: XI1 in the plane x = cx')
    call volume_side_points(v, SIDE_ZETA1, idx, n)
    call t%true(all(idx == [(k, k = 31, 45)]), 'sides: ZETA1 the last layer of direction 3')
    call t%true(all(volume_elem_ijk(v, 2) == [1, 2, 1]), 'element 2 is span (1, 2, 1)')
  end subroutine check_sides

  pure real(dp) function det3(a)
    real(dp), intent(in) :: a(3, 3)
    det3 = a(1, 1)*(a(2, 2)*a(3, 3) - a(2, 3)*a(3, 2)) - a(1, 2)*(a(2, 1)*a(3, 3) - &
        a(2, 3)*a(3, 1)) + a(1, 3)*(a(2, 1)*a(3, 2) - a(2, 2)*a(3, 1))
  end function det3
end program test_iga3d
