!> Builds the contact description (`contact_t`) of a model from the deck's *SURFACE,
!! *CONTACT PAIR and *RIGID WALL cards.
!!
!! Element surfaces: each entry "element id or element set, Sk" gives the face k of finite
!! elements (corner k to corner k+1); an element whose nodes run clockwise is reported as
!! inverted. Patch surfaces: PATCH=, SIDE= gives one rational Bezier segment per knot span of
!! the side, oriented counter-clockwise around the patch whatever the sign of det J.
!! Every problem is reported through `input_error` with its deck location.
module ictus_app_build_contact
  use ictus_core_kinds, only: dp, str_len
  use ictus_core_errors, only: input_error, warning, error_count
  use ictus_core_strings, only: str, upper
  use ictus_geometry_sides, only: side_name, SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, &
      SIDE_ZETA0, SIDE_ZETA1, SIDE_ALL
  use ictus_contact_surface, only: SEG_LAGRANGE, SEG_BEZIER, surface_init, face_segment, &
      element_area, patch_side_segments, contact_surface_t
  use ictus_contact_contact, only: contact_t, contact_init, contact_define_pair, &
      contact_define_wall, contact_setup, PAIR_TWO_HALF_PASS, PAIR_NODE_TO_SEGMENT, &
      contact_define_friction, PAIR_MORTAR, PAIR_TIE, contact_init3d
  use ictus_contact_face3d, only: surface3d_init, MAX_FACE_NODES
  use ictus_contact_volume_faces, only: volume_side_faces, VF_OK, VF_NO_SIDE, VF_DEGREE, &
      VF_COLLAPSED
  use ictus_solver_model, only: model_t, patch_nodes
  use ictus_elements_types, only: element_kind_t
  use ictus_elements_library, only: element_kind
  use ictus_io_deck_types, only: deck_t, surface_in_t, SURF_ELEMENT, SURF_PATCH, &
      CONTACT_NODE_TO_SEGMENT, CONTACT_MORTAR, CONTACT_TWO_HALF_PASS
  use ictus_app_build_model, only: resolve_elem_set, patch_index
  use ictus_app_id_map, only: id_map_t, id_map_init, id_map_find
  implicit none
  private
  public :: build_contact, build_named_surface, named_element_faces

