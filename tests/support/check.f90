!> Minimal test harness for plain-Fortran unit tests run by CTest (no pFUnit here).
!!
!! Each test program calls `start`, then any number of checks, then `finish`, which prints
!! "<name>: PASSED (n checks)" or "<name>: FAILED (k of n)" and exits with status 1 on failure.
module ictus_test_check
  use, intrinsic :: iso_fortran_env, only: output_unit
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: checker_t

  type :: checker_t
    character(len=:), allocatable :: name
    integer :: n_checks = 0
    integer :: n_failed = 0
  contains
    procedure :: start => checker_start
    procedure :: true => checker_true
    procedure :: close => checker_close
    procedure :: close_abs => checker_close_abs
    procedure :: equal_int => checker_equal_int
    procedure :: finish => checker_finish
  end type checker_t

contains

  subroutine checker_start(this, name)
    class(checker_t), intent(inout) :: this
    character(len=*), intent(in) :: name
    this%name = name
    this%n_checks = 0
    this%n_failed = 0
  end subroutine checker_start

  !> Passes when `cond` holds.
  subroutine checker_true(this, cond, label)
    class(checker_t), intent(inout) :: this
    logical, intent(in) :: cond
    character(len=*), intent(in) :: label
    this%n_checks = this%n_checks + 1
    if (.not. cond) then
      this%n_failed = this%n_failed + 1
      write(output_unit, '(a)') '  FAIL '//label
    end if
  end subroutine checker_true

  !> Passes when |got - want| <= rtol*|want| (or <= rtol when want = 0).
  subroutine checker_close(this, got, want, rtol, label)
    class(checker_t), intent(inout) :: this
    real(dp), intent(in) :: got, want, rtol
    character(len=*), intent(in) :: label
    real(dp) :: scale
    scale = abs(want)
    if (scale == 0.0_dp) scale = 1.0_dp
    this%n_checks = this%n_checks + 1
    if (.not. (abs(got - want) <= rtol*scale)) then
      this%n_failed = this%n_failed + 1
      write(output_unit, '(a,es24.16,a,es24.16,a,es10.3,a,es10.3)') '  FAIL '//label//': got ', &
          got, ' want ', want, ' rel.err ', abs(got - want)/scale, ' tol ', rtol
    end if
  end subroutine checker_close

  !> Passes when |got - want| <= atol.
  subroutine checker_close_abs(this, got, want, atol, label)
    class(checker_t), intent(inout) :: this
    real(dp), intent(in) :: got, want, atol
    character(len=*), intent(in) :: label
    this%n_checks = this%n_checks + 1
    if (.not. (abs(got - want) <= atol)) then
      this%n_failed = this%n_failed + 1
      write(output_unit, '(a,es24.16,a,es24.16,a,es10.3,a,es10.3)') '  FAIL '//label//': got ', &
          got, ' want ', want, ' abs.err ', abs(got - want), ' tol ', atol
    end if
  end subroutine checker_close_abs

  subroutine checker_equal_int(this, got, want, label)
    class(checker_t), intent(inout) :: this
    integer, intent(in) :: got, want
    character(len=*), intent(in) :: label
    this%n_checks = this%n_checks + 1
    if (got /= want) then
      this%n_failed = this%n_failed + 1
      write(output_unit, '(a,i0,a,i0)') '  FAIL '//label//': got ', got, ' want ', want
    end if
  end subroutine checker_equal_int

  !> Prints the closing line and stops with exit status 1 if any check failed.
  subroutine checker_finish(this)
    class(checker_t), intent(inout) :: this
    if (this%n_failed == 0 .and. this%n_checks > 0) then
      write(output_unit, '(a,i0,a)') this%name//': PASSED (', this%n_checks, ' checks)'
    else
      write(output_unit, '(a,i0,a,i0,a)') this%name//': FAILED (', this%n_failed, ' of ', &
          this%n_checks, ')'
      flush(output_unit)
      stop 1
    end if
  end subroutine checker_finish
end module ictus_test_check
