/* Checkpoint records of the plugins (plugin.h: stickslip.checkpoint.v1): what several plugins need to key their
 * history by whole-model indices and to find the view's cells and nodes again on another partition. Host-free. */
#ifndef STICKSLIP_PLUGIN_RECORDS_H
#define STICKSLIP_PLUGIN_RECORDS_H

#include "stickslip/plugin.h"

/* The view cell of each whole cell (view->cell_index), -1 for cells the view does not hold: n_cells_global entries
 * (malloc'd; NULL when out of memory). */
int *records_cells_of_view(const sk_view *view);
/* The view node of each whole node (view->node_index), -1 for nodes the view does not hold: n_nodes_global entries. */
int *records_nodes_of_view(const sk_view *view);
/* The view cell of a whole cell index through that table, or -1 (also for -1 and out-of-range indices). */
int records_view_cell(const int *cells_of_view, const sk_view *view, int64_t whole);

#endif
