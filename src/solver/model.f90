!> The model as the solver sees it: the mesh (nodes and control points in one global
!! numbering, one element list for finite elements and NURBS spans; ictus_geometry_mesh), and
!! the run's settings on it: materials, mass and damping choices, boundary and initial
!! conditions, and the step parameters.
!!
!! It is built from a deck by `ictus_app_build_model` (or directly by tests), so physics code
!! never sees the parser.
module ictus_solver_model
  use ictus_core_kinds, only: dp, str_len
  use ictus_geometry_patch, only: patch_t
  use ictus_geometry_volume, only: volume_t
  use ictus_geometry_mesh, only: mesh_t
  use ictus_materials_material, only: material_t
  use ictus_materials_law, only: ANALYSIS_PLANE_STRAIN, kinematics_t
  use ictus_solver_load_spec, only: load_spec_t
  implicit none
  private
  public :: model_t, model_free, model_kinematics, patch_node, patch_nodes, model_force_kind, &
      element_cp_weight, patch_ncp, patch_name, patch_pmax
  public :: FORCE_AUTO, FORCE_ASSEMBLED, FORCE_ELEMENT, MASS_SOLVER_CG, &
      MASS_SOLVER_CHOLESKY, MASS_SOLVER_CORRECTOR, &
      MASS_SOLVER_KRONECKER, MASS_SOLVER_AUTO, output_set_t, VAR_U, VAR_V, VAR_A, VAR_S, &
      VAR_E, VAR_MISES, VAR_PEEQ, VAR_RF, NVAR, VAR_NAMES

  !> Solvers of a consistent mass (*DYNAMIC, EXPLICIT, MASS SOLVER=): a conjugate gradient to
  !! a tolerance, the Cholesky factor (exact), a fixed number of row-sum-preconditioned
  !! corrector passes (an approximate inverse; doc/theory.md §5), 1D factors along the
  !! directions of tensor-product lattices (exact; doc/theory.md §5.2), or AUTO: KRONECKER
  !! where it applies, else CHOLESKY.
  integer, parameter :: MASS_SOLVER_CG = 1, MASS_SOLVER_CHOLESKY = 2, MASS_SOLVER_CORRECTOR = 3, &
      MASS_SOLVER_KRONECKER = 4, MASS_SOLVER_AUTO = 5

  !> How the internal force is formed (*DYNAMIC, EXPLICIT, INTERNAL FORCE=): AUTO (the
  !! assembled K where every law has a constant tangent), ASSEMBLED, or ELEMENT (a loop over
  !! the material laws); ictus_solver_internal_force.
  integer, parameter :: FORCE_AUTO = 0, FORCE_ASSEMBLED = 1, FORCE_ELEMENT = 2

  !> Output variables (*OUTPUT, VARIABLES=; doc/user-guide.md §6): displacement, velocity,
  !! acceleration, Cauchy stress, strain, von Mises stress, equivalent plastic strain and
  !! reaction force, in this order (the order of the processed deck).
  integer, parameter :: VAR_U = 1, VAR_V = 2, VAR_A = 3, VAR_S = 4, VAR_E = 5, VAR_MISES = 6, &
      VAR_PEEQ = 7, VAR_RF = 8, NVAR = 8
  character(len=*), parameter :: VAR_NAMES(NVAR) = [character(len=5) :: 'U', 'V', 'A', 'S', &
      'E', 'MISES', 'PEEQ', 'RF']

  !> A node set with its own history (*OUTPUT, HISTORY, NSET=): its name (lower case, the
  !! group under /history/nset), its nodes (global indices, increasing) and the variables
  !! recorded (VAR_U: mean displacement, VAR_V: mean velocity, VAR_RF: summed reaction).
  type :: output_set_t
    character(len=str_len) :: name = ''
    integer, allocatable :: nodes(:)
    logical :: vars(NVAR) = .false.
  end type output_set_t

  !> The mesh (its parent component `mesh_t`: coordinates, elements, dimension) and the
  !! settings of the run on it.
  type, extends(mesh_t) :: model_t
    character(len=:), allocatable :: title
    !> The kinematic idealisation (ANALYSIS_PLANE_STRAIN or ANALYSIS_PLANE_STRESS), and
    !! finite strain (*STEP, NLGEOM=YES).
    integer :: analysis = ANALYSIS_PLANE_STRAIN
    logical :: nlgeom = .false.
    real(dp) :: thickness = 1.0_dp

    !> Materials: name, density and law each (ictus_materials_material).
    integer :: nmat = 0
    type(material_t), allocatable :: materials(:)

    !> Mass per element: MASS_* kind, alpha (TYPE=ALPHA), HRZ rule (HRZ_*).
    integer, allocatable :: mass_kind(:)
    real(dp), allocatable :: mass_alpha(:)
    integer, allocatable :: hrz_rule(:)
    !> Elements that share their mean dilatation (B-bar / F-bar, doc/theory.md §2.1).
    logical, allocatable :: mean_dil(:)
    !> Mass-proportional damping coefficient per element.
    real(dp), allocatable :: damping(:)

    !> Dirichlet conditions: fixed dofs (2, nn) and their prescribed values.
    logical, allocatable :: fixed(:,:)
    real(dp), allocatable :: u_fixed(:,:)
    !> Initial velocity (2, nn).
    real(dp), allocatable :: v0(:,:)
    !> Loads and prescribed motion (*AMPLITUDE, *CLOAD, *DLOAD, *BOUNDARY with AMPLITUDE= or
    !! TYPE=VELOCITY; their dofs are also `fixed`, with u_fixed = u_p(0)).
    type(load_spec_t) :: loads

    !> NURBS patches as refined, and the index of each patch's first control point minus one
    !! in the list of all control points before merging (FE nodes first). Control point k of
    !! patch p is node cp_node(patch_offset(p) + k); without merged patches cp_node is not
    !! allocated and the node is patch_offset(p) + k (patch_node).
    !! In 3D the patches are trivariate: volumes(1:npatch) hold them and patches has size 0
    !! (patch_ncp, patch_name and patch_pmax answer for either kind).
    integer :: npatch = 0
    type(patch_t), allocatable :: patches(:)
    type(volume_t), allocatable :: volumes(:)
    integer, allocatable :: patch_offset(:)
    integer, allocatable :: cp_node(:)
    !> Control points merged into another one (*PATCH, MERGE=YES; doc/iga.md §1.1).
    integer :: nmerged = 0

    !> Step: time step (0 = automatic), end time, safety factor for automatic steps,
    !! history and field output intervals (in steps).
    real(dp) :: dt = 0.0_dp
    real(dp) :: t_end = 0.0_dp
    real(dp) :: safety = 0.9_dp
    !> Internal force (FORCE_*).
    integer :: force_kind = FORCE_AUTO
    !> The run warns once when |E_total - E_0| exceeds energy_warning times the largest energy.
    real(dp) :: energy_warning = 0.01_dp
    !> Consistent mass: its solver (MASS_SOLVER_*), the relative residual of the conjugate
    !! gradient and the number of passes of the corrector.
    integer :: mass_solver = MASS_SOLVER_AUTO
    real(dp) :: mass_tol = 1.0e-12_dp
    integer :: mass_passes = 2
    !> Undamped lumped-mass steps without output per sweep over K (ictus_solver_sweep);
    !! 0 = AUTO: SWEEP_AUTO_STEPS, timed against single steps at the start of the run.
    integer :: sweep_steps = 0
    !> History records every history_every steps, or with history_interval > 0 at the steps
    !! closest to its multiples (TIME INTERVAL=); the same for field snapshots (field_every
    !! = 0: about 20 snapshots).
    integer :: history_every = 1
    real(dp) :: history_interval = 0.0_dp
    integer :: field_every = 0
    real(dp) :: field_interval = 0.0_dp
    !> The variables of the field snapshots (VAR_*); by default U, V, S and MISES (and PEEQ
    !! where a law has plastic history, set by the model builder).
    logical :: field_vars(NVAR) = [.true., .true., .false., .true., .false., .true., .false., &
        .false.]
    !> Node sets with a history of their own.
    integer :: nout_sets = 0
    type(output_set_t), allocatable :: out_sets(:)
    !> Viewing samples per direction of each NURBS element (*OUTPUT, FIELD, SAMPLES=);
    !! 0 = 2 p_max + 1 of its patch.
    integer :: viz_samples = 0
    !> Checkpoint every n steps (0: only when stopped at a wall-time limit).
    integer :: restart_every = 0
  end type model_t

