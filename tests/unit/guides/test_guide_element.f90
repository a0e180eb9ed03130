!> doc/architecture.md "Adding an element type", followed step by step with a toy element from
!! tests/ only (toy_t3.f90: the 3-node constant-strain triangle):
!!   1. the file with the shape functions, the quadrature rule and t3_kind();
!!   2. the dispatcher entry (for a built-in type one line in fill_table; from outside
!!      src/elements, element_register);
!!   3. its deck name, which element_type_of finds;
!! then a model of it runs through the public seams (assembly, mass operator, stepper).
!! Expected values: the mass rho A; a linear displacement field gives zero force at interior
!! nodes (the patch test of a constant-strain element); a rigid translation u = v0 t exactly,
!! with kinetic energy m |v0|^2 / 2; the element loop and the assembled K agree to round-off.
program test_guide_element
  use ictus_core_kinds, only: dp
  use ictus_parallel_env, only: env_init, env_finalize
  use ictus_elements_library, only: element_register, element_type_of, etype_name
  use ictus_materials_material, only: material_t, material_make_law
  use ictus_materials_law, only: kinematics_t
  use ictus_solver_model, only: model_t, FORCE_ASSEMBLED, FORCE_ELEMENT
  use ictus_solver_internal_force, only: force_op_t, force_op_init, force_apply
  use guide_model, only: rectangle_model, run_t, run_setup, run_record
  use toy_t3, only: t3_kind
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  type(material_t) :: mat
  integer :: et
  real(dp), parameter :: rho = 2.0_dp, e_mod = 1000.0_dp, nu = 0.25_dp
  call env_init()
  call t%start("guides/element")
  ! step 2: the dispatcher entry
  et = element_register(t3_kind())
  ! step 3: the deck name
  call t%equal_int(element_type_of('t3toy'), et, 'the deck name finds the registered type')
  call t%true(etype_name(et) == 'T3TOY', 'the type is named T3TOY')
  mat%name = 'steel'
  mat%density = rho
  call material_make_law('LINEAR ELASTIC', [e_mod, nu], kinematics_t(), mat%law)
  call case_patch(t)
  call case_translation(t)
  call case_two_forces(t)
  call t%finish()
  call env_finalize()

contains

  !> Mass rho lx ly; interior rows of f_int(u) vanish for a linear u (both force operators).
  subroutine case_patch(t)
    type(checker_t), intent(inout) :: t
    type(model_t), target :: model
    type(run_t), target :: r
    type(force_op_t) :: fop
    real(dp), allocatable :: u(:,:), f(:,:), hist(:,:,:)
    real(dp) :: fmax, scale
    integer :: i, kind, ierr, ix, iy
    call rectangle_model(model, et, 4, 3, 1.0_dp, 0.75_dp, mat, 2)
    call run_setup(r, model, 1.0e-5_dp)
    call t%close(r%ops%total_mass, rho*0.75_dp, 1.0e-14_dp, 'mass = rho A')
    allocate(u(2, model%nn), f(2, model%nn))
    do i = 1, model%nn
      u(:, i) = [0.01_dp + 0.02_dp*model%x0(1, i) - 0.013_dp*model%x0(2, i), &
          -0.004_dp + 0.007_dp*model%x0(1, i) + 0.031_dp*model%x0(2, i)]
    end do
    do kind = FORCE_ASSEMBLED, FORCE_ELEMENT
      call force_op_init(fop, kind, model, r%dom, r%ops%k, .false., ierr)
      allocate(hist(0, 3, model%nel))
      call force_apply(fop, u, f, hist)
      deallocate(hist)
      fmax = 0.0_dp
      do i = 1, model%nn
        ix = mod(i - 1, 5)
        iy = (i - 1)/5
        if (ix > 0 .and. ix < 4 .and. iy > 0 .and. iy < 3) fmax = max(fmax, maxval(abs(f(:, i))))
      end do
      scale = e_mod*maxval(abs(u))
      call t%close_abs(fmax, 0.0_dp, 1.0e-12_dp*scale, 'patch test: interior force of a '// &
          'linear field, '//trim(merge('assembled K ', 'element loop', kind == FORCE_ASSEMBLED)))
    end do
  end subroutine case_patch

  !> A free body with a uniform velocity: u = v0 t at every node, no strain energy,
  !! kinetic energy m |v0|^2 / 2.
  subroutine case_translation(t)
    type(checker_t), intent(inout) :: t
    type(model_t), target :: model
    type(run_t), target :: r
    real(dp), parameter :: v0(2) = [0.3_dp, -0.2_dp], dt = 1.0e-4_dp
    real(dp) :: err
    integer :: i
    call rectangle_model(model, et, 4, 3, 1.0_dp, 0.75_dp, mat, 2)
    do i = 1, model%nn
      model%v0(:, i) = v0
    end do
    call run_setup(r, model, dt)
    call run_record(r, 20)
    err = 0.0_dp
    do i = 1, model%nn
      err = max(err, maxval(abs(r%stp%s%u(:, i) - v0*r%stp%s%t)))
    end do
    call t%close_abs(err, 0.0_dp, 1.0e-15_dp, 'translation: u = v0 t after 20 steps')
    call t%close(r%stp%s%e_kin, 0.5_dp*rho*0.75_dp*dot_product(v0, v0), 1.0e-13_dp, &
        'translation: kinetic energy m |v0|^2 / 2')
    call t%close_abs(r%stp%s%e_strain, 0.0_dp, 1.0e-12_dp*r%stp%s%e_kin, &
        'translation: no strain energy')
  end subroutine case_translation

  !> An expanding body (v0 = 0.1 (x - x_c)): the element loop and the assembled K give the
  !! same displacements and energies to round-off over 50 steps, and the energy is kept.
  subroutine case_two_forces(t)
    type(checker_t), intent(inout) :: t
    type(model_t), target :: ma, me
    type(run_t), target :: ra, re
    real(dp), parameter :: dt = 2.0e-4_dp
    real(dp) :: e0, err, umax
    integer :: i, n
    call rectangle_model(ma, et, 4, 3, 1.0_dp, 0.75_dp, mat, 2)
    do i = 1, ma%nn
      ma%v0(:, i) = 0.1_dp*(ma%x0(:, i) - [0.5_dp, 0.375_dp])
    end do
    me = ma
    ma%force_kind = FORCE_ASSEMBLED
    me%force_kind = FORCE_ELEMENT
    call run_setup(ra, ma, dt)
    call run_setup(re, me, dt)
    call t%equal_int(re%stp%fop%kind, FORCE_ELEMENT, 'INTERNAL FORCE=ELEMENT is taken')
    e0 = 0.0_dp
    do n = 0, 50, 10
      call run_record(ra, n)
      call run_record(re, n)
      if (n == 0) e0 = ra%stp%s%e_kin + ra%stp%s%e_strain
    end do
    umax = maxval(abs(ra%stp%s%u))
    err = maxval(abs(ra%stp%s%u - re%stp%s%u))
    call t%close_abs(err, 0.0_dp, 1.0e-12_dp*umax, 'element loop = assembled K u (u)')
    call t%close(re%stp%s%e_strain, ra%stp%s%e_strain, 1.0e-12_dp, &
        'element loop = assembled K u (strain energy)')
    call t%true(ra%stp%s%e_strain > 1.0e-3_dp*e0, 'the body is strained')
    call t%close(ra%stp%s%e_kin + ra%stp%s%e_strain, e0, 1.0e-3_dp, 'energy kept')
  end subroutine case_two_forces
end program test_guide_element
