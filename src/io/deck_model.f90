!> Readers of the model cards of the finite-element mesh and of the names defined on it
!! (doc/user-guide.md §4-5): *HEADING, *ANALYSIS, *NODE, *ELEMENT, *NSET, *ELSET and *SURFACE.
!!
!! Each `read_<card>` checks its parameters, converts its data lines and appends records to
!! the deck (`app/build_model` and `app/build_contact` turn them into the model and the
!! contact surfaces). Names used before they are defined are resolved afterwards by
!! `check_deck` (ictus_io_deck_checks), so the order of these cards does not matter.
module ictus_io_deck_model
  use ictus_core_kinds, only: dp, i8, str_len
  use ictus_core_errors, only: input_error
  use ictus_core_strings, only: upper, str
  use ictus_io_deck_lexer, only: token_t, line_where, split_values, parse_int, shown, &
      collapse_blanks
  use ictus_elements_library, only: element_type_named, element_types_named, &
      element_abaqus_names, element_default_ngauss, etype_ndm
  use ictus_io_deck_types, only: deck_t, element_block_in_t, set_in_t, surface_in_t, &
      where_len, ANALYSIS_PLANE_STRAIN, ANALYSIS_PLANE_STRESS, ANALYSIS_3D, etype_nen, etype_name, SET_NODE, &
      SET_ELEMENT, SIDE_NONE, SIDE_XI0, SIDE_XI1, SIDE_ETA0, &
      SIDE_ETA1, SIDE_ALL, SIDE_ZETA0, SIDE_ZETA1, SURF_ELEMENT, SURF_PATCH
  use ictus_io_deck_card, only: card_t, reader_t, max_generated, card_error, check_params, &
      has_param, has_flag, get_param, get_name, get_choice, get_ints, get_reals, no_data, has_data, &
      count_ok, tok_int, tok_real, tok_name, plural
  use ictus_io_deck_grow, only: grow_blocks, grow_sets, grow_surfaces
  implicit none
  private
  public :: read_heading, read_analysis, read_node, read_element, read_set, read_surface

  !> Codes of the choices of SIDE=, in list order.
  !> The SIDE= values in the order of `side_names`: the sides of a patch and ALL; ZETA0 and
  !! ZETA1 (the faces of the third direction) only in 3D.
  integer, parameter :: side_codes(7) = [SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ALL, &
      SIDE_ZETA0, SIDE_ZETA1]
  character(len=*), parameter :: side_names(7) = ['XI0  ', 'XI1  ', 'ETA0 ', 'ETA1 ', &
      'ALL  ', 'ZETA0', 'ZETA1']

