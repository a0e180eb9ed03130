!> Turns the deck records into the model: global numbering of FE nodes and control points,
!! one element list, refined patches, resolved sets, conditions, mass and damping choices.
!!
!! Every problem that the deck reader could not see on its own (an element-set of the wrong
!! element type for TYPE=ALPHA, a set resolving to nothing, ...) is reported with the deck
!! location through `input_error`; the caller checks `error_count()`.
module ictus_app_build_model
  use ictus_core_kinds, only: dp, i8
  use ictus_core_ticker, only: ticker_t, ticker_start
  use ictus_core_memory, only: available_memory
  use ictus_core_errors, only: input_error, warning
  use ictus_core_strings, only: str, upper, lower
  use ictus_geometry_sides, only: SIDE_NONE
  use ictus_geometry_patch, only: patch_elevate, patch_refine, patch_build_elements, &
      patch_side_points
  use ictus_geometry_volume, only: volume_side_points
  use ictus_elements_types, only: ETYPE_Q8, ETYPE_IGA, ETYPE_IGA3
  use ictus_elements_library, only: etype_name, element_default_ngauss
  use ictus_mass_types, only: MASS_HRZ, MASS_ALPHA, HRZ_FULL, MASS_CONSISTENT
  use ictus_materials_law, only: ANALYSIS_PLANE_STRAIN, ANALYSIS_PLANE_STRESS, ANALYSIS_3D
  use ictus_materials_material, only: material_make_law, material_t
  use ictus_solver_model, only: model_t, model_kinematics, patch_node, patch_nodes, patch_ncp, &
      patch_name, FORCE_AUTO, &
      FORCE_ASSEMBLED, FORCE_ELEMENT, MASS_SOLVER_CG, MASS_SOLVER_CHOLESKY, &
      MASS_SOLVER_CORRECTOR, MASS_SOLVER_KRONECKER, MASS_SOLVER_AUTO, VAR_PEEQ
  use ictus_io_deck_types, only: deck_t, where_len, SET_NODE, SET_ELEMENT, OP_ELEVATE, &
      OP_REFINE, DECK_PLANE_STRAIN => ANALYSIS_PLANE_STRAIN
  use ictus_app_id_map, only: id_map_t, id_map_init, id_map_find
  use ictus_app_merge_patches, only: merge_patch_points, merge_volume_points
  use ictus_app_build_volumes, only: build_volumes
  implicit none
  private
  public :: build_model, element_where, resolve_node_set, resolve_elem_set, patch_index

  !> Largest degree *ELEVATE takes (Gauss rules, element matrices and Bezier extraction are
  !! sized by it; p = 10 already has 121 control points per element).
  integer, parameter :: max_degree = 10

  !> Where each model element was defined (for messages), filled by build_model.
  type :: origin_t
    character(len=where_len), allocatable :: where(:)
  end type origin_t
  type(origin_t) :: origin

