!> Ascending in-place insertion sort of short lists (error lists, timing sets, eigenvalues).
!! For the keyed column sort of the sparse graphs see ictus_solver_sparse.
module ictus_core_sort
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: sort

  !> call sort(v): v(:) integer or real(dp), ascending, stable.
  interface sort
    module procedure sort_int, sort_real
  end interface sort

contains

  pure subroutine sort_int(v)
    integer, intent(inout) :: v(:)
    integer :: i, j, x
    do i = 2, size(v)
      x = v(i)
      j = i - 1
      do while (j >= 1)
        if (v(j) <= x) exit
        v(j + 1) = v(j)
        j = j - 1
      end do
      v(j + 1) = x
    end do
  end subroutine sort_int

  pure subroutine sort_real(v)
    real(dp), intent(inout) :: v(:)
    real(dp) :: x
    integer :: i, j
    do i = 2, size(v)
      x = v(i)
      j = i - 1
      do while (j >= 1)
        if (v(j) <= x) exit
        v(j + 1) = v(j)
        j = j - 1
      end do
      v(j + 1) = x
    end do
  end subroutine sort_real
end module ictus_core_sort
