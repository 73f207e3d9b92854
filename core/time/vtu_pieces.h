/* One piece per rank of a VTU output step (vtu_pieces.c), internal to the simulation layer: the bodies' pieces
 * (recorder.c) and the slave surfaces' (contact_surface.c). */
#ifndef STICKSLIP_VTU_PIECES_H
#define STICKSLIP_VTU_PIECES_H

#include "../model/system.h"
#include "stickslip/output.h"

/* A rank's piece: its points (3 each), cells and fields, as sk_vtu_write takes them. */
typedef struct {
  int n_points, n_cells;
  const double *points;
  const sk_elem_type *types;
  const int *offsets, *conn;
  int n_point_fields, n_cell_fields;
  const sk_vtu_field *point_fields, *cell_fields;
} sk_vtu_piece;

/* Every rank writes `dir`/`prefix`/rank-RRRR.vtu (making the folder), and once all are written rank 0 writes
 * `dir`/`prefix`.pvtu naming them (with rank 0's field names). `status`: the rank's status so far (a rank that failed
 * writes nothing; every rank gets the worst). Collective. */
sk_status sk_vtu_pieces_write(sk_system *sys, sk_status status, const char *dir, const char *prefix,
                              const sk_vtu_piece *piece);

#endif
