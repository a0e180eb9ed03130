!> Core helpers: strings, error counting and the swappable stop hook.
program test_core
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: upper, lower, str, join_ids
  use ictus_core_errors, only: input_error, error_count, reset_errors, stop_hook, terminate, &
      set_error_prefix
  use ictus_core_sort, only: sort
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  integer :: stop_code = -1
  integer :: iv(6)
  real(dp) :: rv(5)
  call t%start("core")
  call t%true(upper('Contact Pair') == 'CONTACT PAIR', "upper")
  call t%true(lower('*NSET') == '*nset', "lower")
  call t%true(str(42) == '42', "str(integer)")
  call t%true(str(0.5_dp) == '0.5', "str(0.5)")
  call t%true(str(2.5e-4_dp, 3) == '2.50E-004', "str(2.5e-4, 3 digits): "//str(2.5e-4_dp, 3))
  call t%true(str(1234.5_dp) == '1234.5', "str(1234.5)")
  call t%true(join_ids([1, 2, 3, 4], 2) == '1, 2 and 2 more', "join_ids")
  iv = [5, -2, 9, 5, 0, -7]
  call sort(iv)
  call t%true(all(iv == [-7, -2, 0, 5, 5, 9]), "sort integers (with a repeat)")
  rv = [2.5_dp, -1.0_dp, 1.0e-300_dp, -3.0e10_dp, 0.0_dp]
  call sort(rv)
  call t%true(all(rv == [-3.0e10_dp, -1.0_dp, 0.0_dp, 1.0e-300_dp, 2.5_dp]), "sort reals")
  ! errors are counted; printing can be switched off (ranks other than 0)
  call set_error_prefix(.false.)
  call reset_errors()
  call input_error('deck.inp:3', 'first')
  call input_error('deck.inp:4', 'second')
  call t%equal_int(error_count(), 2, "input errors are counted")
  ! the stop hook can be swapped, so error paths are testable
  stop_hook => record_stop
  call terminate(1)
  call t%equal_int(stop_code, 1, "terminate calls the stop hook with the exit status")
  call t%finish()
contains
  subroutine record_stop(code)
    integer, intent(in) :: code
    stop_code = code
  end subroutine record_stop
end program test_core
