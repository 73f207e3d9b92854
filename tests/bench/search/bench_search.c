/* Broad-phase scaling benchmark: AABB tree (sk_search_*) against brute force.
 *
 * For master QUAD4 surfaces of n = 1e3 ... 1e6 faces (a flat and a curved m x m patch) and a facing slave surface
 * with about as many nodes, one box per slave node (node +- half a face size) is queried. Reported per n: tree
 * build (first update), refit (second update), all queries, and brute force over every face box (only while its
 * predicted time stays under the limit). Both answers are compared hit for hit (the counts must agree).
 *
 *   bench_search [--max-faces N] [--brute-limit SECONDS] [--csv FILE]
 *
 * Writes the CSV (default search-scaling.csv); tests/bench/search/search-scaling.gp plots it. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "stickslip/contact.h"

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* m x m QUAD4 faces over [0, 1]^2 at height z0; curved: a gentle wave. */
static void make_master(sk_surface *s, double **q, int m, int curved) {
  memset(s, 0, sizeof *s);
  snprintf(s->name, sizeof s->name, "master");
  s->dim = 3, s->face_type = SK_QUAD4, s->nen = 4, s->n_edges = 4;
  int mn = m + 1;
  s->n_faces = m * m;
  s->n_nodes = mn * mn;
  s->conn = malloc((size_t)s->n_faces * 4 * sizeof(int));
  s->nodes = malloc((size_t)s->n_nodes * sizeof(int));
  s->face_neighbors = malloc((size_t)s->n_faces * 4 * sizeof(int));
  *q = malloc((size_t)s->n_nodes * 3 * sizeof(double));
  for (int j = 0; j < mn; ++j)
    for (int i = 0; i < mn; ++i) {
      double *x = *q + 3 * (size_t)(j * mn + i), u = (double)i / m, v = (double)j / m;
      x[0] = u, x[1] = v;
      x[2] = curved ? 0.05 * sin(6.0 * u) * cos(4.0 * v) : 0.0;
      s->nodes[j * mn + i] = j * mn + i;
    }
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      int f = j * m + i, *c = s->conn + 4 * (size_t)f, *nb = s->face_neighbors + 4 * (size_t)f;
      c[0] = j * mn + i, c[1] = j * mn + i + 1, c[2] = (j + 1) * mn + i + 1, c[3] = (j + 1) * mn + i;
      nb[0] = j > 0 ? f - m : -1, nb[1] = i < m - 1 ? f + 1 : -1, nb[2] = j < m - 1 ? f + m : -1;
      nb[3] = i > 0 ? f - 1 : -1;
    }
}

static void free_master(sk_surface *s, double *q) {
  free(s->conn);
  free(s->nodes);
  free(s->face_neighbors);
  free(q);
}

