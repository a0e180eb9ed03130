!> Diagonal (lumped) element mass matrices from the scalar consistent mass (doc/theory.md §3).
!!
!! All routines work on the scalar mass per node of any element (2D or 3D); the same value
!! applies to every displacement component.
module ictus_mass_lumping
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: lump_row_sum, lump_hrz, lump_alpha_q8

contains

  !> Row-sum lumping m_A = sum_B M_AB (= int rho N_A dV; conserves mass, may be negative).
  !! nen: nodes; me(nen, nen): scalar consistent mass; ml(nen): lumped masses.
  pure subroutine lump_row_sum(nen, me, ml)
    integer, intent(in) :: nen
    real(dp), intent(in) :: me(nen, nen)
    real(dp), intent(out) :: ml(nen)
    ml = sum(me, dim=2)
  end subroutine lump_row_sum

  !> HRZ diagonal scaling m_A = M_AA mass_e / sum_B M_BB (Hinton, Rock & Zienkiewicz 1976).
  !! nen: nodes; me_diag(nen): diagonal of the consistent mass, integrated with the rule the
  !! caller chose (full rule, or 2x2 Gauss for the HRZ 2x2 variant); mass_e: element mass
  !! int rho dV; ml(nen): lumped masses (sum = mass_e; zero if the diagonal sums to <= 0).
  pure subroutine lump_hrz(nen, me_diag, mass_e, ml)
    integer, intent(in) :: nen
    real(dp), intent(in) :: me_diag(nen), mass_e
    real(dp), intent(out) :: ml(nen)
    real(dp) :: trace
    trace = sum(me_diag)
    if (trace > 0.0_dp) then
      ml = me_diag*(mass_e/trace)
    else
      ml = 0.0_dp
    end if
  end subroutine lump_hrz

  !> The alpha-family for Q8 (doc/theory.md §3): corners 1-4 get (1/4 - alpha) m, midsides 5-8
  !! get alpha m. mass_e: element mass m; alpha: midside fraction; ml(8): lumped masses.
  pure subroutine lump_alpha_q8(mass_e, alpha, ml)
    real(dp), intent(in) :: mass_e, alpha
    real(dp), intent(out) :: ml(8)
    ml(1:4) = (0.25_dp - alpha)*mass_e
    ml(5:8) = alpha*mass_e
  end subroutine lump_alpha_q8
end module ictus_mass_lumping
