!> ictus: explicit contact-impact dynamics with finite elements and NURBS (IGA).
!!
!!   ictus deck.inp [-o results.h5] [--check] [--quiet | --verbose]
!!   ictus --help | --version
!!
!! Exit status: 0 success, 1 bad input (command line or deck), 2 run-time failure, 3 stopped
!! at the wall-time limit after writing a checkpoint.
program ictus
  use, intrinsic :: iso_fortran_env, only: output_unit
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: command_arg
  use ictus_core_errors, only: input_error, terminate
  use ictus_core_logger, only: log_set_level, LOG_QUIET, LOG_VERBOSE_LEVEL
  use ictus_core_build_info, only: ictus_version, ictus_build_type
  use ictus_parallel_env, only: env_init, env_finalize, env_is_root, env_size
  use ictus_app_driver, only: run_options_t, driver_run
  implicit none
  type(run_options_t) :: opt
  character(len=:), allocatable :: arg
  integer :: i, n, ios
  logical :: exists

  call env_init()
  n = command_argument_count()
  i = 0
  do while (i < n)
    i = i + 1
    arg = command_arg(i)
    select case (arg)
    case ('-h', '--help')
      if (env_is_root()) call usage()
      call terminate(0)
    case ('--version')
      if (env_is_root()) write(output_unit, '(a)') 'ictus '//ictus_version//' ('// &
          ictus_build_type//' build)'
      call terminate(0)
    case ('--check')
      opt%check_only = .true.
    case ('-q', '--quiet')
      call log_set_level(LOG_QUIET)
    case ('-v', '--verbose')
      call log_set_level(LOG_VERBOSE_LEVEL)
    case ('--restart')
      if (i == n) then
        call input_error('command line', '--restart needs a checkpoint file '// &
            '(ictus deck.inp --restart deck.chk.h5)')
        call terminate(1)
      end if
      i = i + 1
      opt%restart_path = command_arg(i)
    case ('--wall-time')
      if (i == n) then
        call input_error('command line', '--wall-time needs a number of seconds')
        call terminate(1)
      end if
      i = i + 1
      arg = command_arg(i)
      read(arg, *, iostat=ios) opt%wall_time
      if (ios /= 0 .or. .not. opt%wall_time > 0.0_dp) then
        call input_error('command line', '--wall-time needs a positive number of seconds, '// &
            'found "'//arg//'"')
        call terminate(1)
      end if
    case ('-o', '--output')
      if (i == n) then
        call input_error('command line', arg//' needs a file name (ictus deck.inp -o results.h5)')
        call terminate(1)
      end if
      i = i + 1
      opt%out_path = command_arg(i)
    case default
      if (arg(1:1) == '-' .and. len(arg) > 1) then
        call input_error('command line', 'unknown option '//arg//' (see ictus --help)')
        call terminate(1)
      end if
      if (allocated(opt%deck_path)) then
        call input_error('command line', 'more than one deck given: '//opt%deck_path// &
            ' and '//arg)
        call terminate(1)
      end if
      opt%deck_path = arg
    end select
  end do
  if (.not. allocated(opt%deck_path)) then
    call input_error('command line', 'no input deck given (usage: ictus deck.inp '// &
        '[-o results.h5] [--check]; see ictus --help)')
    call terminate(1)
  end if
  inquire(file=opt%deck_path, exist=exists)
  if (.not. exists) then
    call input_error(opt%deck_path, 'the input deck does not exist')
    call terminate(1)
  end if
  if (env_is_root() .and. env_size() > 1) write(output_unit, '(a,i0,a)') 'ictus on ', &
      env_size(), ' MPI ranks'
  call driver_run(opt)
  call env_finalize()

contains


  subroutine usage()
    write(output_unit, '(a)') 'usage: ictus deck.inp [-o results.h5] [--check] [--restart F]'
    write(output_unit, '(a)') '             [--wall-time S] [--quiet|--verbose]'
    write(output_unit, '(a)') ''
    write(output_unit, '(a)') 'Explicit contact-impact dynamics with finite elements and NURBS.'
    write(output_unit, '(a)') ''
    write(output_unit, '(a)') '  deck.inp        input deck (doc/user-guide.md)'
    write(output_unit, '(a)') '  -o, --output F  results file (default: the deck name with .h5)'
    write(output_unit, '(a)') '  --check         check the deck and the time step, write nothing'
    write(output_unit, '(a)') '  --restart F     continue from the checkpoint F (results.chk.h5)'
    write(output_unit, '(a)') '  --wall-time S   stop after S seconds with a checkpoint (exit 3)'
    write(output_unit, '(a)') '  -q, --quiet     print errors and warnings only'
    write(output_unit, '(a)') '  -v, --verbose   print more detail'
    write(output_unit, '(a)') '  --version       print the version'
    write(output_unit, '(a)') ''
    write(output_unit, '(a)') 'Exit status: 0 success, 1 bad input, 2 run-time failure,'
    write(output_unit, '(a)') '             3 stopped at the wall-time limit (checkpoint written).'
    write(output_unit, '(a)') 'Parallel: mpirun -np N ictus deck.inp'
  end subroutine usage
end program ictus
