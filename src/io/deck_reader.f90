!> Reads an input deck (deck-format.md) into a `deck_t`, reporting every problem found.
!!
!! How it works:
!! 1. `load_deck` (ictus_io_deck_lexer) turns the file and its *INCLUDEs into logical lines.
!! 2. `read_deck` walks the keyword lines; each card with its data lines becomes a `card_t`
!!    (ictus_io_deck_card) handed to one small routine `read_<card>`, which checks the
!!    parameters, converts the data and appends typed records to the deck. A card with a
!!    broken keyword line is skipped; a card whose data has a bad line stops at that line
!!    (no cascades).
!! 3. `check_deck` (ictus_io_deck_checks) resolves names and ids across the whole deck (sets,
!!    surfaces, materials, nodes used before or after their definition).
!! Every problem goes to `input_error("file:line", "*CARD: what was expected")`; the caller
!! checks `error_count() > 0`. Nothing here stops the program.
module ictus_io_deck_reader
  use ictus_core_kinds, only: dp, i8, str_len
  use ictus_core_errors, only: input_error, error_count
  use ictus_core_strings, only: upper, str
  use ictus_io_deck_lexer, only: token_t, keyword_t, load_deck, line_where, parse_keyword, &
      split_values, parse_real, parse_int, shown, collapse_blanks
  use ictus_io_deck_types, only: deck_t, material_in_t, element_block_in_t, set_in_t, &
      surface_in_t, boundary_in_t, velocity_in_t, mass_in_t, damping_in_t, patch_in_t, &
      patch_op_in_t, contact_pair_in_t, rigid_wall_in_t, where_len, &
      ANALYSIS_PLANE_STRAIN, ANALYSIS_PLANE_STRESS, ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, etype_nen, &
      etype_name, SET_NODE, SET_ELEMENT, SIDE_NONE, SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, &
      SIDE_ALL, &
      SURF_ELEMENT, SURF_PATCH, MASS_CONSISTENT, MASS_ROW_SUM, MASS_HRZ, MASS_ALPHA, &
      HRZ_FULL, HRZ_GAUSS2, OP_ELEVATE, OP_REFINE, &
      CONTACT_NODE_TO_SEGMENT
  use ictus_io_deck_checks, only: check_deck, SKIP_MATERIALS, SKIP_NODES, SKIP_ELEMENTS, &
      SKIP_SETS, SKIP_PATCHES, SKIP_SURFACES
  use ictus_io_deck_card, only: card_t, reader_t, max_generated, card_error, check_params, &
      get_param, has_param, has_flag, get_name, get_choice, get_ints, get_reals, get_positive, &
      no_data, has_data, one_line, line_reals, stream_reals, count_ok, tok_int, tok_real, &
      tok_name, tok_target, plural
  use ictus_io_deck_grow, only: grow_materials, grow_blocks, grow_sets, grow_surfaces, &
      grow_boundaries, grow_velocities, grow_masses, grow_dampings, grow_patches, &
      grow_patch_ops, grow_pairs, grow_walls
  implicit none
  private
  public :: read_deck

  !> Codes of the choices of TYPE= (ELEMENT, MASS), SIDE= and INTEGRATION=, in list order.
  integer, parameter :: etype_codes(3) = [ETYPE_Q4, ETYPE_Q8, ETYPE_Q9]
  integer, parameter :: side_codes(5) = [SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ALL]
  integer, parameter :: mass_codes(4) = [MASS_CONSISTENT, MASS_ROW_SUM, MASS_HRZ, MASS_ALPHA]
  integer, parameter :: hrz_codes(2) = [HRZ_FULL, HRZ_GAUSS2]

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
    call load_deck(path, rd%src)
    if (.not. rd%src%ok) return
    if (rd%src%n_lines == 0) then
      call input_error(path//':1', 'the deck is empty (expected model cards and a *STEP)')
      return
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

  !> Remembers which kind of definition a card with errors was (to avoid follow-up errors).
  subroutine note_broken(kw, rd)
    type(keyword_t), intent(in) :: kw
    type(reader_t), intent(inout) :: rd
    if (.not. allocated(kw%name)) then
      rd%broken = ior(rd%broken, SKIP_SETS)
      return
    end if
    select case (kw%name)
    case ('MATERIAL', 'ELASTIC', 'DENSITY')
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
        deck%velocities(0), deck%masses(0), deck%dampings(0), deck%patches(0), &
        deck%patch_ops(0), deck%pairs(0), deck%walls(0))
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
    deck%masses = deck%masses(1:deck%n_masses)
    deck%dampings = deck%dampings(1:deck%n_dampings)
    deck%patches = deck%patches(1:deck%n_patches)
    deck%patch_ops = deck%patch_ops(1:deck%n_patch_ops)
    deck%pairs = deck%pairs(1:deck%n_pairs)
    deck%walls = deck%walls(1:deck%n_walls)
    call check_deck(deck, rd%broken)
  end subroutine finish_deck

  !> Dispatches one card to its reader, after the context checks (material and patch
  !! sub-cards, model cards versus step cards).
  subroutine read_card(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    logical :: step_card

    if (c%kw%name /= 'ELASTIC' .and. c%kw%name /= 'DENSITY') rd%material = 0
    if (c%kw%name /= 'KNOTS' .and. c%kw%name /= 'CONTROL POINTS') rd%patch = 0
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
    if (rd%in_step .and. .not. step_card .and. is_known_card(c%kw%name)) then
      call input_error(c%where, c%label//': model card inside *STEP (expected *DYNAMIC, '// &
          '*OUTPUT, *RESTART or *END STEP; put model cards before *STEP)')
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
    case ('INITIAL CONDITIONS')
      call read_initial_conditions(c, rd, d)
    case ('CONTACT PAIR')
      call read_contact_pair(c, rd, d)
    case ('RIGID WALL')
      call read_rigid_wall(c, rd, d)
    case ('DAMPING')
      call read_damping(c, rd, d)
    case ('MASS')
      call read_mass(c, rd, d)
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
      call input_error(c%where, 'unknown card '//shown(c%label)//' (expected one of the '// &
          'cards of deck-format.md, e.g. *NODE, *ELEMENT, *PATCH, *STEP)')
    end select
  end subroutine read_card

  !> True for every card name this reader knows.
  pure logical function is_known_card(name)
    character(len=*), intent(in) :: name
    select case (name)
    case ('HEADING', 'ANALYSIS', 'MATERIAL', 'ELASTIC', 'DENSITY', 'NODE', 'ELEMENT', &
        'PATCH', 'KNOTS', 'CONTROL POINTS', 'ELEVATE', 'REFINE', 'NSET', 'ELSET', 'SURFACE', &
        'BOUNDARY', 'INITIAL CONDITIONS', 'CONTACT PAIR', 'RIGID WALL', 'DAMPING', 'MASS', &
        'STEP', 'DYNAMIC', 'OUTPUT', 'RESTART', 'END STEP')
      is_known_card = .true.
    case default
      is_known_card = .false.
    end select
  end function is_known_card

  ! ------------------------------------------------------------------------------------------
  ! Model cards
  ! ------------------------------------------------------------------------------------------

  !> *HEADING: the data lines, joined with blanks, become the title.
  subroutine read_heading(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    integer :: i
    call check_params(c, '', '')
    do i = c%first, c%last
      if (len(d%title) > 0) d%title = d%title//' '
      d%title = d%title//rd%src%lines(i)%text
    end do
  end subroutine read_heading

  !> *ANALYSIS, TYPE=PLANE STRAIN|PLANE STRESS, THICKNESS=t.
  subroutine read_analysis(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    integer :: kind
    real(dp) :: t(1)

    call check_params(c, 'TYPE|THICKNESS', '')
    if (rd%has_analysis) call card_error(c, 'given twice (expected one *ANALYSIS card)')
    rd%has_analysis = .true.
    call get_choice(c, 'TYPE', 'PLANE STRAIN|PLANE STRESS', kind)
    if (kind == 1) d%analysis = ANALYSIS_PLANE_STRAIN
    if (kind == 2) d%analysis = ANALYSIS_PLANE_STRESS
    if (get_reals(c, 'THICKNESS', 1, 'a number t > 0', t)) then
      if (t(1) > 0.0_dp) then
        d%thickness = t(1)
      else
        call card_error(c, 'THICKNESS='//str(t(1))//' must be > 0')
      end if
    end if
    call no_data(c, rd)
  end subroutine read_analysis

  !> *MATERIAL, NAME=name: opens a material for the *ELASTIC and *DENSITY that follow.
  subroutine read_material(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=str_len) :: name
    integer :: k

    rd%material = -1
    call check_params(c, 'NAME', '')
    call get_name(c, 'NAME', .true., name)
    call no_data(c, rd)
    if (c%bad) return
    do k = 1, d%n_materials
      if (d%materials(k)%name == name) then
        call card_error(c, 'duplicate material name '//trim(name)//' (first defined at '// &
            trim(d%materials(k)%where)//')')
        return
      end if
    end do
    call grow_materials(d%materials, d%n_materials + 1)
    d%n_materials = d%n_materials + 1
    d%materials(d%n_materials)%name = name
    d%materials(d%n_materials)%where = c%where
    rd%material = d%n_materials
  end subroutine read_material

  !> *ELASTIC: one data line "E, nu" for the current material.
  subroutine read_elastic(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*ELASTIC: expected 2 numbers (E, nu)'
    real(dp) :: v(2)
    integer :: kind, i

    call check_params(c, 'TYPE', '')
    call get_choice(c, 'TYPE', 'ISOTROPIC', kind)
    if (.not. material_context(c, rd)) return
    associate (m => d%materials(rd%material))
      if (m%has_elastic) then
        call card_error(c, 'second *ELASTIC for material '//trim(m%name))
        return
      end if
      m%has_elastic = .true.
      if (c%bad) return
      if (.not. one_line(c, rd, expect, i)) return
      if (.not. line_reals(rd, i, 2, expect, v)) return
      m%e = v(1)
      m%nu = v(2)
      if (v(1) <= 0.0_dp) call input_error(line_where(rd%src, i), '*ELASTIC: Young''s '// &
          'modulus E must be > 0, found '//str(v(1)))
      if (v(2) <= -1.0_dp .or. v(2) >= 0.5_dp) call input_error(line_where(rd%src, i), &
          '*ELASTIC: Poisson''s ratio nu must lie in (-1, 0.5), found '//str(v(2)))
    end associate
  end subroutine read_elastic

  !> *DENSITY: one data line "rho" for the current material.
  subroutine read_density(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*DENSITY: expected 1 number (rho)'
    real(dp) :: v(1)
    integer :: i

    call check_params(c, '', '')
    if (.not. material_context(c, rd)) return
    associate (m => d%materials(rd%material))
      if (m%has_density) then
        call card_error(c, 'second *DENSITY for material '//trim(m%name))
        return
      end if
      m%has_density = .true.
      if (c%bad) return
      if (.not. one_line(c, rd, expect, i)) return
      if (.not. line_reals(rd, i, 1, expect, v)) return
      m%rho = v(1)
      if (v(1) <= 0.0_dp) call input_error(line_where(rd%src, i), &
          '*DENSITY: density rho must be > 0, found '//str(v(1)))
    end associate
  end subroutine read_density

  !> True when a material card may be read now (after *MATERIAL); reports it otherwise.
  logical function material_context(c, rd) result(ok)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    ok = rd%material > 0
    if (rd%material == 0) call card_error(c, 'no preceding *MATERIAL card (expected '// &
        '*MATERIAL, NAME=name before it)')
  end function material_context

  !> *NODE [, NSET=name]: data lines "id, x, y".
  subroutine read_node(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*NODE: expected "id, x, y"'
    character(len=str_len) :: nset
    type(token_t), allocatable :: toks(:)
    integer :: i, n, id, n0
    real(dp) :: x, y

    call check_params(c, 'NSET', '')
    call get_name(c, 'NSET', .false., nset)
    if (c%bad) return
    if (.not. has_data(c, expect)) return
    call reserve_nodes(rd, d, d%n_nodes + c%last - c%first + 1)
    n0 = d%n_nodes
    do i = c%first, c%last
      call split_values(rd%src%lines(i)%text, toks, n)
      if (n < 3) then
        call input_error(line_where(rd%src, i), expect//', found '//str(n)//' value'// &
            plural(n)//' (a node needs 2 coordinates)')
        exit
      end if
      if (.not. count_ok(n, 3, 3, expect, line_where(rd%src, i))) exit
      if (.not. tok_int(toks, 1, expect, line_where(rd%src, i), id)) exit
      if (.not. tok_real(toks, 2, expect, line_where(rd%src, i), x)) exit
      if (.not. tok_real(toks, 3, expect, line_where(rd%src, i), y)) exit
      if (id <= 0) then
        call input_error(line_where(rd%src, i), '*NODE: node id must be > 0, found '//str(id))
        exit
      end if
      d%n_nodes = d%n_nodes + 1
      d%node_ids(d%n_nodes) = id
      d%node_x(:, d%n_nodes) = [x, y]
      d%node_where(d%n_nodes) = line_where(rd%src, i)
    end do
    if (len_trim(nset) > 0) call add_to_set(d, nset, SET_NODE, c%where, &
        d%node_ids(n0 + 1:d%n_nodes))
  end subroutine read_node

  !> Makes the node arrays hold at least `n` nodes.
  subroutine reserve_nodes(rd, d, n)
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    integer, intent(in) :: n
    integer, allocatable :: ids(:)
    real(dp), allocatable :: x(:,:)
    character(len=where_len), allocatable :: w(:)
    integer :: cap
    if (n <= rd%node_cap) return
    cap = max(n, 2*rd%node_cap)
    allocate(ids(cap), x(2, cap), w(cap))
    ids(1:d%n_nodes) = d%node_ids(1:d%n_nodes)
    x(:, 1:d%n_nodes) = d%node_x(:, 1:d%n_nodes)
    w(1:d%n_nodes) = d%node_where(1:d%n_nodes)
    call move_alloc(ids, d%node_ids)
    call move_alloc(x, d%node_x)
    call move_alloc(w, d%node_where)
    rd%node_cap = cap
  end subroutine reserve_nodes

  !> *ELEMENT, TYPE=Q4|Q8|Q9, MATERIAL=name [, ELSET=name] [, GAUSS=2|3]: data lines
  !! "id, n1, ..., nen". Data lines from different files go to separate blocks.
  subroutine read_element(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=:), allocatable :: expect
    type(element_block_in_t) :: b
    type(token_t), allocatable :: toks(:)
    character(len=:), allocatable :: w
    integer :: kind, i, n, k, nel, g(1), file, id, conn(9)
    logical :: ok

    call check_params(c, 'TYPE|ELSET|MATERIAL|GAUSS', '')
    call get_choice(c, 'TYPE', 'Q4|Q8|Q9', kind, required=.true.)
    if (kind > 0) b%etype = etype_codes(kind)
    call get_name(c, 'MATERIAL', .true., b%material)
    call get_name(c, 'ELSET', .false., b%elset)
    if (get_ints(c, 'GAUSS', 1, '2 or 3 points per direction', g)) then
      if (g(1) == 2 .or. g(1) == 3) then
        b%gauss = g(1)
      else
        call card_error(c, 'bad value GAUSS='//str(g(1))//' (expected 2 or 3)')
      end if
    end if
    if (c%bad .or. kind == 0) return
    b%nen = etype_nen(b%etype)
    if (b%gauss == 0) b%gauss = merge(2, 3, b%etype == ETYPE_Q4)
    expect = '*ELEMENT: expected "id, n1, ..., n'//str(b%nen)//'" (TYPE='// &
        etype_name(b%etype)//': '//str(b%nen + 1)//' integers)'
    if (.not. has_data(c, expect)) return
    b%where = c%where
    nel = 0
    file = 0
    allocate(b%ids(c%last - c%first + 1), b%conn(b%nen, c%last - c%first + 1), &
        b%line(c%last - c%first + 1))
    do i = c%first, c%last
      if (rd%src%lines(i)%file /= file .and. nel > 0) call push_block(d, b, nel)
      file = rd%src%lines(i)%file
      b%file = rd%src%files(file)%s
      w = line_where(rd%src, i)
      call split_values(rd%src%lines(i)%text, toks, n)
      if (.not. count_ok(n, b%nen + 1, b%nen + 1, expect, w)) exit
      ok = tok_int(toks, 1, expect, w, id)
      do k = 2, n
        if (ok) ok = tok_int(toks, k, expect, w, conn(k - 1))
      end do
      if (.not. ok) exit
      if (.not. element_ok(id, conn(1:b%nen), w)) cycle
      nel = nel + 1
      b%ids(nel) = id
      b%conn(:, nel) = conn(1:b%nen)
      b%line(nel) = rd%src%lines(i)%line
    end do
    if (nel > 0) call push_block(d, b, nel)
  end subroutine read_element

  !> Checks one element's ids: positive, no node used twice.
  logical function element_ok(id, conn, where) result(ok)
    integer, intent(in) :: id
    integer, intent(in) :: conn(:)
    character(len=*), intent(in) :: where
    integer :: a, b
    ok = .false.
    if (id <= 0) then
      call input_error(where, '*ELEMENT: element id must be > 0, found '//str(id))
      return
    end if
    do a = 1, size(conn)
      if (conn(a) <= 0) then
        call input_error(where, '*ELEMENT: element '//str(id)//': node id must be > 0, '// &
            'found '//str(conn(a))//' in field '//str(a + 1))
        return
      end if
      do b = 1, a - 1
        if (conn(a) == conn(b)) then
          call input_error(where, '*ELEMENT: element '//str(id)//' uses node '// &
              str(conn(a))//' twice (fields '//str(b + 1)//' and '//str(a + 1)//')')
          return
        end if
      end do
    end do
    ok = .true.
  end function element_ok

  !> Appends the first `nel` elements of `b` as a new block; `nel` is reset to 0 so that `b`
  !! takes the elements of the next file.
  subroutine push_block(d, b, nel)
    type(deck_t), intent(inout) :: d
    type(element_block_in_t), intent(inout) :: b
    integer, intent(inout) :: nel
    call grow_blocks(d%blocks, d%n_blocks + 1)
    d%n_blocks = d%n_blocks + 1
    associate (nb => d%blocks(d%n_blocks))
      nb%etype = b%etype
      nb%nen = b%nen
      nb%elset = b%elset
      nb%material = b%material
      nb%gauss = b%gauss
      nb%ids = b%ids(1:nel)
      nb%conn = b%conn(:, 1:nel)
      nb%line = b%line(1:nel)
      nb%file = b%file
      nb%where = b%where
    end associate
    nel = 0
  end subroutine push_block

  ! ------------------------------------------------------------------------------------------
  ! NURBS patch cards
  ! ------------------------------------------------------------------------------------------

  !> *PATCH, NAME=, MATERIAL=, DEGREE=p1,p2, SIZE=n1,n2: opens a patch for *KNOTS and
  !! *CONTROL POINTS.
  subroutine read_patch(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    type(patch_in_t) :: p
    integer :: k

    rd%patch = -1
    call check_params(c, 'NAME|MATERIAL|DEGREE|SIZE', '')
    call get_name(c, 'NAME', .true., p%name)
    call get_name(c, 'MATERIAL', .true., p%material)
    if (get_ints(c, 'DEGREE', 2, 'p1,p2', p%degree, required=.true.)) then
      if (any(p%degree < 1)) call card_error(c, 'DEGREE='//str(p%degree(1))//','// &
          str(p%degree(2))//' must be >= 1 in both directions')
    end if
    if (get_ints(c, 'SIZE', 2, 'n1,n2 control points per direction', p%size, &
        required=.true.)) then
      if (.not. c%bad .and. any(p%size < p%degree + 1)) then
        call card_error(c, 'SIZE='//str(p%size(1))//','//str(p%size(2))// &
            ' must be at least DEGREE+1 in each direction')
      else if (int(max(p%size(1), 1), i8)*int(max(p%size(2), 1), i8) > max_generated) then
        call card_error(c, 'SIZE='//str(p%size(1))//','//str(p%size(2))// &
            ' is too large (at most '//str(max_generated)//' control points)')
      end if
    end if
    call no_data(c, rd)
    do k = 1, d%n_patches
      if (d%patches(k)%name == p%name .and. len_trim(p%name) > 0) then
        call card_error(c, 'duplicate patch name '//trim(p%name)//' (first defined at '// &
            trim(d%patches(k)%where)//')')
      end if
    end do
    if (c%bad) return
    p%where = c%where
    call grow_patches(d%patches, d%n_patches + 1)
    d%n_patches = d%n_patches + 1
    d%patches(d%n_patches) = p
    rd%patch = d%n_patches
  end subroutine read_patch

  !> True when a patch sub-card may be read now; reports it otherwise.
  logical function patch_context(c, rd) result(ok)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    ok = rd%patch > 0
    if (rd%patch == 0) call card_error(c, 'no preceding *PATCH card (expected *PATCH, '// &
        'NAME=..., DEGREE=..., SIZE=... before it)')
  end function patch_context

  !> *KNOTS, DIRECTION=1|2: the knot vector (stream of numbers over any number of lines).
  subroutine read_knots(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    real(dp), allocatable :: u(:)
    integer, allocatable :: tline(:)
    integer :: dir(1), n, p

    call check_params(c, 'DIRECTION', '')
    if (get_ints(c, 'DIRECTION', 1, '1 or 2', dir, required=.true.)) then
      if (dir(1) /= 1 .and. dir(1) /= 2) call card_error(c, 'bad value DIRECTION='// &
          str(dir(1))//' (expected 1 or 2)')
    end if
    if (.not. patch_context(c, rd) .or. c%bad) return
    associate (pa => d%patches(rd%patch))
      if (pa%has_knots(dir(1))) then
        call card_error(c, 'second *KNOTS, DIRECTION='//str(dir(1))//' for patch '// &
            trim(pa%name))
        return
      end if
      pa%has_knots(dir(1)) = .true.
      n = pa%size(dir(1))
      p = pa%degree(dir(1))
      if (.not. stream_reals(c, rd, '*KNOTS: expected the knot vector (numbers)', u, tline)) &
          return
      if (.not. knots_ok(c, rd, u, tline, n, p, dir(1))) return
      if (dir(1) == 1) then
        pa%knots1 = u
      else
        pa%knots2 = u
      end if
    end associate
  end subroutine read_knots

  !> Checks a knot vector: length n+p+1, non-decreasing, open, interior multiplicity <= p.
  logical function knots_ok(c, rd, u, tline, n, p, dir) result(ok)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(in) :: rd
    real(dp), intent(in) :: u(:)
    integer, intent(in) :: tline(:), n, p, dir
    integer :: k, m, mult
    character(len=:), allocatable :: dd

    ok = .false.
    dd = ', DIRECTION='//str(dir)
    if (size(u) /= n + p + 1) then
      call card_error(c, 'knot vector of length '//str(size(u))//dd//': expected n + p + 1 = '// &
          str(n + p + 1)//' knots (SIZE n='//str(n)//', DEGREE p='//str(p)//')')
      return
    end if
    do k = 2, size(u)
      if (u(k) < u(k - 1)) then
        call input_error(line_where(rd%src, tline(k)), '*KNOTS: decreasing knot vector'//dd// &
            ': knot '//str(k)//' = '//str(u(k))//' < knot '//str(k - 1)//' = '//str(u(k - 1))// &
            ' (expected non-decreasing knots)')
        return
      end if
    end do
    m = size(u)
    if (any(u(1:p + 1) /= u(1)) .or. any(u(m - p:m) /= u(m))) then
      call card_error(c, 'knot vector not open'//dd//': the first and the last p + 1 = '// &
          str(p + 1)//' knots must be equal')
      return
    end if
    if (.not. (u(m) > u(1))) then
      call card_error(c, 'knot vector has zero length'//dd//' (first knot = last knot)')
      return
    end if
    mult = 1
    do k = p + 3, m - p - 1
      if (u(k) == u(k - 1)) then
        mult = mult + 1
      else
        mult = 1
      end if
      if (mult > p) then
        call input_error(line_where(rd%src, tline(k)), '*KNOTS: interior knot '// &
            str(u(k))//dd//' repeated more than p = '//str(p)//' times')
        return
      end if
    end do
    ok = .true.
  end function knots_ok

  !> *CONTROL POINTS: n1*n2 records "x, y, w" (stream), direction-1 index fastest; w > 0.
  subroutine read_control_points(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    real(dp), allocatable :: v(:)
    integer, allocatable :: tline(:)
    integer :: ncp, k

    call check_params(c, '', '')
    if (.not. patch_context(c, rd) .or. c%bad) return
    associate (pa => d%patches(rd%patch))
      if (pa%has_cp) then
        call card_error(c, 'second *CONTROL POINTS for patch '//trim(pa%name))
        return
      end if
      pa%has_cp = .true.
      if (.not. stream_reals(c, rd, '*CONTROL POINTS: expected "x, y, w" records (numbers)', &
          v, tline)) return
      ncp = pa%size(1)*pa%size(2)
      if (size(v) /= 3*ncp) then
        call card_error(c, 'patch '//trim(pa%name)//' has SIZE='//str(pa%size(1))//','// &
            str(pa%size(2))//': expected '//str(ncp)//' control points "x, y, w" = '// &
            str(3*ncp)//' numbers, found '//str(size(v))//' numbers')
        return
      end if
      pa%cp = reshape(v, [3, ncp])
      do k = 1, ncp
        if (.not. (pa%cp(3, k) > 0.0_dp)) then
          call input_error(line_where(rd%src, tline(3*k)), '*CONTROL POINTS: weight w of '// &
              'control point '//str(k)//' must be > 0, found '//str(pa%cp(3, k)))
        end if
      end do
    end associate
  end subroutine read_control_points

  !> *ELEVATE, PATCH=, DEGREE=q1,q2 or *REFINE, PATCH=, SUBDIVIDE=k1,k2 (resolved later).
  subroutine read_patch_op(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    type(patch_op_in_t) :: op
    character(len=:), allocatable :: key

    if (c%kw%name == 'ELEVATE') then
      op%kind = OP_ELEVATE
      key = 'DEGREE'
    else
      op%kind = OP_REFINE
      key = 'SUBDIVIDE'
    end if
    call check_params(c, 'PATCH|'//key, '')
    call get_name(c, 'PATCH', .true., op%patch)
    if (get_ints(c, key, 2, 'two integers', op%values, required=.true.)) then
      if (any(op%values < 1)) call card_error(c, key//'='//str(op%values(1))//','// &
          str(op%values(2))//' must be >= 1 in both directions')
    end if
    call no_data(c, rd)
    if (c%bad) return
    op%where = c%where
    call grow_patch_ops(d%patch_ops, d%n_patch_ops + 1)
    d%n_patch_ops = d%n_patch_ops + 1
    d%patch_ops(d%n_patch_ops) = op
  end subroutine read_patch_op

  ! ------------------------------------------------------------------------------------------
  ! Sets and surfaces
  ! ------------------------------------------------------------------------------------------

  !> *NSET, NSET=name (ids / set names, GENERATE, or PATCH=, SIDE=) and *ELSET, ELSET=name.
  subroutine read_set(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=str_len) :: name, patch
    character(len=:), allocatable :: key
    integer :: kind, side, k

    if (c%kw%name == 'NSET') then
      key = 'NSET'
      kind = SET_NODE
      call check_params(c, 'NSET|PATCH|SIDE', 'GENERATE')
    else
      key = 'ELSET'
      kind = SET_ELEMENT
      call check_params(c, 'ELSET', 'GENERATE')
    end if
    call get_name(c, key, .true., name)
    call get_name(c, 'PATCH', .false., patch)
    call get_choice(c, 'SIDE', 'XI0|XI1|ETA0|ETA1|ALL', side)
    if (side > 0) side = side_codes(side)
    if (has_param(c, 'PATCH') .neqv. has_param(c, 'SIDE')) call card_error(c, &
        'PATCH= and SIDE= go together (expected PATCH=name, SIDE=XI0|XI1|ETA0|ETA1|ALL)')
    if (has_param(c, 'PATCH') .and. has_flag(c, 'GENERATE')) call card_error(c, &
        'GENERATE cannot be combined with PATCH=')
    if (c%bad) return

    if (has_param(c, 'PATCH')) then
      call no_data(c, rd)
      k = set_index(d, name, kind, c%where)
      if (k == 0) return
      if (d%sets(k)%side /= SIDE_NONE) then
        call card_error(c, 'set '//trim(name)//' already has a PATCH=, SIDE= definition')
        return
      end if
      d%sets(k)%patch = patch
      d%sets(k)%side = side
    else if (has_flag(c, 'GENERATE')) then
      call read_set_generate(c, rd, d, name, kind)
    else
      call read_set_list(c, rd, d, name, kind)
    end if
  end subroutine read_set

  !> Data of *NSET/*ELSET, GENERATE: lines "first, last[, step]".
  subroutine read_set_generate(c, rd, d, name, kind)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), intent(in) :: name
    integer, intent(in) :: kind
    character(len=:), allocatable :: expect, w
    type(token_t), allocatable :: toks(:)
    integer, allocatable :: ids(:)
    integer :: i, n, v(3), k
    integer(i8) :: count

    expect = c%label//', GENERATE: expected "first, last, step" (integers)'
    if (.not. has_data(c, expect)) return
    do i = c%first, c%last
      w = line_where(rd%src, i)
      call split_values(rd%src%lines(i)%text, toks, n)
      if (.not. count_ok(n, 2, 3, expect, w)) return
      v(3) = 1
      do k = 1, n
        if (.not. tok_int(toks, k, expect, w, v(k))) return
      end do
      if (v(3) <= 0) then
        call input_error(w, c%label//', GENERATE: step must be > 0, found '//str(v(3)))
        return
      end if
      if (v(2) < v(1)) then
        call input_error(w, c%label//', GENERATE: last = '//str(v(2))//' < first = '// &
            str(v(1))//' (expected first <= last)')
        return
      end if
      if (v(1) <= 0) then
        call input_error(w, c%label//', GENERATE: ids must be > 0, found '//str(v(1)))
        return
      end if
      count = (int(v(2), i8) - v(1))/v(3) + 1
      if (count > max_generated) then
        call input_error(w, c%label//', GENERATE: too many ids ('//str(count)// &
            '; at most '//str(max_generated)//')')
        return
      end if
      ids = [(v(1) + k*v(3), k = 0, int(count) - 1)]
      call add_to_set(d, name, kind, c%where, ids)
    end do
  end subroutine read_set_generate

  !> Data of *NSET/*ELSET as a list: ids and set names, any number per line.
  subroutine read_set_list(c, rd, d, name, kind)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), intent(in) :: name
    integer, intent(in) :: kind
    character(len=:), allocatable :: expect, w
    type(token_t), allocatable :: toks(:)
    integer, allocatable :: ids(:)
    character(len=str_len) :: ref
    integer :: i, n, k, nid, id, s
    logical :: is_int

    expect = c%label//': expected ids or set names'
    if (.not. has_data(c, expect)) return
    s = set_index(d, name, kind, c%where)
    if (s == 0) return
    do i = c%first, c%last
      w = line_where(rd%src, i)
      call split_values(rd%src%lines(i)%text, toks, n)
      allocate(ids(n))
      nid = 0
      do k = 1, n
        call parse_int(toks(k)%s, id, is_int)
        if (is_int) then
          if (id <= 0) then
            call input_error(w, expect//', found id '//str(id)//' in field '//str(k)// &
                ' (ids are > 0)')
            return
          end if
          nid = nid + 1
          ids(nid) = id
        else
          if (.not. tok_name(toks, k, expect, w, ref)) return
          call add_ref(d%sets(s), ref, w)
        end if
      end do
      call add_to_set(d, name, kind, c%where, ids(1:nid))
      deallocate(ids)
    end do
  end subroutine read_set_list

  !> *SURFACE, NAME=name with PATCH=, SIDE= or TYPE=ELEMENT (data "element or elset, Sk").
  subroutine read_surface(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    type(surface_in_t) :: s
    integer :: kind, side, k

    call check_params(c, 'NAME|TYPE|PATCH|SIDE', '')
    call get_name(c, 'NAME', .true., s%name)
    call get_choice(c, 'TYPE', 'ELEMENT', kind)
    call get_name(c, 'PATCH', .false., s%patch)
    call get_choice(c, 'SIDE', 'XI0|XI1|ETA0|ETA1|ALL', side)
    if (has_param(c, 'PATCH') .neqv. has_param(c, 'SIDE')) call card_error(c, &
        'PATCH= and SIDE= go together (expected PATCH=name, SIDE=XI0|XI1|ETA0|ETA1|ALL)')
    if (has_param(c, 'PATCH') .and. has_param(c, 'TYPE')) call card_error(c, &
        'give either PATCH=, SIDE= or TYPE=ELEMENT, not both')
    do k = 1, d%n_surfaces
      if (d%surfaces(k)%name == s%name .and. len_trim(s%name) > 0) call card_error(c, &
          'duplicate surface name '//trim(s%name)//' (first defined at '// &
          trim(d%surfaces(k)%where)//')')
    end do
    if (c%bad) return
    s%where = c%where
    if (has_param(c, 'PATCH')) then
      s%kind = SURF_PATCH
      s%side = side_codes(side)
      allocate(s%elem(0), s%face(0), s%elset(0), s%entry_where(0))
      call no_data(c, rd)
    else
      s%kind = SURF_ELEMENT
      if (.not. read_surface_faces(c, rd, s)) return
    end if
    call grow_surfaces(d%surfaces, d%n_surfaces + 1)
    d%n_surfaces = d%n_surfaces + 1
    d%surfaces(d%n_surfaces) = s
  end subroutine read_surface

  !> Data of *SURFACE, TYPE=ELEMENT: lines "element id or elset name, S1..S4".
  logical function read_surface_faces(c, rd, s) result(ok)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(surface_in_t), intent(inout) :: s
    character(len=*), parameter :: expect = &
        '*SURFACE: expected "element id or element set, face S1..S4"'
    character(len=:), allocatable :: w, face
    type(token_t), allocatable :: toks(:)
    integer :: i, n, m, id
    logical :: is_int

    ok = .false.
    if (.not. has_data(c, expect)) return
    m = c%last - c%first + 1
    allocate(s%elem(m), s%face(m), s%elset(m), s%entry_where(m))
    do i = c%first, c%last
      w = line_where(rd%src, i)
      n = i - c%first + 1
      call split_values(rd%src%lines(i)%text, toks, m)
      if (.not. count_ok(m, 2, 2, expect, w)) return
      call parse_int(toks(1)%s, id, is_int)
      s%elem(n) = 0
      s%elset(n) = ''
      if (is_int) then
        if (id <= 0) then
          call input_error(w, expect//', found element id '//str(id)//' (ids are > 0)')
          return
        end if
        s%elem(n) = id
      else
        if (.not. tok_name(toks, 1, expect, w, s%elset(n))) return
      end if
      face = upper(toks(2)%s)
      select case (face)
      case ('S1', 'S2', 'S3', 'S4')
        s%face(n) = iachar(face(2:2)) - iachar('0')
      case default
        call input_error(w, '*SURFACE: unknown face "'//shown(toks(2)%s)// &
            '" in field 2 (expected S1, S2, S3 or S4)')
        return
      end select
      s%entry_where(n) = w
    end do
    ok = .true.
  end function read_surface_faces

  !> Index of set `name` (created empty when new). 0, with a message, when the name is
  !! already used by a set of the other kind.
  integer function set_index(d, name, kind, where) result(k)
    type(deck_t), intent(inout) :: d
    character(len=*), intent(in) :: name, where
    integer, intent(in) :: kind
    integer :: j
    do j = 1, d%n_sets
      if (d%sets(j)%name == name) then
        k = j
        if (d%sets(j)%kind /= kind) then
          call input_error(where, '*'//trim(merge('NSET ', 'ELSET', kind == SET_NODE))// &
              ': name '//trim(name)//' is already used by an '// &
              trim(merge('ELSET', 'NSET ', kind == SET_NODE))//' (first defined at '// &
              trim(d%sets(j)%where)//')')
          k = 0
        end if
        return
      end if
    end do
    call grow_sets(d%sets, d%n_sets + 1)
    d%n_sets = d%n_sets + 1
    k = d%n_sets
    d%sets(k)%name = name
    d%sets(k)%kind = kind
    d%sets(k)%where = where
    allocate(d%sets(k)%ids(0), d%sets(k)%refs(0), d%sets(k)%ref_where(0))
  end function set_index

  !> Adds `ids` to set `name` of `kind` (created when new).
  subroutine add_to_set(d, name, kind, where, ids)
    type(deck_t), intent(inout) :: d
    character(len=*), intent(in) :: name, where
    integer, intent(in) :: kind
    integer, intent(in) :: ids(:)
    integer :: k
    k = set_index(d, name, kind, where)
    if (k == 0) return
    if (size(ids) > 0) d%sets(k)%ids = [d%sets(k)%ids, ids]
  end subroutine add_to_set

  !> Adds a reference to another set (with its location) to `s`.
  subroutine add_ref(s, ref, where)
    type(set_in_t), intent(inout) :: s
    character(len=*), intent(in) :: ref, where
    character(len=str_len), allocatable :: r(:)
    character(len=where_len), allocatable :: w(:)
    integer :: n
    n = size(s%refs)
    allocate(r(n + 1), w(n + 1))
    r(1:n) = s%refs
    w(1:n) = s%ref_where
    r(n + 1) = ref
    w(n + 1) = where
    call move_alloc(r, s%refs)
    call move_alloc(w, s%ref_where)
  end subroutine add_ref

  ! ------------------------------------------------------------------------------------------
  ! Conditions, contact, mass, damping
  ! ------------------------------------------------------------------------------------------

  !> *BOUNDARY: lines "node set or node id, first dof, last dof[, value]".
  subroutine read_boundary(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = &
        '*BOUNDARY: expected "node set or node id, first dof, last dof[, value]"'
    type(boundary_in_t) :: b
    type(token_t), allocatable :: toks(:)
    character(len=:), allocatable :: w
    integer :: i, n

    call check_params(c, '', '')
    if (c%bad) return
    if (.not. has_data(c, expect)) return
    do i = c%first, c%last
      w = line_where(rd%src, i)
      call split_values(rd%src%lines(i)%text, toks, n)
      if (.not. count_ok(n, 3, 4, expect, w)) return
      if (.not. tok_target(toks, 1, expect, w, b%target)) return
      if (.not. tok_int(toks, 2, expect, w, b%first_dof)) return
      if (.not. tok_int(toks, 3, expect, w, b%last_dof)) return
      b%value = 0.0_dp
      if (n == 4) then
        if (.not. tok_real(toks, 4, expect, w, b%value)) return
      end if
      if (b%first_dof < 1 .or. b%first_dof > 2 .or. b%last_dof < 1 .or. b%last_dof > 2 &
          .or. b%first_dof > b%last_dof) then
        call input_error(w, '*BOUNDARY: dofs '//str(b%first_dof)//' to '// &
            str(b%last_dof)//': expected 1 <= first dof <= last dof <= 2 (1 = x, 2 = y)')
        cycle
      end if
      b%where = w
      call grow_boundaries(d%boundaries, d%n_boundaries + 1)
      d%n_boundaries = d%n_boundaries + 1
      d%boundaries(d%n_boundaries) = b
    end do
  end subroutine read_boundary

  !> *INITIAL CONDITIONS, TYPE=VELOCITY: lines "node set or node id, dof, value".
  subroutine read_initial_conditions(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = &
        '*INITIAL CONDITIONS: expected "node set or node id, dof, value"'
    type(velocity_in_t) :: v
    type(token_t), allocatable :: toks(:)
    character(len=:), allocatable :: w
    integer :: i, n, kind

    call check_params(c, 'TYPE', '')
    call get_choice(c, 'TYPE', 'VELOCITY', kind, required=.true.)
    if (c%bad) return
    if (.not. has_data(c, expect)) return
    do i = c%first, c%last
      w = line_where(rd%src, i)
      call split_values(rd%src%lines(i)%text, toks, n)
      if (.not. count_ok(n, 3, 3, expect, w)) return
      if (.not. tok_target(toks, 1, expect, w, v%target)) return
      if (.not. tok_int(toks, 2, expect, w, v%dof)) return
      if (.not. tok_real(toks, 3, expect, w, v%value)) return
      if (v%dof < 1 .or. v%dof > 2) then
        call input_error(w, '*INITIAL CONDITIONS: dof '//str(v%dof)// &
            ' outside 1..2 (1 = x, 2 = y)')
        cycle
      end if
      v%where = w
      call grow_velocities(d%velocities, d%n_velocities + 1)
      d%n_velocities = d%n_velocities + 1
      d%velocities(d%n_velocities) = v
    end do
  end subroutine read_initial_conditions

  !> *CONTACT PAIR, NAME=, PENALTY=, [ALGORITHM=], [MASS PENALTY=AUTO|value]: one data
  !! line "first surface, second surface".
  subroutine read_contact_pair(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = &
        '*CONTACT PAIR: expected "first surface, second surface"'
    type(contact_pair_in_t) :: p
    type(token_t), allocatable :: toks(:)
    character(len=:), allocatable :: v
    real(dp) :: x(1)
    integer :: kind, i, n, k
    logical :: ok

    call check_params(c, 'NAME|PENALTY|ALGORITHM|MASS PENALTY', '')
    call get_name(c, 'NAME', .true., p%name)
    call get_positive(c, 'PENALTY', p%penalty)
    call get_choice(c, 'ALGORITHM', 'TWO HALF PASS|NODE TO SEGMENT', kind)
    if (kind == 2) p%algorithm = CONTACT_NODE_TO_SEGMENT
    if (get_param(c, 'MASS PENALTY', v)) then
      if (upper(v) == 'AUTO') then
        p%mass_penalty = 0.0_dp
      else
        call parse_real(v, x(1), ok)
        if (ok .and. x(1) > 0.0_dp) then
          p%mass_penalty = x(1)
        else
          call card_error(c, 'bad value MASS PENALTY='//shown(v)// &
              ' (expected AUTO or a number > 0)')
        end if
      end if
    end if
    do k = 1, d%n_pairs
      if (d%pairs(k)%name == p%name .and. len_trim(p%name) > 0) call card_error(c, &
          'duplicate contact pair name '//trim(p%name)//' (first defined at '// &
          trim(d%pairs(k)%where)//')')
    end do
    if (c%bad) return
    if (.not. one_line(c, rd, expect, i)) return
    call split_values(rd%src%lines(i)%text, toks, n)
    if (.not. count_ok(n, 2, 2, expect, line_where(rd%src, i))) return
    if (.not. tok_name(toks, 1, expect, line_where(rd%src, i), p%first)) return
    if (.not. tok_name(toks, 2, expect, line_where(rd%src, i), p%second)) return
    p%where = c%where
    call grow_pairs(d%pairs, d%n_pairs + 1)
    d%n_pairs = d%n_pairs + 1
    d%pairs(d%n_pairs) = p
  end subroutine read_contact_pair

  !> *RIGID WALL, NAME=, POINT=x0,y0, NORMAL=nx,ny, PENALTY=: one data line "surface".
  subroutine read_rigid_wall(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*RIGID WALL: expected "surface"'
    type(rigid_wall_in_t) :: wl
    type(token_t), allocatable :: toks(:)
    integer :: i, n, k

    call check_params(c, 'NAME|POINT|NORMAL|PENALTY', '')
    call get_name(c, 'NAME', .true., wl%name)
    if (get_reals(c, 'POINT', 2, 'x0,y0', wl%point, required=.true.)) continue
    if (get_reals(c, 'NORMAL', 2, 'nx,ny', wl%normal, required=.true.)) then
      if (all(wl%normal == 0.0_dp)) call card_error(c, 'NORMAL=0,0 is zero (expected '// &
          'a non-zero direction nx,ny pointing into the allowed side)')
    end if
    call get_positive(c, 'PENALTY', wl%penalty)
    do k = 1, d%n_walls
      if (d%walls(k)%name == wl%name .and. len_trim(wl%name) > 0) call card_error(c, &
          'duplicate rigid wall name '//trim(wl%name)//' (first defined at '// &
          trim(d%walls(k)%where)//')')
    end do
    if (c%bad) return
    if (.not. one_line(c, rd, expect, i)) return
    call split_values(rd%src%lines(i)%text, toks, n)
    if (.not. count_ok(n, 1, 1, expect, line_where(rd%src, i))) return
    if (.not. tok_name(toks, 1, expect, line_where(rd%src, i), wl%surface)) return
    wl%where = c%where
    call grow_walls(d%walls, d%n_walls + 1)
    d%n_walls = d%n_walls + 1
    d%walls(d%n_walls) = wl
  end subroutine read_rigid_wall

  !> *DAMPING, ALPHA=a [, ELSET= | PATCH=].
  subroutine read_damping(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    type(damping_in_t) :: dm
    real(dp) :: a(1)

    call check_params(c, 'ALPHA|ELSET|PATCH', '')
    if (get_reals(c, 'ALPHA', 1, 'a number >= 0', a)) then
      if (a(1) < 0.0_dp) then
        call card_error(c, 'ALPHA='//str(a(1))//' must be >= 0')
      else
        dm%alpha = a(1)
      end if
    end if
    call get_body(c, dm%elset, dm%patch)
    call no_data(c, rd)
    if (c%bad) return
    dm%where = c%where
    call grow_dampings(d%dampings, d%n_dampings + 1)
    d%n_dampings = d%n_dampings + 1
    d%dampings(d%n_dampings) = dm
  end subroutine read_damping

  !> *MASS, TYPE=CONSISTENT|ROW SUM|HRZ|ALPHA [, ALPHA=a] [, INTEGRATION=FULL|2X2]
  !! [, ELSET= | PATCH=].
  subroutine read_mass(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    type(mass_in_t) :: m
    real(dp) :: a(1)
    integer :: kind, rule

    call check_params(c, 'TYPE|ALPHA|INTEGRATION|ELSET|PATCH', '')
    call get_choice(c, 'TYPE', 'CONSISTENT|ROW SUM|HRZ|ALPHA', kind)
    if (kind > 0) m%kind = mass_codes(kind)
    call get_choice(c, 'INTEGRATION', 'FULL|2X2', rule)
    if (rule > 0) m%hrz_rule = hrz_codes(rule)
    if (rule > 0 .and. m%kind /= MASS_HRZ) call card_error(c, &
        'INTEGRATION= applies to TYPE=HRZ only')
    if (get_reals(c, 'ALPHA', 1, 'a number in [0, 0.25]', a)) then
      if (m%kind /= MASS_ALPHA) then
        call card_error(c, 'ALPHA= applies to TYPE=ALPHA only')
      else if (a(1) < 0.0_dp .or. a(1) > 0.25_dp) then
        call card_error(c, 'ALPHA='//str(a(1))//' outside [0, 0.25] (midside a*m_e, '// &
            'corner (1/4 - a)*m_e must be >= 0)')
      else
        m%alpha = a(1)
      end if
    else if (m%kind == MASS_ALPHA .and. .not. c%bad) then
      call card_error(c, 'TYPE=ALPHA needs ALPHA=a (0 <= a <= 0.25)')
    end if
    call get_body(c, m%elset, m%patch)
    call no_data(c, rd)
    if (c%bad) return
    m%where = c%where
    call grow_masses(d%masses, d%n_masses + 1)
    d%n_masses = d%n_masses + 1
    d%masses(d%n_masses) = m
  end subroutine read_mass

  !> Optional ELSET= or PATCH= (not both) selecting a body.
  subroutine get_body(c, elset, patch)
    type(card_t), intent(inout) :: c
    character(len=*), intent(out) :: elset, patch
    call get_name(c, 'ELSET', .false., elset)
    call get_name(c, 'PATCH', .false., patch)
    if (len_trim(elset) > 0 .and. len_trim(patch) > 0) call card_error(c, &
        'give ELSET= or PATCH=, not both')
  end subroutine get_body

  ! ------------------------------------------------------------------------------------------
  ! Step cards
  ! ------------------------------------------------------------------------------------------

  !> *STEP: opens the (single) step.
  subroutine read_step(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    call check_params(c, '', '')
    call no_data(c, rd)
    if (rd%in_step) then
      call card_error(c, 'a *STEP inside a step (expected *END STEP first)')
      return
    end if
    rd%in_step = .true.
    if (d%has_step) then
      call card_error(c, 'a second *STEP (only one step is allowed; first at '// &
          trim(d%step%where)//')')
      rd%skip_step = .true.
      return
    end if
    d%has_step = .true.
    d%step%where = c%where
  end subroutine read_step

  !> *DYNAMIC, EXPLICIT [, SAFETY=s] [, MASS SOLVER=CHOLESKY|CG|CORRECTOR] [, MASS TOL=tol]
  !! [, MASS PASSES=k] [, SWEEP STEPS=s|AUTO]: one data line "dt, t_end". MASS TOL is the
  !! tolerance of the conjugate gradient, so it needs MASS SOLVER=CG; MASS PASSES counts the
  !! corrector's passes, so it needs MASS SOLVER=CORRECTOR. SWEEP STEPS is the number of
  !! lumped-mass steps per sweep over the stiffness (ictus_solver_sweep); AUTO (0) lets the
  !! run time 6-step sweeps against single steps and keep the faster.
  subroutine read_dynamic(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*DYNAMIC: expected 2 numbers (dt, t_end)'
    character(len=*), parameter :: solvers(5) = [character(len=9) :: 'AUTO', 'KRONECKER', &
        'CHOLESKY', 'CG', 'CORRECTOR']
    real(dp) :: v(2), s(1)
    integer :: i, k, np(1)
    logical :: tol_given, passes_given
    character(len=:), allocatable :: text

    call check_params(c, 'SAFETY|MASS TOL|MASS SOLVER|MASS PASSES|SWEEP STEPS', 'EXPLICIT')
    if (.not. has_flag(c, 'EXPLICIT')) call card_error(c, &
        'only explicit dynamics is supported (expected *DYNAMIC, EXPLICIT)')
    if (get_reals(c, 'SAFETY', 1, 'a number in (0, 1]', s)) then
      if (s(1) <= 0.0_dp .or. s(1) > 1.0_dp) then
        call card_error(c, 'SAFETY='//str(s(1))//' outside (0, 1]')
      else
        d%step%safety = s(1)
      end if
    end if
    tol_given = get_reals(c, 'MASS TOL', 1, 'a number in [1e-14, 1e-3]', s)
    if (tol_given) then
      if (s(1) < 1.0e-14_dp .or. s(1) > 1.0e-3_dp) then
        call card_error(c, 'MASS TOL='//str(s(1))//' outside [1e-14, 1e-3] (relative '// &
            'residual of the consistent-mass solve)')
      else
        d%step%mass_tol = s(1)
      end if
    end if
    np = 0
    passes_given = get_ints(c, 'MASS PASSES', 1, 'an integer in [1, 50]', np)
    if (passes_given) then
      if (np(1) < 1 .or. np(1) > 50) then
        call card_error(c, 'MASS PASSES='//str(np(1))//' outside [1, 50] (corrector '// &
            'passes of the consistent-mass solve)')
      else
        d%step%mass_passes = np(1)
      end if
    end if
    if (get_param(c, 'SWEEP STEPS', text)) then
      if (upper(collapse_blanks(text)) == 'AUTO') then
        d%step%sweep_steps = 0
      else if (get_ints(c, 'SWEEP STEPS', 1, 'AUTO or an integer in [1, 8]', np)) then
        if (np(1) < 1 .or. np(1) > 8) then
          call card_error(c, 'SWEEP STEPS='//str(np(1))//' outside [1, 8] (lumped-mass '// &
              'steps per sweep over the stiffness; 1 = one step per sweep; or AUTO)')
        else
          d%step%sweep_steps = np(1)
        end if
      end if
    end if
    call get_choice(c, 'MASS SOLVER', 'AUTO|KRONECKER|CHOLESKY|CG|CORRECTOR', k)
    if (k > 0) d%step%mass_solver = solvers(k)
    if (tol_given .and. d%step%mass_solver /= 'CG') call card_error(c, &
        'MASS TOL is the tolerance of the conjugate gradient: add MASS SOLVER=CG (the '// &
        'default MASS SOLVER=AUTO solves exactly)')
    if (passes_given .and. d%step%mass_solver /= 'CORRECTOR') call card_error(c, &
        'MASS PASSES counts the passes of the corrector: add MASS SOLVER=CORRECTOR (the '// &
        'default MASS SOLVER=AUTO solves exactly)')
    if (rd%has_dynamic) call card_error(c, 'a second *DYNAMIC in the step')
    rd%has_dynamic = .true.
    d%step%dynamic_where = c%where
    if (c%bad) return
    if (.not. one_line(c, rd, expect, i)) return
    if (.not. line_reals(rd, i, 2, expect, v)) return
    if (v(1) < 0.0_dp) call input_error(line_where(rd%src, i), '*DYNAMIC: dt = '// &
        str(v(1))//' must be >= 0 (0 = automatic)')
    if (v(2) <= 0.0_dp) call input_error(line_where(rd%src, i), '*DYNAMIC: t_end = '// &
        str(v(2))//' must be > 0')
    d%step%dt = v(1)
    d%step%t_end = v(2)
  end subroutine read_dynamic

  !> *OUTPUT, HISTORY|FIELD [, EVERY=n] [, SAMPLES=s (FIELD)].
  subroutine read_output(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    integer :: n(1)
    logical :: history, field

    call check_params(c, 'EVERY|SAMPLES', 'HISTORY|FIELD')
    call no_data(c, rd)
    history = has_flag(c, 'HISTORY')
    field = has_flag(c, 'FIELD')
    if (history .eqv. field) then
      call card_error(c, 'expected exactly one of HISTORY or FIELD')
      return
    end if
    if (history) then
      if (has_param(c, 'SAMPLES')) call card_error(c, 'SAMPLES= goes with *OUTPUT, FIELD '// &
          '(viewing samples of NURBS elements), not with HISTORY')
      if (rd%has_history) call card_error(c, 'a second *OUTPUT, HISTORY in the step')
      rd%has_history = .true.
      if (get_ints(c, 'EVERY', 1, 'an integer n >= 1', n)) then
        if (n(1) < 1) then
          call card_error(c, 'EVERY='//str(n(1))//' must be >= 1')
        else
          d%step%history_every = n(1)
        end if
      end if
    else
      if (rd%has_field) call card_error(c, 'a second *OUTPUT, FIELD in the step')
      rd%has_field = .true.
      if (get_ints(c, 'EVERY', 1, 'an integer n >= 1 (0 = 20 snapshots)', n)) then
        if (n(1) < 0) then
          call card_error(c, 'EVERY='//str(n(1))//' must be >= 1 (or 0 = 20 snapshots)')
        else
          d%step%field_every = n(1)
        end if
      end if
      if (get_ints(c, 'SAMPLES', 1, 'an integer s in [2, 21]', n)) then
        if (n(1) < 2 .or. n(1) > 21) then
          call card_error(c, 'SAMPLES='//str(n(1))//' must lie in [2, 21] (viewing '// &
              'samples per direction of each NURBS element)')
        else
          d%step%field_samples = n(1)
        end if
      end if
      d%step%field_where = c%where
    end if
  end subroutine read_output

  !> *RESTART, WRITE, EVERY=n.
  subroutine read_restart(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    integer :: n(1)
    call check_params(c, 'EVERY', 'WRITE')
    call no_data(c, rd)
    if (.not. has_flag(c, 'WRITE')) call card_error(c, 'expected *RESTART, WRITE, EVERY=n')
    if (rd%has_restart) call card_error(c, 'a second *RESTART in the step')
    rd%has_restart = .true.
    if (get_ints(c, 'EVERY', 1, 'an integer n >= 1', n, required=.true.)) then
      if (n(1) < 1) then
        call card_error(c, 'EVERY='//str(n(1))//' must be >= 1')
      else
        d%step%restart_every = n(1)
      end if
    end if
  end subroutine read_restart

  !> *END STEP: closes the step.
  subroutine read_end_step(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    call check_params(c, '', '')
    call no_data(c, rd)
    rd%in_step = .false.
    if (.not. rd%has_dynamic) call input_error(d%step%where, &
        '*STEP: no *DYNAMIC, EXPLICIT card in the step (expected dt, t_end)')
  end subroutine read_end_step

end module ictus_io_deck_reader
