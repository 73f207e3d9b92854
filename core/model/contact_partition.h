/* The contact partition (docs/design.md, "Contact partition"): with `contact_balance.rebalance: on` each eligible
 * pair's slave nodes and slave faces get a second owner, the contact owner, from a recursive coordinate bisection of
 * their positions over the ranks, computed at set-up from the whole mesh (every rank computes the same split, no
 * message), and again between steps when the contact work per rank is uneven (sk_contact_partition_rebalance). Every
 * rank keeps the whole slave surface (its nodes idle where unused), so that any rank can become a contact owner. The
 * contact owner builds the pair's slave view from its entities (view->owned, cell_owned), holds the
 * nodes those entities use as ghosts and owns the extras anchored at its slave nodes; the unknowns' owners, rows and
 * the bulk partition do not change (rows written by a rank that does not own them travel to their owners). */
#ifndef STICKSLIP_CONTACT_PARTITION_H
#define STICKSLIP_CONTACT_PARTITION_H

#include <stdio.h>

#include "stickslip/model.h"
#include "system.h"

/* Recursive coordinate bisection of n points (pos: 3 coordinates each) with weights (NULL: 1 each) into n_parts
 * parts first_part .. first_part + n_parts - 1 (part[i]). Each cut is across the longest side of its box (the
 * points' box at the first cut, then the parent's box cut at the cut), splitting the weight in proportion to the
 * parts on each side (ties broken by the points' order): deterministic. Returns 0, or -1 when out of memory. */
int sk_rcb(int n, const double *pos, const double *weight, int n_parts, int first_part, int *part);
/* Why pair k keeps the bulk partition with rebalancing on (a self-contact pair, a plugin without records), or NULL
 * when the contact partition applies to it. */
const char *sk_contact_partition_refused(const sk_model *model, int k);
/* The whole model, before it is distributed (collective only in that every rank computes the same): with
 * model->contact_rebalance, every eligible pair's contact owners (sk_contact_pair.contact_node_owner, _face_owner). */
sk_status sk_contact_partition_plan(sk_model *model);
/* After a step that asks for a rebalance (collective): each slave entity's measured work, the next bisection's
 * weight (sk_contact_pair.contact_weight): its contact owner's contact seconds of the step, split between the
 * entities in contact (from the pairs' points) and the others by a fit over the ranks of seconds against entities in
 * contact (entity_weights in contact_partition.c). */
sk_status sk_contact_partition_weigh(sk_system *sys);
/* A new contact partition at the predictor of a step after one whose contact work was uneven
 * (sys->contact_rebalance_pending, core/time/contact_balance.c; collective): each pair's bisection again, over the
 * slave nodes' positions at t_n and the faces' centroids, each entity weighted by its measured work
 * (sk_contact_partition_weigh; 1 each when none is measured). *changed: 1 when an owner
 * changed; the caller then re-creates the pairs' instances over their new views (sk_master_ghosts_renew). */
sk_status sk_contact_partition_rebalance(sk_system *sys, int *changed);
/* The contact owner of the slave surface's k-th node (its position in pair->slave.nodes) and f-th face: the
 * contact partition's, else the bulk owner (the node's owner; the face's element's). */
int sk_contact_node_owner(const sk_model *model, const sk_contact_pair *pair, int k);
int sk_contact_face_owner(const sk_model *model, const sk_contact_pair *pair, int f);
/* The contact owner of model node `node` for pair's plugin instance: the slave node's contact owner when the node
 * is on the slave surface and the pair (NULL: none) has a contact partition, else the node's owner. */
int sk_contact_owner_of_node(const sk_model *model, const sk_contact_pair *pair, int node);
/* The faces of this rank's slave view of the pair (used: 1 per slave face), whose nodes it holds: those it
 * evaluates (it contact-owns the face or one of its nodes) and every face sharing a node with them — two layers: an
 * averaged nodal normal (mortar-dual) needs every face around each node of a face it evaluates (mortar-dual refuses
 * a view without them). Returns 0, or -1 when out of memory. */
int sk_contact_faces_used(const sk_model *model, const sk_contact_pair *pair, unsigned char *used);
/* For `check --explain` and `run --verbose` (rank 0): the partition of every pair and the slave entities per rank. */
void sk_contact_partition_explain(const sk_model *model, FILE *out);

#endif
