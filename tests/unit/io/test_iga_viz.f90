!> Unit tests of ictus_io_iga_viz: viewing samples of NURBS elements.
!!
!! A hand-built model: one Q4 element (4 nodes, not sampled), the half-disc patch of doc/iga.md
!! §10.4 (directions swapped so that det J > 0, centre (0, 4)) refined into 3 x 2 spans, and the
!! same patch elevated to p = 3, refined 2 x 2 and shifted by (10, 0). Checks: counts
!! (s = 2p+1 per direction, or SAMPLES= for all patches, against iga_viz_count), every sample
!! point lies on its patch map (patch_point at the span parameters), a constant field is
!! reproduced (partition of unity), a linear field u = a + B x on the control points is
!! reproduced at the sample points, the samples of a subset of elements evaluated through a
!! node map are those of the whole model, and the cells are valid 0-based counter-clockwise
!! quads.
program test_iga_viz
  use ictus_core_kinds, only: dp, i8, pi
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_IGA
  use ictus_geometry_patch, only: patch_elevate, patch_refine, patch_point, patch_elem_ij
  use ictus_solver_model, only: model_t
  use ictus_io_iga_viz, only: iga_viz_t, iga_viz_init, iga_viz_eval, iga_viz_points, &
      iga_viz_cells, iga_viz_count, iga_viz_free
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  type(model_t) :: m
  type(iga_viz_t) :: viz
  real(dp), allocatable :: points(:,:)

  call t%start("io/iga_viz")
  call build_model(m)
  call iga_viz_init(m, viz)
  allocate(points(2, viz%ns))
  call iga_viz_points(viz, m, points)
  call case_counts(t, m, viz)
  call case_on_patch(t, m, viz, points)
  call case_linear(t, m, viz, points)
  call case_subset(t, m, viz)
  call case_cells(t, m, viz, points)
  call case_samples(t, m)
  call iga_viz_free(viz)
  call t%equal_int(viz%ns, 0, "free resets the sample count")
  call t%finish()

