!> Element library: shape-data dispatch and the element frequency bound element_omega_max.
!!
!! Closed forms (derived symbolically for a free square Q4 of side h, 2x2 Gauss, thickness t):
!! plane stress, nu = 0: lumped (m/4 per node) omega^2 = 4 E/(rho h^2) (omega = 2c/h, like the
!! 1D lumped bar), consistent omega^2 = 18 E/(rho h^2); plane strain, nu = 0.2: lumped
!! omega^2 = (50/9) E/(rho h^2), consistent (55/3) E/(rho h^2).
program test_library
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, ETYPE_IGA, elem_shape_t
  use ictus_elements_library, only: element_shape_data, element_default_ngauss
  use ictus_test_elements, only: element_omega_max
  use ictus_elements_solid2d, only: solid2d_stiffness, solid2d_mass
  use ictus_materials_elastic, only: elastic_dmat, wave_speed_p
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  call t%start("elements/library")
  call case_dispatch(t)
  call case_q4_closed_form(t)
  call case_q8_bounds(t)
  call t%finish()

contains

  !> Square element of side h with its lower-left corner at (x0, y0), deck node order.
  subroutine square(nen, h, x0, y0, xl)
    integer, intent(in) :: nen
    real(dp), intent(in) :: h, x0, y0
    real(dp), intent(out) :: xl(2, nen)
    real(dp), parameter :: c(2, 9) = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, &
        0.0_dp, 1.0_dp, 0.5_dp, 0.0_dp, 1.0_dp, 0.5_dp, 0.5_dp, 1.0_dp, 0.0_dp, 0.5_dp, &
        0.5_dp, 0.5_dp], [2, 9])
    xl(1, :) = x0 + h*c(1, 1:nen)
    xl(2, :) = y0 + h*c(2, 1:nen)
  end subroutine square

  subroutine case_dispatch(t)
    type(checker_t), intent(inout) :: t
    type(elem_shape_t) :: shp
    call t%equal_int(element_default_ngauss(ETYPE_Q4), 2, 'Q4 full rule')
    call t%equal_int(element_default_ngauss(ETYPE_Q8), 3, 'Q8 full rule')
    call t%equal_int(element_default_ngauss(ETYPE_Q9), 3, 'Q9 full rule')
    call element_shape_data(ETYPE_Q8, 2, shp)
    call t%true(shp%nen == 8 .and. shp%ngp == 4 .and. allocated(shp%n), 'Q8 2x2 shape data')
    call element_shape_data(ETYPE_Q9, 3, shp)
    call t%true(shp%nen == 9 .and. shp%ngp == 9 .and. size(shp%dn, 3) == 9, 'Q9 shape data')
    call element_shape_data(ETYPE_IGA, 3, shp)
    call t%true(shp%nen == 0 .and. .not. allocated(shp%n), 'IGA: no Lagrange shape data')
  end subroutine case_dispatch

  !> omega of a free square Q4 for given material; lumped = row-sum (m/4 on the square).
  subroutine q4_omega(h, e, nu, strain, lumped, omega)
    real(dp), intent(in) :: h, e, nu
    logical, intent(in) :: strain, lumped
    real(dp), intent(out) :: omega
    type(elem_shape_t) :: shp
    real(dp) :: xl(2, 4), d(3, 3), ke(8, 8), me(4, 4), mass_e
    integer :: ierr, a, info
    call element_shape_data(ETYPE_Q4, 2, shp)
    call square(4, h, 0.3_dp, -0.7_dp, xl)
    call elastic_dmat(e, nu, strain, d)
    call solid2d_stiffness(4, shp, xl, d, 0.3_dp, ke, ierr)
    call solid2d_mass(4, shp, xl, 1.0_dp, 0.3_dp, me, mass_e, ierr)
    if (lumped) then
      do a = 1, 4
        me(a, a) = sum(me(a, :))
      end do
    end if
    call element_omega_max(4, ke, me, lumped, omega, info)
    call t%equal_int(info, 0, 'Q4 omega info')
  end subroutine q4_omega

  subroutine case_q4_closed_form(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: omega
    call q4_omega(1.0_dp, 1.0_dp, 0.0_dp, .false., .true., omega)
    call t%close(omega, 2.0_dp, 1.0e-12_dp, 'Q4 lumped nu=0: omega = 2c/h')
    call q4_omega(1.0_dp, 1.0_dp, 0.0_dp, .false., .false., omega)
    call t%close(omega, sqrt(18.0_dp), 1.0e-12_dp, 'Q4 consistent nu=0: omega = sqrt(18)c/h')
    call q4_omega(1.0_dp, 1000.0_dp, 0.2_dp, .true., .true., omega)
    call t%close(omega, sqrt(50000.0_dp/9.0_dp), 1.0e-12_dp, 'Q4 lumped plane strain')
    call q4_omega(1.0_dp, 1000.0_dp, 0.2_dp, .true., .false., omega)
    call t%close(omega, sqrt(55000.0_dp/3.0_dp), 1.0e-12_dp, 'Q4 consistent plane strain')
    ! scaling: omega ~ 1/h
    call q4_omega(2.5_dp, 1000.0_dp, 0.2_dp, .true., .true., omega)
    call t%close(omega, sqrt(50000.0_dp/9.0_dp)/2.5_dp, 1.0e-12_dp, 'Q4 lumped h = 2.5')
    call q4_omega(2.5_dp, 1000.0_dp, 0.2_dp, .true., .false., omega)
    call t%close(omega, sqrt(55000.0_dp/3.0_dp)/2.5_dp, 1.0e-12_dp, 'Q4 consistent h = 2.5')
  end subroutine case_q4_closed_form

  !> Square Q8, plane strain, E = 1000, nu = 0.2: a free element's omega bounds the mesh's
  !! (doc/theory.md §7), so omega_e h/c_d must be at least the periodic-mesh values of
  !! doc/reference.md §6.2; omega_e scales like 1/h; a mass with negative entries is rejected.
  subroutine case_q8_bounds(t)
    type(checker_t), intent(inout) :: t
    type(elem_shape_t) :: shp3, shp2
    real(dp) :: xl(2, 8), d(3, 3), ke(16, 16), me(8, 8), me2(8, 8), ml(8, 8), mass_e, cd
    real(dp) :: om(4), om_h(4), h
    integer :: ierr, a, info, k
    character(len=*), parameter :: lab(4) = [character(len=12) :: 'consistent', 'HRZ 2x2', &
        'HRZ 3x3', 'alpha = 1/6']
    real(dp), parameter :: bound(4) = [8.031_dp, 8.724_dp, 7.563_dp, 6.000_dp]
    call element_shape_data(ETYPE_Q8, 3, shp3)
    call element_shape_data(ETYPE_Q8, 2, shp2)
    call elastic_dmat(1000.0_dp, 0.2_dp, .true., d)
    cd = wave_speed_p(1000.0_dp, 0.2_dp, 1.0_dp, .true.)
    do k = 1, 2
      h = merge(1.0_dp, 3.0_dp, k == 1)
      call square(8, h, 0.0_dp, 0.0_dp, xl)
      call solid2d_stiffness(8, shp3, xl, d, 1.0_dp, ke, ierr)
      call solid2d_mass(8, shp3, xl, 1.0_dp, 1.0_dp, me, mass_e, ierr)
      call solid2d_mass(8, shp2, xl, 1.0_dp, 1.0_dp, me2, mass_e, ierr)
      call element_omega_max(8, ke, me, .false., om(1), info)
      call t%equal_int(info, 0, 'Q8 consistent info')
      ml = 0.0_dp
      do a = 1, 8
        ml(a, a) = me2(a, a)*mass_e/sum([(me2(k, k), k = 1, 8)])
      end do
      call element_omega_max(8, ke, ml, .true., om(2))
      do a = 1, 8
        ml(a, a) = me(a, a)*mass_e/sum([(me(k, k), k = 1, 8)])
      end do
      call element_omega_max(8, ke, ml, .true., om(3))
      do a = 1, 8
        ml(a, a) = merge(mass_e/12.0_dp, mass_e/6.0_dp, a <= 4)
      end do
      call element_omega_max(8, ke, ml, .true., om(4))
      if (k == 1) om_h = om*h/cd
    end do
    do k = 1, 4
      call t%true(om_h(k) >= bound(k), 'Q8 '//trim(lab(k))//': omega_e h/c_d >= periodic bound')
      call t%true(om_h(k) < 3.0_dp*bound(k), 'Q8 '//trim(lab(k))//': omega_e same order')
      call t%close(om(k)*h/cd, om_h(k), 1.0e-12_dp, 'Q8 '//trim(lab(k))//': omega ~ 1/h')
    end do
    ! row-sum lumping of Q8 has negative corners: no frequency, info < 0
    do a = 1, 8
      ml(a, a) = sum(me(a, :))
    end do
    call element_omega_max(8, ke, ml, .true., om(1), info)
    call t%true(om(1) < 0.0_dp .and. info == -1, 'Q8 row-sum rejected (corner 1 negative)')
  end subroutine case_q8_bounds
end program test_library
