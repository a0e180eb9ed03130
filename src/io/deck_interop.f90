!> Interoperability with Abaqus, CalculiX and gmsh (deck format 2): the *SOLID SECTION card,
!! the Abaqus cards that ictus refuses by name, and what is settled once the whole deck is read.
!!
!! * `read_solid_section`: *SOLID SECTION, ELSET=, MATERIAL= [data: thickness].
!! * `refused_card`: the Abaqus cards ictus does not take, each with what to use instead.
!! * `resolve_interop` (called by `finish_deck` before `check_deck`):
!!   - the analysis implied by Abaqus element names (CPE*: plane strain, CPS*: plane stress)
!!     against each other and against *ANALYSIS, TYPE=;
!!   - line elements (T3D2, T3D3 of a gmsh boundary; in 3D also its surface elements CPS3,
!!     CPS4, CPS6, CPS8, M3D9) turned into node sets: the ELSET= of their
!!     *ELEMENT cards and every *ELSET made of them become *NSETs of their nodes;
!!   - materials: each element gets exactly one, from MATERIAL= on its *ELEMENT or from the
!!     *SOLID SECTION whose ELSET holds it. Blocks whose elements get different materials are
!!     split into runs of one material, in element order, so the model and the processed deck
!!     are those of the equivalent native deck.
module ictus_io_deck_interop
  use ictus_core_kinds, only: dp, i8, str_len
  use ictus_core_errors, only: input_error, error_count
  use ictus_core_strings, only: str
  use ictus_io_deck_lexer, only: token_t, line_where, split_fields
  use ictus_io_deck_types, only: deck_t, element_block_in_t, section_in_t, set_in_t, &
      SET_NODE, SET_ELEMENT, ANALYSIS_PLANE_STRAIN, ANALYSIS_3D
  use ictus_io_deck_card, only: card_t, reader_t, card_error, check_params, get_name, &
      count_ok, tok_real
  implicit none
  private
  public :: read_solid_section, refused_card, resolve_interop, resolve_twins

  !> Deepest nesting of element-set references followed (deeper: a cycle, reported by
  !! check_deck).
  integer, parameter :: max_depth = 64

  type :: str_list_t
    character(len=str_len), allocatable :: s(:)
  end type str_list_t
  type :: int_list_t
    integer, allocatable :: i(:)
  end type int_list_t

