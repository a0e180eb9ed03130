!> Readers of the contact cards (doc/user-guide.md §5, doc/contact.md): *CONTACT PAIR (two surfaces,
!! penalty, algorithm) and *RIGID WALL (a surface against a fixed line). The surfaces they
!! name are resolved by `check_deck` (ictus_io_deck_checks), the contact itself is built by
!! `app/build_contact`.
module ictus_io_deck_contact
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: upper
  use ictus_io_deck_lexer, only: token_t, line_where, split_values, parse_real, shown
  use ictus_io_deck_types, only: deck_t, contact_pair_in_t, rigid_wall_in_t, &
      CONTACT_NODE_TO_SEGMENT
  use ictus_io_deck_card, only: card_t, reader_t, card_error, check_params, get_param, &
      get_name, get_choice, get_reals, get_positive, one_line, count_ok, tok_name
  use ictus_io_deck_grow, only: grow_pairs, grow_walls
  implicit none
  private
  public :: read_contact_pair, read_rigid_wall

contains

  !> *CONTACT PAIR, NAME=, PENALTY=, [ALGORITHM=], [MASS PENALTY=AUTO|value],
  !! [STABILITY=STOP|WARN]: one data
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

    call check_params(c, 'NAME|PENALTY|ALGORITHM|MASS PENALTY|STABILITY', '')
    call get_name(c, 'NAME', .true., p%name)
    call get_positive(c, 'PENALTY', p%penalty)
    call get_choice(c, 'ALGORITHM', 'TWO HALF PASS|NODE TO SEGMENT', kind)
    if (kind == 2) p%algorithm = CONTACT_NODE_TO_SEGMENT
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

  !> *RIGID WALL, NAME=, POINT=x0,y0, NORMAL=nx,ny, PENALTY=, [STABILITY=STOP|WARN]: one
  !! data line "surface".
  subroutine read_rigid_wall(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*RIGID WALL: expected "surface"'
    type(rigid_wall_in_t) :: wl
    type(token_t), allocatable :: toks(:)
    integer :: i, n, k, kind

    call check_params(c, 'NAME|POINT|NORMAL|PENALTY|STABILITY', '')
    call get_name(c, 'NAME', .true., wl%name)
    if (get_reals(c, 'POINT', 2, 'x0,y0', wl%point, required=.true.)) continue
    if (get_reals(c, 'NORMAL', 2, 'nx,ny', wl%normal, required=.true.)) then
      if (all(wl%normal == 0.0_dp)) call card_error(c, 'NORMAL=0,0 is zero (expected '// &
          'a non-zero direction nx,ny pointing into the allowed side)')
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

end module ictus_io_deck_contact
