!> doc/architecture.md "Adding a material law", followed step by step with a toy law from
!! tests/ only (toy_law.f90: small-strain elasticity in Lame form with one history variable,
!! the largest strain-energy density reached):
!!   1. the file with a type that extends law_t, its init, stress and wave speed;
!!   2. the material holds it (for a deck law, one line in material_make_law);
!! then a Q4 model of it runs through the public seams. Expected values: AUTO takes the
!! element loop for a law without a constant tangent; with lambda and mu of E and nu the run
!! equals the built-in linear elastic law with the assembled K (to round-off); the history
!! holds at least the energy density of every state passed (its integral bounds the strain
!! energy of every record); the wave speed is sqrt((lambda + 2 mu)/rho).
program test_guide_law
  use ictus_core_kinds, only: dp
  use ictus_parallel_env, only: env_init, env_finalize
  use ictus_elements_types, only: ETYPE_Q4
  use ictus_materials_material, only: material_t, material_make_law
  use ictus_materials_law, only: kinematics_t, ANALYSIS_PLANE_STRAIN
  use ictus_solver_model, only: model_t, FORCE_ELEMENT, FORCE_ASSEMBLED
  use ictus_solver_internal_force, only: force_choice
  use guide_model, only: rectangle_model, run_t, run_setup, run_record
  use toy_law, only: lame_law_t
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  type(material_t) :: toy, lin
  real(dp), parameter :: rho = 2.0_dp, e_mod = 1000.0_dp, nu = 0.25_dp
  real(dp) :: lambda, mu
  call env_init()
  call t%start("guides/law")
  lambda = e_mod*nu/((1.0_dp + nu)*(1.0_dp - 2.0_dp*nu))
  mu = e_mod/(2.0_dp*(1.0_dp + nu))
  ! steps 1-2: the law, held by a material
  toy%name = 'toy'
  toy%density = rho
  toy%law = lame_law_t(lambda=lambda, mu=mu)
  toy%law%kin = kinematics_t(ANALYSIS_PLANE_STRAIN, .false.)
  call toy%law%init()
  lin%name = 'linear'
  lin%density = rho
  call material_make_law('LINEAR ELASTIC', [e_mod, nu], kinematics_t(), lin%law)
  call t%close(toy%law%wave_speed(rho), lin%law%wave_speed(rho), 1.0e-14_dp, &
      'wave speed = c_p')
  call case_run(t)
  call t%finish()
  call env_finalize()

contains

  subroutine case_run(t)
    type(checker_t), intent(inout) :: t
    type(model_t), target :: mt, ml
    type(run_t), target :: rt, rl
    real(dp), parameter :: dt = 2.0e-4_dp
    real(dp) :: err, emax, hint
    integer :: i, n, k, g
    call rectangle_model(mt, ETYPE_Q4, 4, 3, 1.0_dp, 0.75_dp, toy, 2)
    do i = 1, mt%nn
      mt%v0(:, i) = [0.1_dp*(mt%x0(1, i) - 0.5_dp), -0.05_dp*mt%x0(1, i)*mt%x0(2, i)]
    end do
    ml = mt
    ml%materials = [lin]
    call t%equal_int(force_choice(mt), FORCE_ELEMENT, 'AUTO: the element loop for the toy law')
    call t%equal_int(force_choice(ml), FORCE_ASSEMBLED, 'AUTO: assembled K for linear elastic')
    call run_setup(rt, mt, dt)
    call run_setup(rl, ml, dt)
    call t%true(all(shape(rt%stp%s%hist) == [1, 4, mt%nel]), 'history in the state: 1 per point')
    emax = 0.0_dp
    err = 0.0_dp
    do n = 0, 60, 5
      call run_record(rt, n)
      call run_record(rl, n)
      emax = max(emax, rt%stp%s%e_strain)
      err = max(err, abs(rt%stp%s%e_strain - rl%stp%s%e_strain)/max(rl%stp%s%e_strain, 1.0e-30_dp))
    end do
    call t%close_abs(maxval(abs(rt%stp%s%u - rl%stp%s%u)), 0.0_dp, &
        1.0e-12_dp*maxval(abs(rl%stp%s%u)), 'toy law = linear elastic (u)')
    call t%close_abs(err, 0.0_dp, 1.0e-12_dp, 'toy law = linear elastic (strain energy)')
    call t%true(emax > 0.0_dp, 'the body is strained')
    ! the integral of the history (max energy density so far) bounds every strain energy
    hint = 0.0_dp
    associate (el => rt%stp%fop%el)
      do k = 1, el%nelem
        do g = 1, el%ngp(k)
          hint = hint + rt%stp%s%hist(1, g, k)*el%dvol(g, k)
        end do
      end do
    end associate
    call t%true(all(rt%stp%s%hist >= 0.0_dp), 'history >= 0')
    call t%true(hint >= emax*(1.0_dp - 1.0e-12_dp), 'integral of the history >= the largest '// &
        'strain energy recorded')
  end subroutine case_run
end program test_guide_law
