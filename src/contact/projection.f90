!> Closest-point projection of a point onto a contact surface (physics.md section 5.2).
!!
!! On one segment, f(t) = (x_s - x(t)).x'(t) = 0 is solved for t in [0, 1] by a safeguarded
!! Newton iteration: start at the nearest of 5 samples; Newton steps only where
!! f' = -|x'|^2 + (x_s - x).x'' < 0 (a distance minimum) and inside the bracket of the
!! minimum, bisection otherwise; steps halved (up to 5 times) while the distance grows;
!! clamping at t = 0 and t = 1. A projection clamped at a segment end moves on to the
!! neighbour segment if the distance keeps decreasing there; if it does not, the point's
!! closest point is the corner between the two (normal: the mean of the two segment
!! normals). Clamped at an end of the surface with f /= 0, the point lies beyond the surface
!! and is not in contact. Several candidate segments: the global minimum distance is kept.
!!
!! Signed distance d = (x_s - xbar).n with the outward normal n = (t_y, -t_x) of the
!! (counter-clockwise) master; penetration gp = max(0, -d).
module ictus_contact_projection
  use ictus_core_kinds, only: dp
  use ictus_contact_surface, only: contact_surface_t, MAX_SEG_NODES, segment_geometry
  implicit none
  private
  public :: projection_t, project_on_segment, project_point, &
      PROJ_NONE, PROJ_INTERIOR, PROJ_CORNER, PROJ_OUTSIDE, PROJ_FAILED, &
      SEG_INTERIOR, SEG_END0, SEG_END1, SEG_FAILED

  !> Outcome of a projection onto a surface: none (no candidate segment), an interior point
  !! of a segment, a corner between two segments, beyond an end of the surface, or failed.
  integer, parameter :: PROJ_NONE = 0, PROJ_INTERIOR = 1, PROJ_CORNER = 2, &
      PROJ_OUTSIDE = 3, PROJ_FAILED = 4
  !> Outcome on one segment.
  integer, parameter :: SEG_INTERIOR = 1, SEG_END0 = 2, SEG_END1 = 3, SEG_FAILED = 4

  !> Newton iterations per segment, start samples, neighbour hops, damping halvings.
  integer, parameter :: max_iter = 60, n_samples = 4, max_hops = 64, max_halvings = 5
  !> Relative convergence tolerance (on distance along the segment).
  real(dp), parameter :: tol = 1.0e-13_dp

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

  !> Closest point of segment s to xs, with t clamped to [0, 1].
  !! @param surf surface; @param s segment; @param x coordinates (2, nn); @param xs point (2);
  !! @param t result parameter; @param status SEG_*; @param iters Newton iterations used
  pure subroutine project_on_segment(surf, s, x, xs, t, status, iters)
    type(contact_surface_t), intent(in) :: surf
    integer, intent(in) :: s
    real(dp), intent(in) :: x(:,:), xs(2)
    real(dp), intent(out) :: t
    integer, intent(out) :: status, iters
    real(dp) :: xp(2), x1(2), x2(2), r(MAX_SEG_NODES), rv(2)
    real(dp) :: a, b, f, fp, tn, dist, best, ell, jac, tk
    integer :: k, it
    ell = max(surf%seg_len(s), tiny(1.0_dp))
    ! start value: the nearest of n_samples + 1 equally spaced samples
    best = huge(1.0_dp)
    t = 0.0_dp
    do k = 0, n_samples
      tk = real(k, dp)/real(n_samples, dp)
      call segment_geometry(surf, s, x, tk, xp, x1, x2, r)
      dist = norm2(xs - xp)
      if (dist < best) then
        best = dist
        t = tk
      end if
    end do
    a = 0.0_dp
    b = 1.0_dp
    status = SEG_FAILED
    do it = 1, max_iter
      iters = it
      call segment_geometry(surf, s, x, t, xp, x1, x2, r)
      rv = xs - xp
      dist = norm2(rv)
      f = dot_product(rv, x1)
      fp = -dot_product(x1, x1) + dot_product(rv, x2)
      jac = norm2(x1)
      if (abs(f) <= tol*jac*max(ell, dist)) then
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
      ! damping: halve the step while the distance grows
      do k = 1, max_halvings
        call segment_geometry(surf, s, x, tn, xp, x1, x2, r)
        if (norm2(xs - xp) <= dist) exit
        tn = t + 0.5_dp*(tn - t)
      end do
      if (abs(tn - t)*jac <= 0.01_dp*tol*ell) then
        ! no progress possible: accept if f is small at round-off level, else give up
        if (abs(f) <= 1.0e3_dp*tol*jac*max(ell, dist)) status = SEG_INTERIOR
        return
      end if
      t = tn
    end do
  end subroutine project_on_segment

  !> Closest point of the surface to xs among the candidate segments (global minimum), each
  !! followed across segment ends into its neighbours.
  !! @param surf surface; @param x coordinates (2, nn); @param xs point (2);
  !! @param cand candidate segments (ncand); @param ncand their number;
  !! @param res the projection; @param nfail 1 if any candidate's projection failed, else 0
  pure subroutine project_point(surf, x, xs, cand, ncand, res, nfail)
    type(contact_surface_t), intent(in) :: surf
    real(dp), intent(in) :: x(:,:), xs(2)
    integer, intent(in) :: cand(:), ncand
    type(projection_t), intent(out) :: res
    integer, intent(out) :: nfail
    type(projection_t) :: one
    integer :: k
    nfail = 0
    res%status = PROJ_NONE
    do k = 1, ncand
      call walk(surf, x, xs, cand(k), one)
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
  end subroutine project_point

  !> Projection starting on segment s0, moving on to neighbours across clamped ends.
  pure subroutine walk(surf, x, xs, s0, res)
    type(contact_surface_t), intent(in) :: surf
    real(dp), intent(in) :: x(:,:), xs(2)
    integer, intent(in) :: s0
    type(projection_t), intent(out) :: res
    integer :: s, from, hop, st, iters, nb
    real(dp) :: t, f
    s = s0
    from = 0
    res%status = PROJ_FAILED
    do hop = 1, max_hops
      call project_on_segment(surf, s, x, xs, t, st, iters)
      select case (st)
      case (SEG_INTERIOR)
        call fill(surf, x, xs, s, t, 0, PROJ_INTERIOR, res)
        return
      case (SEG_END1)
        nb = surf%next(s)
        if (nb == 0) then
          call fill(surf, x, xs, s, 1.0_dp, 0, PROJ_OUTSIDE, res)
          return
        end if
        f = f_at(surf, x, xs, nb, 0.0_dp)
        if (nb == from .or. f <= 0.0_dp) then
          call fill(surf, x, xs, s, 1.0_dp, nb, PROJ_CORNER, res)
          return
        end if
      case (SEG_END0)
        nb = surf%prev(s)
        if (nb == 0) then
          call fill(surf, x, xs, s, 0.0_dp, 0, PROJ_OUTSIDE, res)
          return
        end if
        f = f_at(surf, x, xs, nb, 1.0_dp)
        if (nb == from .or. f >= 0.0_dp) then
          call fill(surf, x, xs, s, 0.0_dp, nb, PROJ_CORNER, res)
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

  !> f(t) = (xs - x(t)).x'(t) on segment s.
  pure real(dp) function f_at(surf, x, xs, s, t) result(f)
    type(contact_surface_t), intent(in) :: surf
    real(dp), intent(in) :: x(:,:), xs(2), t
    integer, intent(in) :: s
    real(dp) :: xp(2), x1(2), x2(2), r(MAX_SEG_NODES)
    call segment_geometry(surf, s, x, t, xp, x1, x2, r)
    f = dot_product(xs - xp, x1)
  end function f_at

  !> Fills a projection result at (s, t); at a corner with segment nb the normal is the mean
  !! of both segments' normals there.
  pure subroutine fill(surf, x, xs, s, t, nb, status, res)
    type(contact_surface_t), intent(in) :: surf
    real(dp), intent(in) :: x(:,:), xs(2), t
    integer, intent(in) :: s, nb, status
    type(projection_t), intent(out) :: res
    real(dp) :: xp(2), x1(2), x2(2), r(MAX_SEG_NODES), n(2), y1(2), jn
    call segment_geometry(surf, s, x, t, xp, x1, x2, r)
    n = [x1(2), -x1(1)]
    jn = norm2(n)
    if (jn <= 0.0_dp) then
      res%status = PROJ_FAILED
      return
    end if
    n = n/jn
    if (nb > 0) then
      call segment_geometry(surf, nb, x, 1.0_dp - t, xp, y1, x2, r)
      jn = norm2(y1)
      if (jn > 0.0_dp) n = n + [y1(2), -y1(1)]/jn
      jn = norm2(n)
      if (jn <= 0.0_dp) then
        res%status = PROJ_FAILED
        return
      end if
      n = n/jn
      call segment_geometry(surf, s, x, t, xp, x1, x2, r)
    end if
    res%status = status
    res%seg = s
    res%t = t
    res%xbar = xp
    res%normal = n
    res%d = dot_product(xs - xp, n)
    res%dist = norm2(xs - xp)
  end subroutine fill
end module ictus_contact_projection
