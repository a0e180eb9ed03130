!> Global contact search: a uniform bucket grid over axis-aligned boxes (the current bounding
!! boxes of master segments, grown by a search radius).
!!
!! The cell size is the largest box extent (enlarged if the grid would have more than
!! 4 nbox + 16 cells), so a box overlaps at most 2 x 2 cells and the grid holds at most
!! 4 nbox entries: building is O(nbox), and a query looks at one cell only. All arrays are
!! sized in `grid_init`; building and querying do not allocate.
module ictus_contact_search
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: search_grid_t, grid_init, grid_build, grid_query, box_contains

  !> A bucket grid over nbox boxes.
  type :: search_grid_t
    !> Number of boxes and the boxes (4, nbox): xmin, ymin, xmax, ymax.
    integer :: nbox = 0
    real(dp), allocatable :: box(:,:)
    !> Lower-left corner of the grid, cell size, cells per direction, cell capacity.
    real(dp) :: origin(2) = 0.0_dp
    real(dp) :: h = 1.0_dp
    integer :: nx = 0, ny = 0
    integer :: ncell_cap = 0
    !> Compressed cell lists: entries of cell c are items(start(c) : start(c+1) - 1).
    integer, allocatable :: start(:)
    integer, allocatable :: items(:)
    !> Work array (ncell_cap + 1).
    integer, allocatable :: fill(:)
  end type search_grid_t

contains

  !> Allocates a grid for nbox boxes.
  !! @param g the grid; @param nbox number of boxes
  subroutine grid_init(g, nbox)
    type(search_grid_t), intent(inout) :: g
    integer, intent(in) :: nbox
    if (allocated(g%box)) deallocate(g%box)
    if (allocated(g%start)) deallocate(g%start)
    if (allocated(g%items)) deallocate(g%items)
    if (allocated(g%fill)) deallocate(g%fill)
    g%nbox = nbox
    g%ncell_cap = 4*nbox + 16
    allocate(g%box(4, nbox), g%start(g%ncell_cap + 1), g%items(4*nbox + 4), &
        g%fill(g%ncell_cap + 1))
    g%box = 0.0_dp
    g%nx = 0
    g%ny = 0
  end subroutine grid_init

  !> Sorts the boxes g%box(:, 1:nbox) (filled by the caller) into the grid cells.
  !! @param g the grid (box set, from grid_init)
  subroutine grid_build(g)
    type(search_grid_t), intent(inout) :: g
    real(dp) :: lo(2), hi(2), h
    integer :: k, ix0, ix1, iy0, iy1, ix, iy, c, ncell
    real(dp) :: nxy
    g%nx = 0
    g%ny = 0
    if (g%nbox == 0) return
    lo = g%box(1:2, 1)
    hi = g%box(3:4, 1)
    h = 0.0_dp
    do k = 1, g%nbox
      lo = min(lo, g%box(1:2, k))
      hi = max(hi, g%box(3:4, k))
      h = max(h, g%box(3, k) - g%box(1, k), g%box(4, k) - g%box(2, k))
    end do
    h = max(h, 1.0e-12_dp*max(1.0_dp, abs(hi(1)), abs(hi(2)), abs(lo(1)), abs(lo(2))))
    do
      nxy = (aint((hi(1) - lo(1))/h) + 1.0_dp)*(aint((hi(2) - lo(2))/h) + 1.0_dp)
      if (nxy <= real(g%ncell_cap, dp)) exit
      h = h*sqrt(nxy/real(g%ncell_cap, dp))*1.01_dp
    end do
    g%h = h
    g%origin = lo
    g%nx = int(floor((hi(1) - lo(1))/h)) + 1
    g%ny = int(floor((hi(2) - lo(2))/h)) + 1
    ncell = g%nx*g%ny
    g%fill(1:ncell+1) = 0
    ! count, then place (counting sort)
    do k = 1, g%nbox
      call cell_range(g, g%box(:, k), ix0, ix1, iy0, iy1)
      do iy = iy0, iy1
        do ix = ix0, ix1
          c = ix + iy*g%nx + 1
          g%fill(c + 1) = g%fill(c + 1) + 1
        end do
      end do
    end do
    g%start(1) = 1
    do c = 1, ncell
      g%start(c + 1) = g%start(c) + g%fill(c + 1)
      g%fill(c) = g%start(c)
    end do
    do k = 1, g%nbox
      call cell_range(g, g%box(:, k), ix0, ix1, iy0, iy1)
      do iy = iy0, iy1
        do ix = ix0, ix1
          c = ix + iy*g%nx + 1
          g%items(g%fill(c)) = k
          g%fill(c) = g%fill(c) + 1
        end do
      end do
    end do
  end subroutine grid_build

  !> Cells (0-based, clamped to the grid) overlapped by a box.
  pure subroutine cell_range(g, box, ix0, ix1, iy0, iy1)
    type(search_grid_t), intent(in) :: g
    real(dp), intent(in) :: box(4)
    integer, intent(out) :: ix0, ix1, iy0, iy1
    ix0 = min(max(int(floor((box(1) - g%origin(1))/g%h)), 0), g%nx - 1)
    ix1 = min(max(int(floor((box(3) - g%origin(1))/g%h)), 0), g%nx - 1)
    iy0 = min(max(int(floor((box(2) - g%origin(2))/g%h)), 0), g%ny - 1)
    iy1 = min(max(int(floor((box(4) - g%origin(2))/g%h)), 0), g%ny - 1)
  end subroutine cell_range

  !> Boxes that contain point xp, in increasing box order.
  !! @param g the grid; @param xp point (2); @param cand candidates (at least nbox);
  !! @param ncand their number
  pure subroutine grid_query(g, xp, cand, ncand)
    type(search_grid_t), intent(in) :: g
    real(dp), intent(in) :: xp(2)
    integer, intent(inout) :: cand(:)
    integer, intent(out) :: ncand
    integer :: ix, iy, c, k
    real(dp) :: fx, fy
    ncand = 0
    if (g%nx == 0) return
    fx = (xp(1) - g%origin(1))/g%h
    fy = (xp(2) - g%origin(2))/g%h
    if (fx < 0.0_dp .or. fy < 0.0_dp .or. fx >= real(g%nx, dp) .or. fy >= real(g%ny, dp)) &
        return
    ix = min(int(fx), g%nx - 1)
    iy = min(int(fy), g%ny - 1)
    c = ix + iy*g%nx + 1
    do k = g%start(c), g%start(c + 1) - 1
      if (box_contains(g%box(:, g%items(k)), xp)) then
        ncand = ncand + 1
        cand(ncand) = g%items(k)
      end if
    end do
  end subroutine grid_query

  !> Whether box (xmin, ymin, xmax, ymax) contains point xp (boundary included).
  pure logical function box_contains(box, xp)
    real(dp), intent(in) :: box(4), xp(2)
    box_contains = xp(1) >= box(1) .and. xp(1) <= box(3) .and. xp(2) >= box(2) .and. &
        xp(2) <= box(4)
  end function box_contains
end module ictus_contact_search
