/*
 * Solves the bench sets with Siconos numerics' lexicographic Lemke (lcp_lexicolemke) and
 * prints, per problem, Siconos' status, its error and z, then the best-of-5 mean time of one
 * solve. A cross-check of moreau-lcp, not part of its build; it needs Siconos numerics
 * (Debian: libsiconos-numerics-dev).
 *
 *   cargo run --release -p moreau-lcp --example write_bench_sets -- /tmp/sets friction_9
 *   cc -O2 -o compare crates/lcp/siconos/compare.c -I/usr/include/siconos -lsiconos_numerics
 *   ./compare /tmp/sets friction_9 2000
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

#define SET_SIZE 16

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv) {
  if (argc != 4) {
    fprintf(stderr, "usage: %s DIR SET REPEATS\n", argv[0]);
    return 2;
  }
  const char *dir = argv[1], *name = argv[2];
  int repeats = atoi(argv[3]);
  LinearComplementarityProblem *p[SET_SIZE];
  int n = 0;
  for (int k = 0; k < SET_SIZE; k++) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s_%d.dat", dir, name, k);
    p[k] = newLCP();
    /* The reader's return value is not a success flag in Siconos 4.4: check the size. */
    linearComplementarity_newFromFilename(p[k], path);
    if (p[k]->size <= 0 || (n && p[k]->size != n)) {
      fprintf(stderr, "cannot read %s\n", path);
      return 1;
    }
    n = p[k]->size;
  }
  double *z = calloc(n, sizeof *z), *w = calloc(n, sizeof *w);
  SolverOptions *options = solver_options_create(SICONOS_LCP_LEMKE);
  int info = 0;
  for (int k = 0; k < SET_SIZE; k++) {
    memset(z, 0, n * sizeof *z);
    lcp_lexicolemke(p[k], z, w, &info, options);
    double error = -1.0;
    lcp_compute_error(p[k], z, w, 1e-10, &error);
    printf("%d info %d error %.3e z", k, info, error);
    for (int i = 0; i < n; i++) printf(" %.17g", z[i]);
    printf("\n");
  }
  double best = 1e300;
  for (int round = 0; round < 5; round++) {
    double t0 = now();
    for (int r = 0; r < repeats; r++) {
      for (int k = 0; k < SET_SIZE; k++) {
        memset(z, 0, n * sizeof *z);
        lcp_lexicolemke(p[k], z, w, &info, options);
      }
    }
    double per_solve = (now() - t0) / ((double)repeats * SET_SIZE);
    if (per_solve < best) best = per_solve;
  }
  fprintf(stderr, "%s: lcp_lexicolemke %.3f us per solve (best of 5 rounds)\n", name, 1e6 * best);
  solver_options_delete(options);
  free(z);
  free(w);
  return 0;
}
