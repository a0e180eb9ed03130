!> Stand-in for `ictus --check` used by the bad-deck tests until the real executable works:
!! reads the deck given as the first argument and exits with status 1 when it has errors.
program deck_check_driver
  use ictus_core_errors, only: error_count
  use ictus_io_deck_types, only: deck_t
  use ictus_io_deck_reader, only: read_deck
  implicit none
  type(deck_t) :: deck
  character(len=:), allocatable :: path
  integer :: n

  call get_command_argument(1, length=n)
  allocate(character(len=n) :: path)
  call get_command_argument(1, path)
  call read_deck(path, deck)
  if (error_count() > 0) stop 1, quiet=.true.
end program deck_check_driver
