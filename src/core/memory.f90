!> Allocation of the large arrays that the time loop streams through (matrices, state vectors).
!!
!! The explicit step is memory-bound: every step streams the stiffness blocks, their column
!! indices and a few vectors from main memory. With 4 KiB pages the hardware prefetchers of
!! x86-64 stop at every page boundary and each page costs a TLB entry; on Linux with
!! transparent huge pages in `madvise` mode (the Debian default) the kernel backs a region with
!! 2 MiB pages only when asked. `alloc_stream` allocates an array, asks for huge pages
!! (madvise(MADV_HUGEPAGE)) before the first touch, and then fills it, so the pages are huge
!! from the start. The advice changes no value; where it is not available (another kernel,
!! THP switched off) the call fails quietly and the array is an ordinary one.
!! Measured effect: doc/performance.md §3.1.
!!
!! `available_memory` tells a large setup allocation (the Cholesky factor of a consistent
!! mass) whether it fits, before the kernel's out-of-memory killer decides.
module ictus_core_memory
  use, intrinsic :: iso_c_binding, only: c_ptr, c_int, c_size_t, c_intptr_t, c_loc, c_null_ptr
  use ictus_core_kinds, only: dp, i8
  use ictus_core_errors, only: warning
  implicit none
  private
  public :: alloc_stream, available_memory

  !> Linux <asm-generic/mman-common.h>: MADV_HUGEPAGE.
  integer(c_int), parameter :: madv_hugepage = 14_c_int
  !> Arrays smaller than this are left alone (they fit in the caches anyway).
  integer(c_size_t), parameter :: min_bytes = 4_c_size_t*1024_c_size_t**2
  integer(c_intptr_t), parameter :: page = 4096_c_intptr_t

  interface
    function c_madvise(addr, length, advice) bind(c, name='madvise') result(ierr)
      import :: c_ptr, c_size_t, c_int
      type(c_ptr), value :: addr
      integer(c_size_t), value :: length
      integer(c_int), value :: advice
      integer(c_int) :: ierr
    end function c_madvise
  end interface

  !> call alloc_stream(a, n1[, n2[, n3]], value): allocate(a(n1, ...)), ask for huge pages,
  !! then a = value (the first touch). `a` must not be allocated on entry.
  interface alloc_stream
    module procedure alloc_real1, alloc_real2, alloc_real3, alloc_int1
  end interface alloc_stream

contains

  subroutine alloc_real1(a, n1, value)
    real(dp), allocatable, target, intent(inout) :: a(:)
    integer, intent(in) :: n1
    real(dp), intent(in) :: value
    allocate(a(n1))
    if (n1 > 0) call advise_huge(c_loc(a), int(n1, c_size_t)*8_c_size_t)
    a = value
  end subroutine alloc_real1

  subroutine alloc_real2(a, n1, n2, value)
    real(dp), allocatable, target, intent(inout) :: a(:,:)
    integer, intent(in) :: n1, n2
    real(dp), intent(in) :: value
    allocate(a(n1, n2))
    if (size(a) > 0) call advise_huge(c_loc(a), int(size(a), c_size_t)*8_c_size_t)
    a = value
  end subroutine alloc_real2

  subroutine alloc_real3(a, n1, n2, n3, value)
    real(dp), allocatable, target, intent(inout) :: a(:,:,:)
    integer, intent(in) :: n1, n2, n3
    real(dp), intent(in) :: value
    allocate(a(n1, n2, n3))
    if (size(a) > 0) call advise_huge(c_loc(a), int(size(a), c_size_t)*8_c_size_t)
    a = value
  end subroutine alloc_real3

  subroutine alloc_int1(a, n1, value)
    integer, allocatable, target, intent(inout) :: a(:)
    integer, intent(in) :: n1
    integer, intent(in) :: value
    allocate(a(n1))
    if (n1 > 0) call advise_huge(c_loc(a), int(n1, c_size_t)*4_c_size_t)
    a = value
  end subroutine alloc_int1

  !> madvise(MADV_HUGEPAGE) on the whole pages inside [addr, addr + nbytes); errors ignored.
  subroutine advise_huge(addr, nbytes)
    type(c_ptr), intent(in) :: addr
    integer(c_size_t), intent(in) :: nbytes
    integer(c_intptr_t) :: first, last
    integer(c_int) :: ierr
    if (nbytes < min_bytes) return
    first = transfer(addr, 0_c_intptr_t)
    last = first + int(nbytes, c_intptr_t)
    first = ((first + page - 1)/page)*page
    last = (last/page)*page
    if (last <= first) return
    ierr = c_madvise(transfer(first, c_null_ptr), int(last - first, c_size_t), madv_hugepage)
  end subroutine advise_huge

  !> Bytes of memory still available on this node: MemAvailable of /proc/meminfo, capped by
  !! the environment variable ICTUS_MEMORY_LIMIT_MB when it is set (a batch job's limit,
  !! which /proc/meminfo does not show); -1 when neither is known.
  function available_memory() result(bytes)
    integer(i8) :: bytes
    character(len=256) :: line, ev
    integer :: u, ios, st, n
    integer(i8) :: kb
    real(dp) :: mb
    bytes = -1
    open(newunit=u, file='/proc/meminfo', status='old', action='read', iostat=ios)
    if (ios == 0) then
      do
        read(u, '(a)', iostat=ios) line
        if (ios /= 0) exit
        if (line(1:13) == 'MemAvailable:') then
          read(line(14:), *, iostat=st) kb
          if (st == 0) bytes = kb*1024_i8
          exit
        end if
      end do
      close(u)
    end if
    call get_environment_variable('ICTUS_MEMORY_LIMIT_MB', ev, length=n, status=st)
    if (st /= 0 .or. n == 0) return
    ! a plain decimal number (no exponent: nothing can overflow)
    mb = -1.0_dp
    if (verify(trim(ev), '0123456789.') == 0 .and. len_trim(ev) <= 12) then
      read(ev, *, iostat=ios) mb
      if (ios /= 0) mb = -1.0_dp
    end if
    if (.not. mb > 0.0_dp) then
      call warning('ICTUS_MEMORY_LIMIT_MB', 'expected a plain number of megabytes > 0 '// &
          '(digits and a point), got "'//trim(ev)//'"; ignored')
    else if (bytes < 0) then
      bytes = int(mb*1024.0_dp**2, i8)
    else
      bytes = min(bytes, int(mb*1024.0_dp**2, i8))
    end if
  end function available_memory
end module ictus_core_memory
