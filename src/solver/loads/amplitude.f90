!> Amplitudes of loads and prescribed motion (*AMPLITUDE, doc/user-guide.md §5): a factor a(t)
!! that multiplies the magnitude of a *CLOAD, *DLOAD or *BOUNDARY line.
!!
!! A table of points (t_1, a_1), ..., (t_m, a_m) with increasing times defines a(t):
!! * TABULAR: linear between consecutive points;
!! * SMOOTH STEP: a = a_i + (a_{i+1} - a_i) xi^3 (10 - 15 xi + 6 xi^2),
!!   xi = (t - t_i)/(t_{i+1} - t_i), between consecutive points (zero first and second
!!   derivatives at every point);
!! and in both a(t) = a_1 before the first point and a_m after the last one
!! (doc/theory.md §4a).
module ictus_solver_amplitude
  use ictus_core_kinds, only: dp, str_len
  implicit none
  private
  public :: amplitude_t, amp_value, amp_factor, AMP_TABULAR, AMP_SMOOTH_STEP

  !> Kinds of amplitude (DEFINITION=).
  integer, parameter :: AMP_TABULAR = 1, AMP_SMOOTH_STEP = 2

  !> One amplitude: its name, kind (AMP_*), times t(m) (increasing) and values a(m).
  type :: amplitude_t
    character(len=str_len) :: name = ''
    integer :: kind = AMP_TABULAR
    real(dp), allocatable :: t(:)
    real(dp), allocatable :: a(:)
  end type amplitude_t

contains

  !> The value a(t) of amplitude `amp` (see the module header).
  pure real(dp) function amp_value(amp, t) result(a)
    type(amplitude_t), intent(in) :: amp
    real(dp), intent(in) :: t
    integer :: m, lo, hi, mid
    real(dp) :: xi
    m = size(amp%t)
    if (m == 0) then
      a = 1.0_dp
      return
    end if
    if (t <= amp%t(1)) then
      a = amp%a(1)
      return
    end if
    if (t >= amp%t(m)) then
      a = amp%a(m)
      return
    end if
    ! t(lo) <= t < t(hi), hi = lo + 1
    lo = 1
    hi = m
    do while (hi - lo > 1)
      mid = (lo + hi)/2
      if (amp%t(mid) <= t) then
        lo = mid
      else
        hi = mid
      end if
    end do
    xi = (t - amp%t(lo))/(amp%t(hi) - amp%t(lo))
    if (amp%kind == AMP_SMOOTH_STEP) xi = xi**3*(10.0_dp - 15.0_dp*xi + 6.0_dp*xi**2)
    a = amp%a(lo) + (amp%a(hi) - amp%a(lo))*xi
  end function amp_value

  !> The factor of a load with amplitude index k of `amps` at time t: 1 for k = 0 (no
  !! amplitude: the load is applied in full from t = 0), else amp_value.
  pure real(dp) function amp_factor(amps, k, t) result(a)
    type(amplitude_t), intent(in) :: amps(:)
    integer, intent(in) :: k
    real(dp), intent(in) :: t
    if (k <= 0) then
      a = 1.0_dp
    else
      a = amp_value(amps(k), t)
    end if
  end function amp_factor
end module ictus_solver_amplitude
