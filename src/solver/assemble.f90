!> Assembly of the constant operators of linear elastodynamics: the stiffness (block CSR, 2x2
!! blocks in 2D, 3x3 in 3D where the model takes the assembled K: `stiffness_fits`), the
!! consistent mass (scalar CSR, where asked for) and the lumped nodal masses.
!!
!! This runs once before the time loop. Elements are processed through the element library
!! with the shape data of their type (Lagrange) or of their Bezier-extracted span (NURBS).
module ictus_solver_assemble
  use ictus_core_kinds, only: dp, i8
  use ictus_core_memory, only: available_memory
  use ictus_core_ticker, only: ticker_t, ticker_start
  use ictus_elements_types, only: elem_shape_t, TASK_MASS, TASK_STIFFNESS, TASK_JACOBIAN
  use ictus_elements_library, only: element_shape_data, element_routine, element_out_t, &
      element_type_count
  use ictus_elements_iga, only: iga_shape_data, iga3_shape_data
  use ictus_geometry_volume, only: volume_elem_ijk
  use ictus_elements_solid2d, only: solid2d_volume
  use ictus_elements_solid3d, only: solid3d_volume
  use ictus_mass_types, only: MASS_CONSISTENT, MASS_ROW_SUM, MASS_HRZ, MASS_ALPHA, HRZ_GAUSS2
  use ictus_mass_lumping, only: lump_row_sum, lump_hrz, lump_alpha_q8
  use ictus_parallel_repro, only: repro_sum
  use ictus_parallel_env, only: allreduce_max, allreduce_sum, env_node_size
  use ictus_solver_model, only: model_t, model_force_kind, FORCE_AUTO, FORCE_ASSEMBLED
  use ictus_solver_domain, only: domain_t, domain_owns
  use ictus_solver_sparse, only: graph_t, bsr_t, csr_t, graph_from_elements, bsr_init, &
      csr_init, bsr_add_element, csr_add_element
  implicit none
  private
  public :: operators_t, assemble_operators, check_jacobians, element_shape, shape_cache_t, &
      mass_overflow_element

  !> The assembled constant operators.
  type :: operators_t
    !> Stiffness K (2x2 blocks in 2D; 3x3 blocks in 3D, where k%val is allocated only when
    !! the model takes the assembled K: `stiffness_fits`).
    type(bsr_t) :: k
    !> 3D: the bytes of the 3x3 K (all ranks), the memory available (bytes; -1 unknown), and
    !! whether AUTO left K out because it would take more than half of it on some node.
    real(dp) :: k_bytes = 0.0_dp
    real(dp) :: k_avail = -1.0_dp
    logical :: k_short = .false.
    !> True when at least one element uses the consistent mass.
    logical :: consistent = .false.
    !> Consistent mass (scalar; lumped elements add their diagonal into it).
    type(csr_t) :: m
    !> Diagonal nodal masses (nn): the lumped masses, or for a consistent mass its row sums.
    real(dp), allocatable :: m_diag(:)
    !> Total mass of the model (all ranks).
    real(dp) :: total_mass = 0.0_dp
    !> Positive diagonal masses (nn): the lumped masses, or for consistent-mass elements the
    !! HRZ lumping of their consistent mass. Used for damping and the positivity check.
    real(dp), allocatable :: m_pos(:)
    !> Element contributions to damping: sum over elements of alpha_e * m_pos (nn).
    real(dp), allocatable :: c_diag(:)
  end type operators_t

  !> Everything is computed per unit thickness (doc/results.md): with a uniform thickness
  !! t, stiffness, mass and contact forces all scale with t, and the motion does not depend
  !! on it. *ANALYSIS, THICKNESS= is recorded in the results file only.
  real(dp), parameter :: unit_thickness = 1.0_dp

  !> Shape data of the finite-element types, computed once per type, rule (1..max_rule) and
  !! slot.
  integer, parameter :: max_rule = 10
  type :: shape_cache_t
    logical, allocatable :: ready(:,:,:)
    type(elem_shape_t), allocatable :: shp(:,:,:)
  end type shape_cache_t

