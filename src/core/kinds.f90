!> Working precision and integer kinds used everywhere in ictus.
module ictus_core_kinds
  use, intrinsic :: iso_fortran_env, only: real64, int32, int64
  implicit none
  private
  public :: dp, i4, i8, pi, str_len

  !> Working real kind (double precision; there is no single-precision build).
  integer, parameter :: dp = real64
  !> Default integer kind for local indices.
  integer, parameter :: i4 = int32
  !> Integer kind for global ids and HDF5 offsets.
  integer, parameter :: i8 = int64
  !> pi to working precision.
  real(dp), parameter :: pi = 3.14159265358979323846264338327950288_dp
  !> Length of names (sets, materials, patches, surfaces).
  integer, parameter :: str_len = 64
end module ictus_core_kinds
