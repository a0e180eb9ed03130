#!/usr/bin/python3
"""Stand-alone measurement of an element-by-element (EBE) stiffness product for Q8
(doc/performance.md §3.3, "Element-by-element storage").

    /usr/bin/python3 scripts/experiments/ebe_kernel.py [--sizes 316,1000] [--fc gfortran] [--avx512]

K u is formed element by element from the stored element matrices instead of the assembled
2x2-block rows: each Q8 element matrix is symmetric 16 x 16, so its upper triangle, 136
values (1088 B), is stored, against the 1807 B per element that the assembled product moves
(src/solver/sparse.f90). The elements are taken 8 at a time, one per vector lane (the
values of a batch stored lane-fastest, so the batch's 8.7 KB are read in order), and the
16 x 16 product is written out in full (generated here: Fortran has no way to keep the 32
vectors of an element's u and K u in registers otherwise), column by column of the packed
triangle with two accumulators.

The mesh is the Q8 square of the benchmark (n x n elements, nodes numbered row by row as
bench/benchmark.py writes them), the element matrices are pseudo-random and symmetric (the
timing does not depend on the values). The product is checked against a plain loop over the
stored entries. The program times, best of 5:
  read    a sum over the stored triangles alone (the floor of this layout),
  kernel  the element products with u and K u kept in the batch (no gather, no scatter),
  K u     the whole product: u gathered per element, the products, K u added node by node
          in element order (the order that keeps the bits independent of the ranks, as
          the assembled rows do),
  gather  the products with u gathered but nothing scattered,
  scatter the products scattered, u not gathered,
and a STREAM triad over 96 MB. Compare with the K u and K read columns of
bench/benchmark.py run in the same session. It takes alloc_stream (src/core/memory.f90:
huge pages, as ictus's K and vectors have them) from the core library of an ictus build
(--build-dir, default build/).

--avx512 also builds the same product in C with AVX-512 intrinsics (gcc): u gathered 8 lanes
at once by vgatherdpd, K u added either node by node as above or, with lanes of elements that
share no node, by vscatterdpd. A measurement only: ictus itself is Fortran.
"""
import argparse
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