contains

  !> Deck location of model element e: "file:line" of its *ELEMENT data line, or for a NURBS
  !! element "file:line: patch NAME, element k" with the line of the *PATCH card.
  function element_where(e) result(w)
    integer, intent(in) :: e
    character(len=:), allocatable :: w
    w = 'element'
    if (allocated(origin%where)) then
      if (e >= 1 .and. e <= size(origin%where)) w = trim(origin%where(e))
    end if
  end function element_where

  !> Builds `model` from `deck`. Problems are reported through input_error.
  subroutine build_model(deck, model)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(out) :: model
    type(id_map_t) :: node_map
    type(ticker_t) :: tk
    integer :: nfe
    call ticker_start(tk, 'model building')
    model%title = ''
    if (allocated(deck%title)) model%title = deck%title
    model%ndm = deck%ndm
    model%analysis = ANALYSIS_PLANE_STRESS
    if (deck%analysis == DECK_PLANE_STRAIN) model%analysis = ANALYSIS_PLANE_STRAIN
    if (deck%ndm == 3) model%analysis = ANALYSIS_3D
    model%nlgeom = deck%has_step .and. deck%step%nlgeom
    model%thickness = deck%thickness
    call build_materials(deck, model)
    call build_patches(deck, model)
    call tk%tick(1, 5)
    call build_nodes(deck, model, node_map, nfe)
    call tk%tick(2, 5)
    ! the internal force first: AUTO dilatation depends on it
    if (deck%has_step) then
      select case (deck%step%internal_force)
      case ('ASSEMBLED')
        model%force_kind = FORCE_ASSEMBLED
      case ('ELEMENT')
        model%force_kind = FORCE_ELEMENT
      case default
        model%force_kind = FORCE_AUTO
      end select
    end if
    call build_elements(deck, model, node_map)
    call tk%tick(3, 5)
    call build_conditions(deck, model, node_map)
    call tk%tick(4, 5)
    call build_mass_damping(deck, model)
    if (deck%has_step) then
      model%dt = deck%step%dt
      model%t_end = deck%step%t_end
      model%safety = deck%step%safety
      model%mass_tol = deck%step%mass_tol
      select case (deck%step%mass_solver)
      case ('CG')
        model%mass_solver = MASS_SOLVER_CG
      case ('CORRECTOR')
        model%mass_solver = MASS_SOLVER_CORRECTOR
      case ('KRONECKER')
        model%mass_solver = MASS_SOLVER_KRONECKER
      case ('CHOLESKY')
        model%mass_solver = MASS_SOLVER_CHOLESKY
      case default
        model%mass_solver = MASS_SOLVER_AUTO
      end select
      model%mass_passes = deck%step%mass_passes
      if (deck%step%energy_warning > 0.0_dp) model%energy_warning = deck%step%energy_warning
      model%sweep_steps = deck%step%sweep_steps
      model%viz_samples = deck%step%field_samples
      model%restart_every = deck%step%restart_every
      call build_output(deck, model, node_map)
      if (model%ndm == 3) call step_3d(deck, model)
    end if
    if (model%nel == 0) call input_error(deck%path, &
        'the deck defines no elements (*ELEMENT) and no patches (*PATCH)')
  end subroutine build_model

  subroutine build_materials(deck, model)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    integer :: i
    model%nmat = deck%n_materials
    allocate(model%materials(model%nmat))
    do i = 1, model%nmat
      associate (m => deck%materials(i))
        model%materials(i)%name = m%name
        model%materials(i)%density = m%rho
        if (m%has_hyperelastic) then
          call material_make_law('NEO HOOKE', [m%c10, m%d1], model_kinematics(model), &
              model%materials(i)%law)
        else if (m%has_plastic) then
          call material_make_law('J2', [m%e, m%nu, reshape(m%plastic, [size(m%plastic)])], &
              model_kinematics(model), model%materials(i)%law)
        else
          call material_make_law('LINEAR ELASTIC', [m%e, m%nu], model_kinematics(model), &
              model%materials(i)%law)
        end if
      end associate
    end do
  end subroutine build_materials

  !> Index of material `name`, 0 when undefined.
  integer function material_index(model, name)
    type(model_t), intent(in) :: model
    character(len=*), intent(in) :: name
    integer :: i
    material_index = 0
    do i = 1, model%nmat
      if (upper(trim(model%materials(i)%name)) == upper(trim(name))) then
        material_index = i
        return
      end if
    end do
  end function material_index

  !> Reads the patches, applies *ELEVATE and *REFINE in deck order, builds their elements.
  subroutine build_patches(deck, model)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    integer :: ip, k, j
    if (model%ndm == 3) then
      call build_volumes(deck, model, max_degree)
      return
    end if
    model%npatch = deck%n_patches
    allocate(model%patches(model%npatch), model%patch_offset(model%npatch))
    do ip = 1, model%npatch
      associate (pin => deck%patches(ip))
        call model%patches(ip)%init(pin%name, pin%degree(1:2), pin%size(1:2), pin%knots1, &
            pin%knots2, pin%cp)
      end associate
    end do
    do k = 1, deck%n_patch_ops
      j = patch_index(model, deck%patch_ops(k)%patch)
      if (j == 0) cycle
      associate (op => deck%patch_ops(k), pt => model%patches(j))
        select case (op%kind)
        case (OP_ELEVATE)
          if (any(op%values(1:2) < pt%p)) then
            call input_error(op%where, '*ELEVATE: DEGREE must not be below the current '// &
                'degree '//str(pt%p(1))//','//str(pt%p(2)))
            cycle
          end if
          if (any(op%values(1:2) > max_degree)) then
            call input_error(op%where, '*ELEVATE: DEGREE='//str(op%values(1))//','// &
                str(op%values(2))//' is above the largest degree ictus takes, '// &
                str(max_degree))
            cycle
          end if
          ! each of the at most n - p spans gains q - p control points per direction
          if (.not. patch_fits(op%where, '*ELEVATE', pt%name, &
              int(pt%n, i8) + int(op%values(1:2) - pt%p, i8)*int(pt%n - pt%p, i8), &
              op%values(1:2), other_patches_bytes(model, j))) cycle
          call patch_elevate(pt, op%values(1:2))
        case (OP_REFINE)
          ! each of the at most n - p spans gains k - 1 control points per direction
          if (.not. patch_fits(op%where, '*REFINE', pt%name, &
              int(pt%n, i8) + int(op%values(1:2) - 1, i8)*int(pt%n - pt%p, i8), pt%p, &
              other_patches_bytes(model, j))) cycle
          call patch_refine(pt, op%values(1:2))
        end select
      end associate
    end do
    do ip = 1, model%npatch
      call patch_build_elements(model%patches(ip))
    end do
  end subroutine build_patches

  !> Whether a patch of at most n(1) x n(2) control points of degree p still fits: its
  !! stiffness blocks, (2 p1 + 1)(2 p2 + 1) per control point, must be countable by the default
  !! integers of the sparse structure, and the set-up of the model (patch_bytes, plus `other`
  !! bytes of the other patches) must fit in the memory left on this node. Otherwise reports
  !! it at `where` and returns false.
  logical function patch_fits(where, card, name, n, p, other)
    character(len=*), intent(in) :: where, card, name
    integer(i8), intent(in) :: n(2)
    integer, intent(in) :: p(2)
    real(dp), intent(in) :: other
    integer(i8) :: ncp, blocks, avail
    real(dp) :: gb
    ncp = n(1)*n(2)
    blocks = ncp*int((2*p(1) + 1)*(2*p(2) + 1), i8)
    patch_fits = .true.
    if (blocks > int(huge(1), i8)) then
      call input_error(where, card//': patch '//trim(name)//' would have up to '//str(ncp)// &
          ' control points and '//str(blocks)//' stiffness blocks; at most '//str(huge(1))// &
          ' blocks fit the sparse structure (a smaller refinement, or several patches)')
      patch_fits = .false.
      return
    end if
    avail = available_memory()
    gb = (patch_bytes(n, p) + other)/1024.0_dp**3
    if (avail >= 0 .and. patch_bytes(n, p) + other > real(avail, dp)) then
      call input_error(where, card//': patch '//trim(name)//' would have up to '// &
          str(ncp)//' control points; the set-up of the model would need about '// &
          str(gb)//' GB, more than the '//str(real(avail, dp)/1024.0_dp**3)// &
          ' GB available (/proc/meminfo, the control group, ulimit -v, '// &
          'ICTUS_MEMORY_LIMIT_MB; a smaller refinement, or more memory)')
      patch_fits = .false.
    end if
  end function patch_fits

  !> Peak memory of the set-up for a patch of n(1) x n(2) control points of degree p: 36 bytes
  !! per stiffness block (2 x 2 doubles and a column index) and about 800 bytes per control
  !! point (at most one element each) for everything else. The 800 are measured: the peak
  !! resident size of `ictus --check` on the half-disc refined to 1e6 p = 2 elements (1.66 GB)
  !! and to 1.6e6 p = 3 elements (4.56 GB) is 36 bytes per block plus 757 bytes per element.
  pure real(dp) function patch_bytes(n, p)
    integer(i8), intent(in) :: n(2)
    integer, intent(in) :: p(2)
    patch_bytes = real(n(1), dp)*real(n(2), dp)*(36.0_dp*(2*p(1) + 1)*(2*p(2) + 1) + 800.0_dp)
  end function patch_bytes

  !> patch_bytes of all patches but patch j, at their present sizes.
  real(dp) function other_patches_bytes(model, j) result(b)
    type(model_t), intent(in) :: model
    integer, intent(in) :: j
    integer :: ip
    b = 0.0_dp
    do ip = 1, model%npatch
      if (ip /= j) b = b + patch_bytes(int(model%patches(ip)%n, i8), model%patches(ip)%p)
    end do
  end function other_patches_bytes

  !> Index of patch `name`, 0 when undefined.
  integer function patch_index(model, name)
    type(model_t), intent(in) :: model
    character(len=*), intent(in) :: name
    integer :: i
    patch_index = 0
    do i = 1, model%npatch
      if (upper(patch_name(model, i)) == upper(trim(name))) then
        patch_index = i
        return
      end if
    end do
  end function patch_index

  !> Global numbering: FE nodes in deck order, then each patch's control points (direction 1
  !! fastest), where control points merged into an earlier one (*PATCH, MERGE=YES; in 3D the
  !! coincident control points of one trivariate patch, merge_volume_points) take that one's
  !! number. Control points get the ids max(FE id) + 1, + 2, ...
  subroutine build_nodes(deck, model, node_map, nfe)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    type(id_map_t), intent(out) :: node_map
    integer, intent(out) :: nfe
    integer :: ip, k, n, g, next_id
    logical, allocatable :: seen(:)
    nfe = deck%n_nodes
    n = nfe
    do ip = 1, model%npatch
      model%patch_offset(ip) = n
      n = n + patch_ncp(model, ip)
    end do
    model%nn = n
    if (model%ndm == 3 .and. model%npatch > 0) then
      ! the coincident control points of each trivariate patch (collapsed sides)
      call merge_volume_points(model%volumes, model%patch_offset, n, model%cp_node, model%nn)
      model%nmerged = n - model%nn
      if (model%nmerged == 0) deallocate(model%cp_node)
    else if (any(deck%patches(1:model%npatch)%merge)) then
      call merge_patch_points(model%patches, model%patch_offset, &
          deck%patches(1:model%npatch)%merge, deck%patches(1:model%npatch)%where, n, &
          model%cp_node, model%nn)
      model%nmerged = n - model%nn
      ! nothing merged: the plain numbering
      if (model%nmerged == 0) deallocate(model%cp_node)
    end if
    allocate(model%x0(model%ndm, model%nn), model%weight(model%nn), model%node_id(model%nn))
    if (nfe > 0) then
      model%x0(:, 1:nfe) = deck%node_x(:, 1:nfe)
      model%node_id(1:nfe) = deck%node_ids(1:nfe)
      next_id = maxval(deck%node_ids(1:nfe)) + 1
    else
      next_id = 1
    end if
    model%weight = 1.0_dp
    allocate(seen(model%nn), source=.false.)
    do ip = 1, model%npatch
      do k = 1, patch_ncp(model, ip)
        g = patch_node(model, ip, k)
        if (seen(g)) cycle
        seen(g) = .true.
        if (model%ndm == 3) then
          model%x0(:, g) = model%volumes(ip)%cp(1:3, k)
          model%weight(g) = model%volumes(ip)%cp(4, k)
        else
          model%x0(:, g) = model%patches(ip)%cp(1:2, k)
          model%weight(g) = model%patches(ip)%cp(3, k)
        end if
        model%node_id(g) = next_id + (g - nfe - 1)
      end do
    end do
    call id_map_init(node_map, model%node_id)
  end subroutine build_nodes

  !> One element list: FE blocks in deck order, then the spans of each patch.
  subroutine build_elements(deck, model, node_map)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    type(id_map_t), intent(in) :: node_map
    integer :: nel, ib, k, e, a, ip, ie, nen_max, m, g, pe, pn, pp(3)
    integer, allocatable :: nodes(:)
    nel = 0
    nen_max = 0
    do ib = 1, deck%n_blocks
      nel = nel + size(deck%blocks(ib)%ids)
      nen_max = max(nen_max, deck%blocks(ib)%nen)
    end do
    do ip = 1, model%npatch
      call patch_spans(model, ip, pe, pn, pp)
      nel = nel + pe
      nen_max = max(nen_max, pn)
    end do
    model%nel = nel
    model%nen_max = nen_max
    allocate(model%etype(nel), model%nen(nel), model%conn(nen_max, nel), model%mat(nel), &
        model%gauss(model%ndm, nel), model%elem_id(nel), model%patch(nel), model%patch_elem(nel), &
        model%mean_dil(nel))
    ! a second model in the same process (tests, tools) replaces the first one's origins
    if (allocated(origin%where)) deallocate(origin%where)
    allocate(origin%where(nel))
    model%conn = 0
    e = 0
    do ib = 1, deck%n_blocks
      associate (b => deck%blocks(ib))
        m = material_index(model, b%material)
        if (m == 0) call input_error(b%where, '*ELEMENT: MATERIAL='//trim(b%material)// &
            ' is not defined by a *MATERIAL card')
        g = b%gauss
        if (g == 0) g = element_default_ngauss(b%etype)
        do k = 1, size(b%ids)
          e = e + 1
          model%etype(e) = b%etype
          model%nen(e) = b%nen
          model%mat(e) = max(m, 1)
          model%gauss(:, e) = g
          model%mean_dil(e) = mean_dilatation_of(b%dilatation, model%materials(max(m, 1)), &
              model%force_kind)
          model%elem_id(e) = b%ids(k)
          model%patch(e) = 0
          model%patch_elem(e) = 0
          write(origin%where(e), '(a,":",i0)') trim(b%file), b%line(k)
          do a = 1, b%nen
            model%conn(a, e) = id_map_find(node_map, b%conn(a, k))
            if (model%conn(a, e) == 0) then
              call input_error(origin%where(e), '*ELEMENT: element '//str(b%ids(k))// &
                  ' refers to node '//str(b%conn(a, k))//', which no *NODE card defines')
              model%conn(a, e) = 1
            end if
          end do
        end do
      end associate
    end do
    do ip = 1, model%npatch
      m = material_index(model, deck%patches(ip)%material)
      if (m == 0) call input_error(deck%patches(ip)%where, '*PATCH: MATERIAL='// &
          trim(deck%patches(ip)%material)//' is not defined by a *MATERIAL card')
      nodes = patch_nodes(model, ip)
      call patch_spans(model, ip, pe, pn, pp)
      do ie = 1, pe
        e = e + 1
        model%etype(e) = merge(ETYPE_IGA3, ETYPE_IGA, model%ndm == 3)
        model%nen(e) = pn
        model%mat(e) = max(m, 1)
        ! p + 1 Gauss points per direction
        model%gauss(:, e) = pp(1:model%ndm) + 1
        model%mean_dil(e) = mean_dilatation_of(deck%patches(ip)%dilatation, &
            model%materials(max(m, 1)), model%force_kind)
        model%elem_id(e) = ie
        model%patch(e) = ip
        model%patch_elem(e) = ie
        if (model%ndm == 3) then
          model%conn(1:pn, e) = nodes(model%volumes(ip)%ien(:, ie))
        else
          model%conn(1:pn, e) = nodes(model%patches(ip)%ien(:, ie))
        end if
        write(origin%where(e), '(a,i0)') trim(deck%patches(ip)%where)//': patch '// &
            patch_name(model, ip)//', element ', ie
      end do
    end do
  end subroutine build_elements

  !> Elements ne, control points per element nen and degrees p (p(3) = 0 in 2D) of patch ip.
  subroutine patch_spans(model, ip, ne, nen, p)
    type(model_t), intent(in) :: model
    integer, intent(in) :: ip
    integer, intent(out) :: ne, nen, p(3)
    p = 0
    if (model%ndm == 3) then
      ne = product(model%volumes(ip)%nel)
      nen = model%volumes(ip)%nen
      p = model%volumes(ip)%p
    else
      ne = product(model%patches(ip)%nel)
      nen = model%patches(ip)%nen
      p(1:2) = model%patches(ip)%p
    end if
  end subroutine patch_spans

  !> Whether an element shares its mean dilatation: DILATATION=MEAN (2) or FULL (1) as the
  !! deck says, else (AUTO) where its law is (nearly) isochoric, unless the deck asks for the
  !! assembled K (INTERNAL FORCE=ASSEMBLED: the full formulation).
  logical function mean_dilatation_of(choice, mat, force_kind)
    integer, intent(in) :: choice, force_kind
    type(material_t), intent(in) :: mat
    mean_dilatation_of = choice == 2
    if (choice == 0 .and. force_kind /= FORCE_ASSEMBLED .and. allocated(mat%law)) &
        mean_dilatation_of = mat%law%isochoric
  end function mean_dilatation_of

  !> Elements of element set `name` (an ELSET, or a patch name) into `mask`.
  recursive subroutine resolve_elem_set(deck, model, name, where, mask, depth)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    character(len=*), intent(in) :: name, where
    logical, intent(inout) :: mask(:)
    integer, intent(in) :: depth
    integer :: i, j, e, ip, ib, k
    logical :: found
    type(id_map_t) :: fe_map
    integer, allocatable :: fe(:)
    found = .false.
    if (depth > 20) then
      call input_error(where, 'set '//trim(name)//' refers to itself (a cycle of set names)')
      return
    end if
    ip = patch_index(model, name)
    if (ip > 0) then
      found = .true.
      where (model%patch == ip) mask = .true.
    end if
    e = 0
    do ib = 1, deck%n_blocks
      k = size(deck%blocks(ib)%ids)
      if (upper(trim(deck%blocks(ib)%elset)) == upper(trim(name)) .and. &
          len_trim(deck%blocks(ib)%elset) > 0 .and. k > 0) then
        mask(e + 1:e + k) = .true.
        found = .true.
      end if
      e = e + k
    end do
    do i = 1, deck%n_sets
      associate (s => deck%sets(i))
        if (s%kind /= SET_ELEMENT .or. upper(trim(s%name)) /= upper(trim(name))) cycle
        found = .true.
        if (allocated(s%ids)) then
          ! the FE elements by id (unique: check_deck), a lookup per id instead of a search
          if (.not. allocated(fe_map%keys)) then
            fe = pack([(e, e = 1, model%nel)], model%patch == 0)
            call id_map_init(fe_map, model%elem_id(fe))
          end if
          do j = 1, size(s%ids)
            k = id_map_find(fe_map, s%ids(j))
            if (k > 0) then
              mask(fe(k)) = .true.
            else
              call input_error(s%where, '*ELSET '//trim(s%name)//': element '// &
                  str(s%ids(j))//' is not defined')
            end if
          end do
        end if
        if (allocated(s%refs)) then
          do j = 1, size(s%refs)
            call resolve_elem_set(deck, model, s%refs(j), s%ref_where(j), mask, depth + 1)
          end do
        end if
      end associate
    end do
    if (.not. found) call input_error(where, 'element set '//trim(name)//' is not defined '// &
        '(expected an *ELSET, an ELSET= of *ELEMENT, or a patch name)')
  end subroutine resolve_elem_set

  !> The output settings of the step: history and field schedules, the field variables (by
  !! default U, V, S, MISES, and PEEQ where a law has plastic history) and the node sets with
  !! a history of their own.
  subroutine build_output(deck, model, node_map)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    type(id_map_t), intent(in) :: node_map
    logical, allocatable :: mask(:)
    integer :: k, i
    model%history_every = deck%step%history_every
    model%history_interval = deck%step%history_interval
    model%field_every = deck%step%field_every
    model%field_interval = deck%step%field_interval
    if (deck%step%field_vars_given) then
      model%field_vars = deck%step%field_vars
    else
      model%field_vars(VAR_PEEQ) = any([(model%materials(k)%law%hist_peeq > 0, &
          k = 1, model%nmat)])
    end if
    model%nout_sets = deck%step%n_out_sets
    allocate(model%out_sets(model%nout_sets))
    allocate(mask(model%nn))
    do k = 1, model%nout_sets
      associate (o => deck%step%out_sets(k), m => model%out_sets(k))
        mask = .false.
        call resolve_node_set(deck, model, node_map, o%name, o%where, mask, 0)
        if (.not. any(mask)) call warning(o%where, '*OUTPUT, HISTORY: set '//trim(o%name)// &
            ' holds no nodes (its means are written as 0)')
        m%name = lower(trim(o%name))
        m%nodes = pack([(i, i = 1, model%nn)], mask)
        m%vars = o%vars
      end associate
    end do
  end subroutine build_output

  !> Nodes of node set `name` (an NSET, an element set's nodes, a patch's control points, or a
  !! node id written as a number) into `mask` (nn). `node_map` maps the user ids of
  !! `model%node_id` to their rows.
  recursive subroutine resolve_node_set(deck, model, node_map, name, where, mask, depth)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    type(id_map_t), intent(in) :: node_map
    character(len=*), intent(in) :: name, where
    logical, intent(inout) :: mask(:)
    integer, intent(in) :: depth
    integer :: i, j, e, ip, id, ios, n
    logical :: found
    logical, allocatable :: emask(:)
    integer, allocatable :: idx(:), nodes(:)
    if (depth > 20) then
      call input_error(where, 'set '//trim(name)//' refers to itself (a cycle of set names)')
      return
    end if
    read(name, *, iostat=ios) id
    if (ios == 0 .and. verify(trim(name), '0123456789+-') == 0) then
      call mark_node_id(node_map, id, where, mask)
      return
    end if
    found = .false.
    do i = 1, deck%n_sets
      associate (s => deck%sets(i))
        if (s%kind /= SET_NODE .or. upper(trim(s%name)) /= upper(trim(name))) cycle
        found = .true.
        if (allocated(s%ids)) then
          do j = 1, size(s%ids)
            call mark_node_id(node_map, s%ids(j), s%where, mask)
          end do
        end if
        if (allocated(s%refs)) then
          do j = 1, size(s%refs)
            call resolve_node_set(deck, model, node_map, s%refs(j), s%ref_where(j), mask, &
                depth + 1)
          end do
        end if
        if (s%side /= SIDE_NONE) then
          ip = patch_index(model, s%patch)
          if (ip == 0) then
            call input_error(s%where, '*NSET: PATCH='//trim(s%patch)//' is not defined')
          else
            if (model%ndm == 3) then
              call volume_side_points(model%volumes(ip), s%side, idx, n)
            else
              call patch_side_points(model%patches(ip), s%side, idx, n)
            end if
            nodes = patch_nodes(model, ip)
            mask(nodes(idx(1:n))) = .true.
            deallocate(idx)
          end if
        end if
      end associate
    end do
    if (.not. found .and. has_elem_set(deck, model, name)) then
      found = .true.
      allocate(emask(model%nel), source=.false.)
      call resolve_elem_set(deck, model, name, where, emask, depth + 1)
      do e = 1, model%nel
        if (emask(e)) mask(model%conn(1:model%nen(e), e)) = .true.
      end do
    end if
    if (.not. found) call input_error(where, 'node set '//trim(name)//' is not defined '// &
        '(expected an *NSET, an element set, a patch name or a node id)')
  end subroutine resolve_node_set

  !> True when `name` names an element set (ELSET card, ELSET= of *ELEMENT, or a patch).
  logical function has_elem_set(deck, model, name)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    character(len=*), intent(in) :: name
    integer :: i
    has_elem_set = patch_index(model, name) > 0
    do i = 1, deck%n_blocks
      if (len_trim(deck%blocks(i)%elset) > 0 .and. &
          upper(trim(deck%blocks(i)%elset)) == upper(trim(name))) has_elem_set = .true.
    end do
    do i = 1, deck%n_sets
      if (deck%sets(i)%kind == SET_ELEMENT .and. &
          upper(trim(deck%sets(i)%name)) == upper(trim(name))) has_elem_set = .true.
    end do
  end function has_elem_set

  !> Marks the row of node `id` (the first, as the ids are unique), or reports it undefined.
  !! A lookup in the map, not a search of all nodes: sets of every node stay linear.
  subroutine mark_node_id(node_map, id, where, mask)
    type(id_map_t), intent(in) :: node_map
    integer, intent(in) :: id
    character(len=*), intent(in) :: where
    logical, intent(inout) :: mask(:)
    integer :: i
    i = id_map_find(node_map, id)
    if (i > 0) then
      mask(i) = .true.
      return
    end if
    call input_error(where, 'node '//str(id)//' is not defined')
  end subroutine mark_node_id

  !> *BOUNDARY and *INITIAL CONDITIONS.
  subroutine build_conditions(deck, model, node_map)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    type(id_map_t), intent(in) :: node_map
    logical, allocatable :: mask(:)
    integer :: k, d
    allocate(model%fixed(model%ndm, model%nn), source=.false.)
    allocate(model%u_fixed(model%ndm, model%nn), model%v0(model%ndm, model%nn), source=0.0_dp)
    allocate(mask(model%nn))
    do k = 1, deck%n_boundaries
      associate (b => deck%boundaries(k))
        mask = .false.
        call resolve_node_set(deck, model, node_map, b%target, b%where, mask, 0)
        if (.not. any(mask)) call warning(b%where, '*BOUNDARY: set '//trim(b%target)// &
            ' holds no nodes')
        do d = max(b%first_dof, 1), min(b%last_dof, model%ndm)
          where (mask)
            model%fixed(d, :) = .true.
            model%u_fixed(d, :) = b%value
          end where
        end do
      end associate
    end do
    do k = 1, deck%n_velocities
      associate (v => deck%velocities(k))
        mask = .false.
        call resolve_node_set(deck, model, node_map, v%target, v%where, mask, 0)
        if (v%dof >= 1 .and. v%dof <= model%ndm) then
          where (mask) model%v0(v%dof, :) = v%value
        end if
      end associate
    end do
    where (model%fixed) model%v0 = 0.0_dp
  end subroutine build_conditions

  !> The step settings that a 3D model has no solver for yet, refused at *DYNAMIC: the
  !! consistent-mass solvers KRONECKER and CORRECTOR (2D: tensor-product lattices of
  !! quadrilaterals and patches, and the corrector's passes on two components). AUTO takes CG
  !! for a consistent mass of hexahedra; CHOLESKY factorises it for the three components.
  !! The internal force: ictus_solver_internal_force (AUTO weighs the memory of K in 3D).
  subroutine step_3d(deck, model)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    character(len=:), allocatable :: at
    at = trim(deck%step%dynamic_where)
    select case (model%mass_solver)
    case (MASS_SOLVER_AUTO)
      model%mass_solver = MASS_SOLVER_CG
    case (MASS_SOLVER_KRONECKER, MASS_SOLVER_CORRECTOR)
      if (.not. any(model%mass_kind == MASS_CONSISTENT)) return
      call input_error(at, '*DYNAMIC, EXPLICIT: MASS SOLVER='// &
          trim(deck%step%mass_solver)//': not yet in 3D; a consistent mass of hexahedra is '// &
          'solved by MASS SOLVER=CG (which AUTO takes in 3D) or CHOLESKY')
    end select
  end subroutine step_3d

  !> *MASS (default HRZ everywhere) and *DAMPING, applied in deck order.
  subroutine build_mass_damping(deck, model)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    logical, allocatable :: mask(:)
    integer :: k, e
    allocate(model%mass_kind(model%nel), model%hrz_rule(model%nel))
    allocate(model%mass_alpha(model%nel), model%damping(model%nel), source=0.0_dp)
    model%mass_kind = MASS_HRZ
    model%hrz_rule = HRZ_FULL
    allocate(mask(model%nel))
    do k = 1, deck%n_masses
      associate (m => deck%masses(k))
        call body_mask(deck, model, m%elset, m%patch, m%where, mask)
        if (m%kind == MASS_ALPHA) then
          do e = 1, model%nel
            if (mask(e) .and. model%etype(e) /= ETYPE_Q8) then
              call input_error(m%where, '*MASS, TYPE=ALPHA applies to 8-node serendipity '// &
                  'elements only, but element '//str(model%elem_id(e))//' is '// &
                  etype_name(model%etype(e)))
              exit
            end if
          end do
        end if
        where (mask)
          model%mass_kind = m%kind
          model%mass_alpha = m%alpha
          model%hrz_rule = m%hrz_rule
        end where
      end associate
    end do
    do k = 1, deck%n_dampings
      associate (d => deck%dampings(k))
        call body_mask(deck, model, d%elset, d%patch, d%where, mask)
        where (mask) model%damping = d%alpha
      end associate
    end do
  end subroutine build_mass_damping

  !> Elements selected by ELSET= or PATCH= (all when both are empty).
  subroutine body_mask(deck, model, elset, patch, where, mask)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(in) :: model
    character(len=*), intent(in) :: elset, patch, where
    logical, intent(out) :: mask(:)
    integer :: ip
    if (len_trim(elset) == 0 .and. len_trim(patch) == 0) then
      mask = .true.
      return
    end if
    mask = .false.
    if (len_trim(elset) > 0) call resolve_elem_set(deck, model, elset, where, mask, 0)
    if (len_trim(patch) > 0) then
      ip = patch_index(model, patch)
      if (ip == 0) then
        call input_error(where, 'PATCH='//trim(patch)//' is not defined by a *PATCH card')
      else
        where (model%patch == ip) mask = .true.
      end if
    end if
  end subroutine body_mask
end module ictus_app_build_model
