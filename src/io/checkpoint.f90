!> Checkpoints for restarting a run: the state of the time loop in global numbering, so a run
!! can continue on any number of ranks and produce the same bits as an uninterrupted one.
!!
!! A checkpoint is written to `<path>.tmp` and renamed over `<path>` only when complete, so a
!! run killed while writing leaves the previous checkpoint intact. It stores the processed deck
!! (the record of the results file with the digest of its bulk data, `ictus_io_deck_record`),
!! which a restart compares with its own, so a checkpoint cannot be continued with another deck.
module ictus_io_checkpoint
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: str
  use ictus_parallel_env, only: env_is_root, barrier, bcast
  use ictus_contact_contact, only: contact_t, contact_pair_t, pair_resultant
  use ictus_solver_domain, only: domain_t, domain_owns
  use ictus_solver_explicit, only: state_t
  use ictus_solver_contact_step, only: contact_step_t
  use ictus_io_hdf5_util, only: hid_t, h5u_create_file, h5u_close_file, h5u_group, &
      h5u_close_group, h5u_attr_string, h5u_attr_int, h5u_attr_real, h5u_write, &
      h5u_write_rows, h5u_open_file, h5u_read, h5u_read_attr_real, h5u_read_attr_int, &
      h5u_read_attr_string
  implicit none
  private
  public :: checkpoint_t, checkpoint_write, checkpoint_read

  !> The scalars of a checkpoint besides the state arrays.
  type :: checkpoint_t
    !> Loop index at which the run continues (the step after the checkpoint).
    integer :: next_step = 0
    !> Energy at the start, history records and field snapshots written so far.
    real(dp) :: e0 = 0.0_dp
    integer :: n_history = 0
    integer, allocatable :: field_steps(:)
    real(dp), allocatable :: field_times(:)
    !> Contact: pairs that have been active, projection failures so far.
    logical, allocatable :: was_active(:)
    integer :: failures = 0
  end type checkpoint_t

  interface
    function c_rename(old, new) bind(c, name='rename') result(status)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: old(*), new(*)
      integer(c_int) :: status
    end function c_rename
  end interface

