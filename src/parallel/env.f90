!> The only module that talks to MPI: start-up, shut-down, rank queries, reductions and
!! broadcasts on a duplicate of MPI_COMM_WORLD.
module ictus_parallel_env
  use mpi_f08, only: MPI_Comm, MPI_COMM_WORLD, MPI_Init, MPI_Initialized, MPI_Finalize, &
      MPI_Finalized, MPI_Comm_dup, MPI_Comm_rank, MPI_Comm_size, MPI_Comm_free, MPI_INFO_NULL, &
      MPI_Allreduce, MPI_Bcast, MPI_Barrier, MPI_IN_PLACE, MPI_SUM, MPI_MAX, MPI_MIN, &
      MPI_DOUBLE_PRECISION, MPI_INTEGER, MPI_INTEGER8, MPI_CHARACTER, MPI_LOGICAL, MPI_LOR
  use ictus_core_kinds, only: dp, i8
  use ictus_core_errors, only: stop_hook, set_error_prefix
  use ictus_core_logger, only: log_set_root
  implicit none
  private
  public :: env_init, env_finalize, env_rank, env_size, env_is_root, env_comm_f, &
      env_info_null_f, allreduce_sum, allreduce_max, allreduce_min, allreduce_or, bcast, barrier

  !> Sum over all ranks, in place.
  interface allreduce_sum
    module procedure sum_real, sum_real_array, sum_int, sum_i8
  end interface allreduce_sum
  !> Maximum over all ranks, in place.
  interface allreduce_max
    module procedure max_real, max_int
  end interface allreduce_max
  !> Minimum over all ranks, in place.
  interface allreduce_min
    module procedure min_real
  end interface allreduce_min
  !> Broadcast from rank 0.
  interface bcast
    module procedure bcast_int, bcast_int_array, bcast_real_array, bcast_string, bcast_logical
  end interface bcast

  !> ictus' communicator (a duplicate of MPI_COMM_WORLD).
  type(MPI_Comm) :: comm
  integer :: rank = 0
  integer :: nranks = 1
  logical :: started = .false.

contains

  !> Starts MPI (if not yet started), duplicates the world communicator and sets the hooks.
  subroutine env_init()
    logical :: flag
    call MPI_Initialized(flag)
    if (.not. flag) call MPI_Init()
    call MPI_Comm_dup(MPI_COMM_WORLD, comm)
    call MPI_Comm_rank(comm, rank)
    call MPI_Comm_size(comm, nranks)
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

end module ictus_parallel_env
