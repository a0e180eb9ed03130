!> Several lumped-mass steps in one sweep over the stiffness (temporal blocking).
!!
!! An undamped lumped-mass step without output is K u, then per node v += dt (-K u)/m and
!! u_new = u + dt v (`fused_lumped_step`): K dominates the bytes, and once it is read from
!! memory its rows could serve more than one step while they are in the cache. A sweep of
!! `nstage` steps runs step 1 ("stage 1") over the rows in slots of consecutive rows, and each
!! later stage k on a row as soon as stage k-1 has finished the row's whole stencil (its
!! columns) — by then the K rows it needs were read a few slots earlier and are still in the L2
!! cache. The slots go strip by strip: the rows are cut into strips across the coordinate
!! along which the numbering runs (the one that changes most between consecutive rows), each
!! an equal share of the rows with about `window` rows per line of the mesh; inside a strip the
!! rows go in increasing number, in slots of window/4 rows. A row's neighbours on the next
!! line of its strip are then reached a few slots later, whatever the mesh size. Rows at the
!! edge of a strip wait for the next strip (their K rows are read from memory again); they are
!! a few per cent of the rows (doc/performance.md §3.7).
!!
!! Stage k reads the displacements of stage k-1 and writes those of stage k into the other of
!! two arrays (odd stages a -> b, even stages b -> a), in place of the values of stage k-2,
!! which no row still to do reads: a row's stage k waits for all its neighbours' stage k-1, and
!! the stencil is symmetric. Every row does exactly the operations of `fused_lumped_step`, in
!! the same order, so the result is bit for bit that of nstage separate steps.
!!
!! Mass-proportional damping changes only the update of each row (`fused_lumped_rows` with
!! the damping arguments). The
!! work of the damping forces needs the power of every step, a global sum over the nodes: each
!! row leaves its terms of stage k in pw(:, row, k), and the caller sums them stage by stage
!! after the sweep, with the reproducible sum a single step uses, so the work has its bits too.
!!
!! Rows that take part in something between two steps — rows with ghost neighbours (the halo
!! exchange of each step) and contact nodes (the contact correction) — form the set R. They
!! and the rows around them are done first, stage by stage ("zones"), with the exchange or
!! correction after each stage; zone Z_nstage = R, Z_k = Z_(k+1) with its neighbours. Stage k of
!! a row outside Z_k then needs nothing from outside this rank, and the sweep does the rest.
module ictus_solver_sweep
  use ictus_core_kinds, only: dp, i8k => i8
  use ictus_solver_sparse, only: graph_t, fused_lumped_rows
  implicit none
  private
  public :: sweep_t, sweep_plan, sweep_zone_stage, sweep_rows, sweep_move, MAX_STAGES

  !> Most stages a sweep can have.
  integer, parameter :: MAX_STAGES = 8

  !> The schedule of one sweep. Runs are consecutive rows [run_lo, run_lo + run_len - 1].
  !! Stage k >= 1 has the runs run_ptr(slot, k) .. run_ptr(slot + 1, k) - 1 in each slot; the
  !! zone of stage k has the runs zone_ptr(k) .. zone_ptr(k + 1) - 1.
  type :: sweep_t
    integer :: nstage = 0
    integer :: nslot = 0
    integer :: n = 0
    !> Half bandwidth of the rows and number of strips the slots were made with.
    integer :: w = 0
    integer :: strip = 0
    integer, allocatable :: run_lo(:), run_len(:)
    integer, allocatable :: run_ptr(:,:)
    integer, allocatable :: zone_lo(:), zone_len(:), zone_ptr(:)
    !> Rows done per stage in the zones (for the log and the tests).
    integer, allocatable :: zone_rows(:)
  end type sweep_t

