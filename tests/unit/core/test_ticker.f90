!> The set-up ticker: lines at most once per interval, the clock read only every `stride`
!! items, the percentage or the count in the text. A fake clock (one second per look, or
!! set by hand) makes the expected lines exact.
module fake_clocks
  use ictus_core_kinds, only: dp
  implicit none
  !> The fake clock's time and how often it was read.
  real(dp) :: now = 0.0_dp
  integer :: looks = 0
contains

  !> One second later at every look.
  function step_clock() result(s)
    real(dp) :: s
    looks = looks + 1
    s = now
    now = now + 1.0_dp
  end function step_clock

  !> The time set by the test.
  function fixed_clock() result(s)
    real(dp) :: s
    s = now
  end function fixed_clock
end module fake_clocks

program test_ticker
  use ictus_core_ticker, only: ticker_t, ticker_start
  use ictus_test_check, only: checker_t
  use fake_clocks, only: dp, now, looks, step_clock, fixed_clock
  implicit none
  type(checker_t) :: t
  type(ticker_t) :: tk
  integer :: i, lines_at(8), nat
  call t%start("ticker")

  ! interval 10 s, the clock read at every item and advancing 1 s per look: a line at the
  ! 10th, 20th and 30th look, i.e. after 10, 20 and 30 of 40 items
  now = 0.0_dp
  looks = 0
  call ticker_start(tk, 'deck reading', interval=10.0_dp, clock=step_clock)
  nat = 0
  do i = 1, 40
    call tk%tick(i, 40)
    if (tk%nlines > nat) then
      nat = nat + 1
      lines_at(nat) = i
    end if
  end do
  call t%equal_int(tk%nlines, 4, "one line per 10 s over 40 s (at 10, 20, 30, 40 s)")
  call t%true(all(lines_at(1:3) == [10, 20, 30]), "lines when 10 s have passed")
  call t%true(tk%last == 'deck reading: 100 % (40.0 s)', "last line: "//tk%last)
  call t%equal_int(looks, 41, "the clock is read at the start and once per item")

  ! stride 100: the clock is looked at every 100 items only; with interval 0 each look prints
  now = 0.0_dp
  looks = 0
  call ticker_start(tk, 'assembly', stride=100, interval=0.0_dp, clock=step_clock)
  do i = 1, 1000
    call tk%tick(i, 1000)
  end do
  call t%equal_int(looks, 11, "stride 100 over 1000 items: 10 looks (and the start)")
  call t%equal_int(tk%nlines, 10, "interval 0: a line at every look")
  call t%true(tk%last == 'assembly: 100 % (10.0 s)', "stride: last line: "//tk%last)

  ! a second loop of the same phase (the count starts again) is still watched
  call tk%tick(100, 1000)
  call t%equal_int(tk%nlines, 11, "a count that starts again is still watched")
  call t%true(tk%last == 'assembly: 10 % (11.0 s)', "restarted count: "//tk%last)

  ! a fixed clock: nothing until the interval has passed, then the time since the start
  now = 5.0_dp
  call ticker_start(tk, 'omega_max estimate', interval=10.0_dp, clock=fixed_clock, &
      unit='iterations')
  now = 14.9_dp
  call tk%tick(50, 0)
  call t%equal_int(tk%nlines, 0, "no line before the interval")
  now = 17.3_dp
  call tk%tick(120, 0)
  call t%true(tk%last == 'omega_max estimate: 120 iterations (12.3 s)', &
      "unknown total: the count and its unit: "//tk%last)
  now = 20.0_dp
  call tk%tick(121, 0)
  call t%equal_int(tk%nlines, 1, "the interval counts from the last line")
  now = 5.5_dp
  call ticker_start(tk, 'results file', interval=0.0_dp, clock=fixed_clock)
  call tk%tick(1, 3)
  call t%true(tk%last == 'results file: 33 % (0.0 s)', "under one second: "//tk%last)
  call t%finish()
end program test_ticker
