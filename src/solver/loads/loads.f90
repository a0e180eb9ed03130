!> The loads and the prescribed motion of one rank during the run (doc/theory.md §4a):
!!
!!     f_ext(t) = sum_g a_g(t) F_g + sum_s a_s(t) f_p,s(x)
!!
!! with F_g the constant nodal vectors of the *CLOAD and GRAV lines that share amplitude g
!! (owned rows; a GRAV line adds rho g (gx, gy) int N_A dV, the row sums of the element's
!! consistent mass, from the rank's elements in global order as the assembly does) and f_p,s
!! the pressure of *DLOAD, P line s (ictus_solver_pressure). Prescribed motion (*BOUNDARY with
!! AMPLITUDE= or TYPE=VELOCITY) sets the half-step velocity of its dofs:
!!
!!     v_{n+1/2} = (u_p(t_{n+1}) - u_n)/dt     (TYPE=DISPLACEMENT; then u_{n+1} = u_p(t_{n+1}))
!!     v_{n+1/2} = v_p(t_{n+1/2})              (TYPE=VELOCITY)
!!
!! Every owned row is summed in the same order on any number of ranks.
module ictus_solver_loads
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: elem_shape_t, TASK_MASS
  use ictus_elements_library, only: element_routine, element_out_t
  use ictus_solver_amplitude, only: amplitude_t, amp_factor
  use ictus_solver_load_spec, only: load_spec_active, MOTION_DISPLACEMENT
  use ictus_solver_pressure, only: pressure_rt_t, pressure_setup, pressure_add
  use ictus_solver_face_pressure, only: face_pressure_t, face_pressure_setup, face_pressure_add
  use ictus_solver_model, only: model_t
  use ictus_solver_domain, only: domain_t
  use ictus_solver_assemble, only: element_shape, shape_cache_t
  implicit none
  private
  public :: loads_t, loads_init, loads_force, motion_start, motion_velocity, &
      motion_set_displacement

  !> The rank's loads: constant vectors per amplitude, pressures, prescribed dofs.
  type :: loads_t
    !> Any load or prescribed motion on any rank.
    logical :: active = .false.
    integer :: nn = 0
    type(amplitude_t), allocatable :: amps(:)
    !> Constant nodal vectors F_g (ndm, nn, ngroup) and the amplitude of each (ngroup).
    integer :: ngroup = 0
    integer, allocatable :: group_amp(:)
    real(dp), allocatable :: fg(:,:,:)
    !> Pressure loads, and whether they follow the deformed surface (NLGEOM).
    type(pressure_rt_t), allocatable :: press(:)
    !> 3D: the pressure loads on faces of hexahedra (press is then empty).
    type(face_pressure_t), allocatable :: fpress(:)
    logical :: follow = .false.
    !> Local reference coordinates (ndm, nlocal).
    real(dp), allocatable :: x0(:,:)
    !> Prescribed dofs of owned nodes: local node, dof, MOTION_* kind, amplitude, value.
    integer :: nmot = 0
    integer, allocatable :: mot_node(:), mot_dof(:), mot_kind(:), mot_amp(:)
    real(dp), allocatable :: mot_value(:)
  end type loads_t

contains

  !> The rank's loads from the model's load description (model%loads).
  subroutine loads_init(ld, model, dom)
    type(loads_t), intent(out) :: ld
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    integer :: k, j, ig, i
    integer, allocatable :: gamp(:)
    associate (ls => model%loads)
      ld%active = load_spec_active(ls)
      ld%nn = dom%nowned
      if (.not. ld%active) return
      ld%amps = ls%amps
      ! one constant vector per amplitude used by a nodal load, in order of first use
      allocate(gamp(0))
      do k = 1, ls%nnodal
        if (findloc(gamp, ls%nodal(k)%amp, dim=1) == 0) gamp = [gamp, ls%nodal(k)%amp]
      end do
      ld%ngroup = size(gamp)
      ld%group_amp = gamp
      allocate(ld%fg(model%ndm, dom%nowned, ld%ngroup), source=0.0_dp)
      do k = 1, ls%nnodal
        ig = findloc(gamp, ls%nodal(k)%amp, dim=1)
        associate (nl => ls%nodal(k))
          if (allocated(nl%nodes)) then
            do j = 1, size(nl%nodes)
              i = dom%g2l(nl%nodes(j))
              if (i >= 1 .and. i <= dom%nowned) ld%fg(nl%dof, i, ig) = &
                  ld%fg(nl%dof, i, ig) + nl%value
            end do
          end if
          if (allocated(nl%elems)) call add_gravity(model, dom, nl%elems, nl%g, &
              ld%fg(:, :, ig))
        end associate
      end do
      ld%follow = model%nlgeom
      if (model%ndm == 3) then
        allocate(ld%press(0), ld%fpress(ls%npress))
        do k = 1, ls%npress
          associate (pl => ls%press(k))
            call face_pressure_setup(pl%nface, pl%face_nfn, pl%face_conn, pl%p, pl%amp, &
                dom%g2l, dom%nowned, ld%fpress(k))
          end associate
        end do
      else
        allocate(ld%press(ls%npress), ld%fpress(0))
        do k = 1, ls%npress
          call pressure_setup(ls%press(k)%surf, ls%press(k)%p, ls%press(k)%amp, dom%g2l, &
              dom%nowned, ld%press(k))
        end do
      end if
      ld%x0 = model%x0(:, dom%halo%gid)
      ld%nmot = 0
      do k = 1, ls%nmotion
        i = dom%g2l(ls%m_node(k))
        if (i >= 1 .and. i <= dom%nowned) ld%nmot = ld%nmot + 1
      end do
      allocate(ld%mot_node(ld%nmot), ld%mot_dof(ld%nmot), ld%mot_kind(ld%nmot), &
          ld%mot_amp(ld%nmot), ld%mot_value(ld%nmot))
      j = 0
      do k = 1, ls%nmotion
        i = dom%g2l(ls%m_node(k))
        if (i < 1 .or. i > dom%nowned) cycle
        j = j + 1
        ld%mot_node(j) = i
        ld%mot_dof(j) = ls%m_dof(k)
        ld%mot_kind(j) = ls%m_kind(k)
        ld%mot_amp(j) = ls%m_amp(k)
        ld%mot_value(j) = ls%m_value(k)
      end do
    end associate
  end subroutine loads_init

  !> Adds the body force rho g int N_A dV of the elements `elems` (global indices) to the owned
  !! rows of f (ndm, nowned): the row sums of each element's consistent mass, elements in global
  !! order (the rank's elements that hold an owned node).
  subroutine add_gravity(model, dom, elems, g, f)
    type(model_t), intent(in) :: model
    type(domain_t), intent(in) :: dom
    integer, intent(in) :: elems(:)
    real(dp), intent(in) :: g(:)
    real(dp), intent(inout) :: f(:,:)
    logical, allocatable :: in_set(:)
    type(shape_cache_t) :: cache
    type(elem_shape_t) :: shp
    type(element_out_t) :: mout
    integer :: k, e, a, i, nen
    real(dp) :: row
    allocate(in_set(model%nel), source=.false.)
    in_set(elems) = .true.
    do k = 1, dom%nelem
      e = dom%elem(k)
      if (.not. in_set(e)) cycle
      nen = model%nen(e)
      call element_shape(model, e, model%gauss(:, e), cache, 1, shp)
      call element_routine(TASK_MASS, model%etype(e), shp, model%x0(:, model%conn(1:nen, e)), &
          model%materials(model%mat(e)), mout)
      do a = 1, nen
        i = dom%conn(a, k)
        if (i > dom%nowned) cycle
        row = sum(mout%s(a, 1:nen))
        f(:, i) = f(:, i) + row*g(1:size(f, 1))
      end do
    end do
  end subroutine add_gravity

  !> The external force at time t on the owned rows of f (ndm, nlocal): f = f_ext(t); x0 the
  !! local reference coordinates (ld%x0), u the local displacements (for NLGEOM pressure).
  subroutine loads_force(ld, t, x0, u, f)
    type(loads_t), intent(in) :: ld
    real(dp), intent(in) :: t
    real(dp), intent(in) :: x0(:,:), u(:,:)
    real(dp), intent(inout) :: f(:,:)
    integer :: g, k, nn
    real(dp) :: a
    nn = ld%nn
    f(:, 1:nn) = 0.0_dp
    do g = 1, ld%ngroup
      a = amp_factor(ld%amps, ld%group_amp(g), t)
      f(:, 1:nn) = f(:, 1:nn) + a*ld%fg(:, :, g)
    end do
    do k = 1, size(ld%press)
      a = amp_factor(ld%amps, ld%press(k)%amp, t)
      call pressure_add(ld%press(k), a, x0, u, ld%follow, nn, f)
    end do
    do k = 1, size(ld%fpress)
      a = amp_factor(ld%amps, ld%fpress(k)%amp, t)
      call face_pressure_add(ld%fpress(k), a, x0, u, ld%follow, nn, f)
    end do
  end subroutine loads_force

  !> The start-up half-step velocity v_{-1/2} of the prescribed dofs: (u_p(0) - u_p(-dt))/dt
  !! (TYPE=DISPLACEMENT) or v_p(-dt/2) (TYPE=VELOCITY).
  subroutine motion_start(ld, dt, v)
    type(loads_t), intent(in) :: ld
    real(dp), intent(in) :: dt
    real(dp), intent(inout) :: v(:,:)
    integer :: k
    do k = 1, ld%nmot
      associate (i => ld%mot_node(k), d => ld%mot_dof(k), c => ld%mot_value(k), &
          m => ld%mot_amp(k))
        if (ld%mot_kind(k) == MOTION_DISPLACEMENT) then
          v(d, i) = (c*amp_factor(ld%amps, m, 0.0_dp) - c*amp_factor(ld%amps, m, -dt))/dt
        else
          v(d, i) = c*amp_factor(ld%amps, m, -0.5_dp*dt)
        end if
      end associate
    end do
  end subroutine motion_start

  !> The half-step velocity v_{n+1/2} of the prescribed dofs, from u_n at t_n = t.
  subroutine motion_velocity(ld, t, dt, u, v)
    type(loads_t), intent(in) :: ld
    real(dp), intent(in) :: t, dt
    real(dp), intent(in) :: u(:,:)
    real(dp), intent(inout) :: v(:,:)
    integer :: k
    do k = 1, ld%nmot
      associate (i => ld%mot_node(k), d => ld%mot_dof(k), c => ld%mot_value(k), &
          m => ld%mot_amp(k))
        if (ld%mot_kind(k) == MOTION_DISPLACEMENT) then
          v(d, i) = (c*amp_factor(ld%amps, m, t + dt) - u(d, i))/dt
        else
          v(d, i) = c*amp_factor(ld%amps, m, t + 0.5_dp*dt)
        end if
      end associate
    end do
  end subroutine motion_velocity

  !> u = u_p(t) exactly on the TYPE=DISPLACEMENT dofs (after the update to t).
  subroutine motion_set_displacement(ld, t, u)
    type(loads_t), intent(in) :: ld
    real(dp), intent(in) :: t
    real(dp), intent(inout) :: u(:,:)
    integer :: k
    do k = 1, ld%nmot
      if (ld%mot_kind(k) /= MOTION_DISPLACEMENT) cycle
      u(ld%mot_dof(k), ld%mot_node(k)) = ld%mot_value(k)*amp_factor(ld%amps, ld%mot_amp(k), t)
    end do
  end subroutine motion_set_displacement
end module ictus_solver_loads
