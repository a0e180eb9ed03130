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
  use ictus_io_deck_types, only: deck_t, out_set_in_t
  use ictus_solver_model, only: NVAR, VAR_NAMES, VAR_U, VAR_V, VAR_RF
  use ictus_io_deck_card, only: card_t, reader_t, card_error, check_params, get_param, &
      get_name, has_param, has_flag, get_choice, get_ints, get_reals, no_data, one_line, &
      line_reals, count_ok, tok_real
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

  !> *OUTPUT, HISTORY|FIELD [, EVERY=n | TIME INTERVAL=dt_out] [, VARIABLES=v1,v2,...]
  !! [, NSET=name (HISTORY)] [, SAMPLES=s (FIELD)]. A HISTORY card without NSET sets the
  !! history records (energies, contact); one with NSET adds a node set whose means and sums
  !! are written at those records; FIELD sets the snapshots and their variables.
  subroutine read_output(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    logical :: history, field

    call merge_variables(c)
    call check_params(c, 'EVERY|SAMPLES|TIME INTERVAL|VARIABLES|NSET', 'HISTORY|FIELD')
    call no_data(c, rd)
    history = has_flag(c, 'HISTORY')
    field = has_flag(c, 'FIELD')
    if (history .eqv. field) then
      call card_error(c, 'expected exactly one of HISTORY or FIELD')
      return
    end if
    if (has_param(c, 'EVERY') .and. has_param(c, 'TIME INTERVAL')) call card_error(c, &
        'EVERY= and TIME INTERVAL= given together (expected one of them: a number of '// &
        'steps, or a time between outputs)')
    if (field) then
      if (has_param(c, 'NSET')) call card_error(c, 'NSET= goes with *OUTPUT, HISTORY '// &
          '(the history of a node set), not with FIELD')
      call read_field_output(c, rd, d)
      return
    end if
    if (has_param(c, 'SAMPLES')) call card_error(c, 'SAMPLES= goes with *OUTPUT, FIELD '// &
        '(viewing samples of NURBS elements), not with HISTORY')
    if (has_param(c, 'NSET')) then
      call read_set_history(c, d)
      return
    end if
    if (has_param(c, 'VARIABLES')) call card_error(c, 'VARIABLES= goes with *OUTPUT, '// &
        'HISTORY, NSET=name (the means and sums of a node set: U, V, RF) or with *OUTPUT, '// &
        'FIELD; the history without NSET holds the energies and the contact resultants')
    if (rd%has_history) call card_error(c, 'a second *OUTPUT, HISTORY in the step')
    rd%has_history = .true.
    d%step%history_where = c%where
    call read_every(c, 1, d%step%history_every)
    call read_interval(c, d%step%history_interval)
  end subroutine read_output

  !> *OUTPUT, FIELD: EVERY= (0 = 20 snapshots) or TIME INTERVAL=, SAMPLES=, VARIABLES=.
  subroutine read_field_output(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    integer :: n(1)
    logical :: allowed(NVAR)
    if (rd%has_field) call card_error(c, 'a second *OUTPUT, FIELD in the step')
    rd%has_field = .true.
    call read_every(c, 0, d%step%field_every)
    call read_interval(c, d%step%field_interval)
    if (get_ints(c, 'SAMPLES', 1, 'an integer s in [2, 21]', n)) then
      if (n(1) < 2 .or. n(1) > 21) then
        call card_error(c, 'SAMPLES='//str(n(1))//' must lie in [2, 21] (viewing '// &
            'samples per direction of each NURBS element)')
      else
        d%step%field_samples = n(1)
      end if
    end if
    allowed = .true.
    call read_variables(c, allowed, 'FIELD', d%step%field_vars, d%step%field_vars_given)
    d%step%field_where = c%where
  end subroutine read_field_output

  !> *OUTPUT, HISTORY, NSET=name [, VARIABLES=U,V,RF] [, EVERY= | TIME INTERVAL=]: one node
  !! set per card; its records go with the history records.
  subroutine read_set_history(c, d)
    type(card_t), intent(inout) :: c
    type(deck_t), intent(inout) :: d
    type(out_set_in_t) :: o
    logical :: allowed(NVAR)
    integer :: k
    call get_name(c, 'NSET', .true., o%name)
    if (len_trim(o%name) == 0) return
    if (.not. allocated(d%step%out_sets)) allocate(d%step%out_sets(0))
    do k = 1, d%step%n_out_sets
      if (d%step%out_sets(k)%name == o%name) then
        call card_error(c, 'a second *OUTPUT, HISTORY for node set '//trim(o%name)// &
            ' (first at '//trim(d%step%out_sets(k)%where)//'; expected one card per set)')
        return
      end if
    end do
    allowed = .false.
    allowed([VAR_U, VAR_V, VAR_RF]) = .true.
    call read_variables(c, allowed, 'HISTORY, NSET=', o%vars, o%vars_given)
    if (.not. o%vars_given) o%vars(VAR_U) = .true.
    if (.not. o%vars_given) o%vars([VAR_V, VAR_RF]) = .true.
    if (has_param(c, 'EVERY')) call read_every(c, 1, o%every)
    call read_interval(c, o%interval)
    o%where = c%where
    d%step%out_sets = [d%step%out_sets, o]
    d%step%n_out_sets = d%step%n_out_sets + 1
  end subroutine read_set_history

  !> EVERY=n into `every` when given: n >= 1, or n >= 0 where `least` = 0 (0 = 20 snapshots).
  subroutine read_every(c, least, every)
    type(card_t), intent(inout) :: c
    integer, intent(in) :: least
    integer, intent(inout) :: every
    integer :: n(1)
    if (least == 0) then
      if (.not. get_ints(c, 'EVERY', 1, 'an integer n >= 1 (0 = 20 snapshots)', n)) return
      if (n(1) < 0) then
        call card_error(c, 'EVERY='//str(n(1))//' must be >= 1 (or 0 = 20 snapshots)')
        return
      end if
    else
      if (.not. get_ints(c, 'EVERY', 1, 'an integer n >= 1', n)) return
      if (n(1) < 1) then
        call card_error(c, 'EVERY='//str(n(1))//' must be >= 1')
        return
      end if
    end if
    every = n(1)
  end subroutine read_every

  !> TIME INTERVAL=dt_out into `interval` when given (a time > 0).
  subroutine read_interval(c, interval)
    type(card_t), intent(inout) :: c
    real(dp), intent(inout) :: interval
    real(dp) :: x(1)
    if (.not. get_reals(c, 'TIME INTERVAL', 1, 'a time > 0', x)) return
    if (.not. x(1) > 0.0_dp) then
      call card_error(c, 'TIME INTERVAL='//str(x(1))//' must be > 0 (the time between '// &
          'outputs; or EVERY=n steps)')
    else
      interval = x(1)
    end if
  end subroutine read_interval

  !> VARIABLES=v1,v2,... into `vars` (VAR_* of ictus_solver_model), `given` when present.
  !! Each name must be one of VAR_NAMES and `allowed` for the card (described by `what`).
  subroutine read_variables(c, allowed, what, vars, given)
    type(card_t), intent(inout) :: c
    logical, intent(in) :: allowed(NVAR)
    character(len=*), intent(in) :: what
    logical, intent(inout) :: vars(NVAR)
    logical, intent(out) :: given
    character(len=:), allocatable :: text, name
    integer :: pos, k, j
    given = get_param(c, 'VARIABLES', text)
    if (.not. given) return
    vars = .false.
    pos = 1
    do while (pos <= len(text))
      k = index(text(pos:), ',')
      if (k == 0) k = len(text) - pos + 2
      name = upper(collapse_blanks(trim(adjustl(text(pos:pos + k - 2)))))
      pos = pos + k
      if (len(name) == 0) cycle
      j = 1
      do while (j <= NVAR)
        if (trim(VAR_NAMES(j)) == name) exit
        j = j + 1
      end do
      if (j > NVAR) then
        call card_error(c, 'unknown variable '//name//' in VARIABLES= (expected some of '// &
            var_list([(.true., k = 1, NVAR)])//')')
      else if (.not. allowed(j)) then
        call card_error(c, 'variable '//name//' does not go with *OUTPUT, '//what// &
            ' (expected some of '//var_list(allowed)//')')
      else
        vars(j) = .true.
      end if
    end do
  end subroutine read_variables

  !> The names of the variables `mask` selects, as "U, V, RF".
  pure function var_list(mask) result(r)
    logical, intent(in) :: mask(NVAR)
    character(len=:), allocatable :: r
    integer :: j
    r = ''
    do j = 1, NVAR
      if (.not. mask(j)) cycle
      if (len(r) > 0) r = r//', '
      r = r//trim(VAR_NAMES(j))
    end do
  end function var_list

  !> VARIABLES=U,V,S: the keyword lexer reads the names after the first as bare words (flags);
  !! they are joined to the value of VARIABLES= here, up to the next NAME=value parameter
  !! (HISTORY and FIELD stay flags).
  subroutine merge_variables(c)
    type(card_t), intent(inout) :: c
    logical, allocatable :: keep(:)
    integer :: k, j
    allocate(keep(c%kw%n_params), source=.true.)
    do k = 1, c%kw%n_params
      if (c%kw%params(k)%name /= 'VARIABLES' .or. c%kw%params(k)%is_flag) cycle
      do j = k + 1, c%kw%n_params
        associate (p => c%kw%params(j))
          if (.not. p%is_flag) exit
          if (p%name == 'HISTORY' .or. p%name == 'FIELD') cycle
          c%kw%params(k)%value = c%kw%params(k)%value//','//p%name
          keep(j) = .false.
        end associate
      end do
      exit
    end do
    c%kw%params = pack(c%kw%params(1:c%kw%n_params), keep)
    c%kw%n_params = size(c%kw%params)
  end subroutine merge_variables

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
    call check_set_schedules(d)
  end subroutine read_end_step

  !> The records of a node set are written with the history records: EVERY= or TIME
  !! INTERVAL= on an *OUTPUT, HISTORY, NSET= card must be those of the history.
  subroutine check_set_schedules(d)
    type(deck_t), intent(in) :: d
    character(len=:), allocatable :: mine, global
    integer :: k
    if (d%step%history_interval > 0.0_dp) then
      global = 'TIME INTERVAL='//str(d%step%history_interval)
    else
      global = 'EVERY='//str(d%step%history_every)
    end if
    if (len_trim(d%step%history_where) > 0) then
      global = global//' of *OUTPUT, HISTORY at '//trim(d%step%history_where)
    else
      global = global//', the default'
    end if
    do k = 1, d%step%n_out_sets
      associate (o => d%step%out_sets(k))
        if (o%every > 0 .and. (o%every /= d%step%history_every .or. &
            d%step%history_interval > 0.0_dp)) then
          mine = 'EVERY='//str(o%every)
        else if (o%interval > 0.0_dp .and. o%interval /= d%step%history_interval) then
          mine = 'TIME INTERVAL='//str(o%interval)
        else
          cycle
        end if
        call input_error(o%where, '*OUTPUT, HISTORY, NSET='//trim(o%name)//': '//mine// &
            ' differs from the history records ('//global//'); the records of a node set'// &
            ' are written with the history records (expected no EVERY= or TIME INTERVAL='// &
            ' here, or the same as on *OUTPUT, HISTORY without NSET)')
      end associate
    end do
  end subroutine check_set_schedules

end module ictus_io_deck_step