contains

  !> The internal force that the deck and the laws give model m: the deck's INTERNAL FORCE=
  !! where it names one, else (AUTO) FORCE_ASSEMBLED where every law is linear, the strain
  !! small and no element shares its mean dilatation, FORCE_ELEMENT otherwise. In 3D AUTO
  !! also weighs the memory of the assembled K (`assemble_operators`, `force_choice`).
  integer function model_force_kind(m) result(kind)
    type(model_t), intent(in) :: m
    integer :: k
    kind = m%force_kind
    if (kind /= FORCE_AUTO) return
    kind = FORCE_ASSEMBLED
    if (m%nlgeom) kind = FORCE_ELEMENT
    if (allocated(m%mean_dil)) then
      if (any(m%mean_dil)) kind = FORCE_ELEMENT
    end if
    do k = 1, m%nmat
      if (.not. m%materials(k)%law%linear) kind = FORCE_ELEMENT
    end do
  end function model_force_kind

  !> How the material laws of model m are evaluated.
  pure function model_kinematics(m) result(k)
    type(model_t), intent(in) :: m
    type(kinematics_t) :: k
    k%analysis = m%analysis
    k%nlgeom = m%nlgeom
  end function model_kinematics

  !> Global node of control point k of patch ip.
  pure integer function patch_node(m, ip, k)
    type(model_t), intent(in) :: m
    integer, intent(in) :: ip, k
    patch_node = m%patch_offset(ip) + k
    if (allocated(m%cp_node)) patch_node = m%cp_node(patch_node)
  end function patch_node

  !> Weight of the local control point a of element e: its patch's (merged coincident control
  !! points of a degenerate trivariate patch share a node but not always a weight), 1 for a
  !! finite element.
  pure real(dp) function element_cp_weight(m, e, a) result(w)
    type(model_t), intent(in) :: m
    integer, intent(in) :: e, a
    integer :: ip
    w = 1.0_dp
    ip = m%patch(e)
    if (ip == 0) return
    if (m%ndm == 3) then
      w = m%volumes(ip)%cp(4, m%volumes(ip)%ien(a, m%patch_elem(e)))
    else
      w = m%patches(ip)%cp(3, m%patches(ip)%ien(a, m%patch_elem(e)))
    end if
  end function element_cp_weight

  !> Global nodes of all control points of patch ip (direction 1 fastest).
  pure function patch_nodes(m, ip) result(nodes)
    type(model_t), intent(in) :: m
    integer, intent(in) :: ip
    integer, allocatable :: nodes(:)
    integer :: k
    nodes = [(patch_node(m, ip, k), k = 1, patch_ncp(m, ip))]
  end function patch_nodes

  !> Number of control points of patch ip (bivariate in 2D, trivariate in 3D).
  pure integer function patch_ncp(m, ip)
    type(model_t), intent(in) :: m
    integer, intent(in) :: ip
    if (m%ndm == 3) then
      patch_ncp = product(m%volumes(ip)%n)
    else
      patch_ncp = product(m%patches(ip)%n)
    end if
  end function patch_ncp

  !> Name of patch ip.
  pure function patch_name(m, ip) result(name)
    type(model_t), intent(in) :: m
    integer, intent(in) :: ip
    character(len=:), allocatable :: name
    if (m%ndm == 3) then
      name = trim(m%volumes(ip)%name)
    else
      name = trim(m%patches(ip)%name)
    end if
  end function patch_name

  !> Largest degree of patch ip over its directions.
  pure integer function patch_pmax(m, ip)
    type(model_t), intent(in) :: m
    integer, intent(in) :: ip
    if (m%ndm == 3) then
      patch_pmax = maxval(m%volumes(ip)%p)
    else
      patch_pmax = maxval(m%patches(ip)%p)
    end if
  end function patch_pmax

  !> Releases everything a model holds.
  subroutine model_free(m)
    type(model_t), intent(inout) :: m
    type(model_t) :: empty
    m = empty
  end subroutine model_free
end module ictus_solver_model