PROGRAM = r"""
module ebe_kernel
  implicit none
  integer, parameter :: dp = kind(1.0d0), nl = 8, npk = 136
contains
  subroutine kern(kp, ue, ye)
    real(dp), intent(in) :: kp(nl, npk), ue(nl, 16)
    real(dp), intent(out) :: ye(nl, 16)
    real(dp) :: a1(nl), a2(nl)
    ye = 0
@KERNEL@
  end subroutine kern
end module ebe_kernel

program ebe
  use, intrinsic :: iso_fortran_env, only: int64
  use ictus_core_memory, only: alloc_stream
  use ebe_kernel, only: dp, nl, npk, kern
  implicit none
  integer :: n, nel, nn, nb, b, l, i, j, k, e, ex, ey, rep, nsteps, s, mode, a
  real(dp), allocatable, target :: kp(:,:,:), u(:,:), y(:,:), yref(:,:), ta(:), tb(:), tc(:)
  ! node numbers of lane l, node a of batch b: cn(l + nl*(a - 1) + 8*nl*(b - 1))
  integer, allocatable, target :: cn(:)
  real(dp) :: ke(16, 16), t(5), tt, ttriad, err
  integer(int64) :: c0, c1, cr
  character(len=32) :: arg
  call get_command_argument(1, arg)
  read (arg, *) n
  call get_command_argument(2, arg)
  read (arg, *) nsteps
  nel = n*n
  nn = (2*n + 1)*(n + 1) + (n + 1)*n
  nb = (nel + nl - 1)/nl
  call alloc_stream(kp, nl, npk, nb, 0.0_dp)
  call alloc_stream(cn, 8*nl*nb, 0)
  do b = 1, nb
    do l = 1, nl
      e = min((b - 1)*nl + l, nel) - 1
      ex = mod(e, n)
      ey = e/n
      cn(l + nl*[(a, a = 0, 7)] + 8*nl*(b - 1)) = [vr(ey) + 2*ex + 1, vr(ey) + 2*ex + 3, &
          vr(ey + 1) + 2*ex + 3, &
          vr(ey + 1) + 2*ex + 1, vr(ey) + 2*ex + 2, mr(ey) + ex + 2, vr(ey + 1) + 2*ex + 2, &
          mr(ey) + ex + 1]
      call random_number(ke)
      if ((b - 1)*nl + l > nel) ke = 0
      k = 0
      do j = 1, 16
        do i = 1, j
          k = k + 1
          kp(l, k, b) = ke(i, j)
        end do
      end do
    end do
  end do
  call alloc_stream(u, 2, nn, 0.0_dp)
  call alloc_stream(y, 2, nn, 0.0_dp)
  allocate(yref(2, nn))
  call random_number(u)
  yref = 0
  do b = 1, nb
    do l = 1, nl
      k = 0
      do j = 1, 16
        do i = 1, j
          k = k + 1
          call addk(cn(1 + 8*nl*(b - 1):8*nl*b), l, i, j, kp(l, k, b))
          if (i /= j) call addk(cn(1 + 8*nl*(b - 1):8*nl*b), l, j, i, kp(l, k, b))
        end do
      end do
    end do
  end do
  call apply(3)
  err = maxval(abs(y - yref))/maxval(abs(yref))
  if (err > 1.0e-13_dp) then
    print '(a, es10.2)', 'ebe: the product does not match the reference, relative error', err
    stop 1
  end if
  call alloc_stream(ta, 4194304, 1.0_dp)
  call alloc_stream(tb, 4194304, 2.0_dp)
  call alloc_stream(tc, 4194304, 3.0_dp)
  t = huge(1.0_dp)
  ttriad = huge(1.0_dp)
  do rep = 1, 5
    do mode = 1, 5
      call system_clock(c0, cr)
      do s = 1, nsteps
        call apply(mode)
        u(1, 1) = u(1, 1) + 1.0e-300_dp*y(1, 2)
      end do
      call system_clock(c1)
      t(mode) = min(t(mode), real(c1 - c0, dp)/cr/nsteps)
    end do
    call system_clock(c0, cr)
    do s = 1, 10
      ta = tb + 1.5_dp*tc
      tb(1) = ta(2)
    end do
    call system_clock(c1)
    ttriad = min(ttriad, real(c1 - c0, dp)/cr/10)
  end do
  tt = 24.0_dp*size(ta)/ttriad/1.0e9_dp
  print '(a, i8, 5(a, f7.1), a, f6.1, a, es8.1)', 'EBE nel=', nel, ' read_ns=', &
      1.0e9_dp*t(1)/nel, ' kernel_ns=', 1.0e9_dp*t(2)/nel, ' ku_ns=', 1.0e9_dp*t(3)/nel, &
      ' gather_ns=', 1.0e9_dp*t(4)/nel, ' scatter_ns=', 1.0e9_dp*t(5)/nel, &
      ' triad_gbs=', tt, ' err=', err
contains
  integer function vr(jy)
    integer, intent(in) :: jy
    vr = jy*((2*n + 1) + (n + 1))
  end function vr
  integer function mr(jy)
    integer, intent(in) :: jy
    mr = jy*((2*n + 1) + (n + 1)) + (2*n + 1)
  end function mr
  ! yref(row dof i) += v * u(column dof j) of lane l's element; local dof d is node (d+1)/2,
  ! component 2 - mod(d, 2)
  subroutine addk(c, l, i, j, v)
    integer, intent(in) :: c(nl, 8), l, i, j
    real(dp), intent(in) :: v
    yref(2 - mod(i, 2), c(l, (i + 1)/2)) = yref(2 - mod(i, 2), c(l, (i + 1)/2)) &
        + v*u(2 - mod(j, 2), c(l, (j + 1)/2))
  end subroutine addk
  ! mode 1: read the stored triangles; 2: element products only; 3: the whole K u;
  ! 4: gather and products; 5: products and scatter
  subroutine apply(mode)
    integer, intent(in) :: mode
    real(dp) :: ue(nl, 16), ye(nl, 16), acc(nl)
    integer :: b, l, a, k, o
    if (mode == 1) then
      acc = 0
      do b = 1, nb
        do k = 1, npk
          acc = acc + kp(:, k, b)
        end do
      end do
      y(1, 1) = sum(acc)
      return
    end if
    if (mode >= 3) y = 0
    ue = 1
    do b = 1, nb
      o = 8*nl*(b - 1)
      if (mode == 3 .or. mode == 4) then
        do a = 1, 8
          do l = 1, nl
            ue(l, 2*a - 1) = u(1, cn(l + nl*(a - 1) + o))
            ue(l, 2*a) = u(2, cn(l + nl*(a - 1) + o))
          end do
        end do
      end if
      call kern(kp(:, :, b), ue, ye)
      if (mode == 3 .or. mode == 5) then
        do l = 1, nl
          do a = 1, 8
            y(1, cn(l + nl*(a - 1) + o)) = y(1, cn(l + nl*(a - 1) + o)) + ye(l, 2*a - 1)
            y(2, cn(l + nl*(a - 1) + o)) = y(2, cn(l + nl*(a - 1) + o)) + ye(l, 2*a)
          end do
        end do
      else
        y(1, mod(b, nn) + 1) = ye(1, 1) + ye(nl, 16)
      end if
    end do
  end subroutine apply
end program ebe
"""

