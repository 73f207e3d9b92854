/* The contact fields on the slave surfaces over the ranks (contact_surface.c), internal to contact_output.c: each
 * rank holds the contact nodes and faces of its part of the slave surfaces, adds the fields of the points it reports
 * there, completes them with the ranks it shares nodes and faces with (ghost exchanges, no whole-surface array) and
 * writes its piece of the step's surfaces. */
#ifndef STICKSLIP_CONTACT_SURFACE_H
#define STICKSLIP_CONTACT_SURFACE_H

#include "../model/system.h"
#include "stickslip/output.h"

/* One contact point as contact.csv writes it after `step` and `time` (contact_output.c completes it). */
enum {
  R_PAIR, R_NODE, R_FACE, R_X, R_REFERENCE = R_X + 3, R_NORMAL = R_REFERENCE + 3, R_GAP = R_NORMAL + 3, R_STATE,
  R_PRESSURE, R_NORMAL_FORCE, R_AREA, R_TRACTION, R_SLIP_INCREMENT = R_TRACTION + 3, R_SLIP = R_SLIP_INCREMENT + 3,
  R_MULTIPLIER, N_RECORD
};

typedef struct sk_contact_surfaces sk_contact_surfaces;

/* This rank's part of the distinct slave surfaces of the model's pairs and the exchanges over them; the optional
 * VTU fields with friction / multipliers. Collective; *out is set even on failure. */
sk_status sk_contact_surfaces_open(const sk_model *model, int with_friction, int with_multipliers,
                                   sk_contact_surfaces **out);
void sk_contact_surfaces_free(sk_contact_surfaces *cs);
/* The fields of the step from this rank's points (records, N_RECORD each), completed on every contact node and face
 * this rank holds: a node's points (the one most in contact), else the mean of the faces around it; a face's Gauss
 * points (weighted by their measure), else the mean of its nodes. Collective. */
sk_status sk_contact_surfaces_fields(sk_contact_surfaces *cs, const double *records, int n_records);
/* The fields at the nodes this rank holds (local numbering, 0 away from the slave surfaces), for its piece of the
 * bodies' VTU: up to `max` into `fields`, returns how many (valid until the next call of _fields). */
int sk_contact_surfaces_node_fields(const sk_contact_surfaces *cs, sk_vtu_field *fields, int max);
/* Writes this rank's piece, `dir`/`prefix`/rank-RRRR.vtu: the slave faces it owns and their nodes at displacement u
 * (local dofs, ghosts included), with the fields; rank 0 also `dir`/`prefix`.pvtu naming every rank's piece.
 * Collective. */
sk_status sk_contact_surfaces_write(const sk_contact_surfaces *cs, sk_system *sys, const double *u, const char *dir,
                                    const char *prefix);

#endif
