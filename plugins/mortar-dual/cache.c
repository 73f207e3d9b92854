/* mortar-dual glue: the values of the segment integrals at the last configuration (mortar.h). The value-only passes
 * of one Newton iteration (the active-set update, the residual; at a converged point the decision and the commit)
 * evaluate the same positions: the first integrates and records every face part's and pair's integrals, the others
 * read them back. The record is keyed on the positions of both views and the time (an obstacle moves with t) and
 * dropped whenever the candidates change (mortar_cache_size) or the step is decided; the Jacobian integrates afresh
 * (it needs the derivatives). Values only: a value-only integration seeds no derivative slot, so the restored
 * integrals are those it would compute, bit for bit. */
#include <stdlib.h>
#include <string.h>

#include "mortar.h"

/* doubles per entry: D (nen_s^2), M (nen_s nen_m), gap and cover (nen_s), measure, gap_min */
static int stride(const sk_instance *inst) {
  const int ns = inst->slave->nen, nm = inst->master ? inst->master->nen : 0;
  return ns * ns + ns * nm + 2 * ns + 2;
}

sk_status mortar_cache_size(sk_instance *inst) {
  inst->cache_valid = 0;
  const int need = 2 * inst->slave->n_cells + inst->cand_ptr[inst->slave->n_cells];
  if (!inst->cache_x) {
    const size_t nx = (size_t)inst->slave->n_nodes * inst->dim + (inst->master ? (size_t)inst->master->n_nodes * inst->dim : 0);
    inst->cache_x = malloc(sizeof(double) * (nx > 0 ? nx : 1));
    if (!inst->cache_x) return inst->api->error(inst->host, SK_ERR_NOMEM, "mortar-dual: out of memory (integral cache)");
  }
  if (need <= inst->cache_cap) return SK_OK;
  const int cap = need + need / 4 + 16;
  double *v = realloc(inst->cache_values, sizeof(double) * (size_t)stride(inst) * (size_t)cap);
  if (v) inst->cache_values = v;
  int *n = realloc(inst->cache_cells, sizeof(int) * (size_t)cap);
  if (n) inst->cache_cells = n;
  if (!v || !n) return inst->api->error(inst->host, SK_ERR_NOMEM, "mortar-dual: out of memory (integral cache)");
  inst->cache_cap = cap;
  return SK_OK;
}

int mortar_cache_begin(sk_instance *inst, const sk_state *state, int value_only) {
  inst->cache_use = CACHE_OFF;
  if (!value_only || !inst->cache_x || inst->cache_cap < 2 * inst->slave->n_cells + inst->cand_ptr[inst->slave->n_cells]) {
    if (value_only) inst->cache_valid = 0; /* cannot record here: keep no stale record */
    return 0;
  }
  const size_t ns = (size_t)inst->slave->n_nodes * inst->dim;
  const size_t nm = inst->master ? (size_t)inst->master->n_nodes * inst->dim : 0;
  if (inst->cache_valid && inst->cache_t == state->t && memcmp(inst->cache_x, state->x[0], sizeof(double) * ns) == 0 &&
      (nm == 0 || memcmp(inst->cache_x + ns, state->x[1], sizeof(double) * nm) == 0)) {
    inst->cache_use = CACHE_READ;
    return 1;
  }
  memcpy(inst->cache_x, state->x[0], sizeof(double) * ns);
  if (nm > 0) memcpy(inst->cache_x + ns, state->x[1], sizeof(double) * nm);
  inst->cache_t = state->t;
  inst->cache_valid = 0; /* until the pass completes */
  inst->cache_use = CACHE_WRITE;
  return 0;
}

void mortar_cache_end(sk_instance *inst, sk_status status) {
  if (inst->cache_use == CACHE_WRITE) inst->cache_valid = status == SK_OK;
  inst->cache_use = CACHE_OFF;
}

void mortar_cache_put(sk_instance *inst, int entry, const mortar_integrals *I) {
  if (inst->cache_use != CACHE_WRITE) return;
  const int ns = I->nen_s, nm = I->nen_m;
  double *v = inst->cache_values + (size_t)stride(inst) * (size_t)entry;
  for (int j = 0; j < ns; ++j) {
    for (int k = 0; k < ns; ++k) *v++ = I->D[j][k].v;
    for (int l = 0; l < nm; ++l) *v++ = I->M[j][l].v;
    *v++ = I->gap[j].v;
    *v++ = I->cover[j];
  }
  *v++ = I->measure;
  *v = I->gap_min;
  inst->cache_cells[entry] = I->n_cells;
}

void mortar_cache_get(const sk_instance *inst, int entry, mortar_integrals *I) {
  const int ns = I->nen_s, nm = I->nen_m;
  const double *v = inst->cache_values + (size_t)stride(inst) * (size_t)entry;
  for (int j = 0; j < ns; ++j) {
    for (int k = 0; k < ns; ++k) I->D[j][k].v = *v++;
    for (int l = 0; l < nm; ++l) I->M[j][l].v = *v++;
    I->gap[j].v = *v++;
    I->cover[j] = *v++;
  }
  I->measure = *v++;
  I->gap_min = *v;
  I->n_cells = inst->cache_cells[entry];
}
