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
!! mass, a refined patch, the viewing samples) whether it fits, before the allocation fails
!! or the kernel's out-of-memory killer decides: the least of what the node has free, what
!! the process's control group (a batch job's memory limit, cgroup v1 or v2) still allows,
!! what its address-space limit (`ulimit -v`) still allows, and ICTUS_MEMORY_LIMIT_MB.
module ictus_core_memory
  use, intrinsic :: iso_c_binding, only: c_ptr, c_int, c_size_t, c_intptr_t, c_loc, &
      c_null_ptr, c_long
  use ictus_core_kinds, only: dp, i8
  use ictus_core_errors, only: warning, fatal
  implicit none
  private
  public :: alloc_stream, available_memory

  !> Linux <asm-generic/mman-common.h>: MADV_HUGEPAGE.
  integer(c_int), parameter :: madv_hugepage = 14_c_int
  !> Arrays smaller than this are left alone (they fit in the caches anyway).
  integer(c_size_t), parameter :: min_bytes = 4_c_size_t*1024_c_size_t**2
  integer(c_intptr_t), parameter :: page = 4096_c_intptr_t
  !> Linux <asm-generic/resource.h>: RLIMIT_AS, the address-space limit of `ulimit -v`.
  integer(c_int), parameter :: rlimit_as = 9_c_int
  !> Control-group limits at or above this (2^60 bytes) mean "no limit".
  integer(i8), parameter :: no_limit = 2_i8**60

  !> struct rlimit of Linux x86-64 and aarch64: two unsigned longs (RLIM_INFINITY = all ones).
  type, bind(c) :: rlimit_t
    integer(c_long) :: cur, max
  end type rlimit_t

  interface
    function c_madvise(addr, length, advice) bind(c, name='madvise') result(ierr)
      import :: c_ptr, c_size_t, c_int
      type(c_ptr), value :: addr
      integer(c_size_t), value :: length
      integer(c_int), value :: advice
      integer(c_int) :: ierr
    end function c_madvise
    function c_getrlimit(resource, rlim) bind(c, name='getrlimit') result(ierr)
      import :: c_int, rlimit_t
      integer(c_int), value :: resource
      type(rlimit_t), intent(out) :: rlim
      integer(c_int) :: ierr
    end function c_getrlimit
  end interface

  !> call alloc_stream(a, n1[, n2[, n3]], value): allocate(a(n1, ...)), ask for huge pages,
  !! then a = value (the first touch). `a` must not be allocated on entry. When the memory is
  !! not there the run stops with exit status 2 and a message that gives the sizes (the
  !! set-up checks what it can foresee before: a refined patch, a Cholesky factor, the
  !! viewing samples; this is the last guard, without a backtrace).
  interface alloc_stream
    module procedure alloc_real1, alloc_real2, alloc_real3, alloc_int1
  end interface alloc_stream