contains

  !> The half-disc control net, directions swapped (direction 1 from the cut to the arc),
  !! centred at (0, 4), shifted by (dx, 0).
  pure function half_disc_net(dx) result(cp)
    real(dp), intent(in) :: dx
    real(dp) :: cp(3, 9)
    real(dp) :: c, tn, s2, r
    r = 4.0_dp
    c = cos(pi/8.0_dp)
    tn = tan(pi/8.0_dp)
    s2 = sqrt(0.5_dp)
    cp(:, 1) = [0.0_dp, -r, 1.0_dp]
    cp(:, 2) = [r*tn, -r, c]
    cp(:, 3) = [r*s2, -r*s2, 1.0_dp]
    cp(:, 4) = [0.0_dp, 0.0_dp, 1.0_dp]
    cp(:, 5) = [r/2.0_dp, 0.0_dp, 1.0_dp]
    cp(:, 6) = [2.0_dp*r*s2, 0.0_dp, s2]
    cp(:, 7) = [0.0_dp, r, 1.0_dp]
    cp(:, 8) = [r*tn, r, c]
    cp(:, 9) = [r*s2, r*s2, 1.0_dp]
    cp(1, :) = cp(1, :) + dx
    cp(2, :) = cp(2, :) + r
  end function half_disc_net

  !> One Q4 element and two patches, numbered as build_model does (FE nodes, then each
  !! patch's control points, direction 1 fastest; FE elements, then each patch's spans).
  subroutine build_model(m)
    type(model_t), intent(inout) :: m
    real(dp) :: kn(6)
    integer :: ip, ie, e, n0, nelp
    kn = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    m%npatch = 2
    allocate(m%patches(2), m%patch_offset(2))
    call m%patches(1)%init('A', [2, 2], [3, 3], kn, kn, half_disc_net(0.0_dp))
    call patch_refine(m%patches(1), [3, 2])
    call m%patches(2)%init('B', [2, 2], [3, 3], kn, kn, half_disc_net(10.0_dp))
    call patch_elevate(m%patches(2), [3, 3])
    call patch_refine(m%patches(2), [2, 2])
    m%nn = 4 + size(m%patches(1)%cp, 2) + size(m%patches(2)%cp, 2)
    allocate(m%x0(2, m%nn), m%weight(m%nn))
    m%x0(:, 1:4) = reshape([-3.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, -1.0_dp, 1.0_dp, -3.0_dp, &
        1.0_dp], [2, 4])
    m%weight(1:4) = 1.0_dp
    n0 = 4
    nelp = 0
    do ip = 1, 2
      m%patch_offset(ip) = n0
      associate (pt => m%patches(ip))
        m%x0(:, n0 + 1:n0 + size(pt%cp, 2)) = pt%cp(1:2, :)
        m%weight(n0 + 1:n0 + size(pt%cp, 2)) = pt%cp(3, :)
        n0 = n0 + size(pt%cp, 2)
        nelp = nelp + pt%nel(1)*pt%nel(2)
      end associate
    end do
    m%nel = 1 + nelp
    m%nen_max = 16
    allocate(m%etype(m%nel), m%nen(m%nel), m%conn(16, m%nel), m%patch(m%nel), &
        m%patch_elem(m%nel))
    m%conn = 0
    m%etype(1) = ETYPE_Q4
    m%nen(1) = 4
    m%conn(1:4, 1) = [1, 2, 3, 4]
    m%patch(1) = 0
    m%patch_elem(1) = 0
    e = 1
    do ip = 1, 2
      associate (pt => m%patches(ip))
        do ie = 1, pt%nel(1)*pt%nel(2)
          e = e + 1
          m%etype(e) = ETYPE_IGA
          m%nen(e) = pt%nen
          m%conn(1:pt%nen, e) = m%patch_offset(ip) + pt%ien(:, ie)
          m%patch(e) = ip
          m%patch_elem(e) = ie
        end do
      end associate
    end do
  end subroutine build_model

  !> 6 elements with s = 5 and 4 elements with s = 7.
  subroutine case_counts(t, m, viz)
    type(checker_t), intent(inout) :: t
    type(model_t), intent(in) :: m
    type(iga_viz_t), intent(in) :: viz
    real(dp), allocatable :: uc(:,:), us(:,:)
    integer(i8) :: ns, nc
    integer :: e
    call t%equal_int(viz%ns, 6*25 + 4*49, "sample points: s^2 per element, s = 2p+1")
    call t%equal_int(viz%ncells, 6*16 + 4*36, "cells: (s-1)^2 per element")
    call t%equal_int(viz%nen_max, 16, "largest nen")
    call iga_viz_count(m, 0, ns, nc)
    call t%true(ns == viz%ns .and. nc == viz%ncells, "iga_viz_count gives the same counts")
    call t%true(viz%first_point(1) == -1 .and. all(viz%first_point(2:) >= 0), &
        "the Q4 element is not sampled")
    allocate(uc(2, m%nn), us(2, viz%ns))
    uc = 1.0_dp
    call iga_viz_eval(viz, m, [(e, e = 2, m%nel)], uc, us, [(e, e = 1, m%nn)])
    call t%true(all(abs(us - 1.0_dp) < 1.0e-14_dp), "the basis at each sample sums to 1")
  end subroutine case_counts

  !> Every sample point is the patch map at its span parameters (sample order: elements in
  !! model order, direction 1 fastest, xi~ = -1 + 2 i/(s-1)).
  subroutine case_on_patch(t, m, viz, points)
    type(checker_t), intent(inout) :: t
    type(model_t), intent(in) :: m
    type(iga_viz_t), intent(in) :: viz
    real(dp), intent(in) :: points(:,:)
    real(dp) :: u(2), x(2), err, rmax
    integer :: e, s, i1, i2, k, ij(2)
    err = 0.0_dp
    rmax = 0.0_dp
    k = 0
    do e = 2, m%nel
      associate (pt => m%patches(m%patch(e)))
        s = 2*maxval(pt%p) + 1
        ij = patch_elem_ij(pt, m%patch_elem(e))
        do i2 = 0, s - 1
          do i1 = 0, s - 1
            k = k + 1
            u(1) = pt%span_lo1(ij(1)) + (pt%span_hi1(ij(1)) - pt%span_lo1(ij(1))) &
                *real(i1, dp)/real(s - 1, dp)
            u(2) = pt%span_lo2(ij(2)) + (pt%span_hi2(ij(2)) - pt%span_lo2(ij(2))) &
                *real(i2, dp)/real(s - 1, dp)
            call patch_point(pt, u, x)
            err = max(err, maxval(abs(x - points(:, k))))
            ! distance from the disc centre (0, 4) or (10, 4): at most R = 4
            rmax = max(rmax, hypot(points(1, k) - 10.0_dp*(m%patch(e) - 1), &
                points(2, k) - 4.0_dp))
          end do
        end do
      end associate
    end do
    call t%true(k == viz%ns, "all sample points visited")
    call t%true(err < 1.0e-12_dp, "sample points lie on the patch map (1e-12)")
    call t%true(rmax < 4.0_dp + 1.0e-12_dp, "sample points inside the disc, R = 4")
  end subroutine case_on_patch

  !> u = a + B x on all nodes gives a + B x at every sample point.
  subroutine case_linear(t, m, viz, points)
    type(checker_t), intent(inout) :: t
    type(model_t), intent(in) :: m
    type(iga_viz_t), intent(in) :: viz
    real(dp), intent(in) :: points(:,:)
    real(dp) :: a(2), b(2, 2)
    real(dp), allocatable :: uc(:,:), us(:,:)
    integer :: n, k
    real(dp) :: err
    a = [0.3_dp, -0.2_dp]
    b = reshape([0.01_dp, -0.03_dp, 0.02_dp, 0.005_dp], [2, 2])
    allocate(uc(2, m%nn), us(2, viz%ns))
    do n = 1, m%nn
      uc(:, n) = a + matmul(b, m%x0(:, n))
    end do
    call iga_viz_eval(viz, m, [(n, n = 2, m%nel)], uc, us, [(n, n = 1, m%nn)])
    err = 0.0_dp
    do k = 1, viz%ns
      err = max(err, maxval(abs(us(:, k) - a - matmul(b, points(:, k)))))
    end do
    call t%true(err < 1.0e-13_dp, "linear field reproduced at the sample points")
  end subroutine case_linear

  !> The samples of elements 7 and 3 (in that order), evaluated on a field stored in another
  !! numbering (node i at column nn + 1 - i, as a rank's local numbering), are those rows of
  !! the whole model's samples, bit for bit (results do not depend on the ranks).
  subroutine case_subset(t, m, viz)
    type(checker_t), intent(inout) :: t
    type(model_t), intent(in) :: m
    type(iga_viz_t), intent(in) :: viz
    real(dp), allocatable :: uc(:,:), ur(:,:), us(:,:), sub(:,:)
    integer :: n, n7, n3
    allocate(uc(2, m%nn), ur(2, m%nn), us(2, viz%ns))
    do n = 1, m%nn
      uc(:, n) = [sin(real(n, dp)), cos(3.0_dp*n)]
    end do
    ur = uc(:, m%nn:1:-1)
    call iga_viz_eval(viz, m, [(n, n = 2, m%nel)], uc, us, [(n, n = 1, m%nn)])
    n7 = viz%first_point(8) - viz%first_point(7)
    n3 = viz%first_point(4) - viz%first_point(3)
    allocate(sub(2, n7 + n3))
    call iga_viz_eval(viz, m, [7, 3], ur, sub, [(m%nn + 1 - n, n = 1, m%nn)])
    call t%true(all(sub(:, 1:n7) == us(:, viz%first_point(7) + 1:viz%first_point(7) + n7)) &
        .and. all(sub(:, n7 + 1:) == us(:, viz%first_point(3) + 1:viz%first_point(3) + n3)), &
        "samples of a subset of elements through a node map: the same bits")
  end subroutine case_subset

  !> SAMPLES=2 for all patches: 4 corner points per element and one cell, at the corners of
  !! the spans.
  subroutine case_samples(t, m)
    type(checker_t), intent(inout) :: t
    type(model_t), intent(in) :: m
    type(iga_viz_t) :: v2
    integer(i8) :: ns, nc
    call iga_viz_init(m, v2, 2)
    call iga_viz_count(m, 2, ns, nc)
    call t%true(v2%ns == 10*4 .and. v2%ncells == 10 .and. ns == v2%ns .and. nc == v2%ncells, &
        "SAMPLES=2: 4 points and 1 cell per element")
    call case_cells(t, m, v2)
    call iga_viz_free(v2)
  end subroutine case_samples

  !> Cells: 0-based indices in range, counter-clockwise (positive area) since det J > 0.
  subroutine case_cells(t, m, viz, given)
    type(checker_t), intent(inout) :: t
    type(model_t), intent(in) :: m
    type(iga_viz_t), intent(in) :: viz
    real(dp), intent(in), optional :: given(:,:)
    real(dp) :: xc(2, 4), area, amin
    real(dp), allocatable :: points(:,:)
    integer, allocatable :: cells(:,:)
    integer :: c, j
    allocate(points(2, viz%ns), cells(4, viz%ncells))
    if (present(given)) then
      points = given
    else
      call iga_viz_points(viz, m, points)
    end if
    call iga_viz_cells(viz, m, cells)
    call t%true(minval(cells) == 0 .and. maxval(cells) == viz%ns - 1, &
        "cell indices are 0-based and cover all points")
    amin = huge(1.0_dp)
    do c = 1, viz%ncells
      xc = points(:, cells(:, c) + 1)
      area = 0.0_dp
      do j = 1, 4
        area = area + xc(1, j)*xc(2, mod(j, 4) + 1) - xc(1, mod(j, 4) + 1)*xc(2, j)
      end do
      amin = min(amin, 0.5_dp*area)
    end do
    call t%true(amin > 0.0_dp, "all cells counter-clockwise")
  end subroutine case_cells
end program test_iga_viz
