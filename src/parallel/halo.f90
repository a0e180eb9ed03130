!> Owned and ghost nodes of a rank, and the halo exchange that copies owned values to the
!! ranks that hold them as ghosts.
!!
!! Every node has one owner. A rank stores its owned nodes first (in increasing global
!! index), then its ghosts (likewise). Rows of the operators exist for owned nodes only;
!! ghosts are read-only copies refreshed by `halo_exchange`, so no floating-point sum ever
!! crosses ranks and results do not depend on the partition.
module ictus_parallel_halo
  use ictus_core_kinds, only: dp
  use ictus_parallel_env, only: env_size, env_rank, alltoall_int, exchange
  implicit none
  private
  public :: halo_t, halo_setup, halo_exchange

  type :: halo_t
    !> Owned, ghost and all local nodes.
    integer :: nowned = 0
    integer :: nghost = 0
    integer :: nlocal = 0
    !> Global index of each local node (nlocal).
    integer, allocatable :: gid(:)
    !> Neighbour ranks and, per neighbour, the local nodes sent (owned) and received (ghost).
    integer, allocatable :: neigh(:)
    integer, allocatable :: send_ptr(:), send_idx(:)
    integer, allocatable :: recv_ptr(:), recv_idx(:)
    !> Buffers (up to max_comp values per node) and the offsets of each neighbour's values
    !! in them for the number of components of the last exchange (ncomp).
    real(dp), allocatable :: sbuf(:), rbuf(:)
    integer, allocatable :: sptr2(:), rptr2(:)
    integer :: ncomp = 0
  end type halo_t

  !> Most values per node an exchange carries (a 3D vector).
  integer, parameter :: max_comp = 3

contains

  !> Sets up the halo of this rank: `owned_gid` (sorted) are the nodes it owns, `ghost_gid`
  !! (sorted) the nodes it reads, `owner(ng)` the owner rank of every global node.
  subroutine halo_setup(h, owned_gid, ghost_gid, owner)
    type(halo_t), intent(out) :: h
    integer, intent(in) :: owned_gid(:), ghost_gid(:), owner(:)
    integer :: np, q, k, i, nn_glob
    integer, allocatable :: need_count(:), give_count(:), need(:), need_ptr(:), give(:), &
        give_ptr(:), g2l(:), nbr(:)
    np = env_size()
    h%nowned = size(owned_gid)
    h%nghost = size(ghost_gid)
    h%nlocal = h%nowned + h%nghost
    h%gid = [owned_gid, ghost_gid]
    nn_glob = size(owner)
    ! ghosts grouped by owner (ghost_gid is sorted, so within a group too)
    allocate(need_count(np), give_count(np), source=0)
    do i = 1, h%nghost
      q = owner(ghost_gid(i)) + 1
      need_count(q) = need_count(q) + 1
    end do
    call alltoall_int(need_count, give_count)
    ! neighbours: ranks I need from or give to
    allocate(nbr(0))
    do q = 1, np
      if (q - 1 == env_rank()) cycle
      if (need_count(q) > 0 .or. give_count(q) > 0) nbr = [nbr, q - 1]
    end do
    h%neigh = nbr
    allocate(need_ptr(size(nbr) + 1), give_ptr(size(nbr) + 1))
    need_ptr(1) = 1
    give_ptr(1) = 1
    do k = 1, size(nbr)
      need_ptr(k + 1) = need_ptr(k) + need_count(nbr(k) + 1)
      give_ptr(k + 1) = give_ptr(k) + give_count(nbr(k) + 1)
    end do
    allocate(need(h%nghost), give(give_ptr(size(nbr) + 1) - 1))
    h%recv_ptr = need_ptr
    allocate(h%recv_idx(h%nghost))
    do k = 1, size(nbr)
      i = need_ptr(k)
      do q = 1, h%nghost
        if (owner(ghost_gid(q)) == nbr(k)) then
          need(i) = ghost_gid(q)
          h%recv_idx(i) = h%nowned + q
          i = i + 1
        end if
      end do
    end do
    ! tell every owner which of its nodes I need; learn which of mine the others need
    call exchange(nbr, need_ptr, need, give_ptr, give)
    allocate(g2l(nn_glob), source=0)
    do i = 1, h%nowned
      g2l(owned_gid(i)) = i
    end do
    h%send_ptr = give_ptr
    allocate(h%send_idx(size(give)))
    do i = 1, size(give)
      h%send_idx(i) = g2l(give(i))
    end do
    allocate(h%sbuf(max_comp*size(give)), h%rbuf(max_comp*h%nghost))
    allocate(h%sptr2(size(h%send_ptr)), h%rptr2(size(h%recv_ptr)))
    h%ncomp = 0
  end subroutine halo_setup

  !> Copies the owned values of x(nc, nlocal) (nc = 1..3 values per node: a 2D or 3D vector)
  !! into the ghost entries on the other ranks.
  subroutine halo_exchange(h, x)
    type(halo_t), intent(inout) :: h
    real(dp), intent(inout) :: x(:,:)
    integer :: i, nc
    if (size(h%neigh) == 0) return
    nc = size(x, 1)
    if (nc > max_comp) error stop 'halo_exchange: more than 3 values per node'
    if (nc /= h%ncomp) then
      h%sptr2 = nc*(h%send_ptr - 1) + 1
      h%rptr2 = nc*(h%recv_ptr - 1) + 1
      h%ncomp = nc
    end if
    do i = 1, size(h%send_idx)
      h%sbuf(nc*(i - 1) + 1:nc*i) = x(:, h%send_idx(i))
    end do
    call exchange(h%neigh, h%sptr2, h%sbuf, h%rptr2, h%rbuf)
    do i = 1, h%nghost
      x(:, h%recv_idx(i)) = h%rbuf(nc*(i - 1) + 1:nc*i)
    end do
  end subroutine halo_exchange
end module ictus_parallel_halo
