!> Reads an input deck (doc/user-guide.md) into a `deck_t`, reporting every problem found.
!!
!! How it works:
!! 1. `load_deck` (ictus_io_deck_lexer) turns the file and its *INCLUDEs into logical lines.
!! 2. `read_deck` walks the keyword lines; each card with its data lines becomes a `card_t`
!!    (ictus_io_deck_card) handed by `read_card` to one small routine `read_<card>`, which
!!    checks the parameters, converts the data and appends typed records to the deck. A card
!!    with a broken keyword line is skipped; a card whose data has a bad line stops at that
!!    line (no cascades). The readers are grouped by what they feed:
!!    * ictus_io_deck_model: *HEADING, *ANALYSIS, *NODE, *ELEMENT, *NSET, *ELSET, *SURFACE;
!!    * ictus_io_deck_patch: *PATCH, *KNOTS, *CONTROL POINTS, *ELEVATE, *REFINE;
!!    * ictus_io_deck_material: *MATERIAL, *ELASTIC, *DENSITY, *MASS, *DAMPING;
!!    * ictus_io_deck_conditions: *BOUNDARY, *INITIAL CONDITIONS;
!!    * ictus_io_deck_loads: *AMPLITUDE, *CLOAD, *DLOAD (in the model part or the step);
!!    * ictus_io_deck_contact: *CONTACT PAIR, *RIGID WALL;
!!    * ictus_io_deck_step: *STEP, *DYNAMIC, *OUTPUT, *RESTART, *END STEP;
!!    * ictus_io_deck_interop: *SOLID SECTION, and the Abaqus cards refused by name.
!! 3. `resolve_interop` (ictus_io_deck_interop) settles the analysis of Abaqus element names,
!!    line elements as node sets and the materials of *SOLID SECTION; then
!!    `check_deck` (ictus_io_deck_checks) resolves names and ids across the whole deck (sets,
!!    surfaces, materials, nodes used before or after their definition).
!! Every problem goes to `input_error("file:line", "*CARD: what was expected")`; the caller
!! checks `error_count() > 0`. Nothing here stops the program.
module ictus_io_deck_reader
  use ictus_core_errors, only: input_error, error_count
  use ictus_core_strings, only: str
  use ictus_core_ticker, only: ticker_start
  use ictus_core_strings, only: upper
  use ictus_io_deck_lexer, only: keyword_t, load_deck, line_where, parse_keyword, shown, &
      deck_source_t, token_t, split_values
  use ictus_io_deck_types, only: deck_t
  use ictus_io_deck_checks, only: check_deck, SKIP_MATERIALS, SKIP_NODES, SKIP_ELEMENTS, &
      SKIP_SETS, SKIP_PATCHES, SKIP_SURFACES
  use ictus_io_deck_card, only: card_t, reader_t
  use ictus_io_deck_model, only: read_heading, read_analysis, read_node, read_element, &
      read_set, read_surface
  use ictus_io_deck_patch, only: read_patch, read_knots, read_control_points, read_patch_op
  use ictus_io_deck_material, only: read_material, read_elastic, read_density, read_mass, &
      read_damping, read_hyperelastic, read_plastic
  use ictus_io_deck_conditions, only: read_boundary, read_initial_conditions
  use ictus_io_deck_loads, only: read_amplitude, read_cload, read_dload
  use ictus_io_deck_contact, only: read_contact_pair, read_rigid_wall, read_tie, &
      read_surface_interaction, read_friction
  use ictus_io_deck_interop, only: read_solid_section, refused_card, resolve_interop, &
      resolve_twins
  use ictus_io_deck_step, only: read_step, read_dynamic, read_output, read_restart, &
      read_end_step
  implicit none
  private
  public :: read_deck

