/*
 * Solves Siconos FC2D and GFC2D files with Siconos numerics' 2D frictional-contact solvers
 * and prints, per file, one line: the solver, Siconos' info flag, the iterations done, its
 * own error (fc2d_compute_error, normalised by the norm of q as its NSGS does), and the
 * mean time of one solve from r = 0 over the repeats. The peer of the fc2d example of
 * moreau-lcp, not part of its build; it needs Siconos numerics (Debian:
 * libsiconos-numerics-dev). compare_fc2d.sh runs both side by side.
 *
 *   cc -O2 -o compare_fc2d crates/lcp/siconos/compare_fc2d.c -I/usr/include/siconos -lsiconos_numerics -lm
 *   ./compare_fc2d nsgs|lemke|enum TOL REPEATS FILE...
 *
 * A GFC2D file (name starting with "gfc2d") is reduced to the contact space by Siconos'
 * globalFrictionContact_reformulation_FrictionContact; a W in CSparse storage is converted to
 * sparse-block storage (fc2d_driver takes dense or sparse-block W only), outside the timed
 * part. NSGS runs at most 100,000 sweeps.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <siconos/numerics/FrictionContactProblem.h>
#include <siconos/numerics/GlobalFrictionContactProblem.h>
#include <siconos/numerics/NonSmoothDrivers.h>
#include <siconos/numerics/SolverOptions.h>
#include <siconos/numerics/Friction_cst.h>
#include <siconos/numerics/fc2d_Solvers.h>
#include <siconos/numerics/fc2d_compute_error.h>
#include <siconos/numerics/NumericsMatrix.h>
#include <siconos/numerics/SparseBlockMatrix.h>

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

static FrictionContactProblem *read_problem(const char *path) {
  const char *base = strrchr(path, '/');
  base = base ? base + 1 : path;
  if (strncmp(base, "gfc2d", 5) == 0) {
    GlobalFrictionContactProblem *g = globalFrictionContact_new_from_filename(path);
    if (!g) return NULL;
    return globalFrictionContact_reformulation_FrictionContact(g);
  }
  return frictionContact_new_from_filename(path);
}

static double norm2(const double *x, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) s += x[i] * x[i];
  return sqrt(s);
}

int main(int argc, char **argv) {
  if (argc < 5) {
    fprintf(stderr, "usage: %s nsgs|lemke|enum TOL REPEATS FILE...\n", argv[0]);
    return 2;
  }
  const char *name = argv[1];
  double tol = atof(argv[2]);
  int repeats = atoi(argv[3]);
  int id = strcmp(name, "nsgs") == 0    ? SICONOS_FRICTION_2D_NSGS
           : strcmp(name, "lemke") == 0 ? SICONOS_FRICTION_2D_LEMKE
           : strcmp(name, "enum") == 0  ? SICONOS_FRICTION_2D_ENUM
                                        : -1;
  if (id < 0 || repeats < 1) {
    fprintf(stderr, "unknown solver %s or repeats %d\n", name, repeats);
    return 2;
  }
  for (int f = 4; f < argc; f++) {
    FrictionContactProblem *p = read_problem(argv[f]);
    if (!p) {
      fprintf(stderr, "cannot read %s\n", argv[f]);
      return 1;
    }
    int n = 2 * p->numberOfContacts;
    if (n > 0 && p->M->storageType == NM_SPARSE) {
      /* fc2d_driver takes dense or sparse-block W only: convert CSparse to 2x2 blocks. */
      SparseBlockStructuredMatrix *sbm = SBM_new();
      if (SBM_from_csparse(2, NM_csc(p->M), sbm) != 0) {
        fprintf(stderr, "cannot convert W of %s to blocks\n", argv[f]);
        return 1;
      }
      p->M = NM_new_SBM(n, n, sbm);
    }
    if (n == 0) {
      printf("%s %s contacts 0 info 0 iterations 0 error 0 seconds 0\n", argv[f], name);
      continue;
    }
    double *r = calloc(n, sizeof *r), *u = calloc(n, sizeof *u);
    SolverOptions *options = solver_options_create(id);
    options->iparam[SICONOS_IPARAM_MAX_ITER] = 100000;
    options->dparam[SICONOS_DPARAM_TOL] = tol;
    int info = 0;
    double t0 = now();
    for (int k = 0; k < repeats; k++) {
      memset(r, 0, n * sizeof *r);
      memset(u, 0, n * sizeof *u);
      info = fc2d_driver(p, r, u, options);
    }
    double seconds = (now() - t0) / repeats;
    double error = -1.0;
    fc2d_compute_error(p, r, u, tol, norm2(p->q, n), &error);
    printf("%s %s contacts %d info %d iterations %d error %.3e seconds %.6e\n", argv[f], name,
           p->numberOfContacts, info, options->iparam[SICONOS_IPARAM_ITER_DONE], error, seconds);
    fflush(stdout);
    solver_options_delete(options);
    free(r);
    free(u);
  }
  return 0;
}
