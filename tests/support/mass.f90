!> Mass routines that only the tests use.
module ictus_test_mass
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: check_positive

contains

  !> Indices of the non-positive (or NaN) entries of a lumped mass vector.
  !! n: length; ml(n): masses; bad(n): the first nbad entries are the offending indices, the
  !! rest 0; nbad: how many.
  pure subroutine check_positive(n, ml, bad, nbad)
    integer, intent(in) :: n
    real(dp), intent(in) :: ml(n)
    integer, intent(out) :: bad(n)
    integer, intent(out) :: nbad
    integer :: i
    bad = 0
    nbad = 0
    do i = 1, n
      if (.not. ml(i) > 0.0_dp) then
        nbad = nbad + 1
        bad(nbad) = i
      end if
    end do
  end subroutine check_positive
end module ictus_test_mass
