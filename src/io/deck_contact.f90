!> Readers of the contact cards (doc/user-guide.md §5, doc/contact.md): *CONTACT PAIR (two surfaces,
!! penalty, algorithm) and *RIGID WALL (a surface against a fixed line), both with an optional
!! INTERACTION= naming a *SURFACE INTERACTION, whose *FRICTION gives the Coulomb coefficient.
!! The surfaces and interactions they name are resolved by `check_deck`
!! (ictus_io_deck_checks), the contact itself is built by `app/build_contact`.
module ictus_io_deck_contact
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: upper
  use ictus_core_errors, only: input_error
  use ictus_io_deck_lexer, only: token_t, line_where, split_values, parse_real, shown
  use ictus_io_deck_types, only: deck_t, contact_pair_in_t, rigid_wall_in_t, &
      CONTACT_NODE_TO_SEGMENT, CONTACT_MORTAR, interaction_in_t
  use ictus_io_deck_card, only: card_t, reader_t, card_error, check_params, get_param, &
      get_name, get_choice, get_reals, get_positive, one_line, count_ok, tok_name, &
      no_data, line_reals, has_param
  use ictus_io_deck_grow, only: grow_pairs, grow_walls, grow_interactions
  implicit none
  private
  public :: read_contact_pair, read_rigid_wall, read_surface_interaction, read_friction, &
      read_tie

