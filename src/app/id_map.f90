!> A map from user ids (node or element numbers, any order, gaps allowed) to positions 1..n,
!! by a sorted copy and bisection.
module ictus_app_id_map
  implicit none
  private
  public :: id_map_t, id_map_init, id_map_find, merge_sort

  type :: id_map_t
    integer, allocatable :: keys(:)
    integer, allocatable :: pos(:)
  end type id_map_t

contains

  !> Builds the map of ids(1..n) -> 1..n. Duplicates keep the first position.
  subroutine id_map_init(map, ids)
    type(id_map_t), intent(out) :: map
    integer, intent(in) :: ids(:)
    integer :: i
    map%keys = ids
    map%pos = [(i, i = 1, size(ids))]
    call merge_sort(map%keys, map%pos)
  end subroutine id_map_init

  !> Position of `id`, or 0 if it is not in the map.
  pure integer function id_map_find(map, id) result(p)
    type(id_map_t), intent(in) :: map
    integer, intent(in) :: id
    integer :: lo, hi, mid
    p = 0
    lo = 1
    hi = size(map%keys)
    do while (lo <= hi)
      mid = (lo + hi)/2
      if (map%keys(mid) < id) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
    if (lo <= size(map%keys)) then
      if (map%keys(lo) == id) p = map%pos(lo)
    end if
  end function id_map_find

  !> Stable merge sort of keys, carrying pos along.
  subroutine merge_sort(keys, pos)
    integer, intent(inout) :: keys(:), pos(:)
    integer, allocatable :: k2(:), p2(:)
    integer :: n, width, lo, mid, hi, i, j, m
    n = size(keys)
    allocate(k2(n), p2(n))
    width = 1
    do while (width < n)
      lo = 1
      do while (lo <= n)
        mid = min(lo + width, n + 1)
        hi = min(lo + 2*width, n + 1)
        i = lo
        j = mid
        m = lo
        do while (m < hi)
          if (i < mid .and. (j >= hi .or. keys(min(i, n)) <= keys(min(j, n)))) then
            k2(m) = keys(i)
            p2(m) = pos(i)
            i = i + 1
          else
            k2(m) = keys(j)
            p2(m) = pos(j)
            j = j + 1
          end if
          m = m + 1
        end do
        lo = hi
      end do
      keys = k2
      pos = p2
      width = 2*width
    end do
  end subroutine merge_sort
end module ictus_app_id_map