contains

  !> to <- from without a copy (the arrays move; from is left empty).
  subroutine sweep_move(from, to)
    type(sweep_t), intent(inout) :: from, to
    to%nstage = from%nstage
    to%nslot = from%nslot
    to%n = from%n
    to%w = from%w
    to%strip = from%strip
    call move_alloc(from%run_lo, to%run_lo)
    call move_alloc(from%run_len, to%run_len)
    call move_alloc(from%run_ptr, to%run_ptr)
    call move_alloc(from%zone_lo, to%zone_lo)
    call move_alloc(from%zone_len, to%zone_len)
    call move_alloc(from%zone_ptr, to%zone_ptr)
    call move_alloc(from%zone_rows, to%zone_rows)
  end subroutine sweep_move

  !> Plans sweeps of `nstage` steps over the n owned rows of graph g (columns > n are ghosts).
  !! sync(n) marks the rows that take part in the correction between steps; rows with a ghost
  !! column are added here. `window`: rows per line of the mesh in a strip; x(2, n): the
  !! coordinates of the owned nodes (the strips follow them).
  subroutine sweep_plan(sw, g, nstage, window, x, sync)
    type(sweep_t), intent(out) :: sw
    type(graph_t), intent(in) :: g
    integer, intent(in) :: nstage, window
    real(dp), intent(in) :: x(:,:)
    logical, intent(in) :: sync(:)
    integer, allocatable :: slot(:), tk(:), tprev(:), cnt(:), order(:), lo(:), len(:), &
        strip(:), hist(:)
    logical, allocatable :: zone(:,:)
    integer :: n, nstrip, nbin, i, k, c, t, nr, q, ax, b, acc, per_slot, fill
    real(dp) :: fmin, fmax, sx, sy
    n = g%n
    sw%n = n
    sw%nstage = max(1, min(nstage, MAX_STAGES))
    sw%w = 0
    do i = 1, n
      do c = g%row_ptr(i), g%row_ptr(i + 1) - 1
        if (g%col(c) <= n) sw%w = max(sw%w, abs(g%col(c) - i))
      end do
    end do
    ! strips across the axis along which the numbering runs (consecutive rows differ most in
    ! it), each holding an equal share of the rows, about `window` rows per line of the mesh
    sx = 0.0_dp
    sy = 0.0_dp
    do i = 1, n - 1
      sx = sx + abs(x(1, i + 1) - x(1, i))
      sy = sy + abs(x(2, i + 1) - x(2, i))
    end do
    ax = 1
    if (sy > sx) ax = 2
    nstrip = max(1, (sw%w + window - 1)/max(1, window))
    sw%strip = nstrip
    allocate(strip(n), slot(n))
    strip = 1
    if (nstrip > 1 .and. n > 0) then
      fmin = minval(x(ax, 1:n))
      fmax = maxval(x(ax, 1:n))
      nbin = 64*nstrip
      allocate(hist(nbin))
      hist = 0
      do i = 1, n
        b = bin_of(x(ax, i))
        hist(b) = hist(b) + 1
      end do
      ! the bins' strips: equal shares of the rows in increasing coordinate
      acc = 0
      do b = 1, nbin
        c = hist(b)
        hist(b) = min(nstrip, int((int(acc, i8k) * nstrip)/n) + 1)
        acc = acc + c
      end do
      do i = 1, n
        strip(i) = hist(bin_of(x(ax, i)))
      end do
    end if
    ! stage 1 order: strip by strip, increasing row in a strip; slots of up to per_slot rows
    per_slot = max(16, window/4)
    allocate(cnt(0:max(nstrip, n) + 1), order(n))
    cnt = 0
    do i = 1, n
      cnt(strip(i)) = cnt(strip(i)) + 1
    end do
    do c = 1, nstrip
      cnt(c) = cnt(c) + cnt(c - 1)
    end do
    do i = n, 1, -1
      order(cnt(strip(i))) = i
      cnt(strip(i)) = cnt(strip(i)) - 1
    end do
    t = 0
    fill = per_slot
    do q = 1, n
      i = order(q)
      if (fill == per_slot .or. q == 1) then
        t = t + 1
        fill = 0
      else if (strip(i) /= strip(order(q - 1))) then
        t = t + 1
        fill = 0
      end if
      slot(i) = t
      fill = fill + 1
    end do
    sw%nslot = t
    deallocate(cnt)
    allocate(cnt(0:sw%nslot + 1))
    ! zones, from the last stage down: Z_nstage = sync rows and rows with a ghost column,
    ! Z_k = Z_(k+1) and the neighbours of its rows
    allocate(zone(n, sw%nstage))
    zone(:, sw%nstage) = sync(1:n)
    do i = 1, n
      if (any(g%col(g%row_ptr(i):g%row_ptr(i + 1) - 1) > n)) zone(i, sw%nstage) = .true.
    end do
    do k = sw%nstage - 1, 1, -1
      zone(:, k) = zone(:, k + 1)
      do i = 1, n
        if (.not. zone(i, k + 1)) cycle
        do c = g%row_ptr(i), g%row_ptr(i + 1) - 1
          if (g%col(c) <= n) zone(g%col(c), k) = .true.
        end do
      end do
    end do
    allocate(lo(n), len(n))
    allocate(sw%zone_ptr(sw%nstage + 1), sw%zone_rows(sw%nstage))
    allocate(sw%zone_lo(0), sw%zone_len(0), sw%run_lo(0), sw%run_len(0))
    do k = 1, sw%nstage
      sw%zone_ptr(k) = size(sw%zone_lo) + 1
      sw%zone_rows(k) = count(zone(:, k))
      nr = 0
      do i = 1, n
        if (zone(i, k)) call add_row(i, lo, len, nr, .true.)
      end do
      sw%zone_lo = [sw%zone_lo, lo(1:nr)]
      sw%zone_len = [sw%zone_len, len(1:nr)]
    end do
    sw%zone_ptr(sw%nstage + 1) = size(sw%zone_lo) + 1
    ! ready slots of the rows outside the zones: t_1 = slot, t_k = the largest t_(k-1) of the
    ! row's stencil (at least 1), where rows done in the zone count as slot 0
    allocate(tk(n), tprev(n))
    allocate(sw%run_ptr(sw%nslot + 1, sw%nstage))
    do k = 1, sw%nstage
      if (k == 1) then
        tk = slot
      else
        do i = 1, n
          t = tprev(i)
          do c = g%row_ptr(i), g%row_ptr(i + 1) - 1
            if (g%col(c) <= n) t = max(t, tprev(g%col(c)))
          end do
          ! a row whose whole stencil was done in the zones goes in the first slot
          tk(i) = max(t, 1)
        end do
      end if
      where (zone(:, k)) tk = 0
      ! the rows sorted by (ready slot, row): counting sort; cnt(t) ends as slot t's last
      cnt = 0
      do i = 1, n
        cnt(tk(i) + 1) = cnt(tk(i) + 1) + 1
      end do
      do t = 1, sw%nslot + 1
        cnt(t) = cnt(t) + cnt(t - 1)
      end do
      do i = 1, n
        cnt(tk(i)) = cnt(tk(i)) + 1
        order(cnt(tk(i))) = i
      end do
      nr = 0
      do t = 1, sw%nslot
        sw%run_ptr(t, k) = size(sw%run_lo) + nr + 1
        do q = cnt(t - 1) + 1, cnt(t)
          call add_row(order(q), lo, len, nr, q > cnt(t - 1) + 1)
        end do
      end do
      sw%run_ptr(sw%nslot + 1, k) = size(sw%run_lo) + nr + 1
      sw%run_lo = [sw%run_lo, lo(1:nr)]
      sw%run_len = [sw%run_len, len(1:nr)]
      tprev = tk
    end do

  contains

    !> Histogram bin of coordinate value f.
    pure integer function bin_of(f)
      real(dp), intent(in) :: f
      bin_of = 1
      if (fmax > fmin) bin_of = min(nbin, int(real(nbin, dp)*(f - fmin)/(fmax - fmin)) + 1)
    end function bin_of

    !> Adds row r to the runs (lo_, len_), nr_ of them so far: it extends the last run when
    !! `may_join` and r follows it.
    pure subroutine add_row(r, lo_, len_, nr_, may_join)
      integer, intent(in) :: r
      integer, intent(inout) :: lo_(:), len_(:), nr_
      logical, intent(in) :: may_join
      if (may_join .and. nr_ > 0) then
        if (lo_(nr_) + len_(nr_) == r) then
          len_(nr_) = len_(nr_) + 1
          return
        end if
      end if
      nr_ = nr_ + 1
      lo_(nr_) = r
      len_(nr_) = 1
    end subroutine add_row
  end subroutine sweep_plan

  !> Stage k on the rows of its zone: reads x_in (stage k-1, ghosts current), writes x_out.
  !! With `alpha`, `m_pos` and `pw` the damped step (`fused_lumped_rows`), whose power terms
  !! of stage k go to pw(:, :, k).
  subroutine sweep_zone_stage(sw, k, row_ptr, col, val, inv_m, dt, x_in, v, x_out, alpha, &
      m_pos, pw)
    type(sweep_t), intent(in) :: sw
    integer, intent(in) :: k
    integer, intent(in) :: row_ptr(:), col(*)
    real(dp), intent(in) :: val(2, 2, *), inv_m(2, *), dt
    real(dp), intent(in) :: x_in(2, *)
    real(dp), intent(inout) :: v(2, *), x_out(2, *)
    real(dp), intent(in), optional :: alpha(*), m_pos(*)
    real(dp), intent(inout), optional :: pw(2, sw%n, *)
    integer :: r
    do r = sw%zone_ptr(k), sw%zone_ptr(k + 1) - 1
      if (present(pw)) then
        call fused_lumped_rows(sw%zone_lo(r), sw%zone_len(r), row_ptr, col, val, inv_m, dt, &
            x_in, v, x_out, alpha, m_pos, pw(1, 1, k))
      else
        call fused_lumped_rows(sw%zone_lo(r), sw%zone_len(r), row_ptr, col, val, inv_m, dt, &
            x_in, v, x_out)
      end if
    end do
  end subroutine sweep_zone_stage

  !> All stages on the rows outside the zones, slot by slot. a holds the displacements before
  !! the sweep, b receives stage 1; stage k reads the array stage k-1 wrote. Damping as in
  !! `sweep_zone_stage`.
  subroutine sweep_rows(sw, row_ptr, col, val, inv_m, dt, a, b, v, alpha, m_pos, pw)
    type(sweep_t), intent(in) :: sw
    integer, intent(in) :: row_ptr(:), col(*)
    real(dp), intent(in) :: val(2, 2, *), inv_m(2, *), dt
    real(dp), intent(inout) :: a(2, *), b(2, *), v(2, *)
    real(dp), intent(in), optional :: alpha(*), m_pos(*)
    real(dp), intent(inout), optional :: pw(2, sw%n, *)
    integer :: t, k, r
    do t = 1, sw%nslot
      do k = 1, sw%nstage
        do r = sw%run_ptr(t, k), sw%run_ptr(t + 1, k) - 1
          if (present(pw)) then
            if (mod(k, 2) == 1) then
              call fused_lumped_rows(sw%run_lo(r), sw%run_len(r), row_ptr, col, val, inv_m, &
                  dt, a, v, b, alpha, m_pos, pw(1, 1, k))
            else
              call fused_lumped_rows(sw%run_lo(r), sw%run_len(r), row_ptr, col, val, inv_m, &
                  dt, b, v, a, alpha, m_pos, pw(1, 1, k))
            end if
          else if (mod(k, 2) == 1) then
            call fused_lumped_rows(sw%run_lo(r), sw%run_len(r), row_ptr, col, val, inv_m, dt, &
                a, v, b)
          else
            call fused_lumped_rows(sw%run_lo(r), sw%run_len(r), row_ptr, col, val, inv_m, dt, &
                b, v, a)
          end if
        end do
      end do
    end do
  end subroutine sweep_rows

end module ictus_solver_sweep
