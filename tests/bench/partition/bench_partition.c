/* The contact partition's bisection (sk_rcb, core/model/contact_partition.c) against Zoltan2's RCB and multijagged
 * on the same weighted slave entities (docs/scaling.md, "Contact partition: sk_rcb against Zoltan2").
 *
 * Input: the files a run writes at each rebalance with STICKSLIP_DUMP_CONTACT_PARTITION=DIR (a pair's slave nodes
 * at t_n and face centroids, each with the weight the rebalance bisects, and the faces' nodes). For each file, each
 * number of parts and each partitioner, the nodes and the faces are split as the rebalance splits them, with the
 * measured weights and with unit weights (the set-up's split), and reported:
 *   time      CPU seconds to split the nodes and the faces (the median of --repeat calls)
 *   node_imb  the largest part's node weight over the mean part's; face_imb the same for the faces
 *   cut       node pairs sharing a face whose nodes lie in different parts (of all such pairs)
 *   nbrs      the most parts any part shares such a pair with
 *   evals     face evaluations per face: a face is evaluated by every part owning it or one of its nodes (the
 *             repeated work of mortar-dual, docs/design.md "Contact partition", item 8)
 *
 *   bench_partition [--repeat N] [--parts 2,4,8] [--tolerance T] FILE...
 * Runs on one process (MPI_COMM_SELF): every rank computes the split of the whole slave surface, as the host does. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "contact_partition.h"
#include "zoltan2_partition.h"

typedef struct {
  int n, nf, nen;
  double *node_pos, *node_w, *face_pos, *face_w;
  int *conn;
} entities;

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t); /* CPU time: a loaded machine deschedules the bench */
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int read_entities(const char *path, entities *e) {
  memset(e, 0, sizeof *e);
  FILE *in = fopen(path, "r");
  if (!in) return fprintf(stderr, "bench_partition: cannot read %s\n", path), -1;
  char line[512];
  int ok = 0;
  while (fgets(line, sizeof line, in))
    if (line[0] != '#') {
      ok = sscanf(line, "nodes %d faces %d nen %d", &e->n, &e->nf, &e->nen) == 3;
      break;
    }
  if (ok && e->n > 0 && e->nf > 0 && e->nen > 0) {
    e->node_pos = calloc(3 * (size_t)e->n, sizeof(double));
    e->node_w = malloc(sizeof(double) * (size_t)e->n);
    e->face_pos = calloc(3 * (size_t)e->nf, sizeof(double));
    e->face_w = malloc(sizeof(double) * (size_t)e->nf);
    e->conn = malloc(sizeof(int) * (size_t)e->nf * (size_t)e->nen);
    ok = e->node_pos && e->node_w && e->face_pos && e->face_w && e->conn;
  } else {
    ok = 0;
  }
  for (int j = 0; ok && j < e->n; ++j)
    ok = fscanf(in, "%lf %lf %lf %lf", &e->node_pos[3 * j], &e->node_pos[3 * j + 1], &e->node_pos[3 * j + 2],
                &e->node_w[j]) == 4;
  for (int f = 0; ok && f < e->nf; ++f) {
    ok = fscanf(in, "%lf %lf %lf %lf", &e->face_pos[3 * f], &e->face_pos[3 * f + 1], &e->face_pos[3 * f + 2],
                &e->face_w[f]) == 4;
    for (int a = 0; ok && a < e->nen; ++a) {
      int *c = &e->conn[(size_t)f * e->nen + a];
      ok = fscanf(in, "%d", c) == 1 && *c >= 0 && *c < e->n;
    }
  }
  fclose(in);
  if (!ok) fprintf(stderr, "bench_partition: %s is not a contact partition dump (or out of memory)\n", path);
  return ok ? 0 : -1;
}