contains

  !> *CONTACT PAIR, NAME=, PENALTY=, [ALGORITHM=], [MASS PENALTY=AUTO|value],
  !! [INTERACTION=name], [TANGENTIAL PENALTY=value], [STABILITY=STOP|WARN]: one data line
  !! "first surface, second surface".
  subroutine read_contact_pair(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = &
        '*CONTACT PAIR: expected "first surface, second surface"'
    type(contact_pair_in_t) :: p
    character(len=:), allocatable :: v
    real(dp) :: x(1)
    integer :: kind
    logical :: ok

    call check_params(c, 'NAME|PENALTY|ALGORITHM|MASS PENALTY|INTERACTION|TANGENTIAL PENALTY|'// &
        'STABILITY', '')
    call get_name(c, 'NAME', .true., p%name)
    call get_positive(c, 'PENALTY', p%penalty)
    call get_interaction(c, p%interaction, p%tangential_penalty)
    call get_choice(c, 'ALGORITHM', 'TWO HALF PASS|NODE TO SEGMENT|MORTAR', kind)
    if (kind == 2) p%algorithm = CONTACT_NODE_TO_SEGMENT
    if (kind == 3) p%algorithm = CONTACT_MORTAR
    call get_choice(c, 'STABILITY', 'STOP|WARN', kind)
    p%stability_warn = kind == 2
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
    call add_pair(c, rd, d, p, expect)
  end subroutine read_contact_pair

  !> *TIE, NAME=, [PENALTY=]: one data line "first surface, second surface", glued by a
  !! MORTAR tie (doc/contact.md §4b); without PENALTY= the penalty is set from the time step
  !! (contact ratio r = 1/2).
  subroutine read_tie(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*TIE: expected "first surface, second surface"'
    type(contact_pair_in_t) :: p
    call check_params(c, 'NAME|PENALTY', '')
    call get_name(c, 'NAME', .true., p%name)
    if (has_param(c, 'PENALTY')) call get_positive(c, 'PENALTY', p%penalty)
    p%tie = .true.
    p%algorithm = CONTACT_MORTAR
    call add_pair(c, rd, d, p, expect)
  end subroutine read_tie

  !> Adds the contact pair or tie p of card c with its data line "first, second" (expect:
  !! the message for a bad line); names must differ from those of the earlier pairs.
  subroutine add_pair(c, rd, d, p, expect)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    type(contact_pair_in_t), intent(inout) :: p
    character(len=*), intent(in) :: expect
    type(token_t), allocatable :: toks(:)
    integer :: i, n, k
    do k = 1, d%n_pairs
      if (d%pairs(k)%name == p%name .and. len_trim(p%name) > 0) call card_error(c, &
          'duplicate contact pair or tie name '//trim(p%name)//' (first defined at '// &
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
  end subroutine add_pair

  !> *RIGID WALL, NAME=, POINT=x0,y0[,z0], NORMAL=nx,ny[,nz] (3 values in 3D), PENALTY=, [INTERACTION=name],
  !! [TANGENTIAL PENALTY=value], [STABILITY=STOP|WARN]: one data line "surface".
  subroutine read_rigid_wall(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*RIGID WALL: expected "surface"'
    type(rigid_wall_in_t) :: wl
    type(token_t), allocatable :: toks(:)
    integer :: i, n, k, kind

    call check_params(c, 'NAME|POINT|NORMAL|PENALTY|INTERACTION|TANGENTIAL PENALTY|STABILITY', &
        '')
    call get_name(c, 'NAME', .true., wl%name)
    call get_interaction(c, wl%interaction, wl%tangential_penalty)
    if (d%ndm == 3) then
      if (get_reals(c, 'POINT', 3, 'x0,y0,z0', wl%point, required=.true.)) continue
      if (get_reals(c, 'NORMAL', 3, 'nx,ny,nz', wl%normal, required=.true.)) then
        if (all(wl%normal == 0.0_dp)) call card_error(c, 'NORMAL=0,0,0 is zero (expected '// &
            'a non-zero direction nx,ny,nz pointing into the allowed side)')
      end if
    else
      if (get_reals(c, 'POINT', 2, 'x0,y0', wl%point(1:2), required=.true.)) continue
      if (get_reals(c, 'NORMAL', 2, 'nx,ny', wl%normal(1:2), required=.true.)) then
        if (all(wl%normal == 0.0_dp)) call card_error(c, 'NORMAL=0,0 is zero (expected '// &
            'a non-zero direction nx,ny pointing into the allowed side)')
      end if
    end if
    call get_positive(c, 'PENALTY', wl%penalty)
    call get_choice(c, 'STABILITY', 'STOP|WARN', kind)
    wl%stability_warn = kind == 2
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

  !> INTERACTION=name and TANGENTIAL PENALTY=value (> 0, only with INTERACTION=) of a
  !! *CONTACT PAIR or *RIGID WALL. Whether the interaction exists is checked by check_deck.
  subroutine get_interaction(c, name, eps_t)
    type(card_t), intent(inout) :: c
    character(len=*), intent(out) :: name
    real(dp), intent(out) :: eps_t
    character(len=:), allocatable :: v
    real(dp) :: x
    logical :: ok
    name = ''
    eps_t = 0.0_dp
    call get_name(c, 'INTERACTION', .false., name)
    if (.not. get_param(c, 'TANGENTIAL PENALTY', v)) return
    call parse_real(v, x, ok)
    if (.not. (ok .and. x > 0.0_dp)) then
      call card_error(c, 'bad value TANGENTIAL PENALTY='//shown(v)//' (expected a number > 0)')
    else if (len_trim(name) == 0) then
      call card_error(c, 'TANGENTIAL PENALTY= without INTERACTION= (the tangential penalty '// &
          'belongs to friction: expected INTERACTION=name of a *SURFACE INTERACTION with '// &
          '*FRICTION)')
    else
      eps_t = x
    end if
  end subroutine get_interaction

  !> *SURFACE INTERACTION, NAME=: no data lines; opens the interaction for the *FRICTION
  !! that follows.
  subroutine read_surface_interaction(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    type(interaction_in_t) :: si
    integer :: k
    rd%interaction = -1
    call check_params(c, 'NAME', '')
    call get_name(c, 'NAME', .true., si%name)
    call no_data(c, rd)
    do k = 1, d%n_interactions
      if (d%interactions(k)%name == si%name .and. len_trim(si%name) > 0) call card_error(c, &
          'duplicate surface interaction name '//trim(si%name)//' (first defined at '// &
          trim(d%interactions(k)%where)//')')
    end do
    if (c%bad) return
    si%where = c%where
    call grow_interactions(d%interactions, d%n_interactions + 1)
    d%n_interactions = d%n_interactions + 1
    d%interactions(d%n_interactions) = si
    rd%interaction = d%n_interactions
  end subroutine read_surface_interaction

  !> *FRICTION: one data line "mu" (>= 0), the Coulomb coefficient of the *SURFACE
  !! INTERACTION it follows.
  subroutine read_friction(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*FRICTION: expected 1 number (mu >= 0)'
    real(dp) :: v(1)
    integer :: i
    call check_params(c, '', '')
    if (rd%interaction == 0) then
      call card_error(c, 'outside a *SURFACE INTERACTION (expected *FRICTION right after '// &
          '*SURFACE INTERACTION, NAME=name)')
      return
    end if
    if (rd%interaction < 0) return
    associate (si => d%interactions(rd%interaction))
      if (si%mu >= 0.0_dp) then
        call card_error(c, 'second *FRICTION for surface interaction '//trim(si%name))
        return
      end if
      ! given (a bad data line is reported once, not again as a missing *FRICTION)
      si%mu = 0.0_dp
      if (c%bad) return
      if (.not. one_line(c, rd, expect, i)) return
      if (.not. line_reals(rd, i, 1, expect, v)) return
      if (.not. (v(1) >= 0.0_dp)) then
        call input_error(line_where(rd%src, i), '*FRICTION: the friction coefficient mu = '// &
            trim(rd%src%lines(i)%text)//' is negative (expected mu >= 0)')
        return
      end if
      si%mu = v(1)
    end associate
  end subroutine read_friction

end module ictus_io_deck_contact
