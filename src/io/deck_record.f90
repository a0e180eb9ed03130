!> The bulk data of the processed deck in the results file: the lines the record of
!! `deck_echo(deck, .true., record=.true.)` replaces by "** data: <group>, <n> lines" are
!! written to <group> as exact integers and doubles (doc/results.md "The processed deck").
!!
!! Each group has the attribute `columns`, the names of its datasets in the order their
!! values appear on a data line; a line is row k of each of them. A group with the attribute
!! `per_line` has one 1-D dataset whose values fill lines of `per_line` values (the ids of a
!! set). Writing binary data instead of formatted text keeps the record exact and costs
!! next to nothing on big meshes.
module ictus_io_deck_record
  use ictus_core_kinds, only: dp, i8
  use ictus_io_deck_types, only: deck_t
  use ictus_io_deck_echo, only: record_path
  use ictus_io_hdf5_util, only: hid_t, h5u_group, h5u_close_group, h5u_attr_string, &
      h5u_attr_int, h5u_write
  implicit none
  private
  public :: deck_record_write, deck_record_digest

  !> Values per line of a set's ids (as in the deck echo).
  integer, parameter :: set_per_line = 8
  !> Two primes below 2^31 and their bases for the digest: h <- mod(h B + v, P) stays
  !! below 2^62 for values v below 2^32.
  integer(i8), parameter :: p1 = 2147483647_i8, b1 = 1000003_i8
  integer(i8), parameter :: p2 = 2147483629_i8, b2 = 998244353_i8

  !> The running digest: two polynomial hashes.
  type :: digest_t
    integer(i8) :: h1 = 0, h2 = 0
  end type digest_t

contains

  !> Writes the groups /deck/... of the record to the open results file (collective; rank 0
  !! writes the data).
  subroutine deck_record_write(file, d)
    integer(hid_t), intent(in) :: file
    type(deck_t), intent(in) :: d
    integer(hid_t) :: top, g
    integer :: k
    call h5u_group(file, 'deck', top)
    if (d%n_nodes > 0) then
      call open_group(file, record_path('nodes', 1), 'ids coordinates', g)
      call h5u_write(g, 'ids', d%node_ids(1:d%n_nodes))
      call h5u_write(g, 'coordinates', d%node_x(:, 1:d%n_nodes))
      call h5u_close_group(g)
    end if
    do k = 1, d%n_blocks
      associate (b => d%blocks(k))
        if (size(b%ids) == 0) cycle
        call open_group(file, record_path('elements', k), 'ids connectivity', g)
        call h5u_write(g, 'ids', b%ids)
        call h5u_write(g, 'connectivity', b%conn(1:b%nen, :))
        call h5u_close_group(g)
      end associate
    end do
    do k = 1, d%n_patches
      if (.not. allocated(d%patches(k)%cp)) cycle
      if (size(d%patches(k)%cp, 2) == 0) cycle
      call open_group(file, record_path('control_points', k), 'control_points', g)
      call h5u_write(g, 'control_points', d%patches(k)%cp)
      call h5u_close_group(g)
    end do
    do k = 1, d%n_sets
      if (size(d%sets(k)%ids) == 0) cycle
      call open_group(file, record_path('sets', k), 'ids', g)
      call h5u_attr_int(g, 'per_line', set_per_line)
      call h5u_write(g, 'ids', d%sets(k)%ids)
      call h5u_close_group(g)
    end do
    call h5u_close_group(top)
  end subroutine deck_record_write

  !> Opens (creating) the group at `path` = /deck/<a>[/<b>] and gives it its `columns`.
  subroutine open_group(file, path, columns, g)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: path, columns
    integer(hid_t), intent(out) :: g
    integer(hid_t) :: parent
    integer :: cut
    cut = index(path, '/', back=.true.)
    if (cut > len('/deck/')) then
      call h5u_group(file, path(2:cut - 1), parent)
      call h5u_close_group(parent)
    end if
    call h5u_group(file, path(2:), g)
    call h5u_attr_string(g, 'columns', columns)
  end subroutine open_group

  !> A digest of the bulk data of the record (16 hex digits): decks whose nodes, elements,
  !! control points or set ids differ in any bit give different digests but for a chance
  !! of about 2^-62. A checkpoint stores it with the record (see deck_echo).
  function deck_record_digest(d) result(hex)
    type(deck_t), intent(in) :: d
    character(len=16) :: hex
    type(digest_t) :: h
    integer :: k
    call add_ints(h, d%node_ids(1:d%n_nodes))
    call add_reals(h, reshape(d%node_x(:, 1:d%n_nodes), [size(d%node_x, 1)*d%n_nodes]))
    do k = 1, d%n_blocks
      call add_ints(h, [d%blocks(k)%nen, size(d%blocks(k)%ids)])
      call add_ints(h, d%blocks(k)%ids)
      call add_ints(h, reshape(d%blocks(k)%conn, [size(d%blocks(k)%conn)]))
    end do
    do k = 1, d%n_patches
      if (.not. allocated(d%patches(k)%cp)) cycle
      call add_ints(h, [size(d%patches(k)%cp)])
      call add_reals(h, reshape(d%patches(k)%cp, [size(d%patches(k)%cp)]))
    end do
    do k = 1, d%n_sets
      call add_ints(h, [size(d%sets(k)%ids)])
      call add_ints(h, d%sets(k)%ids)
    end do
    write(hex, '(z8.8,z8.8)') h%h1, h%h2
  end function deck_record_digest

  !> Adds integers (each as one value below 2^32).
  subroutine add_ints(h, v)
    type(digest_t), intent(inout) :: h
    integer, intent(in) :: v(:)
    integer :: k
    do k = 1, size(v)
      call add(h, modulo(int(v(k), i8), 4294967296_i8))
    end do
  end subroutine add_ints

  !> Adds doubles bit for bit (each as its two 32-bit halves).
  subroutine add_reals(h, x)
    type(digest_t), intent(inout) :: h
    real(dp), intent(in) :: x(:)
    integer(i8) :: bits
    integer :: k
    do k = 1, size(x)
      bits = transfer(x(k), bits)
      call add(h, ibits(bits, 0, 32))
      call add(h, ibits(bits, 32, 32))
    end do
  end subroutine add_reals

  pure subroutine add(h, v)
    type(digest_t), intent(inout) :: h
    integer(i8), intent(in) :: v
    h%h1 = mod(h%h1*b1 + v, p1)
    h%h2 = mod(h%h2*b2 + v, p2)
  end subroutine add

end module ictus_io_deck_record
