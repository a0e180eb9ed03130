!> Pressure on a surface (*DLOAD, P): the nodal forces
!!
!!     f_A = -p int R_A n dGamma = -p sum_q (w_q/2) R_A(t_q) (x'_y, -x'_x)(t_q)
!!
!! over the segments of a surface (ictus_contact_surface: 2- or 3-node edges of finite
!! elements, rational Bezier spans of patch sides, each oriented with the body on its left, so
!! that n = (x'_y, -x'_x)/|x'| is the outward normal), with Gauss-Legendre rules of the
!! segment's degree + 1 points on t in [0, 1] (doc/theory.md §4a). x are the reference
!! coordinates (small strain), or the current ones x0 + u (NLGEOM: the pressure follows the
!! deformed surface). Per unit thickness.
!!
!! A rank keeps the segments that hold one of its owned nodes; their nodes are all local (the
!! segment's element holds an owned node, so it is one of the rank's elements). Each owned
!! row sums its segments in the surface's order, the same on any number of ranks.
module ictus_solver_pressure
  use ictus_core_kinds, only: dp
  use ictus_elements_quadrature, only: gauss_legendre
  use ictus_contact_surface, only: contact_surface_t, segment_shape, MAX_SEG_NODES
  implicit none
  private
  public :: pressure_rt_t, pressure_setup, pressure_add

  !> The segments of one pressure load that touch this rank's owned nodes.
  type :: pressure_rt_t
    real(dp) :: p = 0.0_dp
    integer :: amp = 0
    integer :: nseg = 0
    integer :: nen_max = 0
    integer :: ngp_max = 0
    !> Nodes and Gauss points per segment (nseg); local nodes (nen_max, nseg).
    integer, allocatable :: nen(:), ng(:)
    integer, allocatable :: lnode(:,:)
    !> Shape values and derivatives d/dt at the Gauss points (nen_max, ngp_max, nseg), and
    !! the weights w_q/2 on [0, 1] (ngp_max, nseg).
    real(dp), allocatable :: r(:,:,:), dr(:,:,:), w(:,:)
  end type pressure_rt_t

contains

  !> The rank's part of the pressure load p (amplitude amp) on surface `surf` (global nodes):
  !! the segments with an owned node (g2l(node) in 1..nowned), their local nodes, shape
  !! data and weights.
  subroutine pressure_setup(surf, p, amp, g2l, nowned, pr)
    type(contact_surface_t), intent(in) :: surf
    real(dp), intent(in) :: p
    integer, intent(in) :: amp, g2l(:), nowned
    type(pressure_rt_t), intent(out) :: pr
    integer :: s, k, q, n, ng
    real(dp) :: xi(MAX_SEG_NODES), wq(MAX_SEG_NODES), r(MAX_SEG_NODES), dr(MAX_SEG_NODES), &
        ddr(MAX_SEG_NODES)
    pr%p = p
    pr%amp = amp
    pr%nen_max = max(surf%nen_max, 1)
    pr%ngp_max = pr%nen_max
    n = 0
    do s = 1, surf%nseg
      if (touches(s)) n = n + 1
    end do
    pr%nseg = n
    allocate(pr%nen(n), pr%ng(n), pr%lnode(pr%nen_max, n), source=0)
    allocate(pr%r(pr%nen_max, pr%ngp_max, n), pr%dr(pr%nen_max, pr%ngp_max, n), &
        pr%w(pr%ngp_max, n), source=0.0_dp)
    k = 0
    do s = 1, surf%nseg
      if (.not. touches(s)) cycle
      k = k + 1
      pr%nen(k) = surf%nen(s)
      ! the segment's degree + 1 points: 2 on a linear edge, 3 on a quadratic one, p + 1 on a
      ! Bezier span of degree p
      ng = surf%nen(s)
      pr%ng(k) = ng
      pr%lnode(1:ng, k) = g2l(surf%conn(1:ng, s))
      call gauss_legendre(ng, xi(1:ng), wq(1:ng))
      do q = 1, ng
        call segment_shape(surf, s, 0.5_dp*(1.0_dp + xi(q)), r, dr, ddr)
        pr%r(1:ng, q, k) = r(1:ng)
        pr%dr(1:ng, q, k) = dr(1:ng)
        pr%w(q, k) = 0.5_dp*wq(q)
      end do
    end do

  contains

    logical function touches(ss)
      integer, intent(in) :: ss
      integer :: a, l
      touches = .false.
      do a = 1, surf%nen(ss)
        l = g2l(surf%conn(a, ss))
        if (l >= 1 .and. l <= nowned) touches = .true.
      end do
    end function touches
  end subroutine pressure_setup

  !> Adds scale * (the pressure forces) to the owned rows of f (2, nlocal). x0 are the local
  !! reference coordinates (2, nlocal); with `follow` the segments are taken on x0 + u.
  pure subroutine pressure_add(pr, scale, x0, u, follow, nowned, f)
    type(pressure_rt_t), intent(in) :: pr
    real(dp), intent(in) :: scale, x0(:,:), u(:,:)
    logical, intent(in) :: follow
    integer, intent(in) :: nowned
    real(dp), intent(inout) :: f(:,:)
    real(dp) :: xl(2, MAX_SEG_NODES), fl(2, MAX_SEG_NODES), xp(2), pw
    integer :: k, q, a, n, l
    if (pr%nseg == 0) return
    pw = -scale*pr%p
    do k = 1, pr%nseg
      n = pr%nen(k)
      do a = 1, n
        l = pr%lnode(a, k)
        xl(:, a) = x0(:, l)
        if (follow) xl(:, a) = xl(:, a) + u(:, l)
      end do
      fl(:, 1:n) = 0.0_dp
      do q = 1, pr%ng(k)
        xp = 0.0_dp
        do a = 1, n
          xp = xp + pr%dr(a, q, k)*xl(:, a)
        end do
        ! n dGamma = (x'_y, -x'_x) dt
        do a = 1, n
          fl(1, a) = fl(1, a) + pr%w(q, k)*pr%r(a, q, k)*xp(2)
          fl(2, a) = fl(2, a) - pr%w(q, k)*pr%r(a, q, k)*xp(1)
        end do
      end do
      do a = 1, n
        l = pr%lnode(a, k)
        if (l <= nowned) f(:, l) = f(:, l) + pw*fl(:, a)
      end do
    end do
  end subroutine pressure_add
end module ictus_solver_pressure
