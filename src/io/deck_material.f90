!> Readers of the material and mass cards (doc/user-guide.md §4-5): *MATERIAL with its *ELASTIC and
!! *DENSITY, then *MASS (the mass matrix and its lumping) and *DAMPING (mass-proportional
!! damping), both for the whole model or one body (ELSET= or PATCH=).
!!
!! *ELASTIC and *DENSITY belong to the *MATERIAL just before them (`reader_t%material`);
!! that every material got both is checked by `check_deck` (ictus_io_deck_checks).
module ictus_io_deck_material
  use ictus_core_kinds, only: dp, str_len
  use ictus_core_errors, only: input_error
  use ictus_core_strings, only: str
  use ictus_io_deck_lexer, only: line_where
  use ictus_io_deck_types, only: deck_t, mass_in_t, damping_in_t, MASS_CONSISTENT, &
      MASS_ROW_SUM, MASS_HRZ, MASS_ALPHA, HRZ_FULL, HRZ_GAUSS2
  use ictus_io_deck_card, only: card_t, reader_t, card_error, check_params, get_name, &
      get_choice, get_reals, no_data, one_line, line_reals, has_flag, has_data
  use ictus_io_deck_grow, only: grow_materials, grow_masses, grow_dampings
  implicit none
  private
  public :: read_material, read_elastic, read_density, read_mass, read_damping, &
      read_hyperelastic, read_plastic

  !> Codes of the choices of *MASS, TYPE= and INTEGRATION=, in list order.
  integer, parameter :: mass_codes(4) = [MASS_CONSISTENT, MASS_ROW_SUM, MASS_HRZ, MASS_ALPHA]
  integer, parameter :: hrz_codes(2) = [HRZ_FULL, HRZ_GAUSS2]

