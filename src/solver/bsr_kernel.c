/*
 * The row loop of the stiffness product y = K x (bsr_matvec in sparse.f90), in C for one
 * reason: Fortran cannot ask the processor to prefetch, and this product needs it.
 *
 * K is stored in block CSR with 2x2 blocks, val(2, 2, nnz) in Fortran order, and is read
 * once per product from memory. With the core busy gathering x and multiplying, the hardware
 * prefetchers keep too little of the block stream in flight. So the loop asks for the block
 * PREFETCH_BYTES ahead, once per 64-byte pair of blocks, which lets the product stream K at
 * about the rate of a loop that only reads the same arrays (see doc/performance.md §3.1).
 *
 * The arithmetic is the order that bsr_matvec (sparse.f90) documents, operation for
 * operation: each block's two products are added first, the blocks of a row go alternately
 * into two partial sums (odd and even positions), added at the end. Compiled without
 * contraction into fused multiply-adds (ICTUS_DETERMINISTIC, -ffp-contract=off, as the
 * Fortran sources), so the bits are fixed by that order and, the columns being sorted by
 * global index, do not depend on the partition. tests/unit/solver/test_sparse.f90 checks
 * both.
 *
 * Indices are Fortran's: row_ptr(n + 1) and col(*) are 1-based.
 */
#include <stdint.h>

/* How far ahead of the current block the stream is prefetched (bytes); the distance and the
 * others tried: doc/performance.md §3.1. */
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

/*
 * The stiffness product of the consistent-mass step, in "column order": each row's sum is one
 * chain over its blocks in the order of their columns (global indices),
 *
 *     y_i = ((0 + t_1) + t_2) + ... ,   t_k = (K_ik(:, 1) x_k1 + K_ik(:, 2) x_k2),
 *
 * each t_k a pair of lanes (both components of the row), formed as lo * x_k1 + hi * x_k2 with
 * lo, hi the block's two columns. Two kernels give these bits: ictus_bsr_matvec_ordered on the
 * full rows (any partition), and ictus_bsr_symv on the upper blocks only (one rank whose nodes
 * are numbered in global order): K is symmetric bit for bit (assemble.f90 adds each element
 * matrix's upper triangle mirrored), so a row's blocks left of the diagonal are the transposes
 * of blocks above it, and ictus_bsr_symv adds their terms to y_j as it passes row i < j, in
 * the order of i, before row j itself starts from the sum so far. It reads about half the
 * bytes of the full product (timings: doc/performance.md §3.3). The unit test
 * tests/unit/solver/test_sparse.f90 checks that the two agree bit for bit and the order of
 * the sum.
 */
typedef double v2d __attribute__((vector_size(16)));

static inline v2d load2(const double *p) { v2d r; __builtin_memcpy(&r, p, sizeof r); return r; }
static inline void store2(double *p, v2d r) { __builtin_memcpy(p, &r, sizeof r); }
static inline v2d splat(double a) { return (v2d){a, a}; }

void ictus_bsr_matvec_ordered(int n, const int *restrict row_ptr, const int *restrict col,
                              const double *restrict val, const double *restrict x,
                              double *restrict y)
{
  for (int i = 0; i < n; i++) {
    v2d acc = splat(0.0);
    for (int k = row_ptr[i] - 1; k < row_ptr[i + 1] - 1; k++) {
      const double *v = val + 4 * (intptr_t)k;
      if ((k & 1) == 0)
        __builtin_prefetch((const void *)((uintptr_t)v + PREFETCH_BYTES), 0, 3);
      const double *xk = x + 2 * (intptr_t)(col[k] - 1);
      acc = acc + (load2(v) * splat(xk[0]) + load2(v + 2) * splat(xk[1]));
    }
    store2(y + 2 * (intptr_t)i, acc);
  }
}

/* Rows of the upper blocks: row i's first block is its diagonal (checked when the storage
 * is built, bsr_upper_init), the others have columns j > i. y_j is set to 0 before the first
 * row that reaches column j (no pass over y beforehand; the attribute keeps the compiler from
 * turning the short zeroing loop into a call of memset per row). */
