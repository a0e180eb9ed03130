!> Reproducible sums: the same bits in any order of the terms, and accurate far beyond a
!! plain left-to-right sum (reference: the sum in quadruple precision).
program test_repro
  use, intrinsic :: iso_fortran_env, only: real128
  use ictus_core_kinds, only: dp
  use ictus_parallel_repro, only: repro_sum, repro_dot, repro_sigma, repro_totals, levels
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  integer, parameter :: n = 10000
  real(dp) :: x(n), xs(n), a, b, p(2, n), q(2, n)
  real(real128) :: exact
  integer :: perm(n), i, j, k
  call t%start("parallel/repro")
  ! terms of mixed sign over 12 orders of magnitude
  do i = 1, n
    x(i) = sin(real(i, dp)*1.3_dp)*10.0_dp**mod(i, 13)
  end do
  ! a fixed pseudo-random permutation
  perm = [(i, i = 1, n)]
  do i = n, 2, -1
    j = 1 + mod(i*7919 + 13, i)
    k = perm(i)
    perm(i) = perm(j)
    perm(j) = k
  end do
  xs = x(perm)
  a = repro_sum(n, x, n)
  b = repro_sum(n, xs, n)
  call t%true(a == b, "same bits for a permutation of the terms")
  exact = sum(real(x, real128))
  call t%close(a, real(exact, dp), 1.0e-15_dp, "agrees with the quadruple-precision sum")
  ! cancellation: 1e16 + 1 - 1e16 = 1 exactly
  call t%close(repro_sum(3, [1.0e16_dp, 1.0_dp, -1.0e16_dp], 3), 1.0_dp, 0.0_dp, &
      "exact under catastrophic cancellation")
  ! dot products of 2-vectors per node
  do i = 1, n
    p(:, i) = [x(i), -x(n + 1 - i)]
    q(:, i) = [cos(real(i, dp)), 1.0_dp/real(i, dp)]
  end do
  exact = sum(real(p, real128)*real(q, real128))
  a = repro_dot(n, p, q, n)
  call t%close(a, real(exact, dp), 1.0e-14_dp, "dot product agrees with quadruple precision")
  call t%true(a == repro_dot(n, p(:, perm), q(:, perm), n), "dot product: same bits permuted")
  call t%close(repro_sum(1, [0.0_dp], 1), 0.0_dp, 0.0_dp, "zero")
  ! sums folded into a kernel's loop: level boundaries from an upper bound (here 100 x the
  ! largest term, as the a priori bounds of the CG are loose), terms spread over lanes
  call t%true(inline_sum(x, 3, 100.0_dp) == inline_sum(xs, 2, 100.0_dp), &
      "folded sum: same bits for a permutation and another number of lanes")
  call t%true(inline_sum(x, 1, 100.0_dp) == inline_sum(x, 4, 100.0_dp), &
      "folded sum: lanes do not change the bits")
  call t%close(inline_sum(x, 2, 100.0_dp), real(exact_x(), dp), 1.0e-15_dp, &
      "folded sum with a loose bound agrees with the quadruple-precision sum")
  call t%close(inline_sum(x, 2, 1.0e6_dp), real(exact_x(), dp), 1.0e-15_dp, &
      "folded sum with a bound 1e6 x too large is still accurate")
  call t%finish()
contains

  !> sum(v) as a kernel computes it: terms dealt round-robin to `lanes` accumulators, levels
  !! extracted inline with repro_sigma's boundaries for the bound f * max|v|.
  real(dp) function inline_sum(v, lanes, f) result(total)
    real(dp), intent(in) :: v(:), f
    integer, intent(in) :: lanes
    real(dp) :: sigma(levels), part(lanes, levels, 1), s(1), r, w
    integer :: i, l, lane
    call repro_sigma(f*maxval(abs(v)), size(v), sigma)
    part = 0.0_dp
    do i = 1, size(v)
      lane = 1 + mod(i, lanes)
      r = v(i)
      do l = 1, levels
        w = (r + sigma(l)) - sigma(l)
        part(lane, l, 1) = part(lane, l, 1) + w
        r = r - w
      end do
    end do
    s = repro_totals(part)
    total = s(1)
  end function inline_sum

  real(real128) function exact_x() result(e)
    e = sum(real(x, real128))
  end function exact_x
end program test_repro
