!> Sweeps of several lumped-mass steps over K (ictus_solver_sweep): the schedule does every
!! (stage, row) once and only after the stencil's previous stage, and the sweep gives the bits
!! of the same number of single fused steps, undamped and with mass-proportional damping (then
!! also the terms of the damping power of every stage, and the single damped step those of the
!! unfused step written out here).
program test_sweep
  use ictus_core_kinds, only: dp
  use ictus_solver_sparse, only: graph_t, bsr_t, graph_from_elements, bsr_init, &
      bsr_add_element, fused_lumped_step, fused_lumped_rows, bsr_matvec
  use ictus_solver_sweep, only: sweep_t, sweep_plan, sweep_zone_stage, sweep_rows
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  call t%start("solver/sweep")
  call test_schedule(t, nstage=6, window=8, ghosts=.false., contact=.false.)
  call test_schedule(t, nstage=6, window=8, ghosts=.false., contact=.true.)
  call test_schedule(t, nstage=4, window=16, ghosts=.true., contact=.true.)
  call test_schedule(t, nstage=8, window=1000, ghosts=.true., contact=.false.)
  call test_bits(t, nstage=6, window=8, damped=.false.)
  call test_bits(t, nstage=5, window=12, damped=.false.)
  call test_bits(t, nstage=2, window=1000, damped=.false.)
  call test_bits(t, nstage=6, window=8, damped=.true.)
  call test_bits(t, nstage=5, window=12, damped=.true.)
  call test_bits(t, nstage=2, window=1000, damped=.true.)
  call t%finish()
