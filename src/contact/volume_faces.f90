!> The faces of a side of a trivariate NURBS patch (ictus_geometry_volume) as rational Bezier
!! faces of a 3D contact surface (ictus_contact_face3d, doc/contact.md §9): one face per
!! element on the side, of the degrees of the two in-face directions, with their 1D extraction
!! operators, the weights and the global nodes of the face's control points.
!!
!! Orientation: the side XI0/XI1 has the normal direction 1 and the in-face directions (2, 3),
!! ETA0/ETA1 direction 2 and (3, 1), ZETA0/ZETA1 direction 3 and (1, 2) (cyclic, so that
!! (a_i x a_j).a_d = det J). The face's first and second directions are these, or swapped,
!! so that a1 x a2 points out of the patch: on a side ...1 where det J > 0, on a side ...0
!! where det J < 0. det J is sampled at the face's Gauss points ((p + 1)^2, inside the face:
!! an edge of the face that collapses to a point, as the pole of the quarter-ball's sphere, is
!! not sampled); it must keep one sign beyond 1e-10 of the element's size cubed on the whole
!! side, else the outward normal is undefined.
module ictus_contact_volume_faces
  use ictus_core_kinds, only: dp
  use ictus_geometry_volume, only: volume_t, volume_elem_ijk
  use ictus_geometry_sides, only: SIDE_XI0, SIDE_XI1, SIDE_ETA0, SIDE_ETA1, SIDE_ZETA0, &
      SIDE_ZETA1
  use ictus_elements_iga, only: iga3_basis_at
  use ictus_elements_quadrature, only: gauss_legendre
  use ictus_contact_face3d, only: MAX_FACE_NODES
  implicit none
  private
  public :: volume_side_faces, VF_OK, VF_NO_SIDE, VF_DEGREE, VF_COLLAPSED, VF_DEGENERATE

  !> Outcome: faces built; not a side of a volume; an in-face degree above 3 (face3d takes
  !! bicubic faces at most); det J vanishes at every sample (a collapsed side: a line or a
  !! point); det J vanishes somewhere or changes sign (inverted or partly degenerate patch).
  integer, parameter :: VF_OK = 0, VF_NO_SIDE = 1, VF_DEGREE = 2, VF_COLLAPSED = 3, &
      VF_DEGENERATE = 4

  !> det J below this times the element's bounding-box diagonal cubed counts as zero.
  real(dp), parameter :: det_tol = 1.0e-10_dp

