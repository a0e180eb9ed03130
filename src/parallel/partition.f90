!> The calls to METIS: element partitioning (dual graph: elements are neighbours when they
!! share a side: an edge, two nodes, in 2D; a face of a hexahedron, four nodes, in 3D) and the
!! nested-dissection order of a sparse factorisation.
module ictus_parallel_partition
  use, intrinsic :: iso_c_binding, only: c_int, c_null_ptr, c_ptr, c_loc
  use ictus_parallel_metis_kinds, only: idx_t
  implicit none
  private
  public :: partition_elements, nested_dissection

  interface
    function metis_partmeshdual(ne, nn, eptr, eind, vwgt, vsize, ncommon, nparts, tpwgts, &
        options, objval, epart, npart) bind(c, name='METIS_PartMeshDual') result(status)
      import :: c_int, c_ptr, idx_t
      integer(idx_t), intent(in) :: ne, nn, ncommon, nparts
      integer(idx_t), intent(in) :: eptr(*), eind(*)
      type(c_ptr), value :: vwgt, vsize, tpwgts, options
      integer(idx_t), intent(out) :: objval
      integer(idx_t), intent(out) :: epart(*), npart(*)
      integer(c_int) :: status
    end function metis_partmeshdual
    function metis_nodend(nvtxs, xadj, adjncy, vwgt, options, perm, iperm) &
        bind(c, name='METIS_NodeND') result(status)
      import :: c_int, c_ptr, idx_t
      integer(idx_t), intent(in) :: nvtxs
      integer(idx_t), intent(in) :: xadj(*), adjncy(*)
      type(c_ptr), value :: vwgt, options
      integer(idx_t), intent(out) :: perm(*), iperm(*)
      integer(c_int) :: status
    end function metis_nodend
  end interface

contains

  !> Splits nel elements (nen(e) nodes each, conn(nen_max, nel) in 1..nn) into nparts parts.
  !! part(e) in 0..nparts-1. `ierr` /= 0 when METIS fails. METIS with default options is
  !! deterministic, so every rank computing it gets the same partition. ncommon: the nodes two
  !! neighbouring elements share (2 in 2D: an edge; 4 in 3D: a face, not an edge, of the
  !! hexahedra, whose edges hold at most 3 nodes).
  subroutine partition_elements(nn, nel, nen_max, nen, conn, nparts, part, ierr, ncommon)
    integer, intent(in) :: nn, nel, nen_max, nparts, ncommon
    integer, intent(in) :: nen(nel), conn(nen_max, nel)
    integer, intent(out) :: part(nel)
    integer, intent(out) :: ierr
    integer(idx_t), allocatable :: eptr(:), eind(:), epart(:), npart(:)
    integer(idx_t) :: objval
    integer :: e, k
    ierr = 0
    if (nparts <= 1 .or. nel == 0) then
      part = 0
      return
    end if
    allocate(eptr(nel + 1), eind(sum(nen)), epart(nel), npart(nn))
    eptr(1) = 0
    k = 0
    do e = 1, nel
      eind(k + 1:k + nen(e)) = int(conn(1:nen(e), e) - 1, idx_t)
      k = k + nen(e)
      eptr(e + 1) = int(k, idx_t)
    end do
    ierr = 1 - metis_partmeshdual(int(nel, idx_t), int(nn, idx_t), eptr, eind, c_null_ptr, &
        c_null_ptr, int(ncommon, idx_t), int(nparts, idx_t), c_null_ptr, c_null_ptr, objval, epart, npart)
    part = int(epart)
  end subroutine partition_elements

  !> Fill-reducing order of the symmetric pattern (row_ptr, col) of n rows (1-based, full
  !! rows; the diagonal is skipped): order(k) = the row eliminated k-th. METIS nested
  !! dissection with default options, deterministic. `ierr` /= 0 when METIS fails.
  subroutine nested_dissection(n, row_ptr, col, order, ierr)
    integer, intent(in) :: n, row_ptr(n + 1), col(*)
    integer, intent(out) :: order(n)
    integer, intent(out) :: ierr
    integer(idx_t), allocatable :: xadj(:), adjncy(:), perm(:), iperm(:)
    integer :: i, p, k
    ierr = 0
    if (n <= 2) then
      order = [(i, i = 1, n)]
      return
    end if
    allocate(xadj(n + 1), adjncy(row_ptr(n + 1) - 1), perm(n), iperm(n))
    k = 0
    xadj(1) = 0
    do i = 1, n
      do p = row_ptr(i), row_ptr(i + 1) - 1
        if (col(p) == i) cycle
        k = k + 1
        adjncy(k) = int(col(p) - 1, idx_t)
      end do
      xadj(i + 1) = int(k, idx_t)
    end do
    ierr = 1 - metis_nodend(int(n, idx_t), xadj, adjncy, c_null_ptr, c_null_ptr, perm, iperm)
    ! METIS: perm(new) = old (0-based)
    order = int(perm) + 1
  end subroutine nested_dissection
end module ictus_parallel_partition
