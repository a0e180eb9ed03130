!> Readers of the condition cards (doc/user-guide.md §5): *BOUNDARY (prescribed displacements,
!! or with AMPLITUDE= or TYPE=VELOCITY prescribed motion) and
!! *INITIAL CONDITIONS, TYPE=VELOCITY. Each data line names a node set or a node id; the
!! names are resolved by `check_deck` (ictus_io_deck_checks), the nodes by `app/build_model`.
module ictus_io_deck_conditions
  use ictus_core_kinds, only: dp
  use ictus_core_errors, only: input_error
  use ictus_core_strings, only: str
  use ictus_io_deck_lexer, only: token_t, line_where, split_values, split_fields
  use ictus_io_deck_types, only: deck_t, boundary_in_t, velocity_in_t, BC_DISPLACEMENT, &
      BC_VELOCITY
  use ictus_io_deck_card, only: card_t, reader_t, check_params, get_choice, get_name, &
      has_data, count_ok, tok_int, tok_real, tok_target, target_dof_value, dof_names, &
      LINE_STOP, LINE_SKIP
  use ictus_io_deck_grow, only: grow_boundaries, grow_velocities
  implicit none
  private
  public :: read_boundary, read_initial_conditions

contains

  !> *BOUNDARY [, AMPLITUDE=name] [, TYPE=DISPLACEMENT|VELOCITY]: lines "node set or node
  !! id, first dof, last dof[, value]"; the value (a displacement or a velocity) times the
  !! amplitude at time t.
  subroutine read_boundary(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = &
        '*BOUNDARY: expected "node set or node id, first dof, last dof[, value]"'
    ! An empty or absent last dof is the first dof, an empty value 0 (Abaqus).
    type(boundary_in_t) :: b
    type(token_t), allocatable :: toks(:)
    character(len=:), allocatable :: w
    integer :: i, n, kind

    call check_params(c, 'AMPLITUDE|TYPE', '')
    call get_name(c, 'AMPLITUDE', .false., b%amplitude)
    call get_choice(c, 'TYPE', 'DISPLACEMENT|VELOCITY', kind)
    b%kind = BC_DISPLACEMENT
    if (kind == 2) b%kind = BC_VELOCITY
    b%card_where = c%where
    if (c%bad) return
    if (.not. has_data(c, expect)) return
    do i = c%first, c%last
      w = line_where(rd%src, i)
      call split_fields(rd%src%lines(i)%text, toks, n)
      if (.not. count_ok(n, 2, 4, expect, w)) return
      if (.not. tok_target(toks, 1, expect, w, b%target)) return
      if (.not. tok_int(toks, 2, expect, w, b%first_dof)) return
      b%last_dof = b%first_dof
      if (n >= 3) then
        if (len(toks(3)%s) > 0) then
          if (.not. tok_int(toks, 3, expect, w, b%last_dof)) return
        end if
      end if
      b%value = 0.0_dp
      if (n == 4) then
        if (len(toks(4)%s) > 0) then
          if (.not. tok_real(toks, 4, expect, w, b%value)) return
        end if
      end if
      if (b%first_dof < 1 .or. b%first_dof > d%ndm .or. b%last_dof < 1 .or. &
          b%last_dof > d%ndm .or. b%first_dof > b%last_dof) then
        call input_error(w, '*BOUNDARY: dofs '//str(b%first_dof)//' to '// &
            str(b%last_dof)//': expected 1 <= first dof <= last dof <= '//str(d%ndm)// &
            ' ('//dof_names(d%ndm)//')')
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
    character(len=:), allocatable :: w
    integer :: i, kind

    call check_params(c, 'TYPE', '')
    call get_choice(c, 'TYPE', 'VELOCITY', kind, required=.true.)
    if (c%bad) return
    if (.not. has_data(c, expect)) return
    do i = c%first, c%last
      w = line_where(rd%src, i)
      select case (target_dof_value(rd%src%lines(i)%text, '*INITIAL CONDITIONS', expect, w, &
          v%target, v%dof, v%value, d%ndm))
      case (LINE_STOP)
        return
      case (LINE_SKIP)
        cycle
      end select
      v%where = w
      call grow_velocities(d%velocities, d%n_velocities + 1)
      d%n_velocities = d%n_velocities + 1
      d%velocities(d%n_velocities) = v
    end do
  end subroutine read_initial_conditions

end module ictus_io_deck_conditions
