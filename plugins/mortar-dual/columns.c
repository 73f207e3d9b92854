/* mortar-dual glue: the columns of every owned node's rows — the unknowns its weighted gap, slip and NCP rows can
 * depend on (the slave faces around it and their nodes' stars, the candidate master faces, the slip history's nodes),
 * sorted and unique, rebuilt after every change of the candidates (outside Newton). */
#include <stdlib.h>

#include "mortar.h"

struct column_entry {
  int64_t dof;
  int side, node, comp;
};

static int compare_entries(const void *a, const void *b) {
  const int64_t x = ((const struct column_entry *)a)->dof, y = ((const struct column_entry *)b)->dof;
  return x < y ? -1 : x > y;
}

static sk_status push_node(sk_instance *inst, int *n, int side, int node) {
  if (*n + inst->dim > inst->tmp_cap) {
    const int cap = 2 * (*n + inst->dim) + 64;
    struct column_entry *t = realloc(inst->tmp_entries, sizeof *t * (size_t)cap);
    if (!t) return inst->api->error(inst->host, SK_ERR_NOMEM, "mortar-dual: out of memory (column lists)");
    inst->tmp_entries = t;
    inst->tmp_cap = cap;
  }
  for (int i = 0; i < inst->dim; ++i)
    inst->tmp_entries[(*n)++] = (struct column_entry){mortar_node_dof(inst, side, node, i), side, node, i};
  return SK_OK;
}

sk_status mortar_build_columns(sk_instance *inst) {
  const sk_view *sv = inst->slave;
  SK_TRY(mortar_cache_size(inst)); /* the candidates changed */
  inst->n_col = 0;
  int max_cols = 0;
  for (int oi = 0; oi < inst->n_owned; ++oi) {
    owned_node *o = &inst->owned[oi];
    int n = 0;
    for (int e = inst->star_face_ptr[o->node]; e < inst->star_face_ptr[o->node + 1]; ++e) {
      const int f = inst->star_face[e];
      for (int a = 0; a < sv->nen; ++a) {
        const int b = sv->conn[(int64_t)f * sv->nen + a];
        for (int s = inst->star_node_ptr[b]; s < inst->star_node_ptr[b + 1]; ++s)
          SK_TRY(push_node(inst, &n, SIDE_SLAVE, inst->star_node[s]));
      }
      if (inst->master)
        for (int c = inst->cand_ptr[f]; c < inst->cand_ptr[f + 1]; ++c)
          for (int b = 0; b < inst->master->nen; ++b)
            SK_TRY(push_node(inst, &n, SIDE_MASTER,
                             inst->master->conn[(int64_t)inst->cand[c] * inst->master->nen + b]));
    }
    for (int h = o->hist; h < o->hist + o->n_hist; ++h)
      SK_TRY(push_node(inst, &n, inst->hist_side[h], inst->hist_node[h]));
    qsort(inst->tmp_entries, (size_t)n, sizeof *inst->tmp_entries, compare_entries);
    int unique = 0;
    for (int k = 0; k < n; ++k)
      if (unique == 0 || inst->tmp_entries[k].dof != inst->tmp_entries[unique - 1].dof)
        inst->tmp_entries[unique++] = inst->tmp_entries[k];
    if (inst->n_col + unique > inst->col_cap) {
      const int cap = 2 * (inst->n_col + unique) + 256;
      int64_t *c = realloc(inst->col, sizeof *c * (size_t)cap);
      if (c) inst->col = c;
      int *cs = realloc(inst->col_side, sizeof *cs * (size_t)cap);
      if (cs) inst->col_side = cs;
      int *cn = realloc(inst->col_node, sizeof *cn * (size_t)cap);
      if (cn) inst->col_node = cn;
      int *cc = realloc(inst->col_comp, sizeof *cc * (size_t)cap);
      if (cc) inst->col_comp = cc;
      double *ag = realloc(inst->acc_gap, sizeof *ag * (size_t)cap);
      if (ag) inst->acc_gap = ag;
      double *cr = realloc(inst->commit_rows, sizeof *cr * (size_t)cap);
      if (cr) inst->commit_rows = cr;
      if (!c || !cs || !cn || !cc || !ag || !cr)
        return inst->api->error(inst->host, SK_ERR_NOMEM, "mortar-dual: out of memory (column lists)");
      inst->col_cap = cap;
    }
    o->cols = inst->n_col;
    o->n_cols = unique;
    for (int k = 0; k < unique; ++k) {
      inst->col[inst->n_col + k] = inst->tmp_entries[k].dof;
      inst->col_side[inst->n_col + k] = inst->tmp_entries[k].side;
      inst->col_node[inst->n_col + k] = inst->tmp_entries[k].node;
      inst->col_comp[inst->n_col + k] = inst->tmp_entries[k].comp;
    }
    inst->n_col += unique;
    if (unique > max_cols) max_cols = unique;
  }
  /* acc_W holds 3 columns lists; the scratch block dim rows of the longest list (or of a pair chain) */
  double *aw = realloc(inst->acc_W, sizeof(double) * 3 * (size_t)(inst->n_col > 0 ? inst->n_col : 1));
  if (!aw) return inst->api->error(inst->host, SK_ERR_NOMEM, "mortar-dual: out of memory (accumulators)");
  inst->acc_W = aw;
  const int need = 3 * max_cols;
  if (need > inst->block_cap) {
    double *b = realloc(inst->block, sizeof(double) * (size_t)need);
    if (!b) return inst->api->error(inst->host, SK_ERR_NOMEM, "mortar-dual: out of memory (scratch)");
    inst->block = b;
    inst->block_cap = need;
  }
  return SK_OK;
}
