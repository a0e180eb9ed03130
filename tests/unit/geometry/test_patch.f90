!> Unit tests of ictus_geometry_patch: elements (ien, spans, extraction), boundary of the
!! half-disc patch, sides and side elements of a 4 x 3-span patch.
program test_patch
  use ictus_core_kinds, only: dp, pi
  use ictus_geometry_sides, only: SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ALL, &
      SIDE_NONE
  use ictus_geometry_patch, only: patch_t, patch_elevate, patch_refine, patch_point, &
      patch_side_points, patch_side_elements, patch_elem_ij
  use ictus_test_check, only: checker_t
  use ictus_test_halfdisc, only: half_disc
  implicit none
  type(checker_t) :: t
  real(dp), parameter :: rr = 4.0_dp, s2 = sqrt(2.0_dp)/2.0_dp

  call t%start("geometry/patch")
  call case_half_disc_boundary(t)
  call case_grid_elements(t)
  call case_sides(t)
  call t%finish()

contains


  !> Radius error along the three arcs (xi = 0, eta = 1, xi = 1), x = 0 along the cut, and
  !! the derivatives at A; before and after refinement and elevation.
  subroutine case_half_disc_boundary(t)
    type(checker_t), intent(inout) :: t
    type(patch_t) :: q
    integer :: stage
    real(dp) :: x(2), du(2), dv(2)
    call half_disc(q)
    call t%equal_int(q%nel(1)*q%nel(2), 1, "half disc: one element")
    call t%equal_int(q%nen, 9, "half disc: nen")
    call t%true(all(q%ien(:, 1) == [1, 2, 3, 4, 5, 6, 7, 8, 9]), "half disc: ien")
    do stage = 1, 3
      if (stage == 2) call patch_refine(q, [3, 5])
      if (stage == 3) call patch_elevate(q, [3, 4])
      call check_boundary(t, q)
      call patch_point(q, [0.0_dp, 0.0_dp], x, du, dv)
      call t%close_abs(norm2(x - [0.0_dp, -rr]), 0.0_dp, 1.0e-15_dp, "A = (0, -R)")
      call t%close_abs(norm2(du - [0.0_dp, 8.0_dp]), 0.0_dp, 1.0e-13_dp, "dx/dxi at A")
      call t%close_abs(norm2(dv - [8.0_dp*sin(pi/8.0_dp), 0.0_dp]), 0.0_dp, 1.0e-13_dp, &
          "dx/deta at A")
    end do
    ! G1 = corner (xi, eta) = (0, 1), B = (1, 0)
    call patch_point(q, [0.0_dp, 1.0_dp], x)
    call t%close_abs(norm2(x - [rr*s2, -rr*s2]), 0.0_dp, 1.0e-14_dp, "G1")
    call patch_point(q, [1.0_dp, 0.0_dp], x)
    call t%close_abs(norm2(x - [0.0_dp, rr]), 0.0_dp, 1.0e-14_dp, "B")
  end subroutine case_half_disc_boundary

  subroutine check_boundary(t, q)
    type(checker_t), intent(inout) :: t
    type(patch_t), intent(in) :: q
    real(dp) :: x(2), s, e_arc, e_cut
    integer :: i
    e_arc = 0.0_dp
    e_cut = 0.0_dp
    do i = 0, 500
      s = real(i, dp)/500.0_dp
      call patch_point(q, [0.0_dp, s], x)
      e_arc = max(e_arc, abs(norm2(x) - rr))
      call patch_point(q, [s, 1.0_dp], x)
      e_arc = max(e_arc, abs(norm2(x) - rr))
      call patch_point(q, [1.0_dp, s], x)
      e_arc = max(e_arc, abs(norm2(x) - rr))
      call patch_point(q, [s, 0.0_dp], x)
      e_cut = max(e_cut, abs(x(1)))
    end do
    call t%close_abs(e_arc, 0.0_dp, 1.0e-13_dp, "boundary radius error")
    call t%close_abs(e_cut, 0.0_dp, 1.0e-13_dp, "cut edge x = 0")
  end subroutine check_boundary

  !> A p = (2,2) patch with 4 x 3 uniform spans on [0,1]^2: n = (6, 5).
  subroutine grid_patch(q)
    type(patch_t), intent(inout) :: q
    real(dp) :: cp(3, 30)
    integer :: i, j
    do j = 1, 5
      do i = 1, 6
        cp(:, i + (j-1)*6) = [real(i, dp), real(j, dp) + 0.1_dp*real(i, dp), 1.0_dp]
      end do
    end do
    call q%init('GRID', [2, 2], [6, 5], &
        [0.0_dp, 0.0_dp, 0.0_dp, 0.25_dp, 0.5_dp, 0.75_dp, 1.0_dp, 1.0_dp, 1.0_dp], &
        [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp/3, 2.0_dp/3, 1.0_dp, 1.0_dp, 1.0_dp], cp)
  end subroutine grid_patch

  subroutine case_grid_elements(t)
    type(checker_t), intent(inout) :: t
    type(patch_t) :: q
    integer :: ij(2)
    call grid_patch(q)
    call t%equal_int(q%nel(1), 4, "grid nel1")
    call t%equal_int(q%nel(2), 3, "grid nel2")
    call t%equal_int(size(q%ien, 2), 12, "grid elements")
    call t%equal_int(size(q%c1, 3), 4, "grid c1")
    call t%equal_int(size(q%c2, 3), 3, "grid c2")
    ! element 6 = (i1, i2) = (2, 2): control points 2..4 x 2..4
    ij = patch_elem_ij(q, 6)
    call t%true(all(ij == [2, 2]), "element 6 is (2,2)")
    call t%true(all(q%ien(:, 6) == [8, 9, 10, 14, 15, 16, 20, 21, 22]), "ien of element 6")
    call t%true(all(q%ien(:, 1) == [1, 2, 3, 7, 8, 9, 13, 14, 15]), "ien of element 1")
    call t%true(all(q%ien(:, 12) == [16, 17, 18, 22, 23, 24, 28, 29, 30]), "ien of element 12")
    call t%close_abs(q%span_lo1(2), 0.25_dp, 0.0_dp, "span_lo1(2)")
    call t%close_abs(q%span_hi1(2), 0.5_dp, 0.0_dp, "span_hi1(2)")
    call t%close_abs(q%span_lo2(3), 2.0_dp/3, 1.0e-16_dp, "span_lo2(3)")
    call t%close_abs(q%span_hi2(3), 1.0_dp, 0.0_dp, "span_hi2(3)")
    ! first element operator of a uniform open p = 2 knot vector (Borden et al. 2011):
    ! N1 = B1, N2 = B2 + B3/2, N3 = B3/2 (rows of C; reshape fills columns)
    call t%close_abs(maxval(abs(q%c1(:, :, 1) - reshape([1.0_dp, 0.0_dp, 0.0_dp, &
        0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.5_dp], [3, 3]))), 0.0_dp, 1.0e-15_dp, &
        "C^1 of uniform p = 2")
    call patch_refine(q, [2, 1])
    call t%equal_int(q%nel(1), 8, "refined nel1")
    call t%equal_int(q%nel(2), 3, "refined nel2")
    call t%equal_int(q%n(1), 10, "refined n1")
  end subroutine case_grid_elements

  subroutine case_sides(t)
    type(checker_t), intent(inout) :: t
    type(patch_t) :: q
    integer, allocatable :: idx(:), el(:), fc(:)
    integer :: n, nf, k, e, ij(2)
    call grid_patch(q)
    call patch_side_points(q, SIDE_XI0, idx, n)
    call t%true(n == 5 .and. all(idx == [1, 7, 13, 19, 25]), "points XI0")
    call patch_side_points(q, SIDE_XI1, idx, n)
    call t%true(n == 5 .and. all(idx == [6, 12, 18, 24, 30]), "points XI1")
    call patch_side_points(q, SIDE_ETA0, idx, n)
    call t%true(n == 6 .and. all(idx == [1, 2, 3, 4, 5, 6]), "points ETA0")
    call patch_side_points(q, SIDE_ETA1, idx, n)
    call t%true(n == 6 .and. all(idx == [25, 26, 27, 28, 29, 30]), "points ETA1")
    call patch_side_points(q, SIDE_ALL, idx, n)
    call t%true(n == 18 .and. all(idx == [1, 2, 3, 4, 5, 6, 12, 18, 24, 30, 29, 28, 27, &
        26, 25, 19, 13, 7]), "points ALL")
    call patch_side_points(q, SIDE_NONE, idx, n)
    call t%equal_int(n, 0, "points of no side")

    call patch_side_elements(q, SIDE_XI0, el, fc, nf)
    call t%true(nf == 3 .and. all(el == [1, 5, 9]) .and. all(fc == 4), "elements XI0")
    call patch_side_elements(q, SIDE_XI1, el, fc, nf)
    call t%true(nf == 3 .and. all(el == [4, 8, 12]) .and. all(fc == 2), "elements XI1")
    call patch_side_elements(q, SIDE_ETA0, el, fc, nf)
    call t%true(nf == 4 .and. all(el == [1, 2, 3, 4]) .and. all(fc == 1), "elements ETA0")
    call patch_side_elements(q, SIDE_ETA1, el, fc, nf)
    call t%true(nf == 4 .and. all(el == [9, 10, 11, 12]) .and. all(fc == 3), "elements ETA1")
    call patch_side_elements(q, SIDE_ALL, el, fc, nf)
    call t%true(nf == 14 .and. all(el == [1, 2, 3, 4, 4, 8, 12, 12, 11, 10, 9, 9, 5, 1]) &
        .and. all(fc == [1, 1, 1, 1, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4]), "elements ALL")

    ! consistency: the face's local control points (e.g. a1 = 0 for face 4) are the side's
    ! points, and the element span touches the side's end of the knot vector
    call patch_side_points(q, SIDE_XI0, idx, n)
    call patch_side_elements(q, SIDE_XI0, el, fc, nf)
    do k = 1, nf
      e = el(k)
      ij = patch_elem_ij(q, e)
      call t%true(q%span_lo1(ij(1)) == q%knots1(1), "XI0 element at first knot")
      call t%true(all(q%ien([1, 4, 7], e) == idx(k:k+2)), "XI0 face control points")
    end do
    call patch_side_points(q, SIDE_ETA1, idx, n)
    call patch_side_elements(q, SIDE_ETA1, el, fc, nf)
    do k = 1, nf
      e = el(k)
      ij = patch_elem_ij(q, e)
      call t%true(q%span_hi2(ij(2)) == q%knots2(size(q%knots2)), "ETA1 element at last knot")
      call t%true(all(q%ien([7, 8, 9], e) == idx(k:k+2)), "ETA1 face control points")
    end do
  end subroutine case_sides
end program test_patch
