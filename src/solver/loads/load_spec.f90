!> The loads and the prescribed motion of a model as the deck gives them, in global numbering
!! (doc/user-guide.md §5: *AMPLITUDE, *CLOAD, *DLOAD, *BOUNDARY with AMPLITUDE= or
!! TYPE=VELOCITY). `ictus_app_build_loads` fills it from the deck; the stepper turns it into
!! the rank's `loads_t` (ictus_solver_loads).
module ictus_solver_load_spec
  use ictus_core_kinds, only: dp
  use ictus_contact_surface, only: contact_surface_t
  use ictus_solver_amplitude, only: amplitude_t
  implicit none
  private
  public :: load_spec_t, nodal_load_t, pressure_load_t, load_spec_active, &
      MOTION_DISPLACEMENT, MOTION_VELOCITY

  !> Kinds of prescribed motion (*BOUNDARY, TYPE=).
  integer, parameter :: MOTION_DISPLACEMENT = 1, MOTION_VELOCITY = 2

  !> A constant nodal force vector times an amplitude: the forces `value` on dof `dof` of the
  !! nodes `nodes` (*CLOAD), or the body force rho g of the elements `elems` (*DLOAD, GRAV;
  !! g(3) is g times the normalised direction; g(3) = 0 in 2D).
  type :: nodal_load_t
    integer :: amp = 0
    integer :: dof = 0
    real(dp) :: value = 0.0_dp
    integer, allocatable :: nodes(:)
    integer, allocatable :: elems(:)
    real(dp) :: g(3) = 0.0_dp
  end type nodal_load_t

  !> A pressure p times an amplitude on a surface (*DLOAD, P); positive pushes into the body.
  !! 2D: the surface's segments `surf`; 3D: the faces of hexahedra, global nodes
  !! face_conn(:, 1:nface), face_nfn(k) (4, 8 or 9) each.
  type :: pressure_load_t
    type(contact_surface_t) :: surf
    integer :: nface = 0
    integer, allocatable :: face_conn(:,:), face_nfn(:)
    real(dp) :: p = 0.0_dp
    integer :: amp = 0
  end type pressure_load_t

  !> Everything a model is loaded with. Amplitude index 0 means none (applied in full from
  !! t = 0). Prescribed motion, one entry per dof: node (global), dof, MOTION_* kind,
  !! amplitude and value (the displacement or velocity times the amplitude).
  type :: load_spec_t
    type(amplitude_t), allocatable :: amps(:)
    integer :: nnodal = 0
    type(nodal_load_t), allocatable :: nodal(:)
    integer :: npress = 0
    type(pressure_load_t), allocatable :: press(:)
    integer :: nmotion = 0
    integer, allocatable :: m_node(:), m_dof(:), m_kind(:), m_amp(:)
    real(dp), allocatable :: m_value(:)
  end type load_spec_t

contains

  !> Whether the model has any load or prescribed motion (then every step takes the plain
  !! path: force, loads, mass solve).
  pure logical function load_spec_active(ls)
    type(load_spec_t), intent(in) :: ls
    load_spec_active = ls%nnodal > 0 .or. ls%npress > 0 .or. ls%nmotion > 0
  end function load_spec_active
end module ictus_solver_load_spec
