!> Lumping schemes against the exact fractions of doc/theory.md §3 (square Q8) and the
!! conservation/positivity properties of that section (Q4, Q9, distorted elements).
program test_lumping
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, elem_shape_t
  use ictus_elements_library, only: etype_name, etype_nen
  use ictus_elements_lagrange, only: lagrange_shape_data
  use ictus_elements_solid2d, only: solid2d_mass
  use ictus_mass_lumping, only: lump_row_sum, lump_hrz, lump_alpha_q8
  use ictus_test_mass, only: check_positive
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  !> Unit-square node positions in deck order.
  real(dp), parameter :: sq(2, 9) = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, &
      0.0_dp, 1.0_dp, 0.5_dp, 0.0_dp, 1.0_dp, 0.5_dp, 0.5_dp, 1.0_dp, 0.0_dp, 0.5_dp, &
      0.5_dp, 0.5_dp], [2, 9])
  call t%start("mass/lumping")
  call case_q8_square(t)
  call case_alpha(t)
  call case_q9_square(t)
  call case_conservation(t, ETYPE_Q4)
  call case_conservation(t, ETYPE_Q8)
  call case_conservation(t, ETYPE_Q9)
  call t%finish()

contains

  !> Checks corner (1..4) and midside (5..8) fractions of m, absolute 1e-14.
  subroutine check_fractions(t, ml, m, corner, midside, label)
    type(checker_t), intent(inout) :: t
    real(dp), intent(in) :: ml(:), m, corner, midside
    character(len=*), intent(in) :: label
    integer :: a
    do a = 1, 4
      call t%close_abs(ml(a)/m, corner, 1.0e-14_dp, label//' corner')
      call t%close_abs(ml(a + 4)/m, midside, 1.0e-14_dp, label//' midside')
    end do
  end subroutine check_fractions

  !> Square Q8 of side 2, rho = 1.5, thickness 0.8 (m = 4.8).
  subroutine case_q8_square(t)
    type(checker_t), intent(inout) :: t
    type(elem_shape_t) :: shp2, shp3
    real(dp) :: xl(2, 8), me(8, 8), me2(8, 8), m, m2, ml(8), diag(8), diag2(8)
    integer :: ierr, a, bad(8), nbad
    call lagrange_shape_data(ETYPE_Q8, 3, shp3)
    call lagrange_shape_data(ETYPE_Q8, 2, shp2)
    xl = 2.0_dp*sq(:, 1:8)
    call solid2d_mass(8, shp3, xl, 1.5_dp, 0.8_dp, me, m, ierr)
    call solid2d_mass(8, shp2, xl, 1.5_dp, 0.8_dp, me2, m2, ierr)
    call t%close(m, 4.8_dp, 1.0e-14_dp, 'Q8 square m')
    call t%close(m2, 4.8_dp, 1.0e-14_dp, 'Q8 square m (2x2)')
    diag = [(me(a, a), a = 1, 8)]
    diag2 = [(me2(a, a), a = 1, 8)]
    call check_fractions(t, diag, m, 1.0_dp/30.0_dp, 8.0_dp/45.0_dp, 'consistent diagonal')
    call check_fractions(t, diag2, m, 1.0_dp/54.0_dp, 4.0_dp/27.0_dp, '2x2 raw diagonal')
    call lump_hrz(8, diag2, m, ml)
    call check_fractions(t, ml, m, 1.0_dp/36.0_dp, 8.0_dp/36.0_dp, 'HRZ 2x2 (alpha = 2/9)')
    call t%close(sum(ml), m, 1.0e-14_dp, 'HRZ 2x2 conserves mass')
    call lump_hrz(8, diag, m, ml)
    call check_fractions(t, ml, m, 3.0_dp/76.0_dp, 16.0_dp/76.0_dp, 'HRZ 3x3 (alpha = 4/19)')
    call lump_row_sum(8, me, ml)
    call check_fractions(t, ml, m, -1.0_dp/12.0_dp, 1.0_dp/3.0_dp, 'row-sum (alpha = 1/3)')
    call t%close(sum(ml), m, 1.0e-14_dp, 'row-sum conserves mass')
    call check_positive(8, ml, bad, nbad)
    call t%equal_int(nbad, 4, 'row-sum Q8: 4 non-positive')
    call t%true(all(bad(1:4) == [1, 2, 3, 4]) .and. all(bad(5:8) == 0), &
        'row-sum Q8: the corners are flagged')
  end subroutine case_q8_square

  subroutine case_alpha(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: ml(8)
    integer :: bad(8), nbad
    call lump_alpha_q8(4.8_dp, 2.0_dp/9.0_dp, ml)
    call t%close(sum(ml), 4.8_dp, 1.0e-14_dp, 'alpha = 2/9 sums to m')
    call check_fractions(t, ml, 4.8_dp, 1.0_dp/36.0_dp, 8.0_dp/36.0_dp, 'alpha = 2/9')
    call lump_alpha_q8(4.8_dp, 4.0_dp/19.0_dp, ml)
    call check_fractions(t, ml, 4.8_dp, 3.0_dp/76.0_dp, 16.0_dp/76.0_dp, 'alpha = 4/19')
    call check_positive(8, ml, bad, nbad)
    call t%equal_int(nbad, 0, 'alpha = 4/19 positive')
    call lump_alpha_q8(1.0_dp, 1.0_dp/3.0_dp, ml)
    call t%close(sum(ml), 1.0_dp, 1.0e-14_dp, 'alpha = 1/3 sums to m')
    call check_positive(8, ml, bad, nbad)
    call t%equal_int(nbad, 4, 'alpha = 1/3 has 4 negative corners')
  end subroutine case_alpha

  !> Square Q9 of side 1: row-sum = tensor product of 1/6, 2/3, 1/6.
  subroutine case_q9_square(t)
    type(checker_t), intent(inout) :: t
    type(elem_shape_t) :: shp
    real(dp) :: me(9, 9), m, ml(9)
    integer :: ierr, a, bad(9), nbad
    call lagrange_shape_data(ETYPE_Q9, 3, shp)
    call solid2d_mass(9, shp, sq, 1.0_dp, 1.0_dp, me, m, ierr)
    call lump_row_sum(9, me, ml)
    do a = 1, 4
      call t%close_abs(ml(a), 1.0_dp/36.0_dp, 1.0e-14_dp, 'Q9 row-sum corner 1/36')
      call t%close_abs(ml(a + 4), 1.0_dp/9.0_dp, 1.0e-14_dp, 'Q9 row-sum midside 1/9')
    end do
    call t%close_abs(ml(9), 4.0_dp/9.0_dp, 1.0e-14_dp, 'Q9 row-sum centre 4/9')
    call check_positive(9, ml, bad, nbad)
    call t%equal_int(nbad, 0, 'Q9 row-sum positive')
  end subroutine case_q9_square

  !> Distorted, curved element: row-sum and HRZ (both rules) conserve the element mass, and
  !! HRZ is positive.
  subroutine case_conservation(t, et)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    type(elem_shape_t) :: shp, shp2
    real(dp) :: xl(2, 9), m, m2, ml(9)
    real(dp), allocatable :: me(:,:), me2(:,:)
    integer :: nen, ierr, a, bad(9), nbad
    nen = etype_nen(et)
    allocate(me(nen, nen), me2(nen, nen))
    call lagrange_shape_data(et, merge(2, 3, et == ETYPE_Q4), shp)
    call lagrange_shape_data(et, 2, shp2)
    xl(:, 1) = [0.0_dp, 0.0_dp]
    xl(:, 2) = [2.1_dp, 0.3_dp]
    xl(:, 3) = [2.4_dp, 1.8_dp]
    xl(:, 4) = [-0.3_dp, 1.5_dp]
    do a = 5, 8
      xl(:, a) = 0.5_dp*(xl(:, a - 4) + xl(:, mod(a - 4, 4) + 1)) + [0.07_dp, -0.05_dp]
    end do
    xl(:, 9) = 0.25_dp*sum(xl(:, 1:4), dim=2) + [0.05_dp, 0.04_dp]
    call solid2d_mass(nen, shp, xl(:, 1:nen), 2.0_dp, 0.5_dp, me, m, ierr)
    call solid2d_mass(nen, shp2, xl(:, 1:nen), 2.0_dp, 0.5_dp, me2, m2, ierr)
    call lump_row_sum(nen, me, ml(1:nen))
    call t%close(sum(ml(1:nen)), m, 1.0e-14_dp, etype_name(et)//' row-sum conserves mass')
    call lump_hrz(nen, [(me(a, a), a = 1, nen)], m, ml(1:nen))
    call t%close(sum(ml(1:nen)), m, 1.0e-14_dp, etype_name(et)//' HRZ conserves mass')
    call check_positive(nen, ml(1:nen), bad(1:nen), nbad)
    call t%equal_int(nbad, 0, etype_name(et)//' HRZ positive')
    call lump_hrz(nen, [(me2(a, a), a = 1, nen)], m, ml(1:nen))
    call t%close(sum(ml(1:nen)), m, 1.0e-14_dp, etype_name(et)//' HRZ 2x2 conserves mass')
    if (et == ETYPE_Q4) then
      call lump_row_sum(4, me, ml(1:4))
      call check_positive(4, ml(1:4), bad(1:4), nbad)
      call t%equal_int(nbad, 0, 'Q4 row-sum positive')
    end if
  end subroutine case_conservation
end program test_lumping
