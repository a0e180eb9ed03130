!> Lumping schemes against the exact fractions of doc/theory.md §3 (square Q8) and the
!! conservation/positivity properties of that section (Q4, Q9, distorted elements).
!!
!! The hexahedra (doc/elements3d.md §4): fractions derived here from the integrals of the
!! shape functions over the parent cube [-1, 1]^3 (volume 8); the element mass m = rho V, so a
!! fraction is (the integral)/8.
!!
!! C3D20, corner at (1, 1, 1): N_c = (1 + xi)(1 + eta)(1 + zeta)(xi + eta + zeta - 2)/8.
!! With int_{-1}^{1} (1 + xi) = 2 and int (1 + xi) xi = 2/3, int N_c = (3 (2/3) 2 2 - 2 8)/8
!! = -1, so the row sum (int rho N_A dV) gives each corner -1/8 of m. A midside, e.g.
!! N_m = (1 - xi^2)(1 + eta)(1 + zeta)/4, integrates to (4/3) 2 2/4 = 4/3: 1/6 of m.
!! Check: 8 (-1/8) + 12 (1/6) = 1. The 8 corners are negative: they are the nodes the run
!! refuses with row-sum lumping (check_positive names 1..8).
!! C3D20 HRZ: the diagonal int N_A^2 (exact with 3x3x3 Gauss: degree 4 per direction) is
!! 28/135 at a corner and 64/135 at a midside; the trace 8 (28/135) + 12 (64/135) = 992/135,
!! so HRZ gives corners 28/992 = 7/248 and midsides 64/992 = 2/31 of m (8 (7/248) +
!! 12 (2/31) = 1, all positive). The consistent diagonal itself is 7/270 and 8/135 of m.
!! With the 2x2x2 rule the diagonal changes: corners 1/40, midsides 1/15 of m.
!! C3D27 and C3D8: tensor products. In 1D on [-1, 1] the quadratics through -1, 0, 1
!! integrate to 1/3, 4/3, 1/3 (fractions 1/6, 2/3, 1/6) and their squares to 4/15, 16/15,
!! 4/15 (HRZ fractions 1/6, 2/3, 1/6 again). So row-sum and HRZ of C3D27 both give
!! corners 1/216, midsides 1/54, face centres 2/27 and the centre 8/27; C3D8 gives 1/8
!! everywhere.
!! Distorted, curved hexahedra: row-sum and HRZ conserve the element mass; HRZ is positive.
program test_lumping
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, ETYPE_C3D8, ETYPE_C3D20, &
      ETYPE_C3D27, elem_shape_t
  use ictus_elements_library, only: etype_name, etype_nen, element_shape_data
  use ictus_elements_lagrange, only: lagrange_shape_data
  use ictus_elements_hexahedra, only: hexahedra_node_xi
  use ictus_elements_solid2d, only: solid2d_mass
  use ictus_elements_solid3d, only: solid3d_mass
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
  call case_c3d8_cube(t)
  call case_c3d20_cube(t)
  call case_c3d27_cube(t)
  call case_conservation3(t, ETYPE_C3D8)
  call case_conservation3(t, ETYPE_C3D20)
  call case_conservation3(t, ETYPE_C3D27)
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
    call check_conservation(t, etype_name(et), nen, me, me2, m)
    if (et == ETYPE_Q4) then
      call lump_row_sum(4, me, ml(1:4))
      call check_positive(4, ml(1:4), bad(1:4), nbad)
      call t%equal_int(nbad, 0, 'Q4 row-sum positive')
    end if
  end subroutine case_conservation

  !> Row-sum and HRZ of the consistent mass me(nen, nen) conserve the element mass m; HRZ is
  !! positive; HRZ of the diagonal of me2 (the 2x2 or 2x2x2 rule) conserves m too.
  subroutine check_conservation(t, label, nen, me, me2, m)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: label
    integer, intent(in) :: nen
    real(dp), intent(in) :: me(nen, nen), me2(nen, nen), m
    real(dp) :: ml(nen)
    integer :: a, bad(nen), nbad
    call lump_row_sum(nen, me, ml)
    call t%close(sum(ml), m, 1.0e-14_dp, label//' row-sum conserves mass')
    call lump_hrz(nen, [(me(a, a), a = 1, nen)], m, ml)
    call t%close(sum(ml), m, 1.0e-14_dp, label//' HRZ conserves mass')
    call check_positive(nen, ml, bad, nbad)
    call t%equal_int(nbad, 0, label//' HRZ positive')
    call lump_hrz(nen, [(me2(a, a), a = 1, nen)], m, ml)
    call t%close(sum(ml), m, 1.0e-14_dp, label//' HRZ 2x2 conserves mass')
  end subroutine check_conservation

  !> Nodes of a cube of side h at the origin (nen of type et), its shape data for ng points
  !! per direction, and its consistent mass me (allocated) and mass m with density rho.
  subroutine cube_mass(et, ng, h, rho, me, m)
    integer, intent(in) :: et, ng
    real(dp), intent(in) :: h, rho
    real(dp), allocatable, intent(out) :: me(:,:)
    real(dp), intent(out) :: m
    type(elem_shape_t) :: shp
    real(dp) :: xl(3, 27), xa(3)
    integer :: nen, a, ierr
    nen = etype_nen(et)
    do a = 1, nen
      call hexahedra_node_xi(a, xa)
      xl(:, a) = 0.5_dp*h*(xa + 1.0_dp)
    end do
    call element_shape_data(et, ng, shp)
    allocate(me(nen, nen))
    call solid3d_mass(nen, shp, xl(:, 1:nen), rho, me, m, ierr)
  end subroutine cube_mass

  !> Checks the fractions ml(a)/m of a hexahedron's node groups: corners 1-8, midsides 9-20, face
  !! centres 21-26, centre 27 (as far as ml goes), absolute 1e-14.
  subroutine check_fractions3(t, ml, m, fr, label)
    type(checker_t), intent(inout) :: t
    real(dp), intent(in) :: ml(:), m, fr(4)
    character(len=*), intent(in) :: label
    character(len=*), parameter :: grp(4) = [character(len=12) :: 'corner', 'midside', &
        'face centre', 'centre']
    integer :: a, k
    do a = 1, size(ml)
      ! C3D27: node 21 the centre, 22-27 the face centres
      k = merge(1, merge(2, merge(4, 3, a == 21), a <= 20), a <= 8)
      call t%close_abs(ml(a)/m, fr(k), 1.0e-14_dp, label//' '//trim(grp(k)))
    end do
  end subroutine check_fractions3

  subroutine case_c3d8_cube(t)
    type(checker_t), intent(inout) :: t
    real(dp), allocatable :: me(:,:)
    real(dp) :: m, ml(8)
    integer :: a
    call cube_mass(ETYPE_C3D8, 2, 2.0_dp, 1.5_dp, me, m)
    call t%close(m, 12.0_dp, 1.0e-14_dp, 'C3D8 cube m = rho h^3')
    call lump_row_sum(8, me, ml)
    call check_fractions3(t, ml, m, [0.125_dp, 0.0_dp, 0.0_dp, 0.0_dp], 'C3D8 row-sum')
    call lump_hrz(8, [(me(a, a), a = 1, 8)], m, ml)
    call check_fractions3(t, ml, m, [0.125_dp, 0.0_dp, 0.0_dp, 0.0_dp], 'C3D8 HRZ')
  end subroutine case_c3d8_cube

  subroutine case_c3d20_cube(t)
    type(checker_t), intent(inout) :: t
    real(dp), allocatable :: me(:,:), me2(:,:)
    real(dp) :: m, m2, ml(20), diag(20)
    integer :: a, bad(20), nbad
    call cube_mass(ETYPE_C3D20, 3, 2.0_dp, 1.5_dp, me, m)
    call cube_mass(ETYPE_C3D20, 2, 2.0_dp, 1.5_dp, me2, m2)
    call t%close(m, 12.0_dp, 1.0e-14_dp, 'C3D20 cube m')
    call t%close(m2, 12.0_dp, 1.0e-14_dp, 'C3D20 cube m (2x2x2)')
    diag = [(me(a, a), a = 1, 20)]
    call check_fractions3(t, diag, m, [7.0_dp/270.0_dp, 8.0_dp/135.0_dp, 0.0_dp, 0.0_dp], &
        'C3D20 consistent diagonal')
    call lump_row_sum(20, me, ml)
    call check_fractions3(t, ml, m, [-0.125_dp, 1.0_dp/6.0_dp, 0.0_dp, 0.0_dp], &
        'C3D20 row-sum')
    call t%close(sum(ml), m, 1.0e-14_dp, 'C3D20 row-sum conserves mass')
    call check_positive(20, ml, bad, nbad)
    call t%equal_int(nbad, 8, 'C3D20 row-sum: 8 non-positive')
    call t%true(all(bad(1:8) == [1, 2, 3, 4, 5, 6, 7, 8]) .and. all(bad(9:) == 0), &
        'C3D20 row-sum: the corners are flagged')
    call lump_hrz(20, diag, m, ml)
    call check_fractions3(t, ml, m, [7.0_dp/248.0_dp, 2.0_dp/31.0_dp, 0.0_dp, 0.0_dp], &
        'C3D20 HRZ')
    call t%close(sum(ml), m, 1.0e-14_dp, 'C3D20 HRZ conserves mass')
    call check_positive(20, ml, bad, nbad)
    call t%equal_int(nbad, 0, 'C3D20 HRZ positive')
    call lump_hrz(20, [(me2(a, a), a = 1, 20)], m, ml)
    call check_fractions3(t, ml, m, [1.0_dp/40.0_dp, 1.0_dp/15.0_dp, 0.0_dp, 0.0_dp], &
        'C3D20 HRZ 2x2x2')
  end subroutine case_c3d20_cube

  subroutine case_c3d27_cube(t)
    type(checker_t), intent(inout) :: t
    real(dp), allocatable :: me(:,:)
    real(dp) :: m, ml(27), fr(4)
    integer :: a, bad(27), nbad
    call cube_mass(ETYPE_C3D27, 3, 1.0_dp, 1.0_dp, me, m)
    fr = [1.0_dp/216.0_dp, 1.0_dp/54.0_dp, 2.0_dp/27.0_dp, 8.0_dp/27.0_dp]
    call lump_row_sum(27, me, ml)
    call check_fractions3(t, ml, m, fr, 'C3D27 row-sum')
    call check_positive(27, ml, bad, nbad)
    call t%equal_int(nbad, 0, 'C3D27 row-sum positive')
    call lump_hrz(27, [(me(a, a), a = 1, 27)], m, ml)
    call check_fractions3(t, ml, m, fr, 'C3D27 HRZ')
  end subroutine case_c3d27_cube

  !> Distorted hexahedron with curved edges: row-sum and HRZ (full and 2x2x2 diagonal)
  !! conserve the element mass, HRZ is positive.
  subroutine case_conservation3(t, et)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    type(elem_shape_t) :: shp, shp2
    real(dp) :: xl(3, 27), xa(3), m, m2
    real(dp), allocatable :: me(:,:), me2(:,:)
    integer :: nen, a, ierr
    nen = etype_nen(et)
    allocate(me(nen, nen), me2(nen, nen))
    call element_shape_data(et, merge(2, 3, et == ETYPE_C3D8), shp)
    call element_shape_data(et, 2, shp2)
    do a = 1, nen
      call hexahedra_node_xi(a, xa)
      xl(:, a) = [1.2_dp*xa(1) + 0.2_dp*xa(2)*xa(3), 0.9_dp*xa(2) + 0.1_dp*xa(1)**2, &
          0.7_dp*xa(3) - 0.15_dp*xa(1)*xa(2)]
      if (a > 8) xl(:, a) = xl(:, a) + 0.03_dp*[cos(1.7_dp*a), sin(0.9_dp*a), cos(2.3_dp*a)]
    end do
    call solid3d_mass(nen, shp, xl(:, 1:nen), 2.0_dp, me, m, ierr)
    call t%equal_int(ierr, 0, etype_name(et)//' distorted mass ierr')
    call solid3d_mass(nen, shp2, xl(:, 1:nen), 2.0_dp, me2, m2, ierr)
    call check_conservation(t, etype_name(et), nen, me, me2, m)
  end subroutine case_conservation3
end program test_lumping
