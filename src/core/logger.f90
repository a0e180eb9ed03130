!> Rank-0 logger with levels. Warnings and errors go through `ictus_core_errors`.
module ictus_core_logger
  use, intrinsic :: iso_fortran_env, only: output_unit
  implicit none
  private
  public :: log_info, log_verbose, log_debug, log_set_level, log_set_root, log_level, &
      LOG_QUIET, LOG_INFO_LEVEL, LOG_VERBOSE_LEVEL, LOG_DEBUG_LEVEL, log_is

  integer, parameter :: LOG_QUIET = 0, LOG_INFO_LEVEL = 1, LOG_VERBOSE_LEVEL = 2, &
      LOG_DEBUG_LEVEL = 3
  !> Current level; messages above it are suppressed.
  integer :: level = LOG_INFO_LEVEL
  !> True on the process that prints (rank 0).
  logical :: is_root = .true.

contains

  !> Sets the level (LOG_QUIET ... LOG_DEBUG_LEVEL).
  subroutine log_set_level(new_level)
    integer, intent(in) :: new_level
    level = new_level
  end subroutine log_set_level

  !> Marks whether this process prints.
  subroutine log_set_root(root)
    logical, intent(in) :: root
    is_root = root
  end subroutine log_set_root

  !> The current level.
  integer function log_level()
    log_level = level
  end function log_level

  !> True when messages of `lev` are printed on this process.
  logical function log_is(lev)
    integer, intent(in) :: lev
    log_is = is_root .and. level >= lev
  end function log_is

  subroutine log_info(msg)
    character(len=*), intent(in) :: msg
    call emit(LOG_INFO_LEVEL, msg)
  end subroutine log_info

  subroutine log_verbose(msg)
    character(len=*), intent(in) :: msg
    call emit(LOG_VERBOSE_LEVEL, msg)
  end subroutine log_verbose

  subroutine log_debug(msg)
    character(len=*), intent(in) :: msg
    call emit(LOG_DEBUG_LEVEL, msg)
  end subroutine log_debug

  subroutine emit(lev, msg)
    integer, intent(in) :: lev
    character(len=*), intent(in) :: msg
    if (.not. is_root .or. level < lev) return
    write(output_unit, '(a)') trim(msg)
    flush(output_unit)
  end subroutine emit
end module ictus_core_logger
