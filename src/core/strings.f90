!> Small string helpers: case conversion and number formatting for messages.
module ictus_core_strings
  use ictus_core_kinds, only: dp, i8
  implicit none
  private
  public :: upper, lower, str, join_ids

  !> Converts a number to its shortest readable text.
  interface str
    module procedure str_int, str_i8, str_real
  end interface str

contains

  !> Upper-case copy of `s` (ASCII).
  pure function upper(s) result(r)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: r
    integer :: i, c
    r = s
    do i = 1, len(s)
      c = iachar(s(i:i))
      if (c >= iachar('a') .and. c <= iachar('z')) r(i:i) = achar(c - 32)
    end do
  end function upper

  !> Lower-case copy of `s` (ASCII).
  pure function lower(s) result(r)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: r
    integer :: i, c
    r = s
    do i = 1, len(s)
      c = iachar(s(i:i))
      if (c >= iachar('A') .and. c <= iachar('Z')) r(i:i) = achar(c + 32)
    end do
  end function lower

  pure function str_int(i) result(r)
    integer, intent(in) :: i
    character(len=:), allocatable :: r
    character(len=24) :: buf
    write(buf, '(i0)') i
    r = trim(buf)
  end function str_int

  pure function str_i8(i) result(r)
    integer(i8), intent(in) :: i
    character(len=:), allocatable :: r
    character(len=24) :: buf
    write(buf, '(i0)') i
    r = trim(buf)
  end function str_i8

  !> Real number in a compact general format (7 significant digits unless `digits` given).
  pure function str_real(x, digits) result(r)
    real(dp), intent(in) :: x
    integer, intent(in), optional :: digits
    character(len=:), allocatable :: r
    character(len=40) :: buf
    character(len=20) :: fmt
    integer :: d
    d = 7
    if (present(digits)) d = digits
    write(fmt, '(a,i0,a,i0,a)') '(g', d + 8, '.', d, ')'
    write(buf, fmt) x
    r = trim(adjustl(buf))
  end function str_real

  !> "1, 5, 7 and 3 more" style list of ids for messages.
  pure function join_ids(ids, max_shown) result(r)
    integer, intent(in) :: ids(:)
    integer, intent(in) :: max_shown
    character(len=:), allocatable :: r
    integer :: i
    r = ''
    do i = 1, min(size(ids), max_shown)
      if (i > 1) r = r//', '
      r = r//str_int(ids(i))
    end do
    if (size(ids) > max_shown) r = r//' and '//str_int(size(ids) - max_shown)//' more'
  end function join_ids
end module ictus_core_strings