contains

  ! ------------------------------------------------------------------------------------------
  ! Model-wide cards
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

  !> *ANALYSIS, TYPE=PLANE STRAIN|PLANE STRESS|3D, THICKNESS=t (2D only).
  subroutine read_analysis(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    integer :: kind
    real(dp) :: t(1)

    call check_params(c, 'TYPE|THICKNESS', '')
    if (rd%has_analysis) call card_error(c, 'given twice (expected one *ANALYSIS card)')
    rd%has_analysis = .true.
    call get_choice(c, 'TYPE', 'PLANE STRAIN|PLANE STRESS|3D', kind)
    if (kind == 1) d%analysis = ANALYSIS_PLANE_STRAIN
    if (kind == 2) d%analysis = ANALYSIS_PLANE_STRESS
    if (kind == 3) d%analysis = ANALYSIS_3D
    if (kind > 0) d%analysis_where = c%where
    if (get_reals(c, 'THICKNESS', 1, 'a number t > 0', t)) then
      if (d%ndm == 3) then
        call card_error(c, 'THICKNESS= is the thickness of a 2D model; a 3D analysis has '// &
            'none (expected *ANALYSIS, TYPE=3D without THICKNESS=)')
      else if (t(1) > 0.0_dp) then
        d%thickness = t(1)
        d%thickness_where = c%where
      else
        call card_error(c, 'THICKNESS='//str(t(1))//' must be > 0')
      end if
    end if
    call no_data(c, rd)
  end subroutine read_analysis

  ! ------------------------------------------------------------------------------------------
  ! Nodes and elements
  ! ------------------------------------------------------------------------------------------

  !> *NODE [, NSET=name]: data lines "id, x, y" or "id, x, y, z" with z = 0 in 2D; "id, x, y, z"
  !! in 3D.
  subroutine read_node(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=:), allocatable :: expect
    character(len=str_len) :: nset
    type(token_t), allocatable :: toks(:)
    integer :: i, n, id, n0
    real(dp) :: x(3)

    expect = '*NODE: expected "id, x, y"'
    if (d%ndm == 3) expect = '*NODE: expected "id, x, y, z"'
    call check_params(c, 'NSET', '')
    call get_name(c, 'NSET', .false., nset)
    if (c%bad) return
    if (.not. has_data(c, expect)) return
    call reserve_nodes(rd, d, d%n_nodes + c%last - c%first + 1)
    n0 = d%n_nodes
    do i = c%first, c%last
      call rd%tk%tick(i, rd%src%n_lines)
      call split_values(rd%src%lines(i)%text, toks, n)
      if (n < d%ndm + 1) then
        call input_error(line_where(rd%src, i), expect//', found '//str(n)//' value'// &
            plural(n)//' (a node needs '//str(d%ndm)//' coordinates'// &
            trim(merge(' in a 3D analysis', '                 ', d%ndm == 3))//')')
        exit
      end if
      if (.not. count_ok(n, d%ndm + 1, 4, expect, line_where(rd%src, i))) exit
      if (.not. tok_int(toks, 1, expect, line_where(rd%src, i), id)) exit
      if (.not. tok_real(toks, 2, expect, line_where(rd%src, i), x(1))) exit
      if (.not. tok_real(toks, 3, expect, line_where(rd%src, i), x(2))) exit
      if (n == 4 .and. d%ndm == 3) then
        if (.not. tok_real(toks, 4, expect, line_where(rd%src, i), x(3))) exit
      else if (n == 4) then
        if (.not. tok_real(toks, 4, expect//' or "id, x, y, z"', line_where(rd%src, i), &
            x(3))) exit
        if (x(3) /= 0.0_dp) then
          call input_error(line_where(rd%src, i), '*NODE: node '//str(id)//' has z = '// &
              str(x(3))//', but the analysis is 2D (expected z = 0, or "id, x, y"; a 3D '// &
              'model needs *ANALYSIS, TYPE=3D)')
          exit
        end if
      end if
      if (id <= 0) then
        call input_error(line_where(rd%src, i), '*NODE: node id must be > 0, found '//str(id))
        exit
      end if
      d%n_nodes = d%n_nodes + 1
      d%node_ids(d%n_nodes) = id
      d%node_x(:, d%n_nodes) = x(1:d%ndm)
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
    allocate(ids(cap), x(d%ndm, cap), w(cap))
    ids(1:d%n_nodes) = d%node_ids(1:d%n_nodes)
    x(:, 1:d%n_nodes) = d%node_x(:, 1:d%n_nodes)
    w(1:d%n_nodes) = d%node_where(1:d%n_nodes)
    call move_alloc(ids, d%node_ids)
    call move_alloc(x, d%node_x)
    call move_alloc(w, d%node_where)
    rd%node_cap = cap
  end subroutine reserve_nodes

  !> *ELEMENT, TYPE=Q4|Q8|Q9 (or an Abaqus name; in 3D C3D8, C3D20, C3D20R, C3D27),
  !! [MATERIAL=name] [, ELSET=name] [, GAUSS=2|3] [, DILATATION=FULL|MEAN]: data lines
  !! "id, n1, ..., nen"; a line that ends with a comma before all nen nodes are given goes on
  !! to the next line (as Abaqus and gmsh write 20- and 27-node elements). Data lines from
  !! different files go to separate blocks. Line elements (T3D2, T3D3, as gmsh writes a
  !! boundary) and in 3D the surface elements of a boundary (CPS3, CPS4, CPS6, CPS8, M3D9)
  !! go to `d%edges`: their ELSET names become node sets (ictus_io_deck_interop).
  subroutine read_element(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=:), allocatable :: expect
    type(element_block_in_t) :: b
    type(token_t), allocatable :: toks(:)
    character(len=:), allocatable :: w, text
    integer :: i, i0, n, k, nel, g(1), file, id, conn(27), gauss
    logical :: ok

    call check_params(c, 'TYPE|ELSET|MATERIAL|GAUSS|DILATATION', '')
    call get_element_type(c, d, b, gauss)
    call get_choice(c, 'DILATATION', 'FULL|MEAN', b%dilatation)
    call get_name(c, 'MATERIAL', .false., b%material)
    call get_name(c, 'ELSET', .false., b%elset)
    if (get_ints(c, 'GAUSS', 1, '2 or 3 points per direction', g)) then
      if (g(1) /= 2 .and. g(1) /= 3) then
        call card_error(c, 'bad value GAUSS='//str(g(1))//' (expected 2 or 3)')
      else if (gauss > 0 .and. g(1) /= gauss) then
        call card_error(c, 'GAUSS='//str(g(1))//' contradicts TYPE='//trim(b%type_name)// &
            ' ('//gauss_text(gauss, d%ndm)//' Gauss points)')
      else
        b%gauss = g(1)
      end if
    end if
    if (c%bad .or. b%nen == 0) return
    if (b%gauss == 0) b%gauss = gauss
    if (b%gauss == 0 .and. b%etype > 0) b%gauss = element_default_ngauss(b%etype)
    expect = '*ELEMENT: expected "id, n1, ..., n'//str(b%nen)//'" (TYPE='// &
        trim(b%type_name)//': '//str(b%nen + 1)//' integers)'
    if (.not. has_data(c, expect)) return
    b%where = c%where
    b%analysis_where = c%where
    nel = 0
    file = 0
    allocate(b%ids(c%last - c%first + 1), b%conn(b%nen, c%last - c%first + 1), &
        b%line(c%last - c%first + 1))
    i = c%first
    do while (i <= c%last)
      call rd%tk%tick(i, rd%src%n_lines)
      if (rd%src%lines(i)%file /= file .and. nel > 0) call push_block(d, b, nel)
      file = rd%src%lines(i)%file
      b%file = rd%src%files(file)%s
      w = line_where(rd%src, i)
      i0 = i
      call element_text(rd, i, c%last, b%nen + 1, text)
      call split_values(text, toks, n)
      i = i + 1
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
      b%line(nel) = rd%src%lines(i0)%line
    end do
    if (nel > 0) call push_block(d, b, nel)
  end subroutine read_element

  !> The text of the element whose data starts at line i (at most `last`): the line, joined
  !! with the next ones while it ends with a comma and holds fewer than `nval` values (an
  !! element continued over several lines); i is left at its last line.
  subroutine element_text(rd, i, last, nval, text)
    type(reader_t), intent(in) :: rd
    integer, intent(inout) :: i
    integer, intent(in) :: last, nval
    character(len=:), allocatable, intent(out) :: text
    type(token_t), allocatable :: toks(:)
    integer :: n
    text = rd%src%lines(i)%text
    do while (i < last)
      if (len_trim(text) == 0) exit
      if (text(len_trim(text):len_trim(text)) /= ',') exit
      if (rd%src%lines(i + 1)%file /= rd%src%lines(i)%file) exit
      call split_values(text, toks, n)
      if (n >= nval) exit
      i = i + 1
      text = text//' '//rd%src%lines(i)%text
    end do
  end subroutine element_text

  !> "2x2" (or "2x2x2" in 3D) for n points per direction.
  pure function gauss_text(n, ndm) result(t)
    integer, intent(in) :: n, ndm
    character(len=:), allocatable :: t
    t = str(n)//'x'//str(n)
    if (ndm == 3) t = t//'x'//str(n)
  end function gauss_text

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
    if (b%etype == 0) then
      call grow_blocks(d%edges, d%n_edges + 1)
      d%n_edges = d%n_edges + 1
      call copy_block(d%edges(d%n_edges), b, nel)
    else
      call grow_blocks(d%blocks, d%n_blocks + 1)
      d%n_blocks = d%n_blocks + 1
      call copy_block(d%blocks(d%n_blocks), b, nel)
    end if
    nel = 0
  end subroutine push_block

  !> The first `nel` elements of `b` into `nb`.
  subroutine copy_block(nb, b, nel)
    type(element_block_in_t), intent(inout) :: nb
    type(element_block_in_t), intent(in) :: b
    integer, intent(in) :: nel
    associate (nb => nb)
      nb%etype = b%etype
      nb%nen = b%nen
      nb%elset = b%elset
      nb%material = b%material
      nb%gauss = b%gauss
      nb%dilatation = b%dilatation
      nb%ids = b%ids(1:nel)
      nb%conn = b%conn(:, 1:nel)
      nb%line = b%line(1:nel)
      nb%file = b%file
      nb%where = b%where
      nb%analysis = b%analysis
      nb%analysis_where = b%analysis_where
      nb%type_name = b%type_name
    end associate
  end subroutine copy_block

  !> TYPE= of *ELEMENT: a type of the element library by its name or Abaqus name (b%etype,
  !! b%nen, b%analysis it implies; `gauss` the rule the name implies, 0: the type's own), or a
  !! boundary element (b%etype = 0, b%nen its nodes): a line element T3D2/T3D3, or in 3D a
  !! surface element (face_element_nodes). The type must have the dimension
  !! of the deck (d%ndm). b%nen = 0 when bad (reported).
  subroutine get_element_type(c, d, b, gauss)
    type(card_t), intent(inout) :: c
    type(deck_t), intent(in) :: d
    type(element_block_in_t), intent(inout) :: b
    integer, intent(out) :: gauss
    character(len=:), allocatable :: v, mat
    gauss = 0
    b%nen = 0
    if (.not. get_param(c, 'TYPE', v)) then
      call card_error(c, 'missing required parameter TYPE=Q4|Q8|Q9'// &
          trim(merge('|C3D8|C3D20|C3D20R|C3D27', '                        ', d%ndm == 3)))
      return
    end if
    b%type_name = upper(collapse_blanks(v))
    if (d%ndm == 3 .and. face_element_nodes(b%type_name) > 0 .and. &
        .not. get_param(c, 'MATERIAL', mat)) then
      ! the surface elements of a gmsh 3D export: sets of boundary nodes, as line elements
      ! (with a MATERIAL= the card means solids: a 2D element in a 3D analysis, refused below)
      b%etype = 0
      b%nen = face_element_nodes(b%type_name)
      return
    end if
    call element_type_named(b%type_name, b%etype, b%analysis, gauss)
    if (b%etype > 0) then
      if (etype_ndm(b%etype) /= d%ndm) then
        call card_error(c, 'bad value TYPE='//shown(v)//': '//dimension_text(b, d))
        return
      end if
      b%nen = etype_nen(b%etype)
    else if (b%type_name == 'T3D2' .or. b%type_name == 'T3D3') then
      b%nen = merge(2, 3, b%type_name == 'T3D2')
    else
      call card_error(c, 'bad value TYPE='//shown(v)//' (expected one of '// &
          element_types_named(d%ndm)//'; or the Abaqus names '// &
          element_abaqus_names(d%ndm)//'; ictus has no triangles, tetrahedra, '// &
          'axisymmetric, beam or shell elements; line elements T3D2, T3D3 (and in 3D the '// &
          'surface elements CPS3, CPS4, CPS6, CPS8, M3D9 of a gmsh export) are read as sets '// &
          'of boundary nodes)')
    end if
  end subroutine get_element_type

  !> Nodes of a surface element that a 3D mesh export writes on its boundary (gmsh: CPS3,
  !! CPS4, CPS6, CPS8 and M3D9; also the CPE and membrane M3D names of the same shapes), 0
  !! for any other name. In a 3D analysis such elements are sets of boundary nodes.
  pure integer function face_element_nodes(name)
    character(len=*), intent(in) :: name
    select case (name)
    case ('CPS3', 'CPE3', 'M3D3')
      face_element_nodes = 3
    case ('CPS4', 'CPE4', 'M3D4', 'CPS4R', 'CPE4R', 'M3D4R')
      face_element_nodes = 4
    case ('CPS6', 'CPE6', 'M3D6')
      face_element_nodes = 6
    case ('CPS8', 'CPE8', 'M3D8', 'CPS8R', 'CPE8R', 'M3D8R')
      face_element_nodes = 8
    case ('M3D9', 'CPS9', 'CPE9', 'M3D9R')
      face_element_nodes = 9
    case default
      face_element_nodes = 0
    end select
  end function face_element_nodes

  !> Why element type b%etype does not fit the analysis of deck d (a 3D type in a 2D
  !! analysis, or a 2D type in a 3D one), with the types that would.
  function dimension_text(b, d) result(msg)
    type(element_block_in_t), intent(in) :: b
    type(deck_t), intent(in) :: d
    character(len=:), allocatable :: msg
    if (d%ndm == 2) then
      msg = trim(b%type_name)//' is a 3D element, which needs *ANALYSIS, TYPE=3D; this '// &
          'analysis is 2D (expected one of '//element_types_named(2)//', or the Abaqus names '// &
          element_abaqus_names(2)//')'
    else
      msg = trim(b%type_name)//' is a 2D element, but the analysis is 3D (*ANALYSIS, '// &
          'TYPE=3D; expected one of '//element_types_named(3)//', or the Abaqus names '// &
          element_abaqus_names(3)//')'
    end if
  end function dimension_text

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
    call get_side(c, d%ndm, side)
    if (side > 0) side = side_codes(side)
    if (has_param(c, 'PATCH') .neqv. has_param(c, 'SIDE')) call card_error(c, &
        'PATCH= and SIDE= go together (expected PATCH=name, SIDE='//side_choices(d%ndm)//')')
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

  !> *SURFACE, NAME=name with PATCH=, SIDE= or TYPE=ELEMENT (data "element or elset, Sk"). A
  !! surface of patch sides may list further sides (several patches of one merged body) as
  !! data lines "PATCH=name, SIDE=side", with or without PATCH=, SIDE= on the card.
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
    call get_side(c, d%ndm, side)
    if (has_param(c, 'PATCH') .neqv. has_param(c, 'SIDE')) call card_error(c, &
        'PATCH= and SIDE= go together (expected PATCH=name, SIDE='//side_choices(d%ndm)//')')
    if (has_param(c, 'PATCH') .and. has_param(c, 'TYPE')) call card_error(c, &
        'give either PATCH=, SIDE= or TYPE=ELEMENT, not both')
    do k = 1, d%n_surfaces
      if (d%surfaces(k)%name == s%name .and. len_trim(s%name) > 0) call card_error(c, &
          'duplicate surface name '//trim(s%name)//' (first defined at '// &
          trim(d%surfaces(k)%where)//')')
    end do
    if (c%bad) return
    s%where = c%where
    if (has_param(c, 'PATCH') .or. (.not. has_param(c, 'TYPE') .and. side_data(c, rd))) then
      s%kind = SURF_PATCH
      allocate(s%elem(0), s%face(0), s%elset(0))
      if (.not. read_surface_sides(c, rd, s, side, d%ndm)) return
    else
      s%kind = SURF_ELEMENT
      if (.not. read_surface_faces(c, rd, s, d%ndm)) return
    end if
    call grow_surfaces(d%surfaces, d%n_surfaces + 1)
    d%n_surfaces = d%n_surfaces + 1
    d%surfaces(d%n_surfaces) = s
  end subroutine read_surface

  !> True when the first data line of a *SURFACE card starts with PATCH= (a surface of patch
  !! sides given by data lines).
  logical function side_data(c, rd)
    type(card_t), intent(in) :: c
    type(reader_t), intent(in) :: rd
    character(len=:), allocatable :: t
    side_data = .false.
    if (c%last < c%first) return
    t = upper(no_blanks(rd%src%lines(c%first)%text))
    side_data = index(t, 'PATCH=') == 1
  end function side_data

  !> The text without blanks.
  pure function no_blanks(text) result(t)
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: t
    integer :: i
    t = ''
    do i = 1, len(text)
      if (text(i:i) /= ' ' .and. iachar(text(i:i)) /= 9) t = t//text(i:i)
    end do
  end function no_blanks

  !> The patch sides of a *SURFACE: PATCH=, SIDE= of the card (code index `side` of
  !! side_codes) when given, then one "PATCH=name, SIDE=side" per data line. A side listed
  !! twice is an error.
  logical function read_surface_sides(c, rd, s, side, ndm) result(ok)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(surface_in_t), intent(inout) :: s
    integer, intent(in) :: side, ndm
    character(len=:), allocatable :: w, key, val, expect
    type(token_t), allocatable :: toks(:)
    integer :: i, n, n0, m, j, k, eq
    logical :: got(2)

    ok = .false.
    expect = '*SURFACE: expected "PATCH=name, SIDE='//side_choices(ndm)//'"'
    n0 = merge(1, 0, has_param(c, 'PATCH'))
    m = n0 + max(c%last - c%first + 1, 0)
    allocate(s%side_patch(m), s%side_code(m), s%entry_where(m))
    if (n0 == 1) then
      s%side_patch(1) = s%patch
      s%side_code(1) = side_codes(max(side, 1))
      s%entry_where(1) = c%where
    end if
    do i = c%first, c%last
      w = line_where(rd%src, i)
      n = n0 + i - c%first + 1
      call split_values(no_blanks(rd%src%lines(i)%text), toks, m)
      if (.not. count_ok(m, 2, 2, expect, w)) return
      got = .false.
      do j = 1, 2
        eq = index(toks(j)%s, '=')
        if (eq < 2 .or. eq == len(toks(j)%s)) then
          call input_error(w, expect//', found "'//shown(toks(j)%s)//'" in field '//str(j))
          return
        end if
        key = upper(toks(j)%s(1:eq - 1))
        val = toks(j)%s(eq + 1:)
        select case (key)
        case ('PATCH')
          s%side_patch(n) = val
          got(1) = .true.
        case ('SIDE')
          k = findloc(side_names, upper(val), dim=1)
          if (ndm == 2 .and. k > 5) k = 0
          if (k == 0) then
            call input_error(w, '*SURFACE: bad value SIDE='//shown(val)//' ('// &
                side_expected(val, ndm)//')')
            return
          end if
          s%side_code(n) = side_codes(k)
          got(2) = .true.
        case default
          call input_error(w, expect//', found "'//shown(toks(j)%s)//'" in field '//str(j))
          return
        end select
      end do
      if (.not. all(got)) then
        call input_error(w, expect//' (each line names one patch and one side)')
        return
      end if
      s%entry_where(n) = w
    end do
    do n = 2, size(s%side_code)
      do j = 1, n - 1
        if (upper(trim(s%side_patch(j))) == upper(trim(s%side_patch(n))) .and. &
            s%side_code(j) == s%side_code(n)) then
          call input_error(s%entry_where(n), '*SURFACE '//trim(s%name)//': side '// &
              trim(side_names(findloc(side_codes, s%side_code(n), dim=1)))//' of patch '// &
              trim(s%side_patch(n))//' is listed twice (first at '//trim(s%entry_where(j))//')')
          return
        end if
      end do
    end do
    s%patch = s%side_patch(1)
    s%side = s%side_code(1)
    ok = .true.
  end function read_surface_sides

  !> Data of *SURFACE, TYPE=ELEMENT: lines "element id or elset name, face": S1..S4 on the
  !! quadrilaterals of a 2D analysis, S1..S6 on the hexahedra of a 3D one (ndm).
  logical function read_surface_faces(c, rd, s, ndm) result(ok)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(surface_in_t), intent(inout) :: s
    integer, intent(in) :: ndm
    character(len=:), allocatable :: expect, w, face
    type(token_t), allocatable :: toks(:)
    integer :: i, n, m, id, nface
    logical :: is_int

    nface = merge(6, 4, ndm == 3)
    expect = '*SURFACE: expected "element id or element set, face S1..S'//str(nface)//'"'
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
      case ('S5', 'S6')
        if (ndm /= 3) then
          call input_error(w, '*SURFACE: face '//face//' in field 2: the quadrilaterals '// &
              'of a 2D analysis have the faces S1, S2, S3 and S4 (S5 and S6 are faces of '// &
              'the hexahedra of a 3D analysis, *ANALYSIS, TYPE=3D)')
          return
        end if
        s%face(n) = iachar(face(2:2)) - iachar('0')
      case default
        call input_error(w, '*SURFACE: unknown face "'//shown(toks(2)%s)// &
            '" in field 2 (expected '//trim(merge('S1, S2, S3, S4, S5 or S6', &
            'S1, S2, S3 or S4        ', ndm == 3))//')')
        return
      end select
      s%entry_where(n) = w
    end do
    ok = .true.
  end function read_surface_faces

  !> Index of set `name` of `kind` (created empty when new). A set of the other kind with the
  !! same name makes the new one a `twin`, settled by ictus_io_deck_interop once the deck is
  !! read (allowed when both hold the same nodes, as gmsh writes them).
  integer function set_index(d, name, kind, where) result(k)
    type(deck_t), intent(inout) :: d
    character(len=*), intent(in) :: name, where
    integer, intent(in) :: kind
    integer :: j
    logical :: twin
    twin = .false.
    do j = 1, d%n_sets
      if (d%sets(j)%name == name) then
        k = j
        if (d%sets(j)%kind == kind) return
        twin = .true.
      end if
    end do
    call grow_sets(d%sets, d%n_sets + 1)
    d%n_sets = d%n_sets + 1
    k = d%n_sets
    d%sets(k)%name = name
    d%sets(k)%kind = kind
    d%sets(k)%where = where
    d%sets(k)%twin = twin
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


  !> SIDE= of a patch side on card c: its position in XI0|XI1|ETA0|ETA1|ALL|ZETA0|ZETA1
  !! (side_names; ZETA0 and ZETA1 only in 3D, ndm = 3); 0 when absent or bad (a bad value is
  !! an error naming what is expected, side_expected).
  subroutine get_side(c, ndm, side)
    type(card_t), intent(inout) :: c
    integer, intent(in) :: ndm
    integer, intent(out) :: side
    character(len=:), allocatable :: v
    side = 0
    if (get_param(c, 'SIDE', v)) then
      if (is_zeta(v) .and. ndm == 2) then
        call card_error(c, 'bad value SIDE='//shown(v)//' ('//side_expected(v, ndm)//')')
        return
      end if
    end if
    call get_choice(c, 'SIDE', side_choices(ndm), side)
  end subroutine get_side

  !> The SIDE= values of a patch of dimension ndm, as get_choice takes them.
  function side_choices(ndm) result(list)
    integer, intent(in) :: ndm
    character(len=:), allocatable :: list
    list = 'XI0|XI1|ETA0|ETA1|ALL'
    if (ndm == 3) list = list//'|ZETA0|ZETA1'
  end function side_choices

  !> What a SIDE= value should be instead of v: ZETA0 and ZETA1 are sides of trivariate
  !! (3D) patches, which the patches of a 2D analysis are not.
  function side_expected(v, ndm) result(msg)
    character(len=*), intent(in) :: v
    integer, intent(in) :: ndm
    character(len=:), allocatable :: msg
    msg = 'expected one of XI0, XI1, ETA0, ETA1, ALL'
    if (ndm == 3) msg = 'expected one of XI0, XI1, ETA0, ETA1, ALL, ZETA0, ZETA1'
    if (is_zeta(v) .and. ndm == 2) msg = upper(v)//' is a side of a trivariate patch (3D); '// &
        'the patches of a 2D analysis have the sides XI0, XI1, ETA0, ETA1 (or ALL)'
  end function side_expected

  !> Whether v names a side of the third parametric direction.
  pure logical function is_zeta(v)
    character(len=*), intent(in) :: v
    is_zeta = upper(trim(adjustl(v))) == 'ZETA0' .or. upper(trim(adjustl(v))) == 'ZETA1'
  end function is_zeta
end module ictus_io_deck_model
