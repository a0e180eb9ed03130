!> Error reporting: input errors are collected and counted, fatal errors stop the program.
!!
!! Kernels never print or stop; they return error codes. Setup code calls `input_error` for
!! each problem it finds in user input (so the user sees every problem at once) and the driver
!! ends the run with `terminate(1)` when `error_count() > 0`. `fatal` is for run-time failures.
!! The stop hook is a procedure pointer so that the parallel layer can finalise MPI first and
!! tests can intercept it.
module ictus_core_errors
  use, intrinsic :: iso_fortran_env, only: error_unit
  implicit none
  private
  public :: input_error, error_count, reset_errors, fatal, terminate, stop_hook, &
      stop_hook_iface, set_error_prefix, warning, warning_count, max_reported_errors

  abstract interface
    !> Ends the program with the given exit status (never returns).
    subroutine stop_hook_iface(code)
      integer, intent(in) :: code
    end subroutine stop_hook_iface
  end interface

  !> Called by `terminate`; the parallel layer replaces it with one that finalises MPI.
  procedure(stop_hook_iface), pointer :: stop_hook => default_stop

  !> Number of input errors reported so far.
  integer :: n_errors = 0
  !> Number of warnings issued so far.
  integer :: n_warnings = 0
  !> Whether this process prints (only rank 0 does).
  logical :: printing = .true.
  !> After this many messages further input errors are only counted.
  integer, parameter :: max_reported_errors = 50

contains

  !> Selects whether this process prints messages (false on ranks other than 0).
  subroutine set_error_prefix(is_printing)
    logical, intent(in) :: is_printing
    printing = is_printing
  end subroutine set_error_prefix

  !> Reports one problem in the user's input. `where` is "file:line" or an object name.
  subroutine input_error(where, msg)
    character(len=*), intent(in) :: where, msg
    n_errors = n_errors + 1
    if (.not. printing) return
    if (n_errors <= max_reported_errors) then
      if (len_trim(where) > 0) then
        write(error_unit, '(a)') 'error: '//trim(where)//': '//trim(msg)
      else
        write(error_unit, '(a)') 'error: '//trim(msg)
      end if
    else if (n_errors == max_reported_errors + 1) then
      write(error_unit, '(a)') 'error: too many errors; further errors are counted only'
    end if
    flush(error_unit)
  end subroutine input_error

  !> Prints a warning (always shown, whatever the log level).
  subroutine warning(where, msg)
    character(len=*), intent(in) :: where, msg
    n_warnings = n_warnings + 1
    if (.not. printing) return
    if (len_trim(where) > 0) then
      write(error_unit, '(a)') 'warning: '//trim(where)//': '//trim(msg)
    else
      write(error_unit, '(a)') 'warning: '//trim(msg)
    end if
    flush(error_unit)
  end subroutine warning

  !> Number of input errors reported since the start (or the last reset).
  integer function error_count()
    error_count = n_errors
  end function error_count

  !> Number of warnings issued.
  integer function warning_count()
    warning_count = n_warnings
  end function warning_count

  !> Forgets the errors counted so far (tests only).
  subroutine reset_errors()
    n_errors = 0
  end subroutine reset_errors

  !> Reports a run-time failure and ends the program with exit status `code` (default 2).
  subroutine fatal(where, msg, code)
    character(len=*), intent(in) :: where, msg
    integer, intent(in), optional :: code
    integer :: c
    c = 2
    if (present(code)) c = code
    if (printing) then
      if (len_trim(where) > 0) then
        write(error_unit, '(a)') 'error: '//trim(where)//': '//trim(msg)
      else
        write(error_unit, '(a)') 'error: '//trim(msg)
      end if
      flush(error_unit)
    end if
    call terminate(c)
  end subroutine fatal

  !> Ends the program with exit status `code` through the stop hook (no backtrace).
  subroutine terminate(code)
    integer, intent(in) :: code
    call stop_hook(code)
  end subroutine terminate

  subroutine default_stop(code)
    integer, intent(in) :: code
    stop code, quiet=.true.
  end subroutine default_stop

end module ictus_core_errors
