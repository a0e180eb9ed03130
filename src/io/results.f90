!> The results file (layout version 1: doc/results.md).
!!
!! One HDF5 file per run, written while the run goes on: the model once, history records
!! buffered and appended in blocks, field snapshots as they come, and a flush after each
!! block, so a run that stops leaves everything written so far readable. The root attribute
!! `status` is written last ("completed" or the failure), so a file without it is from a run
!! that did not finish.
module ictus_io_results
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: lower
  use ictus_elements_types, only: ETYPE_IGA, ETYPE_IGA3, etype_is_nurbs, element_kind_t
  use ictus_elements_library, only: etype_name, etype_nen, element_type_count, element_kind
  use ictus_contact_contact, only: contact_t, pair_resultant
  use ictus_solver_model, only: model_t, patch_nodes, patch_name
  use ictus_solver_model, only: NVAR, VAR_U, VAR_V, VAR_A, VAR_S, VAR_E, VAR_MISES, &
      VAR_PEEQ, VAR_RF
  use ictus_materials_law, only: ANALYSIS_PLANE_STRAIN, ANALYSIS_3D
  use ictus_solver_domain, only: domain_t
  use ictus_solver_fields, only: element_fields_t
  use ictus_io_iga_viz, only: iga_viz_t, iga_viz_init, iga_viz_eval, iga_viz_points, &
      iga_viz_cells
  use ictus_io_hdf5_util, only: hid_t, h5u_create_file, h5u_close_file, h5u_flush, h5u_group, &
      h5u_close_group, h5u_attr_string, h5u_attr_int, h5u_attr_real, h5u_write, &
      h5u_create_ext, h5u_append, h5u_write_rows, h5u_open_file, h5u_truncate, h5u_delete, &
      h5u_delete_attr, h5u_members
  use ictus_io_xdmf, only: xdmf_write, xdmf_grid_t, xdmf_block_path
  implicit none
  private
  public :: results_t, results_open, results_history, results_field, results_close, &
      results_reaction, &
      history_record_t, results_contact, results_reopen, results_flush, results_records, &
      results_element_fields, results_sets, results_want_stress

  !> Records kept in memory before they are appended to the file.
  integer, parameter :: buffer_size = 512

  !> The datasets of a node-set history and the variables that ask for them.
  integer, parameter :: SET_VARS(3) = [VAR_U, VAR_V, VAR_RF]
  character(len=*), parameter :: SET_DATASETS(3) = [character(len=12) :: 'displacement', &
      'velocity', 'reaction']

  !> One history record.
  type :: history_record_t
    real(dp) :: time = 0.0_dp
    real(dp) :: dt = 0.0_dp
    real(dp) :: kinetic = 0.0_dp
    real(dp) :: strain = 0.0_dp
    real(dp) :: contact = 0.0_dp
    real(dp) :: external_work = 0.0_dp
    real(dp) :: plastic_work = 0.0_dp
    real(dp) :: frictional_work = 0.0_dp
  end type history_record_t

  type :: results_t
    integer(hid_t) :: file = -1
    character(len=:), allocatable :: path
    character(len=:), allocatable :: xdmf_path
    integer :: nbuf = 0
    !> Whether the energies have a plastic-work term (a material law dissipates).
    logical :: plastic = .false.
    !> Whether a contact pair has Coulomb friction (then /history/energy has frictional_work
    !! and such pairs friction_force).
    logical :: friction = .false.
    !> History records already appended to the file.
    integer :: n_written = 0
    type(history_record_t) :: buf(buffer_size)
    !> Contiguous work column for writing one quantity of the buffered records.
    real(dp) :: col(buffer_size)
    !> Contact pairs (lower-case names) and their buffered records: force_first (2),
    !! force_second (3; z = 0 in 2D), max_pressure, max_penetration, active_points,
    !! outside_points, friction_force (2), per record; whether each pair has friction; the
    !! components of the written forces (ndm).
    integer :: npairs = 0
    integer :: cdim = 2
    character(len=64), allocatable :: pair_name(:)
    logical, allocatable :: pair_friction(:)
    real(dp), allocatable :: cbuf(:,:,:)
    !> Node sets with a history (lower-case names), their variables (VAR_U, VAR_V, VAR_RF of
    !! model%out_sets) and their buffered records (ndm, slot, set, record): slot 1 the mean
    !! displacement, 2 the mean velocity, 3 the summed reaction.
    integer :: nsets = 0
    character(len=64), allocatable :: set_name(:)
    logical, allocatable :: set_vars(:,:)
    real(dp), allocatable :: sbuf(:,:,:,:)
    !> The variables of the field snapshots (model%field_vars).
    logical :: vars(NVAR) = .true.
    real(dp) :: col2(2, buffer_size)
    integer :: icol(buffer_size)
    !> Field snapshots written so far: step numbers and times.
    integer :: n_fields = 0
    integer, allocatable :: field_step(:)
    real(dp), allocatable :: field_time(:)
    !> Element blocks for the XDMF sidecar.
    type(xdmf_grid_t), allocatable :: grids(:)
    integer :: nn = 0
    !> Viewing samples of the NURBS elements: the elements whose samples this rank evaluates
    !! (those whose first control point it owns), the rows of their samples and their values
    !! (2, nmine).
    type(iga_viz_t) :: viz
    !> Per model element: its row in the cell block of its type (the FE blocks' cell fields
    !! when a block is not the whole model), and its viewing cells (NURBS elements).
    integer, allocatable :: block_row(:), ncells_of(:), elem_type(:)
    integer :: nviz_mine = 0
    integer, allocatable :: viz_elems(:), viz_mine(:)
    real(dp), allocatable :: viz_u(:,:), viz_v(:,:)
  end type results_t

