!> Typed records of an input deck, as read (before any resolution into the model).
!!
!! The deck reader (`ictus_io_deck_reader`) fills a `deck_t`; `ictus_app_build_model` turns it
!! into the model. Every record keeps `where` = "file:line" of the card (or data line) it came
!! from, so that later checks can name the place in the deck.
!! Identifiers (set, material, patch, surface names) are stored in upper case.
module ictus_io_deck_types
  use ictus_core_kinds, only: dp, str_len
  use ictus_geometry_sides, only: SIDE_NONE, SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, &
      SIDE_ALL, SIDE_ZETA0, SIDE_ZETA1, side_name
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9
  use ictus_elements_library, only: etype_name, etype_nen
  use ictus_solver_model, only: NVAR
  use ictus_mass_types, only: MASS_CONSISTENT, MASS_ROW_SUM, MASS_HRZ, MASS_ALPHA, mass_name, &
      HRZ_FULL, HRZ_GAUSS2
  implicit none
  private
  public :: deck_t, material_in_t, element_block_in_t, set_in_t, surface_in_t, &
      boundary_in_t, velocity_in_t, mass_in_t, damping_in_t, patch_in_t, patch_op_in_t, &
      step_in_t, out_set_in_t, section_in_t, contact_pair_in_t, rigid_wall_in_t, where_len, &
      interaction_in_t, &
      amplitude_in_t, cload_in_t, dload_in_t, DLOAD_PRESSURE, DLOAD_GRAV, &
      AMP_DEF_TABULAR, AMP_DEF_SMOOTH_STEP, BC_DISPLACEMENT, BC_VELOCITY, &
      ANALYSIS_PLANE_STRAIN, ANALYSIS_PLANE_STRESS, ANALYSIS_3D, &
      ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, etype_name, etype_nen, &
      SET_NODE, SET_ELEMENT, &
      SIDE_NONE, SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ALL, SIDE_ZETA0, SIDE_ZETA1, &
      side_name, SURF_ELEMENT, SURF_PATCH, &
      MASS_CONSISTENT, MASS_ROW_SUM, MASS_HRZ, MASS_ALPHA, mass_name, &
      HRZ_FULL, HRZ_GAUSS2, &
      OP_ELEVATE, OP_REFINE, &
      CONTACT_TWO_HALF_PASS, CONTACT_NODE_TO_SEGMENT, CONTACT_MORTAR

  !> Length of a "file:line" location string.
  integer, parameter :: where_len = 320

  !> *ANALYSIS, TYPE=: the codes of ictus_materials_law (and of `element_type_named`).
  integer, parameter :: ANALYSIS_PLANE_STRAIN = 1, ANALYSIS_PLANE_STRESS = 2, ANALYSIS_3D = 3
  integer, parameter :: SET_NODE = 1, SET_ELEMENT = 2
  integer, parameter :: SURF_ELEMENT = 1, SURF_PATCH = 2
  integer, parameter :: OP_ELEVATE = 1, OP_REFINE = 2
  integer, parameter :: CONTACT_TWO_HALF_PASS = 1, CONTACT_NODE_TO_SEGMENT = 2, &
      CONTACT_MORTAR = 3
  !> *DLOAD load types, *AMPLITUDE definitions, *BOUNDARY types.
  integer, parameter :: DLOAD_PRESSURE = 1, DLOAD_GRAV = 2
  integer, parameter :: AMP_DEF_TABULAR = 1, AMP_DEF_SMOOTH_STEP = 2
  integer, parameter :: BC_DISPLACEMENT = 1, BC_VELOCITY = 2

  !> *MATERIAL with its *ELASTIC (or *HYPERELASTIC), *PLASTIC and *DENSITY.
  type :: material_in_t
    character(len=str_len) :: name = ''
    real(dp) :: e = 0.0_dp
    real(dp) :: nu = 0.0_dp
    real(dp) :: rho = 0.0_dp
    logical :: has_elastic = .false.
    logical :: has_density = .false.
    !> *HYPERELASTIC, NEO HOOKE: C10, D1.
    logical :: has_hyperelastic = .false.
    real(dp) :: c10 = 0.0_dp
    real(dp) :: d1 = 0.0_dp
    !> *PLASTIC: the hardening table, (sigma_y, epbar) pairs in rows.
    logical :: has_plastic = .false.
    real(dp), allocatable :: plastic(:,:)
    character(len=where_len) :: where = ''
    character(len=where_len) :: law_where = ''
  end type material_in_t

  !> One *ELEMENT card and its data lines.
  type :: element_block_in_t
    integer :: etype = 0
    !> Nodes per element (4, 8 or 9).
    integer :: nen = 0
    character(len=str_len) :: elset = ''
    character(len=str_len) :: material = ''
    !> Gauss points per direction for stiffness and consistent mass (2 or 3; 0 = default:
    !! 2 for Q4, 3 for Q8 and Q9).
    integer :: gauss = 0
    !> DILATATION=: 0 AUTO (not given), 1 FULL, 2 MEAN (doc/theory.md §2.1).
    integer :: dilatation = 0
    !> Element ids, (nel).
    integer, allocatable :: ids(:)
    !> Node ids, (nen, nel), in the order of the deck.
    integer, allocatable :: conn(:,:)
    !> Line of each element's data, (nel); the file is `file`.
    integer, allocatable :: line(:)
    character(len=where_len) :: file = ''
    character(len=where_len) :: where = ''
    !> TYPE= as written (upper case), the analysis its name implies (0: none; CPE*, CPS*) and
    !! the *ELEMENT line that names it.
    character(len=16) :: type_name = ''
    integer :: analysis = 0
    character(len=where_len) :: analysis_where = ''
  end type element_block_in_t

  !> *SOLID SECTION, ELSET=, MATERIAL= [data: thickness].
  type :: section_in_t
    character(len=str_len) :: elset = ''
    character(len=str_len) :: material = ''
    real(dp) :: thickness = 0.0_dp
    character(len=where_len) :: where = ''
  end type section_in_t

  !> *NSET or *ELSET (one card; several cards with one name are merged by the reader).
  type :: set_in_t
    character(len=str_len) :: name = ''
    !> SET_NODE or SET_ELEMENT.
    integer :: kind = 0
    !> Explicit ids (after GENERATE expansion).
    integer, allocatable :: ids(:)
    !> Names of other sets included in this one.
    character(len=str_len), allocatable :: refs(:)
    !> Location of each reference, for messages.
    character(len=where_len), allocatable :: ref_where(:)
    !> For *NSET, PATCH=, SIDE=: the patch and side (SIDE_NONE otherwise).
    character(len=str_len) :: patch = ''
    integer :: side = SIDE_NONE
    character(len=where_len) :: where = ''
    !> A second set of the other kind with the same name (an *NSET and an *ELSET), settled
    !! after the deck is read (ictus_io_deck_interop).
    logical :: twin = .false.
  end type set_in_t

  !> *SURFACE.
  type :: surface_in_t
    character(len=str_len) :: name = ''
    !> SURF_ELEMENT or SURF_PATCH.
    integer :: kind = 0
    !> TYPE=ELEMENT: element id (0 when `elset` is used) and face 1..4 (1..6 in 3D) of each entry.
    integer, allocatable :: elem(:)
    integer, allocatable :: face(:)
    !> TYPE=ELEMENT: element set name of each entry ('' when `elem` is used).
    character(len=str_len), allocatable :: elset(:)
    character(len=where_len), allocatable :: entry_where(:)
    !> PATCH=, SIDE= of the card, or of its first data line.
    character(len=str_len) :: patch = ''
    integer :: side = SIDE_NONE
    !> Patch sides: every PATCH=, SIDE= pair (the card's first, then each data line's; a
    !! multi-patch body's surface lists several), with the "file:line" of each in entry_where.
    character(len=str_len), allocatable :: side_patch(:)
    integer, allocatable :: side_code(:)
    character(len=where_len) :: where = ''
  end type surface_in_t

  !> One data line of *BOUNDARY: prescribed displacement on dofs first..last.
  type :: boundary_in_t
    !> Node set name, or a node id written as text.
    character(len=str_len) :: target = ''
    integer :: first_dof = 0
    integer :: last_dof = 0
    real(dp) :: value = 0.0_dp
    character(len=where_len) :: where = ''
    !> AMPLITUDE= of the card ('' for none), TYPE= (BC_DISPLACEMENT or BC_VELOCITY) and the
    !! "file:line" of the card.
    character(len=str_len) :: amplitude = ''
    integer :: kind = BC_DISPLACEMENT
    character(len=where_len) :: card_where = ''
  end type boundary_in_t

  !> *AMPLITUDE: name, definition (AMP_DEF_*), times and values.
  type :: amplitude_in_t
    character(len=str_len) :: name = ''
    integer :: definition = AMP_DEF_TABULAR
    real(dp), allocatable :: t(:), a(:)
    character(len=where_len) :: where = ''
  end type amplitude_in_t

  !> One data line of *CLOAD: a force `value` on dof `dof` of each node of `target`.
  type :: cload_in_t
    character(len=str_len) :: target = ''
    integer :: dof = 0
    real(dp) :: value = 0.0_dp
    character(len=str_len) :: amplitude = ''
    character(len=where_len) :: where = ''
    character(len=where_len) :: card_where = ''
  end type cload_in_t

  !> One data line of *DLOAD: pressure `value` on surface `target` (DLOAD_PRESSURE), or the
  !! body force rho value dir on element set `target` ('' = all elements; DLOAD_GRAV).
  type :: dload_in_t
    character(len=str_len) :: target = ''
    integer :: kind = DLOAD_PRESSURE
    real(dp) :: value = 0.0_dp
    real(dp) :: dir(3) = 0.0_dp
    character(len=str_len) :: amplitude = ''
    character(len=where_len) :: where = ''
    character(len=where_len) :: card_where = ''
  end type dload_in_t

  !> One data line of *INITIAL CONDITIONS, TYPE=VELOCITY.
  type :: velocity_in_t
    character(len=str_len) :: target = ''
    integer :: dof = 0
    real(dp) :: value = 0.0_dp
    character(len=where_len) :: where = ''
  end type velocity_in_t

  !> *MASS.
  type :: mass_in_t
    integer :: kind = MASS_HRZ
    !> TYPE=ALPHA: midside fraction.
    real(dp) :: alpha = 0.0_dp
    !> TYPE=HRZ: HRZ_FULL (default) or HRZ_GAUSS2 (parameter INTEGRATION=2X2).
    integer :: hrz_rule = HRZ_FULL
    !> Which body: ELSET= or PATCH= ('' for all).
    character(len=str_len) :: elset = ''
    character(len=str_len) :: patch = ''
    character(len=where_len) :: where = ''
  end type mass_in_t

  !> *DAMPING.
  type :: damping_in_t
    real(dp) :: alpha = 0.0_dp
    character(len=str_len) :: elset = ''
    character(len=str_len) :: patch = ''
    character(len=where_len) :: where = ''
  end type damping_in_t

  !> *PATCH with its *KNOTS and *CONTROL POINTS, as read (before refinement).
  type :: patch_in_t
    character(len=str_len) :: name = ''
    character(len=str_len) :: material = ''
    !> Degrees and control points per direction: two directions in 2D (the third 0), three
    !! in 3D (a trivariate patch).
    integer :: degree(3) = 0
    integer :: size(3) = 0
    real(dp), allocatable :: knots1(:)
    real(dp), allocatable :: knots2(:)
    real(dp), allocatable :: knots3(:)
    !> Control points (3, n1*n2): x, y, w in 2D; (4, n1*n2*n3): x, y, z, w in 3D; direction-1
    !! index fastest, then 2, then 3.
    real(dp), allocatable :: cp(:,:)
    logical :: has_knots(3) = .false.
    logical :: has_cp = .false.
    !> DILATATION=: 0 AUTO (not given), 1 FULL, 2 MEAN (doc/theory.md §2.1).
    integer :: dilatation = 0
    !> MERGE=YES: control points on its sides that coincide with those of another MERGE=YES
    !! patch side become one node (a multi-patch body; doc/iga.md §1.1).
    logical :: merge = .false.
    character(len=where_len) :: where = ''
  end type patch_in_t

  !> *ELEVATE or *REFINE, in deck order.
  type :: patch_op_in_t
    integer :: kind = 0
    character(len=str_len) :: patch = ''
    !> ELEVATE: target degrees q1, q2[, q3]; REFINE: subdivisions k1, k2[, k3] (the third 0
    !! in 2D).
    integer :: values(3) = 0
    character(len=where_len) :: where = ''
  end type patch_op_in_t

  !> *OUTPUT, HISTORY, NSET=: a node set with a history of its own.
  type :: out_set_in_t
    character(len=str_len) :: name = ''
    !> VARIABLES= (VAR_* of ictus_solver_model) and whether it was given (default U, V, RF).
    logical :: vars(NVAR) = .false.
    logical :: vars_given = .false.
    !> EVERY= and TIME INTERVAL= when given (0 otherwise): they must agree with the history
    !! card without NSET.
    integer :: every = 0
    real(dp) :: interval = 0.0_dp
    character(len=where_len) :: where = ''
  end type out_set_in_t

  !> *STEP ... *END STEP.
  type :: step_in_t
    !> Time step; 0 = automatic (safety * 2/omega_max).
    real(dp) :: dt = 0.0_dp
    real(dp) :: t_end = 0.0_dp
    real(dp) :: safety = 0.9_dp
    !> Relative residual at which the consistent-mass conjugate gradient stops (MASS TOL=).
    real(dp) :: mass_tol = 1.0e-12_dp
    !> MASS SOLVER=AUTO (default: KRONECKER where it applies, else CHOLESKY), KRONECKER
    !! (1D factors along lattice directions), CHOLESKY (M factorised once), CG or CORRECTOR.
    character(len=16) :: mass_solver = 'AUTO'
    !> Corrector passes of MASS SOLVER=CORRECTOR (MASS PASSES=).
    integer :: mass_passes = 2
    !> How the internal force is formed (INTERNAL FORCE=): AUTO (the assembled stiffness
    !! where every law is linear, else the element loop), ASSEMBLED or ELEMENT.
    character(len=16) :: internal_force = 'AUTO'
    !> *STEP, NLGEOM=YES: finite strain.
    logical :: nlgeom = .false.
    !> ENERGY WARNING=f: warn once when |E_total - E_0| exceeds f E_max (0: not given, the
    !! default 0.01).
    real(dp) :: energy_warning = 0.0_dp
    !> Lumped-mass steps per sweep over the stiffness (SWEEP STEPS=); 0 = AUTO (6 steps,
    !! kept where the run measures them faster than single steps).
    integer :: sweep_steps = 0
    !> History output every n steps (default 1), or at the steps closest to the multiples of
    !! history_interval > 0 (TIME INTERVAL=; 0: not given).
    integer :: history_every = 1
    real(dp) :: history_interval = 0.0_dp
    !> "file:line" of *OUTPUT, HISTORY without NSET ('' when the deck has none).
    character(len=where_len) :: history_where = ''
    !> Node sets with a history of their own (*OUTPUT, HISTORY, NSET=).
    integer :: n_out_sets = 0
    type(out_set_in_t), allocatable :: out_sets(:)
    !> Field output every n steps (0 = default: 20 snapshots over the run), or at the steps
    !! closest to the multiples of field_interval > 0 (TIME INTERVAL=; 0: not given).
    integer :: field_every = 0
    real(dp) :: field_interval = 0.0_dp
    !> VARIABLES= of *OUTPUT, FIELD (VAR_* of ictus_solver_model) and whether it was given.
    logical :: field_vars(NVAR) = .false.
    logical :: field_vars_given = .false.
    !> Viewing samples per direction of NURBS elements (SAMPLES=; 0 = 2 p_max + 1 per patch).
    integer :: field_samples = 0
    !> "file:line" of *OUTPUT, FIELD ('' when the deck has none).
    character(len=where_len) :: field_where = ''
    !> Checkpoint every n steps (0 = none).
    integer :: restart_every = 0
    !> "file:line" of *STEP and of *DYNAMIC.
    character(len=where_len) :: where = ''
    character(len=where_len) :: dynamic_where = ''
  end type step_in_t

  !> *CONTACT PAIR or *TIE.
  type :: contact_pair_in_t
    character(len=str_len) :: name = ''
    real(dp) :: penalty = 0.0_dp
    integer :: algorithm = CONTACT_TWO_HALF_PASS
    !> Bipenalty mass penalty: < 0 none (default), 0 = AUTO, > 0 the given epsilon_m.
    real(dp) :: mass_penalty = -1.0_dp
    !> INTERACTION= (a *SURFACE INTERACTION; '' none) and TANGENTIAL PENALTY= (0: PENALTY).
    character(len=str_len) :: interaction = ''
    real(dp) :: tangential_penalty = 0.0_dp
    !> STABILITY=WARN: run even when the contact ratio r exceeds its limit (default STOP:
    !! an input error).
    logical :: stability_warn = .false.
    !> *TIE (a MORTAR tie; penalty 0: set from the time step).
    logical :: tie = .false.
    character(len=str_len) :: first = ''
    character(len=str_len) :: second = ''
    character(len=where_len) :: where = ''
  end type contact_pair_in_t

  !> *RIGID WALL: POINT= and NORMAL= with ndm components (z = 0 in 2D).
  type :: rigid_wall_in_t
    character(len=str_len) :: name = ''
    real(dp) :: point(3) = 0.0_dp
    real(dp) :: normal(3) = 0.0_dp
    real(dp) :: penalty = 0.0_dp
    !> INTERACTION= (a *SURFACE INTERACTION; '' none) and TANGENTIAL PENALTY= (0: PENALTY).
    character(len=str_len) :: interaction = ''
    real(dp) :: tangential_penalty = 0.0_dp
    !> STABILITY=WARN (see contact_pair_in_t).
    logical :: stability_warn = .false.
    character(len=str_len) :: surface = ''
    character(len=where_len) :: where = ''
  end type rigid_wall_in_t

  !> *SURFACE INTERACTION with its *FRICTION (mu < 0: no *FRICTION given).
  type :: interaction_in_t
    character(len=str_len) :: name = ''
    real(dp) :: mu = -1.0_dp
    character(len=where_len) :: where = ''
  end type interaction_in_t

  !> The whole deck.
  type :: deck_t
    !> Path of the main deck file.
    character(len=:), allocatable :: path
    character(len=:), allocatable :: title
    integer :: analysis = ANALYSIS_PLANE_STRAIN
    !> The dimension: 3 when *ANALYSIS, TYPE=3D (anywhere in the deck), else 2. The reader
    !! knows it before the first card, so that nodes, element types, dofs and faces are
    !! checked against it where they are read.
    integer :: ndm = 2
    real(dp) :: thickness = 1.0_dp
    !> Where *ANALYSIS gave THICKNESS= ('' when it did not).
    character(len=where_len) :: thickness_where = ''
    integer :: n_materials = 0
    type(material_in_t), allocatable :: materials(:)
    !> FE nodes: ids (n) and coordinates (ndm, n), in deck order.
    integer :: n_nodes = 0
    integer, allocatable :: node_ids(:)
    real(dp), allocatable :: node_x(:,:)
    character(len=where_len), allocatable :: node_where(:)
    !> Where *ANALYSIS gave TYPE= ('' when it did not).
    character(len=where_len) :: analysis_where = ''
    integer :: n_blocks = 0
    type(element_block_in_t), allocatable :: blocks(:)
    !> Boundary elements (T3D2, T3D3 of a gmsh boundary; in 3D its surface elements CPS3..M3D9):
    !! not part of the model, their ELSET names become node sets.
    integer :: n_edges = 0
    type(element_block_in_t), allocatable :: edges(:)
    integer :: n_sections = 0
    type(section_in_t), allocatable :: sections(:)
    integer :: n_sets = 0
    type(set_in_t), allocatable :: sets(:)
    integer :: n_surfaces = 0
    type(surface_in_t), allocatable :: surfaces(:)
    integer :: n_boundaries = 0
    type(boundary_in_t), allocatable :: boundaries(:)
    integer :: n_velocities = 0
    type(velocity_in_t), allocatable :: velocities(:)
    integer :: n_amplitudes = 0
    type(amplitude_in_t), allocatable :: amplitudes(:)
    integer :: n_cloads = 0
    type(cload_in_t), allocatable :: cloads(:)
    integer :: n_dloads = 0
    type(dload_in_t), allocatable :: dloads(:)
    integer :: n_masses = 0
    type(mass_in_t), allocatable :: masses(:)
    integer :: n_dampings = 0
    type(damping_in_t), allocatable :: dampings(:)
    integer :: n_patches = 0
    type(patch_in_t), allocatable :: patches(:)
    integer :: n_patch_ops = 0
    type(patch_op_in_t), allocatable :: patch_ops(:)
    integer :: n_pairs = 0
    type(contact_pair_in_t), allocatable :: pairs(:)
    integer :: n_walls = 0
    type(rigid_wall_in_t), allocatable :: walls(:)
    integer :: n_interactions = 0
    type(interaction_in_t), allocatable :: interactions(:)
    logical :: has_step = .false.
    type(step_in_t) :: step
  end type deck_t


end module ictus_io_deck_types