contains

  !> The faces of side `side` of volume v: nface faces, control points per face nens, their
  !! global nodes conn (MAX_FACE_NODES, nface) (node(k): the node of control point k), degrees
  !! deg (2, nface), extraction operators ext1, ext2 (4, 4, nface), weights wgt
  !! (MAX_FACE_NODES, nface); ierr one of VF_*.
  subroutine volume_side_faces(v, side, node, nface, nens, conn, deg, ext1, ext2, wgt, ierr)
    type(volume_t), intent(in) :: v
    integer, intent(in) :: side, node(:)
    integer, intent(out) :: nface, ierr
    integer, allocatable, intent(out) :: nens(:), conn(:,:), deg(:,:)
    real(dp), allocatable, intent(out) :: ext1(:,:,:), ext2(:,:,:), wgt(:,:)
    integer, allocatable :: elems(:)
    integer :: d, fd(2), e, k, ijk(3), npos, nneg, nzero, m
    logical :: hi, flip
    nface = 0
    ierr = VF_OK
    call side_axes(side, d, fd, hi)
    if (d == 0) then
      ierr = VF_NO_SIDE
    else if (any(v%p(fd) > 3)) then
      ierr = VF_DEGREE
    end if
    if (ierr /= VF_OK) then
      allocate(nens(0), conn(MAX_FACE_NODES, 0), deg(2, 0), ext1(4, 4, 0), ext2(4, 4, 0), &
          wgt(MAX_FACE_NODES, 0))
      return
    end if
    allocate(elems(product(v%nel)))
    do e = 1, product(v%nel)
      ijk = volume_elem_ijk(v, e)
      if (ijk(d) == merge(v%nel(d), 1, hi)) then
        nface = nface + 1
        elems(nface) = e
      end if
    end do
    npos = 0
    nneg = 0
    nzero = 0
    do k = 1, nface
      call count_signs(v, elems(k), d, fd, hi, npos, nneg, nzero)
    end do
    if (npos + nneg == 0) then
      ierr = VF_COLLAPSED
    else if (nzero > 0 .or. (npos > 0 .and. nneg > 0)) then
      ierr = VF_DEGENERATE
    end if
    ! outward a1 x a2: (a_fd1 x a_fd2).a_d = det J points along +a_d, out of a side ...1
    flip = hi .eqv. (nneg > 0)
    if (flip) fd = fd([2, 1])
    m = MAX_FACE_NODES
    allocate(nens(nface), conn(m, nface), deg(2, nface), source=0)
    allocate(ext1(4, 4, nface), ext2(4, 4, nface), wgt(m, nface), source=0.0_dp)
    do k = 1, nface
      call one_face(v, elems(k), d, fd, hi, node, nens(k), conn(:, k), deg(:, k), &
          ext1(:, :, k), ext2(:, :, k), wgt(:, k))
    end do
  end subroutine volume_side_faces

  !> The normal direction d (0: not a side of a volume), the in-face directions fd (cyclic
  !! after d) and whether the side is the last knot (...1) of direction d.
  pure subroutine side_axes(side, d, fd, hi)
    integer, intent(in) :: side
    integer, intent(out) :: d, fd(2)
    logical, intent(out) :: hi
    d = 0
    select case (side)
    case (SIDE_XI0, SIDE_XI1)
      d = 1
    case (SIDE_ETA0, SIDE_ETA1)
      d = 2
    case (SIDE_ZETA0, SIDE_ZETA1)
      d = 3
    end select
    hi = side == SIDE_XI1 .or. side == SIDE_ETA1 .or. side == SIDE_ZETA1
    fd = [mod(d, 3) + 1, mod(d + 1, 3) + 1]
  end subroutine side_axes

  !> The extraction operator of span i of direction dir (p + 1, p + 1).
  pure function span_ext(v, dir, i) result(c)
    type(volume_t), intent(in) :: v
    integer, intent(in) :: dir, i
    real(dp) :: c(v%p(dir) + 1, v%p(dir) + 1)
    select case (dir)
    case (1)
      c = v%c1(:, :, i)
    case (2)
      c = v%c2(:, :, i)
    case default
      c = v%c3(:, :, i)
    end select
  end function span_ext

  !> Local index (1-based, direction 1 fastest) of the element control point a (0-based).
  pure integer function local_point(p, a)
    integer, intent(in) :: p(3), a(3)
    local_point = 1 + a(1) + (p(1) + 1)*(a(2) + (p(2) + 1)*a(3))
  end function local_point

  !> Counts the signs of det J of element e at the Gauss points of its face on the side
  !! (normal direction d, in-face fd, last knot when hi): > tol, < -tol, else zero.
  subroutine count_signs(v, e, d, fd, hi, npos, nneg, nzero)
    type(volume_t), intent(in) :: v
    integer, intent(in) :: e, d, fd(2)
    logical, intent(in) :: hi
    integer, intent(inout) :: npos, nneg, nzero
    real(dp) :: g1(4), w1(4), g2(4), w2(4), xi(3), r(v%nen), dr(3, v%nen), x(3, v%nen), &
        jm(3, 3), det, tol
    integer :: ijk(3), i, j, q(2), k
    ijk = volume_elem_ijk(v, e)
    do k = 1, v%nen
      ! relative to the first control point: a collapsed side gives a zero tangent exactly
      x(:, k) = v%cp(1:3, v%ien(k, e)) - v%cp(1:3, v%ien(1, e))
    end do
    tol = det_tol*norm2(maxval(x, dim=2) - minval(x, dim=2))**3
    q = min(v%p(fd) + 1, 4)
    call gauss_legendre(q(1), g1(1:q(1)), w1(1:q(1)))
    call gauss_legendre(q(2), g2(1:q(2)), w2(1:q(2)))
    xi(d) = merge(1.0_dp, -1.0_dp, hi)
    do j = 1, q(2)
      do i = 1, q(1)
        xi(fd(1)) = g1(i)
        xi(fd(2)) = g2(j)
        call iga3_basis_at(v%p, span_ext(v, 1, ijk(1)), span_ext(v, 2, ijk(2)), &
            span_ext(v, 3, ijk(3)), v%cp(4, v%ien(:, e)), xi, r, dr)
        jm = matmul(x, transpose(dr))
        det = jm(1, 1)*(jm(2, 2)*jm(3, 3) - jm(3, 2)*jm(2, 3)) - &
            jm(1, 2)*(jm(2, 1)*jm(3, 3) - jm(3, 1)*jm(2, 3)) + &
            jm(1, 3)*(jm(2, 1)*jm(3, 2) - jm(3, 1)*jm(2, 2))
        if (det > tol) then
          npos = npos + 1
        else if (det < -tol) then
          nneg = nneg + 1
        else
          nzero = nzero + 1
        end if
      end do
    end do
  end subroutine count_signs

  !> The Bezier face of element e on the side: its first direction fd(1), second fd(2),
  !! control points fd(1) fastest.
  subroutine one_face(v, e, d, fd, hi, node, nen, conn, deg, ext1, ext2, wgt)
    type(volume_t), intent(in) :: v
    integer, intent(in) :: e, d, fd(2), node(:)
    logical, intent(in) :: hi
    integer, intent(out) :: nen, conn(:), deg(2)
    real(dp), intent(out) :: ext1(:,:), ext2(:,:), wgt(:)
    integer :: ijk(3), a(3), b1, b2, k, g
    ijk = volume_elem_ijk(v, e)
    deg = v%p(fd)
    ext1(1:deg(1) + 1, 1:deg(1) + 1) = span_ext(v, fd(1), ijk(fd(1)))
    ext2(1:deg(2) + 1, 1:deg(2) + 1) = span_ext(v, fd(2), ijk(fd(2)))
    a(d) = merge(v%p(d), 0, hi)
    nen = 0
    do b2 = 0, deg(2)
      do b1 = 0, deg(1)
        a(fd(1)) = b1
        a(fd(2)) = b2
        nen = nen + 1
        k = v%ien(local_point(v%p, a), e)
        g = node(k)
        conn(nen) = g
        wgt(nen) = v%cp(4, k)
      end do
    end do
  end subroutine one_face
end module ictus_contact_volume_faces
