!> Reproducible global sums: the same bits for any number of ranks and any order of terms.
!!
!! Method (pre-rounding, after Demmel & Nguyen): with M = max |x_i| over all ranks and N the
!! global number of terms, choose 2^e > N M and sigma = 1.5 * 2^e. Then q_i = (x_i + sigma) -
!! sigma rounds x_i to a multiple of 2^(e-52), every partial sum of the q_i is exact, and so
!! the global sum of the q_i does not depend on the order or the partition. The remainders
!! x_i - q_i are exact as well and are summed the same way at finer levels. Three levels give
!! an absolute accuracy of about N M 2^-92, far below double-precision rounding of the sum.
!! Needs strict IEEE evaluation (no -ffast-math; -ffp-contract=off is set by CMake).
module ictus_parallel_repro
  use ictus_core_kinds, only: dp
  use ictus_parallel_env, only: allreduce_max, allreduce_sum
  implicit none
  private
  public :: repro_sum, repro_dot, repro_sigma, repro_totals, levels

  !> Number of pre-rounding levels. Kernels that fold a reproducible sum into their own loop
  !! (the conjugate gradient of ictus_solver_mass_cg) extract, for each term t,
  !! q = (t + sigma(k)) - sigma(k); part(k) += q; t = t - q for k = 1..levels, with sigma
  !! from `repro_sigma`, and finish with `repro_totals`.
  integer, parameter :: levels = 3

contains

  !> Global sum of x(1:n) over all ranks (nglobal = the total number of terms).
  function repro_sum(n, x, nglobal) result(total)
    integer, intent(in) :: n
    real(dp), intent(in) :: x(n)
    integer, intent(in) :: nglobal
    real(dp) :: total
    real(dp) :: part(levels), sigma(levels), m, r, q
    integer :: i, k
    m = 0.0_dp
    do i = 1, n
      m = max(m, abs(x(i)))
    end do
    call allreduce_max(m)
    total = 0.0_dp
    if (m == 0.0_dp) return
    call level_boundaries(m, nglobal, sigma)
    part = 0.0_dp
    do i = 1, n
      r = x(i)
      do k = 1, levels
        q = (r + sigma(k)) - sigma(k)
        part(k) = part(k) + q
        r = r - q
      end do
    end do
    call allreduce_sum(part)
    total = part(1) + (part(2) + part(3))
  end function repro_sum

  !> Global dot product sum_i x(:, i) . y(:, i) for i = 1..n on all ranks (vectors of
  !! size(x, 1) components per node: 2 in 2D, 3 in 3D).
  function repro_dot(n, x, y, nglobal) result(total)
    integer, intent(in) :: n
    real(dp), intent(in) :: x(:,:), y(:,:)
    integer, intent(in) :: nglobal
    real(dp) :: total
    real(dp) :: part(levels), sigma(levels), m, r, q, t
    integer :: i, k, c, nc
    nc = size(x, 1)
    m = 0.0_dp
    do i = 1, n
      do c = 1, nc
        m = max(m, abs(x(c, i)*y(c, i)))
      end do
    end do
    call allreduce_max(m)
    total = 0.0_dp
    if (m == 0.0_dp) return
    call level_boundaries(m, nc*nglobal, sigma)
    part = 0.0_dp
    do i = 1, n
      do c = 1, nc
        t = x(c, i)*y(c, i)
        r = t
        do k = 1, levels
          q = (r + sigma(k)) - sigma(k)
          part(k) = part(k) + q
          r = r - q
        end do
      end do
    end do
    call allreduce_sum(part)
    total = part(1) + (part(2) + part(3))
  end function repro_dot

  !> Level boundaries for a sum of at most `nterms` terms (over all ranks) of magnitude at
  !! most `bound`, the same on every rank. Any upper bound gives an exact, order-independent
  !! sum; a tight one keeps more bits at the first level.
  pure subroutine repro_sigma(bound, nterms, sigma)
    real(dp), intent(in) :: bound
    integer, intent(in) :: nterms
    real(dp), intent(out) :: sigma(levels)
    call level_boundaries(max(bound, tiny(1.0_dp)), nterms, sigma)
  end subroutine repro_sigma

  !> Global totals of several reproducible sums from this rank's level partial sums
  !! part(lanes, levels, nsums): lanes (independent accumulators of one loop) and ranks are
  !! added exactly, then each sum's levels are combined, finest last.
  function repro_totals(part) result(total)
    real(dp), intent(in) :: part(:,:,:)
    real(dp) :: total(size(part, 3))
    real(dp) :: lv(levels, size(part, 3))
    integer :: j, k
    do j = 1, size(part, 3)
      do k = 1, levels
        lv(k, j) = sum(part(:, k, j))
      end do
    end do
    call allreduce_sum(lv)
    do j = 1, size(part, 3)
      total(j) = lv(1, j) + (lv(2, j) + lv(3, j))
    end do
  end function repro_totals

  !> sigma_k = 1.5 * 2^e_k with 2^e_1 > N M and each next level 53 - log2(N) - 1 bits finer.
  pure subroutine level_boundaries(m, nterms, sigma)
    real(dp), intent(in) :: m
    integer, intent(in) :: nterms
    real(dp), intent(out) :: sigma(levels)
    integer :: e, lg, k
    lg = ceiling(log(real(max(nterms, 2), dp))/log(2.0_dp)) + 1
    e = exponent(m) + lg
    do k = 1, levels
      sigma(k) = 1.5_dp*scale(1.0_dp, e)
      e = e - 52 + lg
    end do
  end subroutine level_boundaries
end module ictus_parallel_repro