contains

  !> Creates the file and writes the root attributes and the model.
  !! `omega_max` is the estimated largest natural frequency, `dt` the time step used.
  !! `m_diag` holds the nodal masses of this rank's owned nodes `gid`.
  subroutine results_open(r, path, model, dom, contact, deck_text, ranks, m_diag, gid, &
      omega_max, dt)
    type(results_t), intent(out) :: r
    character(len=*), intent(in) :: path, deck_text
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    type(contact_t), intent(in) :: contact
    integer, intent(in) :: ranks
    real(dp), intent(in) :: m_diag(:)
    integer, intent(in) :: gid(:)
    real(dp), intent(in) :: omega_max, dt
    integer(hid_t) :: g
    call set_paths(r, path)
    r%nn = model%nn
    r%plastic = dissipates(model)
    r%vars = model%field_vars
    allocate(r%field_step(0), r%field_time(0))
    call h5u_create_file(path, r%file)
    call h5u_attr_string(r%file, 'program', 'ictus')
    call h5u_attr_string(r%file, 'version', ictus_version_string())
    call h5u_attr_int(r%file, 'format_version', 1)
    call h5u_attr_string(r%file, 'title', model%title)
    if (model%analysis == ANALYSIS_3D) then
      call h5u_attr_string(r%file, 'analysis', '3D')
    else if (model%analysis == ANALYSIS_PLANE_STRAIN) then
      call h5u_attr_string(r%file, 'analysis', 'plane strain')
    else
      call h5u_attr_string(r%file, 'analysis', 'plane stress')
    end if
    call h5u_attr_int(r%file, 'dimension', model%ndm)
    if (model%ndm == 2) call h5u_attr_real(r%file, 'thickness', model%thickness)
    call h5u_attr_int(r%file, 'ranks', ranks)
    call h5u_attr_string(r%file, 'deck', deck_text)
    call h5u_attr_real(r%file, 'omega_max', omega_max)
    call h5u_attr_real(r%file, 'dt', dt)
    call write_model(r, model, m_diag, gid)
    call write_partition(r, dom)
    call setup_views(r, model, dom)
    call grid_fields(r)
    call write_viz(r, model)
    call h5u_group(r%file, 'history', g)
    call h5u_create_ext(g, 'time', 0, buffer_size)
    call h5u_create_ext(g, 'dt', 0, buffer_size)
    call h5u_close_group(g)
    call h5u_group(r%file, 'history/energy', g)
    call h5u_create_ext(g, 'kinetic', 0, buffer_size)
    call h5u_create_ext(g, 'strain', 0, buffer_size)
    call h5u_create_ext(g, 'contact', 0, buffer_size)
    call h5u_create_ext(g, 'external_work', 0, buffer_size)
    if (r%plastic) call h5u_create_ext(g, 'plastic_work', 0, buffer_size)
    r%friction = contact%friction
    if (r%friction) call h5u_create_ext(g, 'frictional_work', 0, buffer_size)
    call h5u_create_ext(g, 'total', 0, buffer_size)
    call h5u_close_group(g)
    call h5u_group(r%file, 'fields', g)
    call h5u_close_group(g)
    call open_contact(r, contact)
    call open_sets(r, model, .true.)
    call h5u_flush(r%file)
  end subroutine results_open

  !> The node sets with a history of their own, and with `create` their datasets
  !! /history/nset/<name>/{displacement,velocity,reaction} (those asked for).
  subroutine open_sets(r, model, create)
    type(results_t), intent(inout) :: r
    type(model_t), intent(in) :: model
    logical, intent(in) :: create
    integer(hid_t) :: g
    integer :: k, j
    r%nsets = model%nout_sets
    allocate(r%set_name(r%nsets), r%set_vars(NVAR, r%nsets))
    allocate(r%sbuf(model%ndm, 3, r%nsets, buffer_size), source=0.0_dp)
    do k = 1, r%nsets
      r%set_name(k) = trim(model%out_sets(k)%name)
      r%set_vars(:, k) = model%out_sets(k)%vars
    end do
    if (r%nsets == 0 .or. .not. create) return
    call h5u_group(r%file, 'history/nset', g)
    call h5u_close_group(g)
    do k = 1, r%nsets
      call h5u_group(r%file, 'history/nset/'//trim(r%set_name(k)), g)
      do j = 1, 3
        if (r%set_vars(SET_VARS(j), k)) call h5u_create_ext(g, trim(SET_DATASETS(j)), &
            model%ndm, buffer_size)
      end do
      call h5u_close_group(g)
    end do
  end subroutine open_sets

  !> Stores the node-set values of the history record being added next: vals(ndm, slot, set)
  !! with slot 1 the mean displacement, 2 the mean velocity, 3 the summed reaction (call it
  !! right before results_history).
  subroutine results_sets(r, vals)
    type(results_t), intent(inout) :: r
    real(dp), intent(in) :: vals(:,:,:)
    if (r%nsets > 0) r%sbuf(:, :, :, r%nbuf + 1) = vals(:, 1:3, 1:r%nsets)
  end subroutine results_sets

  !> Whether a material law of the model dissipates energy (then /history/energy has
  !! plastic_work).
  logical function dissipates(model)
    type(model_t), intent(in) :: model
    integer :: m
    dissipates = .false.
    do m = 1, model%nmat
      if (model%materials(m)%law%hist_dissipation > 0) dissipates = .true.
    end do
  end function dissipates

  !> /history/contact/<pair>/ datasets and the /contact group.
  subroutine open_contact(r, contact)
    type(results_t), intent(inout) :: r
    type(contact_t), intent(in) :: contact
    integer(hid_t) :: g
    integer :: k
    r%npairs = contact%npairs
    r%cdim = contact%ndm
    allocate(r%pair_name(r%npairs), r%cbuf(12, r%npairs, buffer_size))
    r%pair_friction = [(contact%pairs(k)%fr%on, k = 1, r%npairs)]
    if (r%npairs == 0) return
    call h5u_group(r%file, 'history/contact', g)
    call h5u_close_group(g)
    call h5u_group(r%file, 'contact', g)
    call h5u_close_group(g)
    do k = 1, r%npairs
      r%pair_name(k) = trim(lower(contact%pairs(k)%name))
      call h5u_group(r%file, 'history/contact/'//trim(r%pair_name(k)), g)
      call h5u_create_ext(g, 'force_first', r%cdim, buffer_size)
      call h5u_create_ext(g, 'force_second', r%cdim, buffer_size)
      call h5u_create_ext(g, 'max_pressure', 0, buffer_size)
      call h5u_create_ext(g, 'max_penetration', 0, buffer_size)
      call h5u_create_ext(g, 'active_points', 0, buffer_size, is_integer=.true.)
      call h5u_create_ext(g, 'outside_points', 0, buffer_size, is_integer=.true.)
      if (r%pair_friction(k)) call h5u_create_ext(g, 'friction_force', 2, buffer_size)
      call h5u_close_group(g)
      call h5u_group(r%file, 'contact/'//trim(r%pair_name(k)), g)
      call h5u_close_group(g)
    end do
  end subroutine open_contact

  !> Stores the contact quantities of every pair for the history record being added next
  !! (call it right before results_history).
  subroutine results_contact(r, contact)
    type(results_t), intent(inout) :: r
    type(contact_t), intent(in) :: contact
    integer :: k, n
    n = r%nbuf + 1
    do k = 1, r%npairs
      associate (p => contact%pairs(k))
        r%cbuf(:, k, n) = [pair_resultant(contact, k, 1), pair_resultant(contact, k, 2), &
            p%max_pressure, p%max_penetration, real(p%active_points, dp), &
            real(p%outside_points, dp), p%fr%force]
      end associate
    end do
  end subroutine results_contact

  function ictus_version_string() result(v)
    use ictus_core_build_info, only: ictus_version
    character(len=:), allocatable :: v
    v = ictus_version
  end function ictus_version_string

  !> /model: coordinates, weights, masses, ids, element blocks and patches.
  subroutine write_model(r, model, m_diag, gid)
    type(results_t), intent(inout) :: r
    type(model_t), intent(in) :: model
    real(dp), intent(in) :: m_diag(:)
    integer, intent(in) :: gid(:)
    integer(hid_t) :: g, ge, gp
    integer :: t, ne, e, k, ip, nen
    integer, allocatable :: conn(:,:), ids(:)
    character(len=:), allocatable :: tname
    type(element_kind_t) :: kd
    call h5u_group(r%file, 'model', g)
    call h5u_write(g, 'coordinates', model%x0)
    call h5u_write(g, 'weights', model%weight)
    call h5u_write_rows(g, 'mass', m_diag(1:size(gid)), gid, model%nn)
    call h5u_write(g, 'node_ids', model%node_id)
    call h5u_group(g, 'elements', ge)
    do t = 1, element_type_count()
      ne = count(model%etype == t)
      if (ne == 0) cycle
      nen = maxval(model%nen, mask=model%etype == t)
      allocate(conn(nen, ne), ids(ne))
      conn = -1
      k = 0
      do e = 1, model%nel
        if (model%etype(e) /= t) cycle
        k = k + 1
        conn(1:model%nen(e), k) = model%conn(1:model%nen(e), e) - 1
        ids(k) = model%elem_id(e)
      end do
      tname = lower(etype_name(t))
      call h5u_group(ge, tname, gp)
      call h5u_write(gp, 'connectivity', conn)
      ! the node order of the XDMF topology where it differs (C3D27: Hexahedron_27)
      kd = element_kind(t)
      if (allocated(kd%xdmf_order)) call h5u_write(gp, 'xdmf_connectivity', &
          conn(kd%xdmf_order, :))
      call h5u_write(gp, 'ids', ids)
      call h5u_close_group(gp)
      deallocate(conn, ids)
    end do
    call h5u_close_group(ge)
    if (model%npatch > 0) then
      call h5u_group(g, 'patches', ge)
      do ip = 1, model%npatch
        call h5u_group(ge, lower(patch_name(model, ip)), gp)
        if (model%ndm == 3) then
          associate (v => model%volumes(ip))
            call h5u_write(gp, 'degree', v%p)
            call h5u_write(gp, 'size', v%n)
            call h5u_write(gp, 'knots_1', v%knots1)
            call h5u_write(gp, 'knots_2', v%knots2)
            call h5u_write(gp, 'knots_3', v%knots3)
          end associate
        else
          associate (pt => model%patches(ip))
            call h5u_write(gp, 'degree', pt%p)
            call h5u_write(gp, 'size', pt%n)
            call h5u_write(gp, 'knots_1', pt%knots1)
            call h5u_write(gp, 'knots_2', pt%knots2)
          end associate
        end if
        call h5u_write(gp, 'ids', patch_nodes(model, ip))
        call h5u_close_group(gp)
      end do
      call h5u_close_group(ge)
    end if
    call h5u_close_group(g)
  end subroutine write_model

  !> /model/partition: the rank that owns each node (the only dataset that depends on the
  !! number of ranks), and /model/element_partition: the METIS part of each element.
  subroutine write_partition(r, dom)
    type(results_t), intent(inout) :: r
    type(domain_t), intent(in) :: dom
    integer(hid_t) :: g
    call h5u_group(r%file, 'model', g)
    call h5u_write(g, 'partition', dom%owner)
    call h5u_write(g, 'element_partition', dom%part)
    call h5u_close_group(g)
  end subroutine write_partition

  !> /viz/iga: sample points and linear sub-cells of the NURBS elements, for viewing.
  !! Both are formed here and released: the run keeps only the patches' tables.
  subroutine write_viz(r, model)
    type(results_t), intent(inout) :: r
    type(model_t), intent(in) :: model
    integer(hid_t) :: g
    real(dp), allocatable :: points(:,:)
    integer, allocatable :: cells(:,:)
    if (r%viz%ns == 0) return
    call h5u_group(r%file, 'viz', g)
    call h5u_close_group(g)
    call h5u_group(r%file, 'viz/iga', g)
    allocate(points(model%ndm, r%viz%ns))
    call iga_viz_points(r%viz, model, points)
    call h5u_write(g, 'points', points)
    deallocate(points)
    allocate(cells(2**model%ndm, r%viz%ncells))
    call iga_viz_cells(r%viz, model, cells)
    call h5u_write(g, 'cells', cells)
    call h5u_close_group(g)
  end subroutine write_viz

  !> The XDMF cell blocks (one per FE type, plus the NURBS viewing cells) and the viewing
  !! samples this rank evaluates.
  subroutine setup_views(r, model, dom)
    type(results_t), intent(inout) :: r
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    integer :: t, ne, e, q, k, s
    type(element_kind_t) :: kd
    allocate(r%grids(0), r%block_row(model%nel), r%ncells_of(model%nel))
    r%elem_type = model%etype
    do t = 1, element_type_count()
      ne = count(model%etype == t)
      ! NURBS elements are shown on their viewing cells (below)
      if (ne == 0 .or. etype_nen(t) == 0) cycle
      kd = element_kind(t)
      r%grids = [r%grids, xdmf_grid_t(lower(etype_name(t)), t, ne, &
          maxval(model%nen, mask=model%etype == t), model%nn, ne == model%nel, &
          ndm=model%ndm, permuted=allocated(kd%xdmf_order))]
    end do
    do t = 1, element_type_count()
      k = 0
      do e = 1, model%nel
        if (model%etype(e) /= t) cycle
        k = k + 1
        r%block_row(e) = k
      end do
    end do
    r%ncells_of = 0
    if (model%npatch == 0) return
    call iga_viz_init(model, r%viz, model%viz_samples)
    do e = 1, model%nel
      if (r%viz%first_cell(e) >= 0) r%ncells_of(e) = &
          (r%viz%patches(model%patch(e))%s - 1)**model%ndm
    end do
    r%viz_elems = pack([(e, e = 1, model%nel)], r%viz%first_point >= 0)
    r%viz_elems = pack(r%viz_elems, dom%owner(model%conn(1, r%viz_elems)) == dom%rank)
    r%nviz_mine = 0
    do q = 1, size(r%viz_elems)
      r%nviz_mine = r%nviz_mine + r%viz%patches(model%patch(r%viz_elems(q)))%s**model%ndm
    end do
    allocate(r%viz_mine(r%nviz_mine), r%viz_u(model%ndm, r%nviz_mine), &
        r%viz_v(model%ndm, r%nviz_mine))
    k = 0
    do q = 1, size(r%viz_elems)
      e = r%viz_elems(q)
      do s = 1, r%viz%patches(model%patch(e))%s**model%ndm
        k = k + 1
        r%viz_mine(k) = r%viz%first_point(e) + s
      end do
    end do
    r%grids = [r%grids, xdmf_grid_t('iga', merge(ETYPE_IGA3, ETYPE_IGA, model%ndm == 3), &
        r%viz%ncells, 2**model%ndm, r%viz%ns, .false., ndm=model%ndm)]
  end subroutine setup_views

  !> What the snapshots hold for the XDMF sidecar (the attributes of absent datasets are
  !! left out).
  subroutine grid_fields(r)
    type(results_t), intent(inout) :: r
    r%grids(:)%displacement = r%vars(VAR_U)
    r%grids(:)%velocity = r%vars(VAR_V)
    r%grids(:)%mises = r%vars(VAR_MISES)
    r%grids(:)%peeq = r%vars(VAR_PEEQ)
    r%grids(:)%stress = r%vars(VAR_S)
    r%grids(:)%strain = r%vars(VAR_E)
  end subroutine grid_fields

  !> Reopens the results file of an interrupted run to continue it from a checkpoint: history
  !! datasets are cut back to `n_history` records, the snapshots that are not among
  !! `field_steps` (those after the checkpoint) and the `status` attribute are removed. `ok` is false when the file
  !! cannot be opened.
  subroutine results_reopen(r, path, model, dom, contact, n_history, field_steps, field_times, &
      ok)
    type(results_t), intent(out) :: r
    character(len=*), intent(in) :: path
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    type(contact_t), intent(in) :: contact
    integer, intent(in) :: n_history, field_steps(:)
    real(dp), intent(in) :: field_times(:)
    logical, intent(out) :: ok
    integer(hid_t) :: g
    integer :: k, j
    character(len=16), allocatable :: names(:)
    character(len=*), parameter :: energies(5) = [character(len=13) :: 'kinetic', 'strain', &
        'contact', 'external_work', 'total']
    character(len=*), parameter :: cnames(6) = [character(len=15) :: 'force_first', &
        'force_second', 'max_pressure', 'max_penetration', 'active_points', 'outside_points']
    call set_paths(r, path)
    r%nn = model%nn
    r%plastic = dissipates(model)
    r%vars = model%field_vars
    call h5u_open_file(path, .true., r%file, ok)
    if (.not. ok) return
    call setup_views(r, model, dom)
    call grid_fields(r)
    r%npairs = contact%npairs
    r%cdim = contact%ndm
    r%friction = contact%friction
    allocate(r%pair_name(r%npairs), r%cbuf(12, r%npairs, buffer_size))
    r%pair_friction = [(contact%pairs(k)%fr%on, k = 1, r%npairs)]
    do k = 1, r%npairs
      r%pair_name(k) = trim(lower(contact%pairs(k)%name))
    end do
    call h5u_group(r%file, 'history', g)
    call h5u_truncate(g, 'time', n_history)
    call h5u_truncate(g, 'dt', n_history)
    call h5u_close_group(g)
    call h5u_group(r%file, 'history/energy', g)
    if (r%plastic) call h5u_truncate(g, 'plastic_work', n_history)
    if (r%friction) call h5u_truncate(g, 'frictional_work', n_history)
    do k = 1, size(energies)
      call h5u_truncate(g, trim(energies(k)), n_history)
    end do
    call h5u_close_group(g)
    do k = 1, r%npairs
      call h5u_group(r%file, 'history/contact/'//trim(r%pair_name(k)), g)
      do j = 1, size(cnames)
        call h5u_truncate(g, trim(cnames(j)), n_history)
      end do
      if (r%pair_friction(k)) call h5u_truncate(g, 'friction_force', n_history)
      call h5u_close_group(g)
    end do
    call open_sets(r, model, .false.)
    do k = 1, r%nsets
      call h5u_group(r%file, 'history/nset/'//trim(r%set_name(k)), g)
      do j = 1, 3
        if (r%set_vars(SET_VARS(j), k)) call h5u_truncate(g, trim(SET_DATASETS(j)), n_history)
      end do
      call h5u_close_group(g)
    end do
    ! the snapshots the interrupted run wrote after its checkpoint go (they come again)
    call h5u_members(r%file, 'fields', names)
    do j = 1, size(names)
      if (any(field_steps == step_of(names(j)))) cycle
      call h5u_delete(r%file, 'fields/'//trim(names(j)))
      do k = 1, r%npairs
        call h5u_delete(r%file, 'contact/'//trim(r%pair_name(k))//'/'//trim(names(j)))
      end do
    end do
    call h5u_delete_attr(r%file, 'status')
    r%field_step = field_steps
    r%field_time = field_times
    r%n_fields = size(field_steps)
    r%n_written = n_history
    call h5u_flush(r%file)
  end subroutine results_reopen

  !> The step of a snapshot group's name (its 8 digits; -1 if it is not a number).
  integer function step_of(name)
    character(len=*), intent(in) :: name
    integer :: ios
    read(name, *, iostat=ios) step_of
    if (ios /= 0) step_of = -1
  end function step_of

  !> The results path and the XDMF path next to it.
  subroutine set_paths(r, path)
    type(results_t), intent(inout) :: r
    character(len=*), intent(in) :: path
    integer :: k
    r%path = path
    k = index(path, '.h5', back=.true.)
    if (k > 0 .and. k == len(path) - 2) then
      r%xdmf_path = path(1:k - 1)//'.xdmf'
    else
      r%xdmf_path = path//'.xdmf'
    end if
  end subroutine set_paths

  !> Appends the buffered history to the file and flushes it (before a checkpoint).
  subroutine results_flush(r)
    type(results_t), intent(inout) :: r
    call flush_history(r)
  end subroutine results_flush

  !> Number of history records in the file plus those buffered.
  integer function results_records(r)
    type(results_t), intent(in) :: r
    results_records = r%n_written + r%nbuf
  end function results_records

  !> Adds one history record (appended to the file in blocks).
  subroutine results_history(r, rec)
    type(results_t), intent(inout) :: r
    type(history_record_t), intent(in) :: rec
    r%nbuf = r%nbuf + 1
    r%buf(r%nbuf) = rec
    if (r%nbuf == buffer_size) call flush_history(r)
  end subroutine results_history

  subroutine flush_history(r)
    type(results_t), intent(inout) :: r
    integer(hid_t) :: g
    integer :: n, k, j
    real(dp), allocatable :: sv(:,:)
    n = r%nbuf
    if (n == 0) return
    call h5u_group(r%file, 'history', g)
    r%col(1:n) = r%buf(1:n)%time
    call h5u_append(g, 'time', r%col(1:n))
    r%col(1:n) = r%buf(1:n)%dt
    call h5u_append(g, 'dt', r%col(1:n))
    call h5u_close_group(g)
    call h5u_group(r%file, 'history/energy', g)
    r%col(1:n) = r%buf(1:n)%kinetic
    call h5u_append(g, 'kinetic', r%col(1:n))
    r%col(1:n) = r%buf(1:n)%strain
    call h5u_append(g, 'strain', r%col(1:n))
    r%col(1:n) = r%buf(1:n)%contact
    call h5u_append(g, 'contact', r%col(1:n))
    r%col(1:n) = r%buf(1:n)%external_work
    call h5u_append(g, 'external_work', r%col(1:n))
    r%col(1:n) = r%buf(1:n)%kinetic + r%buf(1:n)%strain + r%buf(1:n)%contact &
        - r%buf(1:n)%external_work
    if (r%friction) r%col(1:n) = r%col(1:n) + r%buf(1:n)%frictional_work
    if (r%plastic) then
      r%col(1:n) = r%col(1:n) + r%buf(1:n)%plastic_work
      call h5u_append(g, 'total', r%col(1:n))
      r%col(1:n) = r%buf(1:n)%plastic_work
      call h5u_append(g, 'plastic_work', r%col(1:n))
    else
      call h5u_append(g, 'total', r%col(1:n))
    end if
    if (r%friction) then
      r%col(1:n) = r%buf(1:n)%frictional_work
      call h5u_append(g, 'frictional_work', r%col(1:n))
    end if
    call h5u_close_group(g)
    do k = 1, r%npairs
      call h5u_group(r%file, 'history/contact/'//trim(r%pair_name(k)), g)
      call append_vector(g, 'force_first', r%cbuf(1:r%cdim, k, 1:n))
      call append_vector(g, 'force_second', r%cbuf(4:3 + r%cdim, k, 1:n))
      r%col(1:n) = r%cbuf(7, k, 1:n)
      call h5u_append(g, 'max_pressure', r%col(1:n))
      r%col(1:n) = r%cbuf(8, k, 1:n)
      call h5u_append(g, 'max_penetration', r%col(1:n))
      r%icol(1:n) = nint(r%cbuf(9, k, 1:n))
      call h5u_append(g, 'active_points', r%icol(1:n))
      r%icol(1:n) = nint(r%cbuf(10, k, 1:n))
      call h5u_append(g, 'outside_points', r%icol(1:n))
      if (r%pair_friction(k)) then
        r%col2(:, 1:n) = r%cbuf(11:12, k, 1:n)
        call h5u_append(g, 'friction_force', r%col2(:, 1:n))
      end if
      call h5u_close_group(g)
    end do
    do k = 1, r%nsets
      call h5u_group(r%file, 'history/nset/'//trim(r%set_name(k)), g)
      do j = 1, 3
        if (.not. r%set_vars(SET_VARS(j), k)) cycle
        sv = r%sbuf(:, j, k, 1:n)
        call h5u_append(g, trim(SET_DATASETS(j)), sv)
      end do
      call h5u_close_group(g)
    end do
    r%n_written = r%n_written + n
    r%nbuf = 0
    call h5u_flush(r%file)
  end subroutine flush_history

  !> Writes a field snapshot /fields/<step>/ (the variables r%vars asks for) and refreshes the
  !! XDMF sidecar. u, v and a hold the values of this rank's owned nodes `gid` (u and v local
  !! with ghosts where the model has patches).
  subroutine results_field(r, model, dom, step, time, u, v, a, gid, contact)
    type(results_t), intent(inout) :: r
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    integer, intent(in) :: step
    real(dp), intent(in) :: time
    real(dp), intent(in) :: u(:,:), v(:,:), a(:,:)
    integer, intent(in) :: gid(:)
    type(contact_t), intent(in) :: contact
    integer(hid_t) :: g
    integer :: k
    character(len=8) :: name
    write(name, '(i8.8)') step
    call h5u_group(r%file, 'fields/'//name, g)
    call h5u_attr_real(g, 'time', time)
    call h5u_attr_int(g, 'step', step)
    if (r%vars(VAR_U)) call node_vector(r, model, dom, g, 'displacement', u, gid, r%viz_u)
    if (r%vars(VAR_V)) call node_vector(r, model, dom, g, 'velocity', v, gid, r%viz_v)
    if (r%vars(VAR_A)) call h5u_write_rows(g, 'acceleration', a(:, 1:size(gid)), gid, r%nn)
    call h5u_close_group(g)
    ! contact points of each pair's first surface (the same on every rank)
    do k = 1, r%npairs
      associate (p => contact%pairs(k))
        call h5u_group(r%file, 'contact/'//trim(r%pair_name(k))//'/'//name, g)
        call h5u_attr_real(g, 'time', time)
        call h5u_attr_int(g, 'step', step)
        call h5u_write(g, 'x', p%x(:, 1:p%npoints))
        call h5u_write(g, 'pressure', p%pressure(1:p%npoints))
        call h5u_close_group(g)
      end associate
    end do
    r%n_fields = r%n_fields + 1
    r%field_step = [r%field_step, step]
    r%field_time = [r%field_time, time]
    call flush_history(r)
    call xdmf_write(r%xdmf_path, r%path, r%grids, r%field_step, r%field_time)
    ! with several blocks, also one sidecar per block (readers of one mesh per file: meshio)
    if (size(r%grids) > 1) then
      do k = 1, size(r%grids)
        call xdmf_write(xdmf_block_path(r%xdmf_path, r%grids(k)%name), r%path, &
            r%grids(k:k), r%field_step, r%field_time)
      end do
    end if
  end subroutine results_field

  !> Appends the records v (ndm, n) to the extendible dataset `name` of group g.
  subroutine append_vector(g, name, v)
    integer(hid_t), intent(in) :: g
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: v(:,:)
    real(dp) :: w(size(v, 1), size(v, 2))
    w = v
    call h5u_append(g, name, w)
  end subroutine append_vector

  !> A node vector of a snapshot: `name` (n, 2) from x (owned nodes `gid` first), its values
  !! at the viewing samples of the patches (viz_<name>, evaluated into `xv`) and the copies
  !! with z = 0 for the XDMF sidecar (<name>_3d, viz_<name>_3d).
  subroutine node_vector(r, model, dom, g, name, x, gid, xv)
    type(results_t), intent(inout) :: r
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    integer(hid_t), intent(in) :: g
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: x(:,:)
    integer, intent(in) :: gid(:)
    real(dp), intent(inout) :: xv(:,:)
    call h5u_write_rows(g, name, x(:, 1:size(gid)), gid, r%nn)
    if (r%viz%ns > 0) then
      call iga_viz_eval(r%viz, model, r%viz_elems, x, xv, dom%g2l)
      call h5u_write_rows(g, 'viz_'//name, xv, r%viz_mine, r%viz%ns)
    end if
    if (any(r%grids%etype /= ETYPE_IGA) .and. model%ndm == 2) call write_3d(g, name//'_3d', &
        x(:, 1:size(gid)), gid, r%nn)
    if (r%viz%ns > 0 .and. model%ndm == 2) call write_3d(g, 'viz_'//name//'_3d', xv, &
        r%viz_mine, r%viz%ns)
  end subroutine node_vector

  !> Whether a snapshot needs the element fields (a variable of ictus_solver_fields is asked).
  logical function results_want_stress(r)
    type(results_t), intent(in) :: r
    results_want_stress = any(r%vars([VAR_S, VAR_E, VAR_MISES, VAR_PEEQ]))
  end function results_want_stress

  !> The element fields of step `step` (ictus_solver_fields) that r%vars asks for: per
  !! element /fields/<step>/stress and strain (ne, 4: xx, yy, xy, zz), mises and peeq (ne); at
  !! the nodes nodal_stress (n, 4) with stress and nodal_mises (n) with mises. gid: the global
  !! indices of the owned nodes.
  subroutine results_element_fields(r, step, ef, gid, nel)
    type(results_t), intent(inout) :: r
    integer, intent(in) :: step, nel
    type(element_fields_t), intent(in) :: ef
    integer, intent(in) :: gid(:)
    integer(hid_t) :: g
    character(len=8) :: name
    write(name, '(i8.8)') step
    call h5u_group(r%file, 'fields/'//name, g)
    if (r%vars(VAR_S)) call h5u_write_rows(g, 'stress', ef%stress, ef%elem, nel)
    if (r%vars(VAR_E)) call h5u_write_rows(g, 'strain', ef%strain, ef%elem, nel)
    if (r%vars(VAR_MISES)) call h5u_write_rows(g, 'mises', ef%mises, ef%elem, nel)
    if (r%vars(VAR_PEEQ)) call h5u_write_rows(g, 'peeq', ef%peeq, ef%elem, nel)
    if (r%vars(VAR_S)) call h5u_write_rows(g, 'nodal_stress', ef%nodal_stress, gid, r%nn)
    if (r%vars(VAR_MISES)) call h5u_write_rows(g, 'nodal_mises', ef%nodal_mises, gid, r%nn)
    if (r%vars(VAR_S)) call block_cells(r, g, 'stress', ef%stress, ef%elem)
    if (r%vars(VAR_E)) call block_cells(r, g, 'strain', ef%strain, ef%elem)
    if (r%vars(VAR_MISES)) call block_cells(r, g, 'mises', reshape(ef%mises, [1, size(ef%mises)]), &
        ef%elem)
    if (r%vars(VAR_PEEQ)) call block_cells(r, g, 'peeq', reshape(ef%peeq, [1, size(ef%peeq)]), &
        ef%elem)
    call h5u_close_group(g)
  end subroutine results_element_fields

  !> The per-element values v(ncomp, :) of the elements elem (this rank's) as cell fields of
  !! the XDMF blocks that are not the whole model: `<type>_<name>` (one row per element of
  !! that type, in model order) for an FE block beside others, `viz_<name>` (the element's
  !! value on each of its viewing cells) for NURBS elements (doc/results.md). A scalar
  !! (ncomp = 1) is written as a 1-D dataset, else (rows, ncomp).
  subroutine block_cells(r, g, name, v, elem)
    type(results_t), intent(inout) :: r
    integer(hid_t), intent(in) :: g
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: v(:,:)
    integer, intent(in) :: elem(:)
    real(dp), allocatable :: vals(:,:)
    integer, allocatable :: rows(:), pick(:)
    integer :: k, j, n, q
    do k = 1, size(r%grids)
      associate (gr => r%grids(k))
        if (gr%whole) cycle
        if (etype_is_nurbs(gr%etype)) then
          n = sum(r%ncells_of(elem))
          allocate(vals(size(v, 1), n), rows(n))
          n = 0
          do j = 1, size(elem)
            do q = 1, r%ncells_of(elem(j))
              n = n + 1
              rows(n) = r%viz%first_cell(elem(j)) + q
              vals(:, n) = v(:, j)
            end do
          end do
          call write_cells(g, 'viz_'//name, vals, rows, gr%nel)
        else
          pick = pack([(j, j = 1, size(elem))], r%elem_type(elem) == gr%etype)
          vals = v(:, pick)
          rows = r%block_row(elem(pick))
          call write_cells(g, trim(gr%name)//'_'//name, vals, rows, gr%nel)
        end if
        deallocate(vals, rows)
      end associate
    end do
  end subroutine block_cells

  !> Rows `rows` of the cell dataset `name` (nglobal rows): 1-D for one component.
  subroutine write_cells(g, name, vals, rows, nglobal)
    integer(hid_t), intent(in) :: g
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: vals(:,:)
    integer, intent(in) :: rows(:), nglobal
    if (size(vals, 1) == 1) then
      call h5u_write_rows(g, name, vals(1, :), rows, nglobal)
    else
      call h5u_write_rows(g, name, vals, rows, nglobal)
    end if
  end subroutine write_cells

  !> The reaction forces of step `step`, /fields/<step>/reaction (n, 2), when the snapshots
  !! hold RF (*OUTPUT, FIELD, VARIABLES=...RF): rf (2, :) holds the values of this rank's
  !! owned nodes `gid` (0 on the dofs that are not constrained).
  subroutine results_reaction(r, step, rf, gid)
    type(results_t), intent(inout) :: r
    integer, intent(in) :: step
    real(dp), intent(in) :: rf(:,:)
    integer, intent(in) :: gid(:)
    integer(hid_t) :: g
    character(len=8) :: name
    if (.not. r%vars(VAR_RF)) return
    write(name, '(i8.8)') step
    call h5u_group(r%file, 'fields/'//name, g)
    call h5u_write_rows(g, 'reaction', rf(:, 1:size(gid)), gid, r%nn)
    call h5u_close_group(g)
  end subroutine results_reaction

  !> Writes the rows `rows` of the (nglobal, 3) dataset `name`: the vectors x (2, :) with a
  !! third component 0.
  subroutine write_3d(g, name, x, rows, nglobal)
    integer(hid_t), intent(in) :: g
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: x(:,:)
    integer, intent(in) :: rows(:), nglobal
    real(dp), allocatable :: x3(:,:)
    allocate(x3(3, size(rows)))
    x3(1:2, :) = x(1:2, 1:size(rows))
    x3(3, :) = 0.0_dp
    call h5u_write_rows(g, name, x3, rows, nglobal)
  end subroutine write_3d

  !> Writes the remaining history, the final `status` attribute, and closes the file.
  subroutine results_close(r, status)
    type(results_t), intent(inout) :: r
    character(len=*), intent(in) :: status
    if (r%file < 0) return
    call flush_history(r)
    call h5u_attr_string(r%file, 'status', status)
    call h5u_close_file(r%file)
  end subroutine results_close
end module ictus_io_results
