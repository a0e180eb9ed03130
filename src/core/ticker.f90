!> Progress lines inside a long set-up phase: "<phase>: 45 % (12.3 s)" at most once per
!! interval (10 s by default), so a big model never stays silent for long.
!!
!! `tick(done, total)` costs one integer comparison on most calls: the clock is read only
!! every `stride` items (and at most once per call). The clock is a procedure pointer, so a
!! test can drive the ticker with a clock of its own; the lines go to the rank-0 logger, and
!! the last one is kept in `last` (with the count in `nlines`) for the same reason.
module ictus_core_ticker
  use ictus_core_kinds, only: dp, i8
  use ictus_core_logger, only: log_info
  use ictus_core_timer, only: wall_time
  implicit none
  private
  public :: ticker_t, ticker_start, ticker_clock, TICK_INTERVAL

  !> Seconds between two progress lines of one phase.
  real(dp), parameter :: TICK_INTERVAL = 10.0_dp

  abstract interface
    !> Seconds since an arbitrary origin.
    function ticker_clock() result(t)
      import :: dp
      real(dp) :: t
    end function ticker_clock
  end interface

  type :: ticker_t
    !> The phase, as it begins each line.
    character(len=:), allocatable :: name
    !> What is counted when the total is unknown (total <= 0): "120 <unit>".
    character(len=:), allocatable :: unit
    real(dp) :: interval = TICK_INTERVAL
    !> Clock at the start and at the last line (or the start).
    real(dp) :: t_start = 0.0_dp
    real(dp) :: t_last = 0.0_dp
    !> The clock is read when `done` reaches `next_check`, which then moves `stride` on.
    integer(i8) :: stride = 1
    integer(i8) :: next_check = 0
    procedure(ticker_clock), pointer, nopass :: clock => null()
    !> Lines printed so far and the last of them.
    integer :: nlines = 0
    character(len=:), allocatable :: last
  contains
    procedure :: tick => ticker_tick
  end type ticker_t

contains

  !> Starts the ticker of phase `name` now. `stride`: items between two looks at the clock
  !! (default 1; choose it so that `stride` items take well under a second). `interval`:
  !! seconds between lines (default TICK_INTERVAL; 0 prints at every look). `clock`: the
  !! time source (default the wall clock). `unit`: the name of the items, used when the
  !! total is not known.
  subroutine ticker_start(tk, name, stride, interval, clock, unit)
    type(ticker_t), intent(out) :: tk
    character(len=*), intent(in) :: name
    integer, intent(in), optional :: stride
    real(dp), intent(in), optional :: interval
    procedure(ticker_clock), optional :: clock
    character(len=*), intent(in), optional :: unit
    tk%name = name
    tk%unit = 'done'
    if (present(unit)) tk%unit = unit
    if (present(stride)) tk%stride = max(1, stride)
    if (present(interval)) tk%interval = interval
    if (present(clock)) then
      tk%clock => clock
    else
      tk%clock => wall_time
    end if
    tk%next_check = tk%stride
    tk%t_start = tk%clock()
    tk%t_last = tk%t_start
    tk%last = ''
  end subroutine ticker_start

  !> Reports `done` of `total` items (total <= 0: not known) when the interval has passed.
  subroutine ticker_tick(tk, done, total)
    class(ticker_t), intent(inout) :: tk
    integer, intent(in) :: done, total
    real(dp) :: t
    character(len=32) :: amount, secs
    ! a count below the last stride starts over (a second loop of the same phase)
    if (done < tk%next_check .and. done >= tk%next_check - tk%stride) return
    tk%next_check = int(done, i8) + tk%stride
    if (.not. associated(tk%clock)) return
    t = tk%clock()
    if (t - tk%t_last < tk%interval) return
    tk%t_last = t
    if (total > 0) then
      write(amount, '(i0,a)') min(100, int(100.0_dp*real(done, dp)/real(total, dp))), ' %'
    else
      write(amount, '(i0,a)') done, ' '//tk%unit
    end if
    write(secs, '(f0.1)') t - tk%t_start
    ! f0.1 drops the zero before the point below one second
    if (secs(1:1) == '.') then
      tk%last = tk%name//': '//trim(amount)//' (0'//trim(secs)//' s)'
    else
      tk%last = tk%name//': '//trim(amount)//' ('//trim(secs)//' s)'
    end if
    tk%nlines = tk%nlines + 1
    call log_info(tk%last)
  end subroutine ticker_tick

end module ictus_core_ticker
