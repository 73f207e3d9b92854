/* nts-augmented — self contact (glue.h): which side of a contact zone of one surface carries the constraints.
 *
 * In a self-contact pair every node of the surface is a slave and every face a master. Node-to-surface both ways
 * over one zone ("two-pass") constrains the gap twice: the gaps of the one side's nodes on the other side's faces
 * and those of the other side's nodes back on the first are linearly dependent (on a flat zone both sets vanish
 * exactly when the two polylines coincide, a space of dimension >= 2 that n_1 + n_2 constraints cannot all cut).
 * A penalty method shares the force between them; exact multipliers make the system singular (ring-crush-2d:
 * MUMPS numerical factorisation error -22 at step 85 when the walls meet). So each zone is one-pass, as the
 * paper's node-to-surface element is: one side's nodes are slaves, the other side's nodes are only master nodes.
 *
 * The zones come from the step's facets (begin_step): nodes i and j face each other when j is a node of i's facet
 * and i one of j's. The facing relation links the two sides of a zone alternately, so a breadth-first sweep colours
 * them 0 and 1; per zone the slave side is the one with more nodes active at t_n (the zone keeps its sides while it
 * persists), then the one with more nodes (the finer mesh), then the one holding the smallest node index. A node
 * that faces nobody keeps its facet. The table is over the whole surface and summed over ranks, so every rank
 * makes the same choice. */
#include <stdlib.h>
#include <string.h>

#include "glue.h"

sk_status nts_self_setup(sk_instance *inst) {
  const size_t n = (size_t)inst->slave->n_nodes_global + 1;
  inst->self_table = calloc(n * (NTS_MAX_NEN + 1), sizeof *inst->self_table);
  inst->self_colour = malloc(n * sizeof *inst->self_colour);
  inst->self_queue = malloc(n * sizeof *inst->self_queue);
  inst->self_master_only = calloc(n, 1);
  if (!inst->self_table || !inst->self_colour || !inst->self_queue || !inst->self_master_only)
    return inst->api->error(inst->host, SK_ERR_NOMEM, "%s: out of memory", inst->name);
  return SK_OK;
}

void nts_self_free(sk_instance *inst) {
  free(inst->self_table);
  free(inst->self_colour);
  free(inst->self_queue);
  free(inst->self_master_only);
}

enum { ROW = NTS_MAX_NEN + 1 }; /* per node: its facet's node indices + 1 (0: none), then 1 when active at t_n */

/* 1 when node j's facet holds node i. */
static int facet_holds(const double *table, int nen, int64_t j, int64_t i) {
  for (int a = 0; a < nen; ++a)
    if (table[ROW * j + a] == (double)(i + 1)) return 1;
  return 0;
}

sk_status nts_self_sides(sk_instance *inst, sk_projection *proj) {
  const sk_view *master = inst->master;
  const int nen = inst->facet.nen;
  const int64_t n = inst->slave->n_nodes_global;
  double *table = inst->self_table;
  memset(table, 0, sizeof *table * (size_t)(ROW * n));
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (!nts_owned(inst, p)) continue;
    if (proj[k].face >= 0 && proj[k].kind != SK_PROJ_OUTSIDE)
      for (int a = 0; a < nen; ++a)
        table[ROW * p->index + a] = (double)(master->node_index[master->conn[proj[k].face * master->nen + a]] + 1);
    table[ROW * p->index + NTS_MAX_NEN] = p->c_active;
  }
  SK_TRY(inst->api->reduce(inst->host, 0, table, (int)(ROW * n)));

  int *colour = inst->self_colour;
  int64_t *queue = inst->self_queue;
  for (int64_t i = 0; i < n; ++i) {
    colour[i] = -1;
    inst->self_master_only[i] = 0;
  }
  for (int64_t seed = 0; seed < n; ++seed) {
    if (colour[seed] >= 0) continue;
    /* the zone of seed, breadth first: queue[0 .. end) */
    int64_t head = 0, end = 0;
    colour[seed] = 0;
    queue[end++] = seed;
    while (head < end) {
      const int64_t i = queue[head++];
      for (int a = 0; a < nen; ++a) {
        const int64_t j = (int64_t)table[ROW * i + a] - 1;
        if (j < 0 || j == i || !facet_holds(table, nen, j, i) || colour[j] >= 0) continue;
        colour[j] = 1 - colour[i];
        queue[end++] = j;
      }
    }
    if (end == 1) continue; /* faces nobody */
    int64_t nodes[2] = {0, 0}, active[2] = {0, 0}, smallest[2] = {n, n};
    for (int64_t q = 0; q < end; ++q) {
      const int64_t i = queue[q];
      ++nodes[colour[i]];
      active[colour[i]] += table[ROW * i + NTS_MAX_NEN] > 0.5;
      if (i < smallest[colour[i]]) smallest[colour[i]] = i;
    }
    int slave_side = 0;
    if (active[1] != active[0])
      slave_side = active[1] > active[0];
    else if (nodes[1] != nodes[0])
      slave_side = nodes[1] > nodes[0];
    else
      slave_side = smallest[1] < smallest[0];
    for (int64_t q = 0; q < end; ++q)
      if (colour[queue[q]] != slave_side) inst->self_master_only[queue[q]] = 1;
  }
  for (int k = 0; k < inst->n_points; ++k)
    if (inst->self_master_only[inst->points[k].index]) proj[k].face = -1;
  return SK_OK;
}