contains

  !> Reads the deck `path` (and its includes) into `deck`. Reports every problem with
  !! `input_error`; the caller checks `error_count()`. Never stops.
  subroutine read_deck(path, deck)
    character(len=*), intent(in) :: path
    type(deck_t), intent(out) :: deck
    type(reader_t) :: rd
    type(card_t) :: card
    integer :: i, j, n0
    logical :: ok

    call init_deck(path, deck)
    ! one ticker for the whole phase: lines every 10 s across the files and the cards
    call ticker_start(rd%tk, 'deck reading', stride=1000)
    call load_deck(path, rd%src, rd%tk)
    if (.not. rd%src%ok) return
    if (rd%src%n_lines == 0) then
      call input_error(path//':1', 'the deck is empty (expected model cards and a *STEP)')
      return
    end if
    rd%tk%name = 'deck reading, cards'
    deck%ndm = deck_dimension(rd%src)
    if (deck%ndm /= 2) then
      deallocate(deck%node_x)
      allocate(deck%node_x(deck%ndm, 0))
    end if
    i = 1
    if (.not. rd%src%lines(1)%is_keyword) then
      call input_error(line_where(rd%src, 1), 'data line "'//shown(rd%src%lines(1)%text)// &
          '" before the first card (expected a keyword line *NAME)')
      do while (i <= rd%src%n_lines)
        if (rd%src%lines(i)%is_keyword) exit
        i = i + 1
      end do
    end if
    do while (i <= rd%src%n_lines)
      j = i + 1
      do while (j <= rd%src%n_lines)
        if (rd%src%lines(j)%is_keyword) exit
        j = j + 1
      end do
      call rd%tk%tick(i, rd%src%n_lines)
      card%where = line_where(rd%src, i)
      card%first = i + 1
      card%last = j - 1
      card%bad = .false.
      n0 = error_count()
      call parse_keyword(rd%src%lines(i)%text, trim(card%where), card%kw, ok)
      if (ok) then
        card%label = '*'//card%kw%name
        call read_card(card, rd, deck)
      end if
      if (error_count() > n0) call note_broken(card%kw, rd)
      i = j
    end do
    call finish_deck(rd, deck)
  end subroutine read_deck

  !> The dimension of the deck: 3 when a keyword line *ANALYSIS has the parameter TYPE=3D,
  !! else 2. Looked for before the cards are read, so that every card is read against it
  !! whatever the order of the cards (the line itself is read by read_analysis, which
  !! reports what is wrong with it).
  integer function deck_dimension(src) result(ndm)
    type(deck_source_t), intent(in) :: src
    type(token_t), allocatable :: fields(:)
    character(len=:), allocatable :: t
    integer :: i, k, n
    ndm = 2
    do i = 1, src%n_lines
      if (.not. src%lines(i)%is_keyword) cycle
      ! the fields without blanks: "*ANALYSIS", "TYPE=3D", ...
      t = ''
      do k = 1, len(src%lines(i)%text)
        if (src%lines(i)%text(k:k) /= ' ' .and. iachar(src%lines(i)%text(k:k)) /= 9) &
            t = t//src%lines(i)%text(k:k)
      end do
      call split_values(upper(t), fields, n)
      if (n < 2) cycle
      if (fields(1)%s /= '*ANALYSIS') cycle
      do k = 2, n
        if (fields(k)%s == 'TYPE=3D') ndm = 3
      end do
    end do
  end function deck_dimension

  !> Remembers which kind of definition a card with errors was (to avoid follow-up errors).
  subroutine note_broken(kw, rd)
    type(keyword_t), intent(in) :: kw
    type(reader_t), intent(inout) :: rd
    if (.not. allocated(kw%name)) then
      rd%broken = ior(rd%broken, SKIP_SETS)
      return
    end if
    select case (kw%name)
    case ('MATERIAL', 'ELASTIC', 'DENSITY', 'HYPERELASTIC', 'PLASTIC', 'SOLID SECTION')
      rd%broken = ior(rd%broken, SKIP_MATERIALS)
    case ('NODE')
      rd%broken = ior(rd%broken, ior(SKIP_NODES, SKIP_SETS))
    case ('ELEMENT')
      rd%broken = ior(rd%broken, ior(SKIP_ELEMENTS, SKIP_SETS))
    case ('NSET', 'ELSET')
      rd%broken = ior(rd%broken, SKIP_SETS)
    case ('PATCH', 'KNOTS', 'CONTROL POINTS', 'ELEVATE', 'REFINE')
      rd%broken = ior(rd%broken, ior(SKIP_PATCHES, SKIP_SETS))
    case ('SURFACE')
      rd%broken = ior(rd%broken, SKIP_SURFACES)
    case default
      if (.not. is_known_card(kw%name)) rd%broken = ior(rd%broken, 63)
    end select
  end subroutine note_broken

  !> Sets `deck` to an empty deck with every array allocated (size 0).
  subroutine init_deck(path, deck)
    character(len=*), intent(in) :: path
    type(deck_t), intent(inout) :: deck
    deck%path = path
    deck%title = ''
    allocate(deck%materials(0), deck%node_ids(0), deck%node_x(2, 0), deck%node_where(0), &
        deck%blocks(0), deck%sets(0), deck%surfaces(0), deck%boundaries(0), &
        deck%velocities(0), deck%amplitudes(0), deck%cloads(0), deck%dloads(0), &
        deck%masses(0), deck%dampings(0), deck%patches(0), deck%patch_ops(0), &
        deck%pairs(0), deck%walls(0), deck%edges(0), deck%sections(0), deck%interactions(0))
  end subroutine init_deck

  !> Closes the step, trims the arrays to their counts and runs the whole-deck checks.
  subroutine finish_deck(rd, deck)
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: deck
    character(len=:), allocatable :: where_end
    where_end = rd%src%files(1)%s//':'//str(max(1, rd%src%main_last_line))
    if (rd%in_step .and. .not. rd%skip_step) then
      call input_error(deck%step%where, '*STEP: missing *END STEP')
      if (.not. rd%has_dynamic) call input_error(deck%step%where, &
          '*STEP: no *DYNAMIC, EXPLICIT card in the step (expected dt, t_end)')
    end if
    if (.not. deck%has_step) call input_error(where_end, &
        'no *STEP in the deck (expected *STEP, *DYNAMIC, EXPLICIT ... *END STEP)')
    deck%node_ids = deck%node_ids(1:deck%n_nodes)
    deck%node_x = deck%node_x(:, 1:deck%n_nodes)
    deck%node_where = deck%node_where(1:deck%n_nodes)
    deck%materials = deck%materials(1:deck%n_materials)
    deck%blocks = deck%blocks(1:deck%n_blocks)
    deck%sets = deck%sets(1:deck%n_sets)
    deck%surfaces = deck%surfaces(1:deck%n_surfaces)
    deck%boundaries = deck%boundaries(1:deck%n_boundaries)
    deck%velocities = deck%velocities(1:deck%n_velocities)
    deck%amplitudes = deck%amplitudes(1:deck%n_amplitudes)
    deck%cloads = deck%cloads(1:deck%n_cloads)
    deck%dloads = deck%dloads(1:deck%n_dloads)
    deck%masses = deck%masses(1:deck%n_masses)
    deck%dampings = deck%dampings(1:deck%n_dampings)
    deck%patches = deck%patches(1:deck%n_patches)
    deck%patch_ops = deck%patch_ops(1:deck%n_patch_ops)
    deck%pairs = deck%pairs(1:deck%n_pairs)
    deck%walls = deck%walls(1:deck%n_walls)
    deck%interactions = deck%interactions(1:deck%n_interactions)
    deck%edges = deck%edges(1:deck%n_edges)
    if (iand(rd%broken, SKIP_ELEMENTS) == 0) then
      call resolve_interop(deck, iand(rd%broken, SKIP_MATERIALS) /= 0)
    else
      call resolve_twins(deck, .false.)
    end if
    call check_deck(deck, rd%broken)
  end subroutine finish_deck

  !> Dispatches one card to its reader, after the context checks (material and patch
  !! sub-cards, model cards versus step cards).
  subroutine read_card(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    logical :: step_card

    select case (c%kw%name)
    case ('ELASTIC', 'DENSITY', 'HYPERELASTIC', 'PLASTIC')
    case default
      rd%material = 0
    end select
    if (c%kw%name /= 'KNOTS' .and. c%kw%name /= 'CONTROL POINTS') rd%patch = 0
    if (c%kw%name /= 'FRICTION') rd%interaction = 0
    select case (c%kw%name)
    case ('DYNAMIC', 'OUTPUT', 'RESTART', 'END STEP')
      step_card = .true.
    case default
      step_card = .false.
    end select
    if (rd%skip_step) then
      if (c%kw%name == 'END STEP') then
        rd%skip_step = .false.
        rd%in_step = .false.
      end if
      return
    end if
    if (step_card .and. .not. rd%in_step) then
      call input_error(c%where, c%label//': outside a step (expected it between *STEP and '// &
          '*END STEP)')
      return
    end if
    if (rd%in_step .and. .not. step_card .and. is_known_card(c%kw%name) .and. &
        .not. load_card(c%kw%name)) then
      call input_error(c%where, c%label//': model card inside *STEP (expected *DYNAMIC, '// &
          '*OUTPUT, *RESTART, *END STEP or the load cards *AMPLITUDE, *BOUNDARY, *CLOAD, '// &
          '*DLOAD; put model cards before *STEP)')
      return
    end if

    if (d%ndm == 3 .and. len(not_yet_3d(c%kw%name)) > 0) then
      call input_error(c%where, c%label//': not yet in 3D: '//not_yet_3d(c%kw%name))
      return
    end if
    select case (c%kw%name)
    case ('HEADING')
      call read_heading(c, rd, d)
    case ('ANALYSIS')
      call read_analysis(c, rd, d)
    case ('MATERIAL')
      call read_material(c, rd, d)
    case ('ELASTIC')
      call read_elastic(c, rd, d)
    case ('DENSITY')
      call read_density(c, rd, d)
    case ('HYPERELASTIC')
      call read_hyperelastic(c, rd, d)
    case ('PLASTIC')
      call read_plastic(c, rd, d)
    case ('NODE')
      call read_node(c, rd, d)
    case ('ELEMENT')
      call read_element(c, rd, d)
    case ('PATCH')
      call read_patch(c, rd, d)
    case ('KNOTS')
      call read_knots(c, rd, d)
    case ('CONTROL POINTS')
      call read_control_points(c, rd, d)
    case ('ELEVATE', 'REFINE')
      call read_patch_op(c, rd, d)
    case ('NSET', 'ELSET')
      call read_set(c, rd, d)
    case ('SURFACE')
      call read_surface(c, rd, d)
    case ('BOUNDARY')
      call read_boundary(c, rd, d)
    case ('AMPLITUDE')
      call read_amplitude(c, rd, d)
    case ('CLOAD')
      call read_cload(c, rd, d)
    case ('DLOAD')
      call read_dload(c, rd, d)
    case ('INITIAL CONDITIONS')
      call read_initial_conditions(c, rd, d)
    case ('CONTACT PAIR')
      call read_contact_pair(c, rd, d)
    case ('RIGID WALL')
      call read_rigid_wall(c, rd, d)
    case ('TIE')
      call read_tie(c, rd, d)
    case ('SURFACE INTERACTION')
      call read_surface_interaction(c, rd, d)
    case ('FRICTION')
      call read_friction(c, rd, d)
    case ('DAMPING')
      call read_damping(c, rd, d)
    case ('MASS')
      call read_mass(c, rd, d)
    case ('SOLID SECTION')
      call read_solid_section(c, rd, d)
    case ('STEP')
      call read_step(c, rd, d)
    case ('DYNAMIC')
      call read_dynamic(c, rd, d)
    case ('OUTPUT')
      call read_output(c, rd, d)
    case ('RESTART')
      call read_restart(c, rd, d)
    case ('END STEP')
      call read_end_step(c, rd, d)
    case default
      if (len(refused_card(c%kw%name)) > 0) then
        call input_error(c%where, c%label//': an Abaqus card that ictus does not take; '// &
            refused_card(c%kw%name))
      else
        call input_error(c%where, 'unknown card '//shown(c%label)//' (expected one of '// &
            'the cards of doc/user-guide.md, e.g. *NODE, *ELEMENT, *PATCH, *STEP)')
      end if
    end select
  end subroutine read_card

  !> What a card of a 3D deck asks for that ictus does not have in 3D yet ('' for the cards
  !! that 3D takes): contact comes after the hexahedra and the trivariate NURBS patches.
  pure function not_yet_3d(name) result(what)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: what
    select case (name)
    case ('TIE')
      what = 'ties (*TIE) between the faces of hexahedra; 3D contact has *CONTACT PAIR '// &
          '(TWO HALF PASS) and *RIGID WALL'
    case default
      what = ''
    end select
  end function not_yet_3d

  !> True for every card name this reader knows.
  pure logical function is_known_card(name)
    character(len=*), intent(in) :: name
    select case (name)
    case ('HEADING', 'ANALYSIS', 'MATERIAL', 'ELASTIC', 'DENSITY', 'HYPERELASTIC', 'PLASTIC', &
        'NODE', 'ELEMENT', &
        'PATCH', 'KNOTS', 'CONTROL POINTS', 'ELEVATE', 'REFINE', 'NSET', 'ELSET', 'SURFACE', &
        'BOUNDARY', 'INITIAL CONDITIONS', 'CONTACT PAIR', 'RIGID WALL', 'DAMPING', 'MASS', &
        'SOLID SECTION', 'STEP', 'DYNAMIC', 'OUTPUT', 'RESTART', 'END STEP', 'AMPLITUDE', &
        'CLOAD', 'DLOAD', 'SURFACE INTERACTION', 'FRICTION', 'TIE')
      is_known_card = .true.
    case default
      is_known_card = .false.
    end select
  end function is_known_card

  !> True for the cards that may stand in the model part and inside the step (Abaqus puts
  !! loads in the step; with one step both mean the same).
  pure logical function load_card(name)
    character(len=*), intent(in) :: name
    select case (name)
    case ('AMPLITUDE', 'BOUNDARY', 'CLOAD', 'DLOAD')
      load_card = .true.
    case default
      load_card = .false.
    end select
  end function load_card

end module ictus_io_deck_reader