PROGRAM_C = r"""
/* The same product with AVX-512 intrinsics: u gathered by vgatherdpd, 8 lanes at once.
   Scatter 0: K u added node by node from a stored batch (scalar, element order);
   scatter 1: lanes of elements that share no node (each batch the even or the odd elements
   of 16 in a row), K u added by gather, add and vscatterdpd. */
#include <immintrin.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#define NL 8
static int n;
static int vr(int j) { return j * ((2 * n + 1) + (n + 1)); }
static int mr(int j) { return vr(j) + 2 * n + 1; }
static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}
static void *big(size_t bytes) { /* huge pages before the first touch, as alloc_stream */
  size_t h = (size_t)2 << 20, m = (bytes + h - 1) / h * h;
  void *p = aligned_alloc(h, m);
  if (!p) { fprintf(stderr, "out of memory\n"); exit(1); }
  madvise(p, m, MADV_HUGEPAGE);
  memset(p, 0, m);
  return p;
}
static void ku(int nb, const double *K, const int *cn, const double *u, double *y, int sc) {
  for (int b = 0; b < nb; b++) {
    const double *kp = K + (size_t)b * 136 * NL;
    const int *c = cn + (size_t)b * 8 * NL;
    __m512d ue[16], ye[16], a1, a2, kv;
    for (int a = 0; a < 8; a++) {
      __m256i idx = _mm256_slli_epi32(_mm256_loadu_si256((const __m256i *)(c + a * NL)), 1);
      ue[2 * a] = _mm512_i32gather_pd(idx, u, 8);
      ue[2 * a + 1] = _mm512_i32gather_pd(idx, u + 1, 8);
      ye[2 * a] = _mm512_setzero_pd();
      ye[2 * a + 1] = _mm512_setzero_pd();
    }
@KERNEL@
    if (sc) {
      for (int a = 0; a < 8; a++) {
        __m256i idx = _mm256_slli_epi32(_mm256_loadu_si256((const __m256i *)(c + a * NL)), 1);
        __m512d y1 = _mm512_i32gather_pd(idx, y, 8), y2 = _mm512_i32gather_pd(idx, y + 1, 8);
        _mm512_i32scatter_pd(y, idx, _mm512_add_pd(y1, ye[2 * a]), 8);
        _mm512_i32scatter_pd(y + 1, idx, _mm512_add_pd(y2, ye[2 * a + 1]), 8);
      }
    } else {
      double t[16][NL];
      for (int a = 0; a < 16; a++) _mm512_storeu_pd(t[a], ye[a]);
      for (int l = 0; l < NL; l++)
        for (int a = 0; a < 8; a++) {
          int nd = c[a * NL + l];
          y[2 * nd] += t[2 * a][l];
          y[2 * nd + 1] += t[2 * a + 1][l];
        }
    }
  }
}
int main(int argc, char **argv) {
  n = atoi(argv[1]);
  int steps = atoi(argv[2]), sc = atoi(argv[3]);
  int nel = n * n, nn = vr(n) + 2 * n + 1, nb = (nel + NL - 1) / NL;
  if (sc && n % 16) { fprintf(stderr, "scatter 1 needs n a multiple of 16\n"); return 1; }
  double *K = big((size_t)nb * 136 * NL * 8), *u = big((size_t)2 * nn * 8);
  double *y = big((size_t)2 * nn * 8), *yr = calloc((size_t)2 * nn, 8);
  int *cn = big((size_t)nb * 8 * NL * 4);
  srand(1);
  for (int b = 0; b < nb; b++)
    for (int l = 0; l < NL; l++) {
      int e = sc ? (b / 2) * 16 + 2 * l + b % 2 : b * NL + l, pad = e >= nel;
      if (pad) e = nel - 1;
      int ex = e % n, ey = e / n;
      int nd[8] = {vr(ey) + 2 * ex, vr(ey) + 2 * ex + 2, vr(ey + 1) + 2 * ex + 2,
                   vr(ey + 1) + 2 * ex,
                   vr(ey) + 2 * ex + 1, mr(ey) + ex + 1, vr(ey + 1) + 2 * ex + 1, mr(ey) + ex};
      for (int a = 0; a < 8; a++) cn[b * 8 * NL + a * NL + l] = nd[a];
      for (int k = 0; k < 136; k++)
        K[((size_t)b * 136 + k) * NL + l] = pad ? 0.0 : (double)rand() / RAND_MAX;
    }
  for (int i = 0; i < 2 * nn; i++) u[i] = (double)rand() / RAND_MAX;
  for (int b = 0; b < nb; b++)
    for (int l = 0; l < NL; l++)
      for (int j = 0, k = 0; j < 16; j++)
        for (int i = 0; i <= j; i++, k++) {
          double v = K[((size_t)b * 136 + k) * NL + l];
          int ni = cn[b * 8 * NL + (i / 2) * NL + l], nj = cn[b * 8 * NL + (j / 2) * NL + l];
          yr[2 * ni + i % 2] += v * u[2 * nj + j % 2];
          if (i != j) yr[2 * nj + j % 2] += v * u[2 * ni + i % 2];
        }
  ku(nb, K, cn, u, y, sc);
  double err = 0, mx = 0;
  for (int i = 0; i < 2 * nn; i++) {
    double d = y[i] > yr[i] ? y[i] - yr[i] : yr[i] - y[i];
    if (d > err) err = d;
    if (yr[i] > mx) mx = yr[i];
  }
  if (err > 1e-13 * mx) {
    printf("ebe: the product does not match the reference (%.1e)\n", err / mx);
    return 1;
  }
  double best = 1e30;
  for (int r = 0; r < 5; r++) {
    double t0 = now();
    for (int s = 0; s < steps; s++) {
      memset(y, 0, (size_t)2 * nn * 8);
      ku(nb, K, cn, u, y, sc);
    }
    double t = (now() - t0) / steps;
    if (t < best) best = t;
  }
  printf("EBE-AVX512 nel=%8d scatter=%d ku_ns=%7.1f err=%.1e\n", nel, sc, best / nel * 1e9,
         err / mx);
  return 0;
}
"""


