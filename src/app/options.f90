!> What the command line asks of a run (main.f90 fills it, the driver and the time loop read it).
module ictus_app_options
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: run_options_t, EXIT_RUNTIME, EXIT_WALL_TIME

  type :: run_options_t
    character(len=:), allocatable :: deck_path
    character(len=:), allocatable :: out_path
    !> Read, build and check the model, print the summary and stop.
    logical :: check_only = .false.
    !> Continue from this checkpoint.
    character(len=:), allocatable :: restart_path
    !> Stop with a checkpoint after this many seconds of the time loop (0: no limit).
    real(dp) :: wall_time = 0.0_dp
  end type run_options_t

  !> Exit status of a run-time failure, and of a run stopped at its wall-time limit.
  integer, parameter :: EXIT_RUNTIME = 2, EXIT_WALL_TIME = 3
end module ictus_app_options
