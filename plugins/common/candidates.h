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

#endif
