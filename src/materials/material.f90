!> A material of the model: its name, density and law, and the dispatcher that makes a law
!! from the deck's name for it.
!!
!! Adding a law: a new file in this folder with a type that extends `law_t`
!! (ictus_materials_law), and one line in `material_make_law`; doc/architecture.md
!! "Adding a material law" walks through it.
module ictus_materials_material
  use ictus_core_kinds, only: dp, str_len
  use ictus_materials_law, only: law_t, kinematics_t
  use ictus_materials_linear_elastic, only: linear_elastic_t
  use ictus_materials_neo_hooke, only: neo_hooke_t
  use ictus_materials_j2_plastic, only: j2_plastic
  implicit none
  private
  public :: material_t, material_make_law

  type :: material_t
    character(len=str_len) :: name = ''
    real(dp) :: density = 0.0_dp
    class(law_t), allocatable :: law
  end type material_t

contains

  !> Allocates the law `name` with its properties `props` (in the order of the deck cards) for
  !! the kinematics `kin` and initialises it; `law` stays unallocated for an unknown name.
  subroutine material_make_law(name, props, kin, law)
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: props(:)
    type(kinematics_t), intent(in) :: kin
    class(law_t), allocatable, intent(out) :: law
    select case (name)
    case ('LINEAR ELASTIC')
      law = linear_elastic_t(e=props(1), nu=props(2))
    case ('NEO HOOKE')
      law = neo_hooke_t(c10=props(1), d1=props(2))
    case ('J2')
      ! E, nu, then the pairs (sigma_y, epbar) of the hardening table
      law = j2_plastic(props(1), props(2), props(3:))
    end select
    if (.not. allocated(law)) return
    law%kin = kin
    call law%init()
  end subroutine material_make_law
end module ictus_materials_material
