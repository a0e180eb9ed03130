!> The only module that talks to MPI: start-up, shut-down, rank queries, reductions and
!! broadcasts on a duplicate of MPI_COMM_WORLD.
module ictus_parallel_env
  use mpi_f08, only: MPI_Comm, MPI_COMM_WORLD, MPI_Init, MPI_Initialized, MPI_Finalize, &
      MPI_Finalized, MPI_Comm_dup, MPI_Comm_rank, MPI_Comm_size, MPI_Comm_free, MPI_INFO_NULL, &
      MPI_Allreduce, MPI_Bcast, MPI_Barrier, MPI_IN_PLACE, MPI_SUM, MPI_MAX, MPI_MIN, &
      MPI_DOUBLE_PRECISION, MPI_INTEGER, MPI_INTEGER8, MPI_CHARACTER, MPI_LOGICAL, MPI_LOR, &
      MPI_Request, MPI_Isend, MPI_Irecv, MPI_Waitall, MPI_STATUSES_IGNORE, MPI_Alltoall, &
      MPI_Allgatherv, MPI_Allgather, MPI_Comm_split_type, MPI_COMM_TYPE_SHARED
  use ictus_core_kinds, only: dp, i8
  use ictus_core_errors, only: stop_hook, set_error_prefix
  use ictus_core_logger, only: log_set_root
  implicit none
  private
  public :: env_init, env_finalize, env_rank, env_size, env_node_size, env_is_root, env_comm_f, &
      env_info_null_f, allreduce_sum, allreduce_max, allreduce_min, allreduce_or, bcast, barrier, &
      alltoall_int, exchange, allgatherv_real, allgatherv_int, allgather_int

  !> Sum over all ranks, in place.
  interface allreduce_sum
    module procedure sum_real, sum_real_array, sum_real_array2, sum_int, sum_i8
  end interface allreduce_sum
  !> Maximum over all ranks, in place.
  interface allreduce_max
    module procedure max_real, max_int, max_real_array
  end interface allreduce_max
  !> Minimum over all ranks, in place.
  interface allreduce_min
    module procedure min_real
  end interface allreduce_min
  !> Point-to-point exchange with neighbour ranks (Isend/Irecv/Waitall).
  interface exchange
    module procedure exchange_int, exchange_real
  end interface exchange
  !> Broadcast from rank 0.
  interface bcast
    module procedure bcast_int, bcast_int_array, bcast_real_array, bcast_string, bcast_logical
  end interface bcast

  !> ictus' communicator (a duplicate of MPI_COMM_WORLD).
  type(MPI_Comm) :: comm
  integer :: rank = 0
  integer :: nranks = 1
  !> Ranks on this rank's node (shared memory).
  integer :: node_ranks = 1
  logical :: started = .false.

