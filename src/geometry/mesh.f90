!> The mesh: reference coordinates of the nodes and control points, and the elements over
!! them. It knows its dimension; everything else about a run (materials, mass, conditions,
!! step) is the model's (ictus_solver_model, whose model_t extends mesh_t).
module ictus_geometry_mesh
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: mesh_t

  type :: mesh_t
    !> Spatial dimension (2; 3 when 3D elements come).
    integer :: ndm = 2
    !> Number of nodes (FE nodes first, then the control points of each patch in turn).
    integer :: nn = 0
    !> Reference coordinates (ndm, nn).
    real(dp), allocatable :: x0(:,:)
    !> NURBS weights (nn); 1 for finite-element nodes.
    real(dp), allocatable :: weight(:)
    !> Id of each node as the user sees it (FE node id, or control-point number), (nn).
    integer, allocatable :: node_id(:)

    !> Number of elements, largest nodes per element.
    integer :: nel = 0
    integer :: nen_max = 0
    !> Element type (ETYPE_* of ictus_elements_types), nodes per element, connectivity
    !! (nen_max, nel) in global node indices (1..nn), material index, quadrature rule per
    !! element (Gauss points per direction, (ndm, nel)).
    integer, allocatable :: etype(:)
    integer, allocatable :: nen(:)
    integer, allocatable :: conn(:,:)
    integer, allocatable :: mat(:)
    integer, allocatable :: gauss(:,:)
    !> User element id (FE) or the element's number within its patch (NURBS).
    integer, allocatable :: elem_id(:)
    !> Patch index (0 for FE elements) and element index within that patch.
    integer, allocatable :: patch(:)
    integer, allocatable :: patch_elem(:)
  end type mesh_t
end module ictus_geometry_mesh
