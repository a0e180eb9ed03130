!> Contact surfaces: orientation of patch sides (including the half-disc patch of
!! doc/iga.md §10.4, whose det J is negative), nodal weights l_A, neighbours, Gauss points, the
!! inverted-element check, and the segment curves (Bezier form) against segment_geometry.
program test_surface
  use ictus_core_kinds, only: dp, pi
  use ictus_test_check, only: checker_t
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8
  use ictus_geometry_patch, only: patch_t, patch_refine
  use ictus_geometry_sides, only: SIDE_XI0, SIDE_ETA0, SIDE_ETA1, SIDE_ALL
  use ictus_contact_surface, only: contact_surface_t, surface_init, patch_side_segments, &
      segment_geometry, element_area, SEG_BEZIER, SEG_LAGRANGE, segment_curve_t, &
      surface_curves, curve_point, curve_geometry, CURVE_SAMPLES
  implicit none
  type(checker_t) :: t
  real(dp), parameter :: rr = 4.0_dp
  call t%start("contact/surface")
  call half_disc_sides(t)
  call half_disc_swapped(t)
  call lagrange_weights(t)
  call inverted_element(t)
  call curves_match_geometry(t)
  call t%finish()

contains

  !> The half-disc patch of doc/iga.md §10.4 (R = 4), refined k x k.
  subroutine half_disc(patch, k, swap)
    type(patch_t), intent(out) :: patch
    integer, intent(in) :: k
    logical, intent(in) :: swap
    real(dp) :: cp(3, 9), c, tn, cpt(3, 9)
    integer :: i, j
    c = cos(pi/8.0_dp)
    tn = tan(pi/8.0_dp)
    cp(:, 1) = [0.0_dp, -rr, 1.0_dp]
    cp(:, 2) = [0.0_dp, 0.0_dp, 1.0_dp]
    cp(:, 3) = [0.0_dp, rr, 1.0_dp]
    cp(:, 4) = [tn*rr, -rr, c]
    cp(:, 5) = [rr/2.0_dp, 0.0_dp, 1.0_dp]
    cp(:, 6) = [tn*rr, rr, c]
    cp(:, 7) = [rr/sqrt(2.0_dp), -rr/sqrt(2.0_dp), 1.0_dp]
    cp(:, 8) = [sqrt(2.0_dp)*rr, 0.0_dp, sqrt(0.5_dp)]
    cp(:, 9) = [rr/sqrt(2.0_dp), rr/sqrt(2.0_dp), 1.0_dp]
    if (swap) then
      ! transpose: direction 1 <-> direction 2, which makes det J positive
      do j = 0, 2
        do i = 0, 2
          cpt(:, 1 + i + 3*j) = cp(:, 1 + j + 3*i)
        end do
      end do
      cp = cpt
    end if
    call patch%init('DISC', [2, 2], [3, 3], [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], &
        [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], cp)
    if (k > 1) call patch_refine(patch, [k, k])
  end subroutine half_disc

  !> Builds the surface of one side of a patch (control points are nodes 1..n1*n2).
  subroutine side_surface(patch, side, surf, x, ierr)
    type(patch_t), intent(in) :: patch
    integer, intent(in) :: side
    type(contact_surface_t), intent(out) :: surf
    real(dp), allocatable, intent(out) :: x(:,:)
    integer, intent(out) :: ierr
    integer :: nseg, k
    integer, allocatable :: nens(:), conn(:,:), elem(:), kinds(:)
    real(dp), allocatable :: wgt(:,:), ext(:,:,:)
    x = patch%cp(1:2, :)
    call patch_side_segments(patch, 0, side, nseg, nens, conn, wgt, ext, elem, ierr)
    allocate(kinds(nseg))
    kinds = SEG_BEZIER
    call surface_init(surf, 'S', kinds, nens, conn, x, wgt=wgt, ext=ext, &
        ngauss=[(12, k = 1, nseg)])
  end subroutine side_surface

  !> Outward normals: on the arc n = x/R; on the cut x = 0, n = (-1, 0). Checked at the
  !! middle of every segment; also the chain of neighbours and the sum of l_A.
  subroutine check_outward(t, surf, x, label)
    type(checker_t), intent(inout) :: t
    type(contact_surface_t), intent(in) :: surf
    real(dp), intent(in) :: x(:,:)
    character(len=*), intent(in) :: label
    real(dp) :: xp(2), x1(2), x2(2), r(surf%nen_max), n(2), want(2)
    integer :: s, nbad
    nbad = 0
    do s = 1, surf%nseg
      call segment_geometry(surf, s, x, 0.5_dp, xp, x1, x2, r)
      n = [x1(2), -x1(1)]/norm2(x1)
      if (abs(xp(1)) < 1.0e-12_dp) then
        want = [-1.0_dp, 0.0_dp]
      else
        want = xp/norm2(xp)
      end if
      if (norm2(n - want) > 1.0e-12_dp) nbad = nbad + 1
    end do
    call t%equal_int(nbad, 0, label//': outward normals')
  end subroutine check_outward

  subroutine half_disc_sides(t)
    type(checker_t), intent(inout) :: t
    type(patch_t) :: patch
    type(contact_surface_t) :: surf
    real(dp), allocatable :: x(:,:)
    integer :: ierr, s, side, nopen
    ! det J < 0 for this patch (doc/iga.md §10.4): the sides whose parameter runs clockwise
    ! (ETA0, XI1 here) must be flipped, the others kept
    call half_disc(patch, 4, .false.)
    do side = SIDE_XI0, SIDE_ETA1
      call side_surface(patch, side, surf, x, ierr)
      call check_outward(t, surf, x, 'half disc side')
    end do
    call side_surface(patch, SIDE_XI0, surf, x, ierr)
    call t%equal_int(surf%nseg, 4, 'XI0: 4 segments')
    ! the 45 degree arc A -> G1: length pi R/4; the sum of l_A is the length
    call t%close(sum(surf%ell), pi*rr/4.0_dp, 1.0e-10_dp, 'XI0: sum l_A = pi R/4')
    call t%close(sum(surf%gp_wj), pi*rr/4.0_dp, 1.0e-10_dp, 'XI0: sum w J = pi R/4')
    nopen = count(surf%next == 0)
    call t%equal_int(nopen, 1, 'XI0: one open end after t = 1')
    ! counter-clockwise around the body, the arc runs from A = (0, -R) to G1
    call t%close_abs(x(1, surf%conn(1, 1)), 0.0_dp, 1.0e-14_dp, 'XI0 starts at A: x')
    call t%close_abs(x(2, surf%conn(1, 1)), -rr, 1.0e-14_dp, 'XI0 starts at A: y')
    ! the whole boundary: closed chain, perimeter pi R + 2 R
    call side_surface(patch, SIDE_ALL, surf, x, ierr)
    call check_outward(t, surf, x, 'half disc ALL')
    call t%close(sum(surf%ell), pi*rr + 2.0_dp*rr, 1.0e-10_dp, 'ALL: perimeter')
    nopen = 0
    do s = 1, surf%nseg
      if (surf%next(s) == 0 .or. surf%prev(s) == 0) nopen = nopen + 1
      if (surf%next(s) > 0) then
        if (surf%prev(surf%next(s)) /= s) nopen = nopen + 1
      end if
    end do
    call t%equal_int(nopen, 0, 'ALL: closed, consistent chain')
  end subroutine half_disc_sides

  !> The same patch with the directions swapped (det J > 0): still outward.
  subroutine half_disc_swapped(t)
    type(checker_t), intent(inout) :: t
    type(patch_t) :: patch
    type(contact_surface_t) :: surf
    real(dp), allocatable :: x(:,:)
    integer :: ierr, side
    call half_disc(patch, 3, .true.)
    do side = SIDE_XI0, SIDE_ALL
      call side_surface(patch, side, surf, x, ierr)
      call check_outward(t, surf, x, 'swapped half disc')
    end do
    call side_surface(patch, SIDE_ETA0, surf, x, ierr)
    call t%close(sum(surf%ell), pi*rr/4.0_dp, 1.0e-10_dp, 'swapped ETA0: pi R/4')
  end subroutine half_disc_swapped

  !> Straight edges: l_A of a quadratic edge of length h is h/6, 2h/3, h/6; linear h/2.
  subroutine lagrange_weights(t)
    type(checker_t), intent(inout) :: t
    type(contact_surface_t) :: surf
    real(dp) :: x(2, 5)
    x = reshape([0.0_dp, 0.0_dp, 0.5_dp, 0.0_dp, 1.0_dp, 0.0_dp, 1.5_dp, 0.0_dp, &
        2.0_dp, 0.0_dp], [2, 5])
    call surface_init(surf, 'L', [SEG_LAGRANGE, SEG_LAGRANGE], [3, 3], &
        reshape([1, 2, 3, 3, 4, 5], [3, 2]), x)
    call t%close(surf%ell(1), 1.0_dp/6.0_dp, 1.0e-14_dp, 'quadratic: end corner h/6')
    call t%close(surf%ell(2), 2.0_dp/3.0_dp, 1.0e-14_dp, 'quadratic: midside 2h/3')
    call t%close(surf%ell(3), 1.0_dp/3.0_dp, 1.0e-14_dp, 'quadratic: shared corner h/3')
    call t%equal_int(surf%ngp, 6, 'quadratic: 3 Gauss points per edge')
    call t%equal_int(surf%next(1), 2, 'quadratic: chained')
    call surface_init(surf, 'L', [SEG_LAGRANGE], [2], reshape([1, 3], [2, 1]), x)
    call t%close(surf%ell(1), 0.5_dp, 1.0e-14_dp, 'linear: h/2')
    call t%equal_int(surf%ngp, 2, 'linear: 2 Gauss points')
  end subroutine lagrange_weights

  !> element_area: positive for counter-clockwise nodes, negative for clockwise ones.
  subroutine inverted_element(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: xl(2, 8), xr(2, 8)
    xl = reshape([0.0_dp, 0.0_dp, 2.0_dp, 0.0_dp, 2.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, &
        1.0_dp, 0.0_dp, 2.0_dp, 0.5_dp, 1.0_dp, 1.0_dp, 0.0_dp, 0.5_dp], [2, 8])
    call t%close(element_area(ETYPE_Q8, xl), 2.0_dp, 1.0e-14_dp, 'Q8 area')
    call t%close(element_area(ETYPE_Q4, xl), 2.0_dp, 1.0e-14_dp, 'Q4 area')
    ! clockwise: corners 1 4 3 2, midsides 8 7 6 5
    xr = xl(:, [1, 4, 3, 2, 8, 7, 6, 5])
    call t%true(element_area(ETYPE_Q8, xr) < 0.0_dp, 'clockwise Q8 is inverted')
  end subroutine inverted_element

  !> The segment curves give segment_geometry's point and derivatives to round-off: linear
  !! and quadratic Lagrange edges, and rational Bezier segments of degree 1 to 5 with
  !! unequal weights and a full extraction operator (non-negative, columns summing to 1),
  !! far from the origin (where the derivatives of a Bezier form without its origin at a
  !! node lost 2 to 3 digits).
  subroutine curves_match_geometry(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: ns = 7, nm = 6
    real(dp), parameter :: tq(5) = [0.0_dp, 0.13_dp, 0.5_dp, 0.77_dp, 1.0_dp]
    type(contact_surface_t) :: surf
    type(segment_curve_t) :: curves(ns)
    real(dp) :: x(2, ns*nm), wgt(nm, ns), ext(nm, nm, ns), xp(2), x1(2), x2(2), r(nm)
    real(dp) :: yp(2), y1(2), y2(2), zp(2), e0, e1, e2, ek, scale
    integer :: kinds(ns), nens(ns), conn(nm, ns), s, a, j, q, k
    kinds = [SEG_LAGRANGE, SEG_LAGRANGE, (SEG_BEZIER, s = 3, ns)]
    nens = [2, 3, (s - 1, s = 3, ns)]
    conn = 0
    wgt = 1.0_dp
    ext = 0.0_dp
    do s = 1, ns
      do a = 1, nens(s)
        conn(a, s) = a + nm*(s - 1)
        ! a wavy arc near (100, -50), about 1 long
        x(:, conn(a, s)) = [100.0_dp + 0.3_dp*a + 0.05_dp*sin(3.0_dp*a + s), &
            -50.0_dp + 0.1_dp*a*a/nens(s) + 0.02_dp*cos(2.0_dp*a*s)]
        wgt(a, s) = 0.6_dp + 0.5_dp*abs(sin(1.7_dp*a + s))
        do j = 1, nens(s)
          ext(a, j, s) = 1.0_dp + abs(cos(0.9_dp*a*j + s))
        end do
      end do
      do j = 1, nens(s)
        ext(1:nens(s), j, s) = ext(1:nens(s), j, s)/sum(ext(1:nens(s), j, s))
      end do
    end do
    call surface_init(surf, 'C', kinds, nens, conn, x, wgt=wgt, ext=ext)
    call surface_curves(surf, x, curves)
    e0 = 0.0_dp
    e1 = 0.0_dp
    e2 = 0.0_dp
    ek = 0.0_dp
    do s = 1, ns
      do q = 1, size(tq)
        call segment_geometry(surf, s, x, tq(q), xp, x1, x2, r)
        call curve_geometry(curves(s), tq(q), yp, y1, y2)
        call curve_point(curves(s), tq(q), zp)
        scale = maxval(abs(xp))
        e0 = max(e0, maxval(abs(yp - xp))/scale, maxval(abs(zp - xp))/scale)
        e1 = max(e1, maxval(abs(y1 - x1))/max(norm2(x1), scale*epsilon(1.0_dp)))
        e2 = max(e2, maxval(abs(y2 - x2))/max(norm2(x2), norm2(x1)))
      end do
      do k = 0, CURVE_SAMPLES
        call segment_geometry(surf, s, x, real(k, dp)/real(CURVE_SAMPLES, dp), xp, x1, x2, r)
        ek = max(ek, maxval(abs(curves(s)%xk(:, k) - xp))/maxval(abs(xp)))
      end do
    end do
    call t%close_abs(e0, 0.0_dp, 1.0e-14_dp, 'curve point = segment_geometry')
    call t%close_abs(e1, 0.0_dp, 1.0e-11_dp, 'curve x'' = segment_geometry')
    call t%close_abs(e2, 0.0_dp, 1.0e-11_dp, 'curve x'''' = segment_geometry')
    call t%close_abs(ek, 0.0_dp, 1.0e-14_dp, 'curve samples = segment_geometry')
  end subroutine curves_match_geometry
end program test_surface
