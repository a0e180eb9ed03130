!> Reproducible sums: the same bits in any order of the terms, and accurate far beyond a
!! plain left-to-right sum (reference: the sum in quadruple precision).
program test_repro
  use, intrinsic :: iso_fortran_env, only: real128
  use ictus_core_kinds, only: dp
  use ictus_parallel_repro, only: repro_sum, repro_dot
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
  call t%finish()
end program test_repro