contains

  !> Shape data of element `e` for `ngauss` Gauss points per direction. `slot` keeps two rules
  !! of the same type apart (1: the element's rule, 2: the HRZ 2x2 rule).
  subroutine element_shape(model, e, ngauss, cache, slot, shp)
    type(model_t), intent(in) :: model
    integer, intent(in) :: e, ngauss(:), slot
    type(shape_cache_t), intent(inout) :: cache
    type(elem_shape_t), intent(inout) :: shp
    integer :: ip, ie, i1, i2, t, ijk(3)
    if (model%patch(e) > 0 .and. model%ndm == 3) then
      ip = model%patch(e)
      ie = model%patch_elem(e)
      associate (v => model%volumes(ip))
        ijk = volume_elem_ijk(v, ie)
        call iga3_shape_data(v%p, v%c1(:, :, ijk(1)), v%c2(:, :, ijk(2)), v%c3(:, :, ijk(3)), &
            v%cp(4, v%ien(:, ie)), ngauss, shp)
      end associate
    else if (model%patch(e) > 0) then
      ip = model%patch(e)
      ie = model%patch_elem(e)
      associate (pt => model%patches(ip))
        i1 = mod(ie - 1, pt%nel(1)) + 1
        i2 = (ie - 1)/pt%nel(1) + 1
        call iga_shape_data(pt%p, pt%c1(:, :, i1), pt%c2(:, :, i2), &
            pt%cp(3, pt%ien(:, ie)), ngauss, shp)
      end associate
    else
      t = model%etype(e)
      if (.not. allocated(cache%ready)) then
        allocate(cache%ready(element_type_count(), max_rule, 2), source=.false.)
        allocate(cache%shp(element_type_count(), max_rule, 2))
      end if
      if (.not. cache%ready(t, ngauss(1), slot)) then
        call element_shape_data(t, ngauss(1), cache%shp(t, ngauss(1), slot))
        cache%ready(t, ngauss(1), slot) = .true.
      end if
      shp = cache%shp(t, ngauss(1), slot)
    end if
  end subroutine element_shape

  !> Assembles this rank's rows of K, of the consistent mass (if any element asks for it) and
  !! of the nodal masses, from the elements of `dom` in global order. Elements with det J <= 0
  !! are skipped (the caller checks them first with `check_jacobians`); owned nodes whose
  !! lumped mass is not positive are listed by global index in `bad_mass` (a consistent mass is
  !! checked through its HRZ diagonal, which is positive for any valid element); an infinite
  !! mass (coordinates or a density too large) is listed too.
  subroutine assemble_operators(model, dom, ops, bad_mass, nbad_mass, tk)
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    type(operators_t), intent(out) :: ops
    integer, allocatable, intent(out) :: bad_mass(:)
    integer, intent(out) :: nbad_mass
    !> The ticker of the caller's phase (progress lines; one of its own if absent).
    type(ticker_t), intent(inout), optional :: tk
    type(graph_t) :: g
    type(shape_cache_t) :: cache
    type(elem_shape_t) :: shp, shp2
    type(element_out_t) :: kout, mout, mout2
    real(dp), allocatable :: xl(:,:), me2(:,:), ml(:), diag(:), emass(:)
    real(dp) :: mass_e
    integer :: e, k, nen, i, mt, nl, nmine
    integer, allocatable :: nodes(:)
    type(ticker_t) :: tkl
    nl = dom%nlocal
    call graph_from_elements(dom%nowned, nl, dom%nelem, model%nen_max, &
        model%nen(dom%elem), dom%conn, dom%halo%gid, g)
    if (model%ndm == 2) then
      call bsr_init(ops%k, g)
    else if (stiffness_fits(model, g, ops)) then
      call bsr_init(ops%k, g, 3)
    end if
    ops%consistent = any(model%mass_kind == MASS_CONSISTENT)
    if (ops%consistent) call csr_init(ops%m, g)
    allocate(ops%m_diag(nl), ops%m_pos(nl), ops%c_diag(nl), source=0.0_dp)
    allocate(emass(dom%nelem), source=0.0_dp)
    nmine = 0
    if (present(tk)) then
      tkl = tk
    else
      call ticker_start(tkl, '', stride=1000)
    end if
    tkl%name = 'assembly'
    do k = 1, dom%nelem
      call tkl%tick(k, dom%nelem)
      e = dom%elem(k)
      nen = model%nen(e)
      if (allocated(xl)) then
        if (size(xl, 2) /= nen) deallocate(xl, me2, ml, diag)
      end if
      if (.not. allocated(xl)) allocate(xl(model%ndm, nen), me2(nen, nen), ml(nen), diag(nen))
      nodes = dom%conn(1:nen, k)
      xl = model%x0(:, model%conn(1:nen, e))
      mt = model%mat(e)
      call element_shape(model, e, model%gauss(:, e), cache, 1, shp)
      if (allocated(ops%k%val)) then
        call element_routine(TASK_STIFFNESS, model%etype(e), shp, xl, model%materials(mt), &
            kout)
        if (kout%ierr /= 0) cycle
        ! K symmetric bit for bit (B^T D B rounds its two triangles differently): the upper
        ! triangle mirrored, so that K's upper blocks give the whole product (bsr_upper_init)
        associate (ke => kout%s)
          do i = 1, model%ndm*nen - 1
            ke(i + 1:, i) = ke(i, i + 1:)
          end do
        end associate
        call bsr_add_element(ops%k, nen, nodes, kout%s)
      end if
      call element_routine(TASK_MASS, model%etype(e), shp, xl, model%materials(mt), &
           mout)
      mass_e = mout%scalar
      if (domain_owns(dom, k)) then
        nmine = nmine + 1
        emass(nmine) = mass_e
      end if
      associate (me => mout%s)
      select case (model%mass_kind(e))
      case (MASS_CONSISTENT)
        call csr_add_element(ops%m, nen, nodes, me)
        do i = 1, nen
          diag(i) = me(i, i)
        end do
        call lump_hrz(nen, diag, mass_e, ml)
      case (MASS_ROW_SUM)
        call lump_row_sum(nen, me, ml)
      case (MASS_HRZ)
        if (model%hrz_rule(e) == HRZ_GAUSS2 .and. model%patch(e) == 0) then
          call element_shape(model, e, [2, 2], cache, 2, shp2)
          call element_routine(TASK_MASS, model%etype(e), shp2, xl, model%materials(mt), &
               mout2)
          do i = 1, nen
            diag(i) = mout2%s(i, i)
          end do
        else
          do i = 1, nen
            diag(i) = me(i, i)
          end do
        end if
        call lump_hrz(nen, diag, mass_e, ml)
      case (MASS_ALPHA)
        call lump_alpha_q8(mass_e, model%mass_alpha(e), ml)
      end select
      if (ops%consistent .and. model%mass_kind(e) /= MASS_CONSISTENT) then
        do i = 1, nen
          me2(:, i) = 0.0_dp
          me2(i, i) = ml(i)
        end do
        call csr_add_element(ops%m, nen, nodes, me2)
      end if
      ops%m_pos(nodes) = ops%m_pos(nodes) + ml
      ops%c_diag(nodes) = ops%c_diag(nodes) + model%damping(e)*ml
      if (model%mass_kind(e) == MASS_CONSISTENT) then
        ! the row sums of the consistent mass, reported as its nodal masses
        do i = 1, nen
          ml(i) = sum(me(i, :))
        end do
      end if
      end associate
      ops%m_diag(nodes) = ops%m_diag(nodes) + ml
    end do
    if (present(tk)) tk = tkl
    ops%total_mass = repro_sum(nmine, emass, model%nel)
    ! owned nodes that carry elements must have a positive mass
    allocate(bad_mass(dom%nowned))
    nbad_mass = 0
    do i = 1, dom%nowned
      if (g%row_ptr(i + 1) - g%row_ptr(i) > 1 .and. &
          .not. (ops%m_pos(i) > 0.0_dp .and. ops%m_pos(i) <= huge(1.0_dp))) then
        nbad_mass = nbad_mass + 1
        bad_mass(nbad_mass) = dom%halo%gid(i)
      end if
    end do
  end subroutine assemble_operators

  !> Whether a 3D model gets its stiffness assembled in 3x3 blocks on graph g: where the deck
  !! and the laws take the assembled K (`model_force_kind`), and under INTERNAL FORCE=AUTO only
  !! while its blocks, columns and row pointers take at most half the memory available on
  !! every node (this rank's bytes times the ranks of its node, against `available_memory`;
  !! the same decision on all ranks). Sets ops%k_bytes (all ranks), k_avail and k_short.
  logical function stiffness_fits(model, g, ops) result(fits)
    type(model_t), intent(in) :: model
    type(graph_t), intent(in) :: g
    type(operators_t), intent(inout) :: ops
    real(dp) :: mine, mem(2)
    integer(i8) :: avail
    fits = model_force_kind(model) == FORCE_ASSEMBLED
    if (.not. fits) return
    mine = 76.0_dp*real(size(g%col), dp) + 4.0_dp*real(g%n + 1, dp)
    ops%k_bytes = mine
    call allreduce_sum(ops%k_bytes)
    avail = available_memory()
    mem(1) = mine*env_node_size()
    mem(2) = -huge(1.0_dp)
    if (avail >= 0) mem(2) = -real(avail, dp)
    call allreduce_max(mem)
    if (mem(2) > -huge(1.0_dp)) ops%k_avail = -mem(2)
    if (model%force_kind /= FORCE_AUTO) return
    ops%k_short = mem(2) > -huge(1.0_dp) .and. 2.0_dp*mem(1) > -mem(2)
    fits = .not. ops%k_short
  end function stiffness_fits

  !> Elements (global indices, increasing) with a non-positive or non-finite Jacobian
  !! determinant at a quadrature point; nonfinite(k) tells which of the two bad(k) has. Runs
  !! over the whole model on every rank, so all ranks agree.
  subroutine check_jacobians(model, bad, nbad, nonfinite, tk)
    type(model_t), intent(in) :: model
    integer, allocatable, intent(out) :: bad(:)
    integer, intent(out) :: nbad
    logical, allocatable, intent(out) :: nonfinite(:)
    !> The ticker of the caller's phase (progress lines; one of its own if absent).
    type(ticker_t), intent(inout), optional :: tk
    type(shape_cache_t) :: cache
    type(elem_shape_t) :: shp
    type(element_out_t) :: out
    real(dp) :: detj_min
    integer :: e, nen
    type(ticker_t) :: tkl
    allocate(bad(model%nel), nonfinite(model%nel))
    nbad = 0
    if (present(tk)) then
      tkl = tk
    else
      call ticker_start(tkl, '', stride=1000)
    end if
    tkl%name = 'element check'
    do e = 1, model%nel
      call tkl%tick(e, model%nel)
      nen = model%nen(e)
      call element_shape(model, e, model%gauss(:, e), cache, 1, shp)
      call element_routine(TASK_JACOBIAN, model%etype(e), shp, &
          model%x0(:, model%conn(1:nen, e)), model%materials(model%mat(e)),  out)
      detj_min = out%scalar
      if (.not. (detj_min > 0.0_dp .and. detj_min <= huge(1.0_dp))) then
        nbad = nbad + 1
        bad(nbad) = e
        nonfinite(nbad) = .not. abs(detj_min) <= huge(1.0_dp)
      end if
    end do
    if (present(tk)) tk = tkl
  end subroutine check_jacobians
  !> The first element (global index) at which the running sum of the element masses,
  !! density times area, stops being a finite number; 0 when the total is finite. Used to
  !! name an element when a model's mass overflows (coordinates or densities too large).
  integer function mass_overflow_element(model) result(ebad)
    type(model_t), intent(in) :: model
    type(shape_cache_t) :: cache
    type(elem_shape_t) :: shp
    real(dp) :: vol, total
    integer :: e, nen
    ebad = 0
    total = 0.0_dp
    do e = 1, model%nel
      nen = model%nen(e)
      call element_shape(model, e, model%gauss(:, e), cache, 1, shp)
      if (model%ndm == 3) then
        call solid3d_volume(nen, shp, model%x0(:, model%conn(1:nen, e)), vol)
      else
        call solid2d_volume(nen, shp, model%x0(:, model%conn(1:nen, e)), unit_thickness, vol)
      end if
      total = total + model%materials(model%mat(e))%density*abs(vol)
      if (.not. total <= huge(1.0_dp)) then
        ebad = e
        return
      end if
    end do
  end function mass_overflow_element
end module ictus_solver_assemble
