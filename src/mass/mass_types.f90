!> Mass-matrix kinds shared by the lumping routines, the model and the deck reader.
module ictus_mass_types
  implicit none
  private
  public :: MASS_CONSISTENT, MASS_ROW_SUM, MASS_HRZ, MASS_ALPHA, mass_name, HRZ_FULL, HRZ_GAUSS2

  integer, parameter :: MASS_CONSISTENT = 1, MASS_ROW_SUM = 2, MASS_HRZ = 3, MASS_ALPHA = 4
  !> How the HRZ diagonal is integrated: the element's full rule (default) or 2x2 Gauss.
  integer, parameter :: HRZ_FULL = 1, HRZ_GAUSS2 = 2

contains

  !> Deck name of a mass type.
  pure function mass_name(kind) result(name)
    integer, intent(in) :: kind
    character(len=:), allocatable :: name
    select case (kind)
    case (MASS_CONSISTENT)
      name = 'CONSISTENT'
    case (MASS_ROW_SUM)
      name = 'ROW SUM'
    case (MASS_HRZ)
      name = 'HRZ'
    case (MASS_ALPHA)
      name = 'ALPHA'
    case default
      name = '?'
    end select
  end function mass_name
end module ictus_mass_types
