/* One piece per rank of a VTU output step (vtu_pieces.h). */
#define _GNU_SOURCE
#include "vtu_pieces.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

sk_status sk_vtu_pieces_write(sk_system *sys, sk_status status, const char *dir, const char *prefix,
                              const sk_vtu_piece *piece) {
  const sk_model *m = sys->model;
  char folder[1200], path[1400];
  snprintf(folder, sizeof folder, "%s/%s", dir, prefix);
  /* every rank makes the step's folder (the first one does, the others find it) */
  if (status == SK_OK && mkdir(folder, 0777) != 0 && errno != EEXIST)
    status = sk_error_set(SK_ERR_IO, "cannot create directory '%s': %s", folder, strerror(errno));
  snprintf(path, sizeof path, "%s/rank-%04d.vtu", folder, m->rank);
  if (status == SK_OK)
    status = sk_vtu_write(path, piece->n_points, piece->points, piece->n_cells, piece->types, piece->offsets,
                          piece->conn, piece->n_point_fields, piece->point_fields, piece->n_cell_fields,
                          piece->cell_fields);
  /* the pieces are complete before the .pvtu names them */
  status = sk_system_collective(sys, status);
  if (status != SK_OK || m->rank != 0) return status;
  char **names = malloc(sizeof(char *) * (size_t)m->n_ranks);
  char *storage = malloc(96 * (size_t)m->n_ranks);
  if (!names || !storage) status = sk_error_set(SK_ERR_NOMEM, "out of memory for the VTU output");
  for (int r = 0; status == SK_OK && r < m->n_ranks; ++r) {
    names[r] = storage + 96 * r;
    snprintf(names[r], 96, "%s/rank-%04d.vtu", prefix, r);
  }
  snprintf(path, sizeof path, "%s/%s.pvtu", dir, prefix);
  if (status == SK_OK)
    status = sk_pvtu_write(path, m->n_ranks, (const char *const *)names, piece->n_point_fields, piece->point_fields,
                           piece->n_cell_fields, piece->cell_fields);
  free(names);
  free(storage);
  return status;
}
