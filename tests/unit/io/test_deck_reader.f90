!> Tests of the deck reader (ictus_io_deck_reader), its lexer and the deck echo:
!! good decks read field by field, number parsing, and the echo round trip
!! (deck_echo(full=.true.) written to a file and read again gives the same records), the
!! record of the results file (marker lines for the bulk data) and the digest of that data.
!! Argument 1: the directory of the test decks (tests/unit/io/decks).
program test_deck_reader
  use ictus_core_kinds, only: dp
  use ictus_core_errors, only: error_count, reset_errors
  use ictus_test_check, only: checker_t
  use ictus_io_deck_types, only: deck_t, ANALYSIS_PLANE_STRAIN, ANALYSIS_PLANE_STRESS, &
      ETYPE_Q4, ETYPE_Q8, SET_NODE, SET_ELEMENT, SIDE_NONE, SIDE_XI0, SIDE_ETA0, &
      SURF_ELEMENT, SURF_PATCH, MASS_ALPHA, MASS_HRZ, MASS_ROW_SUM, HRZ_FULL, HRZ_GAUSS2, &
      OP_ELEVATE, OP_REFINE, CONTACT_TWO_HALF_PASS, CONTACT_NODE_TO_SEGMENT, &
      AMP_DEF_SMOOTH_STEP, AMP_DEF_TABULAR, DLOAD_GRAV, DLOAD_PRESSURE, BC_DISPLACEMENT, &
      BC_VELOCITY, ANALYSIS_3D, SIDE_ZETA0, SIDE_ZETA1
  use ictus_elements_types, only: ETYPE_C3D8, ETYPE_C3D20, ETYPE_C3D27
  use ictus_io_deck_reader, only: read_deck
  use ictus_io_deck_echo, only: deck_echo, real_text
  use ictus_io_deck_record, only: deck_record_digest
  use ictus_io_deck_lexer, only: parse_real, parse_int
  implicit none
  type(checker_t) :: t
  character(len=:), allocatable :: dir
  integer :: n

  call t%start('io/deck_reader')
  call get_command_argument(1, length=n)
  allocate(character(len=n) :: dir)
  call get_command_argument(1, dir)
  call t%true(n > 0, 'deck directory given as argument 1')
  call case_numbers(t)
  call case_real_text(t)
  call case_fe_deck(t, dir//'/model_fe.inp')
  call case_patch_deck(t, dir//'/patch_halfdisc.inp')
  call case_round_trip(t, dir//'/model_fe.inp', 'roundtrip_model_fe.inp')
  call case_round_trip(t, dir//'/patch_halfdisc.inp', 'roundtrip_patch.inp')
  call case_corrector(t, dir//'/step_corrector.inp')
  call case_round_trip(t, dir//'/step_corrector.inp', 'roundtrip_corrector.inp')
  call case_output(t, dir//'/step_output.inp')
  call case_round_trip(t, dir//'/step_output.inp', 'roundtrip_output.inp')
  call case_loads(t, dir//'/loads.inp')
  call case_round_trip(t, dir//'/loads.inp', 'roundtrip_loads.inp')
  call case_3d(t, dir//'/model_3d.inp')
  call case_round_trip(t, dir//'/model_3d.inp', 'roundtrip_3d.inp')
  call case_patch_3d(t, dir//'/patch_3d.inp')
  call case_round_trip(t, dir//'/patch_3d.inp', 'roundtrip_patch_3d.inp')
  call case_record(t, dir//'/model_3d.inp')
  call case_short_echo(t, dir//'/model_fe.inp')
  call case_record(t, dir//'/model_fe.inp')
  call case_record(t, dir//'/patch_halfdisc.inp')
  call case_missing_file(t)
  call t%finish()

contains

  !> Number tokens: plain decimal numbers only, nothing that overflows.
  subroutine case_numbers(t)
    type(checker_t), intent(inout) :: t
    character(len=8), parameter :: bad(12) = [character(len=8) :: '1.0.0', 'nan', 'inf', &
        '1e400', '.', 'e5', '1e', '--1', '1,0', 'abc', '1.5x', '-1e-400']
    real(dp) :: x
    integer :: i, k
    logical :: ok
    do k = 1, size(bad)
      call parse_real(trim(bad(k)), x, ok)
      call t%true(.not. ok, 'parse_real rejects "'//trim(bad(k))//'"')
    end do
    call parse_real('1d3', x, ok)
    call t%true(ok .and. x == 1000.0_dp, 'parse_real 1d3')
    call parse_real('-.5', x, ok)
    call t%true(ok .and. x == -0.5_dp, 'parse_real -.5')
    call parse_real('+3.', x, ok)
    call t%true(ok .and. x == 3.0_dp, 'parse_real +3.')
    call parse_real('2.5E-3', x, ok)
    call t%true(ok .and. x == 2.5e-3_dp, 'parse_real 2.5E-3')
    call parse_real('0.000e999', x, ok)
    call t%true(ok .and. x == 0.0_dp, 'parse_real of zero with a large exponent')
    call parse_int('2147483648', i, ok)
    call t%true(.not. ok, 'parse_int rejects 2^31')
    call parse_int('1.0', i, ok)
    call t%true(.not. ok, 'parse_int rejects 1.0')
    call parse_int('-7', i, ok)
    call t%true(ok .and. i == -7, 'parse_int -7')
  end subroutine case_numbers

  !> Shortest round-trip text of reals.
  subroutine case_real_text(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: x(9), y
    integer :: k
    logical :: ok
    call t%true(real_text(0.1_dp) == '0.1', 'real_text 0.1: '//real_text(0.1_dp))
    call t%true(real_text(210000.0_dp) == '210000', 'real_text 210000: '// &
        real_text(210000.0_dp))
    call t%true(real_text(-1.5_dp) == '-1.5', 'real_text -1.5')
    call t%true(real_text(7.8e-9_dp) == '7.8E-9', 'real_text 7.8e-9: '//real_text(7.8e-9_dp))
    call t%true(real_text(0.0_dp) == '0', 'real_text 0')
    x = [1.0_dp/3.0_dp, sqrt(2.0_dp), 1.0e300_dp, -2.2e-300_dp, huge(1.0_dp)/10, 0.3_dp, &
        1.0e15_dp, 123456789012345.6_dp, 4.0e-5_dp]
    do k = 1, size(x)
      call parse_real(real_text(x(k)), y, ok)
      call t%true(ok .and. y == x(k), 'real_text reads back exactly: '//real_text(x(k)))
    end do
  end subroutine case_real_text

  !> The FE deck: every FE card, an include, mixed case and separators.
  subroutine case_fe_deck(t, path)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: path
    type(deck_t) :: d
    integer :: n0

    n0 = error_count()
    call read_deck(path, d)
    call t%equal_int(error_count() - n0, 0, 'fe: no errors')
    call t%true(d%title == 'Two bodies: a Q4 block and a Q8 block above it', 'fe: title')
    call t%equal_int(d%analysis, ANALYSIS_PLANE_STRESS, 'fe: analysis')
    call t%close(d%thickness, 0.5_dp, 0.0_dp, 'fe: thickness')
    call t%equal_int(d%n_materials, 2, 'fe: materials')
    if (d%n_materials == 2) then
      call t%true(d%materials(1)%name == 'STEEL' .and. d%materials(2)%name == 'SOFT', &
          'fe: material names upper case')
      call t%close(d%materials(1)%e, 210000.0_dp, 0.0_dp, 'fe: E steel')
      call t%close(d%materials(1)%nu, 0.3_dp, 0.0_dp, 'fe: nu steel')
      call t%close(d%materials(1)%rho, 7.8e-9_dp, 0.0_dp, 'fe: rho steel')
      call t%close(d%materials(2)%e, 1000.0_dp, 0.0_dp, 'fe: E soft (blank separated)')
      call t%close(d%materials(2)%nu, 0.2_dp, 0.0_dp, 'fe: nu soft')
      call t%close(d%materials(2)%rho, 1.0_dp, 0.0_dp, 'fe: rho soft (density first)')
    end if
    call t%equal_int(d%n_nodes, 14, 'fe: nodes (6 + 8 included)')
    if (d%n_nodes == 14) then
      call t%true(all(d%node_ids == [1, 2, 3, 4, 5, 6, 11, 12, 13, 14, 15, 16, 17, 18]), &
          'fe: node ids in deck order')
      call t%true(all(d%node_x(:, 2) == [1.0_dp, 0.0_dp]), 'fe: node 2 (blank separated)')
      call t%true(all(d%node_x(:, 4) == [0.0_dp, 1.0_dp]), 'fe: node 4 (no blanks)')
      call t%true(all(d%node_x(:, 14) == [0.0_dp, 2.0_dp]), 'fe: node 18 (included)')
      call t%true(ends_with(d%node_where(7), 'include/q8_nodes.inc:3'), &
          'fe: location of an included node: '//trim(d%node_where(7)))
      call t%true(ends_with(d%node_where(5), 'model_fe.inp:24'), &
          'fe: location of node 5: '//trim(d%node_where(5)))
    end if
    call t%equal_int(d%n_blocks, 2, 'fe: element blocks')
    if (d%n_blocks == 2) then
      call t%equal_int(d%blocks(1)%etype, ETYPE_Q4, 'fe: block 1 type')
      call t%equal_int(d%blocks(1)%nen, 4, 'fe: block 1 nen')
      call t%equal_int(d%blocks(1)%gauss, 2, 'fe: block 1 default Gauss points (Q4: 2)')
      call t%true(d%blocks(1)%elset == 'LOWER' .and. d%blocks(1)%material == 'STEEL', &
          'fe: block 1 elset, material')
      call t%true(all(d%blocks(1)%ids == [1, 2]), 'fe: block 1 ids')
      call t%true(all(d%blocks(1)%conn(:, 2) == [2, 3, 6, 5]), 'fe: element 2 nodes')
      call t%equal_int(d%blocks(2)%etype, ETYPE_Q8, 'fe: block 2 type (q8)')
      call t%equal_int(d%blocks(2)%gauss, 2, 'fe: block 2 GAUSS=2')
      call t%true(all(d%blocks(2)%conn(:, 1) == [11, 12, 13, 14, 15, 16, 17, 18]), &
          'fe: element 10 nodes')
      call t%equal_int(d%blocks(2)%line(1), 31, 'fe: element 10 line')
    end if
    call check_fe_sets(t, d)
    call check_fe_conditions(t, d)
  end subroutine case_fe_deck

  subroutine check_fe_sets(t, d)
    type(checker_t), intent(inout) :: t
    type(deck_t), intent(in) :: d
    call t%equal_int(d%n_sets, 6, 'fe: sets')
    if (d%n_sets /= 6) return
    call t%true(d%sets(1)%name == 'BASE_NODES' .and. all(d%sets(1)%ids == [1, 2, 3, 4, 5, 6]), &
        'fe: *NODE, NSET= set')
    call t%true(d%sets(2)%name == 'Q8_NODES' .and. size(d%sets(2)%ids) == 8, &
        'fe: included *NODE, NSET= set')
    call t%true(d%sets(3)%name == 'BOTTOM' .and. all(d%sets(3)%ids == [1, 2, 3]), &
        'fe: GENERATE set')
    call t%true(all(d%sets(4)%ids == [13, 17, 14]), 'fe: set over two lines, blanks')
    call t%true(all(d%sets(5)%ids == [4]) .and. size(d%sets(5)%refs) == 2, 'fe: mixed set')
    if (size(d%sets(5)%refs) == 2) call t%true(d%sets(5)%refs(1) == 'BOTTOM' .and. &
        d%sets(5)%refs(2) == 'TOP_Q8', 'fe: set references upper case')
    call t%equal_int(d%sets(6)%kind, SET_ELEMENT, 'fe: ELSET kind')
    call t%equal_int(d%sets(1)%kind, SET_NODE, 'fe: NSET kind')
    call t%equal_int(d%sets(3)%side, SIDE_NONE, 'fe: no side on a list set')
    call t%equal_int(d%n_surfaces, 2, 'fe: surfaces')
    if (d%n_surfaces /= 2) return
    call t%equal_int(d%surfaces(1)%kind, SURF_ELEMENT, 'fe: surface kind')
    call t%true(all(d%surfaces(1)%elem == [1, 2]) .and. all(d%surfaces(1)%face == [3, 3]), &
        'fe: surface faces (s3 lower case)')
    call t%true(d%surfaces(2)%elem(1) == 0 .and. d%surfaces(2)%elset(1) == 'UPPER' .and. &
        d%surfaces(2)%face(1) == 1, 'fe: surface on an element set, default TYPE=ELEMENT')
  end subroutine check_fe_sets

  subroutine check_fe_conditions(t, d)
    type(checker_t), intent(inout) :: t
    type(deck_t), intent(in) :: d
    call t%equal_int(d%n_boundaries, 3, 'fe: boundaries (two cards)')
    if (d%n_boundaries == 3) then
      call t%true(d%boundaries(1)%target == 'BOTTOM' .and. d%boundaries(1)%first_dof == 1 &
          .and. d%boundaries(1)%last_dof == 2 .and. d%boundaries(1)%value == 0.0_dp, &
          'fe: boundary 1')
      call t%true(d%boundaries(2)%target == '4' .and. d%boundaries(2)%last_dof == 1, &
          'fe: boundary on a node id')
      call t%true(d%boundaries(3)%value == -0.01_dp .and. d%boundaries(3)%first_dof == 2, &
          'fe: boundary value')
    end if
    call t%equal_int(d%n_velocities, 2, 'fe: velocities')
    if (d%n_velocities == 2) then
      call t%true(d%velocities(1)%target == 'UPPER' .and. d%velocities(1)%dof == 2 .and. &
          d%velocities(1)%value == -1.5_dp, 'fe: velocity 1')
      call t%true(d%velocities(2)%target == '5' .and. d%velocities(2)%value == 0.25_dp, &
          'fe: velocity on a node id')
    end if
    call t%equal_int(d%n_pairs, 2, 'fe: contact pairs')
    if (d%n_pairs == 2) then
      call t%true(d%pairs(1)%name == 'TOUCH' .and. d%pairs(1)%penalty == 1.0e6_dp .and. &
          d%pairs(1)%algorithm == CONTACT_NODE_TO_SEGMENT .and. &
          d%pairs(1)%mass_penalty == 0.0_dp, 'fe: pair 1 (MASS PENALTY=AUTO -> 0)')
      call t%true(d%pairs(1)%first == 'UPPER_BOTTOM' .and. d%pairs(1)%second == 'LOWER_TOP', &
          'fe: pair 1 surfaces')
      call t%true(d%pairs(2)%algorithm == CONTACT_TWO_HALF_PASS .and. &
          d%pairs(2)%mass_penalty == 3.5_dp .and. d%pairs(2)%second == 'UPPER_BOTTOM', &
          'fe: pair 2 (default algorithm, mass penalty value, blank separated)')
      call t%true(d%pairs(1)%stability_warn .and. .not. d%pairs(2)%stability_warn, &
          'fe: STABILITY=WARN on pair 1, STOP (default) on pair 2')
    end if
    call t%equal_int(d%n_walls, 1, 'fe: rigid walls')
    if (d%n_walls == 1) call t%true(all(d%walls(1)%point(1:2) == [0.0_dp, -0.5_dp]) .and. &
        all(d%walls(1)%normal(1:2) == [0.0_dp, 1.0_dp]) .and. d%walls(1)%penalty == 1.0e7_dp .and. &
        d%walls(1)%surface == 'LOWER_TOP' .and. d%walls(1)%stability_warn, &
        'fe: wall (stability=warn)')
    call t%equal_int(d%n_masses, 2, 'fe: masses')
    if (d%n_masses == 2) then
      call t%true(d%masses(1)%kind == MASS_ALPHA .and. d%masses(1)%alpha == 0.1666_dp .and. &
          d%masses(1)%elset == 'UPPER', 'fe: alpha mass')
      call t%true(d%masses(2)%kind == MASS_HRZ .and. d%masses(2)%hrz_rule == HRZ_GAUSS2, &
          'fe: HRZ 2x2')
    end if
    call t%equal_int(d%n_dampings, 1, 'fe: damping')
    if (d%n_dampings == 1) call t%true(d%dampings(1)%alpha == 0.05_dp .and. &
        d%dampings(1)%elset == 'BOTH', 'fe: damping values')
    call t%true(d%has_step, 'fe: step')
    call t%true(d%step%dt == 1.0e-6_dp .and. d%step%t_end == 2.0e-3_dp .and. &
        d%step%safety == 0.8_dp, 'fe: dynamic')
    call t%true(d%step%mass_solver == 'CG' .and. d%step%mass_tol == 1.0e-9_dp, &
        'fe: MASS SOLVER=CG, MASS TOL=1e-9')
    call t%true(d%step%history_every == 5 .and. d%step%field_every == 100 .and. &
        d%step%restart_every == 1000, 'fe: output and restart')
  end subroutine check_fe_conditions

  !> The patch deck: half-disc patch of doc/iga.md §10.4, a C0 ring, elevation and refinement.
  subroutine case_patch_deck(t, path)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: path
    type(deck_t) :: d
    integer :: n0, k
    real(dp) :: r

    n0 = error_count()
    call read_deck(path, d)
    call t%equal_int(error_count() - n0, 0, 'patch: no errors')
    call t%equal_int(d%analysis, ANALYSIS_PLANE_STRAIN, 'patch: default analysis')
    call t%close(d%thickness, 1.0_dp, 0.0_dp, 'patch: default thickness')
    call t%equal_int(d%n_patches, 2, 'patch: patches')
    if (d%n_patches /= 2) return
    associate (p => d%patches(1))
      call t%true(p%name == 'LOWER' .and. p%material == 'SOFT', 'patch: names')
      call t%true(all(p%degree == [2, 2, 0]) .and. all(p%size == [3, 3, 0]), 'patch: degree, size')
      call t%true(all(p%has_knots(1:2)) .and. p%has_cp, 'patch: knots and control points read')
      call t%true(all(p%knots1 == [0, 0, 0, 1, 1, 1]) .and. all(p%knots2 == [0, 0, 0, 1, 1, &
          1]), 'patch: knot vectors over two lines')
      call t%equal_int(size(p%cp, 2), 9, 'patch: 9 control points')
      ! Corner control points lie on the circle of radius 4 about (0, -4) (doc/iga.md §10.4).
      do k = 1, 9, 2
        if (k == 5) cycle
        r = hypot(p%cp(1, k), p%cp(2, k) + 4.0_dp)
        call t%close(r, 4.0_dp, 1.0e-15_dp, 'patch: corner point on the circle')
      end do
      call t%close(p%cp(1, 8), 4.0_dp*sqrt(2.0_dp), 1.0e-15_dp, 'patch: P[1][2] = sqrt(2) R')
      call t%close(p%cp(3, 4), cos(acos(-1.0_dp)/8), 1.0e-15_dp, 'patch: weight cos 22.5')
      call t%close(p%cp(3, 8), sqrt(0.5_dp), 1.0e-15_dp, 'patch: weight sqrt(2)/2')
    end associate
    associate (p => d%patches(2))
      call t%true(all(p%degree == [2, 1, 0]) .and. all(p%size == [5, 2, 0]), 'ring: degree, size')
      call t%true(all(p%knots1 == [0.0_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.5_dp, 1.0_dp, 1.0_dp, &
          1.0_dp]), 'ring: C0 knot vector over three lines')
      call t%true(all(p%cp(:, 2) == [1.0_dp, 11.0_dp, sqrt(0.5_dp)]), &
          'ring: two control points on one line')
    end associate
    call t%equal_int(d%n_patch_ops, 3, 'patch: ops')
    if (d%n_patch_ops == 3) then
      call t%true(d%patch_ops(1)%kind == OP_ELEVATE .and. all(d%patch_ops(1)%values == [3, 3, 0]), &
          'patch: elevate')
      call t%true(d%patch_ops(2)%kind == OP_REFINE .and. &
          all(d%patch_ops(2)%values == [16, 16, 0]), 'patch: refine')
      call t%true(d%patch_ops(3)%patch == 'LOWER' .and. all(d%patch_ops(3)%values == [3, 4, 0]), &
          'patch: second elevate (lower case name)')
    end if
    call t%equal_int(d%n_sets, 1, 'patch: sets')
    if (d%n_sets == 1) call t%true(d%sets(1)%patch == 'LOWER' .and. &
        d%sets(1)%side == SIDE_ETA0 .and. size(d%sets(1)%ids) == 0, 'patch: side set')
    call t%equal_int(d%n_surfaces, 2, 'patch: surfaces')
    if (d%n_surfaces == 2) call t%true(d%surfaces(1)%kind == SURF_PATCH .and. &
        d%surfaces(1)%side == SIDE_XI0 .and. d%surfaces(2)%side == SIDE_ETA0, 'patch: sides')
    call t%equal_int(d%n_pairs, 1, 'patch: pair')
    if (d%n_pairs == 1) call t%true(d%pairs(1)%algorithm == CONTACT_TWO_HALF_PASS .and. &
        d%pairs(1)%mass_penalty < 0.0_dp, 'patch: pair defaults (no mass penalty: -1)')
    call t%equal_int(d%n_masses, 2, 'patch: masses')
    if (d%n_masses == 2) call t%true(d%masses(1)%kind == MASS_ROW_SUM .and. &
        d%masses(1)%patch == 'RING' .and. d%masses(2)%hrz_rule == HRZ_FULL, 'patch: mass')
    call t%equal_int(d%n_dampings, 1, 'patch: damping')
    if (d%n_dampings == 1) call t%true(d%dampings(1)%alpha == 0.0_dp, 'patch: damping alpha 0')
    call t%true(d%step%dt == 5.0e-4_dp .and. d%step%t_end == 0.9_dp .and. &
        d%step%safety == 0.9_dp, 'patch: step with default safety')
    call t%true(d%step%mass_solver == 'AUTO' .and. d%step%mass_passes == 2, &
        'patch: default MASS SOLVER=AUTO')
    call t%true(d%step%history_every == 1 .and. d%step%field_every == 0 .and. &
        d%step%restart_every == 0, 'patch: output defaults')
  end subroutine case_patch_deck

  !> *DYNAMIC, EXPLICIT, MASS SOLVER=CORRECTOR, MASS PASSES=3 (choice in lower case).
  subroutine case_corrector(t, path)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: path
    type(deck_t) :: d
    integer :: n0
    n0 = error_count()
    call read_deck(path, d)
    call t%equal_int(error_count() - n0, 0, 'corrector: no errors')
    call t%true(d%step%mass_solver == 'CORRECTOR' .and. d%step%mass_passes == 3, &
        'corrector: MASS SOLVER=CORRECTOR, MASS PASSES=3')
  end subroutine case_corrector

  !> *OUTPUT with TIME INTERVAL=, VARIABLES= and NSET= (deck version 2).
  subroutine case_output(t, path)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: path
    type(deck_t) :: d
    integer :: n0
    n0 = error_count()
    call read_deck(path, d)
    call t%equal_int(error_count() - n0, 0, 'output: no errors')
    call t%true(d%step%history_interval == 5.0e-4_dp .and. d%step%history_every == 1, &
        'output: history TIME INTERVAL=5e-4')
    call t%true(d%step%field_interval == 2.5e-3_dp .and. d%step%field_samples == 3 .and. &
        d%step%field_vars_given .and. all(d%step%field_vars .eqv. [.true., .false., .false., &
        .true., .false., .true., .false., .false.]), 'output: field U, S, MISES, interval')
    call t%equal_int(d%step%n_out_sets, 2, 'output: two node sets')
    if (d%step%n_out_sets /= 2) return
    associate (a => d%step%out_sets(1), b => d%step%out_sets(2))
      call t%true(a%name == 'EDGE' .and. a%vars_given .and. all(a%vars .eqv. [.true., &
          .false., .false., .false., .false., .false., .false., .true.]) .and. a%every == 0 &
          .and. a%interval == 0.0_dp, 'output: set EDGE with U, RF')
      call t%true(b%name == 'SQ' .and. .not. b%vars_given .and. count(b%vars) == 3 .and. &
          b%interval == 5.0e-4_dp, 'output: set SQ with the default U, V, RF')
    end associate
  end subroutine case_output

  !> The load cards (format version 2), in the model part and inside the step.
  subroutine case_loads(t, path)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: path
    type(deck_t) :: d
    integer :: n0
    n0 = error_count()
    call read_deck(path, d)
    call t%equal_int(error_count() - n0, 0, 'loads: no errors')
    call t%equal_int(d%n_amplitudes, 2, 'loads: two amplitudes')
    if (d%n_amplitudes == 2) then
      call t%true(d%amplitudes(1)%name == 'RAMP' .and. d%amplitudes(1)%definition == &
          AMP_DEF_SMOOTH_STEP .and. size(d%amplitudes(1)%t) == 2, &
          'loads: RAMP, SMOOTH STEP, pairs over two lines')
      call t%true(d%amplitudes(2)%definition == AMP_DEF_TABULAR .and. &
          all(d%amplitudes(2)%t == [0.0_dp, 0.1_dp, 0.2_dp]) .and. &
          all(d%amplitudes(2)%a == [0.0_dp, 1.0_dp, 0.0_dp]), 'loads: PULSE in the step, TABULAR')
    end if
    call t%equal_int(d%n_cloads, 2, 'loads: two *CLOAD lines')
    if (d%n_cloads == 2) call t%true(d%cloads(1)%target == '3' .and. d%cloads(1)%dof == 2 .and. &
        d%cloads(1)%value == -1.5_dp .and. d%cloads(2)%target == 'LEFT' .and. &
        d%cloads(2)%amplitude == 'RAMP', 'loads: *CLOAD by node id and by set, AMPLITUDE=')
    call t%equal_int(d%n_dloads, 3, 'loads: three *DLOAD lines')
    if (d%n_dloads == 3) then
      call t%true(d%dloads(1)%kind == DLOAD_GRAV .and. len_trim(d%dloads(1)%target) == 0 .and. &
          all(d%dloads(1)%dir == [0.0_dp, -2.0_dp, 0.0_dp]) .and. d%dloads(1)%value == 9.81_dp, &
          'loads: GRAV on the whole model, direction as given')
      call t%true(d%dloads(2)%kind == DLOAD_PRESSURE .and. d%dloads(2)%target == 'TOP' .and. &
          d%dloads(2)%value == 4.0_dp .and. d%dloads(2)%amplitude == 'PULSE', &
          'loads: P on a surface with its amplitude')
      call t%true(d%dloads(3)%target == 'BODY' .and. d%dloads(3)%dir(1) == 1.0_dp, &
          'loads: GRAV with gz = 0 given')
    end if
    call t%equal_int(d%n_boundaries, 3, 'loads: three *BOUNDARY lines')
    if (d%n_boundaries == 3) then
      call t%true(d%boundaries(1)%kind == BC_DISPLACEMENT .and. &
          len_trim(d%boundaries(1)%amplitude) == 0, 'loads: a version-1 *BOUNDARY line')
      call t%true(d%boundaries(2)%kind == BC_VELOCITY .and. d%boundaries(2)%amplitude == &
          'PULSE' .and. d%boundaries(2)%value == 0.5_dp, 'loads: TYPE=VELOCITY in the step')
      call t%true(d%boundaries(3)%kind == BC_DISPLACEMENT .and. d%boundaries(3)%amplitude == &
          'RAMP' .and. d%boundaries(3)%last_dof == 2 .and. d%boundaries(3)%value == 0.25_dp, &
          'loads: TYPE=DISPLACEMENT with an amplitude, empty last dof')
    end if
  end subroutine case_loads

  !> A 3D deck: three coordinates per node, the hexahedra (C3D20 and C3D27 continued over
  !! two lines, C3D20R with its 2x2x2 rule), faces S5 and S6, dof 3, gravity along z.
  subroutine case_3d(t, path)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: path
    type(deck_t) :: d
    integer :: n0
    n0 = error_count()
    call read_deck(path, d)
    call t%equal_int(error_count() - n0, 0, '3d: no errors')
    call t%true(d%ndm == 3 .and. d%analysis == ANALYSIS_3D, '3d: dimension 3, analysis 3D')
    call t%true(d%n_nodes == 36 .and. size(d%node_x, 1) == 3, '3d: 36 nodes of 3 coordinates')
    if (d%n_nodes == 36) call t%true(all(d%node_x(:, 36) == [2.0_dp, 1.0_dp, 1.0_dp]), &
        '3d: coordinates of node 36')
    call t%equal_int(d%n_blocks, 4, '3d: four element blocks')
    if (d%n_blocks == 4) then
      call t%true(d%blocks(1)%etype == ETYPE_C3D8 .and. d%blocks(1)%gauss == 2, &
          '3d: C3D8, 2x2x2 points')
      call t%true(d%blocks(2)%etype == ETYPE_C3D20 .and. d%blocks(2)%nen == 20 .and. &
          d%blocks(2)%gauss == 3, '3d: C3D20, 3x3x3 points')
      call t%true(all(d%blocks(2)%conn(15:20, 1) == [34, 29, 13, 15, 23, 21]), &
          '3d: C3D20 continued on the next line')
      call t%true(d%blocks(3)%etype == ETYPE_C3D20 .and. d%blocks(3)%gauss == 2, &
          '3d: C3D20R is C3D20 with 2x2x2 points')
      call t%true(d%blocks(4)%etype == ETYPE_C3D27 .and. d%blocks(4)%conn(27, 1) == 17 .and. &
          d%blocks(4)%line(1) == 58, '3d: C3D27 over two lines, located at its first')
    end if
    call t%true(d%n_surfaces == 1, '3d: one surface')
    if (d%n_surfaces == 1) call t%true(all(d%surfaces(1)%face == [5, 6]), '3d: faces S5, S6')
    call t%true(d%n_boundaries == 1, '3d: one boundary line')
    if (d%n_boundaries == 1) call t%true(d%boundaries(1)%last_dof == 3, '3d: dofs 1 to 3')
    if (d%n_velocities == 1) call t%true(d%velocities(1)%dof == 3, '3d: velocity dof 3')
    if (d%n_cloads == 1) call t%true(d%cloads(1)%dof == 3, '3d: load on dof 3')
    call t%true(d%n_dloads == 1, '3d: one gravity line')
    if (d%n_dloads == 1) call t%true(all(d%dloads(1)%dir == [0.0_dp, 0.0_dp, -1.0_dp]), &
        '3d: gravity along -z')
    call t%true(index(deck_echo(d, .true.), '*ANALYSIS, TYPE=3D') > 0 .and. &
        index(deck_echo(d, .true.), '36, 2, 1, 1') > 0 .and. &
        index(deck_echo(d, .true.), ', GRAV, 9.81, 0, 0, -1') > 0, &
        '3d: echo of the analysis, a node and the gravity')
  end subroutine case_3d

  !> A trivariate patch in a 3D deck (the quarter-ball of quarter_ball.py): three degrees,
  !! sizes and knot vectors, control points x, y, z, w, *ELEVATE and *REFINE with three
  !! values, the sides ZETA0 and ZETA1.
  subroutine case_patch_3d(t, path)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: path
    type(deck_t) :: d
    integer :: n0, k
    n0 = error_count()
    call read_deck(path, d)
    call t%equal_int(error_count() - n0, 0, 'patch 3d: no errors')
    call t%equal_int(d%n_patches, 1, 'patch 3d: one patch')
    if (d%n_patches /= 1) return
    associate (p => d%patches(1))
      call t%true(all(p%degree == [2, 2, 2]) .and. all(p%size == [3, 5, 3]), &
          'patch 3d: degree, size')
      call t%true(all(p%has_knots) .and. p%has_cp, 'patch 3d: three knot vectors, points')
      call t%true(size(p%knots3) == 6 .and. p%knots3(4) == 1.0_dp, 'patch 3d: knots3')
      call t%true(size(p%cp, 1) == 4 .and. size(p%cp, 2) == 45, 'patch 3d: cp (4, 45)')
      call t%true(all(p%cp(4, :) > 0.0_dp) .and. p%cp(3, 45) == 2.0_dp, &
          'patch 3d: x, y, z, w of the last point (top of the ball)')
    end associate
    call t%true(d%n_patch_ops == 2, 'patch 3d: two patch operations')
    if (d%n_patch_ops == 2) call t%true(all(d%patch_ops(1)%values == [3, 3, 3]) .and. &
        all(d%patch_ops(2)%values == [2, 2, 2]), 'patch 3d: elevate 3,3,3, refine 2,2,2')
    k = findloc(d%sets(1:d%n_sets)%name, 'BALL_X0_ZETA0', dim=1)
    call t%true(k > 0, 'patch 3d: node set of side ZETA0')
    if (k > 0) call t%equal_int(d%sets(k)%side, SIDE_ZETA0, 'patch 3d: side ZETA0')
    call t%true(d%n_surfaces == 1, 'patch 3d: one surface')
    if (d%n_surfaces == 1) call t%equal_int(d%surfaces(1)%side, SIDE_ZETA1, &
        'patch 3d: surface on side ZETA1')
    call t%true(index(deck_echo(d, .true.), 'DEGREE=2,2,2, SIZE=3,5,3') > 0 .and. &
        index(deck_echo(d, .true.), '*KNOTS, DIRECTION=3') > 0 .and. &
        index(deck_echo(d, .true.), 'SIDE=ZETA1') > 0 .and. &
        index(deck_echo(d, .true.), 'SUBDIVIDE=2,2,2') > 0, &
        'patch 3d: echo of the patch card, the third knot vector, a ZETA side, *REFINE')
  end subroutine case_patch_3d

  !> deck_echo(full) written to a file and read again gives the same deck.
  subroutine case_round_trip(t, path, copy)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: path, copy
    type(deck_t) :: a, b
    character(len=:), allocatable :: text
    integer :: u, n0

    n0 = error_count()
    call read_deck(path, a)
    text = deck_echo(a, .true.)
    open(newunit=u, file=copy, status='replace', action='write', access='stream', &
        form='unformatted')
    write(u) text
    close(u)
    call read_deck(copy, b)
    call t%equal_int(error_count() - n0, 0, 'round trip '//copy//': no errors')
    call compare_decks(t, a, b, copy)
    call t%true(deck_echo(b, .true.) == text, 'round trip '//copy//': same echo')
  end subroutine case_round_trip

  !> The short echo cuts long data after 5 lines.
  subroutine case_short_echo(t, path)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: path
    type(deck_t) :: d
    character(len=:), allocatable :: text
    call read_deck(path, d)
    text = deck_echo(d, .false.)
    call t%true(index(text, '** ... 9 more lines') > 0, 'short echo: 14 nodes cut after 5')
    call t%true(index(text, '*MASS, TYPE=HRZ, INTEGRATION=2X2, ELSET=LOWER') > 0, &
        'short echo: mass card')
    call t%true(index(text, '*ANALYSIS, TYPE=PLANE STRESS, THICKNESS=0.5') > 0, &
        'short echo: analysis card')
    call t%true(index(text, '*DYNAMIC, EXPLICIT, SAFETY=0.8') > 0, 'short echo: dynamic')
  end subroutine case_short_echo

  !> The record: the card lines of the full echo, one marker line per bulk block in place of
  !! its data lines; the digest of the bulk data sees a change of one bit of one coordinate,
  !! of one node of one element and of one set id.
  subroutine case_record(t, path)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: path
    type(deck_t) :: d
    character(len=:), allocatable :: full, rec
    character(len=16) :: h0
    integer :: k, nmark, nbulk
    call read_deck(path, d)
    full = deck_echo(d, .true.)
    rec = deck_echo(d, .true., record=.true.)
    call t%equal_int(count_lines(rec, '*'), count_lines(full, '*'), &
        'record '//path//': every card line of the full echo')
    nbulk = merge(1, 0, d%n_nodes > 0) + d%n_blocks
    do k = 1, d%n_patches
      if (allocated(d%patches(k)%cp)) nbulk = nbulk + 1
    end do
    do k = 1, d%n_sets
      if (size(d%sets(k)%ids) > 0) nbulk = nbulk + 1
    end do
    nmark = count_lines(rec, '** data: /deck/')
    call t%equal_int(nmark, nbulk, 'record '//path//': one marker per bulk block')
    call t%true(len(rec) < len(full) .and. index(rec, '** ...') == 0, &
        'record '//path//': shorter than the full echo, nothing cut')
    if (d%n_nodes > 0) call t%true(index(rec, '*NODE'//achar(10)//'** data: /deck/nodes, '// &
        str_of(d%n_nodes)//' lines'//achar(10)) > 0, 'record '//path//': the node marker')
    h0 = deck_record_digest(d)
    call t%true(deck_record_digest(d) == h0 .and. verify(h0, '0123456789ABCDEF') == 0, &
        'digest '//path//': the same for the same data, 16 hex digits: '//h0)
    if (d%n_nodes > 0) then
      d%node_x(2, 1) = nearest(d%node_x(2, 1), 1.0_dp)
      call t%true(deck_record_digest(d) /= h0, 'digest '//path//': one ulp of one coordinate')
      d%node_x(2, 1) = nearest(d%node_x(2, 1), -1.0_dp)
      call t%true(deck_record_digest(d) == h0, 'digest '//path//': the coordinate restored')
    end if
    if (d%n_blocks > 0) then
      k = d%blocks(1)%conn(1, 1)
      d%blocks(1)%conn(1, 1) = d%blocks(1)%conn(2, 1)
      d%blocks(1)%conn(2, 1) = k
      call t%true(deck_record_digest(d) /= h0, 'digest '//path//': two nodes of an element swapped')
    end if
    if (d%n_patches > 0) then
      d%patches(1)%cp(3, 1) = 2.0_dp*d%patches(1)%cp(3, 1)
      call t%true(deck_record_digest(d) /= h0, 'digest '//path//': a weight changed')
    end if
  end subroutine case_record

  !> Number of lines of `text` that begin with `head` ('*': card lines, not comments).
  integer function count_lines(text, head) result(n)
    character(len=*), intent(in) :: text, head
    integer :: p, q
    n = 0
    p = 1
    do while (p <= len(text))
      q = index(text(p:), achar(10))
      if (q == 0) q = len(text) - p + 2
      if (q - 1 >= len(head)) then
        if (text(p:p + len(head) - 1) == head) then
          if (head /= '*' .or. text(p:min(p + 1, len(text))) /= '**') n = n + 1
        end if
      end if
      p = p + q
    end do
  end function count_lines

  function str_of(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=12) :: b
    write(b, '(i0)') i
    s = trim(b)
  end function str_of

  !> A missing deck file is one error, no crash.
  subroutine case_missing_file(t)
    type(checker_t), intent(inout) :: t
    type(deck_t) :: d
    integer :: n0
    n0 = error_count()
    call read_deck('no/such/deck.inp', d)
    call t%equal_int(error_count() - n0, 1, 'missing file: one error')
    call reset_errors()
  end subroutine case_missing_file

  !> Field-by-field comparison of two decks (locations excepted).
  subroutine compare_decks(t, a, b, label)
    type(checker_t), intent(inout) :: t
    type(deck_t), intent(in) :: a, b
    character(len=*), intent(in) :: label
    integer :: k
    logical :: same

    same = a%title == b%title .and. a%analysis == b%analysis .and. a%thickness == b%thickness
    call t%true(same, label//': heading and analysis')
    same = a%n_materials == b%n_materials
    do k = 1, min(a%n_materials, b%n_materials)
      associate (x => a%materials(k), y => b%materials(k))
        same = same .and. x%name == y%name .and. x%e == y%e .and. x%nu == y%nu .and. &
            x%rho == y%rho .and. (x%has_elastic .eqv. y%has_elastic) .and. &
            (x%has_density .eqv. y%has_density)
      end associate
    end do
    call t%true(same, label//': materials')
    same = a%n_nodes == b%n_nodes
    if (same) same = all(a%node_ids == b%node_ids) .and. all(a%node_x == b%node_x)
    call t%true(same, label//': nodes')
    same = a%n_blocks == b%n_blocks
    do k = 1, min(a%n_blocks, b%n_blocks)
      associate (x => a%blocks(k), y => b%blocks(k))
        same = same .and. x%etype == y%etype .and. x%nen == y%nen .and. x%elset == y%elset &
            .and. x%material == y%material .and. x%gauss == y%gauss .and. &
            size(x%ids) == size(y%ids)
        if (same) same = all(x%ids == y%ids) .and. all(x%conn == y%conn)
      end associate
    end do
    call t%true(same, label//': element blocks')
    same = a%n_sets == b%n_sets
    do k = 1, min(a%n_sets, b%n_sets)
      associate (x => a%sets(k), y => b%sets(k))
        same = same .and. x%name == y%name .and. x%kind == y%kind .and. x%patch == y%patch &
            .and. x%side == y%side .and. size(x%ids) == size(y%ids) .and. &
            size(x%refs) == size(y%refs)
        if (same) same = all(x%ids == y%ids) .and. all(x%refs == y%refs)
      end associate
    end do
    call t%true(same, label//': sets')
    same = a%n_surfaces == b%n_surfaces
    do k = 1, min(a%n_surfaces, b%n_surfaces)
      associate (x => a%surfaces(k), y => b%surfaces(k))
        same = same .and. x%name == y%name .and. x%kind == y%kind .and. x%patch == y%patch &
            .and. x%side == y%side .and. size(x%elem) == size(y%elem)
        if (same) same = all(x%elem == y%elem) .and. all(x%face == y%face) .and. &
            all(x%elset == y%elset)
      end associate
    end do
    call t%true(same, label//': surfaces')
    call compare_conditions(t, a, b, label)
    call compare_patches(t, a, b, label)
  end subroutine compare_decks

  subroutine compare_conditions(t, a, b, label)
    type(checker_t), intent(inout) :: t
    type(deck_t), intent(in) :: a, b
    character(len=*), intent(in) :: label
    integer :: k
    logical :: same
    same = a%n_boundaries == b%n_boundaries .and. a%n_velocities == b%n_velocities
    do k = 1, min(a%n_boundaries, b%n_boundaries)
      associate (x => a%boundaries(k), y => b%boundaries(k))
        same = same .and. x%target == y%target .and. x%first_dof == y%first_dof .and. &
            x%last_dof == y%last_dof .and. x%value == y%value
      end associate
    end do
    do k = 1, min(a%n_velocities, b%n_velocities)
      associate (x => a%velocities(k), y => b%velocities(k))
        same = same .and. x%target == y%target .and. x%dof == y%dof .and. x%value == y%value
      end associate
    end do
    call t%true(same, label//': boundaries and velocities')
    same = a%n_masses == b%n_masses .and. a%n_dampings == b%n_dampings
    do k = 1, min(a%n_masses, b%n_masses)
      associate (x => a%masses(k), y => b%masses(k))
        same = same .and. x%kind == y%kind .and. x%alpha == y%alpha .and. &
            x%hrz_rule == y%hrz_rule .and. x%elset == y%elset .and. x%patch == y%patch
      end associate
    end do
    do k = 1, min(a%n_dampings, b%n_dampings)
      associate (x => a%dampings(k), y => b%dampings(k))
        same = same .and. x%alpha == y%alpha .and. x%elset == y%elset .and. x%patch == y%patch
      end associate
    end do
    call t%true(same, label//': mass and damping')
    same = a%n_pairs == b%n_pairs .and. a%n_walls == b%n_walls
    do k = 1, min(a%n_pairs, b%n_pairs)
      associate (x => a%pairs(k), y => b%pairs(k))
        same = same .and. x%name == y%name .and. x%penalty == y%penalty .and. &
            x%algorithm == y%algorithm .and. x%mass_penalty == y%mass_penalty .and. &
            x%first == y%first .and. x%second == y%second
      end associate
    end do
    do k = 1, min(a%n_walls, b%n_walls)
      associate (x => a%walls(k), y => b%walls(k))
        same = same .and. x%name == y%name .and. all(x%point == y%point) .and. &
            all(x%normal == y%normal) .and. x%penalty == y%penalty .and. x%surface == y%surface
      end associate
    end do
    call t%true(same, label//': contact pairs and walls')
    same = (a%has_step .eqv. b%has_step) .and. a%step%dt == b%step%dt .and. &
        a%step%t_end == b%step%t_end .and. a%step%safety == b%step%safety .and. &
        a%step%history_every == b%step%history_every .and. &
        a%step%field_every == b%step%field_every .and. &
        a%step%history_interval == b%step%history_interval .and. &
        a%step%field_interval == b%step%field_interval .and. &
        all(a%step%field_vars .eqv. b%step%field_vars) .and. &
        (a%step%field_vars_given .eqv. b%step%field_vars_given) .and. &
        a%step%n_out_sets == b%step%n_out_sets .and. &
        a%step%restart_every == b%step%restart_every .and. &
        a%step%mass_solver == b%step%mass_solver .and. a%step%mass_tol == b%step%mass_tol &
        .and. a%step%mass_passes == b%step%mass_passes
    do k = 1, min(a%step%n_out_sets, b%step%n_out_sets)
      associate (x => a%step%out_sets(k), y => b%step%out_sets(k))
        same = same .and. x%name == y%name .and. all(x%vars .eqv. y%vars) .and. &
            (x%vars_given .eqv. y%vars_given) .and. x%every == y%every .and. &
            x%interval == y%interval
      end associate
    end do
    call t%true(same, label//': step')
  end subroutine compare_conditions

  subroutine compare_patches(t, a, b, label)
    type(checker_t), intent(inout) :: t
    type(deck_t), intent(in) :: a, b
    character(len=*), intent(in) :: label
    integer :: k
    logical :: same
    same = a%n_patches == b%n_patches .and. a%n_patch_ops == b%n_patch_ops
    do k = 1, min(a%n_patches, b%n_patches)
      associate (x => a%patches(k), y => b%patches(k))
        same = same .and. x%name == y%name .and. x%material == y%material .and. &
            all(x%degree == y%degree) .and. all(x%size == y%size) .and. &
            all(x%has_knots .eqv. y%has_knots) .and. (x%has_cp .eqv. y%has_cp)
        if (same) same = size(x%knots1) == size(y%knots1) .and. &
            size(x%knots2) == size(y%knots2) .and. size(x%cp) == size(y%cp)
        if (same) same = all(x%knots1 == y%knots1) .and. all(x%knots2 == y%knots2) .and. &
            all(x%cp == y%cp)
        if (same .and. allocated(x%knots3)) same = allocated(y%knots3)
        if (same .and. allocated(x%knots3)) same = all(x%knots3 == y%knots3)
      end associate
    end do
    do k = 1, min(a%n_patch_ops, b%n_patch_ops)
      associate (x => a%patch_ops(k), y => b%patch_ops(k))
        same = same .and. x%kind == y%kind .and. x%patch == y%patch .and. &
            all(x%values == y%values)
      end associate
    end do
    call t%true(same, label//': patches and patch operations')
  end subroutine compare_patches

  !> True when trim(s) ends with `tail`.
  logical function ends_with(s, tail)
    character(len=*), intent(in) :: s, tail
    integer :: n
    n = len_trim(s)
    ends_with = n >= len(tail)
    if (ends_with) ends_with = s(n - len(tail) + 1:n) == tail
  end function ends_with

end program test_deck_reader
