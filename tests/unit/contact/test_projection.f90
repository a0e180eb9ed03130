!> Closest-point projection (doc/contact.md §3): the quarter-circle table, clamping at the
!! surface ends, moving across segment ends, quadratic Lagrange edges, a concave master
!! with two local minima, and a point close to its master (round-off regime).
program test_projection
  use ictus_core_kinds, only: dp
  use ictus_test_check, only: checker_t
  use ictus_contact_surface, only: contact_surface_t, surface_init, segment_geometry, &
      SEG_BEZIER, SEG_LAGRANGE, MAX_SEG_NODES
  use ictus_contact_projection, only: projection_t, project_point, PROJ_INTERIOR, &
      PROJ_OUTSIDE, PROJ_CORNER
  implicit none
  type(checker_t) :: t
  call t%start("contact/projection")
  call quarter_circle_table(t)
  call beyond_the_ends(t)
  call across_segments(t)
  call quadratic_edge(t)
  call concave_two_minima(t)
  call corner_point(t)
  call close_to_master(t)
  call t%finish()

contains

  !> One rational quadratic segment: the quarter circle R = 4 of doc/contact.md §3.
  subroutine quarter(surf, x)
    type(contact_surface_t), intent(out) :: surf
    real(dp), allocatable, intent(out) :: x(:,:)
    real(dp) :: w(3, 1)
    x = reshape([4.0_dp, 0.0_dp, 4.0_dp, 4.0_dp, 0.0_dp, 4.0_dp], [2, 3])
    w(:, 1) = [1.0_dp, sqrt(0.5_dp), 1.0_dp]
    call surface_init(surf, 'Q', [SEG_BEZIER], [3], reshape([1, 2, 3], [3, 1]), x, wgt=w)
  end subroutine quarter

  subroutine quarter_circle_table(t)
    type(checker_t), intent(inout) :: t
    type(contact_surface_t) :: surf
    real(dp), allocatable :: x(:,:)
    type(projection_t) :: pr
    integer :: nf
    call quarter(surf, x)
    call project_point(surf, x, [5.0_dp, 5.0_dp], [1], 1, pr, nf)
    call t%equal_int(pr%status, PROJ_INTERIOR, '(5,5) interior')
    call t%close_abs(pr%t, 0.5_dp, 1.0e-9_dp, '(5,5) xi')
    call t%close_abs(pr%d, 5.0_dp*sqrt(2.0_dp) - 4.0_dp, 1.0e-9_dp, '(5,5) d = +3.0711')
    call t%close_abs(pr%xbar(1), 2.0_dp*sqrt(2.0_dp), 1.0e-9_dp, '(5,5) xbar')
    call project_point(surf, x, [2.0_dp, 1.0_dp], [1], 1, pr, nf)
    call t%close_abs(pr%t, 0.304113535976_dp, 1.0e-9_dp, '(2,1) xi')
    call t%close_abs(pr%d, -(4.0_dp - sqrt(5.0_dp)), 1.0e-9_dp, '(2,1) d = -(4 - sqrt 5)')
    call t%close_abs(pr%xbar(1), 8.0_dp/sqrt(5.0_dp), 1.0e-9_dp, '(2,1) xbar x')
    call t%close_abs(pr%xbar(2), 4.0_dp/sqrt(5.0_dp), 1.0e-9_dp, '(2,1) xbar y')
    call project_point(surf, x, [3.9_dp, 0.5_dp], [1], 1, pr, nf)
    call t%close_abs(pr%t, 0.087959244724_dp, 1.0e-9_dp, '(3.9,0.5) xi')
    call t%close_abs(pr%d, norm2([3.9_dp, 0.5_dp]) - 4.0_dp, 1.0e-9_dp, '(3.9,0.5) d')
    call t%close_abs(pr%d, -0.068079_dp, 1.0e-6_dp, '(3.9,0.5) d = -0.068079')
    call t%close_abs(pr%normal(1), 3.9_dp/norm2([3.9_dp, 0.5_dp]), 1.0e-12_dp, 'normal')
    call t%equal_int(nf, 0, 'no failures')
  end subroutine quarter_circle_table

  !> Points whose closest point on the whole circle lies beyond the arc: clamped, outside.
  subroutine beyond_the_ends(t)
    type(checker_t), intent(inout) :: t
    type(contact_surface_t) :: surf
    real(dp), allocatable :: x(:,:)
    type(projection_t) :: pr
    integer :: nf
    call quarter(surf, x)
    call project_point(surf, x, [5.0_dp, -1.0_dp], [1], 1, pr, nf)
    call t%equal_int(pr%status, PROJ_OUTSIDE, '(5,-1) beyond t = 0')
    call t%close_abs(pr%t, 0.0_dp, 0.0_dp, '(5,-1) clamped at t = 0')
    call project_point(surf, x, [-0.5_dp, 3.0_dp], [1], 1, pr, nf)
    call t%equal_int(pr%status, PROJ_OUTSIDE, '(-0.5,3) beyond t = 1')
    call t%close_abs(pr%t, 1.0_dp, 0.0_dp, '(-0.5,3) clamped at t = 1')
    ! exactly on the end normal: an interior solution at the end
    call project_point(surf, x, [4.5_dp, 0.0_dp], [1], 1, pr, nf)
    call t%equal_int(pr%status, PROJ_INTERIOR, '(4.5,0) on the end normal')
    call t%close_abs(pr%d, 0.5_dp, 1.0e-12_dp, '(4.5,0) d')
  end subroutine beyond_the_ends

  !> Half circle as two quarter arcs: a projection started on the first moves to the second.
  subroutine across_segments(t)
    type(checker_t), intent(inout) :: t
    type(contact_surface_t) :: surf
    real(dp) :: x(2, 5), w(3, 2), xs(2)
    type(projection_t) :: pr
    integer :: nf
    x = reshape([4.0_dp, 0.0_dp, 4.0_dp, 4.0_dp, 0.0_dp, 4.0_dp, -4.0_dp, 4.0_dp, &
        -4.0_dp, 0.0_dp], [2, 5])
    w(:, 1) = [1.0_dp, sqrt(0.5_dp), 1.0_dp]
    w(:, 2) = w(:, 1)
    call surface_init(surf, 'H', [SEG_BEZIER, SEG_BEZIER], [3, 3], &
        reshape([1, 2, 3, 3, 4, 5], [3, 2]), x, wgt=w)
    call t%equal_int(surf%next(1), 2, 'next of 1')
    call t%equal_int(surf%prev(2), 1, 'prev of 2')
    xs = [-3.0_dp, 3.5_dp]
    call project_point(surf, x, xs, [1], 1, pr, nf)
    call t%equal_int(pr%status, PROJ_INTERIOR, 'moved on: interior')
    call t%equal_int(pr%seg, 2, 'moved on to segment 2')
    call t%close_abs(pr%xbar(1), 4.0_dp*xs(1)/norm2(xs), 1.0e-10_dp, 'xbar x')
    call t%close_abs(pr%xbar(2), 4.0_dp*xs(2)/norm2(xs), 1.0e-10_dp, 'xbar y')
    call t%close_abs(pr%d, norm2(xs) - 4.0_dp, 1.0e-10_dp, 'd on segment 2')
    ! beyond the far end of the chain: outside
    call project_point(surf, x, [-5.0_dp, -1.0_dp], [1], 1, pr, nf)
    call t%equal_int(pr%status, PROJ_OUTSIDE, 'beyond the far end')
  end subroutine across_segments

  !> Quadratic Lagrange edge x(t) = (2t, t(1-t)); points placed on the normal of known
  !! points, so the closest point and the signed distance are known exactly.
  subroutine quadratic_edge(t)
    type(checker_t), intent(inout) :: t
    type(contact_surface_t) :: surf
    real(dp) :: x(2, 3), xs(2), xst(2), tan(2), n(2), ts, delta
    real(dp), parameter :: tlist(3) = [0.3_dp, 0.5_dp, 0.85_dp], dlist(3) = [-0.05_dp, &
        0.1_dp, -0.2_dp]
    type(projection_t) :: pr
    integer :: nf, k
    x = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.25_dp, 2.0_dp, 0.0_dp], [2, 3])
    call surface_init(surf, 'E', [SEG_LAGRANGE], [3], reshape([1, 2, 3], [3, 1]), x)
    call t%close(surf%ell(1), surf%ell(3), 1.0e-14_dp, 'l of the corners equal')
    do k = 1, 3
      ts = tlist(k)
      delta = dlist(k)
      xst = [2.0_dp*ts, ts*(1.0_dp - ts)]
      tan = [2.0_dp, 1.0_dp - 2.0_dp*ts]
      n = [tan(2), -tan(1)]/norm2(tan)
      xs = xst + delta*n
      call project_point(surf, x, xs, [1], 1, pr, nf)
      call t%equal_int(pr%status, PROJ_INTERIOR, 'quadratic edge interior')
      call t%close_abs(pr%t, ts, 1.0e-11_dp, 'quadratic edge t')
      call t%close_abs(pr%d, delta, 1.0e-11_dp, 'quadratic edge d')
    end do
    ! the outward normal of this edge (body on the left, above) points down
    call project_point(surf, x, [1.0_dp, 0.35_dp], [1], 1, pr, nf)
    call t%close_abs(pr%d, -0.1_dp, 1.0e-12_dp, 'above the apex: inside, d = -0.1')
    call t%close_abs(pr%normal(2), -1.0_dp, 1.0e-12_dp, 'normal (0,-1) at the apex')
  end subroutine quadratic_edge

  !> A V-shaped (concave) master, body y < |x|: segment 1 (2,2) -> (0,0), segment 2
  !! (0,0) -> (-2,2). Points have a local minimum on each segment; the global one is kept.
  subroutine concave_two_minima(t)
    type(checker_t), intent(inout) :: t
    type(contact_surface_t) :: surf
    real(dp) :: x(2, 3)
    type(projection_t) :: pr
    integer :: nf
    x = reshape([2.0_dp, 2.0_dp, 0.0_dp, 0.0_dp, -2.0_dp, 2.0_dp], [2, 3])
    call surface_init(surf, 'V', [SEG_LAGRANGE, SEG_LAGRANGE], [2, 2], &
        reshape([1, 2, 2, 3], [2, 2]), x)
    call t%equal_int(surf%next(1), 2, 'V chained')
    ! outside: distances 0.7/sqrt2 to segment 1 and 1.3/sqrt2 to segment 2
    call project_point(surf, x, [0.3_dp, 1.0_dp], [2, 1], 2, pr, nf)
    call t%equal_int(pr%seg, 1, 'outside: global minimum on segment 1')
    call t%close_abs(pr%d, 0.7_dp/sqrt(2.0_dp), 1.0e-12_dp, 'outside: d')
    ! inside, near segment 1: d = -0.1/sqrt2 (segment 2's half-plane would say outside)
    call project_point(surf, x, [0.3_dp, 0.2_dp], [2, 1], 2, pr, nf)
    call t%equal_int(pr%seg, 1, 'inside: global minimum on segment 1')
    call t%close_abs(pr%d, -0.1_dp/sqrt(2.0_dp), 1.0e-12_dp, 'inside: d')
    call project_point(surf, x, [-0.5_dp, 1.2_dp], [1, 2], 2, pr, nf)
    call t%equal_int(pr%seg, 2, 'mirror: segment 2')
    call t%close_abs(pr%d, 0.7_dp/sqrt(2.0_dp), 1.0e-12_dp, 'mirror: d')
  end subroutine concave_two_minima

  !> Convex corner (body y < -|x|, the roof of a tent): a point above the apex has the apex
  !! as its closest point, with the mean normal (0, 1).
  subroutine corner_point(t)
    type(checker_t), intent(inout) :: t
    type(contact_surface_t) :: surf
    real(dp) :: x(2, 3)
    type(projection_t) :: pr
    integer :: nf
    x = reshape([1.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, -1.0_dp, -1.0_dp], [2, 3])
    call surface_init(surf, 'A', [SEG_LAGRANGE, SEG_LAGRANGE], [2, 2], &
        reshape([1, 2, 2, 3], [2, 2]), x)
    call project_point(surf, x, [0.05_dp, 0.5_dp], [1, 2], 2, pr, nf)
    call t%equal_int(pr%status, PROJ_CORNER, 'apex is a corner point')
    call t%close_abs(pr%normal(2), 1.0_dp, 1.0e-14_dp, 'mean normal (0,1)')
    call t%close_abs(pr%d, 0.5_dp, 1.0e-14_dp, 'corner d')
  end subroutine corner_point

  !> A Gauss point of the striker of verification/contact_striker, 8e-5 inside a Q8 edge
  !! 0.05 long: once Newton's step is small, the distance decrease it brings is below the
  !! round-off of the distance; the damping used to halve such steps and the iteration to
  !! creep until it failed (the point was treated as open). Converges now, to the foot of
  !! the normal.
  subroutine close_to_master(t)
    type(checker_t), intent(inout) :: t
    type(contact_surface_t) :: surf
    real(dp) :: x(2, 3), xs(2), xp(2), x1(2), x2(2), r(MAX_SEG_NODES)
    type(projection_t) :: pr
    integer :: nf
    x = reshape([6.48934341905694073e-02_dp, 5.00020633903862088e-02_dp, &
        6.48936701567039975e-02_dp, 2.49999999999975589e-02_dp, &
        6.48934341905692963e-02_dp, -2.06339039114389183e-06_dp], [2, 3])
    xs = [6.49728301091865856e-02_dp, 5.63348497363406944e-03_dp]
    call surface_init(surf, 'E', [SEG_LAGRANGE], [3], reshape([1, 2, 3], [3, 1]), x)
    call project_point(surf, x, xs, [1], 1, pr, nf)
    call t%equal_int(nf, 0, 'close to the master: no failure')
    call t%equal_int(pr%status, PROJ_INTERIOR, 'close to the master: interior')
    call segment_geometry(surf, 1, x, pr%t, xp, x1, x2, r)
    call t%close_abs(dot_product(xs - xp, x1)/norm2(x1), 0.0_dp, 1.0e-16_dp, &
        'close to the master: xs - xbar normal to the edge')
    call t%close_abs(pr%d, -norm2(xs - xp), 1.0e-16_dp, 'close to the master: d = -|xs - xbar|')
    call t%close_abs(pr%d, -7.93e-5_dp, 1.0e-7_dp, 'close to the master: d = -7.93e-5')
  end subroutine close_to_master
end program test_projection