contains

  !> Starts MPI (if not yet started), duplicates the world communicator and sets the hooks.
  subroutine env_init()
    logical :: flag
    type(MPI_Comm) :: node_comm
    call MPI_Initialized(flag)
    if (.not. flag) call MPI_Init()
    call MPI_Comm_dup(MPI_COMM_WORLD, comm)
    call MPI_Comm_rank(comm, rank)
    call MPI_Comm_size(comm, nranks)
    call MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, node_comm)
    call MPI_Comm_size(node_comm, node_ranks)
    call MPI_Comm_free(node_comm)
    started = .true.
    call set_error_prefix(rank == 0)
    call log_set_root(rank == 0)
    stop_hook => mpi_stop
  end subroutine env_init

  !> Shuts MPI down (collective).
  subroutine env_finalize()
    logical :: flag
    if (.not. started) return
    call MPI_Finalized(flag)
    if (flag) return
    call MPI_Comm_free(comm)
    call MPI_Finalize()
    started = .false.
  end subroutine env_finalize

  !> Stop hook: collective clean exit when every rank stops with the same code, otherwise the
  !! caller should have used a collective decision first. Exit status is `code`.
  subroutine mpi_stop(code)
    integer, intent(in) :: code
    call env_finalize()
    stop code, quiet=.true.
  end subroutine mpi_stop

  integer function env_rank()
    env_rank = rank
  end function env_rank

  !> Number of ranks on this rank's node (they share its memory).
  integer function env_node_size()
    env_node_size = node_ranks
  end function env_node_size

  integer function env_size()
    env_size = nranks
  end function env_size

  logical function env_is_root()
    env_is_root = rank == 0
  end function env_is_root

  !> The communicator as a Fortran integer handle (for the HDF5 MPI-IO interface).
  integer function env_comm_f()
    env_comm_f = comm%mpi_val
  end function env_comm_f

  !> MPI_INFO_NULL as a Fortran integer handle (for the HDF5 MPI-IO interface).
  integer function env_info_null_f()
    env_info_null_f = MPI_INFO_NULL%mpi_val
  end function env_info_null_f

  subroutine barrier()
    call MPI_Barrier(comm)
  end subroutine barrier

  subroutine sum_real(x)
    real(dp), intent(inout) :: x
    if (nranks > 1) call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_DOUBLE_PRECISION, MPI_SUM, comm)
  end subroutine sum_real

  subroutine sum_real_array(x)
    real(dp), intent(inout) :: x(:)
    if (nranks > 1) call MPI_Allreduce(MPI_IN_PLACE, x, size(x), MPI_DOUBLE_PRECISION, &
        MPI_SUM, comm)
  end subroutine sum_real_array

  subroutine sum_real_array2(x)
    real(dp), intent(inout), contiguous :: x(:,:)
    if (nranks > 1) call MPI_Allreduce(MPI_IN_PLACE, x, size(x), MPI_DOUBLE_PRECISION, &
        MPI_SUM, comm)
  end subroutine sum_real_array2

  subroutine sum_int(x)
    integer, intent(inout) :: x
    if (nranks > 1) call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_INTEGER, MPI_SUM, comm)
  end subroutine sum_int

  subroutine sum_i8(x)
    integer(i8), intent(inout) :: x
    if (nranks > 1) call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_INTEGER8, MPI_SUM, comm)
  end subroutine sum_i8

  subroutine max_real(x)
    real(dp), intent(inout) :: x
    if (nranks > 1) call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
  end subroutine max_real

  subroutine max_real_array(x)
    real(dp), intent(inout) :: x(:)
    if (nranks > 1) call MPI_Allreduce(MPI_IN_PLACE, x, size(x), MPI_DOUBLE_PRECISION, &
        MPI_MAX, comm)
  end subroutine max_real_array

  subroutine max_int(x)
    integer, intent(inout) :: x
    if (nranks > 1) call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_INTEGER, MPI_MAX, comm)
  end subroutine max_int

  subroutine min_real(x)
    real(dp), intent(inout) :: x
    if (nranks > 1) call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_DOUBLE_PRECISION, MPI_MIN, comm)
  end subroutine min_real

  subroutine allreduce_or(x)
    logical, intent(inout) :: x
    if (nranks > 1) call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_LOGICAL, MPI_LOR, comm)
  end subroutine allreduce_or

  subroutine bcast_int(x)
    integer, intent(inout) :: x
    if (nranks > 1) call MPI_Bcast(x, 1, MPI_INTEGER, 0, comm)
  end subroutine bcast_int

  subroutine bcast_logical(x)
    logical, intent(inout) :: x
    if (nranks > 1) call MPI_Bcast(x, 1, MPI_LOGICAL, 0, comm)
  end subroutine bcast_logical

  subroutine bcast_int_array(x)
    integer, intent(inout) :: x(:)
    if (nranks > 1) call MPI_Bcast(x, size(x), MPI_INTEGER, 0, comm)
  end subroutine bcast_int_array

  subroutine bcast_real_array(x)
    real(dp), intent(inout) :: x(:)
    if (nranks > 1) call MPI_Bcast(x, size(x), MPI_DOUBLE_PRECISION, 0, comm)
  end subroutine bcast_real_array

  !> Broadcasts an allocatable string of any length from rank 0.
  subroutine bcast_string(s)
    character(len=:), allocatable, intent(inout) :: s
    integer :: n
    if (nranks == 1) return
    n = 0
    if (rank == 0) n = len(s)
    call MPI_Bcast(n, 1, MPI_INTEGER, 0, comm)
    if (rank /= 0) then
      if (allocated(s)) deallocate(s)
      allocate(character(len=n) :: s)
    end if
    if (n > 0) call MPI_Bcast(s, n, MPI_CHARACTER, 0, comm)
  end subroutine bcast_string

  !> Every rank sends sendcounts(q) items to rank q-1 and learns recvcounts(q) from it.
  subroutine alltoall_int(sendcounts, recvcounts)
    integer, intent(in) :: sendcounts(:)
    integer, intent(out) :: recvcounts(:)
    if (nranks == 1) then
      recvcounts = sendcounts
      return
    end if
    call MPI_Alltoall(sendcounts, 1, MPI_INTEGER, recvcounts, 1, MPI_INTEGER, comm)
  end subroutine alltoall_int

  !> Gathers every rank's `x` (its own length) into `all` on every rank, in rank order.
  !! `displs` (the offsets of the ranks' parts, 0-based), when given, saves computing them:
  !! then nothing is allocated (for use in the time loop).
  subroutine allgatherv_real(x, counts, all, displs)
    real(dp), intent(in) :: x(:)
    integer, intent(in) :: counts(:)
    real(dp), intent(out) :: all(:)
    integer, intent(in), optional :: displs(:)
    if (nranks == 1) then
      all(1:size(x)) = x
    else if (present(displs)) then
      call MPI_Allgatherv(x, size(x), MPI_DOUBLE_PRECISION, all, counts, displs, &
          MPI_DOUBLE_PRECISION, comm)
    else
      call MPI_Allgatherv(x, size(x), MPI_DOUBLE_PRECISION, all, counts, offsets(counts), &
          MPI_DOUBLE_PRECISION, comm)
    end if
  end subroutine allgatherv_real

  !> 0-based offsets of consecutive parts of the given sizes.
  pure function offsets(counts) result(displs)
    integer, intent(in) :: counts(:)
    integer :: displs(size(counts))
    integer :: q
    displs(1) = 0
    do q = 2, size(counts)
      displs(q) = displs(q - 1) + counts(q - 1)
    end do
  end function offsets

  !> Gathers every rank's `x` (its own length) into `all` on every rank, in rank order.
  subroutine allgatherv_int(x, counts, all)
    integer, intent(in) :: x(:)
    integer, intent(in) :: counts(:)
    integer, intent(out) :: all(:)
    if (nranks == 1) then
      all(1:size(x)) = x
      return
    end if
    call MPI_Allgatherv(x, size(x), MPI_INTEGER, all, counts, offsets(counts), MPI_INTEGER, &
        comm)
  end subroutine allgatherv_int

  !> Gathers one integer per rank into `all(nranks)` on every rank.
  subroutine allgather_int(x, all)
    integer, intent(in) :: x
    integer, intent(out) :: all(:)
    if (nranks == 1) then
      all(1) = x
      return
    end if
    call MPI_Allgather(x, 1, MPI_INTEGER, all, 1, MPI_INTEGER, comm)
  end subroutine allgather_int

  !> Sends sendbuf(send_ptr(k):send_ptr(k+1)-1) to rank neigh(k) and receives
  !! recvbuf(recv_ptr(k):recv_ptr(k+1)-1) from it, for k = 1..size(neigh).
  subroutine exchange_int(neigh, send_ptr, sendbuf, recv_ptr, recvbuf)
    integer, intent(in) :: neigh(:), send_ptr(:), recv_ptr(:)
    integer, intent(in) :: sendbuf(:)
    integer, intent(inout) :: recvbuf(:)
    type(MPI_Request) :: req(2*size(neigh))
    integer :: k, n
    n = size(neigh)
    do k = 1, n
      call MPI_Irecv(recvbuf(recv_ptr(k):), recv_ptr(k + 1) - recv_ptr(k), MPI_INTEGER, &
          neigh(k), 7, comm, req(k))
    end do
    do k = 1, n
      call MPI_Isend(sendbuf(send_ptr(k):), send_ptr(k + 1) - send_ptr(k), MPI_INTEGER, &
          neigh(k), 7, comm, req(n + k))
    end do
    if (n > 0) call MPI_Waitall(2*n, req, MPI_STATUSES_IGNORE)
  end subroutine exchange_int

  !> As exchange_int for real buffers.
  subroutine exchange_real(neigh, send_ptr, sendbuf, recv_ptr, recvbuf)
    integer, intent(in) :: neigh(:), send_ptr(:), recv_ptr(:)
    real(dp), intent(in) :: sendbuf(:)
    real(dp), intent(inout) :: recvbuf(:)
    type(MPI_Request) :: req(2*size(neigh))
    integer :: k, n
    n = size(neigh)
    do k = 1, n
      call MPI_Irecv(recvbuf(recv_ptr(k):), recv_ptr(k + 1) - recv_ptr(k), &
          MPI_DOUBLE_PRECISION, neigh(k), 8, comm, req(k))
    end do
    do k = 1, n
      call MPI_Isend(sendbuf(send_ptr(k):), send_ptr(k + 1) - send_ptr(k), &
          MPI_DOUBLE_PRECISION, neigh(k), 8, comm, req(n + k))
    end do
    if (n > 0) call MPI_Waitall(2*n, req, MPI_STATUSES_IGNORE)
  end subroutine exchange_real
end module ictus_parallel_env
