!> Builds the loads and the prescribed motion of a model (model%loads, ictus_solver_load_spec)
!! from the deck's *AMPLITUDE, *CLOAD, *DLOAD and *BOUNDARY cards (doc/user-guide.md §5).
!!
!! *BOUNDARY lines apply in deck order, a later line overriding an earlier one on the same
!! dof (as `build_model` does for the fixed dofs); a dof whose last line has AMPLITUDE= or
!! TYPE=VELOCITY is prescribed motion, starting from u_p(0) (0 for TYPE=VELOCITY). A time-
!! varying boundary with a consistent mass is refused: its acceleration would couple to the
!! free dofs through M_fc. Run after `build_model` has succeeded; problems are reported
!! through `input_error` at their deck lines.
module ictus_app_build_loads
  use ictus_core_kinds, only: dp
  use ictus_core_errors, only: input_error, warning
  use ictus_mass_types, only: MASS_CONSISTENT
  use ictus_solver_amplitude, only: amplitude_t, amp_factor, AMP_TABULAR, AMP_SMOOTH_STEP
  use ictus_solver_load_spec, only: load_spec_t, MOTION_DISPLACEMENT, MOTION_VELOCITY
  use ictus_solver_model, only: model_t
  use ictus_io_deck_types, only: deck_t, DLOAD_PRESSURE, AMP_DEF_SMOOTH_STEP, BC_VELOCITY
  use ictus_app_build_model, only: resolve_node_set, resolve_elem_set
  use ictus_app_build_contact, only: build_named_surface, named_element_faces
  use ictus_app_id_map, only: id_map_t, id_map_init
  implicit none
  private
  public :: build_loads

