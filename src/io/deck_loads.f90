!> Readers of the load cards (doc/user-guide.md §5, deck format version 2): *AMPLITUDE (a
!! time function), *CLOAD (nodal forces) and *DLOAD (pressure on a surface, gravity on an
!! element set). They may stand in the model part or inside the step. Names (amplitudes,
!! sets, surfaces) are resolved by `check_deck` (ictus_io_deck_checks), the nodes, elements
!! and faces by `app/build_loads`.
module ictus_io_deck_loads
  use ictus_core_kinds, only: dp, str_len
  use ictus_core_errors, only: input_error
  use ictus_core_strings, only: str, upper
  use ictus_io_deck_lexer, only: token_t, line_where, split_values, split_fields, shown
  use ictus_io_deck_types, only: deck_t, amplitude_in_t, cload_in_t, dload_in_t, &
      DLOAD_PRESSURE, DLOAD_GRAV, AMP_DEF_TABULAR, AMP_DEF_SMOOTH_STEP
  use ictus_io_deck_card, only: card_t, reader_t, check_params, get_choice, get_name, &
      has_data, count_ok, tok_int, tok_real, tok_name, tok_target, stream_reals, &
      target_dof_value, LINE_STOP, LINE_SKIP
  use ictus_io_deck_grow, only: grow_amplitudes, grow_cloads, grow_dloads
  implicit none
  private
  public :: read_amplitude, read_cload, read_dload

contains

  !> *AMPLITUDE, NAME=name [, DEFINITION=TABULAR|SMOOTH STEP]: data "t1, a1, t2, a2, ..."
  !! over any number of lines, times increasing.
  subroutine read_amplitude(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = &
        '*AMPLITUDE: expected pairs "time, value" (times increasing)'
    type(amplitude_in_t) :: a
    real(dp), allocatable :: v(:)
    integer, allocatable :: tline(:)
    integer :: k, m
    call check_params(c, 'NAME|DEFINITION', '')
    call get_name(c, 'NAME', .true., a%name)
    call get_choice(c, 'DEFINITION', 'TABULAR|SMOOTH STEP', k)
    if (k == 2) a%definition = AMP_DEF_SMOOTH_STEP
    if (k == 1) a%definition = AMP_DEF_TABULAR
    if (c%bad) return
    if (.not. stream_reals(c, rd, expect, v, tline)) return
    m = size(v)
    if (mod(m, 2) /= 0) then
      call input_error(line_where(rd%src, tline(m)), expect//', found '//str(m)// &
          ' numbers (an odd count: the last time has no value)')
      return
    end if
    a%t = v(1:m:2)
    a%a = v(2:m:2)
    do k = 2, m/2
      if (.not. a%t(k) > a%t(k - 1)) then
        call input_error(line_where(rd%src, tline(2*k - 1)), '*AMPLITUDE '//trim(a%name)// &
            ': time '//str(a%t(k))//' does not increase (the time before it is '// &
            str(a%t(k - 1))//'; expected increasing times)')
        return
      end if
    end do
    a%where = c%where
    call grow_amplitudes(d%amplitudes, d%n_amplitudes + 1)
    d%n_amplitudes = d%n_amplitudes + 1
    d%amplitudes(d%n_amplitudes) = a
  end subroutine read_amplitude

  !> *CLOAD [, AMPLITUDE=name]: lines "node set or node id, dof, magnitude".
  subroutine read_cload(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = &
        '*CLOAD: expected "node set or node id, dof, magnitude"'
    type(cload_in_t) :: l
    character(len=:), allocatable :: w
    character(len=str_len) :: amp
    integer :: i
    call check_params(c, 'AMPLITUDE', '')
    call get_name(c, 'AMPLITUDE', .false., amp)
    if (c%bad) return
    if (.not. has_data(c, expect)) return
    do i = c%first, c%last
      w = line_where(rd%src, i)
      select case (target_dof_value(rd%src%lines(i)%text, '*CLOAD', expect, w, l%target, &
          l%dof, l%value, d%ndm))
      case (LINE_STOP)
        return
      case (LINE_SKIP)
        cycle
      end select
      l%amplitude = amp
      l%where = w
      l%card_where = c%where
      call grow_cloads(d%cloads, d%n_cloads + 1)
      d%n_cloads = d%n_cloads + 1
      d%cloads(d%n_cloads) = l
    end do
  end subroutine read_cload

  !> *DLOAD [, AMPLITUDE=name]: lines "surface, P, magnitude" (pressure) or
  !! "element set, GRAV, g, gx, gy[, gz]" (gravity; an empty element set is the whole model).
  subroutine read_dload(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*DLOAD: expected "surface, P, magnitude" or '// &
        '"element set, GRAV, g, gx, gy[, gz]"'
    type(dload_in_t) :: l
    type(token_t), allocatable :: toks(:)
    character(len=:), allocatable :: w, label
    character(len=str_len) :: amp
    integer :: i, n, k
    call check_params(c, 'AMPLITUDE', '')
    call get_name(c, 'AMPLITUDE', .false., amp)
    if (c%bad) return
    if (.not. has_data(c, expect)) return
    do i = c%first, c%last
      w = line_where(rd%src, i)
      call split_fields(rd%src%lines(i)%text, toks, n)
      if (.not. count_ok(n, 2, 6, expect, w)) return
      label = upper(toks(2)%s)
      l = dload_in_t()
      select case (label)
      case ('P')
        l%kind = DLOAD_PRESSURE
        if (.not. count_ok(n, 3, 3, '*DLOAD, P: expected "surface, P, magnitude"', w)) return
        if (len(toks(1)%s) == 0) then
          call input_error(w, '*DLOAD, P: expected "surface, P, magnitude", found no '// &
              'surface in field 1')
          return
        end if
        if (.not. tok_name(toks, 1, expect, w, l%target)) return
        if (.not. tok_real(toks, 3, expect, w, l%value)) return
      case ('GRAV')
        l%kind = DLOAD_GRAV
        if (.not. count_ok(n, 5, 6, '*DLOAD, GRAV: expected "element set, GRAV, g, gx, '// &
            'gy[, gz]"', w)) return
        if (len(toks(1)%s) > 0) then
          if (.not. tok_name(toks, 1, expect, w, l%target)) return
        end if
        if (.not. tok_real(toks, 3, expect, w, l%value)) return
        do k = 4, n
          if (.not. tok_real(toks, k, expect, w, l%dir(k - 3))) return
        end do
        if (l%dir(3) /= 0.0_dp .and. d%ndm == 2) then
          call input_error(w, '*DLOAD, GRAV: gz = '//str(l%dir(3))//' must be 0 (the '// &
              'model is 2D: the direction lies in the x-y plane; a 3D model needs *ANALYSIS, '// &
              'TYPE=3D)')
          cycle
        end if
        if (all(l%dir == 0.0_dp)) then
          call input_error(w, '*DLOAD, GRAV: the direction '//trim(merge( &
              '(gx, gy, gz) = (0, 0, 0)', '(gx, gy) = (0, 0)       ', d%ndm == 3))// &
              ' is zero (expected a non-zero direction; it is normalised)')
          cycle
        end if
      case default
        call input_error(w, expect//', found the load type "'//shown(toks(2)%s)// &
            '" in field 2 (ictus takes P on a surface and GRAV)')
        return
      end select
      l%amplitude = amp
      l%where = w
      l%card_where = c%where
      call grow_dloads(d%dloads, d%n_dloads + 1)
      d%n_dloads = d%n_dloads + 1
      d%dloads(d%n_dloads) = l
    end do
  end subroutine read_dload
end module ictus_io_deck_loads
