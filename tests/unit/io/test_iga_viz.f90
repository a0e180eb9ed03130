!> Unit tests of ictus_io_iga_viz: viewing samples of NURBS elements.
!!
!! A hand-built model: one Q4 element (4 nodes, not sampled), the half-disc patch of physics.md
!! §7.4 (directions swapped so that det J > 0, centre (0, 4)) refined into 3 x 2 spans, and the
!! same patch elevated to p = 3, refined 2 x 2 and shifted by (10, 0). Checks: counts
!! (s = 2p+1 per direction), every sample point lies on its patch map (patch_point at the
!! span parameters), the interpolation rows are partitions of unity, a linear field
!! u = a + B x on the control points is reproduced at the sample points, and the cells are
!! valid 0-based counter-clockwise quads.
program test_iga_viz
  use ictus_core_kinds, only: dp, pi
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_IGA
  use ictus_geometry_patch, only: patch_elevate, patch_refine, patch_point, patch_elem_ij
  use ictus_solver_model, only: model_t
  use ictus_io_iga_viz, only: iga_viz_t, iga_viz_init, iga_viz_eval, iga_viz_free
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  type(model_t) :: m
  type(iga_viz_t) :: viz

  call t%start("io/iga_viz")
  call build_model(m)
  call iga_viz_init(m, viz)
  call case_counts(t, m, viz)
  call case_on_patch(t, m, viz)
  call case_linear(t, m, viz)
  call case_cells(t, viz)
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
    call t%equal_int(viz%ns, 6*25 + 4*49, "sample points: s^2 per element, s = 2p+1")
    call t%equal_int(viz%ncells, 6*16 + 4*36, "cells: (s-1)^2 per element")
    call t%equal_int(viz%nen_max, 16, "rows of the interpolation matrix = largest nen")
    call t%true(all(viz%elem >= 2 .and. viz%elem <= m%nel), "the Q4 element is not sampled")
    call t%true(all(abs(sum(viz%val, dim=1) - 1.0_dp) < 1.0e-14_dp), &
        "each interpolation row sums to 1")
  end subroutine case_counts

  !> Every sample point is the patch map at its span parameters (sample order: elements in
  !! model order, direction 1 fastest, xi~ = -1 + 2 i/(s-1)).
  subroutine case_on_patch(t, m, viz)
    type(checker_t), intent(inout) :: t
    type(model_t), intent(in) :: m
    type(iga_viz_t), intent(in) :: viz
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
            err = max(err, maxval(abs(x - viz%points(:, k))))
            ! distance from the disc centre (0, 4) or (10, 4): at most R = 4
            rmax = max(rmax, hypot(viz%points(1, k) - 10.0_dp*(m%patch(e) - 1), &
                viz%points(2, k) - 4.0_dp))
          end do
        end do
      end associate
    end do
    call t%true(k == viz%ns, "all sample points visited")
    call t%true(err < 1.0e-12_dp, "sample points lie on the patch map (1e-12)")
    call t%true(rmax < 4.0_dp + 1.0e-12_dp, "sample points inside the disc, R = 4")
  end subroutine case_on_patch

  !> u = a + B x on all nodes gives a + B x at every sample point.
  subroutine case_linear(t, m, viz)
    type(checker_t), intent(inout) :: t
    type(model_t), intent(in) :: m
    type(iga_viz_t), intent(in) :: viz
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
    call iga_viz_eval(viz, uc, us)
    err = 0.0_dp
    do k = 1, viz%ns
      err = max(err, maxval(abs(us(:, k) - a - matmul(b, viz%points(:, k)))))
    end do
    call t%true(err < 1.0e-13_dp, "linear field reproduced at the sample points")
  end subroutine case_linear

  !> Cells: 0-based indices in range, counter-clockwise (positive area) since det J > 0.
  subroutine case_cells(t, viz)
    type(checker_t), intent(inout) :: t
    type(iga_viz_t), intent(in) :: viz
    real(dp) :: xc(2, 4), area, amin
    integer :: c, j
    call t%true(minval(viz%cells) == 0 .and. maxval(viz%cells) == viz%ns - 1, &
        "cell indices are 0-based and cover all points")
    amin = huge(1.0_dp)
    do c = 1, viz%ncells
      xc = viz%points(:, viz%cells(:, c) + 1)
      area = 0.0_dp
      do j = 1, 4
        area = area + xc(1, j)*xc(2, mod(j, 4) + 1) - xc(1, mod(j, 4) + 1)*xc(2, j)
      end do
      amin = min(amin, 0.5_dp*area)
    end do
    call t%true(amin > 0.0_dp, "all cells counter-clockwise")
  end subroutine case_cells
end program test_iga_viz
