/* The broad phase of the node- and point-to-surface plugins (penalty-nts, covariant-penalty): the candidate master
 * faces of one contact point from the box its point sweeps over a step, through the host's search tree. Built into
 * stickslip_plugin_common with the covariant kernel; it calls the host only through the sk_contact_services table. */
#ifndef STICKSLIP_PLUGIN_COMMON_CANDIDATES_H
#define STICKSLIP_PLUGIN_COMMON_CANDIDATES_H

#include "stickslip/plugin.h"

/* The candidates of all points of an instance, point by point: point k's are faces[start_k .. start_k + count_k). */
typedef struct {
  int *faces;
  int capacity;
  int used; /* 0 before the first point of a search */
} cand_list;

/* Appends the faces whose (refitted) boxes meet the box of the segment r0 -> r1 (dim coordinates) inflated by
 * margin, growing the list; *start and *count describe them. Returns 0, or -1 when out of memory. */
int cand_query_swept(const sk_contact_services *cs, sk_search *search, const double *r0, const double *r1, int dim,
                     double margin, cand_list *list, int *start, int *count);

/* 1 when face is among the count candidates from start. */
int cand_contains(const cand_list *list, int start, int count, int face);

/* The help line of `master_extension`, the same in the node-to-surface plugins that take it. */
#define MASTER_EXTENSION_HELP                                                                                        \
  "master_extension: a slave node up to this fraction of a face beyond the master's border stays in contact with "   \
  "the extrapolated face (0 switches it off) [0.1]"

/* 1 when the face parameters xi of a face of `type` lie within `band` (a fraction of the face) beyond its border:
 * |xi| <= 1 + 2 band on lines and quadrilaterals, barycentrics >= -band on triangles (`master_extension`). */
int cand_within_band(sk_elem_type type, const double xi[2], double band);

#endif
