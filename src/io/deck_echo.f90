!> The processed deck written back as deck text, in canonical form with every default
!! explicit (for the log, the results file, and the reader's round-trip test).
!!
!! Cards come in a fixed order (heading, analysis, materials, nodes, elements, patches,
!! patch operations, sets, surfaces, amplitudes, conditions, loads, mass, damping, contact,
!! walls, step; the load cards go to the model part wherever the deck had them). Reals
!! are written with the fewest digits that read back to the identical double. Reading the text
!! of `deck_echo(deck, full=.true.)` with `read_deck` gives the same records again (locations
!! apart). Node sets given on *NODE, NSET= are written as *NSET cards; *NSET GENERATE is
!! written expanded.
!!
!! The record of the results file (`record = .true.`, doc/results.md "The processed deck")
!! keeps every card and parameter line but puts a marker line "** data: <group>, <n> lines"
!! in place of the bulk data lines (nodes, elements, control points, the ids of sets), which
!! go to that group as exact binary data (`ictus_io_deck_record`).
module ictus_io_deck_echo
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: str, str_list
  use ictus_io_deck_types, only: deck_t, set_in_t, material_in_t, ANALYSIS_PLANE_STRESS, &
      etype_name, surface_in_t, &
      SET_NODE, SIDE_NONE, side_name, SURF_PATCH, MASS_HRZ, MASS_ALPHA, mass_name, HRZ_GAUSS2, &
      OP_ELEVATE, CONTACT_NODE_TO_SEGMENT, CONTACT_MORTAR, BC_VELOCITY, DLOAD_PRESSURE, AMP_DEF_SMOOTH_STEP
  use ictus_solver_model, only: NVAR, VAR_NAMES
  implicit none
  private
  public :: deck_echo, real_text, record_path, record_digest_line

  !> A growing text (lines joined with newlines).
  type :: text_t
    character(len=:), allocatable :: s
    integer :: n = 0
  end type text_t

  !> Data lines shown per card when full = .false.
  integer, parameter :: short_lines = 5
  !> Values per line for knot vectors and set lists.
  integer, parameter :: per_line = 8

contains

  !> The deck as canonical deck text. With full = .false. the data of *NODE, *ELEMENT,
  !! *CONTROL POINTS and long sets stops after 5 lines with a comment "** ... N more lines".
  !! With record = .true. (and full) their data lines are marker lines naming the groups of
  !! `record_path` instead.
  function deck_echo(deck, full, record) result(text)
    type(deck_t), intent(in) :: deck
    logical, intent(in) :: full
    logical, intent(in), optional :: record
    character(len=:), allocatable :: text
    type(text_t) :: t
    logical :: rec

    rec = .false.
    if (present(record)) rec = record

    allocate(character(len=4096) :: t%s)
    call put(t, '** ictus: processed deck, every default written out')
    if (allocated(deck%title)) then
      if (len_trim(deck%title) > 0) then
        call put(t, '*HEADING')
        call put(t, trim(deck%title))
      end if
    end if
    if (deck%ndm == 3) then
      call put(t, '*ANALYSIS, TYPE=3D')
    else
      call put(t, '*ANALYSIS, TYPE='//trim(merge('PLANE STRESS', 'PLANE STRAIN', &
          deck%analysis == ANALYSIS_PLANE_STRESS))//', THICKNESS='//real_text(deck%thickness))
    end if
    call echo_materials(deck, t)
    call echo_mesh(deck, full, rec, t)
    call echo_patches(deck, full, rec, t)
    call echo_sets(deck, full, rec, t)
    call echo_conditions(deck, t)
    call echo_step(deck, t)
    text = t%s(1:t%n)
  end function deck_echo

  subroutine echo_materials(d, t)
    type(deck_t), intent(in) :: d
    type(text_t), intent(inout) :: t
    integer :: k
    do k = 1, d%n_materials
      associate (m => d%materials(k))
        call put(t, '*MATERIAL, NAME='//trim(m%name))
        if (m%has_elastic) then
          call put(t, '*ELASTIC')
          call put(t, real_text(m%e)//', '//real_text(m%nu))
        end if
        if (m%has_hyperelastic) then
          call put(t, '*HYPERELASTIC, NEO HOOKE')
          call put(t, real_text(m%c10)//', '//real_text(m%d1))
        end if
        if (m%has_plastic) call echo_plastic(m, t)
        if (m%has_density) then
          call put(t, '*DENSITY')
          call put(t, real_text(m%rho))
        end if
      end associate
    end do
  end subroutine echo_materials

  !> *PLASTIC with its table.
  subroutine echo_plastic(m, t)
    type(material_in_t), intent(in) :: m
    type(text_t), intent(inout) :: t
    integer :: k
    call put(t, '*PLASTIC')
    if (.not. allocated(m%plastic)) return
    do k = 1, size(m%plastic, 2)
      call put(t, real_text(m%plastic(1, k))//', '//real_text(m%plastic(2, k)))
    end do
  end subroutine echo_plastic

  !> *NODE and *ELEMENT cards.
  subroutine echo_mesh(d, full, rec, t)
    type(deck_t), intent(in) :: d
    logical, intent(in) :: full, rec
    type(text_t), intent(inout) :: t
    integer :: k, e, a, nshow
    character(len=:), allocatable :: line

    if (d%n_nodes > 0) then
      call put(t, '*NODE')
      nshow = shown_count(d%n_nodes, full)
      if (rec) then
        call marker(t, record_path('nodes', 1), d%n_nodes)
      else
        do k = 1, nshow
          line = str(d%node_ids(k))
          do a = 1, d%ndm
            line = line//', '//real_text(d%node_x(a, k))
          end do
          call put(t, line)
        end do
        call more(t, d%n_nodes - nshow)
      end if
    end if
    do k = 1, d%n_blocks
      associate (b => d%blocks(k))
        line = '*ELEMENT, TYPE='//etype_name(b%etype)//', MATERIAL='//trim(b%material)
        if (len_trim(b%elset) > 0) line = line//', ELSET='//trim(b%elset)
        line = line//', GAUSS='//str(b%gauss)
        if (b%dilatation > 0) line = line//', DILATATION='//trim(merge('FULL', 'MEAN', &
            b%dilatation == 1))
        call put(t, line)
        nshow = shown_count(size(b%ids), full)
        if (rec) then
          call marker(t, record_path('elements', k), size(b%ids))
        else
          do e = 1, nshow
            line = str(b%ids(e))
            do a = 1, b%nen
              line = line//', '//str(b%conn(a, e))
            end do
            call put(t, line)
          end do
          call more(t, size(b%ids) - nshow)
        end if
      end associate
    end do
  end subroutine echo_mesh

  !> *PATCH with *KNOTS and *CONTROL POINTS, then *ELEVATE / *REFINE in deck order.
  subroutine echo_patches(d, full, rec, t)
    type(deck_t), intent(in) :: d
    logical, intent(in) :: full, rec
    type(text_t), intent(inout) :: t
    integer :: k, nshow, ncp
    character(len=:), allocatable :: line

    do k = 1, d%n_patches
      associate (p => d%patches(k))
        line = '*PATCH, NAME='//trim(p%name)//', MATERIAL='//trim(p%material)// &
            ', DEGREE='//str_list(p%degree(1:d%ndm))//', SIZE='//str_list(p%size(1:d%ndm))
        if (p%dilatation > 0) line = line//', DILATATION='//trim(merge('FULL', 'MEAN', &
            p%dilatation == 1))
        if (p%merge) line = line//', MERGE=YES'
        call put(t, line)
        if (allocated(p%knots1)) then
          call put(t, '*KNOTS, DIRECTION=1')
          call put_reals(t, p%knots1)
        end if
        if (allocated(p%knots2)) then
          call put(t, '*KNOTS, DIRECTION=2')
          call put_reals(t, p%knots2)
        end if
        if (allocated(p%knots3)) then
          call put(t, '*KNOTS, DIRECTION=3')
          call put_reals(t, p%knots3)
        end if
        if (allocated(p%cp)) then
          call put(t, '*CONTROL POINTS')
          ncp = size(p%cp, 2)
          nshow = shown_count(ncp, full)
          if (rec) then
            call marker(t, record_path('control_points', k), ncp)
            nshow = 0
            ncp = 0
          end if
          call put_cp(t, p%cp(:, 1:nshow))
          call more(t, ncp - nshow)
        end if
      end associate
    end do
    do k = 1, d%n_patch_ops
      associate (op => d%patch_ops(k))
        if (op%kind == OP_ELEVATE) then
          call put(t, '*ELEVATE, PATCH='//trim(op%patch)//', DEGREE='// &
              str_list(op%values(1:d%ndm)))
        else
          call put(t, '*REFINE, PATCH='//trim(op%patch)//', SUBDIVIDE='// &
              str_list(op%values(1:d%ndm)))
        end if
      end associate
    end do
  end subroutine echo_patches

  subroutine put_cp(t, cp)
    type(text_t), intent(inout) :: t
    real(dp), intent(in) :: cp(:,:)
    integer :: k, i
    character(len=:), allocatable :: line
    do k = 1, size(cp, 2)
      line = real_text(cp(1, k))
      do i = 2, size(cp, 1)
        line = line//', '//real_text(cp(i, k))
      end do
      call put(t, line)
    end do
  end subroutine put_cp

  !> *NSET / *ELSET cards (ids first, then set names) and *SURFACE cards.
  subroutine echo_sets(d, full, rec, t)
    type(deck_t), intent(in) :: d
    logical, intent(in) :: full, rec
    type(text_t), intent(inout) :: t
    integer :: k, e
    character(len=:), allocatable :: key

    do k = 1, d%n_sets
      associate (s => d%sets(k))
        key = trim(merge('NSET ', 'ELSET', s%kind == SET_NODE))
        if (s%side /= SIDE_NONE) call put(t, '*NSET, NSET='//trim(s%name)//', PATCH='// &
            trim(s%patch)//', SIDE='//side_name(s%side))
        if (size(s%ids) + size(s%refs) > 0) then
          call put(t, '*'//key//', '//key//'='//trim(s%name))
          call put_set_list(t, s, full, rec, k)
        end if
      end associate
    end do
    do k = 1, d%n_surfaces
      associate (s => d%surfaces(k))
        if (s%kind == SURF_PATCH .and. several_sides(s)) then
          call put(t, '*SURFACE, NAME='//trim(s%name))
          do e = 1, size(s%side_code)
            call put(t, 'PATCH='//trim(s%side_patch(e))//', SIDE='//side_name(s%side_code(e)))
          end do
        else if (s%kind == SURF_PATCH) then
          call put(t, '*SURFACE, NAME='//trim(s%name)//', PATCH='//trim(s%patch)// &
              ', SIDE='//side_name(s%side))
        else
          call put(t, '*SURFACE, NAME='//trim(s%name)//', TYPE=ELEMENT')
          do e = 1, size(s%elem)
            if (s%elem(e) > 0) then
              call put(t, str(s%elem(e))//', S'//str(s%face(e)))
            else
              call put(t, trim(s%elset(e))//', S'//str(s%face(e)))
            end if
          end do
        end if
      end associate
    end do
  end subroutine echo_sets

  !> The data lines of set number `iset`: `per_line` ids, then `per_line` names per line. In
  !! the record (rec) the lines of ids are one marker line.
  subroutine put_set_list(t, s, full, rec, iset)
    type(text_t), intent(inout) :: t
    type(set_in_t), intent(in) :: s
    logical, intent(in) :: full, rec
    integer, intent(in) :: iset
    integer :: k, j, nid, nref, nlines, shown
    character(len=:), allocatable :: line

    nid = size(s%ids)
    nref = size(s%refs)
    if (rec .and. nid > 0) then
      call marker(t, record_path('sets', iset), (nid + per_line - 1)/per_line)
      nid = 0
    end if
    nlines = (nid + per_line - 1)/per_line + (nref + per_line - 1)/per_line
    shown = 0
    do k = 1, nid, per_line
      if (shown == shown_count(nlines, full)) exit
      line = str(s%ids(k))
      do j = k + 1, min(k + per_line - 1, nid)
        line = line//', '//str(s%ids(j))
      end do
      call put(t, line)
      shown = shown + 1
    end do
    do k = 1, nref, per_line
      if (shown == shown_count(nlines, full)) exit
      line = trim(s%refs(k))
      do j = k + 1, min(k + per_line - 1, nref)
        line = line//', '//trim(s%refs(j))
      end do
      call put(t, line)
      shown = shown + 1
    end do
    call more(t, nlines - shown)
  end subroutine put_set_list

  !> *BOUNDARY, *INITIAL CONDITIONS, *MASS, *DAMPING, *CONTACT PAIR, *RIGID WALL and
  !! *SURFACE INTERACTION with its *FRICTION.
  subroutine echo_conditions(d, t)
    type(deck_t), intent(in) :: d
    type(text_t), intent(inout) :: t
    integer :: k
    character(len=:), allocatable :: line

    call echo_amplitudes(d, t)
    do k = 1, d%n_boundaries
      associate (b => d%boundaries(k))
        ! a new card where AMPLITUDE= or TYPE= changes (a deck without them: one *BOUNDARY)
        line = '*BOUNDARY'
        if (len_trim(b%amplitude) > 0) line = line//', AMPLITUDE='//trim(b%amplitude)
        if (b%kind == BC_VELOCITY) line = line//', TYPE=VELOCITY'
        if (k == 1) then
          call put(t, line)
        else if (d%boundaries(k - 1)%amplitude /= b%amplitude .or. &
            d%boundaries(k - 1)%kind /= b%kind) then
          call put(t, line)
        end if
        call put(t, trim(b%target)//', '//str(b%first_dof)//', '//str(b%last_dof)//', '// &
            real_text(b%value))
      end associate
    end do
    call echo_loads(d, t)
    if (d%n_velocities > 0) call put(t, '*INITIAL CONDITIONS, TYPE=VELOCITY')
    do k = 1, d%n_velocities
      associate (v => d%velocities(k))
        call put(t, trim(v%target)//', '//str(v%dof)//', '//real_text(v%value))
      end associate
    end do
    if (d%n_masses == 0) call put(t, '** no *MASS card: the program default applies')
    do k = 1, d%n_masses
      associate (m => d%masses(k))
        line = '*MASS, TYPE='//mass_name(m%kind)
        if (m%kind == MASS_HRZ) line = line//', INTEGRATION='// &
            trim(merge('2X2 ', 'FULL', m%hrz_rule == HRZ_GAUSS2))
        if (m%kind == MASS_ALPHA) line = line//', ALPHA='//real_text(m%alpha)
        call put(t, line//body(m%elset, m%patch))
      end associate
    end do
    do k = 1, d%n_dampings
      associate (dm => d%dampings(k))
        call put(t, '*DAMPING, ALPHA='//real_text(dm%alpha)//body(dm%elset, dm%patch))
      end associate
    end do
    do k = 1, d%n_pairs
      associate (p => d%pairs(k))
        if (p%tie) then
          line = '*TIE, NAME='//trim(p%name)
          if (p%penalty > 0.0_dp) line = line//', PENALTY='//real_text(p%penalty)
          call put(t, line)
          call put(t, trim(p%first)//', '//trim(p%second))
          cycle
        end if
        line = '*CONTACT PAIR, NAME='//trim(p%name)//', PENALTY='//real_text(p%penalty)// &
            ', ALGORITHM='//trim(algorithm_name(p%algorithm))
        if (p%mass_penalty == 0.0_dp) then
          line = line//', MASS PENALTY=AUTO'
        else if (p%mass_penalty > 0.0_dp) then
          line = line//', MASS PENALTY='//real_text(p%mass_penalty)
        end if
        if (p%stability_warn) line = line//', STABILITY=WARN'
        call put(t, line//interaction_text(p%interaction, p%tangential_penalty))
        call put(t, trim(p%first)//', '//trim(p%second))
      end associate
    end do
    do k = 1, d%n_walls
      associate (w => d%walls(k))
        call put(t, '*RIGID WALL, NAME='//trim(w%name)//', POINT='// &
            reals_text(w%point(1:d%ndm))//', NORMAL='//reals_text(w%normal(1:d%ndm))// &
            ', PENALTY='//real_text(w%penalty)// &
            interaction_text(w%interaction, w%tangential_penalty)// &
            trim(merge(', STABILITY=WARN', '                ', w%stability_warn)))
        call put(t, trim(w%surface))
      end associate
    end do
    do k = 1, d%n_interactions
      call put(t, '*SURFACE INTERACTION, NAME='//trim(d%interactions(k)%name))
      call put(t, '*FRICTION')
      call put(t, real_text(d%interactions(k)%mu))
    end do
  end subroutine echo_conditions

  !> ', INTERACTION=name[, TANGENTIAL PENALTY=value]' of a contact pair or wall ('' none).
  function interaction_text(name, eps_t) result(r)
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: eps_t
    character(len=:), allocatable :: r
    r = ''
    if (len_trim(name) == 0) return
    r = ', INTERACTION='//trim(name)
    if (eps_t > 0.0_dp) r = r//', TANGENTIAL PENALTY='//real_text(eps_t)
  end function interaction_text

  !> *AMPLITUDE cards, one "time, value" pair per line.
  subroutine echo_amplitudes(d, t)
    type(deck_t), intent(in) :: d
    type(text_t), intent(inout) :: t
    integer :: k, j
    do k = 1, d%n_amplitudes
      associate (a => d%amplitudes(k))
        call put(t, '*AMPLITUDE, NAME='//trim(a%name)//', DEFINITION='// &
            trim(merge('SMOOTH STEP', 'TABULAR    ', a%definition == AMP_DEF_SMOOTH_STEP)))
        do j = 1, size(a%t)
          call put(t, real_text(a%t(j))//', '//real_text(a%a(j)))
        end do
      end associate
    end do
  end subroutine echo_amplitudes

  !> *CLOAD and *DLOAD cards, a new card where AMPLITUDE= changes.
  subroutine echo_loads(d, t)
    type(deck_t), intent(in) :: d
    type(text_t), intent(inout) :: t
    integer :: k
    character(len=:), allocatable :: line
    do k = 1, d%n_cloads
      associate (l => d%cloads(k))
        if (k == 1) then
          call put(t, '*CLOAD'//amp_param(l%amplitude))
        else if (d%cloads(k - 1)%amplitude /= l%amplitude) then
          call put(t, '*CLOAD'//amp_param(l%amplitude))
        end if
        call put(t, trim(l%target)//', '//str(l%dof)//', '//real_text(l%value))
      end associate
    end do
    do k = 1, d%n_dloads
      associate (l => d%dloads(k))
        if (k == 1) then
          call put(t, '*DLOAD'//amp_param(l%amplitude))
        else if (d%dloads(k - 1)%amplitude /= l%amplitude) then
          call put(t, '*DLOAD'//amp_param(l%amplitude))
        end if
        if (l%kind == DLOAD_PRESSURE) then
          line = trim(l%target)//', P, '//real_text(l%value)
        else
          line = trim(l%target)//', GRAV, '//real_text(l%value)//', '//real_text(l%dir(1))// &
              ', '//real_text(l%dir(2))
          if (d%ndm == 3) line = line//', '//real_text(l%dir(3))
        end if
        call put(t, line)
      end associate
    end do
  end subroutine echo_loads

  !> ", AMPLITUDE=name" or ''.
  pure function amp_param(name) result(r)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: r
    r = ''
    if (len_trim(name) > 0) r = ', AMPLITUDE='//trim(name)
  end function amp_param

  !> ", ELSET=x" or ", PATCH=x" or ''.
  pure function body(elset, patch) result(r)
    character(len=*), intent(in) :: elset, patch
    character(len=:), allocatable :: r
    r = ''
    if (len_trim(elset) > 0) r = ', ELSET='//trim(elset)
    if (len_trim(patch) > 0) r = ', PATCH='//trim(patch)
  end function body

  subroutine echo_step(d, t)
    type(deck_t), intent(in) :: d
    type(text_t), intent(inout) :: t
    character(len=:), allocatable :: sweep, samples, sched
    integer :: k
    if (.not. d%has_step) return
    sweep = ', SWEEP STEPS=AUTO'
    if (d%step%sweep_steps > 0) sweep = ', SWEEP STEPS='//str(d%step%sweep_steps)
    ! INTERNAL FORCE= only when given: the processed text of a deck without it stays as it was
    ! (a checkpoint is continued only with the same processed deck)
    if (d%step%internal_force /= 'AUTO') sweep = sweep//', INTERNAL FORCE='// &
        trim(d%step%internal_force)
    if (d%step%energy_warning > 0.0_dp) sweep = sweep//', ENERGY WARNING='// &
        real_text(d%step%energy_warning)
    ! NLGEOM only when YES: the processed text of a small-strain deck stays as it was
    if (d%step%nlgeom) then
      call put(t, '*STEP, NLGEOM=YES')
    else
      call put(t, '*STEP')
    end if
    select case (d%step%mass_solver)
    case ('CG')
      call put(t, '*DYNAMIC, EXPLICIT, SAFETY='//real_text(d%step%safety)// &
          ', MASS SOLVER=CG, MASS TOL='//real_text(d%step%mass_tol)//sweep)
    case ('CORRECTOR')
      call put(t, '*DYNAMIC, EXPLICIT, SAFETY='//real_text(d%step%safety)// &
          ', MASS SOLVER=CORRECTOR, MASS PASSES='//str(d%step%mass_passes)//sweep)
    case default
      call put(t, '*DYNAMIC, EXPLICIT, SAFETY='//real_text(d%step%safety)// &
          ', MASS SOLVER='//trim(d%step%mass_solver)//sweep)
    end select
    call put(t, real_text(d%step%dt)//', '//real_text(d%step%t_end))
    ! TIME INTERVAL=, VARIABLES= and the node-set histories only when given: the processed
    ! text of a deck without them stays as it was
    call put(t, '*OUTPUT, HISTORY'//schedule(d%step%history_every, d%step%history_interval))
    do k = 1, d%step%n_out_sets
      associate (o => d%step%out_sets(k))
        sched = ''
        if (o%every > 0 .or. o%interval > 0.0_dp) sched = schedule(o%every, o%interval)
        call put(t, '*OUTPUT, HISTORY, NSET='//trim(o%name)//sched// &
            variables(o%vars, o%vars_given))
      end associate
    end do
    samples = ''
    if (d%step%field_samples > 0) samples = ', SAMPLES='//str(d%step%field_samples)
    samples = samples//variables(d%step%field_vars, d%step%field_vars_given)
    if (d%step%field_interval > 0.0_dp) then
      call put(t, '*OUTPUT, FIELD'//schedule(0, d%step%field_interval)//samples)
    else if (d%step%field_every == 0) then
      call put(t, '*OUTPUT, FIELD, EVERY=0'//samples//'     ** 0 = default: 20 snapshots '// &
          'over the run')
    else
      call put(t, '*OUTPUT, FIELD, EVERY='//str(d%step%field_every)//samples)
    end if
    if (d%step%restart_every > 0) then
      call put(t, '*RESTART, WRITE, EVERY='//str(d%step%restart_every))
    else
      call put(t, '** no *RESTART: no checkpoints')
    end if
    call put(t, '*END STEP')
  end subroutine echo_step

  !> ", TIME INTERVAL=x" when interval > 0, else ", EVERY=n".
  function schedule(every, interval) result(r)
    integer, intent(in) :: every
    real(dp), intent(in) :: interval
    character(len=:), allocatable :: r
    if (interval > 0.0_dp) then
      r = ', TIME INTERVAL='//real_text(interval)
    else
      r = ', EVERY='//str(every)
    end if
  end function schedule

  !> ", VARIABLES=U,V,..." in the order of VAR_NAMES when given, else ''.
  function variables(vars, given) result(r)
    logical, intent(in) :: vars(NVAR), given
    character(len=:), allocatable :: r
    integer :: j
    r = ''
    if (.not. given) return
    do j = 1, NVAR
      if (vars(j)) r = r//','//trim(VAR_NAMES(j))
    end do
    r = ', VARIABLES='//r(2:)
  end function variables

  ! ------------------------------------------------------------------------------------------

  !> The group of the record that holds the bulk data of a card: `what` is 'nodes' (all
  !! *NODE lines, k = 1), 'elements' (*ELEMENT card k), 'control_points' (patch k) or 'sets'
  !! (the ids of set k), in the order of `deck_t`.
  function record_path(what, k) result(path)
    character(len=*), intent(in) :: what
    integer, intent(in) :: k
    character(len=:), allocatable :: path
    if (what == 'nodes') then
      path = '/deck/nodes'
    else
      path = '/deck/'//what//'/'//str(k)
    end if
  end function record_path

  !> The marker line of the record in place of `n` data lines (nothing when n = 0).
  subroutine marker(t, path, n)
    type(text_t), intent(inout) :: t
    character(len=*), intent(in) :: path
    integer, intent(in) :: n
    if (n > 0) call put(t, '** data: '//path//', '//str(n)//' line'//trim(merge('s', ' ', n /= 1)))
  end subroutine marker

  !> The line a checkpoint adds to the record: the digest of the bulk data, so that a
  !! checkpoint is not continued with a deck whose data differ (the record alone names only
  !! the groups).
  function record_digest_line(digest) result(line)
    character(len=*), intent(in) :: digest
    character(len=:), allocatable :: line
    line = '** data digest: '//digest
  end function record_digest_line

  !> Number of data lines to show out of `n`.
  pure integer function shown_count(n, full)
    integer, intent(in) :: n
    logical, intent(in) :: full
    shown_count = n
    if (.not. full) shown_count = min(n, short_lines)
  end function shown_count

  !> The "** ... N more lines" comment (nothing when N = 0).
  subroutine more(t, n)
    type(text_t), intent(inout) :: t
    integer, intent(in) :: n
    if (n > 0) call put(t, '** ... '//str(n)//' more line'//trim(merge('s', ' ', n /= 1)))
  end subroutine more

  !> Reals, `per_line` per line.
  subroutine put_reals(t, x)
    type(text_t), intent(inout) :: t
    real(dp), intent(in) :: x(:)
    character(len=:), allocatable :: line
    integer :: k
    line = ''
    do k = 1, size(x)
      if (len(line) > 0) line = line//', '
      line = line//real_text(x(k))
      if (mod(k, per_line) == 0 .or. k == size(x)) then
        call put(t, line)
        line = ''
      end if
    end do
  end subroutine put_reals

  !> Appends one line to `t`.
  subroutine put(t, line)
    type(text_t), intent(inout) :: t
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: tmp
    integer :: need
    need = t%n + len(line) + 1
    if (need > len(t%s)) then
      allocate(character(len=max(need, 2*len(t%s))) :: tmp)
      tmp(1:t%n) = t%s(1:t%n)
      call move_alloc(tmp, t%s)
    end if
    t%s(t%n + 1:need) = line//achar(10)
    t%n = need
  end subroutine put

  !> Shortest decimal text of `x` that reads back to exactly `x`: plain notation for
  !! 1e-5 <= |x| < 1e15 ("0.3", "210000", "-1.5"), otherwise "d.dddE<exp>".
  function real_text(x) result(s)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=40) :: buf, fmt
    character(len=:), allocatable :: digits
    integer :: d, e, ke, k, lo, hi

    ! the fewest digits that read back to x: if d digits do, d + 1 do too (the nearest
    ! (d+1)-digit decimal is at least as close), so a bisection over 0..17 finds them
    lo = 0
    hi = 17
    do while (lo < hi)
      d = (lo + hi)/2
      if (reads_back(d)) then
        hi = d
      else
        lo = d + 1
      end if
    end do
    write(fmt, '(a,i0,a)') '(es32.', lo, 'e3)'
    write(buf, fmt) x
    buf = adjustl(buf)
    ke = index(buf, 'E')
    read(buf(ke + 1:), *) e
    digits = ''
    do k = 1, ke - 1
      if (buf(k:k) >= '0' .and. buf(k:k) <= '9') digits = digits//buf(k:k)
    end do
    do while (len(digits) > 1 .and. digits(len(digits):) == '0')
      digits = digits(1:len(digits) - 1)
    end do
    if (digits == '0') e = 0
    if (e >= -5 .and. e < 15) then
      if (e >= 0) then
        if (len(digits) <= e + 1) then
          s = digits//repeat('0', e + 1 - len(digits))
        else
          s = digits(1:e + 1)//'.'//digits(e + 2:)
        end if
      else
        s = '0.'//repeat('0', -e - 1)//digits
      end if
    else
      s = digits(1:1)
      if (len(digits) > 1) s = s//'.'//digits(2:)
      s = s//'E'//str(e)
    end if
    if (buf(1:1) == '-') s = '-'//s

  contains

    !> Whether x written with d + 1 significant digits reads back to x.
    logical function reads_back(d)
      integer, intent(in) :: d
      character(len=40) :: b, f
      real(dp) :: y
      integer :: ios
      write(f, '(a,i0,a)') '(es32.', d, 'e3)'
      write(b, f) x
      read(b, *, iostat=ios) y
      reads_back = ios == 0 .and. y == x
    end function reads_back
  end function real_text

  !> The values x joined by commas, each as real_text writes it.
  function reals_text(x) result(s)
    real(dp), intent(in) :: x(:)
    character(len=:), allocatable :: s
    integer :: k
    s = real_text(x(1))
    do k = 2, size(x)
      s = s//','//real_text(x(k))
    end do
  end function reals_text

  !> True when a surface of patch sides lists more than one side (echoed as data lines).
  pure logical function several_sides(s)
    type(surface_in_t), intent(in) :: s
    several_sides = .false.
    if (allocated(s%side_code)) several_sides = size(s%side_code) > 1
  end function several_sides

  !> The ALGORITHM= value of a CONTACT_* kind.
  pure function algorithm_name(kind) result(name)
    integer, intent(in) :: kind
    character(len=:), allocatable :: name
    select case (kind)
    case (CONTACT_NODE_TO_SEGMENT)
      name = 'NODE TO SEGMENT'
    case (CONTACT_MORTAR)
      name = 'MORTAR'
    case default
      name = 'TWO HALF PASS'
    end select
  end function algorithm_name
end module ictus_io_deck_echo