contains

  !> A grid of nx x ny Q4 elements, nodes numbered line by line; with `ghosts` the nodes right
  !! of the middle come last and are ghosts (no rows). Node coordinates in x.
  subroutine grid(nx, ny, ghosts, g, x, nrows)
    integer, intent(in) :: nx, ny
    logical, intent(in) :: ghosts
    type(graph_t), intent(out) :: g
    real(dp), allocatable, intent(out) :: x(:,:)
    integer, intent(out) :: nrows
    integer, allocatable :: conn(:,:), nen(:), num(:)
    integer :: i, j, e, nn, k
    nn = (nx + 1)*(ny + 1)
    allocate(num(nn), x(2, nn), conn(4, nx*ny), nen(nx*ny))
    ! owned nodes (i <= nx/2 with ghosts) first, then the others, each line by line
    k = 0
    do j = 0, ny
      do i = 0, nx
        if (.not. ghosts .or. i <= nx/2) then
          k = k + 1
          num(node_of(nx, i, j)) = k
        end if
      end do
    end do
    nrows = k
    do j = 0, ny
      do i = 0, nx
        if (ghosts .and. i > nx/2) then
          k = k + 1
          num(node_of(nx, i, j)) = k
        end if
        x(:, num(node_of(nx, i, j))) = [real(i, dp), real(j, dp)]
      end do
    end do
    e = 0
    do j = 0, ny - 1
      do i = 0, nx - 1
        e = e + 1
        conn(:, e) = num([node_of(nx, i, j), node_of(nx, i + 1, j), node_of(nx, i + 1, j + 1), &
            node_of(nx, i, j + 1)])
      end do
    end do
    nen = 4
    call graph_from_elements(nrows, nn, nx*ny, 4, nen, conn, [(i, i = 1, nn)], g)
  end subroutine grid

  !> Grid node (i, j) in line-by-line numbering.
  pure integer function node_of(nx, i, j)
    integer, intent(in) :: nx, i, j
    node_of = j*(nx + 1) + i + 1
  end function node_of

  !> Replays the schedule (zones stage by stage, then slot by slot) and checks that every
  !! (stage, row) is done exactly once, after the previous stage of every row of its stencil
  !! (which also means no row still needs the values it overwrites: the stencil is symmetric),
  !! and that rows with ghost columns and contact rows are zone rows at every stage.
  subroutine test_schedule(t, nstage, window, ghosts, contact)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: nstage, window
    logical, intent(in) :: ghosts, contact
    type(graph_t) :: g
    type(sweep_t) :: sw
    real(dp), allocatable :: x(:,:)
    logical, allocatable :: sync(:)
    integer, allocatable :: stage_done(:)
    integer :: n, k, r, i, tt, bad_order, bad_count, bad_zone
    character(len=80) :: tag
    call grid(30, 20, ghosts, g, x, n)
    allocate(sync(n), source=.false.)
    ! a "contact surface": the top line of nodes, and a ring of nodes around (5, 5), whose
    ! centre is a sweep row at the last stage with its whole stencil done in the zones
    if (contact) sync = x(2, 1:n) == 20.0_dp .or. &
        max(abs(x(1, 1:n) - 5.0_dp), abs(x(2, 1:n) - 5.0_dp)) == 1.0_dp
    call sweep_plan(sw, g, nstage, window, x(:, 1:n), sync)
    write(tag, '(a,i0,a,i0,a,l1,a,l1)') 'nstage ', nstage, ', window ', window, ', ghosts ', &
        ghosts, ', contact ', contact
    allocate(stage_done(n), source=0)
    bad_order = 0
    bad_count = 0
    do k = 1, nstage
      do r = sw%zone_ptr(k), sw%zone_ptr(k + 1) - 1
        do i = sw%zone_lo(r), sw%zone_lo(r) + sw%zone_len(r) - 1
          call visit(g, n, k, i, stage_done, bad_order, bad_count)
        end do
      end do
    end do
    do tt = 1, sw%nslot
      do k = 1, nstage
        do r = sw%run_ptr(tt, k), sw%run_ptr(tt + 1, k) - 1
          do i = sw%run_lo(r), sw%run_lo(r) + sw%run_len(r) - 1
            call visit(g, n, k, i, stage_done, bad_order, bad_count)
          end do
        end do
      end do
    end do
    bad_count = bad_count + count(stage_done /= nstage)
    call t%equal_int(bad_count, 0, trim(tag)//': every row done at every stage')
    call t%equal_int(bad_order, 0, trim(tag)//': every stage after its stencil''s previous one')
    ! zone membership of the rows that talk to the outside
    bad_zone = 0
    do i = 1, n
      if (sync(i) .or. any(g%col(g%row_ptr(i):g%row_ptr(i + 1) - 1) > n)) then
        do k = 1, nstage
          if (.not. in_zone(sw, k, i)) bad_zone = bad_zone + 1
        end do
      end if
    end do
    call t%equal_int(bad_zone, 0, trim(tag)//': ghost-column and contact rows step in the zones')
    call t%true(sw%zone_rows(1) < n .or. n < 100, trim(tag)//': the sweep has rows of its own')
  end subroutine test_schedule

  !> Stage k of row i in the replay: counts a stage out of turn, or a neighbour (owned) that
  !! has not done stage k-1 or has already done k + 1 (overwriting what row i reads).
  subroutine visit(g, n, k, i, stage_done, bad_order, bad_count)
    type(graph_t), intent(in) :: g
    integer, intent(in) :: n, k, i
    integer, intent(inout) :: stage_done(:), bad_order, bad_count
    integer :: c
    if (stage_done(i) /= k - 1) then
      bad_count = bad_count + 1
      return
    end if
    do c = g%row_ptr(i), g%row_ptr(i + 1) - 1
      if (g%col(c) > n) cycle
      if (stage_done(g%col(c)) < k - 1 .or. stage_done(g%col(c)) > k) bad_order = bad_order + 1
    end do
    stage_done(i) = k
  end subroutine visit

  !> Whether row i is a zone row of stage k.
  logical function in_zone(sw, k, i)
    type(sweep_t), intent(in) :: sw
    integer, intent(in) :: k, i
    integer :: r
    in_zone = .false.
    do r = sw%zone_ptr(k), sw%zone_ptr(k + 1) - 1
      if (i >= sw%zone_lo(r) .and. i < sw%zone_lo(r) + sw%zone_len(r)) in_zone = .true.
    end do
  end function in_zone

  !> nstage fused single steps against one sweep (with contact rows stepped in the zones) on a
  !! pseudo-random symmetric block matrix: the same bits for u and v. With `damped`, a
  !! pseudo-random damping coefficient per node (zero on some): the single steps are checked
  !! against the unfused damped step written out, and the sweep against the single steps,
  !! the power terms of each stage included.
  subroutine test_bits(t, nstage, window, damped)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: nstage, window
    logical, intent(in) :: damped
    type(graph_t) :: g
    type(bsr_t) :: k
    type(sweep_t) :: sw
    real(dp), allocatable :: x(:,:), u(:,:), v(:,:), un(:,:), a(:,:), b(:,:), w(:,:), &
        inv_m(:,:), alpha(:), m_pos(:), pw(:,:,:), pw_ref(:,:,:), f(:,:), acc(:,:), &
        vo(:,:), vm(:,:)
    logical, allocatable :: sync(:)
    logical :: unfused_same
    real(dp) :: ke(8, 8), dt, h
    integer :: n, e, i, j, st, nx, ny, c
    character(len=60) :: tag
    nx = 40
    ny = 24
    call grid(nx, ny, .false., g, x, n)
    call bsr_init(k, g)
    do j = 0, ny - 1
      do i = 0, nx - 1
        e = j*nx + i + 1
        do c = 1, 8
          do st = 1, 8
            ke(st, c) = sin(real(st + 3*c + 7*e, dp)) + sin(real(c + 3*st + 7*e, dp))
          end do
          ke(c, c) = ke(c, c) + 8.0_dp
        end do
        call bsr_add_element(k, 4, [j*(nx + 1) + i + 1, j*(nx + 1) + i + 2, &
            (j + 1)*(nx + 1) + i + 2, (j + 1)*(nx + 1) + i + 1], ke)
      end do
    end do
    allocate(u(2, n), v(2, n), un(2, n), inv_m(2, n))
    do i = 1, n
      u(:, i) = [1.0e-3_dp*sin(1.3_dp*i), 1.0e-3_dp*cos(0.7_dp*i)]
      v(:, i) = [cos(2.1_dp*i), sin(0.3_dp*i)]
      inv_m(:, i) = 1.0_dp/(1.0_dp + 0.5_dp*abs(sin(real(i, dp))))
    end do
    inv_m(:, 1:nx + 1) = 0.0_dp
    allocate(alpha(n), m_pos(n), pw(2, n, nstage), pw_ref(2, n, nstage))
    do i = 1, n
      alpha(i) = max(0.0_dp, 3.0_dp*sin(0.37_dp*i))
      m_pos(i) = 1.0_dp/inv_m(1, max(i, nx + 2))
    end do
    dt = 0.05_dp
    a = u
    b = 0.0_dp*u
    w = v
    ! reference: nstage single fused steps; damped, each checked against the unfused step
    ! (K u, a = f/m, the damped update, the mean velocity and the power terms, as
    ! ictus_solver_explicit writes them)
    unfused_same = .true.
    allocate(f(2, n), acc(2, n), vo(2, n), vm(2, n))
    do st = 1, nstage
      if (damped) then
        call bsr_matvec(n, g%row_ptr, g%col, k%val, u, f)
        f = -f
        acc = f*inv_m
        vo = v
        do i = 1, n
          h = 0.5_dp*alpha(i)*dt
          vo(:, i) = ((1.0_dp - h)*v(:, i) + dt*acc(:, i))/(1.0_dp + h)
        end do
        vm = 0.5_dp*(v + vo)
        do i = 1, n
          f(:, i) = -alpha(i)*m_pos(i)*vm(:, i)
        end do
        call fused_lumped_rows(1, n, g%row_ptr, g%col, k%val, inv_m, dt, u, v, un, alpha, &
            m_pos, pw_ref(:, :, st))
        unfused_same = unfused_same .and. all(v == vo) .and. all(un == u + dt*vo) .and. &
            all(pw_ref(:, :, st) == f*vm)
      else
        call fused_lumped_step(n, g%row_ptr, g%col, k%val, inv_m, dt, u, v, un)
      end if
      u = un
    end do
    if (damped) call t%true(unfused_same, 'damped single steps: the bits of the unfused step')
    ! the sweep, with a "contact line" in the middle stepped in the zones
    allocate(sync(n))
    sync = x(2, 1:n) == real(ny/2, dp) .or. &
        max(abs(x(1, 1:n) - 5.0_dp), abs(x(2, 1:n) - 5.0_dp)) == 1.0_dp
    call sweep_plan(sw, g, nstage, window, x, sync)
    pw = huge(1.0_dp)
    do st = 1, nstage
      if (damped .and. mod(st, 2) == 1) then
        call sweep_zone_stage(sw, st, g%row_ptr, g%col, k%val, inv_m, dt, a, w, b, alpha, &
            m_pos, pw)
      else if (damped) then
        call sweep_zone_stage(sw, st, g%row_ptr, g%col, k%val, inv_m, dt, b, w, a, alpha, &
            m_pos, pw)
      else if (mod(st, 2) == 1) then
        call sweep_zone_stage(sw, st, g%row_ptr, g%col, k%val, inv_m, dt, a, w, b)
      else
        call sweep_zone_stage(sw, st, g%row_ptr, g%col, k%val, inv_m, dt, b, w, a)
      end if
    end do
    if (damped) then
      call sweep_rows(sw, g%row_ptr, g%col, k%val, inv_m, dt, a, b, w, alpha, m_pos, pw)
    else
      call sweep_rows(sw, g%row_ptr, g%col, k%val, inv_m, dt, a, b, w)
    end if
    write(tag, '(a,i0,a,i0,a)') 'nstage ', nstage, ', window ', window, &
        trim(merge(', damped', '        ', damped))
    if (damped) call t%true(all(pw == pw_ref), trim(tag)//': the power terms of every stage '// &
        'have the bits of single steps')
    if (mod(nstage, 2) == 0) then
      call t%true(all(a == u), trim(tag)//': u has the bits of single steps')
    else
      call t%true(all(b == u), trim(tag)//': u has the bits of single steps')
    end if
    call t%true(all(w == v), trim(tag)//': v has the bits of single steps')
    call t%true(sw%nslot > 1 .or. window >= 1000, trim(tag)//': more than one slot')
  end subroutine test_bits
end program test_sweep
