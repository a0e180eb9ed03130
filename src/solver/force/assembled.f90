!> The internal force of a linear, small-strain model as the product f = K u with the stiffness
!! assembled once (ictus_solver_assemble).
!!
!! Two products give the step its bits: with a lumped mass the two-chain row loop of the fused
!! lumped kernels (`bsr_matvec`); with a consistent mass (whose step has no such kernel) one
!! chain per row in column order, from K's upper blocks where one rank holds all rows
!! (`bsr_upper_matvec`: about half the bytes) and from the full rows otherwise
!! (`bsr_matvec_ordered`), the same bits either way.
module ictus_solver_force_assembled
  use ictus_core_kinds, only: dp
  use ictus_parallel_repro, only: repro_dot
  use ictus_solver_sparse, only: bsr_t, bsr_matvec, bsr_upper_t, bsr_upper_init, &
      bsr_matvec_ordered, bsr_upper_matvec, bsr3_matvec
  implicit none
  private
  public :: assembled_force_t, assembled_init, assembled_apply, assembled_energy

  type :: assembled_force_t
    !> The stiffness (owned rows; not owned here, see `assembled_init`).
    type(bsr_t), pointer :: k => null()
    !> Whether the product is summed in column order (consistent mass), and K's upper blocks
    !! when one rank holds all rows (kup%n > 0).
    logical :: ordered = .false.
    type(bsr_upper_t) :: kup
  end type assembled_force_t

contains

  !> Points the operator at the assembled K (which the caller keeps alive) and chooses the
  !! product: in column order when `ordered` (a consistent mass).
  subroutine assembled_init(af, k, ordered)
    type(assembled_force_t), intent(out) :: af
    type(bsr_t), target, intent(in) :: k
    logical, intent(in) :: ordered
    af%k => k
    af%ordered = ordered
    if (ordered) call bsr_upper_init(k, af%kup)
  end subroutine assembled_init

  !> f = K u on the n owned rows; u holds owned and ghost values, nb components per node (the
  !! block size of K).
  subroutine assembled_apply(af, n, u, f)
    type(assembled_force_t), intent(in) :: af
    integer, intent(in) :: n
    real(dp), intent(in) :: u(*)
    real(dp), intent(inout) :: f(*)
    if (size(af%k%val, 1) == 3) then
      call bsr3_matvec(n, af%k%g%row_ptr, af%k%g%col, af%k%val, u, f)
    else if (.not. af%ordered) then
      call bsr_matvec(n, af%k%g%row_ptr, af%k%g%col, af%k%val, u, f)
    else if (af%kup%n > 0) then
      call bsr_upper_matvec(af%kup, u, f)
    else
      call bsr_matvec_ordered(n, af%k%g%row_ptr, af%k%g%col, af%k%val, u, f)
    end if
  end subroutine assembled_apply

  !> Strain energy 1/2 u . K u = -1/2 u . r from the nodal force r = -K u (owned rows; a
  !! reproducible global sum).
  function assembled_energy(n, u, r, nglobal) result(e)
    integer, intent(in) :: n, nglobal
    real(dp), intent(in) :: u(:,:), r(:,:)
    real(dp) :: e
    e = -0.5_dp*repro_dot(n, u, r, nglobal)
  end function assembled_energy
end module ictus_solver_force_assembled
