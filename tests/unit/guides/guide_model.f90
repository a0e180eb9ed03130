!> A small model built by hand for the two guides' tests (doc/architecture.md): a plane-strain
!! rectangle of nx x ny cells of Q4 elements or of a registered triangle type (two per cell),
!! free, with a lumped (HRZ) mass, run through the public seams: domain, assembly, mass
!! operator and the stepper.
module guide_model
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_Q4
  use ictus_materials_material, only: material_t
  use ictus_materials_law, only: ANALYSIS_PLANE_STRAIN
  use ictus_mass_types, only: MASS_HRZ, HRZ_FULL
  use ictus_contact_contact, only: contact_t
  use ictus_solver_model, only: model_t
  use ictus_solver_domain, only: domain_t, domain_init
  use ictus_solver_assemble, only: operators_t, assemble_operators
  use ictus_solver_mass_operator, only: mass_op_t, mass_op_init
  use ictus_solver_contact_step, only: contact_step_t
  use ictus_solver_stepper, only: stepper_t, stepper_init, stepper_plan, stepper_record, &
      stepper_advance
  implicit none
  private
  public :: rectangle_model, run_t, run_setup, run_record

  !> Everything a run of the stepper needs, kept alive together.
  type :: run_t
    type(domain_t) :: dom
    type(operators_t) :: ops
    type(mass_op_t) :: mop
    type(contact_t) :: contact
    type(contact_step_t) :: cs
    type(stepper_t) :: stp
  end type run_t

contains

  !> The rectangle [0, lx] x [0, ly] in nx x ny cells: Q4 elements (etype = ETYPE_Q4, 2 x 2
  !! Gauss) or, for another etype, two 3-node elements per cell (corners a b c and a c d,
  !! counter-clockwise) with rule `ngauss`; one material `mat`.
  subroutine rectangle_model(model, etype, nx, ny, lx, ly, mat, ngauss)
    type(model_t), intent(out) :: model
    integer, intent(in) :: etype, nx, ny, ngauss
    real(dp), intent(in) :: lx, ly
    type(material_t), intent(in) :: mat
    integer :: i, j, e, a, b, c, d, nen
    nen = merge(4, 3, etype == ETYPE_Q4)
    model%title = 'guide'
    model%analysis = ANALYSIS_PLANE_STRAIN
    model%nn = (nx + 1)*(ny + 1)
    allocate(model%x0(2, model%nn), model%weight(model%nn), source=1.0_dp)
    model%node_id = [(i, i = 1, model%nn)]
    do j = 0, ny
      do i = 0, nx
        model%x0(:, 1 + i + j*(nx + 1)) = [lx*i/nx, ly*j/ny]
      end do
    end do
    model%nel = merge(nx*ny, 2*nx*ny, etype == ETYPE_Q4)
    model%nen_max = nen
    allocate(model%conn(nen, model%nel))
    e = 0
    do j = 0, ny - 1
      do i = 0, nx - 1
        a = 1 + i + j*(nx + 1)
        b = a + 1
        c = b + nx + 1
        d = a + nx + 1
        if (etype == ETYPE_Q4) then
          e = e + 1
          model%conn(:, e) = [a, b, c, d]
        else
          model%conn(:, e + 1) = [a, b, c]
          model%conn(:, e + 2) = [a, c, d]
          e = e + 2
        end if
      end do
    end do
    allocate(model%etype(model%nel), source=etype)
    allocate(model%nen(model%nel), source=nen)
    allocate(model%mat(model%nel), source=1)
    allocate(model%gauss(2, model%nel), source=merge(2, ngauss, etype == ETYPE_Q4))
    model%elem_id = [(e, e = 1, model%nel)]
    allocate(model%patch(model%nel), model%patch_elem(model%nel), source=0)
    model%nmat = 1
    model%materials = [mat]
    allocate(model%mass_kind(model%nel), source=MASS_HRZ)
    allocate(model%hrz_rule(model%nel), source=HRZ_FULL)
    allocate(model%mass_alpha(model%nel), model%damping(model%nel), source=0.0_dp)
    allocate(model%fixed(2, model%nn), source=.false.)
    allocate(model%u_fixed(2, model%nn), model%v0(2, model%nn), source=0.0_dp)
    allocate(model%patches(0), model%patch_offset(0))
  end subroutine rectangle_model

  !> Partition (one rank here), assembly, lumped mass operator and the stepper with step dt.
  subroutine run_setup(r, model, dt)
    type(run_t), target, intent(inout) :: r
    type(model_t), target, intent(in) :: model
    real(dp), intent(in) :: dt
    integer, allocatable :: bad(:)
    integer :: nbad, ierr
    call domain_init(r%dom, model, ierr)
    call assemble_operators(model, r%dom, r%ops, bad, nbad)
    call mass_op_init(r%mop, r%dom, .false., r%ops%m, r%ops%m_diag, model%fixed)
    call stepper_init(r%stp, model, r%dom, r%ops, r%mop, r%contact, r%cs, dt, huge(1.0_dp), ierr)
    call stepper_plan(r%stp)
  end subroutine run_setup

  !> Advances to step n and runs its predictor with the energies (the state is then at t_n,
  !! with the kinetic and strain energies of t_n in r%stp%s).
  subroutine run_record(r, n)
    type(run_t), intent(inout) :: r
    integer, intent(in) :: n
    call stepper_advance(r%stp, n)
    call stepper_record(r%stp)
  end subroutine run_record
end module guide_model
