!> The output schedules (ictus_app_schedule) against their definition, by brute force:
!!
!! * EVERY=n: due at the multiples of n and at the last step;
!! * TIME INTERVAL=dt_out: due at the step whose time n dt is closest to each multiple
!!   k dt_out (found here by searching all steps for the smallest |n dt - k dt_out|), and at
!!   the last step; an interval not above dt makes every step due;
!! * `schedule_next(n)` is the first due step after n; `schedule_due_at(n dt, dt)` (the
!!   time-based question) agrees with `schedule_due(n)`.
program test_schedule
  use ictus_core_kinds, only: dp
  use ictus_app_schedule, only: schedule_t, schedule_init, schedule_due, schedule_next, &
      schedule_due_at
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  call t%start("app/schedule")
  call check_case(t, 'every 7 of 100', 7, 0.0_dp, 0.01_dp, 100)
  call check_case(t, 'every 1 of 13', 1, 0.0_dp, 0.5_dp, 13)
  call check_case(t, 'every 40 of 30 (first and last only)', 40, 0.0_dp, 1.0_dp, 30)
  call check_case(t, 'interval 0.037, dt 0.00702', 0, 0.037_dp, 0.00702_dp, 72)
  call check_case(t, 'interval 2.37 dt', 0, 2.37_dp*0.013_dp, 0.013_dp, 41)
  call check_case(t, 'interval 1.37 dt', 0, 1.37_dp, 1.0_dp, 57)
  call check_case(t, 'interval 10.4 dt', 0, 10.4_dp*3.0e-7_dp, 3.0e-7_dp, 333)
  call check_case(t, 'interval beyond the run', 0, 5.0_dp, 0.1_dp, 20)
  call check_case(t, 'interval 0.4 dt (every step)', 0, 0.4e-3_dp, 1.0e-3_dp, 25)
  call t%finish()

contains

  !> Compares the schedule of (every, interval) with the brute-force set of due steps.
  subroutine check_case(t, label, every, interval, dt, nlast)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: label
    integer, intent(in) :: every, nlast
    real(dp), intent(in) :: interval, dt
    type(schedule_t) :: sc
    logical :: want(0:nlast)
    logical :: ok_due, ok_next, ok_time
    integer :: n, k, best, m
    want = .false.
    want(nlast) = .true.
    if (interval > 0.0_dp) then
      k = 0
      ! the multiples k dt_out up to half a step past the end
      do while (k*interval <= (nlast + 0.49_dp)*dt)
        best = 0
        do n = 1, nlast
          if (abs(n*dt - k*interval) < abs(best*dt - k*interval)) best = n
        end do
        want(best) = .true.
        k = k + 1
      end do
    else
      do n = 0, nlast
        want(n) = mod(n, every) == 0 .or. want(n)
      end do
    end if
    sc = schedule_init(every, interval, dt, nlast)
    ok_due = .true.
    ok_next = .true.
    ok_time = .true.
    do n = 0, nlast
      ok_due = ok_due .and. (schedule_due(sc, n) .eqv. want(n))
      ok_time = ok_time .and. (schedule_due_at(sc, n*dt, dt, dt, n == nlast) .eqv. want(n))
      if (n < nlast) then
        m = n + 1
        do while (.not. want(m))
          m = m + 1
        end do
        ok_next = ok_next .and. schedule_next(sc, n) == m
      end if
    end do
    call t%true(ok_due, label//': due at the expected steps')
    call t%true(ok_next, label//': next gives the first due step after each step')
    call t%true(ok_time, label//': due at time n dt agrees with due at step n')
  end subroutine check_case
end program test_schedule
