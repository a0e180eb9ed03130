!> The contact faces of the sides of trivariate NURBS patches (ictus_contact_volume_faces,
!! doc/contact.md §9) against exact answers:
!!
!! * A box [0, 2] x [0, 1] x [0, 3] as a p = 2 patch (elevated and refined, 2 x 1 x 3 spans):
!!   on each of the six sides, sum l_A is the side's area (1e-13) and the normal a1 x a2 at
!!   every Gauss point is the outward unit normal of the box (1e-13); the same with direction
!!   1 reversed (det J < 0 everywhere), where the faces must be turned.
!! * The exact quarter-ball of quarter_ball.py --kind nurbs (R = 1.5, 2 x 4 x 2 spans): the
!!   spherical side ZETA1 has the area pi R^2 (1e-10 with 6 x 6 Gauss points) and the normal
!!   (x - c)/R at every Gauss point (1e-12); the collapsed sides XI0 (a segment of the x axis)
!!   and ZETA0 (the centre) are refused as collapsed; the plane side XI1 has the area of a half
!!   disc pi R^2/2 and the normal -e_x.
program test_volume_faces
  use ictus_core_kinds, only: dp
  use ictus_test_check, only: checker_t
  use ictus_geometry_volume, only: volume_t, volume_init, volume_elevate, volume_refine
  use ictus_geometry_sides, only: SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ZETA0, &
      SIDE_ZETA1, side_name
  use ictus_contact_face3d, only: surface3d_t, surface3d_init, face_geometry
  use ictus_contact_volume_faces, only: volume_side_faces, VF_OK, VF_COLLAPSED
  implicit none
  type(checker_t) :: t
  real(dp), parameter :: pi = acos(-1.0_dp)
  call t%start("contact/volume_faces")
  call box(t, .false.)
  call box(t, .true.)
  call ball(t)
  call t%finish()

