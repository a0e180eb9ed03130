!> Pressure on the faces of hexahedra (*DLOAD, P in 3D): the nodal forces
!!
!!     f_A = -p int N_A n dA = -p sum_q w_q N_A(xi_q, eta_q) (x_,xi x x_,eta)(xi_q, eta_q)
!!
!! over the quadrilateral faces of a surface (4, 8 or 9 nodes, the face lists of the element
!! description, doc/elements3d.md §2), with the shape functions of the quadrilateral of the
!! same nodes (Q4, Q8, Q9: a face list is their node order seen from outside, so
!! x_,xi x x_,eta is the outward normal times the area element) and their Gauss rules (2 x 2,
!! 3 x 3). x are the reference coordinates (small strain), or the current ones x0 + u (NLGEOM:
!! the pressure follows the deformed surface).
!!
!! A rank keeps the faces that hold one of its owned nodes; their nodes are all local (the
!! face's element holds an owned node, so it is one of the rank's elements). Each owned row
!! sums its faces in the surface's order, the same on any number of ranks.
module ictus_solver_face_pressure
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: elem_shape_t, ETYPE_Q4, ETYPE_Q8, ETYPE_Q9
  use ictus_elements_library, only: element_shape_data
  implicit none
  private
  public :: face_pressure_t, face_pressure_setup, face_pressure_add

  !> Most nodes of a face (the centre of a C3D27 face is its ninth).
  integer, parameter :: max_face_nodes = 9

  !> The faces of one pressure load that touch this rank's owned nodes.
  type :: face_pressure_t
    real(dp) :: p = 0.0_dp
    integer :: amp = 0
    integer :: nface = 0
    !> Nodes per face (nface); local nodes (max_face_nodes, nface).
    integer, allocatable :: nfn(:)
    integer, allocatable :: lnode(:,:)
    !> The quadrilateral of 4, 8 and 9 nodes: shape values n(9, ngp), parent derivatives
    !! dn(2, 9, ngp) and weights w(ngp) at its Gauss points (index 1, 2, 3 for 4, 8, 9 nodes).
    type(elem_shape_t) :: shp(3)
  end type face_pressure_t

contains

  !> The rank's part of the pressure load p (amplitude amp) on the faces conn(:, 1:nface)
  !! (global nodes, nfn(k) each), with g2l the local index of each global node.
  subroutine face_pressure_setup(nface, nfn, conn, p, amp, g2l, nowned, fp)
    integer, intent(in) :: nface, nfn(:), conn(:,:), amp, g2l(:), nowned
    real(dp), intent(in) :: p
    type(face_pressure_t), intent(out) :: fp
    integer :: k, n, a
    logical :: mine
    fp%p = p
    fp%amp = amp
    call element_shape_data(ETYPE_Q4, 2, fp%shp(1))
    call element_shape_data(ETYPE_Q8, 3, fp%shp(2))
    call element_shape_data(ETYPE_Q9, 3, fp%shp(3))
    allocate(fp%nfn(nface), fp%lnode(max_face_nodes, nface), source=0)
    n = 0
    do k = 1, nface
      mine = .false.
      do a = 1, nfn(k)
        if (g2l(conn(a, k)) >= 1 .and. g2l(conn(a, k)) <= nowned) mine = .true.
      end do
      if (.not. mine) cycle
      n = n + 1
      fp%nfn(n) = nfn(k)
      fp%lnode(1:nfn(k), n) = g2l(conn(1:nfn(k), k))
    end do
    fp%nface = n
  end subroutine face_pressure_setup

  !> Adds scale * (the pressure forces) to the owned rows of f (3, nlocal). x0 are the local
  !! reference coordinates, u the displacements (used when `follow`).
  pure subroutine face_pressure_add(fp, scale, x0, u, follow, nowned, f)
    type(face_pressure_t), intent(in) :: fp
    real(dp), intent(in) :: scale, x0(:,:), u(:,:)
    logical, intent(in) :: follow
    integer, intent(in) :: nowned
    real(dp), intent(inout) :: f(:,:)
    real(dp) :: xl(3, max_face_nodes), fl(3, max_face_nodes), xa(3), xb(3), nda(3), pw
    integer :: k, q, a, n, l, s
    if (fp%nface == 0) return
    pw = -scale*fp%p
    do k = 1, fp%nface
      n = fp%nfn(k)
      s = merge(1, merge(2, 3, n == 8), n == 4)
      do a = 1, n
        l = fp%lnode(a, k)
        xl(:, a) = x0(:, l)
        if (follow) xl(:, a) = xl(:, a) + u(:, l)
      end do
      fl(:, 1:n) = 0.0_dp
      associate (shp => fp%shp(s))
        do q = 1, shp%ngp
          xa = matmul(xl(:, 1:n), shp%dn(1, 1:n, q))
          xb = matmul(xl(:, 1:n), shp%dn(2, 1:n, q))
          ! n dA = (x_,xi x x_,eta) dxi deta
          nda = [xa(2)*xb(3) - xa(3)*xb(2), xa(3)*xb(1) - xa(1)*xb(3), &
              xa(1)*xb(2) - xa(2)*xb(1)]*shp%w(q)
          do a = 1, n
            fl(:, a) = fl(:, a) + shp%n(a, q)*nda
          end do
        end do
      end associate
      do a = 1, n
        l = fp%lnode(a, k)
        if (l <= nowned) f(:, l) = f(:, l) + pw*fl(:, a)
      end do
    end do
  end subroutine face_pressure_add
end module ictus_solver_face_pressure