contains

  !> *SOLID SECTION, ELSET=name, MATERIAL=name: one optional data line, the thickness (empty:
  !! the default).
  subroutine read_solid_section(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*SOLID SECTION: expected "thickness" (optional)'
    type(section_in_t) :: s
    type(section_in_t), allocatable :: tmp(:)
    type(token_t), allocatable :: toks(:)
    integer :: n

    call check_params(c, 'ELSET|MATERIAL', '')
    call get_name(c, 'ELSET', .true., s%elset)
    call get_name(c, 'MATERIAL', .true., s%material)
    if (c%bad) return
    s%where = c%where
    if (c%last > c%first) then
      call input_error(line_where(rd%src, c%first + 1), expect//' on one data line, '// &
          'found another line')
      return
    end if
    if (c%last == c%first) then
      call split_fields(rd%src%lines(c%first)%text, toks, n)
      if (.not. count_ok(n, 0, 1, expect, line_where(rd%src, c%first))) return
      if (n == 1) then
        if (len(toks(1)%s) > 0) then
          if (.not. tok_real(toks, 1, expect, line_where(rd%src, c%first), s%thickness)) return
          if (s%thickness <= 0.0_dp) then
            call input_error(line_where(rd%src, c%first), '*SOLID SECTION: thickness '// &
                str(s%thickness)//' must be > 0')
            return
          end if
        end if
      end if
    end if
    if (.not. allocated(d%sections)) allocate(d%sections(0))
    allocate(tmp(d%n_sections + 1))
    tmp(1:d%n_sections) = d%sections(1:d%n_sections)
    tmp(d%n_sections + 1) = s
    call move_alloc(tmp, d%sections)
    d%n_sections = d%n_sections + 1
  end subroutine read_solid_section

  !> For an Abaqus card that ictus does not take: the message (what to use instead); '' for
  !! any other card.
  function refused_card(name) result(msg)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: msg
    character(len=*), parameter :: no_print = 'ictus writes no printed or .fil output: '// &
        'use *OUTPUT, HISTORY (energies, contact forces) and *OUTPUT, FIELD (displacements, '// &
        'velocities, accelerations, stresses), which go to the HDF5 results file'
    select case (name)
    case ('PART', 'END PART', 'ASSEMBLY', 'END ASSEMBLY', 'INSTANCE', 'END INSTANCE')
      msg = 'ictus has no parts, assemblies or instances: write the nodes, elements and '// &
          'sets at the top level of the deck (a flat input file)'
    case ('NODE PRINT', 'EL PRINT', 'NODE FILE', 'EL FILE', 'CONTACT OUTPUT', 'NODE OUTPUT', &
        'ELEMENT OUTPUT', 'ENERGY PRINT', 'ENERGY FILE', 'CONTACT PRINT', 'CONTACT FILE', &
        'SECTION PRINT', 'OUTPUT FILE')
      msg = no_print
    case ('FILE FORMAT', 'PREPRINT', 'MONITOR', 'CONTROLS', 'SECTION CONTROLS', &
        'DIAGNOSTICS', 'BULK VISCOSITY')
      msg = 'a control of Abaqus output or solution that ictus has no use for: remove the card'
    case ('ORIENTATION', 'TRANSFORM', 'SYSTEM')
      msg = 'ictus has isotropic materials in global axes only: remove the card'
    case ('TRANSVERSE SHEAR', 'SHELL SECTION', 'BEAM SECTION', 'BEAM GENERAL SECTION', &
        'MEMBRANE SECTION', 'TRUSS SECTION')
      msg = 'ictus has 2D solid elements only (no shells, beams, trusses or membranes): '// &
          'use *SOLID SECTION with quadrilaterals'
    case ('STATIC', 'FREQUENCY', 'BUCKLE', 'HEAT TRANSFER', 'VISCO', 'DYNAMIC TEMPERATURE-'// &
        'DISPLACEMENT', 'COUPLED TEMPERATURE-DISPLACEMENT')
      msg = 'ictus runs explicit dynamics only: use *DYNAMIC, EXPLICIT (with *DAMPING for a '// &
          'dynamic relaxation to a static state)'
    case ('EQUATION', 'MPC', 'KINEMATIC COUPLING', 'COUPLING', 'DISTRIBUTING COUPLING')
      msg = 'ictus has no constraint equations: use *BOUNDARY, or *CONTACT PAIR between bodies'
    case default
      msg = ''
    end select
  end function refused_card

  !> Settles what depends on the whole deck: the analysis of Abaqus element names, line
  !! elements as node sets, and the material of every element.
  !! `materials_broken`: a *MATERIAL or *SOLID SECTION card had errors (already reported), so
  !! elements left without a material are not reported again.
  subroutine resolve_interop(d, materials_broken)
    type(deck_t), intent(inout) :: d
    logical, intent(in) :: materials_broken
    integer :: n0
    n0 = error_count()
    call resolve_twins(d, .true.)
    call resolve_analysis(d)
    call resolve_edges(d)
    call resolve_thickness(d)
    if (d%n_sections > 0) call resolve_sections(d)
    if (.not. materials_broken .and. error_count() == n0) call check_unassigned(d)
  end subroutine resolve_interop

  !> An *NSET and an *ELSET of one name (a `twin` set, see set_index): allowed when the node
  !! set holds exactly the nodes of the element set's elements, as gmsh writes each physical
  !! group with Mesh.SaveGroupsOfNodes; the element set then stands for both. Otherwise (or
  !! when `compare` is false: the elements had errors) the later one is reported. Twin records
  !! are removed either way.
  subroutine resolve_twins(d, compare)
    type(deck_t), intent(inout) :: d
    logical, intent(in) :: compare
    logical, allocatable :: drop(:)
    integer, allocatable :: map(:,:)
    integer :: k, j, e, elo
    allocate(drop(d%n_sets))
    drop = .false.
    if (.not. any(d%sets(1:d%n_sets)%twin)) return
    if (compare) call element_map(d, map, elo)
    do k = 1, d%n_sets
      if (.not. d%sets(k)%twin) cycle
      drop(k) = .true.
      do j = 1, d%n_sets
        if (j == k .or. d%sets(j)%name /= d%sets(k)%name .or. d%sets(j)%twin) cycle
        e = merge(j, k, d%sets(j)%kind == SET_ELEMENT)
        if (compare) then
          if (same_nodes(d, d%sets(k + j - e), d%sets(e), map, elo)) then
            drop(k + j - e) = .true.
            drop(e) = .false.
            exit
          end if
        end if
        call input_error(d%sets(k)%where, '*'//trim(merge('NSET ', 'ELSET', &
            d%sets(k)%kind == SET_NODE))//': name '//trim(d%sets(k)%name)// &
            ' is already used by an '//trim(merge('ELSET', 'NSET ', d%sets(k)%kind == &
            SET_NODE))//' (first defined at '//trim(d%sets(j)%where)//'; an *NSET and an '// &
            '*ELSET may share a name only when the node set holds exactly the nodes of the '// &
            'elements)')
        exit
      end do
    end do
    d%sets = pack(d%sets(1:d%n_sets), .not. drop)
    d%n_sets = size(d%sets)
  end subroutine resolve_twins

  !> True when node set `sn` (ids only) holds exactly the nodes of the elements of element set
  !! `se` (ids only, solid or line elements). `map` finds an element: map(1, id) its block
  !! (blocks, then line-element blocks after them), map(2, id) its place; 0: none.
  logical function same_nodes(d, sn, se, map, elo) result(same)
    type(deck_t), intent(in) :: d
    type(set_in_t), intent(in) :: sn, se
    integer, intent(in) :: elo
    integer, intent(in) :: map(:, elo:)
    logical, allocatable :: in_n(:), in_e(:)
    integer :: lo, hi, j, k, e, id
    same = .false.
    if (size(sn%refs) > 0 .or. size(se%refs) > 0 .or. len_trim(sn%patch) > 0) return
    if (size(sn%ids) == 0 .or. size(se%ids) == 0) return
    lo = minval(sn%ids)
    hi = maxval(sn%ids)
    if (int(hi, i8) - lo > 50000000_i8) return
    allocate(in_n(lo:hi), in_e(lo:hi))
    in_n = .false.
    in_e = .false.
    in_n(sn%ids) = .true.
    do j = 1, size(se%ids)
      id = se%ids(j)
      if (id < elo .or. id > ubound(map, 2)) return
      k = map(1, id)
      e = map(2, id)
      if (k == 0) then
        return
      else if (k <= d%n_blocks) then
        if (any(d%blocks(k)%conn(:, e) < lo .or. d%blocks(k)%conn(:, e) > hi)) return
        in_e(d%blocks(k)%conn(:, e)) = .true.
      else
        k = k - d%n_blocks
        if (any(d%edges(k)%conn(:, e) < lo .or. d%edges(k)%conn(:, e) > hi)) return
        in_e(d%edges(k)%conn(:, e)) = .true.
      end if
    end do
    same = all(in_n .eqv. in_e)
  end function same_nodes

  !> Widens lo..hi to the element ids of `blocks`.
  subroutine id_range(blocks, lo, hi)
    type(element_block_in_t), intent(in) :: blocks(:)
    integer, intent(inout) :: lo, hi
    integer :: k
    do k = 1, size(blocks)
      if (size(blocks(k)%ids) == 0) cycle
      lo = min(lo, minval(blocks(k)%ids))
      hi = max(hi, maxval(blocks(k)%ids))
    end do
  end subroutine id_range

  !> The element map of `same_nodes` over the ids elo..ehi of solid and line elements; empty
  !! (ehi < elo) when the ids spread over more than 5e7.
  subroutine element_map(d, map, elo)
    type(deck_t), intent(in) :: d
    integer, allocatable, intent(out) :: map(:,:)
    integer, intent(out) :: elo
    integer :: k, e, ehi
    elo = huge(1)
    ehi = -huge(1)
    call id_range(d%blocks(1:d%n_blocks), elo, ehi)
    call id_range(d%edges(1:d%n_edges), elo, ehi)
    if (ehi < elo .or. int(ehi, i8) - elo > 50000000_i8) then
      elo = 1
      allocate(map(2, 1:0))
      return
    end if
    allocate(map(2, elo:ehi))
    map = 0
    do k = 1, d%n_blocks
      do e = 1, size(d%blocks(k)%ids)
        map(:, d%blocks(k)%ids(e)) = [k, e]
      end do
    end do
    do k = 1, d%n_edges
      do e = 1, size(d%edges(k)%ids)
        map(:, d%edges(k)%ids(e)) = [d%n_blocks + k, e]
      end do
    end do
  end subroutine element_map

  !> The analysis implied by CPE*/CPS* element names: one for all of them, and the same as
  !! *ANALYSIS, TYPE= when that is given; without it, the names set the analysis.
  subroutine resolve_analysis(d)
    type(deck_t), intent(inout) :: d
    integer :: k, first
    first = 0
    do k = 1, d%n_blocks
      associate (b => d%blocks(k))
        if (b%analysis == 0) cycle
        if (len_trim(d%analysis_where) > 0 .and. b%analysis /= d%analysis) then
          call input_error(b%analysis_where, '*ELEMENT: TYPE='//trim(b%type_name)// &
              ' implies '//analysis_text(b%analysis)//', but *ANALYSIS at '// &
              trim(d%analysis_where)//' gives '//analysis_text(d%analysis)// &
              ' (expected element names and *ANALYSIS, TYPE= that agree)')
          return
        end if
        if (first == 0) then
          first = k
        else if (b%analysis /= d%blocks(first)%analysis) then
          call input_error(b%analysis_where, '*ELEMENT: TYPE='//trim(b%type_name)// &
              ' implies '//analysis_text(b%analysis)//', but TYPE='// &
              trim(d%blocks(first)%type_name)//' at '//trim(d%blocks(first)%analysis_where)// &
              ' implies '//analysis_text(d%blocks(first)%analysis)// &
              ' (expected one analysis for the whole model)')
          return
        end if
      end associate
    end do
    if (first > 0) d%analysis = d%blocks(first)%analysis
  end subroutine resolve_analysis

  pure function analysis_text(a) result(r)
    integer, intent(in) :: a
    character(len=:), allocatable :: r
    r = trim(merge('plane strain', 'plane stress', a == ANALYSIS_PLANE_STRAIN))
    if (a == ANALYSIS_3D) r = '3D'
  end function analysis_text

  !> The thickness of the sections: one value for the model, equal to *ANALYSIS, THICKNESS=
  !! when that is given (ictus records one thickness; results are per unit thickness).
  subroutine resolve_thickness(d)
    type(deck_t), intent(inout) :: d
    integer :: k, first
    first = 0
    do k = 1, d%n_sections
      if (d%sections(k)%thickness <= 0.0_dp) cycle
      if (first == 0) then
        first = k
        if (len_trim(d%thickness_where) > 0 .and. d%sections(k)%thickness /= d%thickness) &
            call input_error(d%sections(k)%where, '*SOLID SECTION: thickness '// &
            str(d%sections(k)%thickness)//' differs from THICKNESS='//str(d%thickness)// &
            ' of *ANALYSIS at '//trim(d%thickness_where)//' (ictus takes one thickness)')
        d%thickness = d%sections(k)%thickness
      else if (d%sections(k)%thickness /= d%sections(first)%thickness) then
        call input_error(d%sections(k)%where, '*SOLID SECTION: thickness '// &
            str(d%sections(k)%thickness)//' differs from '//str(d%sections(first)%thickness)// &
            ' at '//trim(d%sections(first)%where)//' (ictus takes one thickness for the model)')
      end if
    end do
  end subroutine resolve_thickness

  !> Line elements become node sets: the ELSET= of their cards, and each *ELSET whose members
  !! are line elements. An element set that mixes line and solid elements is an error.
  subroutine resolve_edges(d)
    type(deck_t), intent(inout) :: d
    integer :: k, j, n_edge, n_solid
    integer, allocatable :: nodes(:)
    if (d%n_edges == 0) return
    do k = 1, d%n_sets
      associate (s => d%sets(k))
        if (s%kind /= SET_ELEMENT) cycle
        allocate(nodes(0))
        n_edge = 0
        n_solid = 0
        do j = 1, size(s%ids)
          call edge_nodes(d, s%ids(j), nodes, n_edge, n_solid)
        end do
        do j = 1, size(s%refs)
          if (edge_block_named(d, s%refs(j))) n_edge = n_edge + 1
        end do
        if (n_edge > 0 .and. n_solid > 0) then
          call input_error(s%where, '*ELSET: set '//trim(s%name)//' mixes boundary '// &
              'elements (T3D2, T3D3; in 3D CPS3..M3D9: boundary nodes) and solid elements '// &
              '(expected one kind per set)')
        else if (n_edge > 0) then
          s%kind = SET_NODE
          s%ids = nodes
        end if
        deallocate(nodes)
      end associate
    end do
    do k = 1, d%n_edges
      if (len_trim(d%edges(k)%elset) == 0) cycle
      call add_node_set(d, d%edges(k)%elset, pack(d%edges(k)%conn, .true.), d%edges(k)%where)
    end do
  end subroutine resolve_edges

  !> Adds the nodes of line element `id` to `nodes` (counted in n_edge), or counts a solid
  !! element (n_solid).
  subroutine edge_nodes(d, id, nodes, n_edge, n_solid)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: id
    integer, allocatable, intent(inout) :: nodes(:)
    integer, intent(inout) :: n_edge, n_solid
    integer :: k, e
    do k = 1, d%n_edges
      do e = 1, size(d%edges(k)%ids)
        if (d%edges(k)%ids(e) == id) then
          nodes = [nodes, d%edges(k)%conn(:, e)]
          n_edge = n_edge + 1
          return
        end if
      end do
    end do
    n_solid = n_solid + 1
  end subroutine edge_nodes

  logical function edge_block_named(d, name)
    type(deck_t), intent(in) :: d
    character(len=*), intent(in) :: name
    integer :: k
    edge_block_named = .false.
    do k = 1, d%n_edges
      if (d%edges(k)%elset == name) edge_block_named = .true.
    end do
  end function edge_block_named

  !> Adds `ids` to node set `name` (created when new; an element set of that name is an error).
  subroutine add_node_set(d, name, ids, where)
    type(deck_t), intent(inout) :: d
    character(len=*), intent(in) :: name, where
    integer, intent(in) :: ids(:)
    type(set_in_t), allocatable :: tmp(:)
    integer :: k
    do k = 1, d%n_sets
      if (d%sets(k)%name /= name) cycle
      if (d%sets(k)%kind == SET_NODE) then
        d%sets(k)%ids = [d%sets(k)%ids, ids]
      else
        call input_error(where, '*ELEMENT: ELSET='//trim(name)//' of line elements (a set of '// &
            'boundary nodes) is also an element set (first defined at '// &
            trim(d%sets(k)%where)//')')
      end if
      return
    end do
    allocate(tmp(d%n_sets + 1))
    tmp(1:d%n_sets) = d%sets(1:d%n_sets)
    call move_alloc(tmp, d%sets)
    d%n_sets = d%n_sets + 1
    d%sets(d%n_sets)%name = name
    d%sets(d%n_sets)%kind = SET_NODE
    d%sets(d%n_sets)%where = where
    d%sets(d%n_sets)%ids = ids
    allocate(d%sets(d%n_sets)%refs(0), d%sets(d%n_sets)%ref_where(0))
  end subroutine add_node_set

  !> Each element gets the material of the *SOLID SECTION whose ELSET holds it; one that also
  !! has MATERIAL= on its *ELEMENT, or is in two sections, is an error. Blocks are then split
  !! into runs of elements of one material.
  subroutine resolve_sections(d)
    type(deck_t), intent(inout) :: d
    type(element_block_in_t), allocatable :: out(:)
    type(str_list_t), allocatable :: mat(:)
    type(int_list_t), allocatable :: from(:)
    integer :: ib, is, e, nout, k0
    allocate(mat(d%n_blocks), from(d%n_blocks))
    do ib = 1, d%n_blocks
      allocate(mat(ib)%s(size(d%blocks(ib)%ids)), from(ib)%i(size(d%blocks(ib)%ids)))
      mat(ib)%s = d%blocks(ib)%material
      from(ib)%i = 0
    end do
    do is = 1, d%n_sections
      call mark_section(d, is, mat, from)
      if (any([(any(from(ib)%i < 0), ib = 1, d%n_blocks)])) return
    end do
    allocate(out(0))
    nout = 0
    do ib = 1, d%n_blocks
      associate (b => d%blocks(ib))
        k0 = 1
        do e = 2, size(b%ids) + 1
          if (e <= size(b%ids)) then
            if (mat(ib)%s(e) == mat(ib)%s(k0)) cycle
          end if
          out = [out, b]
          nout = nout + 1
          out(nout)%material = mat(ib)%s(k0)
          out(nout)%ids = b%ids(k0:e - 1)
          out(nout)%conn = b%conn(:, k0:e - 1)
          out(nout)%line = b%line(k0:e - 1)
          k0 = e
        end do
      end associate
    end do
    call move_alloc(out, d%blocks)
    d%n_blocks = nout
  end subroutine resolve_sections

  !> Gives the elements of section `is` its material (mat, from = is); a second material is
  !! reported once and marked from = -1.
  subroutine mark_section(d, is, mat, from)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: is
    type(str_list_t), intent(inout) :: mat(:)
    type(int_list_t), intent(inout) :: from(:)
    logical, allocatable :: member(:)
    integer :: ib, e, lo, hi
    logical :: dense
    lo = huge(1)
    hi = -huge(1)
    call id_range(d%blocks(1:d%n_blocks), lo, hi)
    if (hi < lo) return
    dense = int(hi, i8) - lo < 50000000_i8
    if (dense) then
      allocate(member(lo:hi))
      member = .false.
      call mark_ids(d, d%sections(is)%elset, member, lo, hi, 0)
    end if
    do ib = 1, d%n_blocks
      associate (b => d%blocks(ib))
        do e = 1, size(b%ids)
          if (dense) then
            if (.not. (member(b%ids(e)) .or. b%elset == d%sections(is)%elset)) cycle
          else
            if (.not. in_elset(d, d%sections(is)%elset, b, e, 0)) cycle
          end if
          if (len_trim(mat(ib)%s(e)) > 0) then
            call two_materials(d, b, e, mat(ib)%s(e), from(ib)%i(e), is)
            from(ib)%i(e) = -1
            return
          end if
          mat(ib)%s(e) = d%sections(is)%material
          from(ib)%i(e) = is
        end do
      end associate
    end do
  end subroutine mark_section

  !> Marks in member(lo:hi) the element ids of the *ELSETs named `name` and their member sets
  !! (the blocks with ELSET=name are tested by the caller).
  recursive subroutine mark_ids(d, name, member, lo, hi, depth)
    type(deck_t), intent(in) :: d
    character(len=*), intent(in) :: name
    integer, intent(in) :: lo, hi, depth
    logical, intent(inout) :: member(lo:hi)
    integer :: k, j, ib
    if (depth > max_depth) return
    do ib = 1, d%n_blocks
      if (d%blocks(ib)%elset == name .and. depth > 0) member(d%blocks(ib)%ids) = .true.
    end do
    do k = 1, d%n_sets
      if (d%sets(k)%name /= name .or. d%sets(k)%kind /= SET_ELEMENT) cycle
      do j = 1, size(d%sets(k)%ids)
        if (d%sets(k)%ids(j) >= lo .and. d%sets(k)%ids(j) <= hi) &
            member(d%sets(k)%ids(j)) = .true.
      end do
      do j = 1, size(d%sets(k)%refs)
        call mark_ids(d, d%sets(k)%refs(j), member, lo, hi, depth + 1)
      end do
    end do
  end subroutine mark_ids

  !> Reports an element that gets a second material.
  subroutine two_materials(d, b, e, first, from, is)
    type(deck_t), intent(in) :: d
    type(element_block_in_t), intent(in) :: b
    integer, intent(in) :: e, from, is
    character(len=*), intent(in) :: first
    character(len=:), allocatable :: where_first
    if (from == 0) then
      where_first = 'MATERIAL= on *ELEMENT at '//trim(b%where)
    else
      where_first = '*SOLID SECTION at '//trim(d%sections(from)%where)
    end if
    call input_error(trim(b%file)//':'//str(b%line(e)), '*ELEMENT: element '//str(b%ids(e))// &
        ' gets two materials: '//trim(first)//' from '//where_first//' and '// &
        trim(d%sections(is)%material)//' from *SOLID SECTION at '//trim(d%sections(is)%where)// &
        ' (expected one material per element)')
  end subroutine two_materials

  !> True when element e of block b belongs to element set `name` (ELSET= of its card, or an
  !! *ELSET listing its id or a set that holds it).
  recursive logical function in_elset(d, name, b, e, depth) result(yes)
    type(deck_t), intent(in) :: d
    character(len=*), intent(in) :: name
    type(element_block_in_t), intent(in) :: b
    integer, intent(in) :: e, depth
    integer :: k, j
    yes = b%elset == name
    if (yes .or. depth > max_depth) return
    do k = 1, d%n_sets
      if (d%sets(k)%name /= name .or. d%sets(k)%kind /= SET_ELEMENT) cycle
      yes = any(d%sets(k)%ids == b%ids(e))
      do j = 1, size(d%sets(k)%refs)
        if (.not. yes) yes = in_elset(d, d%sets(k)%refs(j), b, e, depth + 1)
      end do
      return
    end do
  end function in_elset

  !> Elements without a material: one message per *ELEMENT card (its first such element).
  subroutine check_unassigned(d)
    type(deck_t), intent(in) :: d
    integer :: ib
    do ib = 1, d%n_blocks
      associate (b => d%blocks(ib))
        if (len_trim(b%material) > 0) cycle
        call input_error(trim(b%file)//':'//str(b%line(1)), '*ELEMENT: element '// &
            str(b%ids(1))//' has no material (expected MATERIAL= on its *ELEMENT card, or '// &
            'a *SOLID SECTION, ELSET=, MATERIAL= whose element set holds it)')
      end associate
    end do
  end subroutine check_unassigned

end module ictus_io_deck_interop
