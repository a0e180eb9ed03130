!> Unit tests of ictus_geometry_refine (and patch_elevate/patch_refine): knot insertion and
!! degree elevation leave curves and the half-disc patch unchanged.
program test_refine
  use ictus_core_kinds, only: dp, pi
  use ictus_test_geometry, only: nurbs_curve_point
  use ictus_geometry_refine, only: refine_knot_vector, degree_elevate_curve
  use ictus_geometry_patch, only: patch_t, patch_elevate, patch_refine, patch_point
  use ictus_test_check, only: checker_t
  use ictus_test_halfdisc, only: half_disc
  implicit none
  type(checker_t) :: t
  real(dp), parameter :: rr = 4.0_dp, s2 = sqrt(2.0_dp)/2.0_dp

  call t%start("geometry/refine")
  call case_half_circle_insert(t)
  call case_half_circle_elevate(t)
  call case_cubic_elevate(t)
  call case_half_disc(t)
  call t%finish()

contains

  !> Half circle R = 4 (doc/iga.md §10.3).
  subroutine half(knots, cp)
    real(dp), intent(out) :: knots(8), cp(3, 5)
    knots = [0.0_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.5_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    cp(:, 1) = [rr, 0.0_dp, 1.0_dp]
    cp(:, 2) = [rr, rr, s2]
    cp(:, 3) = [0.0_dp, rr, 1.0_dp]
    cp(:, 4) = [-rr, rr, s2]
    cp(:, 5) = [-rr, 0.0_dp, 1.0_dp]
  end subroutine half

  !> Largest distance between two curves at 1001 parameter values.
  real(dp) function curve_dev(n1, p1, k1, c1, n2, p2, k2, c2) result(dev)
    integer, intent(in) :: n1, p1, n2, p2
    real(dp), intent(in) :: k1(:), c1(:,:), k2(:), c2(:,:)
    real(dp) :: x1(2), x2(2), u
    integer :: i
    dev = 0.0_dp
    do i = 0, 1000
      u = real(i, dp)/1000.0_dp
      call nurbs_curve_point(n1, p1, k1, c1, u, x1)
      call nurbs_curve_point(n2, p2, k2, c2, u, x2)
      dev = max(dev, norm2(x1 - x2))
    end do
  end function curve_dev

  subroutine case_half_circle_insert(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: k(8), cp(3, 5)
    real(dp), allocatable :: ko(:), co(:,:)
    real(dp), parameter :: xn(5) = [0.1_dp, 0.25_dp, 0.25_dp, 0.6_dp, 0.9_dp]
    real(dp), parameter :: kwant(13) = [0.0_dp, 0.0_dp, 0.0_dp, 0.1_dp, 0.25_dp, 0.25_dp, &
        0.5_dp, 0.5_dp, 0.6_dp, 0.9_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    integer :: no
    call half(k, cp)
    call refine_knot_vector(5, 2, k, cp, xn, no, ko, co)
    call t%equal_int(no, 10, "insert: n")
    call t%equal_int(size(ko), 13, "insert: knot count")
    call t%close_abs(maxval(abs(ko - kwant)), 0.0_dp, 0.0_dp, "insert: knot vector")
    call t%close_abs(curve_dev(5, 2, k, cp, no, 2, ko, co), 0.0_dp, 1.0e-13_dp, &
        "insert: half circle unchanged")
    call t%true(all(co(3, :) > 0.0_dp), "insert: positive weights")
    ! end points stay interpolated
    call t%close_abs(maxval(abs(co(:, 1) - cp(:, 1))), 0.0_dp, 1.0e-15_dp, "insert: first cp")
    call t%close_abs(maxval(abs(co(:, no) - cp(:, 5))), 0.0_dp, 1.0e-15_dp, "insert: last cp")
    ! inserting nothing is the identity
    call refine_knot_vector(5, 2, k, cp, [real(dp) ::], no, ko, co)
    call t%equal_int(no, 5, "insert none: n")
    ! a single knot at 1/4 into the quarter arc: Boehm's alpha = 1/2 on the first arc
    call refine_knot_vector(5, 2, k, cp, [0.25_dp], no, ko, co)
    call t%close_abs(curve_dev(5, 2, k, cp, no, 2, ko, co), 0.0_dp, 1.0e-13_dp, &
        "insert one: unchanged")
  end subroutine case_half_circle_insert

  subroutine case_half_circle_elevate(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: k(8), cp(3, 5)
    real(dp), allocatable :: ko(:), co(:,:)
    real(dp), parameter :: k3(11) = [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.5_dp, 0.5_dp, &
        1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    integer :: no
    call half(k, cp)
    call degree_elevate_curve(5, 2, k, cp, 1, no, ko, co)
    call t%equal_int(no, 7, "elevate 2->3: n")
    call t%equal_int(size(ko), 11, "elevate 2->3: knot count")
    if (size(ko) == 11) call t%close_abs(maxval(abs(ko - k3)), 0.0_dp, 0.0_dp, &
        "elevate 2->3: knots")
    call t%close_abs(curve_dev(5, 2, k, cp, no, 3, ko, co), 0.0_dp, 1.0e-13_dp, &
        "elevate 2->3: half circle unchanged")
    call t%true(all(co(3, :) > 0.0_dp), "elevate: positive weights")
    call degree_elevate_curve(5, 2, k, cp, 2, no, ko, co)
    call t%equal_int(no, 9, "elevate 2->4: n")
    call t%equal_int(size(ko), 14, "elevate 2->4: knot count")
    call t%close_abs(curve_dev(5, 2, k, cp, no, 4, ko, co), 0.0_dp, 1.0e-13_dp, &
        "elevate 2->4: half circle unchanged")
    call degree_elevate_curve(5, 2, k, cp, 0, no, ko, co)
    call t%equal_int(no, 5, "elevate by 0: n")
  end subroutine case_half_circle_elevate

  !> A rational cubic with simple interior knots: elevation by 1 and 2 exercises the knot
  !! removal part of A5.9; multiplicities rise by t (n_out = n + t*(interior knots + 1)).
  subroutine case_cubic_elevate(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: k(11) = [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.2_dp, 0.45_dp, 0.7_dp, &
        1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    real(dp) :: cp(3, 7)
    real(dp), allocatable :: ko(:), co(:,:)
    integer :: no, i
    do i = 1, 7
      cp(:, i) = [real(i, dp), sin(real(i, dp)), 1.0_dp + 0.3_dp*cos(2.0_dp*i)]
    end do
    call degree_elevate_curve(7, 3, k, cp, 1, no, ko, co)
    call t%equal_int(no, 11, "cubic +1: n")
    call t%equal_int(count(ko == 0.45_dp), 2, "cubic +1: knot multiplicity")
    call t%close_abs(curve_dev(7, 3, k, cp, no, 4, ko, co), 0.0_dp, 1.0e-13_dp, &
        "cubic +1 unchanged")
    call degree_elevate_curve(7, 3, k, cp, 2, no, ko, co)
    call t%equal_int(no, 15, "cubic +2: n")
    call t%equal_int(count(ko == 1.0_dp), 6, "cubic +2: end multiplicity")
    call t%close_abs(curve_dev(7, 3, k, cp, no, 5, ko, co), 0.0_dp, 1.0e-13_dp, &
        "cubic +2 unchanged")
    ! elevation then insertion (k-refinement) on the same curve
    call degree_elevate_curve(7, 3, k, cp, 3, no, ko, co)
    call t%close_abs(curve_dev(7, 3, k, cp, no, 6, ko, co), 0.0_dp, 1.0e-13_dp, &
        "cubic +3 unchanged")
  end subroutine case_cubic_elevate


  !> Largest distance between two patches on a 32 x 32 grid of parameters (1024 points).
  real(dp) function patch_dev(a, b) result(dev)
    type(patch_t), intent(in) :: a, b
    real(dp) :: xa(2), xb(2), u(2)
    integer :: i, j
    dev = 0.0_dp
    do j = 0, 31
      do i = 0, 31
        u = [real(i, dp), real(j, dp)]/31.0_dp
        call patch_point(a, u, xa)
        call patch_point(b, u, xb)
        dev = max(dev, norm2(xa - xb))
      end do
    end do
  end function patch_dev

  subroutine case_half_disc(t)
    type(checker_t), intent(inout) :: t
    type(patch_t) :: base, q
    integer :: deg, ks(3), i
    call half_disc(base)
    do deg = 3, 4
      call half_disc(q)
      call patch_elevate(q, [deg, deg])
      call t%equal_int(q%n(1), deg + 1, "half disc elevate: n1")
      call t%equal_int(q%p(2), deg, "half disc elevate: p2")
      call t%close_abs(patch_dev(base, q), 0.0_dp, 1.0e-13_dp, "half disc elevate unchanged")
    end do
    ks = [2, 3, 16]
    do i = 1, 3
      call half_disc(q)
      call patch_refine(q, [ks(i), ks(i)])
      call t%equal_int(q%n(1), ks(i) + 2, "half disc refine: n1")
      call t%equal_int(q%nel(2), ks(i), "half disc refine: nel2")
      call t%close_abs(patch_dev(base, q), 0.0_dp, 1.0e-13_dp, "half disc refine unchanged")
    end do
    ! different subdivisions per direction, then k-refinement (elevate, then refine)
    call half_disc(q)
    call patch_refine(q, [3, 2])
    call t%equal_int(q%n(1)*q%n(2), 5*4, "refine 3,2: control points")
    call t%close_abs(patch_dev(base, q), 0.0_dp, 1.0e-13_dp, "refine 3,2 unchanged")
    call half_disc(q)
    call patch_elevate(q, [3, 4])
    call patch_refine(q, [4, 3])
    call t%equal_int(q%n(1), 3 + 4, "k-refine: n1 = p1 + nel1")
    call t%equal_int(q%n(2), 4 + 3, "k-refine: n2 = p2 + nel2")
    call t%close_abs(patch_dev(base, q), 0.0_dp, 1.0e-13_dp, "k-refine unchanged")
    call patch_refine(q, [2, 2])
    call patch_elevate(q, [4, 4])
    call t%close_abs(patch_dev(base, q), 0.0_dp, 1.0e-13_dp, "refine after elevate unchanged")
    call t%true(all(q%cp(3, :) > 0.0_dp), "positive weights after refinement")
  end subroutine case_half_disc
end program test_refine