contains

  !> Writes the checkpoint `path` (collective).
  subroutine checkpoint_write(path, deck_text, dom, s, cs, contact, ck)
    character(len=*), intent(in) :: path, deck_text
    type(domain_t), intent(in) :: dom
    type(state_t), intent(in) :: s
    type(contact_step_t), intent(in) :: cs
    type(contact_t), intent(in) :: contact
    type(checkpoint_t), intent(in) :: ck
    integer(hid_t) :: f, g
    integer :: k, st
    integer, allocatable :: gid(:)
    ! Workaround: gfortran 12 -Wuninitialized false positive on reallocation at assignment
    allocate(gid(dom%nowned))
    gid = dom%halo%gid(1:dom%nowned)
    call h5u_create_file(path//'.tmp', f)
    call h5u_attr_string(f, 'program', 'ictus checkpoint')
    call h5u_attr_string(f, 'deck', deck_text)
    call h5u_attr_int(f, 'next_step', ck%next_step)
    call h5u_attr_int(f, 'step', s%step)
    call h5u_attr_real(f, 'time', s%t)
    call h5u_attr_real(f, 'dt', s%dt)
    call h5u_attr_real(f, 'dt_prev', s%dt_prev)
    call h5u_attr_real(f, 'w_acc', s%w_acc)
    call h5u_attr_real(f, 'pw_prev', s%pw_prev)
    call h5u_attr_real(f, 'e_contact', s%e_contact)
    call h5u_attr_real(f, 'e0', ck%e0)
    call h5u_attr_int(f, 'n_history', ck%n_history)
    call h5u_attr_int(f, 'failures', ck%failures)
    call h5u_attr_int(f, 'nodes', dom%nn_global)
    call h5u_write(f, 'field_steps', ck%field_steps)
    call h5u_write(f, 'field_times', ck%field_times)
    call h5u_write_rows(f, 'u', s%u(:, 1:dom%nowned), gid, dom%nn_global)
    call h5u_write_rows(f, 'v', s%v(:, 1:dom%nowned), gid, dom%nn_global)
    call h5u_write_rows(f, 'a', s%a(:, 1:dom%nowned), gid, dom%nn_global)
    if (allocated(cs%ac)) call h5u_write_rows(f, 'a_contact', cs%ac(:, 1:dom%nowned), gid, &
        dom%nn_global)
    if (size(s%hist) > 0) call write_history(f, dom, s)
    call h5u_attr_int(f, 'npairs', contact%npairs)
    do k = 1, contact%npairs
      associate (p => contact%pairs(k))
        call h5u_group(f, 'pair'//str(k), g)
        call h5u_attr_int(g, 'was_active', merge(1, 0, ck%was_active(k)))
        call h5u_attr_int(g, 'outside_points', p%outside_points)
        call h5u_attr_int(g, 'outside_total', int(min(p%outside_total, &
            int(huge(1), kind(p%outside_total)))))
        call h5u_write(g, 'values', [pair_resultant(contact, k, 1), &
            pair_resultant(contact, k, 2), p%max_pressure, p%max_penetration, &
            real(p%active_points, dp), p%energy])
        if (p%npoints > 0) then
          call h5u_write(g, 'x', p%x(:, 1:p%npoints))
          call h5u_write(g, 'pressure', p%pressure(1:p%npoints))
        end if
        if (p%fr%on) call write_friction(g, p)
        if (size(p%inside) > 0) call h5u_write(g, 'inside', p%inside)
        call h5u_close_group(g)
      end associate
    end do
    if (contact%friction) then
      ! the committed coordinates of the friction increments (replicated on every rank)
      call h5u_attr_real(f, 'e_friction', s%e_friction)
      call h5u_attr_int(f, 'friction_started', merge(1, 0, contact%started))
      if (contact%started) call h5u_write(f, 'contact_x_prev', contact%x_prev)
    end if
    call h5u_close_file(f)
    call barrier()
    if (env_is_root()) st = c_rename(path//'.tmp'//c_null_char, path//c_null_char)
  end subroutine checkpoint_write

  !> Reads the checkpoint `path` into the state (which state_init has set up for this
  !! partition). `msg` is empty on success, otherwise says what is wrong.
  subroutine checkpoint_read(path, deck_text, dom, s, cs, contact, ck, msg)
    character(len=*), intent(in) :: path, deck_text
    type(domain_t), intent(in) :: dom
    type(state_t), intent(inout) :: s
    type(contact_step_t), intent(inout) :: cs
    type(contact_t), intent(inout) :: contact
    type(checkpoint_t), intent(out) :: ck
    character(len=:), allocatable, intent(out) :: msg
    integer(hid_t) :: f, g
    logical :: ok
    real(dp), allocatable :: x(:,:), vals(:)
    integer :: k, nf, nn
    msg = ''
    call h5u_open_file(path, .false., f, ok)
    if (.not. ok) then
      msg = 'cannot open the checkpoint '//path
      return
    end if
    if (h5u_read_attr_string(f, 'program') /= 'ictus checkpoint') then
      msg = path//' is not an ictus checkpoint'
    else if (h5u_read_attr_string(f, 'deck') /= deck_text) then
      msg = 'the checkpoint '//path//' was written for a different deck (the processed '// &
          'decks differ)'
    else if (h5u_read_attr_int(f, 'nodes') /= dom%nn_global) then
      msg = 'the checkpoint '//path//' has a different number of nodes'
    else if (h5u_read_attr_int(f, 'npairs') /= contact%npairs) then
      msg = 'the checkpoint '//path//' has a different number of contact pairs'
    end if
    if (len(msg) > 0) then
      call h5u_close_file(f)
      return
    end if
    nn = dom%nn_global
    ck%next_step = h5u_read_attr_int(f, 'next_step')
    s%step = h5u_read_attr_int(f, 'step')
    s%t = h5u_read_attr_real(f, 'time')
    s%dt = h5u_read_attr_real(f, 'dt')
    s%dt_prev = h5u_read_attr_real(f, 'dt_prev')
    s%w_acc = h5u_read_attr_real(f, 'w_acc')
    s%pw_prev = h5u_read_attr_real(f, 'pw_prev')
    s%e_contact = h5u_read_attr_real(f, 'e_contact')
    ck%e0 = h5u_read_attr_real(f, 'e0')
    ck%n_history = h5u_read_attr_int(f, 'n_history')
    ck%failures = h5u_read_attr_int(f, 'failures')
    nf = field_count(f)
    allocate(ck%field_steps(nf), ck%field_times(nf))
    call h5u_read(f, 'field_steps', ck%field_steps)
    call h5u_read(f, 'field_times', ck%field_times)
    allocate(x(size(s%u, 1), nn))
    call h5u_read(f, 'u', x)
    s%u = x(:, dom%halo%gid)
    call h5u_read(f, 'v', x)
    s%v = x(:, dom%halo%gid)
    call h5u_read(f, 'a', x)
    s%a = x(:, dom%halo%gid)
    if (allocated(cs%ac)) then
      call h5u_read(f, 'a_contact', x)
      cs%ac = x(:, dom%halo%gid)
    end if
    if (size(s%hist) > 0) call read_history(f, dom, s)
    allocate(ck%was_active(contact%npairs))
    allocate(vals(10))
    do k = 1, contact%npairs
      associate (p => contact%pairs(k))
        call h5u_group(f, 'pair'//str(k), g)
        ck%was_active(k) = h5u_read_attr_int(g, 'was_active') == 1
        p%outside_points = h5u_read_attr_int(g, 'outside_points')
        p%outside_total = h5u_read_attr_int(g, 'outside_total')
        call h5u_read(g, 'values', vals)
        if (contact%ndm == 3) then
          contact%d3%pairs(k)%force_first = vals(1:3)
          contact%d3%pairs(k)%force_second = vals(4:6)
        else
          p%force_first = vals(1:2)
          p%force_second = vals(4:5)
        end if
        p%max_pressure = vals(7)
        p%max_penetration = vals(8)
        p%active_points = nint(vals(9))
        p%energy = vals(10)
        if (p%npoints > 0) then
          call h5u_read(g, 'x', p%x(:, 1:p%npoints))
          call h5u_read(g, 'pressure', p%pressure(1:p%npoints))
        end if
        if (p%fr%on) call read_friction(g, p)
        if (size(p%inside) > 0) call h5u_read(g, 'inside', p%inside)
        call h5u_close_group(g)
      end associate
    end do
    if (contact%friction) then
      s%e_friction = h5u_read_attr_real(f, 'e_friction')
      contact%friction_work = s%e_friction
      contact%started = h5u_read_attr_int(f, 'friction_started') == 1
      if (allocated(contact%x_prev)) deallocate(contact%x_prev)
      if (contact%started) then
        allocate(contact%x_prev(2, nn))
        call h5u_read(f, 'contact_x_prev', contact%x_prev)
      end if
    end if
    call h5u_close_file(f)
  end subroutine checkpoint_read

  !> The friction state of a pair: committed tangential tractions, the frictional work and
  !! the tangential resultant of the last evaluation.
  subroutine write_friction(g, p)
    integer(hid_t), intent(in) :: g
    type(contact_pair_t), intent(in) :: p
    call h5u_write(g, 'friction_traction', p%fr%t_old)
    call h5u_write(g, 'friction_values', [p%fr%work, p%fr%force])
  end subroutine write_friction

  !> Reads what write_friction wrote.
  subroutine read_friction(g, p)
    integer(hid_t), intent(in) :: g
    type(contact_pair_t), intent(inout) :: p
    real(dp) :: vals(3)
    call h5u_read(g, 'friction_traction', p%fr%t_old)
    p%fr%t_new = p%fr%t_old
    call h5u_read(g, 'friction_values', vals)
    p%fr%work = vals(1)
    p%fr%force = vals(2:3)
    p%fr%dwork = 0.0_dp
  end subroutine read_friction

  !> The quadrature-point history of the material laws, one row per element (global element
  !! order), written by the rank that owns the element (domain_owns).
  subroutine write_history(f, dom, s)
    integer(hid_t), intent(in) :: f
    type(domain_t), intent(in) :: dom
    type(state_t), intent(in) :: s
    real(dp), allocatable :: rows(:,:)
    integer, allocatable :: gid(:)
    integer :: k, j, m, nown
    m = size(s%hist, 1)*size(s%hist, 2)
    nown = count([(domain_owns(dom, k), k = 1, dom%nelem)])
    allocate(rows(m, nown), gid(nown))
    j = 0
    do k = 1, dom%nelem
      if (.not. domain_owns(dom, k)) cycle
      j = j + 1
      rows(:, j) = reshape(s%hist(:, :, k), [m])
      gid(j) = dom%elem(k)
    end do
    call h5u_write_rows(f, 'history', rows, gid, size(dom%part))
  end subroutine write_history

  !> Reads the history of every element of this rank (any partition) from write_history's
  !! rows.
  subroutine read_history(f, dom, s)
    integer(hid_t), intent(in) :: f
    type(domain_t), intent(in) :: dom
    type(state_t), intent(inout) :: s
    real(dp), allocatable :: rows(:,:)
    integer :: k
    allocate(rows(size(s%hist, 1)*size(s%hist, 2), size(dom%part)))
    call h5u_read(f, 'history', rows)
    do k = 1, dom%nelem
      s%hist(:, :, k) = reshape(rows(:, dom%elem(k)), [size(s%hist, 1), size(s%hist, 2)])
    end do
  end subroutine read_history

  !> Number of field snapshots recorded in the checkpoint.
  integer function field_count(f)
    use ictus_io_hdf5_util, only: h5u_extent
    integer(hid_t), intent(in) :: f
    integer :: dims(2)
    call h5u_extent(f, 'field_steps', dims)
    field_count = dims(1)
  end function field_count
end module ictus_io_checkpoint
