!> Constitutive matrix against the hand formulas, wave speeds against doc/reference.md §1.2.
program test_elastic
  use ictus_core_kinds, only: dp
  use ictus_materials_elastic, only: elastic_dmat, wave_speed_p, wave_speed_s
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  call t%start("materials/elastic")
  call case_dmat(t)
  call case_speeds(t)
  call t%finish()

contains

  !> E = 1000, nu = 0.2. Plane strain: lambda + 2 mu = 10000/9, lambda = 2500/9,
  !! mu = 1250/3. Plane stress: E/(1 - nu^2) = 3125/3, nu E/(1 - nu^2) = 625/3, mu = 1250/3.
  subroutine case_dmat(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: d(3,3), want(3,3)
    integer :: i, j
    character(len=16) :: lab
    call elastic_dmat(1000.0_dp, 0.2_dp, .true., d)
    want = 0.0_dp
    want(1,1) = 10000.0_dp/9.0_dp
    want(2,2) = want(1,1)
    want(1,2) = 2500.0_dp/9.0_dp
    want(2,1) = want(1,2)
    want(3,3) = 1250.0_dp/3.0_dp
    do j = 1, 3
      do i = 1, 3
        write(lab, '(a,2i1)') 'strain D', i, j
        call t%close_abs(d(i,j), want(i,j), 1.0e-12_dp*want(1,1), trim(lab))
      end do
    end do
    call elastic_dmat(1000.0_dp, 0.2_dp, .false., d)
    want(1,1) = 3125.0_dp/3.0_dp
    want(2,2) = want(1,1)
    want(1,2) = 625.0_dp/3.0_dp
    want(2,1) = want(1,2)
    want(3,3) = 1250.0_dp/3.0_dp
    do j = 1, 3
      do i = 1, 3
        write(lab, '(a,2i1)') 'stress D', i, j
        call t%close_abs(d(i,j), want(i,j), 1.0e-12_dp*want(1,1), trim(lab))
      end do
    end do
    ! nu = 0: both reduce to diag(E, E, E/2)
    call elastic_dmat(7.0_dp, 0.0_dp, .true., d)
    call t%close(d(1,1), 7.0_dp, 1.0e-15_dp, 'nu=0 D11')
    call t%close(d(3,3), 3.5_dp, 1.0e-15_dp, 'nu=0 D33')
    call t%close_abs(d(1,2), 0.0_dp, 1.0e-15_dp, 'nu=0 D12')
  end subroutine case_dmat

  !> doc/reference.md §1.2 table: 33.333, 32.275, 20.412 (to 1e-4 relative); exact 100/3 for c_d.
  subroutine case_speeds(t)
    type(checker_t), intent(inout) :: t
    call t%close(wave_speed_p(1000.0_dp, 0.2_dp, 1.0_dp, .true.), 33.333_dp, 1.0e-4_dp, &
        'c_d strain')
    call t%close(wave_speed_p(1000.0_dp, 0.2_dp, 1.0_dp, .true.), 100.0_dp/3.0_dp, 1.0e-14_dp, &
        'c_d strain exact')
    call t%close(wave_speed_p(1000.0_dp, 0.2_dp, 1.0_dp, .false.), 32.275_dp, 1.0e-4_dp, &
        'c_d stress')
    call t%close(wave_speed_s(1000.0_dp, 0.2_dp, 1.0_dp), 20.412_dp, 1.0e-4_dp, 'c_s')
    ! density scaling c ~ rho^(-1/2)
    call t%close(wave_speed_s(1000.0_dp, 0.2_dp, 4.0_dp), 20.412_dp/2.0_dp, 1.0e-4_dp, 'c_s rho=4')
  end subroutine case_speeds
end program test_elastic