def kernel_c():
    """kernel() in AVX-512 intrinsics, the 16 vectors of u and of K u in registers."""
    lines, k = [], 0
    for j in range(16):
        lines.append(f"    a1 = _mm512_mul_pd(_mm512_load_pd(kp + {(k + j) * 8}), ue[{j}]);")
        lines.append("    a2 = _mm512_setzero_pd();")
        for i in range(j):
            acc = "a1" if i % 2 == 0 else "a2"
            lines.append(f"    kv = _mm512_load_pd(kp + {(k + i) * 8}); "
                         f"ye[{i}] = _mm512_fmadd_pd(kv, ue[{j}], ye[{i}]); "
                         f"{acc} = _mm512_fmadd_pd(kv, ue[{i}], {acc});")
        lines.append(f"    ye[{j}] = _mm512_add_pd(ye[{j}], _mm512_add_pd(a1, a2));")
        k += j + 1
    return "\n".join(lines)


def kernel():
    """The 16 x 16 symmetric product written out: column j of the packed upper triangle
    (entries (1, j) .. (j, j)) adds K_ij u_j to ye_i (i < j) and sums K_ij u_i into ye_j."""
    lines, k = [], 0
    for j in range(1, 17):
        lines.append(f"    a1 = kp(:, {k + j})*ue(:, {j})")
        lines.append("    a2 = 0")
        for i in range(1, j):
            lines.append(f"    ye(:, {i}) = ye(:, {i}) + kp(:, {k + i})*ue(:, {j})")
            acc = "a1" if i % 2 else "a2"
            lines.append(f"    {acc} = {acc} + kp(:, {k + i})*ue(:, {i})")
        lines.append(f"    ye(:, {j}) = ye(:, {j}) + (a1 + a2)")
        k += j
    assert k == 136
    return "\n".join(lines)