__attribute__((optimize("no-tree-loop-distribute-patterns")))
void ictus_bsr_symv(int n, const int *restrict row_ptr, const int *restrict col,
                    const double *restrict val, const double *restrict x,
                    double *restrict y)
{
  int zeroed = 0;                      /* y_0 .. y_(zeroed-1) hold their partial sums */
  for (int i = 0; i < n; i++) {
    const int k0 = row_ptr[i] - 1;
    const int k1 = row_ptr[i + 1] - 1; /* one past the row's last block */
    const int last = k1 > k0 ? col[k1 - 1] - 1 : i;
    while (zeroed <= last) {
      store2(y + 2 * (intptr_t)zeroed, splat(0.0));
      zeroed++;
    }
    if (k1 == k0) continue;            /* a node without elements: y_i = 0 */
    const v2d xi1 = splat(x[2 * (intptr_t)i]), xi2 = splat(x[2 * (intptr_t)i + 1]);
    const double *d = val + 4 * (intptr_t)k0;
    v2d acc = load2(y + 2 * (intptr_t)i) + (load2(d) * xi1 + load2(d + 2) * xi2);
    for (int k = k0 + 1; k < k1; k++) {
      const double *v = val + 4 * (intptr_t)k;
      __builtin_prefetch((const void *)((uintptr_t)v + PREFETCH_BYTES), 0, 3);
      const int j = col[k] - 1;
      const double *xj = x + 2 * (intptr_t)j;
      const v2d lo = load2(v), hi = load2(v + 2);
      acc = acc + (lo * splat(xj[0]) + hi * splat(xj[1]));
      /* the block's transpose, K_ji = K_ij^T: columns (v0, v2) and (v1, v3) */
      const v2d tlo = (v2d){v[0], v[2]}, thi = (v2d){v[1], v[3]};
      double *yj = y + 2 * (intptr_t)j;
      store2(yj, load2(yj) + (tlo * xi1 + thi * xi2));
    }
    store2(y + 2 * (intptr_t)i, acc);
  }
}

/*
 * The product y = K x with 3x3 blocks (3D), val(3, 3, nnz) in Fortran order: the arithmetic of
 * ictus_bsr_matvec with one more component. Each block's three products are added first (in
 * column order), the blocks of a row go alternately into two partial sums (odd and even
 * positions), added at the end; the same prefetch of the block stream.
 */
void ictus_bsr3_matvec(int n, const int *restrict row_ptr, const int *restrict col,
                       const double *restrict val, const double *restrict x,
                       double *restrict y)
{
  for (int i = 0; i < n; i++) {
    const int k0 = row_ptr[i] - 1;
    const int k1 = row_ptr[i + 1] - 2;
    double a[3] = {0.0, 0.0, 0.0}, b[3] = {0.0, 0.0, 0.0};
    int k;
    for (k = k0; k < k1; k += 2) {
      const double *v = val + 9 * (intptr_t)k;
      const double *w = v + 9;
      __builtin_prefetch((const void *)((uintptr_t)v + PREFETCH_BYTES), 0, 3);
      const double *xa = x + 3 * (intptr_t)(col[k] - 1);
      const double *xb = x + 3 * (intptr_t)(col[k + 1] - 1);
      for (int c = 0; c < 3; c++) {
        a[c] = a[c] + ((v[c] * xa[0] + v[3 + c] * xa[1]) + v[6 + c] * xa[2]);
        b[c] = b[c] + ((w[c] * xb[0] + w[3 + c] * xb[1]) + w[6 + c] * xb[2]);
      }
    }
    if ((k1 - k0) % 2 == 0) {
      const double *v = val + 9 * (intptr_t)k1;
      const double *xa = x + 3 * (intptr_t)(col[k1] - 1);
      for (int c = 0; c < 3; c++)
        a[c] = a[c] + ((v[c] * xa[0] + v[3 + c] * xa[1]) + v[6 + c] * xa[2]);
    }
    for (int c = 0; c < 3; c++) y[3 * (intptr_t)i + c] = a[c] + b[c];
  }
}