contains

  ! ------------------------------------------------------------------------------------------
  ! Materials
  ! ------------------------------------------------------------------------------------------

  !> *MATERIAL, NAME=name: opens a material for the *ELASTIC and *DENSITY that follow.
  subroutine read_material(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=str_len) :: name
    integer :: k

    rd%material = -1
    call check_params(c, 'NAME', '')
    call get_name(c, 'NAME', .true., name)
    call no_data(c, rd)
    if (c%bad) return
    do k = 1, d%n_materials
      if (d%materials(k)%name == name) then
        call card_error(c, 'duplicate material name '//trim(name)//' (first defined at '// &
            trim(d%materials(k)%where)//')')
        return
      end if
    end do
    call grow_materials(d%materials, d%n_materials + 1)
    d%n_materials = d%n_materials + 1
    d%materials(d%n_materials)%name = name
    d%materials(d%n_materials)%where = c%where
    rd%material = d%n_materials
  end subroutine read_material

  !> *ELASTIC: one data line "E, nu" for the current material.
  subroutine read_elastic(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*ELASTIC: expected 2 numbers (E, nu)'
    real(dp) :: v(2)
    integer :: kind, i

    call check_params(c, 'TYPE', '')
    call get_choice(c, 'TYPE', 'ISOTROPIC', kind)
    if (.not. material_context(c, rd)) return
    associate (m => d%materials(rd%material))
      if (m%has_elastic) then
        call card_error(c, 'second *ELASTIC for material '//trim(m%name))
        return
      end if
      if (m%has_hyperelastic) then
        call card_error(c, 'material '//trim(m%name)//' has *HYPERELASTIC already (at '// &
            trim(m%law_where)//'): one elastic law per material')
        return
      end if
      m%has_elastic = .true.
      m%law_where = c%where
      if (c%bad) return
      if (.not. one_line(c, rd, expect, i)) return
      if (.not. line_reals(rd, i, 2, expect, v)) return
      m%e = v(1)
      m%nu = v(2)
      if (v(1) <= 0.0_dp) call input_error(line_where(rd%src, i), '*ELASTIC: Young''s '// &
          'modulus E must be > 0, found '//str(v(1)))
      if (v(2) <= -1.0_dp .or. v(2) >= 0.5_dp) call input_error(line_where(rd%src, i), &
          '*ELASTIC: Poisson''s ratio nu must lie in (-1, 0.5), found '//str(v(2)))
    end associate
  end subroutine read_elastic

  !> *HYPERELASTIC, NEO HOOKE: one data line "C10, D1" (the compressible neo-Hookean law of
  !! the Abaqus form; it needs NLGEOM=YES on *STEP, checked by check_deck).
  subroutine read_hyperelastic(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*HYPERELASTIC: expected 2 numbers (C10, D1)'
    real(dp) :: v(2)
    integer :: i
    call check_params(c, '', 'NEO HOOKE')
    if (.not. has_flag(c, 'NEO HOOKE')) call card_error(c, 'the neo-Hookean law is the one '// &
        'hyperelastic law (expected *HYPERELASTIC, NEO HOOKE)')
    if (.not. material_context(c, rd)) return
    associate (m => d%materials(rd%material))
      if (m%has_elastic .or. m%has_hyperelastic) then
        call card_error(c, 'material '//trim(m%name)//' has an elastic law already (at '// &
            trim(m%law_where)//'): one elastic law per material')
        return
      end if
      m%has_hyperelastic = .true.
      m%law_where = c%where
      if (c%bad) return
      if (.not. one_line(c, rd, expect, i)) return
      if (.not. line_reals(rd, i, 2, expect, v)) return
      m%c10 = v(1)
      m%d1 = v(2)
      if (.not. v(1) > 0.0_dp) call input_error(line_where(rd%src, i), '*HYPERELASTIC: '// &
          'C10 must be > 0 (the shear modulus is 2 C10), found '//str(v(1)))
      if (.not. v(2) > 0.0_dp) call input_error(line_where(rd%src, i), '*HYPERELASTIC: '// &
          'D1 must be > 0 (the bulk modulus is 2/D1), found '//str(v(2)))
    end associate
  end subroutine read_hyperelastic

  !> *PLASTIC: lines "sigma_y, epbar" of the isotropic hardening table of J2 plasticity,
  !! epbar starting at 0 and increasing; with *ELASTIC (checked by check_deck).
  subroutine read_plastic(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*PLASTIC: expected 2 numbers per line '// &
        '(yield stress, equivalent plastic strain)'
    real(dp) :: v(2)
    integer :: i, n
    call check_params(c, 'HARDENING', '')
    call get_choice(c, 'HARDENING', 'ISOTROPIC', n)
    if (.not. material_context(c, rd)) return
    associate (m => d%materials(rd%material))
      if (m%has_plastic) then
        call card_error(c, 'second *PLASTIC for material '//trim(m%name))
        return
      end if
      m%has_plastic = .true.
      if (c%bad) return
      if (.not. has_data(c, expect)) return
      allocate(m%plastic(2, c%last - c%first + 1))
      n = 0
      do i = c%first, c%last
        if (.not. line_reals(rd, i, 2, expect, v)) return
        n = n + 1
        m%plastic(:, n) = v
        if (.not. v(1) > 0.0_dp) call input_error(line_where(rd%src, i), '*PLASTIC: the '// &
            'yield stress must be > 0, found '//str(v(1)))
        if (n == 1 .and. v(2) /= 0.0_dp) call input_error(line_where(rd%src, i), &
            '*PLASTIC: the first equivalent plastic strain must be 0 (the initial yield '// &
            'stress), found '//str(v(2)))
        if (n > 1) then
          if (.not. v(2) > m%plastic(2, n - 1)) call input_error(line_where(rd%src, i), &
              '*PLASTIC: the equivalent plastic strains must increase, found '// &
              str(v(2))//' after '//str(m%plastic(2, n - 1)))
        end if
      end do
    end associate
  end subroutine read_plastic

  !> *DENSITY: one data line "rho" for the current material.
  subroutine read_density(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    character(len=*), parameter :: expect = '*DENSITY: expected 1 number (rho)'
    real(dp) :: v(1)
    integer :: i

    call check_params(c, '', '')
    if (.not. material_context(c, rd)) return
    associate (m => d%materials(rd%material))
      if (m%has_density) then
        call card_error(c, 'second *DENSITY for material '//trim(m%name))
        return
      end if
      m%has_density = .true.
      if (c%bad) return
      if (.not. one_line(c, rd, expect, i)) return
      if (.not. line_reals(rd, i, 1, expect, v)) return
      m%rho = v(1)
      if (v(1) <= 0.0_dp) call input_error(line_where(rd%src, i), &
          '*DENSITY: density rho must be > 0, found '//str(v(1)))
    end associate
  end subroutine read_density

  !> True when a material card may be read now (after *MATERIAL); reports it otherwise.
  logical function material_context(c, rd) result(ok)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    ok = rd%material > 0
    if (rd%material == 0) call card_error(c, 'no preceding *MATERIAL card (expected '// &
        '*MATERIAL, NAME=name before it)')
  end function material_context

  ! ------------------------------------------------------------------------------------------
  ! Mass and damping
  ! ------------------------------------------------------------------------------------------

  !> *DAMPING, ALPHA=a [, ELSET= | PATCH=].
  subroutine read_damping(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    type(damping_in_t) :: dm
    real(dp) :: a(1)

    call check_params(c, 'ALPHA|ELSET|PATCH', '')
    if (get_reals(c, 'ALPHA', 1, 'a number >= 0', a)) then
      if (a(1) < 0.0_dp) then
        call card_error(c, 'ALPHA='//str(a(1))//' must be >= 0')
      else
        dm%alpha = a(1)
      end if
    end if
    call get_body(c, dm%elset, dm%patch)
    call no_data(c, rd)
    if (c%bad) return
    dm%where = c%where
    call grow_dampings(d%dampings, d%n_dampings + 1)
    d%n_dampings = d%n_dampings + 1
    d%dampings(d%n_dampings) = dm
  end subroutine read_damping

  !> *MASS, TYPE=CONSISTENT|ROW SUM|HRZ|ALPHA [, ALPHA=a] [, INTEGRATION=FULL|2X2]
  !! [, ELSET= | PATCH=].
  subroutine read_mass(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    type(mass_in_t) :: m
    real(dp) :: a(1)
    integer :: kind, rule

    call check_params(c, 'TYPE|ALPHA|INTEGRATION|ELSET|PATCH', '')
    call get_choice(c, 'TYPE', 'CONSISTENT|ROW SUM|HRZ|ALPHA', kind)
    if (kind > 0) m%kind = mass_codes(kind)
    call get_choice(c, 'INTEGRATION', 'FULL|2X2', rule)
    if (rule > 0) m%hrz_rule = hrz_codes(rule)
    if (rule > 0 .and. m%kind /= MASS_HRZ) call card_error(c, &
        'INTEGRATION= applies to TYPE=HRZ only')
    if (get_reals(c, 'ALPHA', 1, 'a number in [0, 0.25]', a)) then
      if (m%kind /= MASS_ALPHA) then
        call card_error(c, 'ALPHA= applies to TYPE=ALPHA only')
      else if (a(1) < 0.0_dp .or. a(1) > 0.25_dp) then
        call card_error(c, 'ALPHA='//str(a(1))//' outside [0, 0.25] (midside a*m_e, '// &
            'corner (1/4 - a)*m_e must be >= 0)')
      else
        m%alpha = a(1)
      end if
    else if (m%kind == MASS_ALPHA .and. .not. c%bad) then
      call card_error(c, 'TYPE=ALPHA needs ALPHA=a (0 <= a <= 0.25)')
    end if
    call get_body(c, m%elset, m%patch)
    call no_data(c, rd)
    if (c%bad) return
    m%where = c%where
    call grow_masses(d%masses, d%n_masses + 1)
    d%n_masses = d%n_masses + 1
    d%masses(d%n_masses) = m
  end subroutine read_mass

  !> Optional ELSET= or PATCH= (not both) selecting a body.
  subroutine get_body(c, elset, patch)
    type(card_t), intent(inout) :: c
    character(len=*), intent(out) :: elset, patch
    call get_name(c, 'ELSET', .false., elset)
    call get_name(c, 'PATCH', .false., patch)
    if (len_trim(elset) > 0 .and. len_trim(patch) > 0) call card_error(c, &
        'give ELSET= or PATCH=, not both')
  end subroutine get_body

end module ictus_io_deck_material
