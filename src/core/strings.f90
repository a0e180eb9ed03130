!> Small string helpers: case conversion and number formatting for messages.
module ictus_core_strings
  use ictus_core_kinds, only: dp, i8
  implicit none
  private
  public :: upper, lower, str, join_ids, command_arg, str_list

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

  !> Real number with `digits` significant digits (default 7): fixed notation for magnitudes
  !! in [0.01, 1e5), scientific otherwise.
  pure function str_real(x, digits) result(r)
    real(dp), intent(in) :: x
    integer, intent(in), optional :: digits
    character(len=:), allocatable :: r
    character(len=40) :: buf
    character(len=24) :: fmt
    integer :: d, k
    d = 7
    if (present(digits)) d = max(1, digits)
    if (x == 0.0_dp) then
      r = '0'
      return
    end if
    if (abs(x) >= 0.01_dp .and. abs(x) < 1.0e5_dp) then
      k = max(1, d - 1 - floor(log10(abs(x))))
      write(fmt, '(a,i0,a,i0,a)') '(f', d + k + 4, '.', k, ')'
      write(buf, fmt) x
      r = trim(adjustl(buf))
      ! drop trailing zeros of the fraction (keep one digit after the point)
      k = len(r)
      do while (k > 2)
        if (r(k:k) /= '0' .or. r(k - 1:k - 1) == '.') exit
        k = k - 1
      end do
      r = r(1:k)
    else
      write(fmt, '(a,i0,a,i0,a)') '(es', d + 8, '.', d - 1, 'e3)'
      write(buf, fmt) x
      r = trim(adjustl(buf))
    end if
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

  !> Integers as a parameter value of a deck card, comma separated without blanks: "2,2,3".
  pure function str_list(v) result(r)
    integer, intent(in) :: v(:)
    character(len=:), allocatable :: r
    integer :: i
    r = ''
    do i = 1, size(v)
      if (i > 1) r = r//','
      r = r//str_int(v(i))
    end do
  end function str_list

  !> Command-line argument k, whatever its length.
  function command_arg(k) result(a)
    integer, intent(in) :: k
    character(len=:), allocatable :: a
    integer :: length
    call get_command_argument(k, length=length)
    allocate(character(len=length) :: a)
    call get_command_argument(k, a)
  end function command_arg
end module ictus_core_strings
