!> Names of the sides of a patch: the four sides of a two-parameter patch, the six faces of a
!! three-parameter (trivariate) one, and all of them together.
module ictus_geometry_sides
  implicit none
  private
  public :: SIDE_NONE, SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ALL, SIDE_ZETA0, &
      SIDE_ZETA1, side_name

  !> XI0/XI1: direction-1 parameter at its first/last knot; ETA0/ETA1 the same for direction 2,
  !! ZETA0/ZETA1 for direction 3 (trivariate patches only).
  integer, parameter :: SIDE_NONE = 0, SIDE_XI0 = 1, SIDE_XI1 = 2, SIDE_ETA0 = 3, &
      SIDE_ETA1 = 4, SIDE_ALL = 5, SIDE_ZETA0 = 6, SIDE_ZETA1 = 7

contains

  !> Deck name of a patch side.
  pure function side_name(side) result(name)
    integer, intent(in) :: side
    character(len=:), allocatable :: name
    select case (side)
    case (SIDE_XI0)
      name = 'XI0'
    case (SIDE_XI1)
      name = 'XI1'
    case (SIDE_ETA0)
      name = 'ETA0'
    case (SIDE_ETA1)
      name = 'ETA1'
    case (SIDE_ZETA0)
      name = 'ZETA0'
    case (SIDE_ZETA1)
      name = 'ZETA1'
    case (SIDE_ALL)
      name = 'ALL'
    case default
      name = ''
    end select
  end function side_name
end module ictus_geometry_sides
