/*
 * Solves one LCP file in Siconos' format with Siconos numerics' lexicographic Lemke
 * (lcp_lexicolemke) and prints its status, pivots, error, z, and the best-of-5 mean time of
 * one solve. A cross-check of moreau-lcp on single files (for example Siconos' own test
 * problems), not part of its build; it needs Siconos numerics (Debian:
 * libsiconos-numerics-dev).
 *
 *   cc -O2 -o solve_file crates/lcp/siconos/solve_file.c -I/usr/include/siconos -lsiconos_numerics
 *   ./solve_file crates/lcp/tests/data/siconos/lcp/lcp_tobenna.dat 1000
 *
 * lcp_lexicolemke writes the basic entries of z only, so z is cleared before every solve.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <siconos/numerics/LinearComplementarityProblem.h>
#include <siconos/numerics/LCP_Solvers.h>
#include <siconos/numerics/SolverOptions.h>
#include <siconos/numerics/lcp_cst.h>

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: %s FILE REPEATS\n", argv[0]);
    return 2;
  }
  int repeats = atoi(argv[2]);
  LinearComplementarityProblem *p = newLCP();
  /* The reader's return value is not a success flag in Siconos 4.4: check the size. */
  linearComplementarity_newFromFilename(p, argv[1]);
  int n = p->size;
  if (n <= 0 || repeats <= 0) {
    fprintf(stderr, "cannot read %s (or REPEATS is not positive)\n", argv[1]);
    return 1;
  }
  double *z = calloc(n, sizeof *z), *w = calloc(n, sizeof *w);
  SolverOptions *options = solver_options_create(SICONOS_LCP_LEMKE);
  int info = 0;
  lcp_lexicolemke(p, z, w, &info, options);
  double error = -1.0;
  lcp_compute_error(p, z, w, 1e-10, &error);
  printf("info %d pivots %d error %.3e z", info, options->iparam[SICONOS_IPARAM_ITER_DONE],
         error);
  for (int i = 0; i < n; i++) printf(" %.17g", z[i]);
  printf("\n");
  double best = 1e300;
  for (int round = 0; round < 5; round++) {
    double t0 = now();
    for (int r = 0; r < repeats; r++) {
      memset(z, 0, n * sizeof *z);
      lcp_lexicolemke(p, z, w, &info, options);
    }
    double per_solve = (now() - t0) / repeats;
    if (per_solve < best) best = per_solve;
  }
  printf("lcp_lexicolemke %.3f us per solve (best of 5 rounds)\n", 1e6 * best);
  solver_options_delete(options);
  free(z);
  free(w);
  return 0;
}
