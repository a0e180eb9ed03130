!> When an output is due: the schedule of one kind of output (history records, field
!! snapshots), every n steps (EVERY=n) or at the steps closest to the multiples of a time
!! interval (TIME INTERVAL=dt_out), always with the last step of the run.
!!
!! With a fixed time step dt, the snapshot of the k-th multiple of dt_out is at step
!! n_k = nint(k dt_out/dt), k = 0, 1, ... (doc/user-guide.md §6); `schedule_due` and
!! `schedule_next` answer by step number. `schedule_due_at` answers the same question by time
!! (is t_n, with steps of size dt around it, the step time closest to a multiple of dt_out?),
!! which is what a run whose step changes needs; with a fixed step it agrees with
!! `schedule_due`.
module ictus_app_schedule
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: schedule_t, schedule_init, schedule_due, schedule_next, schedule_due_at

  !> One output's schedule: `every` > 0 steps, or `interval` > dt in time (then `every` = 0);
  !! `dt` the time step, `nlast` the last step of the run (always due).
  type :: schedule_t
    integer :: every = 1
    real(dp) :: interval = 0.0_dp
    real(dp) :: dt = 0.0_dp
    integer :: nlast = 0
  end type schedule_t

contains

  !> A schedule of `every` steps (used when interval <= 0) or of the time `interval`, for a
  !! run of `nlast` steps of size dt.
  pure function schedule_init(every, interval, dt, nlast) result(sc)
    integer, intent(in) :: every, nlast
    real(dp), intent(in) :: interval, dt
    type(schedule_t) :: sc
    sc%nlast = nlast
    sc%dt = dt
    if (interval > 0.0_dp .and. interval <= dt) then
      ! the multiples are at most one step apart: every step is the closest to one of them
      sc%every = 1
    else if (interval > 0.0_dp) then
      sc%every = 0
      sc%interval = interval
    else
      sc%every = max(1, every)
    end if
  end function schedule_init

  !> The step of the k-th multiple of the interval, nint(k interval/dt), or nlast + 1 when it
  !! lies beyond the run.
  pure integer function step_of(sc, k)
    type(schedule_t), intent(in) :: sc
    integer, intent(in) :: k
    real(dp) :: x
    x = real(k, dp)*sc%interval/sc%dt
    if (x >= real(sc%nlast, dp) + 1.0_dp) then
      step_of = sc%nlast + 1
    else
      step_of = nint(x)
    end if
  end function step_of

  !> The first k whose step nint(k interval/dt) is n or more.
  pure integer function first_k(sc, n) result(k)
    type(schedule_t), intent(in) :: sc
    integer, intent(in) :: n
    ! nint(k r) >= n needs k r >= n - 1/2: start just below and step up (at most a few k)
    k = max(0, int((real(n, dp) - 0.5_dp)*sc%dt/sc%interval) - 1)
    do while (step_of(sc, k) < n)
      k = k + 1
    end do
  end function first_k

  !> Whether an output is due at step n.
  pure logical function schedule_due(sc, n)
    type(schedule_t), intent(in) :: sc
    integer, intent(in) :: n
    if (n == sc%nlast) then
      schedule_due = .true.
    else if (sc%every > 0) then
      schedule_due = mod(n, sc%every) == 0
    else
      schedule_due = step_of(sc, first_k(sc, n)) == n
    end if
  end function schedule_due

  !> The first step after n at which an output is due (at most nlast).
  pure integer function schedule_next(sc, n) result(m)
    type(schedule_t), intent(in) :: sc
    integer, intent(in) :: n
    if (sc%every > 0) then
      m = (n/sc%every + 1)*sc%every
    else
      m = step_of(sc, first_k(sc, n + 1))
    end if
    m = min(m, sc%nlast)
  end function schedule_next

  !> Whether an output is due at time t (at the last step when `last`), with the step dt_before
  !! that led to t and the step dt_after that leaves it: for TIME INTERVAL=, when a multiple
  !! k dt_out lies in [t - dt_before/2, t + dt_after/2) (t is then the step time closest to it;
  !! these intervals of consecutive steps tile the time axis, so every multiple has exactly one
  !! step); for EVERY=n, when t/dt_after is a multiple of n (a fixed step).
  pure logical function schedule_due_at(sc, t, dt_before, dt_after, last)
    type(schedule_t), intent(in) :: sc
    real(dp), intent(in) :: t, dt_before, dt_after
    logical, intent(in) :: last
    real(dp) :: k
    if (last) then
      schedule_due_at = .true.
    else if (sc%every > 0) then
      schedule_due_at = mod(nint(t/dt_after), sc%every) == 0
    else
      k = real(ceiling((t - 0.5_dp*dt_before)/sc%interval), dp)
      schedule_due_at = k*sc%interval < t + 0.5_dp*dt_after
    end if
  end function schedule_due_at
end module ictus_app_schedule
