/* Checkpoint records of the plugins (records.h). */
#include "records.h"

#include <stdlib.h>

int *records_cells_of_view(const sk_view *view) {
  const int64_t n = view->n_cells_global;
  int *cells = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  if (!cells) return NULL;
  for (int64_t c = 0; c < n; ++c) cells[c] = -1;
  for (int c = 0; c < view->n_cells; ++c)
    if (view->cell_index[c] >= 0 && view->cell_index[c] < n) cells[view->cell_index[c]] = c;
  return cells;
}

int *records_nodes_of_view(const sk_view *view) {
  const int64_t n = view->n_nodes_global;
  int *nodes = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  if (!nodes) return NULL;
  for (int64_t k = 0; k < n; ++k) nodes[k] = -1;
  for (int k = 0; k < view->n_nodes; ++k)
    if (view->node_index[k] >= 0 && view->node_index[k] < n) nodes[view->node_index[k]] = k;
  return nodes;
}

int records_view_cell(const int *cells_of_view, const sk_view *view, int64_t whole) {
  return whole >= 0 && whole < view->n_cells_global ? cells_of_view[whole] : -1;
}
