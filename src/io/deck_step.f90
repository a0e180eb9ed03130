!> Readers of the step cards (doc/user-guide.md §6): *STEP opens the single step, *DYNAMIC, EXPLICIT
!! sets its time step, end time and mass solver, *OUTPUT sets the history and field output,
!! *RESTART the checkpoints, and *END STEP closes it.
!!
!! `read_card` (ictus_io_deck_reader) lets these cards through only inside a step, and skips
!! a second (rejected) step up to its *END STEP; the flags in `reader_t` catch a card given
!! twice in the step.
module ictus_io_deck_step
  use ictus_core_kinds, only: dp
  use ictus_core_errors, only: input_error
  use ictus_core_strings, only: upper, str
  use ictus_io_deck_lexer, only: line_where, collapse_blanks, token_t, split_fields
  use ictus_io_deck_types, only: deck_t
  use ictus_io_deck_card, only: card_t, reader_t, card_error, check_params, get_param, &
      has_param, has_flag, get_choice, get_ints, get_reals, no_data, one_line, line_reals, &
      count_ok, tok_real
  implicit none
  private
  public :: read_step, read_dynamic, read_output, read_restart, read_end_step

contains

  !> *STEP [, NLGEOM=YES|NO]: opens the (single) step; NLGEOM=YES is finite strain (default
  !! NO, small strain).
  subroutine read_step(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    integer :: k
    call check_params(c, 'NLGEOM', '')
    call get_choice(c, 'NLGEOM', 'YES|NO', k)
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
    d%step%nlgeom = k == 1
  end subroutine read_step

  !> *DYNAMIC, EXPLICIT [, SAFETY=s] [, MASS SOLVER=CHOLESKY|CG|CORRECTOR] [, MASS TOL=tol]
  !! [, MASS PASSES=k] [, SWEEP STEPS=s|AUTO] [, INTERNAL FORCE=AUTO|ASSEMBLED|ELEMENT]: one
  !! data line "dt, t_end". MASS TOL is the
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
    character(len=*), parameter :: forces(3) = [character(len=9) :: 'AUTO', 'ASSEMBLED', &
        'ELEMENT']
    real(dp) :: v(2), s(1)
    integer :: i, k, np(1)
    logical :: tol_given, passes_given
    character(len=:), allocatable :: text, w
    type(token_t), allocatable :: toks(:)
    integer :: n

    call check_params(c, 'SAFETY|MASS TOL|MASS SOLVER|MASS PASSES|SWEEP STEPS|INTERNAL FORCE|'// &
        'ENERGY WARNING', 'EXPLICIT')
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
    if (get_reals(c, 'ENERGY WARNING', 1, 'a number in (0, 1]', s)) then
      if (.not. (s(1) > 0.0_dp .and. s(1) <= 1.0_dp)) then
        call card_error(c, 'ENERGY WARNING='//str(s(1))//' outside (0, 1] (the fraction of '// &
            'the largest energy the balance error may reach before the run warns)')
      else
        d%step%energy_warning = s(1)
      end if
    end if
    call get_choice(c, 'INTERNAL FORCE', 'AUTO|ASSEMBLED|ELEMENT', k)
    if (k > 0) d%step%internal_force = forces(k)
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
    w = line_where(rd%src, i)
    call split_fields(rd%src%lines(i)%text, toks, n)
    if (.not. count_ok(n, 2, 2, expect, w)) return
    v = 0.0_dp
    if (len(toks(1)%s) > 0) then
      if (.not. tok_real(toks, 1, expect, w, v(1))) return
    end if
    if (len(toks(2)%s) == 0) then
      call input_error(w, expect//': t_end has no default, found an empty field 2')
      return
    end if
    if (.not. tok_real(toks, 2, expect, w, v(2))) return
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

end module ictus_io_deck_step
