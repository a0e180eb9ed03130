!> Whole-deck checks of a `deck_t`, run by the reader after the last card: everything that
!! needs the complete deck (so the order of cards in the deck does not matter).
!!
!! * materials: *ELASTIC and *DENSITY present; MATERIAL= of elements and patches defined;
!! * nodes and elements: unique ids, element nodes defined, surface elements defined;
!! * patches: both *KNOTS and *CONTROL POINTS; *ELEVATE/*REFINE of known patches, elevation
!!   never below the current degree (earlier *ELEVATE of the same patch included);
!! * names used but never defined: set references, *BOUNDARY / *INITIAL CONDITIONS targets,
!!   *SURFACE element sets, PATCH= and ELSET= of *NSET, *SURFACE, *MASS and *DAMPING, the
!!   surfaces of *CONTACT PAIR and *RIGID WALL, the node sets of *OUTPUT, HISTORY, NSET=; set
!!   reference cycles;
!! * loads: amplitude names unique and every AMPLITUDE= defined, the sets and surfaces of
!!   *CLOAD and *DLOAD defined.
!! Every ELSET name (of *ELSET or of *ELEMENT, ELSET=) and every patch name is also a node set.
module ictus_io_deck_checks
  use ictus_core_kinds, only: dp, str_len
  use ictus_core_errors, only: input_error
  use ictus_core_strings, only: str, str_list
  use ictus_io_deck_types, only: deck_t, material_in_t, SET_NODE, SET_ELEMENT, SIDE_NONE, &
      SURF_PATCH, OP_ELEVATE, where_len, ANALYSIS_PLANE_STRESS, DLOAD_PRESSURE
  implicit none
  private
  public :: check_deck, SKIP_MATERIALS, SKIP_NODES, SKIP_ELEMENTS, SKIP_SETS, SKIP_PATCHES, &
      SKIP_SURFACES

  !> Bits of `check_deck`'s `skip`: a card of this kind was broken (already reported), so
  !! "used but never defined" checks of this kind would only repeat that problem.
  integer, parameter :: SKIP_MATERIALS = 1, SKIP_NODES = 2, SKIP_ELEMENTS = 4, SKIP_SETS = 8, &
      SKIP_PATCHES = 16, SKIP_SURFACES = 32

  !> Kinds of defined names (bit flags).
  integer, parameter :: NAME_NSET = 1, NAME_ELSET = 2, NAME_PATCH = 4, NAME_SURFACE = 8

  !> The table of defined names.
  type :: names_t
    integer :: n = 0
    !> SKIP_* bits passed to check_deck.
    integer :: skip = 0
    character(len=str_len), allocatable :: name(:)
    integer, allocatable :: kind(:)
  end type names_t

contains

  !> Runs every whole-deck check on `d`, reporting problems with `input_error`. `skip`
  !! (SKIP_* bits) names the kinds whose definitions had errors already reported.
  subroutine check_deck(d, skip)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: skip
    type(names_t) :: names
    call collect_names(d, names)
    names%skip = skip
    call check_materials(d, iand(skip, SKIP_MATERIALS) /= 0)
    if (d%step%nlgeom .and. d%analysis == ANALYSIS_PLANE_STRESS) call input_error( &
        d%step%where, '*STEP, NLGEOM=YES: finite strain is not implemented in plane stress '// &
        '(the thickness stretch is not solved for; use *ANALYSIS, TYPE=PLANE STRAIN)')
    call check_nodes_elements(d, names)
    call check_patches(d, skip)
    call check_sets(d, names)
    call check_uses(d, names)
    call check_loads(d, names)
    call check_sections(d, names, iand(skip, SKIP_MATERIALS) /= 0)
    call check_dilatation(d)
  end subroutine check_deck

  !> The law of material m against the step: *HYPERELASTIC needs NLGEOM=YES; *PLASTIC needs
  !! *ELASTIC; neither finite strain nor J2 plasticity is implemented in plane stress (the
  !! thickness change would need its own return); INTERNAL FORCE=ASSEMBLED is exact only for a
  !! linear law in small strain.
  subroutine check_laws(d, m)
    type(deck_t), intent(in) :: d
    type(material_in_t), intent(in) :: m
    character(len=:), allocatable :: step
    step = trim(d%step%where)
    if (len(step) == 0) step = trim(m%law_where)
    if (m%has_hyperelastic .and. .not. d%step%nlgeom) call input_error(m%law_where, &
        '*HYPERELASTIC: the neo-Hookean law of material '//trim(m%name)//' is a finite-'// &
        'strain law: it needs *STEP, NLGEOM=YES')
    if (m%has_plastic .and. .not. m%has_elastic) call input_error(m%where, '*PLASTIC: '// &
        'material '//trim(m%name)//' has plasticity without *ELASTIC (J2 plasticity '// &
        'takes its elastic part from *ELASTIC)')
    if (d%analysis == ANALYSIS_PLANE_STRESS .and. m%has_plastic) call input_error(m%where, &
        '*PLASTIC: J2 plasticity of material '//trim(m%name)//' is not implemented in '// &
        'plane stress (use *ANALYSIS, TYPE=PLANE STRAIN)')
    if (d%step%internal_force == 'ASSEMBLED' .and. (d%step%nlgeom .or. m%has_plastic .or. &
        m%has_hyperelastic)) call input_error(d%step%dynamic_where, '*DYNAMIC, EXPLICIT: '// &
        'INTERNAL FORCE=ASSEMBLED is exact only for linear laws in small strain, but '// &
        'material '//trim(m%name)//' is '//trim(merge('nonlinear        ', &
        'in finite strain ', m%has_plastic .or. m%has_hyperelastic))//' (use AUTO or ELEMENT)')
  end subroutine check_laws

  !> DILATATION=MEAN on an *ELEMENT or *PATCH card needs the element loop: INTERNAL
  !! FORCE=ASSEMBLED (the constant K of the full formulation) is refused with it.
  subroutine check_dilatation(d)
    type(deck_t), intent(in) :: d
    integer :: k
    if (d%step%internal_force /= 'ASSEMBLED') return
    do k = 1, d%n_blocks
      if (d%blocks(k)%dilatation == 2) call input_error(d%blocks(k)%where, '*ELEMENT: '// &
          'DILATATION=MEAN needs the element loop, but *DYNAMIC, EXPLICIT asks for INTERNAL '// &
          'FORCE=ASSEMBLED at '//trim(d%step%dynamic_where)//' (use AUTO or ELEMENT)')
    end do
    do k = 1, d%n_patches
      if (d%patches(k)%dilatation == 2) call input_error(d%patches(k)%where, '*PATCH: '// &
          'DILATATION=MEAN needs the element loop, but *DYNAMIC, EXPLICIT asks for INTERNAL '// &
          'FORCE=ASSEMBLED at '//trim(d%step%dynamic_where)//' (use AUTO or ELEMENT)')
    end do
  end subroutine check_dilatation

  !> *SOLID SECTION: its element set and its material are defined.
  subroutine check_sections(d, names, skip_materials)
    type(deck_t), intent(in) :: d
    type(names_t), intent(in) :: names
    logical, intent(in) :: skip_materials
    integer :: k
    do k = 1, d%n_sections
      call need(names, d%sections(k)%elset, NAME_ELSET, 'element set', d%sections(k)%where, &
          '*SOLID SECTION')
      if (.not. skip_materials .and. .not. has_material(d, d%sections(k)%material)) &
          call input_error(d%sections(k)%where, '*SOLID SECTION: material '// &
          trim(d%sections(k)%material)//' is used but never defined')
    end do
  end subroutine check_sections

  !> Builds the table of set, patch and surface names.
  subroutine collect_names(d, t)
    type(deck_t), intent(in) :: d
    type(names_t), intent(out) :: t
    integer :: k
    allocate(t%name(d%n_sets + d%n_blocks + d%n_patches + d%n_surfaces), t%kind(size(t%name)))
    do k = 1, d%n_sets
      if (d%sets(k)%kind == SET_NODE) then
        call add_name(t, d%sets(k)%name, NAME_NSET)
      else
        call add_name(t, d%sets(k)%name, ior(NAME_ELSET, NAME_NSET))
      end if
    end do
    do k = 1, d%n_blocks
      if (len_trim(d%blocks(k)%elset) > 0) call add_name(t, d%blocks(k)%elset, &
          ior(NAME_ELSET, NAME_NSET))
    end do
    do k = 1, d%n_patches
      call add_name(t, d%patches(k)%name, ior(ior(NAME_PATCH, NAME_NSET), NAME_ELSET))
    end do
    do k = 1, d%n_surfaces
      call add_name(t, d%surfaces(k)%name, NAME_SURFACE)
    end do
  end subroutine collect_names

  !> Adds `kind` to the entry of `name` (new entry when absent).
  subroutine add_name(t, name, kind)
    type(names_t), intent(inout) :: t
    character(len=*), intent(in) :: name
    integer, intent(in) :: kind
    integer :: k
    do k = 1, t%n
      if (t%name(k) == name) then
        t%kind(k) = ior(t%kind(k), kind)
        return
      end if
    end do
    t%n = t%n + 1
    t%name(t%n) = name
    t%kind(t%n) = kind
  end subroutine add_name

  !> True when `name` is defined with (at least one bit of) `kind`.
  logical function defined(t, name, kind)
    type(names_t), intent(in) :: t
    character(len=*), intent(in) :: name
    integer, intent(in) :: kind
    integer :: k
    defined = .false.
    do k = 1, t%n
      if (t%name(k) == name) then
        defined = iand(t%kind(k), kind) /= 0
        return
      end if
    end do
  end function defined

  !> Reports `name` at `where` when it is not defined as `kind` (described by `what`).
  subroutine need(t, name, kind, what, where, card)
    type(names_t), intent(in) :: t
    character(len=*), intent(in) :: name, what, where, card
    integer, intent(in) :: kind
    if (len_trim(name) == 0) return
    if (defined(t, name, kind)) return
    if (iand(kind, ior(NAME_NSET, NAME_ELSET)) /= 0 .and. &
        iand(t%skip, ior(SKIP_SETS, ior(SKIP_ELEMENTS, SKIP_PATCHES))) /= 0) return
    if (iand(kind, NAME_PATCH) /= 0 .and. iand(t%skip, SKIP_PATCHES) /= 0) return
    if (iand(kind, NAME_SURFACE) /= 0 .and. iand(t%skip, SKIP_SURFACES) /= 0) return
    call input_error(where, card//': '//what//' '//trim(name)//' is used but never defined')
  end subroutine need

  !> Every material has an elastic law (*ELASTIC or *HYPERELASTIC) and *DENSITY, and its law
  !! fits the kinematics (check_laws); element blocks and patches name a material.
  subroutine check_materials(d, skip_undefined)
    type(deck_t), intent(in) :: d
    logical, intent(in) :: skip_undefined
    integer :: k
    do k = 1, d%n_materials
      if (.not. (d%materials(k)%has_elastic .or. d%materials(k)%has_hyperelastic)) &
          call input_error(d%materials(k)%where, '*MATERIAL: material '// &
          trim(d%materials(k)%name)//' has no *ELASTIC card (expected *ELASTIC with "E, '// &
          'nu", or *HYPERELASTIC, NEO HOOKE with NLGEOM=YES)')
      call check_laws(d, d%materials(k))
      if (.not. d%materials(k)%has_density) call input_error(d%materials(k)%where, &
          '*MATERIAL: material '//trim(d%materials(k)%name)//' has no *DENSITY card '// &
          '(expected *DENSITY with "rho")')
    end do
    if (skip_undefined) return
    do k = 1, d%n_blocks
      if (len_trim(d%blocks(k)%material) == 0) cycle
      if (any(d%sections(1:d%n_sections)%material == d%blocks(k)%material)) cycle
      if (.not. has_material(d, d%blocks(k)%material)) call input_error(d%blocks(k)%where, &
          '*ELEMENT: material '//trim(d%blocks(k)%material)//' is used but never defined')
    end do
    do k = 1, d%n_patches
      if (.not. has_material(d, d%patches(k)%material)) call input_error( &
          d%patches(k)%where, '*PATCH: material '//trim(d%patches(k)%material)// &
          ' is used but never defined')
    end do
  end subroutine check_materials

  logical function has_material(d, name)
    type(deck_t), intent(in) :: d
    character(len=*), intent(in) :: name
    integer :: k
    has_material = .false.
    do k = 1, d%n_materials
      if (d%materials(k)%name == name) has_material = .true.
    end do
  end function has_material

  !> Unique node and element ids; element nodes and surface elements defined.
  subroutine check_nodes_elements(d, t)
    type(deck_t), intent(in) :: d
    type(names_t), intent(in) :: t
    integer, allocatable :: node_sorted(:), node_perm(:), el_ids(:), el_sorted(:), el_perm(:)
    character(len=where_len), allocatable :: el_where(:)
    integer :: k, b, e, a, m, s

    call sort_ids(d%node_ids, node_sorted, node_perm)
    do k = 2, size(node_sorted)
      if (node_sorted(k) == node_sorted(k - 1)) call input_error( &
          d%node_where(node_perm(k)), '*NODE: duplicate node id '//str(node_sorted(k))// &
          ' (first defined at '//trim(d%node_where(node_perm(k - 1)))//')')
    end do

    m = 0
    do b = 1, d%n_blocks
      m = m + size(d%blocks(b)%ids)
    end do
    allocate(el_ids(m), el_where(m))
    m = 0
    do b = 1, d%n_blocks
      do e = 1, size(d%blocks(b)%ids)
        m = m + 1
        el_ids(m) = d%blocks(b)%ids(e)
        el_where(m) = trim(d%blocks(b)%file)//':'//str(d%blocks(b)%line(e))
        do a = 1, d%blocks(b)%nen
          if (iand(t%skip, SKIP_NODES) /= 0) exit
          if (.not. found(node_sorted, d%blocks(b)%conn(a, e))) call input_error( &
              el_where(m), '*ELEMENT: element '//str(el_ids(m))//' references node '// &
              str(d%blocks(b)%conn(a, e))//', which is not defined by any *NODE card')
        end do
      end do
    end do
    call sort_ids(el_ids, el_sorted, el_perm)
    do k = 2, size(el_sorted)
      if (el_sorted(k) == el_sorted(k - 1)) call input_error(el_where(el_perm(k)), &
          '*ELEMENT: duplicate element id '//str(el_sorted(k))//' (first defined at '// &
          trim(el_where(el_perm(k - 1)))//')')
    end do

    do s = 1, d%n_surfaces
      if (d%surfaces(s)%kind == SURF_PATCH) then
        if (allocated(d%surfaces(s)%side_patch)) then
          do k = 1, size(d%surfaces(s)%side_patch)
            call need(t, d%surfaces(s)%side_patch(k), NAME_PATCH, 'patch', &
                d%surfaces(s)%entry_where(k), '*SURFACE')
          end do
        else
          call need(t, d%surfaces(s)%patch, NAME_PATCH, 'patch', d%surfaces(s)%where, &
              '*SURFACE')
        end if
        cycle
      end if
      do k = 1, size(d%surfaces(s)%elem)
        if (d%surfaces(s)%elem(k) > 0) then
          if (iand(t%skip, SKIP_ELEMENTS) /= 0) cycle
          if (.not. found(el_sorted, d%surfaces(s)%elem(k))) call input_error( &
              d%surfaces(s)%entry_where(k), '*SURFACE: element '// &
              str(d%surfaces(s)%elem(k))//' is not defined by any *ELEMENT card')
        else
          call need(t, d%surfaces(s)%elset(k), NAME_ELSET, 'element set', &
              d%surfaces(s)%entry_where(k), '*SURFACE')
          if (d%ndm == 3 .and. any(d%patches(1:d%n_patches)%name == d%surfaces(s)%elset(k))) &
              call input_error(d%surfaces(s)%entry_where(k), '*SURFACE: not yet in 3D: '// &
              'faces of the trivariate patch '//trim(d%surfaces(s)%elset(k))//' (its spans '// &
              'have no faces S1..S6; TYPE=ELEMENT takes the faces of hexahedra)')
        end if
      end do
    end do
  end subroutine check_nodes_elements

  !> Each patch has knots in every direction (two in 2D, three in 3D) and control points;
  !! *ELEVATE / *REFINE refer to known patches and never lower the degree.
  subroutine check_patches(d, skip)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: skip
    integer, allocatable :: deg(:,:)
    integer :: k, p, dir, nd

    nd = d%ndm
    allocate(deg(nd, d%n_patches))
    do p = 1, d%n_patches
      deg(:, p) = d%patches(p)%degree(1:nd)
      do dir = 1, nd
        if (.not. d%patches(p)%has_knots(dir)) call input_error(d%patches(p)%where, &
            '*PATCH: patch '//trim(d%patches(p)%name)//' has no *KNOTS, DIRECTION='// &
            str(dir)//' card (expected its knot vector)')
      end do
      if (.not. d%patches(p)%has_cp) call input_error(d%patches(p)%where, '*PATCH: patch '// &
          trim(d%patches(p)%name)//' has no *CONTROL POINTS card (expected '// &
          trim(merge('n1*n2*n3 lines "x, y, z, w"', 'n1*n2 lines "x, y, w"      ', nd == 3))// &
          ')')
    end do
    do k = 1, d%n_patch_ops
      associate (op => d%patch_ops(k))
        p = 0
        do dir = 1, d%n_patches
          if (d%patches(dir)%name == op%patch) p = dir
        end do
        if (p == 0) then
          if (iand(skip, SKIP_PATCHES) /= 0) cycle
          call input_error(op%where, trim(merge('*ELEVATE', '*REFINE ', &
              op%kind == OP_ELEVATE))//': unknown patch '//trim(op%patch)// &
              ' (expected the NAME= of a *PATCH)')
          cycle
        end if
        if (op%kind /= OP_ELEVATE) cycle
        if (any(op%values(1:nd) < deg(:, p))) then
          call input_error(op%where, '*ELEVATE: DEGREE='//str_list(op%values(1:nd))// &
              ' is below the current degree '//str_list(deg(:, p))//' of patch '// &
              trim(op%patch)//' (expected q_i >= p_i)')
        else
          deg(:, p) = op%values(1:nd)
        end if
      end associate
    end do
  end subroutine check_patches


  !> Set references are defined (with the right kind) and do not form cycles.
  subroutine check_sets(d, t)
    type(deck_t), intent(in) :: d
    type(names_t), intent(in) :: t
    integer, allocatable :: state(:)
    integer :: s, k

    do s = 1, d%n_sets
      associate (st => d%sets(s))
        if (st%side /= SIDE_NONE) call need(t, st%patch, NAME_PATCH, 'patch', st%where, &
            '*NSET')
        do k = 1, size(st%refs)
          if (st%kind == SET_NODE) then
            call need(t, st%refs(k), NAME_NSET, 'node set', st%ref_where(k), '*NSET')
          else
            call need(t, st%refs(k), NAME_ELSET, 'element set', st%ref_where(k), '*ELSET')
          end if
        end do
      end associate
    end do
    allocate(state(d%n_sets))
    state = 0
    do s = 1, d%n_sets
      if (state(s) == 0) call visit(d, s, state)
    end do
  end subroutine check_sets

  !> Depth-first walk of set references; reports a reference that closes a cycle.
  recursive subroutine visit(d, s, state)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: s
    integer, intent(inout) :: state(:)
    integer :: k, r, j
    state(s) = 1
    do k = 1, size(d%sets(s)%refs)
      r = 0
      do j = 1, d%n_sets
        if (d%sets(j)%name == d%sets(s)%refs(k)) r = j
      end do
      if (r == 0) cycle
      if (state(r) == 1) then
        call input_error(d%sets(s)%ref_where(k), '*'//trim(merge('NSET ', 'ELSET', &
            d%sets(s)%kind == SET_NODE))//': set '//trim(d%sets(s)%name)//' includes '// &
            trim(d%sets(r)%name)//', which includes '//trim(d%sets(s)%name)// &
            ' (a cycle of set references)')
      else if (state(r) == 0) then
        call visit(d, r, state)
      end if
    end do
    state(s) = 2
  end subroutine visit

  !> Names used by conditions, mass, damping, contact pairs and walls are defined.
  subroutine check_uses(d, t)
    type(deck_t), intent(in) :: d
    type(names_t), intent(in) :: t
    integer :: k
    do k = 1, d%n_boundaries
      if (.not. is_id(d%boundaries(k)%target)) call need(t, d%boundaries(k)%target, &
          NAME_NSET, 'node set', d%boundaries(k)%where, '*BOUNDARY')
    end do
    do k = 1, d%n_velocities
      if (.not. is_id(d%velocities(k)%target)) call need(t, d%velocities(k)%target, &
          NAME_NSET, 'node set', d%velocities(k)%where, '*INITIAL CONDITIONS')
    end do
    do k = 1, d%n_masses
      call need(t, d%masses(k)%elset, NAME_ELSET, 'element set', d%masses(k)%where, '*MASS')
      call need(t, d%masses(k)%patch, NAME_PATCH, 'patch', d%masses(k)%where, '*MASS')
    end do
    do k = 1, d%n_dampings
      call need(t, d%dampings(k)%elset, NAME_ELSET, 'element set', d%dampings(k)%where, &
          '*DAMPING')
      call need(t, d%dampings(k)%patch, NAME_PATCH, 'patch', d%dampings(k)%where, '*DAMPING')
    end do
    do k = 1, d%n_pairs
      call need(t, d%pairs(k)%first, NAME_SURFACE, 'surface', d%pairs(k)%where, &
          '*CONTACT PAIR')
      call need(t, d%pairs(k)%second, NAME_SURFACE, 'surface', d%pairs(k)%where, &
          '*CONTACT PAIR')
    end do
    do k = 1, d%n_walls
      call need(t, d%walls(k)%surface, NAME_SURFACE, 'surface', d%walls(k)%where, &
          '*RIGID WALL')
    end do
    call check_interactions(d)
    do k = 1, d%step%n_out_sets
      call need(t, d%step%out_sets(k)%name, NAME_NSET, 'node set', d%step%out_sets(k)%where, &
          '*OUTPUT, HISTORY, NSET=')
    end do
  end subroutine check_uses

  !> The INTERACTION= of contact pairs and walls name a *SURFACE INTERACTION, and every
  !! *SURFACE INTERACTION has its *FRICTION.
  subroutine check_interactions(d)
    type(deck_t), intent(in) :: d
    integer :: k
    do k = 1, d%n_pairs
      call need_interaction(d, d%pairs(k)%interaction, d%pairs(k)%where, '*CONTACT PAIR')
    end do
    do k = 1, d%n_walls
      call need_interaction(d, d%walls(k)%interaction, d%walls(k)%where, '*RIGID WALL')
    end do
    do k = 1, d%n_interactions
      if (d%interactions(k)%mu < 0.0_dp) call input_error(d%interactions(k)%where, &
          '*SURFACE INTERACTION: NAME='//trim(d%interactions(k)%name)//' has no *FRICTION '// &
          '(expected a *FRICTION card with the coefficient mu right after it)')
    end do
  end subroutine check_interactions

  !> Reports an INTERACTION= name (not blank) that no *SURFACE INTERACTION defines.
  subroutine need_interaction(d, name, where, card)
    type(deck_t), intent(in) :: d
    character(len=*), intent(in) :: name, where, card
    integer :: k
    if (len_trim(name) == 0) return
    do k = 1, d%n_interactions
      if (d%interactions(k)%name == name) return
    end do
    call input_error(where, card//': INTERACTION='//trim(name)//' is not defined (expected '// &
        'the NAME= of a *SURFACE INTERACTION card with its *FRICTION)')
  end subroutine need_interaction

  !> The load cards: amplitude names unique and every AMPLITUDE= defined; the node sets of
  !! *CLOAD, the surfaces of *DLOAD, P and the element sets of *DLOAD, GRAV defined.
  subroutine check_loads(d, t)
    type(deck_t), intent(in) :: d
    type(names_t), intent(in) :: t
    integer :: k, j
    do k = 2, d%n_amplitudes
      do j = 1, k - 1
        if (d%amplitudes(j)%name == d%amplitudes(k)%name) then
          call input_error(d%amplitudes(k)%where, '*AMPLITUDE: '// &
              trim(d%amplitudes(k)%name)//' is defined twice (first at '// &
              trim(d%amplitudes(j)%where)//')')
          exit
        end if
      end do
    end do
    ! the data lines of one card are consecutive records: each card is checked once
    do k = 1, d%n_boundaries
      if (k > 1) then
        if (d%boundaries(k)%card_where == d%boundaries(k - 1)%card_where) cycle
      end if
      call need_amplitude(d, d%boundaries(k)%amplitude, d%boundaries(k)%card_where, &
          '*BOUNDARY')
    end do
    do k = 1, d%n_cloads
      if (k == 1) then
        call need_amplitude(d, d%cloads(k)%amplitude, d%cloads(k)%card_where, '*CLOAD')
      else if (d%cloads(k)%card_where /= d%cloads(k - 1)%card_where) then
        call need_amplitude(d, d%cloads(k)%amplitude, d%cloads(k)%card_where, '*CLOAD')
      end if
      if (.not. is_id(d%cloads(k)%target)) call need(t, d%cloads(k)%target, NAME_NSET, &
          'node set', d%cloads(k)%where, '*CLOAD')
    end do
    do k = 1, d%n_dloads
      if (k == 1) then
        call need_amplitude(d, d%dloads(k)%amplitude, d%dloads(k)%card_where, '*DLOAD')
      else if (d%dloads(k)%card_where /= d%dloads(k - 1)%card_where) then
        call need_amplitude(d, d%dloads(k)%amplitude, d%dloads(k)%card_where, '*DLOAD')
      end if
      if (d%dloads(k)%kind == DLOAD_PRESSURE) then
        call need(t, d%dloads(k)%target, NAME_SURFACE, 'surface', d%dloads(k)%where, &
            '*DLOAD, P')
        if (d%ndm == 3) call no_patch_pressure(d, d%dloads(k)%target, d%dloads(k)%where)
      else
        call need(t, d%dloads(k)%target, ior(NAME_ELSET, NAME_PATCH), 'element set or patch', &
            d%dloads(k)%where, '*DLOAD, GRAV')
      end if
    end do
  end subroutine check_loads

  !> In 3D a pressure (*DLOAD, P) acts on the faces of hexahedra only: reports a surface of
  !! patch sides (the faces of a trivariate NURBS patch) as not yet in 3D.
  subroutine no_patch_pressure(d, name, where)
    type(deck_t), intent(in) :: d
    character(len=*), intent(in) :: name, where
    integer :: s
    do s = 1, d%n_surfaces
      if (d%surfaces(s)%name /= name .or. d%surfaces(s)%kind /= SURF_PATCH) cycle
      call input_error(where, '*DLOAD, P: not yet in 3D: pressure on the faces of a '// &
          'trivariate NURBS patch (surface '//trim(name)//' lists patch sides); in 3D a '// &
          'pressure acts on the faces S1..S6 of hexahedra (*SURFACE, TYPE=ELEMENT)')
    end do
  end subroutine no_patch_pressure

  !> Reports AMPLITUDE=name of a card (at `where`) when no *AMPLITUDE defines it.
  subroutine need_amplitude(d, name, where, card)
    type(deck_t), intent(in) :: d
    character(len=*), intent(in) :: name, where, card
    integer :: k
    if (len_trim(name) == 0) return
    do k = 1, d%n_amplitudes
      if (d%amplitudes(k)%name == name) return
    end do
    call input_error(where, card//': amplitude '//trim(name)//' is used but never '// &
        'defined (expected an *AMPLITUDE, NAME='//trim(name)//')')
  end subroutine need_amplitude

  !> True when `s` is a node id written as digits.
  pure logical function is_id(s)
    character(len=*), intent(in) :: s
    integer :: k
    is_id = len_trim(s) > 0
    do k = 1, len_trim(s)
      if (s(k:k) < '0' .or. s(k:k) > '9') is_id = .false.
    end do
  end function is_id

  !> Sorted copy of `ids` and the permutation: sorted(k) = ids(perm(k)) (stable merge sort).
  subroutine sort_ids(ids, sorted, perm)
    integer, intent(in) :: ids(:)
    integer, allocatable, intent(out) :: sorted(:), perm(:)
    integer, allocatable :: tmp(:)
    integer :: n, width, lo, mid, hi, i, j, k
    n = size(ids)
    allocate(perm(n), tmp(n))
    perm = [(k, k = 1, n)]
    width = 1
    do while (width < n)
      do lo = 1, n, 2*width
        mid = min(lo + width, n + 1)
        hi = min(lo + 2*width, n + 1)
        i = lo
        j = mid
        do k = lo, hi - 1
          if (i < mid .and. (j >= hi .or. ids(perm(min(i, n))) <= ids(perm(min(j, n))))) then
            tmp(k) = perm(i)
            i = i + 1
          else
            tmp(k) = perm(j)
            j = j + 1
          end if
        end do
      end do
      perm = tmp
      width = 2*width
    end do
    sorted = ids(perm)
  end subroutine sort_ids

  !> Binary search of `id` in the sorted array `a`.
  pure logical function found(a, id)
    integer, intent(in) :: a(:)
    integer, intent(in) :: id
    integer :: lo, hi, mid
    found = .false.
    lo = 1
    hi = size(a)
    do while (lo <= hi)
      mid = (lo + hi)/2
      if (a(mid) == id) then
        found = .true.
        return
      else if (a(mid) < id) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
  end function found

end module ictus_io_deck_checks
