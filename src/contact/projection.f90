!> Closest-point projection of a point onto a contact surface (doc/contact.md §3).
!!
!! On one segment, f(t) = (x_s - x(t)).x'(t) = 0 is solved for t in [0, 1] by a safeguarded
!! Newton iteration: start at the nearest of 5 samples; Newton steps only where
!! f' = -|x'|^2 + (x_s - x).x'' < 0 (a distance minimum) and inside the bracket of the
!! minimum, bisection otherwise; steps halved (up to 5 times) while the distance grows
!! beyond round-off; clamping at t = 0 and t = 1. A projection clamped at a segment end
!! moves on to the neighbour segment if the distance keeps decreasing there; if it does not,
!! the point's closest point is the corner between the two (normal: the mean of the two
!! segment normals). Clamped at an end of the surface with f /= 0, the point lies beyond the
!! surface and is not in contact. Several candidate segments: the global minimum distance is
!! kept.
!!
!! Cost: the segments are evaluated as Bezier curves built once per force evaluation
!! (segment_curve_t, with their 5 samples), and the walks of one point's candidates, which
!! cross into the same segments, project onto each segment once (segment_memo_t). Both give
!! the same results as evaluating and projecting afresh; the curves equal segment_geometry
!! to round-off.
!!
!! Signed distance d = (x_s - xbar).n with the outward normal n = (t_y, -t_x) of the
!! (counter-clockwise) master; penetration gp = max(0, -d).
module ictus_contact_projection
  use ictus_core_kinds, only: dp
  use ictus_contact_surface, only: contact_surface_t, segment_curve_t, &
      surface_curves, curve_geometry, CURVE_SAMPLES
  implicit none
  private
  public :: projection_t, project_point, project_on_curve, &
      PROJ_NONE, PROJ_INTERIOR, PROJ_CORNER, PROJ_OUTSIDE, PROJ_FAILED, &
      SEG_INTERIOR, SEG_END0, SEG_END1, SEG_FAILED

  !> Outcome of a projection onto a surface: none (no candidate segment), an interior point
  !! of a segment, a corner between two segments, beyond an end of the surface, or failed.
  integer, parameter :: PROJ_NONE = 0, PROJ_INTERIOR = 1, PROJ_CORNER = 2, &
      PROJ_OUTSIDE = 3, PROJ_FAILED = 4
  !> Outcome on one segment.
  integer, parameter :: SEG_INTERIOR = 1, SEG_END0 = 2, SEG_END1 = 3, SEG_FAILED = 4

  !> Newton iterations per segment, neighbour hops, damping halvings (start samples:
  !! CURVE_SAMPLES + 1, kept by the segment curves).
  integer, parameter :: max_iter = 60, max_hops = 64, max_halvings = 5
  !> Relative convergence tolerance (on distance along the segment).
  real(dp), parameter :: tol = 1.0e-13_dp
  !> Round-off of a coordinate difference, relative to the size of the coordinates
  !! (ro = roundoff max|x|). f is converged when below |x'| ro as well, and a damped step is
  !! accepted when it does not increase the distance by more than ro: below that, f and
  !! distance changes are noise. tol ell alone can be below the round-off of f (3e-16 for
  !! 316 segments on a unit side); and near a master (x_s 1e-4 from it) the distance
  !! decrease of a small Newton step (|dt| < 1e-9) is below the round-off of the distance:
  !! without this floor the halvings would cut every such step 32-fold, and the iteration
  !! could end at max_iter without converging (the point taken as open).
  real(dp), parameter :: roundoff = 8.0_dp*epsilon(1.0_dp)
  !> Segments whose projection project_point remembers for one point: the walks of
  !! neighbouring candidates cross into the same segments, a few distinct ones per point
  !! (counts on the benchmark meshes: doc/performance-history.md, "Notes moved out of the
  !! code"); a point whose walks meet more simply projects again.
  integer, parameter :: memo_size = 16

  !> Projections onto single segments done for the current point (segment, t, SEG_*
  !! outcome): project_on_curve is a function of the segment and the point alone, so a
  !! remembered result is the one a new call would give, bit for bit. `reported`: a walk has
  !! ended at this interior point already, so another walk ending there adds nothing.
  type :: segment_memo_t
    integer :: n
    integer :: seg(memo_size)
    integer :: status(memo_size)
    real(dp) :: t(memo_size)
    logical :: reported(memo_size)
  end type segment_memo_t

  !> Closest point of a surface to a point: on the segments' curves of the current
  !! coordinates (the contact kernels), or on coordinates (builds the curves; tests).
  interface project_point
    module procedure project_point_curves, project_point_coords
  end interface project_point

  !> The closest point of a surface to a point.
  type :: projection_t
    !> PROJ_* outcome.
    integer :: status = PROJ_NONE
    !> Segment and parameter t in [0, 1] of the closest point.
    integer :: seg = 0
    real(dp) :: t = 0.0_dp
    !> Closest point (2) and unit outward normal there (2).
    real(dp) :: xbar(2) = 0.0_dp
    real(dp) :: normal(2) = 0.0_dp
    !> Signed distance (x_s - xbar).normal and distance |x_s - xbar|.
    real(dp) :: d = 0.0_dp
    real(dp) :: dist = 0.0_dp
  end type projection_t

contains

  !> Closest point of a segment curve to xs, with t clamped to [0, 1] (the algorithm at the top).
  !! @param c the segment's curve; @param seg_len its reference length; @param xs point (2);
  !! @param t result parameter; @param status SEG_*; @param iters Newton iterations used
  pure subroutine project_on_curve(c, seg_len, xs, t, status, iters)
    type(segment_curve_t), intent(in) :: c
    real(dp), intent(in) :: seg_len, xs(2)
    real(dp), intent(out) :: t
    integer, intent(out) :: status, iters
    real(dp) :: xp(2), x1(2), x2(2), yp(2), y1(2), y2(2), rv(2)
    real(dp) :: a, b, f, fp, tn, dist, best, ell, jac, d2, ro
    integer :: k, it
    logical :: have_tn
    ell = max(seg_len, tiny(1.0_dp))
    ! start value: the nearest of the curve's CURVE_SAMPLES + 1 equally spaced samples
    ! (squared distances: no square root)
    best = huge(1.0_dp)
    t = 0.0_dp
    do k = 0, CURVE_SAMPLES
      d2 = (xs(1) - c%xk(1, k))**2 + (xs(2) - c%xk(2, k))**2
      if (d2 < best) then
        best = d2
        t = real(k, dp)/real(CURVE_SAMPLES, dp)
      end if
    end do
    a = 0.0_dp
    b = 1.0_dp
    status = SEG_FAILED
    iters = 0
    call curve_geometry(c, t, xp, x1, x2)
    do it = 1, max_iter
      iters = it
      rv = xs - xp
      dist = sqrt(rv(1)**2 + rv(2)**2)
      f = dot_product(rv, x1)
      fp = -dot_product(x1, x1) + dot_product(rv, x2)
      jac = sqrt(x1(1)**2 + x1(2)**2)
      ro = roundoff*max(abs(xs(1)), abs(xs(2)), abs(xp(1)), abs(xp(2)))
      if (abs(f) <= jac*max(tol*max(ell, dist), ro)) then
        status = SEG_INTERIOR
        return
      end if
      if (t >= 1.0_dp .and. f > 0.0_dp) then
        status = SEG_END1
        return
      end if
      if (t <= 0.0_dp .and. f < 0.0_dp) then
        status = SEG_END0
        return
      end if
      ! the minimum lies right of t when f > 0 (distance decreasing), left when f < 0
      if (f > 0.0_dp) then
        a = max(a, t)
      else
        b = min(b, t)
      end if
      if ((b - a)*jac <= tol*ell) then
        status = SEG_INTERIOR
        return
      end if
      tn = -1.0_dp
      if (fp < 0.0_dp) then
        tn = min(max(t - f/fp, 0.0_dp), 1.0_dp)
        if (tn < a .or. tn > b) tn = -1.0_dp
      end if
      if (tn < 0.0_dp) tn = 0.5_dp*(a + b)
      ! damping: halve the step while the distance grows (beyond round-off); the geometry at
      ! the accepted tn is that of the next iteration
      have_tn = .false.
      do k = 1, max_halvings
        call curve_geometry(c, tn, yp, y1, y2)
        have_tn = sqrt((xs(1) - yp(1))**2 + (xs(2) - yp(2))**2) <= dist + ro
        if (have_tn) exit
        tn = t + 0.5_dp*(tn - t)
      end do
      if (abs(tn - t)*jac <= 0.01_dp*tol*ell) then
        ! no progress possible: accept if f is small at round-off level, else give up
        if (abs(f) <= 1.0e3_dp*tol*jac*max(ell, dist)) status = SEG_INTERIOR
        return
      end if
      t = tn
      if (have_tn) then
        xp = yp
        x1 = y1
        x2 = y2
      else
        call curve_geometry(c, t, xp, x1, x2)
      end if
    end do
  end subroutine project_on_curve

  !> Closest point of the surface to xs among the candidate segments (global minimum), each
  !! followed across segment ends into its neighbours.
  !! @param surf surface; @param curves its segments on the current coordinates (nseg),
  !! from surface_curves; @param xs point (2);
  !! @param cand candidate segments (ncand); @param ncand their number;
  !! @param res the projection; @param nfail 1 if any candidate's projection failed, else 0
  pure subroutine project_point_curves(surf, curves, xs, cand, ncand, res, nfail)
    type(contact_surface_t), intent(in) :: surf
    type(segment_curve_t), intent(in) :: curves(:)
    real(dp), intent(in) :: xs(2)
    integer, intent(in) :: cand(:), ncand
    type(projection_t), intent(out) :: res
    integer, intent(out) :: nfail
    type(projection_t) :: one
    type(segment_memo_t) :: memo
    integer :: k
    nfail = 0
    res%status = PROJ_NONE
    memo%n = 0
    do k = 1, ncand
      call walk(surf, curves, xs, cand(k), memo, one)
      select case (one%status)
      case (PROJ_FAILED)
        nfail = 1
      case (PROJ_INTERIOR, PROJ_CORNER)
        if (res%status /= PROJ_INTERIOR .and. res%status /= PROJ_CORNER) then
          res = one
        else if (one%dist < res%dist) then
          res = one
        end if
      case (PROJ_OUTSIDE)
        if (res%status == PROJ_NONE) res = one
      end select
    end do
    if (nfail > 0 .and. res%status == PROJ_NONE) res%status = PROJ_FAILED
  end subroutine project_point_curves

  !> project_point on coordinates: builds the curves of all segments first (allocates; for
  !! tests and one-off use, the contact kernels keep the curves of an evaluation).
  !! @param surf surface; @param x coordinates (2, nn); other arguments as
  !! project_point_curves
  pure subroutine project_point_coords(surf, x, xs, cand, ncand, res, nfail)
    type(contact_surface_t), intent(in) :: surf
    real(dp), intent(in) :: x(:,:), xs(2)
    integer, intent(in) :: cand(:), ncand
    type(projection_t), intent(out) :: res
    integer, intent(out) :: nfail
    type(segment_curve_t), allocatable :: curves(:)
    allocate(curves(surf%nseg))
    call surface_curves(surf, x, curves)
    call project_point_curves(surf, curves, xs, cand, ncand, res, nfail)
  end subroutine project_point_coords

  !> Projection starting on segment s0, moving on to neighbours across clamped ends; the
  !! projections onto single segments are looked up in, or added to, memo. A walk that ends
  !! at the interior point of an earlier walk (from a neighbouring candidate) returns
  !! PROJ_NONE: its result would be that one, bit for bit, and project_point has it.
  pure subroutine walk(surf, curves, xs, s0, memo, res)
    type(contact_surface_t), intent(in) :: surf
    type(segment_curve_t), intent(in) :: curves(:)
    real(dp), intent(in) :: xs(2)
    integer, intent(in) :: s0
    type(segment_memo_t), intent(inout) :: memo
    type(projection_t), intent(out) :: res
    integer :: s, from, hop, st, nb, slot
    real(dp) :: t, f
    s = s0
    from = 0
    res%status = PROJ_FAILED
    do hop = 1, max_hops
      call memo_project(surf, curves, xs, s, memo, t, st, slot)
      select case (st)
      case (SEG_INTERIOR)
        if (slot > 0) then
          if (memo%reported(slot)) then
            res%status = PROJ_NONE
            return
          end if
          memo%reported(slot) = .true.
        end if
        call fill(curves, xs, s, t, 0, PROJ_INTERIOR, res)
        return
      case (SEG_END1)
        nb = surf%next(s)
        if (nb == 0) then
          call fill(curves, xs, s, 1.0_dp, 0, PROJ_OUTSIDE, res)
          return
        end if
        f = f_at(curves(nb), xs, 0.0_dp)
        if (nb == from .or. f <= 0.0_dp) then
          call fill(curves, xs, s, 1.0_dp, nb, PROJ_CORNER, res)
          return
        end if
      case (SEG_END0)
        nb = surf%prev(s)
        if (nb == 0) then
          call fill(curves, xs, s, 0.0_dp, 0, PROJ_OUTSIDE, res)
          return
        end if
        f = f_at(curves(nb), xs, 1.0_dp)
        if (nb == from .or. f >= 0.0_dp) then
          call fill(curves, xs, s, 0.0_dp, nb, PROJ_CORNER, res)
          return
        end if
      case default
        res%status = PROJ_FAILED
        return
      end select
      from = s
      s = nb
    end do
  end subroutine walk

  !> Projection onto segment s (project_on_curve), or its remembered result for this point;
  !! slot: its entry in memo (0 when memo is full).
  pure subroutine memo_project(surf, curves, xs, s, memo, t, status, slot)
    type(contact_surface_t), intent(in) :: surf
    type(segment_curve_t), intent(in) :: curves(:)
    real(dp), intent(in) :: xs(2)
    integer, intent(in) :: s
    type(segment_memo_t), intent(inout) :: memo
    real(dp), intent(out) :: t
    integer, intent(out) :: status, slot
    integer :: iters
    do slot = 1, memo%n
      if (memo%seg(slot) == s) then
        t = memo%t(slot)
        status = memo%status(slot)
        return
      end if
    end do
    call project_on_curve(curves(s), surf%seg_len(s), xs, t, status, iters)
    slot = 0
    if (memo%n < memo_size) then
      memo%n = memo%n + 1
      slot = memo%n
      memo%seg(slot) = s
      memo%t(slot) = t
      memo%status(slot) = status
      memo%reported(slot) = .false.
    end if
  end subroutine memo_project

  !> f(t) = (xs - x(t)).x'(t) on a segment curve.
  pure real(dp) function f_at(c, xs, t) result(f)
    type(segment_curve_t), intent(in) :: c
    real(dp), intent(in) :: xs(2), t
    real(dp) :: xp(2), x1(2), x2(2)
    call curve_geometry(c, t, xp, x1, x2)
    f = dot_product(xs - xp, x1)
  end function f_at

  !> Fills a projection result at (s, t); at a corner with segment nb the normal is the mean
  !! of both segments' normals there.
  pure subroutine fill(curves, xs, s, t, nb, status, res)
    type(segment_curve_t), intent(in) :: curves(:)
    real(dp), intent(in) :: xs(2), t
    integer, intent(in) :: s, nb, status
    type(projection_t), intent(out) :: res
    real(dp) :: xp(2), x1(2), x2(2), n(2), yp(2), y1(2), jn
    call curve_geometry(curves(s), t, xp, x1, x2)
    n = [x1(2), -x1(1)]
    jn = sqrt(n(1)**2 + n(2)**2)
    if (jn <= 0.0_dp) then
      res%status = PROJ_FAILED
      return
    end if
    n = n/jn
    if (nb > 0) then
      call curve_geometry(curves(nb), 1.0_dp - t, yp, y1, x2)
      jn = sqrt(y1(1)**2 + y1(2)**2)
      if (jn > 0.0_dp) n = n + [y1(2), -y1(1)]/jn
      jn = sqrt(n(1)**2 + n(2)**2)
      if (jn <= 0.0_dp) then
        res%status = PROJ_FAILED
        return
      end if
      n = n/jn
    end if
    res%status = status
    res%seg = s
    res%t = t
    res%xbar = xp
    res%normal = n
    res%d = dot_product(xs - xp, n)
    res%dist = sqrt((xs(1) - xp(1))**2 + (xs(2) - xp(2))**2)
  end subroutine fill
end module ictus_contact_projection