contains

  !> The surface of side `side` of v (nodes: the control points), or ierr.
  subroutine side_surface(v, side, s, ierr, ng)
    type(volume_t), intent(in) :: v
    integer, intent(in) :: side
    type(surface3d_t), intent(out) :: s
    integer, intent(out) :: ierr
    integer, intent(in), optional :: ng
    integer, allocatable :: nens(:), conn(:,:), deg(:,:)
    real(dp), allocatable :: ext1(:,:,:), ext2(:,:,:), wgt(:,:)
    integer :: nface, k
    call volume_side_faces(v, side, [(k, k = 1, product(v%n))], nface, nens, conn, deg, ext1, &
        ext2, wgt, ierr)
    if (ierr /= VF_OK) return
    call surface3d_init(s, nens, conn, v%cp(1:3, :), ng=ng, deg=deg, ext1=ext1, ext2=ext2, &
        wgt=wgt)
  end subroutine side_surface

  !> The largest deviation of the unit normal at the Gauss points of s from normal(x).
  real(dp) function normal_error(s, x, centre, radius, fixed) result(err)
    type(surface3d_t), intent(in) :: s
    real(dp), intent(in) :: x(:,:), centre(3), radius, fixed(3)
    real(dp) :: xp(3), a(3, 2), n(3), jac, m(3)
    integer :: q
    err = 0.0_dp
    do q = 1, s%ngp
      call face_geometry(s, s%gp_face(q), x, s%gp_xi(:, q), xp, a, n, jac)
      m = fixed
      if (radius > 0.0_dp) m = (xp - centre)/radius
      err = max(err, norm2(n - m))
    end do
  end function normal_error

  subroutine box(t, reversed)
    type(checker_t), intent(inout) :: t
    logical, intent(in) :: reversed
    type(volume_t) :: v
    type(surface3d_t) :: s
    real(dp), parameter :: l(3) = [2.0_dp, 1.0_dp, 3.0_dp]
    real(dp) :: cp(4, 8), kn(4), nrm(3)
    integer :: i1, i2, i3, k, side, d, ierr
    character(len=:), allocatable :: label
    integer, parameter :: sides(6) = [SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ZETA0, &
        SIDE_ZETA1]
    kn = [0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp]
    k = 0
    do i3 = 0, 1
      do i2 = 0, 1
        do i1 = 0, 1
          k = k + 1
          cp(:, k) = [l(1)*i1, l(2)*i2, l(3)*i3, 1.0_dp]
          if (reversed) cp(1, k) = l(1)*(1 - i1)
        end do
      end do
    end do
    call volume_init(v, 'BOX', [1, 1, 1], [2, 2, 2], kn, kn, kn, cp)
    call volume_elevate(v, [1, 1, 1])
    call volume_refine(v, [2, 1, 3])
    label = 'box: '
    if (reversed) label = 'box, direction 1 reversed: '
    do k = 1, 6
      side = sides(k)
      d = (k + 1)/2
      call side_surface(v, side, s, ierr)
      call t%equal_int(ierr, VF_OK, label//side_name(side)//' accepted')
      if (ierr /= VF_OK) cycle
      nrm = 0.0_dp
      nrm(d) = merge(1.0_dp, -1.0_dp, mod(k, 2) == 0)
      if (reversed .and. d == 1) nrm = -nrm
      call t%close(sum(s%ell), product(l)/l(d), 1.0e-13_dp, label//side_name(side)// &
          ': sum l_A = area')
      call t%close_abs(normal_error(s, v%cp(1:3, :), [0.0_dp, 0.0_dp, 0.0_dp], 0.0_dp, nrm), &
          0.0_dp, 1.0e-13_dp, label//side_name(side)//': outward normal')
    end do
  end subroutine box

  subroutine ball(t)
    type(checker_t), intent(inout) :: t
    type(volume_t) :: v
    type(surface3d_t) :: s
    real(dp), parameter :: r = 1.5_dp, c(3) = [0.5_dp, -0.25_dp, 2.0_dp]
    real(dp) :: cp(4, 45), pol(3, 3), az(3, 5), h
    real(dp) :: k1(6), k2(8)
    integer :: i, j, l, k, ierr
    h = sqrt(0.5_dp)
    pol = reshape([1.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, h, 0.0_dp, 1.0_dp, 1.0_dp], [3, 3])
    az = reshape([0.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, h, 1.0_dp, 0.0_dp, 1.0_dp, &
        1.0_dp, 1.0_dp, h, 0.0_dp, 1.0_dp, 1.0_dp], [3, 5])
    k = 0
    do l = 0, 2
      do j = 1, 5
        do i = 1, 3
          k = k + 1
          cp(1:3, k) = c + 0.5_dp*l*r*[pol(1, i), pol(2, i)*az(1, j), pol(2, i)*az(2, j)]
          cp(4, k) = pol(3, i)*az(3, j)
          if (i == 2 .and. (j == 2 .or. j == 4)) cp(4, k) = 0.5_dp
        end do
      end do
    end do
    k1 = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    k2 = [0.0_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.5_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    call volume_init(v, 'BALL', [2, 2, 2], [3, 5, 3], k1, k2, k1, cp)
    call volume_refine(v, [2, 2, 2])
    call side_surface(v, SIDE_ZETA1, s, ierr, ng=6)
    call t%equal_int(ierr, VF_OK, 'quarter-ball: ZETA1 accepted')
    call t%close(sum(s%ell), pi*r*r, 1.0e-10_dp, 'quarter-ball: ZETA1 area pi R^2')
    call t%close_abs(normal_error(s, v%cp(1:3, :), c, r, [0.0_dp, 0.0_dp, 0.0_dp]), 0.0_dp, &
        1.0e-12_dp, 'quarter-ball: ZETA1 normal (x - c)/R')
    call side_surface(v, SIDE_XI1, s, ierr, ng=6)
    call t%equal_int(ierr, VF_OK, 'quarter-ball: XI1 accepted')
    call t%close(sum(s%ell), 0.5_dp*pi*r*r, 1.0e-10_dp, 'quarter-ball: XI1 area pi R^2/2')
    call t%close_abs(normal_error(s, v%cp(1:3, :), c, 0.0_dp, [-1.0_dp, 0.0_dp, 0.0_dp]), &
        0.0_dp, 1.0e-12_dp, 'quarter-ball: XI1 normal -e_x')
    call side_surface(v, SIDE_XI0, s, ierr)
    call t%equal_int(ierr, VF_COLLAPSED, 'quarter-ball: XI0 (a line) collapsed')
    call side_surface(v, SIDE_ZETA0, s, ierr)
    call t%equal_int(ierr, VF_COLLAPSED, 'quarter-ball: ZETA0 (a point) collapsed')
  end subroutine ball
end program test_volume_faces
