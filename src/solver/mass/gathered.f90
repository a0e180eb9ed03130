!> The whole consistent mass and the loads gathered on every rank, for the solvers that solve
!! the whole system on every rank (Cholesky, Kronecker), so that the solution is the same bits
!! on any number of ranks.
module ictus_solver_mass_gathered
  use ictus_core_kinds, only: dp
  use ictus_core_memory, only: alloc_stream
  use ictus_parallel_env, only: allgather_int, allgatherv_int, allgatherv_real, env_size
  use ictus_solver_sparse, only: csr_t, csr_diagonal
  use ictus_solver_domain, only: domain_t
  use ictus_solver_mass_solver, only: mass_core_t
  implicit none
  private
  public :: gathered_mass_t, gathered_t, gather_mass, gathered_setup, gathered_loads

  !> The whole consistent mass in the order of the global node numbers (made once by
  !! `gather_mass`, `ready` then): row_ptr(ng + 1), col (global ids, sorted), val, keep(ng, nd)
  !! the dofs of the nd components (2 or 3) to solve (free, and the node has mass: the CG's rule), cnt the owned nodes of
  !! every rank and gid the global id of every gathered node.
  type :: gathered_mass_t
    logical :: ready = .false.
    integer, allocatable :: cnt(:), gid(:), row_ptr(:), col(:)
    real(dp), allocatable :: val(:)
    logical, allocatable :: keep(:,:)
  end type gathered_mass_t

  !> The buffers of the solves on gathered loads: the sizes of every rank's part (nd x its
  !! owned nodes, nd components) and their offsets, this rank's offset in nodes, the send
  !! buffer (nd nn), the gathered f (nd nglobal) and the solution x (nd, nglobal).
  type :: gathered_t
    integer, allocatable :: counts(:), displs(:)
    integer :: offset = 0
    real(dp), allocatable :: fsend(:), fall(:), x(:,:)
  end type gathered_t

contains

  !> gm <- the owned rows of m of every rank (rows of the operator c, dofs `fixed`), once.
  subroutine gather_mass(gm, c, dom, m, fixed)
    type(gathered_mass_t), intent(inout) :: gm
    type(mass_core_t), intent(in) :: c
    type(domain_t), intent(in) :: dom
    type(csr_t), intent(in) :: m
    logical, intent(in) :: fixed(:,:)
    integer, allocatable :: ncnt(:), len_all(:), col_all(:), keep_all(:), keep_loc(:)
    real(dp), allocatable :: val_all(:), d(:)
    integer :: nn, ng, np, i, k, p, q, c2, g, nnz, nd
    if (gm%ready) return
    gm%ready = .true.
    nn = c%nn
    ng = c%nglobal
    np = env_size()
    allocate(d(nn))
    call csr_diagonal(m, d)
    allocate(gm%cnt(np), ncnt(np), gm%gid(ng), len_all(ng))
    ! rows: global ids and lengths, then columns (global ids), values and kept dofs
    call allgather_int(nn, gm%cnt)
    call allgatherv_int(dom%halo%gid(1:nn), gm%cnt, gm%gid)
    call allgatherv_int(m%g%row_ptr(2:nn + 1) - m%g%row_ptr(1:nn), gm%cnt, len_all)
    nnz = m%g%row_ptr(nn + 1) - 1
    call allgather_int(nnz, ncnt)
    allocate(col_all(sum(ncnt)), val_all(sum(ncnt)))
    call allgatherv_int(dom%halo%gid(m%g%col(1:nnz)), ncnt, col_all)
    call allgatherv_real(m%val(1:nnz), ncnt, val_all)
    nd = size(fixed, 1)
    allocate(keep_loc(nd*nn), keep_all(nd*ng))
    do i = 1, nn
      do c2 = 1, nd
        keep_loc(nd*(i - 1) + c2) = merge(1, 0, .not. fixed(c2, i) .and. d(i) > 0.0_dp)
      end do
    end do
    call allgatherv_int(keep_loc, nd*gm%cnt, keep_all)
    ! the global matrix in the order of the global node numbers
    allocate(gm%row_ptr(ng + 1), gm%col(size(col_all)), gm%val(size(col_all)), gm%keep(ng, nd))
    associate (row_ptr => gm%row_ptr, col => gm%col, val => gm%val, keep => gm%keep, &
        gid => gm%gid)
      row_ptr(1) = 1
      do q = 1, ng
        row_ptr(gid(q) + 1) = len_all(q)
      end do
      do g = 1, ng
        row_ptr(g + 1) = row_ptr(g) + row_ptr(g + 1)
      end do
      k = 1
      do q = 1, ng
        g = gid(q)
        p = row_ptr(g)
        col(p:p + len_all(q) - 1) = col_all(k:k + len_all(q) - 1)
        val(p:p + len_all(q) - 1) = val_all(k:k + len_all(q) - 1)
        keep(g, :) = keep_all(nd*(q - 1) + 1:nd*q) == 1
        k = k + len_all(q)
      end do
    end associate
  end subroutine gather_mass

  !> The buffers of g for the operator c, with cnt the owned nodes of every rank.
  subroutine gathered_setup(g, c, dom, cnt)
    type(gathered_t), intent(inout) :: g
    type(mass_core_t), intent(in) :: c
    type(domain_t), intent(in) :: dom
    integer, intent(in) :: cnt(:)
    integer :: q, nd
    nd = size(c%free, 1)
    g%counts = nd*cnt
    g%displs = [0, (sum(g%counts(1:q)), q = 1, size(cnt) - 1)]
    g%offset = g%displs(dom%rank + 1)/nd
    call alloc_stream(g%x, nd, c%nglobal, 0.0_dp)
    allocate(g%fsend(nd*c%nn), g%fall(nd*c%nglobal))
  end subroutine gathered_setup

  !> g%fall <- f on the free dofs of every rank's owned nodes, in rank order (allocates
  !! nothing).
  subroutine gathered_loads(g, c, f)
    type(gathered_t), intent(inout) :: g
    type(mass_core_t), intent(in) :: c
    real(dp), intent(in) :: f(:,:)
    integer :: i, nd
    nd = size(c%free, 1)
    do i = 1, c%nn
      g%fsend(nd*(i - 1) + 1:nd*i) = f(1:nd, i)*c%free(1:nd, i)
    end do
    call allgatherv_real(g%fsend, g%counts, g%fall, g%displs)
  end subroutine gathered_loads
end module ictus_solver_mass_gathered
