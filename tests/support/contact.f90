!> Contact test fixtures: straight Q8 rows and biquadratic NURBS patches with their contact
!! surfaces, for the unit tests of the contact layer.
module ictus_test_contact
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_Q8
  use ictus_geometry_patch, only: patch_t, patch_refine
  use ictus_contact_surface, only: surface_init, face_segment, patch_side_segments, &
      SEG_LAGRANGE, SEG_BEZIER
  use ictus_contact_contact, only: contact_t
  implicit none
  private
  public :: q8_row, q8_surface, nurbs_surface

contains

  !> Appends a row of ne square-ish Q8 elements [xa, xa + ne h] x [ya, ya + hy] to x(:, 1:nn)
  !! and returns their connectivity (8, ne) (corners counter-clockwise, then midsides).
  subroutine q8_row(ne, xa, ya, h, hy, x, nn, econn)
    integer, intent(in) :: ne
    real(dp), intent(in) :: xa, ya, h, hy
    real(dp), intent(inout) :: x(:,:)
    integer, intent(inout) :: nn
    integer, intent(out) :: econn(8, ne)
    integer :: i, e, b0, t0, bm0, tm0, v0
    b0 = nn
    t0 = nn + ne + 1
    bm0 = nn + 2*(ne + 1)
    tm0 = bm0 + ne
    v0 = tm0 + ne
    do i = 0, ne
      x(:, b0 + i + 1) = [xa + i*h, ya]
      x(:, t0 + i + 1) = [xa + i*h, ya + hy]
      x(:, v0 + i + 1) = [xa + i*h, ya + 0.5_dp*hy]
    end do
    do e = 1, ne
      x(:, bm0 + e) = [xa + (e - 0.5_dp)*h, ya]
      x(:, tm0 + e) = [xa + (e - 0.5_dp)*h, ya + hy]
      econn(:, e) = [b0 + e, b0 + e + 1, t0 + e + 1, t0 + e, bm0 + e, v0 + e + 1, tm0 + e, &
          v0 + e]
    end do
    nn = v0 + ne + 1
  end subroutine q8_row

  !> Surface `is` of c from face `face` of every element of a Q8 row.
  subroutine q8_surface(c, is, name, econn, face, x)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: is, econn(:,:), face
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: x(:,:)
    integer :: conn(3, size(econn, 2)), nens(size(econn, 2)), kinds(size(econn, 2)), e
    do e = 1, size(econn, 2)
      call face_segment(ETYPE_Q8, econn(:, e), face, conn(:, e), nens(e))
    end do
    kinds = SEG_LAGRANGE
    call surface_init(c%surfaces(is), name, kinds, nens, conn, x)
  end subroutine q8_surface

  !> Surface `is` of c from side `side` of a biquadratic patch over
  !! [xa, xa + width] x [ya, ya + 1], refined into k1 x 2 elements; its control points are
  !! appended to x. ierr: patch_side_segments' status (0: fine).
  subroutine nurbs_surface(c, is, name, xa, ya, width, k1, side, x, nn, ierr)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: is, k1, side
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: xa, ya, width
    real(dp), intent(inout) :: x(:,:)
    integer, intent(inout) :: nn
    integer, intent(out) :: ierr
    type(patch_t) :: patch
    real(dp) :: cp(3, 9)
    integer :: i, j, nseg
    integer, allocatable :: nens(:), conn(:,:), elem(:), kinds(:)
    real(dp), allocatable :: wgt(:,:), ext(:,:,:)
    do j = 0, 2
      do i = 0, 2
        cp(:, 1 + i + 3*j) = [xa + 0.5_dp*width*i, ya + 0.5_dp*j, 1.0_dp]
      end do
    end do
    call patch%init(name, [2, 2], [3, 3], [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], &
        [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], cp)
    call patch_refine(patch, [k1, 2])
    do i = 1, patch%n(1)*patch%n(2)
      x(:, nn + i) = patch%cp(1:2, i)
    end do
    call patch_side_segments(patch, nn, side, nseg, nens, conn, wgt, ext, elem, ierr)
    nn = nn + patch%n(1)*patch%n(2)
    allocate(kinds(nseg))
    kinds = SEG_BEZIER
    call surface_init(c%surfaces(is), name, kinds, nens, conn, x(:, 1:nn), wgt=wgt, ext=ext)
  end subroutine nurbs_surface
end module ictus_test_contact
