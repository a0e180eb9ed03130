/*
 * The row loop of the stiffness product y = K x (bsr_matvec in sparse.f90), in C for one
 * reason: Fortran cannot ask the processor to prefetch, and this product needs it.
 *
 * K is stored in block CSR with 2x2 blocks, val(2, 2, nnz) in Fortran order, and is read
 * once per product from memory. With the core busy gathering x and multiplying, the hardware
 * prefetchers keep too little of the block stream in flight: the product ran at 0.61-0.70 of
 * the rate at which a loop that only reads the same arrays streams them. Asking for the
 * block PREFETCH_BYTES ahead, once per 64-byte pair of blocks, brings it to about that rate
 * (doc/performance.md §3.1, where the distance was measured).
 *
 * The arithmetic is that of the Fortran kernel it replaced, operation for operation: each
 * block's two products are added first, the blocks of a row go alternately into two partial
 * sums (odd and even positions), added at the end. Compiled without contraction into fused
 * multiply-adds (ICTUS_DETERMINISTIC, -ffp-contract=off, as the Fortran sources), so the
 * bits are those of that kernel and, the columns being sorted by global index, do not depend
 * on the partition. tests/unit/solver/test_sparse.f90 checks both.
 *
 * Indices are Fortran's: row_ptr(n + 1) and col(*) are 1-based.
 */
#include <stdint.h>

/* How far ahead of the current block the stream is prefetched (bytes). On the Zen 5 host
 * 6-12 KiB are within 3 % of each other, 4 and 16 KiB about 5 % slower, no prefetch
 * 1.3-1.4 x slower on meshes beyond the caches and the same in them. */
enum { PREFETCH_BYTES = 8192 };

void ictus_bsr_matvec(int n, const int *restrict row_ptr, const int *restrict col,
                      const double *restrict val, const double *restrict x,
                      double *restrict y)
{
  for (int i = 0; i < n; i++) {
    const int k0 = row_ptr[i] - 1;     /* first and last block of the row, 0-based */
    const int k1 = row_ptr[i + 1] - 2;
    double a1 = 0.0, a2 = 0.0, b1 = 0.0, b2 = 0.0;
    int k;
    for (k = k0; k < k1; k += 2) {
      const double *v = val + 4 * (intptr_t)k;
      /* a hint, never a fault: past the end of val it fetches nothing useful, no harm */
      __builtin_prefetch((const void *)((uintptr_t)v + PREFETCH_BYTES), 0, 3);
      const double *xa = x + 2 * (intptr_t)(col[k] - 1);
      const double *xb = x + 2 * (intptr_t)(col[k + 1] - 1);
      a1 = a1 + (v[0] * xa[0] + v[2] * xa[1]);
      a2 = a2 + (v[1] * xa[0] + v[3] * xa[1]);
      b1 = b1 + (v[4] * xb[0] + v[6] * xb[1]);
      b2 = b2 + (v[5] * xb[0] + v[7] * xb[1]);
    }
    if ((k1 - k0) % 2 == 0) {          /* an odd number of blocks: the last one alone */
      const double *v = val + 4 * (intptr_t)k1;
      const double *xa = x + 2 * (intptr_t)(col[k1] - 1);
      a1 = a1 + (v[0] * xa[0] + v[2] * xa[1]);
      a2 = a2 + (v[1] * xa[0] + v[3] * xa[1]);
    }
    y[2 * (intptr_t)i] = a1 + b1;
    y[2 * (intptr_t)i + 1] = a2 + b2;
  }
}
