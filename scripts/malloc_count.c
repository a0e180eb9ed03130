/* Counts the heap allocations of a process (LD_PRELOAD), for the allocation check of
 * bench/benchmark.py --alloc-check (doc/performance.md):
 *
 *   cc -O2 -shared -fPIC -o malloc_count.so scripts/malloc_count.c
 *   MALLOC_COUNT_OUT=counts.txt LD_PRELOAD=./malloc_count.so build/bin/ictus deck.inp
 *
 * At exit each process appends "<command name> <pid> malloc=<n> calloc=<n> realloc=<n>
 * free=<n>" to $MALLOC_COUNT_OUT (default: stderr). Works with -march=native code (valgrind
 * 3.19 stops at AVX-512 instructions). The wrappers call glibc's __libc_* functions, so no
 * dlsym bootstrap is needed. Counters are not atomic: single-threaded processes only. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

extern void *__libc_malloc(size_t);
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);
extern void __libc_free(void *);

static unsigned long n_malloc, n_calloc, n_realloc, n_free;

void *malloc(size_t n) { n_malloc++; return __libc_malloc(n); }
void *calloc(size_t a, size_t b) { n_calloc++; return __libc_calloc(a, b); }
void *realloc(void *p, size_t n) { n_realloc++; return __libc_realloc(p, n); }
void free(void *p) { if (p) n_free++; __libc_free(p); }

__attribute__((destructor)) static void report(void) {
  char name[64] = "?";
  FILE *f = fopen("/proc/self/comm", "r");
  if (f) {
    if (fgets(name, sizeof name, f)) name[strcspn(name, "\n")] = 0;
    fclose(f);
  }
  unsigned long m = n_malloc, c = n_calloc, r = n_realloc, fr = n_free;
  const char *path = getenv("MALLOC_COUNT_OUT");
  FILE *out = path ? fopen(path, "a") : NULL;
  fprintf(out ? out : stderr, "%s %d malloc=%lu calloc=%lu realloc=%lu free=%lu\n", name,
          (int)getpid(), m, c, r, fr);
  if (out) fclose(out);
}