contains

  !> Builds `c` from the deck's surfaces, contact pairs and rigid walls (pairs first, then
  !! walls, in deck order). Problems are reported through input_error; c is set up only if
  !! no new error was found.
  !! @param deck the deck; @param model the model built from it; @param c the contact
  subroutine build_contact(deck, model, c)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    type(contact_t), intent(inout) :: c
    type(id_map_t) :: emap
    integer :: i, k, n0, s1, s2, kind
    integer, allocatable :: fe_ids(:)
    character(len=str_len) :: name
    n0 = error_count()
    if (model%ndm == 3) then
      call build_contact3d(deck, model, c)
      return
    end if
    call contact_init(c, deck%n_surfaces, deck%n_pairs + deck%n_walls)
    c%node_id = model%node_id
    ! FE elements by user id (IGA elements get id -1, which no deck id matches)
    fe_ids = model%elem_id
    where (model%patch /= 0) fe_ids = -1
    call id_map_init(emap, fe_ids)
    do i = 1, deck%n_surfaces
      call build_surface(deck, model, emap, deck%surfaces(i), c%surfaces(i))
    end do
    do i = 1, deck%n_pairs
      associate (p => deck%pairs(i))
        s1 = surface_index(deck, p%first, p%where, '*CONTACT PAIR '//trim(p%name))
        s2 = surface_index(deck, p%second, p%where, '*CONTACT PAIR '//trim(p%name))
        if (s1 > 0 .and. s1 == s2) call input_error(p%where, '*CONTACT PAIR '// &
            trim(p%name)//': both surfaces are '//trim(p%first)// &
            ' (self-contact is not supported)')
        if (.not. (p%penalty > 0.0_dp) .and. .not. p%tie) call input_error(p%where, &
            '*CONTACT PAIR '//trim(p%name)//': PENALTY must be positive')
        kind = PAIR_TWO_HALF_PASS
        if (p%algorithm == CONTACT_NODE_TO_SEGMENT) kind = PAIR_NODE_TO_SEGMENT
        if (p%algorithm == CONTACT_MORTAR) kind = PAIR_MORTAR
        if (p%tie) kind = PAIR_TIE
        if (p%algorithm == CONTACT_MORTAR .and. p%mass_penalty >= 0.0_dp) call input_error( &
            p%where, '*CONTACT PAIR '//trim(p%name)//': MASS PENALTY (bipenalty) is not '// &
            'available with ALGORITHM=MORTAR; use TWO HALF PASS or NODE TO SEGMENT, or '// &
            'drop MASS PENALTY')
        name = p%name
        if (len_trim(name) == 0) name = 'pair'//str(i)
        call contact_define_pair(c, i, name, kind, p%penalty, max(s1, 1), max(s2, 1))
        c%pairs(i)%mass_penalty = p%mass_penalty
      end associate
    end do
    do i = 1, deck%n_walls
      k = deck%n_pairs + i
      associate (w => deck%walls(i))
        s1 = surface_index(deck, w%surface, w%where, '*RIGID WALL '//trim(w%name))
        if (.not. (w%penalty > 0.0_dp)) call input_error(w%where, '*RIGID WALL '// &
            trim(w%name)//': PENALTY must be positive')
        name = w%name
        if (len_trim(name) == 0) name = 'wall'//str(i)
        if (any(w%normal /= 0.0_dp)) then
          call contact_define_wall(c, k, name, w%point(1:2), w%normal(1:2), w%penalty, &
              max(s1, 1))
        else
          call input_error(w%where, '*RIGID WALL '//trim(w%name)//': NORMAL is zero')
        end if
      end associate
    end do
    call check_names(deck, c)
    if (error_count() == n0) call define_friction(deck, c)
    if (error_count() == n0 .and. c%nsurf > 0) then
      call contact_setup(c, model%x0)
      call check_ties(deck, c)
    end if
  end subroutine build_contact

  !> build_contact in 3D (doc/contact.md §9): the TYPE=ELEMENT surfaces as quadrilateral
  !! faces, the surfaces of the sides of trivariate patches as rational Bezier faces
  !! (volume_sides), the TWO HALF PASS pairs and the rigid walls between them. What 3D contact
  !! does not have yet is an input error at its card: other algorithms, *TIE, friction and
  !! bipenalty.
  subroutine build_contact3d(deck, model, c)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    type(contact_t), intent(inout) :: c
    type(id_map_t) :: emap
    integer, allocatable :: conn(:,:), nens(:), elem(:), deg(:,:)
    real(dp), allocatable :: ext1(:,:,:), ext2(:,:,:), wgt(:,:)
    integer :: i, k, n0, s1, s2, nface, kind
    character(len=str_len) :: name
    character(len=*), parameter :: not_yet = ': not yet in 3D (3D contact has ALGORITHM='// &
        'TWO HALF PASS and NODE TO SEGMENT pairs and rigid walls, frictionless, between '// &
        'element faces and patch sides)'
    n0 = error_count()
    call contact_init3d(c, deck%n_surfaces, deck%n_pairs + deck%n_walls)
    c%node_id = model%node_id
    call id_map_init(emap, model%elem_id)
    do i = 1, deck%n_surfaces
      associate (sin => deck%surfaces(i))
        if (sin%kind == SURF_PATCH) then
          call volume_sides(model, sin, nface, nens, conn, deg, ext1, ext2, wgt)
          call surface3d_init(c%d3%surfaces(i), nens, conn, model%x0, deg=deg, ext1=ext1, &
              ext2=ext2, wgt=wgt)
        else
          if (sin%kind /= SURF_ELEMENT) then
            allocate(nens(0), conn(9, 0))
          else
            call element_faces(deck, model, emap, sin, nface, conn, nens, elem)
            nens = nens(1:nface)
            conn = conn(:, 1:nface)
          end if
          call surface3d_init(c%d3%surfaces(i), nens, conn, model%x0)
        end if
        c%d3%names(i) = sin%name
        deallocate(nens, conn)
        if (allocated(elem)) deallocate(elem)
      end associate
    end do
    do i = 1, deck%n_pairs
      associate (p => deck%pairs(i))
        s1 = surface_index(deck, p%first, p%where, '*CONTACT PAIR '//trim(p%name))
        s2 = surface_index(deck, p%second, p%where, '*CONTACT PAIR '//trim(p%name))
        if (p%tie) then
          call input_error(p%where, '*TIE'//not_yet)
        else if (p%algorithm == CONTACT_MORTAR) then
          call input_error(p%where, '*CONTACT PAIR '//trim(p%name)//': ALGORITHM=MORTAR'// &
              not_yet)
        end if
        if (p%mass_penalty >= 0.0_dp) call input_error(p%where, '*CONTACT PAIR '// &
            trim(p%name)//': MASS PENALTY (bipenalty)'//not_yet)
        if (len_trim(p%interaction) > 0) call input_error(p%where, '*CONTACT PAIR '// &
            trim(p%name)//': INTERACTION= (friction)'//not_yet)
        if (s1 > 0 .and. s1 == s2) call input_error(p%where, '*CONTACT PAIR '// &
            trim(p%name)//': both surfaces are '//trim(p%first)// &
            ' (self-contact is not supported)')
        call check_surface3d(deck, c, s1, p%where, '*CONTACT PAIR '//trim(p%name))
        call check_surface3d(deck, c, s2, p%where, '*CONTACT PAIR '//trim(p%name))
        name = p%name
        if (len_trim(name) == 0) name = 'pair'//str(i)
        kind = PAIR_TWO_HALF_PASS
        if (p%algorithm == CONTACT_NODE_TO_SEGMENT) kind = PAIR_NODE_TO_SEGMENT
        call contact_define_pair(c, i, name, kind, p%penalty, max(s1, 1), max(s2, 1))
      end associate
    end do
    do i = 1, deck%n_walls
      k = deck%n_pairs + i
      associate (w => deck%walls(i))
        s1 = surface_index(deck, w%surface, w%where, '*RIGID WALL '//trim(w%name))
        if (len_trim(w%interaction) > 0) call input_error(w%where, '*RIGID WALL '// &
            trim(w%name)//': INTERACTION= (friction)'//not_yet)
        call check_surface3d(deck, c, s1, w%where, '*RIGID WALL '//trim(w%name))
        name = w%name
        if (len_trim(name) == 0) name = 'wall'//str(i)
        call contact_define_wall(c, k, name, w%point, w%normal, w%penalty, max(s1, 1))
      end associate
    end do
    call check_names(deck, c)
    if (error_count() == n0 .and. c%npairs > 0) call contact_setup(c)
  end subroutine build_contact3d

  !> A surface of a 3D contact (index s, 0: undefined, already reported) must have faces
  !! (element faces or faces of patch sides).
  subroutine check_surface3d(deck, c, s, where, card)
    type(deck_t), intent(in) :: deck
    type(contact_t), intent(in) :: c
    integer, intent(in) :: s
    character(len=*), intent(in) :: where, card
    if (s == 0) return
    if (c%d3%surfaces(s)%nface == 0) call input_error(where, card//': surface '// &
        trim(deck%surfaces(s)%name)//' has no '//trim(merge('element faces', &
        'faces        ', deck%surfaces(s)%kind == SURF_ELEMENT)))
  end subroutine check_surface3d

  !> The rational Bezier faces of the sides of trivariate patches of a 3D surface (PATCH=,
  !! SIDE= of the card and of its data lines), side after side (ictus_contact_volume_faces:
  !! one face per element on the side, a1 x a2 out of the patch). SIDE=ALL takes the six
  !! sides but the collapsed ones (a line or a point); a named side whose outward normal is
  !! undefined (collapsed, inverted or partly degenerate) is an input error at its line.
  subroutine volume_sides(model, sin, nface, nens, conn, deg, ext1, ext2, wgt)
    type(model_t), intent(in) :: model
    type(surface_in_t), intent(in) :: sin
    integer, intent(out) :: nface
    integer, allocatable, intent(out) :: nens(:), conn(:,:), deg(:,:)
    real(dp), allocatable, intent(out) :: ext1(:,:,:), ext2(:,:,:), wgt(:,:)
    integer, allocatable :: nens1(:), conn1(:,:), deg1(:,:), sc(:), sides(:)
    real(dp), allocatable :: ext11(:,:,:), ext21(:,:,:), wgt1(:,:)
    character(len=str_len), allocatable :: sp(:)
    character(len=:), allocatable :: w, what
    integer :: ip, ierr, k, j, n1
    call surface_entries(sin, sp, sc)
    nface = 0
    allocate(nens(0), conn(MAX_FACE_NODES, 0), deg(2, 0), ext1(4, 4, 0), ext2(4, 4, 0), &
        wgt(MAX_FACE_NODES, 0))
    do k = 1, size(sc)
      ip = entry_patch(model, sin, sp(k), k, w)
      if (ip == 0) cycle
      sides = [sc(k)]
      if (sc(k) == SIDE_ALL) sides = [SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ZETA0, &
          SIDE_ZETA1]
      do j = 1, size(sides)
        call volume_side_faces(model%volumes(ip), sides(j), patch_nodes(model, ip), n1, &
            nens1, conn1, deg1, ext11, ext21, wgt1, ierr)
        if (ierr == VF_COLLAPSED .and. sc(k) == SIDE_ALL) cycle
        if (ierr /= VF_OK) then
          select case (ierr)
          case (VF_NO_SIDE)
            what = 'patch side '//side_name(sides(j))//' does not exist (expected XI0, '// &
                'XI1, ETA0, ETA1, ZETA0, ZETA1 or ALL)'
          case (VF_DEGREE)
            what = 'contact faces of degree above 3 are not supported (side '// &
                side_name(sides(j))//' of patch '//trim(sp(k))//'; a 3D contact face is '// &
                'at most bicubic)'
          case (VF_COLLAPSED)
            what = 'side '//side_name(sides(j))//' of patch '//trim(sp(k))//' is '// &
                'collapsed (a line or a point: det J vanishes on it), so it has no outward '// &
                'normal and cannot be a contact surface'
          case default
            what = 'the Jacobian of patch '//trim(sp(k))//' vanishes or changes sign on '// &
                'side '//side_name(sides(j))//', so the outward normal is undefined '// &
                '(inverted or degenerate patch)'
          end select
          call input_error(w, '*SURFACE '//trim(sin%name)//': '//what)
          cycle
        end if
        nens = [nens, nens1]
        conn = reshape([conn, conn1], [MAX_FACE_NODES, nface + n1])
        deg = reshape([deg, deg1], [2, nface + n1])
        ext1 = reshape([ext1, ext11], [4, 4, nface + n1])
        ext2 = reshape([ext2, ext21], [4, 4, nface + n1])
        wgt = reshape([wgt, wgt1], [MAX_FACE_NODES, nface + n1])
        nface = nface + n1
      end do
    end do
  end subroutine volume_sides

  !> The (patch, side) entries of a PATCH= surface: the card's, or its data lines'.
  subroutine surface_entries(sin, sp, sc)
    type(surface_in_t), intent(in) :: sin
    character(len=str_len), allocatable, intent(out) :: sp(:)
    integer, allocatable, intent(out) :: sc(:)
    if (allocated(sin%side_code)) then
      sp = sin%side_patch
      sc = sin%side_code
    else
      sp = [sin%patch]
      sc = [sin%side]
    end if
  end subroutine surface_entries

  !> The patch of entry k (patch name sp) of a PATCH= surface, 0 (and an error) when
  !! undefined; w: the entry's deck location.
  integer function entry_patch(model, sin, sp, k, w) result(ip)
    type(model_t), intent(in) :: model
    type(surface_in_t), intent(in) :: sin
    character(len=*), intent(in) :: sp
    integer, intent(in) :: k
    character(len=:), allocatable, intent(out) :: w
    w = trim(sin%where)
    if (allocated(sin%side_code)) w = trim(sin%entry_where(k))
    ip = patch_index(model, sp)
    if (ip == 0) call input_error(w, '*SURFACE '//trim(sin%name)//': patch '// &
        trim(sp)//' is not defined by a *PATCH card')
  end function entry_patch

  !> Every *TIE must tie something: an input error when no point of its first surface lies
  !! on the second (within 5 % of the longest segment), a warning naming the count when
  !! some do not.
  subroutine check_ties(deck, c)
    type(deck_t), intent(in) :: deck
    type(contact_t), intent(in) :: c
    integer :: i
    do i = 1, deck%n_pairs
      if (.not. deck%pairs(i)%tie) cycle
      associate (p => deck%pairs(i), mo => c%pairs(i)%mo)
        if (mo%n == 0) then
          call input_error(p%where, '*TIE '//trim(p%name)//': no point of surface '// &
              trim(p%first)//' lies on surface '//trim(p%second)//' (within 5 % of the '// &
              'longest segment); tied surfaces must lie on each other')
        else if (mo%untied > 0) then
          call warning(p%where, '*TIE '//trim(p%name)//': '//str(mo%untied)//' of '// &
              str(mo%n + mo%untied)//' integration points of surface '//trim(p%first)// &
              ' lie off surface '//trim(p%second)//' and are not tied')
        end if
      end associate
    end do
  end subroutine check_ties

  !> Coulomb friction of the pairs and walls with INTERACTION= (mu of its *FRICTION; the
  !! tangential penalty TANGENTIAL PENALTY=, by default the pair's PENALTY).
  subroutine define_friction(deck, c)
    type(deck_t), intent(in) :: deck
    type(contact_t), intent(inout) :: c
    integer :: i
    do i = 1, deck%n_pairs
      call friction_of(deck, c, i, deck%pairs(i)%interaction, &
          deck%pairs(i)%tangential_penalty)
    end do
    do i = 1, deck%n_walls
      call friction_of(deck, c, deck%n_pairs + i, deck%walls(i)%interaction, &
          deck%walls(i)%tangential_penalty)
    end do
  end subroutine define_friction

  !> Friction of pair k from the *SURFACE INTERACTION `name` (none when blank).
  subroutine friction_of(deck, c, k, name, eps_t)
    type(deck_t), intent(in) :: deck
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: k
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: eps_t
    integer :: j
    if (len_trim(name) == 0) return
    do j = 1, deck%n_interactions
      if (deck%interactions(j)%name == name) call contact_define_friction(c, k, &
          deck%interactions(j)%mu, eps_t)
    end do
  end subroutine friction_of

  !> Pair and wall names must differ (they name groups of the results file).
  subroutine check_names(deck, c)
    type(deck_t), intent(in) :: deck
    type(contact_t), intent(in) :: c
    integer :: i, j
    do i = 1, deck%n_walls
      do j = 1, deck%n_pairs
        if (c%pairs(deck%n_pairs + i)%name == c%pairs(j)%name) call input_error( &
            deck%walls(i)%where, '*RIGID WALL '//trim(deck%walls(i)%name)// &
            ': the name is already used by the *CONTACT PAIR at '//trim(deck%pairs(j)%where))
      end do
    end do
  end subroutine check_names

  !> Index of surface `name` in the deck, 0 (and an error) when undefined.
  integer function surface_index(deck, name, where, card) result(idx)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: name, where, card
    integer :: i
    idx = 0
    do i = 1, deck%n_surfaces
      if (upper(trim(deck%surfaces(i)%name)) == upper(trim(name))) then
        idx = i
        return
      end if
    end do
    call input_error(where, card//': surface '//trim(name)//' is not defined by a '// &
        '*SURFACE card')
  end function surface_index

  !> Builds the surface `name` of the deck (for a load: *DLOAD, P) into `surf`; an undefined
  !! name is reported at `where` for `card`.
  subroutine build_named_surface(deck, model, name, where, card, surf)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    character(len=*), intent(in) :: name, where, card
    type(contact_surface_t), intent(inout) :: surf
    type(id_map_t) :: emap
    integer, allocatable :: fe_ids(:)
    integer :: i
    i = surface_index(deck, name, where, card)
    if (i == 0) return
    fe_ids = model%elem_id
    where (model%patch /= 0) fe_ids = -1
    call id_map_init(emap, fe_ids)
    call build_surface(deck, model, emap, deck%surfaces(i), surf)
  end subroutine build_named_surface

  !> The faces of the TYPE=ELEMENT surface `name` of a 3D model (the pressure of *DLOAD, P):
  !! nface faces, their global nodes conn(:, 1:nface) in the order of the element
  !! description's face lists (nfn(k) = 4, 8 or 9 nodes). Problems are reported at `where`
  !! (card: the card that names the surface).
  subroutine named_element_faces(deck, model, name, where, card, nface, conn, nfn)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    character(len=*), intent(in) :: name, where, card
    integer, intent(out) :: nface
    integer, allocatable, intent(out) :: conn(:,:), nfn(:)
    type(id_map_t) :: emap
    integer, allocatable :: elem(:)
    integer :: i, n0
    nface = 0
    allocate(conn(9, 0), nfn(0))
    i = surface_index(deck, name, where, card)
    if (i == 0) return
    call id_map_init(emap, model%elem_id)
    n0 = error_count()
    call element_faces(deck, model, emap, deck%surfaces(i), nface, conn, nfn, elem)
    if (nface == 0 .and. error_count() == n0) call input_error(deck%surfaces(i)%where, &
        '*SURFACE '//trim(deck%surfaces(i)%name)//' has no element faces')
  end subroutine named_element_faces

  !> Builds the surface of deck record `sin` into `surf`.
  subroutine build_surface(deck, model, emap, sin, surf)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    type(id_map_t), intent(in) :: emap
    type(surface_in_t), intent(in) :: sin
    type(contact_surface_t), intent(inout) :: surf
    integer, allocatable :: conn(:,:), nens(:), elem(:), kinds(:)
    real(dp), allocatable :: wgt(:,:), ext(:,:,:)
    integer :: nseg, n0
    if (sin%kind == SURF_PATCH) then
      n0 = error_count()
      call patch_sides(model, sin, nseg, nens, conn, wgt, ext, elem)
      if (error_count() > n0) return
      allocate(kinds(nseg))
      kinds = SEG_BEZIER
      call surface_init(surf, sin%name, kinds, nens, conn, model%x0, wgt=wgt, &
          ext=ext, elem=elem)
    else if (sin%kind == SURF_ELEMENT) then
      n0 = error_count()
      call element_faces(deck, model, emap, sin, nseg, conn, nens, elem)
      if (nseg == 0 .and. error_count() == n0) then
        call input_error(sin%where, '*SURFACE '//trim(sin%name)//' has no element faces')
        return
      end if
      allocate(kinds(nseg))
      kinds = SEG_LAGRANGE
      call surface_init(surf, sin%name, kinds, nens(1:nseg), conn(:, 1:nseg), &
          model%x0, elem=elem(1:nseg))
    end if
  end subroutine build_surface

  !> The rational Bezier segments of the patch sides of a surface (PATCH=, SIDE= of the card
  !! and of its data lines), side after side: nodes per segment, global nodes (:, nseg),
  !! weights, extraction operators and model elements.
  subroutine patch_sides(model, sin, nseg, nens, conn, wgt, ext, elem)
    type(model_t), intent(in) :: model
    type(surface_in_t), intent(in) :: sin
    integer, intent(out) :: nseg
    integer, allocatable, intent(out) :: nens(:), conn(:,:), elem(:)
    real(dp), allocatable, intent(out) :: wgt(:,:), ext(:,:,:)
    integer, allocatable :: nens1(:), conn1(:,:), elem1(:), sc(:)
    real(dp), allocatable :: wgt1(:,:), ext1(:,:,:)
    character(len=str_len), allocatable :: sp(:)
    character(len=:), allocatable :: w
    integer :: ip, ierr, e0, k, m, nm, n1, pmax
    call surface_entries(sin, sp, sc)
    pmax = 1
    m = 0
    do k = 1, size(sc)
      ip = patch_index(model, sp(k))
      if (ip == 0) cycle
      pmax = max(pmax, maxval(model%patches(ip)%p))
      m = m + 2*sum(model%patches(ip)%nel)
    end do
    nm = pmax + 1
    allocate(nens(m), conn(nm, m), wgt(nm, m), ext(nm, nm, m), elem(m))
    conn = 0
    wgt = 1.0_dp
    ext = 0.0_dp
    nseg = 0
    do k = 1, size(sc)
      ip = entry_patch(model, sin, sp(k), k, w)
      if (ip == 0) cycle
      call patch_side_segments(model%patches(ip), model%patch_offset(ip), sc(k), n1, &
          nens1, conn1, wgt1, ext1, elem1, ierr, node=patch_nodes(model, ip))
      if (ierr == 1) then
        call input_error(w, '*SURFACE '//trim(sin%name)//': patch side '// &
            side_name(sc(k))//' does not exist (expected XI0, XI1, ETA0, ETA1 or ALL)')
        cycle
      else if (ierr == 2) then
        call input_error(w, '*SURFACE '//trim(sin%name)//': the Jacobian of patch '//&
            trim(sp(k))//' vanishes or changes sign along side '//side_name(sc(k))// &
            ', so the outward normal is undefined (inverted or degenerate patch)')
        cycle
      end if
      e0 = findloc(model%patch, ip, dim=1) - 1
      nens(nseg+1:nseg+n1) = nens1
      conn(1:size(conn1, 1), nseg+1:nseg+n1) = conn1
      wgt(1:size(wgt1, 1), nseg+1:nseg+n1) = wgt1
      ext(1:size(ext1, 1), 1:size(ext1, 2), nseg+1:nseg+n1) = ext1
      elem(nseg+1:nseg+n1) = elem1 + e0
      nseg = nseg + n1
    end do
    nens = nens(1:nseg)
    conn = conn(:, 1:nseg)
    wgt = wgt(:, 1:nseg)
    ext = ext(:, :, 1:nseg)
    elem = elem(1:nseg)
  end subroutine patch_sides

  !> Faces of a TYPE=ELEMENT surface: node lists (3, nseg) in 2D (the edge segments of
  !! face_segment), the quadrilateral faces (9, nseg) of the hexahedra in 3D; nodes per face,
  !! elements.
  subroutine element_faces(deck, model, emap, sin, nseg, conn, nens, elem)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    type(id_map_t), intent(in) :: emap
    type(surface_in_t), intent(in) :: sin
    integer, intent(out) :: nseg
    integer, allocatable, intent(out) :: conn(:,:), nens(:), elem(:)
    logical, allocatable :: mask(:), used(:,:)
    integer :: k, e, nf
    nf = merge(6, 4, model%ndm == 3)
    allocate(conn(merge(9, 3, model%ndm == 3), nf*model%nel), nens(nf*model%nel), &
        elem(nf*model%nel), mask(model%nel), used(nf, model%nel))
    used = .false.
    nseg = 0
    do k = 1, size(sin%face)
      if (len_trim(sin%elset(k)) > 0) then
        mask = .false.
        call resolve_elem_set(deck, model, sin%elset(k), sin%entry_where(k), mask, 0)
        do e = 1, model%nel
          if (mask(e)) call add_face(e, k)
        end do
      else
        e = id_map_find(emap, sin%elem(k))
        if (e == 0) then
          call input_error(sin%entry_where(k), '*SURFACE '//trim(sin%name)//': element '// &
              str(sin%elem(k))//' is not defined by an *ELEMENT card')
        else
          call add_face(e, k)
        end if
      end if
    end do
  contains
    subroutine add_face(ee, kk)
      integer, intent(in) :: ee, kk
      integer :: f, nfn
      real(dp) :: area
      type(element_kind_t) :: kd
      f = sin%face(kk)
      if (model%patch(ee) /= 0) then
        call input_error(sin%entry_where(kk), '*SURFACE '//trim(sin%name)//': element '// &
            str(model%elem_id(ee))//' of patch '//trim(model%patches(model%patch(ee))%name)// &
            ' has no element faces (use *SURFACE, PATCH=, SIDE=)')
        return
      end if
      if (used(f, ee)) then
        call warning(sin%entry_where(kk), '*SURFACE '//trim(sin%name)//': face S'//str(f)// &
            ' of element '//str(model%elem_id(ee))//' is listed twice; counted once')
        return
      end if
      used(f, ee) = .true.
      if (model%ndm == 3) then
        ! a face of a hexahedron (S1..S6), its nodes as the element description lists them
        kd = element_kind(model%etype(ee))
        nseg = nseg + 1
        conn(1:kd%nfn, nseg) = model%conn(kd%face(1:kd%nfn, f), ee)
        nens(nseg) = kd%nfn
        elem(nseg) = ee
        return
      end if
      area = element_area(model%etype(ee), model%x0(:, model%conn(1:model%nen(ee), ee)))
      if (.not. (area > 0.0_dp)) then
        call input_error(sin%entry_where(kk), '*SURFACE '//trim(sin%name)//': element '// &
            str(model%elem_id(ee))//' is inverted (its nodes run clockwise, area '// &
            str(area)//'), so the outward normal of face S'//str(f)//' is undefined')
        return
      end if
      nseg = nseg + 1
      call face_segment(model%etype(ee), model%conn(:, ee), f, conn(:, nseg), nfn)
      nens(nseg) = nfn
      elem(nseg) = ee
      if (nfn == 0) then
        call input_error(sin%entry_where(kk), '*SURFACE '//trim(sin%name)//': element '// &
            str(model%elem_id(ee))//' has no face S'//str(f))
        nseg = nseg - 1
      end if
    end subroutine add_face
  end subroutine element_faces
end module ictus_app_build_contact
