!> This rank's part of the model: the elements METIS gave it, the nodes it owns, the ghost
!! nodes it reads, and the elements it needs to assemble the rows of its owned nodes.
!!
!! Ownership: a node belongs to the lowest-numbered part among the elements that hold it.
!! Rows of K and M exist for owned nodes; they are assembled from every element that holds an
!! owned node, in global element order, and their columns are sorted by global node index.
!! So every row is bit for bit the row a single-rank run computes, and no sum crosses ranks.
module ictus_solver_domain
  use ictus_core_kinds, only: dp
  use ictus_core_ticker, only: ticker_t, ticker_start
  use ictus_parallel_env, only: env_rank, env_size, bcast, allreduce_sum
  use ictus_parallel_partition, only: partition_elements
  use ictus_parallel_halo, only: halo_t, halo_setup
  use ictus_geometry_mesh, only: mesh_t
  implicit none
  private
  public :: domain_t, domain_init, domain_owns

  type :: domain_t
    !> Number of ranks and this rank.
    integer :: nparts = 1
    integer :: rank = 0
    !> Global number of nodes.
    integer :: nn_global = 0
    !> METIS part of every element (0-based) and owner rank of every node (global arrays).
    integer, allocatable :: part(:)
    integer, allocatable :: owner(:)
    !> Owned and ghost nodes, halo exchange; local node k is global node halo%gid(k).
    type(halo_t) :: halo
    integer :: nowned = 0
    integer :: nlocal = 0
    !> Global -> local node index (0 when not on this rank), (nn_global).
    integer, allocatable :: g2l(:)
    !> Elements assembled on this rank (global indices, increasing) and their local
    !! connectivity (nen_max, nelem).
    integer :: nelem = 0
    integer, allocatable :: elem(:)
    integer, allocatable :: conn(:,:)
  end type domain_t

contains

  !> Partitions the mesh (a model_t is one) over the ranks (METIS on rank 0, broadcast) and
  !! sets up this rank's part. `ierr` /= 0 when METIS fails.
  subroutine domain_init(dom, model, ierr)
    type(domain_t), intent(out) :: dom
    class(mesh_t), intent(in) :: model
    integer, intent(out) :: ierr
    integer :: e, a, i, k, nn
    type(ticker_t) :: tk
    logical, allocatable :: mine(:), needed(:)
    integer, allocatable :: owned(:), ghost(:)
    nn = model%nn
    dom%nparts = env_size()
    dom%rank = env_rank()
    dom%nn_global = nn
    allocate(dom%part(model%nel), source=0)
    ierr = 0
    if (dom%nparts > 1) then
      if (dom%rank == 0) call partition_elements(nn, model%nel, model%nen_max, model%nen, &
          model%conn, dom%nparts, dom%part, ierr, merge(4, 2, model%ndm == 3))
      call bcast(ierr)
      call bcast(dom%part)
      if (ierr /= 0) return
    end if
    ! owner = lowest part among the elements of a node (nodes without elements: rank 0)
    call ticker_start(tk, 'partitioning', stride=10000)
    allocate(dom%owner(nn), source=huge(1))
    do e = 1, model%nel
      call tk%tick(e, 2*model%nel)
      do a = 1, model%nen(e)
        i = model%conn(a, e)
        dom%owner(i) = min(dom%owner(i), dom%part(e))
      end do
    end do
    where (dom%owner == huge(1)) dom%owner = 0
    allocate(mine(nn), needed(nn))
    mine = dom%owner == dom%rank
    ! elements holding an owned node, and every node of those elements
    needed = .false.
    allocate(dom%elem(model%nel))
    dom%nelem = 0
    do e = 1, model%nel
      call tk%tick(model%nel + e, 2*model%nel)
      if (any(mine(model%conn(1:model%nen(e), e)))) then
        dom%nelem = dom%nelem + 1
        dom%elem(dom%nelem) = e
        needed(model%conn(1:model%nen(e), e)) = .true.
      end if
    end do
    dom%elem = dom%elem(1:dom%nelem)
    owned = pack([(i, i = 1, nn)], mine)
    ghost = pack([(i, i = 1, nn)], needed .and. .not. mine)
    call halo_setup(dom%halo, owned, ghost, dom%owner)
    dom%nowned = dom%halo%nowned
    dom%nlocal = dom%halo%nlocal
    allocate(dom%g2l(nn), source=0)
    do k = 1, dom%nlocal
      dom%g2l(dom%halo%gid(k)) = k
    end do
    allocate(dom%conn(model%nen_max, dom%nelem), source=0)
    do k = 1, dom%nelem
      e = dom%elem(k)
      dom%conn(1:model%nen(e), k) = dom%g2l(model%conn(1:model%nen(e), e))
    end do
    k = dom%nowned
    call allreduce_sum(k)
    if (k /= nn) ierr = 2
  end subroutine domain_init

  !> Whether this rank owns local element k (dom%elem(k)): the owner of its first node. Every
  !! element has exactly one owning rank, and that rank assembles it (it holds the node), so
  !! per-element output and sums count each element once. (The METIS part of an element need
  !! not own any of its nodes.)
  pure logical function domain_owns(dom, k)
    type(domain_t), intent(in) :: dom
    integer, intent(in) :: k
    domain_owns = dom%conn(1, k) <= dom%nowned
  end function domain_owns
end module ictus_solver_domain