contains

  subroutine alloc_real1(a, n1, value)
    real(dp), allocatable, target, intent(inout) :: a(:)
    integer, intent(in) :: n1
    real(dp), intent(in) :: value
    integer :: st
    allocate(a(n1), stat=st)
    if (st /= 0) call out_of_memory(8.0_dp*n1)
    if (n1 > 0) call advise_huge(c_loc(a), int(n1, c_size_t)*8_c_size_t)
    a = value
  end subroutine alloc_real1

  subroutine alloc_real2(a, n1, n2, value)
    real(dp), allocatable, target, intent(inout) :: a(:,:)
    integer, intent(in) :: n1, n2
    real(dp), intent(in) :: value
    integer :: st
    allocate(a(n1, n2), stat=st)
    if (st /= 0) call out_of_memory(8.0_dp*n1*real(n2, dp))
    if (size(a) > 0) call advise_huge(c_loc(a), int(size(a), c_size_t)*8_c_size_t)
    a = value
  end subroutine alloc_real2

  subroutine alloc_real3(a, n1, n2, n3, value)
    real(dp), allocatable, target, intent(inout) :: a(:,:,:)
    integer, intent(in) :: n1, n2, n3
    real(dp), intent(in) :: value
    integer :: st
    allocate(a(n1, n2, n3), stat=st)
    if (st /= 0) call out_of_memory(8.0_dp*n1*real(n2, dp)*real(n3, dp))
    if (size(a) > 0) call advise_huge(c_loc(a), int(size(a), c_size_t)*8_c_size_t)
    a = value
  end subroutine alloc_real3

  subroutine alloc_int1(a, n1, value)
    integer, allocatable, target, intent(inout) :: a(:)
    integer, intent(in) :: n1
    integer, intent(in) :: value
    integer :: st
    allocate(a(n1), stat=st)
    if (st /= 0) call out_of_memory(4.0_dp*n1)
    if (n1 > 0) call advise_huge(c_loc(a), int(n1, c_size_t)*4_c_size_t)
    a = value
  end subroutine alloc_int1

  !> Stops the run: an array of `bytes` could not be allocated.
  subroutine out_of_memory(bytes)
    real(dp), intent(in) :: bytes
    character(len=32) :: need, avail
    write(need, '(f0.1)') bytes/1.0e6_dp
    write(avail, '(f0.1)') real(available_memory(), dp)/1.0e6_dp
    call fatal('memory', 'not enough memory: an array of '//trim(need)//' MB could not be '// &
        'allocated ('//trim(avail)//' MB available: /proc/meminfo, the control group, '// &
        'ulimit -v, ICTUS_MEMORY_LIMIT_MB); a smaller model, fewer ranks per node, or more '// &
        'memory', 2)
  end subroutine out_of_memory

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

  !> Bytes of memory this process can still allocate: MemAvailable of /proc/meminfo, capped by
  !! the control group's limit less its usage, the address-space limit less the process's
  !! size (VmSize) and the environment variable ICTUS_MEMORY_LIMIT_MB when it is set (a batch
  !! job's limit that none of these shows); -1 when none is known.
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
    call cap(bytes, cgroup_room())
    call cap(bytes, address_space_room())
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

  !> bytes = min(bytes, room) where each is known (>= 0); -1 means unknown.
  subroutine cap(bytes, room)
    integer(i8), intent(inout) :: bytes
    integer(i8), intent(in) :: room
    if (room < 0) return
    if (bytes < 0) then
      bytes = room
    else
      bytes = min(bytes, room)
    end if
  end subroutine cap

  !> What the address-space limit (RLIMIT_AS) leaves: the limit less VmSize of
  !! /proc/self/status; -1 without a limit.
  function address_space_room() result(room)
    integer(i8) :: room
    type(rlimit_t) :: rl
    integer(i8) :: vm
    room = -1
    if (c_getrlimit(rlimit_as, rl) /= 0) return
    if (rl%cur < 0) return
    vm = proc_value('/proc/self/status', 'VmSize:')
    if (vm < 0) return
    room = max(int(rl%cur, i8) - vm*1024_i8, 0_i8)
  end function address_space_room

  !> What the memory limit of this process's control group leaves: limit less usage, of
  !! cgroup v2 (memory.max, memory.current) or v1 (memory.limit_in_bytes,
  !! memory.usage_in_bytes), in the group named by /proc/self/cgroup or, inside a container
  !! whose mount shows its own group at the root, at the root; -1 without a limit.
  function cgroup_room() result(room)
    integer(i8) :: room
    character(len=512) :: line, v2, v1
    integer :: u, ios, k
    room = -1
    v2 = ''
    v1 = ''
    open(newunit=u, file='/proc/self/cgroup', status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (line(1:3) == '0::') v2 = line(4:)
      k = index(line, ':memory:')
      if (k > 0) v1 = line(k + 8:)
    end do
    close(u)
    if (len_trim(v2) > 0) then
      call cap(room, group_room('/sys/fs/cgroup'//trim(v2), 'memory.max', 'memory.current'))
      call cap(room, group_room('/sys/fs/cgroup', 'memory.max', 'memory.current'))
    end if
    if (len_trim(v1) > 0) then
      call cap(room, group_room('/sys/fs/cgroup/memory'//trim(v1), 'memory.limit_in_bytes', &
          'memory.usage_in_bytes'))
      call cap(room, group_room('/sys/fs/cgroup/memory', 'memory.limit_in_bytes', &
          'memory.usage_in_bytes'))
    end if
  end function cgroup_room

  !> limit - usage of one control group's files (bytes); -1 when absent or unlimited.
  function group_room(dir, limit_file, usage_file) result(room)
    character(len=*), intent(in) :: dir, limit_file, usage_file
    integer(i8) :: room
    integer(i8) :: limit, usage
    room = -1
    limit = file_number(trim(dir)//'/'//limit_file)
    if (limit < 0 .or. limit >= no_limit) return
    usage = max(file_number(trim(dir)//'/'//usage_file), 0_i8)
    room = max(limit - usage, 0_i8)
  end function group_room

  !> The number on the first line of a file; -1 when the file is absent or holds no number
  !! (cgroup v2 writes "max" for no limit).
  function file_number(path) result(v)
    character(len=*), intent(in) :: path
    integer(i8) :: v
    character(len=64) :: line
    integer :: u, ios
    v = -1
    open(newunit=u, file=path, status='old', action='read', iostat=ios)
    if (ios /= 0) return
    read(u, '(a)', iostat=ios) line
    close(u)
    if (ios /= 0 .or. verify(trim(line), '0123456789') /= 0 .or. len_trim(line) == 0) return
    read(line, *, iostat=ios) v
    if (ios /= 0) v = -1
  end function file_number

  !> The number after `key` on its line of a /proc file (kB for the sizes); -1 when absent.
  function proc_value(path, key) result(v)
    character(len=*), intent(in) :: path, key
    integer(i8) :: v
    character(len=256) :: line
    integer :: u, ios, st
    v = -1
    open(newunit=u, file=path, status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (line(1:len(key)) == key) then
        read(line(len(key) + 1:), *, iostat=st) v
        if (st /= 0) v = -1
        exit
      end if
    end do
    close(u)
  end function proc_value
end module ictus_core_memory
