!> Wall-clock timer.
module ictus_core_timer
  use ictus_core_kinds, only: dp, i8
  implicit none
  private
  public :: wall_time

contains

  !> Seconds since an arbitrary origin, from the system clock.
  function wall_time() result(t)
    real(dp) :: t
    integer(i8) :: count, rate
    call system_clock(count, rate)
    t = real(count, dp)/real(rate, dp)
  end function wall_time
end module ictus_core_timer