def compile_or_exit(cmd, cwd):
    try:
        p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    except OSError as e:
        sys.exit(f"ebe_kernel: cannot run {cmd[0]}: {e.strerror}")
    if p.returncode != 0:
        sys.exit(f"ebe_kernel: {' '.join(cmd)} failed:\n{p.stdout}{p.stderr}")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="316,1000", help="elements per side, comma-separated")
    ap.add_argument("--fc", default="gfortran")
    ap.add_argument("--flags", default="-O3 -march=native", help="as a Release build of ictus")
    ap.add_argument("--build-dir", default=os.path.join(ROOT, "build"),
                    help="an ictus build: the program takes alloc_stream (huge pages) from its "
                         "core library")
    ap.add_argument("--avx512", action="store_true",
                    help="also the same product in C with AVX-512 intrinsics (needs gcc and a "
                         "CPU with AVX-512)")
    ap.add_argument("--cc", default="gcc")
    args = ap.parse_args()
    try:
        sizes = [int(x) for x in args.sizes.split(",")]
    except ValueError:
        sys.exit("ebe_kernel: --sizes: expected comma-separated integers (elements per side), "
                 f"got {args.sizes}")
    if any(m < 16 for m in sizes):
        sys.exit("ebe_kernel: --sizes: at least 16 elements per side")
    args.build_dir = os.path.abspath(args.build_dir)
    mods = os.path.join(args.build_dir, "modules", "core")
    lib = os.path.join(args.build_dir, "src", "core", "libictus_core.a")
    if not (os.path.isdir(mods) and os.path.isfile(lib)):
        sys.exit(f"ebe_kernel: no ictus build in {args.build_dir} (run scripts/setup.sh Release, "
                 "or give --build-dir)")
    with tempfile.TemporaryDirectory(prefix="ictus-ebe-") as d:
        src = os.path.join(d, "ebe.f90")
        with open(src, "w") as f:
            f.write(PROGRAM.replace("@KERNEL@", kernel()))
        exe = os.path.join(d, "ebe")
        compile_or_exit([args.fc] + args.flags.split() + ["-I", mods, "-o", exe, src, lib], d)
        print("ns per element per product, best of 5; K u stored: 1088 B of matrix + 32 B of "
              "node numbers per element")
        for n in sizes:
            steps = max(3, int(3.0e6 / (n * n)))
            p = subprocess.run([exe, str(n), str(steps)], capture_output=True, text=True)
            sys.stdout.write(p.stdout + p.stderr)
            if p.returncode != 0:
                sys.exit(f"ebe_kernel: the program failed for n = {n}")
        if args.avx512:
            srcc = os.path.join(d, "ebe.c")
            with open(srcc, "w") as f:
                f.write(PROGRAM_C.replace("@KERNEL@", kernel_c()))
            exec_c = os.path.join(d, "ebe_c")
            compile_or_exit([args.cc, "-O3", "-march=native", "-o", exec_c, srcc], d)
            print("the same in C with AVX-512 intrinsics (u gathered by vgatherdpd); the time "
                  "includes zeroing K u")
            for n in sizes:
                steps = max(3, int(3.0e6 / (n * n)))
                for sc in (0, 1):
                    m = n if sc == 0 else n - n % 16
                    p = subprocess.run([exec_c, str(m), str(steps), str(sc)], capture_output=True,
                                       text=True)
                    sys.stdout.write(p.stdout + p.stderr)
                    if p.returncode != 0:
                        sys.exit(f"ebe_kernel: the C program failed for n = {m}")


if __name__ == "__main__":
    main()