int main(int argc, char **argv) {
  long max_faces = 1000000;
  double brute_limit = 8.0;
  const char *csv_path = "search-scaling.csv";
  for (int a = 1; a < argc; ++a) {
    if (!strcmp(argv[a], "--max-faces") && a + 1 < argc) max_faces = atol(argv[++a]);
    else if (!strcmp(argv[a], "--brute-limit") && a + 1 < argc) brute_limit = atof(argv[++a]);
    else if (!strcmp(argv[a], "--csv") && a + 1 < argc) csv_path = argv[++a];
    else {
      fprintf(stderr, "usage: %s [--max-faces N] [--brute-limit SECONDS] [--csv FILE]\n", argv[0]);
      return 2;
    }
  }
  FILE *csv = fopen(csv_path, "w");
  if (!csv) {
    fprintf(stderr, "bench_search: cannot write %s\n", csv_path);
    return 1;
  }
  fprintf(csv, "shape,faces,queries,build_s,refit_s,query_s,us_per_query,hits_per_query,brute_s,"
               "build_ns_per_nlog2n\n");
  printf("%-6s %8s %8s %9s %9s %9s %9s %7s %10s\n", "shape", "faces", "queries", "build s", "refit s", "query s",
         "us/query", "hits", "brute s");
  const int sizes[] = {32, 56, 100, 178, 316, 562, 1000};
  int status = 0;
  for (int shape = 0; shape < 2; ++shape) {
    double brute_cost = 0.0; /* seconds per (query x face), measured at the last size brute force ran */
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; ++k) {
      int m = sizes[k];
      if ((long)m * m > max_faces) break;
      sk_surface master;
      double *q;
      make_master(&master, &q, m, shape == 1);
      /* Slave nodes: a slightly rotated grid of about m^2 points hovering above the master. */
      int ms = m, n_queries = ms * ms;
      double h = 1.0 / m, rotation = 0.1;
      double *boxes = malloc((size_t)n_queries * 6 * sizeof(double));
      for (int j = 0; j < ms; ++j)
        for (int i = 0; i < ms; ++i) {
          double u = (i + 0.5) / ms - 0.5, v = (j + 0.5) / ms - 0.5;
          double x = 0.5 + 0.95 * (cos(rotation) * u - sin(rotation) * v);
          double y = 0.5 + 0.95 * (sin(rotation) * u + cos(rotation) * v);
          double z = (shape == 1 ? 0.05 * sin(6.0 * x) * cos(4.0 * y) : 0.0) + 0.2 * h;
          double *b = boxes + 6 * (size_t)(j * ms + i);
          b[0] = x - 0.5 * h, b[1] = y - 0.5 * h, b[2] = z - 0.5 * h;
          b[3] = x + 0.5 * h, b[4] = y + 0.5 * h, b[5] = z + 0.5 * h;
        }
      int *found = malloc((size_t)master.n_faces * sizeof(int));
      int repeats = master.n_faces < 100000 ? 5 : 1;
      double build = INFINITY, refit = INFINITY, query = INFINITY;
      long hits = 0;
      for (int r = 0; r < repeats; ++r) {
        sk_search *search;
        if (sk_search_create(&master, &search) != SK_OK) {
          fprintf(stderr, "bench_search: %s\n", sk_error_message());
          return 1;
        }
        double t0 = now();
        sk_search_update(search, q, q, 0.0); /* first update: the split */
        double t1 = now();
        sk_search_update(search, q, q, 0.0); /* refit only */
        double t2 = now();
        hits = 0;
        for (int p = 0; p < n_queries; ++p)
          hits += sk_search_query(search, boxes + 6 * (size_t)p, boxes + 6 * (size_t)p + 3, found, master.n_faces);
        double t3 = now();
        build = fmin(build, t1 - t0), refit = fmin(refit, t2 - t1), query = fmin(query, t3 - t2);
        if (r == repeats - 1) {
          double predicted = brute_cost * (double)n_queries * master.n_faces;
          if (brute_cost == 0.0 || predicted < brute_limit) {
            long brute_hits = 0;
            double b0 = now();
            for (int p = 0; p < n_queries; ++p)
              brute_hits += sk_search_brute_force(search, boxes + 6 * (size_t)p, boxes + 6 * (size_t)p + 3, found,
                                                  master.n_faces);
            double brute = now() - b0;
            brute_cost = brute / ((double)n_queries * master.n_faces);
            if (brute_hits != hits) {
              fprintf(stderr, "bench_search: tree found %ld hits, brute force %ld (n = %d)\n", hits, brute_hits,
                      master.n_faces);
              status = 1;
            }
            fprintf(csv, "%s,%d,%d,%.6e,%.6e,%.6e,%.4f,%.2f,%.6e,%.4f\n", shape ? "curved" : "flat", master.n_faces,
                    n_queries, build, refit, query, 1e6 * query / n_queries, (double)hits / n_queries, brute,
                    1e9 * build / (master.n_faces * log2((double)master.n_faces)));
            printf("%-6s %8d %8d %9.4f %9.4f %9.4f %9.3f %7.2f %10.4f\n", shape ? "curved" : "flat", master.n_faces,
                   n_queries, build, refit, query, 1e6 * query / n_queries, (double)hits / n_queries, brute);
          } else {
            fprintf(csv, "%s,%d,%d,%.6e,%.6e,%.6e,%.4f,%.2f,,%.4f\n", shape ? "curved" : "flat", master.n_faces,
                    n_queries, build, refit, query, 1e6 * query / n_queries, (double)hits / n_queries,
                    1e9 * build / (master.n_faces * log2((double)master.n_faces)));
            printf("%-6s %8d %8d %9.4f %9.4f %9.4f %9.3f %7.2f %10s (predicted %.0f s)\n", shape ? "curved" : "flat",
                   master.n_faces, n_queries, build, refit, query, 1e6 * query / n_queries,
                   (double)hits / n_queries, "-", predicted);
          }
        }
        sk_search_destroy(search);
      }
      fflush(stdout);
      free(found);
      free(boxes);
      free_master(&master, q);
    }
  }
  fclose(csv);
  return status;
}