contains

  !> Fills model%loads from the deck, and sets u_fixed of the prescribed-motion dofs to u_p(0).
  subroutine build_loads(deck, model)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    type(id_map_t) :: node_map
    integer :: k
    ! the user ids of the nodes, for the node ids of sets and load lines
    call id_map_init(node_map, model%node_id)
    associate (ls => model%loads)
      allocate(ls%amps(deck%n_amplitudes))
      do k = 1, deck%n_amplitudes
        associate (a => deck%amplitudes(k))
          ls%amps(k)%name = a%name
          ls%amps(k)%kind = AMP_TABULAR
          if (a%definition == AMP_DEF_SMOOTH_STEP) ls%amps(k)%kind = AMP_SMOOTH_STEP
          ls%amps(k)%t = a%t
          ls%amps(k)%a = a%a
        end associate
      end do
    end associate
    call build_motion(deck, model, node_map)
    call build_nodal(deck, model, node_map)
    call build_pressure(deck, model)
  end subroutine build_loads

  !> Index of amplitude `name` in model%loads%amps (0 for '').
  integer function amp_index(model, name) result(k)
    type(model_t), intent(in) :: model
    character(len=*), intent(in) :: name
    k = 0
    if (len_trim(name) == 0) return
    do k = 1, size(model%loads%amps)
      if (model%loads%amps(k)%name == name) return
    end do
    k = 0
  end function amp_index

  !> The prescribed-motion dofs: those whose last *BOUNDARY line has AMPLITUDE= or
  !! TYPE=VELOCITY, in node order.
  subroutine build_motion(deck, model, node_map)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    type(id_map_t), intent(in) :: node_map
    integer, allocatable :: last(:,:)
    logical, allocatable :: mask(:)
    integer :: k, d, i, n, ka
    logical :: refused
    allocate(last(model%ndm, model%nn), source=0)
    allocate(mask(model%nn))
    refused = .false.
    do k = 1, deck%n_boundaries
      associate (b => deck%boundaries(k))
        mask = .false.
        call resolve_node_set(deck, model, node_map, b%target, b%where, mask, 0)
        do d = max(b%first_dof, 1), min(b%last_dof, model%ndm)
          where (mask) last(d, :) = k
        end do
        if (.not. varying(k) .or. refused) cycle
        if (any(model%mass_kind == MASS_CONSISTENT)) then
          call input_error(b%card_where, '*BOUNDARY: a time-varying boundary (AMPLITUDE= '// &
              'or TYPE=VELOCITY) needs a lumped mass, but the model has consistent-mass '// &
              'elements (*MASS, TYPE=CONSISTENT): the acceleration of the prescribed dofs '// &
              'would drive the free ones through the mass coupling; use TYPE=HRZ, ROW SUM '// &
              'or ALPHA for the elements around these nodes')
          refused = .true.
        end if
      end associate
    end do
    n = 0
    do i = 1, model%nn
      do d = 1, model%ndm
        if (last(d, i) > 0) then
          if (varying(last(d, i))) n = n + 1
        end if
      end do
    end do
    associate (ls => model%loads)
      ls%nmotion = n
      allocate(ls%m_node(n), ls%m_dof(n), ls%m_kind(n), ls%m_amp(n), ls%m_value(n))
      n = 0
      do i = 1, model%nn
        do d = 1, model%ndm
          k = last(d, i)
          if (k == 0) cycle
          if (.not. varying(k)) cycle
          n = n + 1
          associate (b => deck%boundaries(k))
            ka = amp_index(model, b%amplitude)
            ls%m_node(n) = i
            ls%m_dof(n) = d
            ls%m_amp(n) = ka
            ls%m_value(n) = b%value
            if (b%kind == BC_VELOCITY) then
              ls%m_kind(n) = MOTION_VELOCITY
              model%u_fixed(d, i) = 0.0_dp
            else
              ls%m_kind(n) = MOTION_DISPLACEMENT
              model%u_fixed(d, i) = b%value*amp_factor(ls%amps, ka, 0.0_dp)
            end if
          end associate
        end do
      end do
    end associate

  contains

    !> Whether *BOUNDARY record kb prescribes motion (AMPLITUDE= or TYPE=VELOCITY).
    logical function varying(kb)
      integer, intent(in) :: kb
      varying = len_trim(deck%boundaries(kb)%amplitude) > 0 .or. &
          deck%boundaries(kb)%kind == BC_VELOCITY
    end function varying

  end subroutine build_motion

  !> *CLOAD lines and *DLOAD, GRAV lines as nodal loads.
  subroutine build_nodal(deck, model, node_map)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    type(id_map_t), intent(in) :: node_map
    logical, allocatable :: mask(:), emask(:)
    integer :: k, n, i
    real(dp) :: dir(3)
    associate (ls => model%loads)
      allocate(ls%nodal(deck%n_cloads + deck%n_dloads))
      n = 0
      allocate(mask(model%nn), emask(model%nel))
      do k = 1, deck%n_cloads
        associate (c => deck%cloads(k))
          mask = .false.
          call resolve_node_set(deck, model, node_map, c%target, c%where, mask, 0)
          if (.not. any(mask)) call warning(c%where, '*CLOAD: set '//trim(c%target)// &
              ' holds no nodes')
          n = n + 1
          ls%nodal(n)%amp = amp_index(model, c%amplitude)
          ls%nodal(n)%dof = c%dof
          ls%nodal(n)%value = c%value
          ls%nodal(n)%nodes = pack([(i, i = 1, model%nn)], mask)
        end associate
      end do
      do k = 1, deck%n_dloads
        associate (l => deck%dloads(k))
          if (l%kind == DLOAD_PRESSURE) cycle
          if (len_trim(l%target) == 0) then
            emask = .true.
          else
            emask = .false.
            call resolve_elem_set(deck, model, l%target, l%where, emask, 0)
          end if
          n = n + 1
          dir = 0.0_dp
          dir(1:model%ndm) = l%dir(1:model%ndm)/norm2(l%dir(1:model%ndm))
          ls%nodal(n)%amp = amp_index(model, l%amplitude)
          ls%nodal(n)%g = l%value*dir
          ls%nodal(n)%elems = pack([(i, i = 1, model%nel)], emask)
        end associate
      end do
      ls%nnodal = n
      ls%nodal = ls%nodal(1:n)
    end associate
  end subroutine build_nodal

  !> *DLOAD, P lines: the surface (as for contact) with the pressure and amplitude.
  subroutine build_pressure(deck, model)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    integer :: k, n
    n = count(deck%dloads(1:deck%n_dloads)%kind == DLOAD_PRESSURE)
    associate (ls => model%loads)
      allocate(ls%press(n))
      ls%npress = n
      n = 0
      do k = 1, deck%n_dloads
        associate (l => deck%dloads(k))
          if (l%kind /= DLOAD_PRESSURE) cycle
          n = n + 1
          if (model%ndm == 3) then
            call named_element_faces(deck, model, l%target, l%where, '*DLOAD, P', &
                ls%press(n)%nface, ls%press(n)%face_conn, ls%press(n)%face_nfn)
          else
            call build_named_surface(deck, model, l%target, l%where, '*DLOAD, P', &
                ls%press(n)%surf)
          end if
          ls%press(n)%p = l%value
          ls%press(n)%amp = amp_index(model, l%amplitude)
        end associate
      end do
    end associate
  end subroutine build_pressure
end module ictus_app_build_loads
