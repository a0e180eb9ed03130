!> Growing the record arrays of a `deck_t` while the deck is read: one routine per record
!! type, each making its array hold at least `n` records. The capacity doubles, so appending
!! one record per card stays linear; `finish_deck` (ictus_io_deck_reader) trims the arrays to
!! their counts after the last card.
module ictus_io_deck_grow
  use ictus_io_deck_types, only: material_in_t, element_block_in_t, set_in_t, surface_in_t, &
      boundary_in_t, velocity_in_t, mass_in_t, damping_in_t, patch_in_t, patch_op_in_t, &
      contact_pair_in_t, rigid_wall_in_t, amplitude_in_t, cload_in_t, dload_in_t, &
      interaction_in_t
  implicit none
  private
  public :: grow_materials, grow_blocks, grow_sets, grow_surfaces, grow_boundaries, &
      grow_velocities, grow_masses, grow_dampings, grow_patches, grow_patch_ops, grow_pairs, &
      grow_walls, grow_amplitudes, grow_cloads, grow_dloads, grow_interactions

contains

  !> Makes `a` hold at least `n` records.
  subroutine grow_interactions(a, n)
    type(interaction_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(interaction_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_interactions

  !> Makes `a` hold at least `n` records.
  subroutine grow_materials(a, n)
    type(material_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(material_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_materials

  !> Makes `a` hold at least `n` records.
  subroutine grow_blocks(a, n)
    type(element_block_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(element_block_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_blocks

  !> Makes `a` hold at least `n` records.
  subroutine grow_sets(a, n)
    type(set_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(set_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_sets

  !> Makes `a` hold at least `n` records.
  subroutine grow_surfaces(a, n)
    type(surface_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(surface_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_surfaces

  !> Makes `a` hold at least `n` records.
  subroutine grow_boundaries(a, n)
    type(boundary_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(boundary_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_boundaries

  !> Makes `a` hold at least `n` records.
  subroutine grow_velocities(a, n)
    type(velocity_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(velocity_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_velocities

  !> Makes `a` hold at least `n` records.
  subroutine grow_masses(a, n)
    type(mass_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(mass_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_masses

  !> Makes `a` hold at least `n` records.
  subroutine grow_dampings(a, n)
    type(damping_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(damping_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_dampings

  !> Makes `a` hold at least `n` records.
  subroutine grow_patches(a, n)
    type(patch_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(patch_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_patches

  !> Makes `a` hold at least `n` records.
  subroutine grow_patch_ops(a, n)
    type(patch_op_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(patch_op_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_patch_ops

  !> Makes `a` hold at least `n` records.
  subroutine grow_pairs(a, n)
    type(contact_pair_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(contact_pair_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_pairs

  !> Makes `a` hold at least `n` records.
  subroutine grow_walls(a, n)
    type(rigid_wall_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(rigid_wall_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_walls

  !> Makes `a` hold at least `n` records.
  subroutine grow_amplitudes(a, n)
    type(amplitude_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(amplitude_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_amplitudes

  !> Makes `a` hold at least `n` records.
  subroutine grow_cloads(a, n)
    type(cload_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(cload_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_cloads

  !> Makes `a` hold at least `n` records.
  subroutine grow_dloads(a, n)
    type(dload_in_t), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    type(dload_in_t), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate(tmp(max(n, 2*size(a), 4)))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_dloads
end module ictus_io_deck_grow
