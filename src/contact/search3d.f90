!> Global contact search in 3D: a uniform bucket grid over axis-aligned boxes (the current
!! bounding boxes of master faces, grown by a search radius), as ictus_contact_search does in
!! 2D. The cell size is the largest box extent (enlarged while the grid would have more than
!! 8 nbox + 16 cells), so a box overlaps at most 2 x 2 x 2 cells and the grid holds at most
!! 8 nbox entries; a query looks at one cell. All arrays are sized in `grid3_init`; building
!! and querying do not allocate.
module ictus_contact_search3d
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: grid3_t, grid3_init, grid3_build, grid3_query

  type :: grid3_t
    !> Boxes (6, nbox): xmin, ymin, zmin, xmax, ymax, zmax.
    integer :: nbox = 0
    real(dp), allocatable :: box(:,:)
    !> Lower corner, cell size, cells per direction (0: empty grid), cell capacity.
    real(dp) :: origin(3) = 0.0_dp
    real(dp) :: h = 1.0_dp
    integer :: n(3) = 0
    integer :: ncell_cap = 0
    !> Compressed cell lists: entries of cell c are items(start(c) : start(c+1) - 1); fill
    !! is work.
    integer, allocatable :: start(:), items(:), fill(:)
  end type grid3_t

contains

  !> Allocates a grid for nbox boxes.
  subroutine grid3_init(g, nbox)
    type(grid3_t), intent(inout) :: g
    integer, intent(in) :: nbox
    g = grid3_t()
    g%nbox = nbox
    g%ncell_cap = 8*nbox + 16
    allocate(g%box(6, nbox), g%start(g%ncell_cap + 1), g%items(8*nbox + 8), &
        g%fill(g%ncell_cap + 1))
    g%box = 0.0_dp
  end subroutine grid3_init

  !> Sorts the boxes g%box(:, 1:nbox) (filled by the caller) into the cells.
  subroutine grid3_build(g)
    type(grid3_t), intent(inout) :: g
    real(dp) :: lo(3), hi(3), h, cells
    integer :: k, pass, c, ncell, i0(3), i1(3), ix, iy, iz
    g%n = 0
    if (g%nbox == 0) return
    lo = minval(g%box(1:3, :), dim=2)
    hi = maxval(g%box(4:6, :), dim=2)
    h = maxval(g%box(4:6, :) - g%box(1:3, :))
    h = max(h, 1.0e-12_dp*max(1.0_dp, maxval(abs(lo)), maxval(abs(hi))))
    do
      cells = product(aint((hi - lo)/h) + 1.0_dp)
      if (cells <= real(g%ncell_cap, dp)) exit
      h = h*(cells/real(g%ncell_cap, dp))**(1.0_dp/3.0_dp)*1.01_dp
    end do
    g%h = h
    g%origin = lo
    g%n = int(floor((hi - lo)/h)) + 1
    ncell = product(g%n)
    g%fill(1:ncell + 1) = 0
    ! count, then place (counting sort): boxes in increasing order within every cell
    do pass = 1, 2
      if (pass == 2) then
        g%start(1) = 1
        do c = 1, ncell
          g%start(c + 1) = g%start(c) + g%fill(c + 1)
          g%fill(c) = g%start(c)
        end do
      end if
      do k = 1, g%nbox
        i0 = cell_of(g, g%box(1:3, k))
        i1 = cell_of(g, g%box(4:6, k))
        do iz = i0(3), i1(3)
          do iy = i0(2), i1(2)
            do ix = i0(1), i1(1)
              c = ix + g%n(1)*(iy + g%n(2)*iz) + 1
              if (pass == 1) then
                g%fill(c + 1) = g%fill(c + 1) + 1
              else
                g%items(g%fill(c)) = k
                g%fill(c) = g%fill(c) + 1
              end if
            end do
          end do
        end do
      end do
    end do
  end subroutine grid3_build

  !> The cell (0-based per direction, clamped to the grid) of point p.
  pure function cell_of(g, p) result(i)
    type(grid3_t), intent(in) :: g
    real(dp), intent(in) :: p(3)
    integer :: i(3)
    i = min(max(int(floor((p - g%origin)/g%h)), 0), g%n - 1)
  end function cell_of

  !> The boxes that contain point xp (boundary included), in increasing box order.
  pure subroutine grid3_query(g, xp, cand, ncand)
    type(grid3_t), intent(in) :: g
    real(dp), intent(in) :: xp(3)
    integer, intent(inout) :: cand(:)
    integer, intent(out) :: ncand
    real(dp) :: f(3)
    integer :: i(3), c, k, b
    ncand = 0
    if (g%n(1) == 0) return
    f = (xp - g%origin)/g%h
    if (any(f < 0.0_dp) .or. any(f >= real(g%n, dp))) return
    i = min(int(f), g%n - 1)
    c = i(1) + g%n(1)*(i(2) + g%n(2)*i(3)) + 1
    do k = g%start(c), g%start(c + 1) - 1
      b = g%items(k)
      if (all(xp >= g%box(1:3, b)) .and. all(xp <= g%box(4:6, b))) then
        ncand = ncand + 1
        cand(ncand) = b
      end if
    end do
  end subroutine grid3_query
end module ictus_contact_search3d