static int compare_double(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* the largest part's weight over the mean part's */
static double imbalance(int n, const double *w, const int *part, int n_parts) {
  double *sum = calloc((size_t)n_parts, sizeof(double)), total = 0.0, most = 0.0;
  for (int j = 0; sum && j < n; ++j) sum[part[j]] += w[j], total += w[j];
  for (int p = 0; sum && p < n_parts; ++p) most = sum[p] > most ? sum[p] : most;
  free(sum);
  return total > 0.0 ? most / (total / n_parts) : 0.0;
}

typedef struct {
  double time, node_imb, face_imb, cut_share, evals;
  long cut, pairs;
  int nbrs;
} figures;

/* cut node pairs, the most neighbour parts, face evaluations per face */
static void connectivity(const entities *e, const int *node_part, const int *face_part, int n_parts, figures *out) {
  unsigned char *adjacent = calloc((size_t)n_parts * n_parts, 1);
  long pairs = 0, cut = 0, evals = 0;
  int seen[64];
  for (int f = 0; f < e->nf; ++f) {
    const int *c = e->conn + (size_t)f * e->nen;
    for (int a = 0; a < e->nen; ++a)
      for (int b = a + 1; b < e->nen; ++b) {
        ++pairs;
        const int p = node_part[c[a]], q = node_part[c[b]];
        if (p == q) continue;
        ++cut;
        if (adjacent) adjacent[p * n_parts + q] = adjacent[q * n_parts + p] = 1;
      }
    int n_seen = 0;
    seen[n_seen++] = face_part[f];
    for (int a = 0; a < e->nen && n_seen < 64; ++a) {
      int known = 0;
      for (int s = 0; s < n_seen; ++s) known |= seen[s] == node_part[c[a]];
      if (!known) seen[n_seen++] = node_part[c[a]];
    }
    evals += n_seen;
  }
  out->nbrs = 0;
  for (int p = 0; adjacent && p < n_parts; ++p) {
    int k = 0;
    for (int q = 0; q < n_parts; ++q) k += adjacent[p * n_parts + q];
    out->nbrs = k > out->nbrs ? k : out->nbrs;
  }
  free(adjacent);
  out->cut = cut, out->pairs = pairs;
  out->evals = (double)evals / e->nf;
}

/* one partitioner ("sk_rcb" or a Zoltan2 algorithm) on the nodes and faces; 0 or -1 */
static int run(const char *method, const entities *e, const double *node_w, const double *face_w, int n_parts,
               int repeat, double tolerance, int *node_part, int *face_part, figures *out) {
  double *times = malloc(sizeof(double) * (size_t)repeat);
  int failed = !times;
  for (int r = 0; !failed && r < repeat; ++r) {
    const double t0 = now();
    if (!strcmp(method, "sk_rcb"))
      failed = sk_rcb(e->n, e->node_pos, node_w, n_parts, 0, node_part) != 0 ||
               sk_rcb(e->nf, e->face_pos, face_w, n_parts, 0, face_part) != 0;
    else
      failed = bench_zoltan2_partition(method, e->n, 3, e->node_pos, node_w, n_parts, tolerance, node_part) != 0 ||
               bench_zoltan2_partition(method, e->nf, 3, e->face_pos, face_w, n_parts, tolerance, face_part) != 0;
    if (!failed) times[r] = now() - t0;
  }
  for (int j = 0; !failed && j < e->n; ++j) failed = node_part[j] < 0 || node_part[j] >= n_parts;
  for (int f = 0; !failed && f < e->nf; ++f) failed = face_part[f] < 0 || face_part[f] >= n_parts;
  if (!failed) {
    qsort(times, (size_t)repeat, sizeof(double), compare_double);
    out->time = times[repeat / 2];
    out->node_imb = imbalance(e->n, node_w, node_part, n_parts);
    out->face_imb = imbalance(e->nf, face_w, face_part, n_parts);
    connectivity(e, node_part, face_part, n_parts, out);
  }
  free(times);
  return failed ? -1 : 0;
}

int main(int argc, char **argv) {
  int repeat = 21, parts[8] = {2, 4, 8}, n_parts_list = 3, first_file = argc;
  double tolerance = 1.0001;
  for (int a = 1; a < argc; ++a) {
    if (!strcmp(argv[a], "--repeat") && a + 1 < argc) repeat = atoi(argv[++a]);
    else if (!strcmp(argv[a], "--tolerance") && a + 1 < argc) tolerance = atof(argv[++a]);
    else if (!strcmp(argv[a], "--parts") && a + 1 < argc) {
      n_parts_list = 0;
      for (char *tok = strtok(argv[++a], ","); tok && n_parts_list < 8; tok = strtok(NULL, ","))
        parts[n_parts_list++] = atoi(tok);
    } else if (argv[a][0] == '-') {
      fprintf(stderr, "usage: %s [--repeat N] [--parts 2,4,8] [--tolerance T] FILE...\n", argv[0]);
      return 2;
    } else {
      first_file = a;
      break;
    }
  }
  if (first_file >= argc || repeat < 1) {
    fprintf(stderr, "usage: %s [--repeat N] [--parts 2,4,8] [--tolerance T] FILE...\n", argv[0]);
    return 2;
  }
  for (int k = 0; k < n_parts_list; ++k)
    if (parts[k] < 1 || parts[k] > 64) return fprintf(stderr, "bench_partition: --parts between 1 and 64\n"), 2;
  MPI_Init(&argc, &argv);
  bench_zoltan2_initialize();
  static const char *const methods[] = {"sk_rcb", "rcb", "multijagged"};
  printf("file,weights,nodes,faces,parts,method,time_us,node_imb,face_imb,cut,pairs,nbrs,evals_per_face\n");
  int status = 0;
  for (int a = first_file; a < argc && status == 0; ++a) {
    entities e;
    if (read_entities(argv[a], &e) != 0) {
      status = 1;
      break;
    }
    double *unit = malloc(sizeof(double) * (size_t)(e.n > e.nf ? e.n : e.nf));
    int *node_part = malloc(sizeof(int) * (size_t)e.n), *face_part = malloc(sizeof(int) * (size_t)e.nf);
    if (!unit || !node_part || !face_part) status = 1;
    for (int j = 0; unit && j < (e.n > e.nf ? e.n : e.nf); ++j) unit[j] = 1.0;
    const char *name = strrchr(argv[a], '/') ? strrchr(argv[a], '/') + 1 : argv[a];
    for (int weighted = 1; status == 0 && weighted >= 0; --weighted)
      for (int k = 0; status == 0 && k < n_parts_list; ++k)
        for (size_t m = 0; status == 0 && m < sizeof methods / sizeof *methods; ++m) {
          figures fig;
          if (run(methods[m], &e, weighted ? e.node_w : unit, weighted ? e.face_w : unit, parts[k], repeat,
                  tolerance, node_part, face_part, &fig) != 0) {
            status = 1;
            break;
          }
          printf("%s,%s,%d,%d,%d,%s,%.1f,%.3f,%.3f,%ld,%ld,%d,%.3f\n", name, weighted ? "measured" : "unit", e.n,
                 e.nf, parts[k], methods[m], 1e6 * fig.time, fig.node_imb, fig.face_imb, fig.cut, fig.pairs,
                 fig.nbrs, fig.evals);
        }
    free(unit), free(node_part), free(face_part);
    free(e.node_pos), free(e.node_w), free(e.face_pos), free(e.face_w), free(e.conn);
  }
  bench_zoltan2_finalize();
  MPI_Finalize();
  return status;
}
