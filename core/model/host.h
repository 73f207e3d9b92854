/* The host side of the plugin ABI (internal to the simulation layer): views of surfaces and bodies as one rank sees
 * them (views.c), the per-instance host handle and the api table (host.c), the contact services over views
 * (host_contact.c). The plugin term (term_plugin.c) ties them to the system. */
#ifndef STICKSLIP_HOST_H
#define STICKSLIP_HOST_H

#include "stickslip/config.h"
#include "stickslip/contact.h"
#include "stickslip/plugin.h"
#include "system.h"

_Static_assert(sizeof(int) == sizeof(int32_t), "views share int arrays with the core's surfaces");

/* A view (plugin_types.h) and what backs it. `view` is the first member: the services convert a const sk_view *
 * back to its data. */
typedef struct {
  sk_view view;
  int is_surface;
  sk_surface local;        /* surfaces: the core surface renumbered into view numbering (conn, neighbours) */
  int *conn;               /* n_cells * nen view node indices */
  unsigned char *cell_owned;
  int64_t *cell_index;
  int *neighbors;
  int *local_nodes;        /* 0 .. n_nodes-1 (the core surface's node list in view numbering) */
  int64_t *node_index, *node_id, *dofs;
  unsigned char *owned;
  double *X;
  int *cell_element;       /* bodies: the global element of each cell */
  int64_t *local_dofs;     /* n_nodes * dim: the local unknown of each view dof (system.h) */
} sk_view_data;

/* A surface as this rank sees it: with `whole`, every face it holds (of those, the ones flagged in `held` when it is
 * not NULL: a master surface's faces ghosted to it); otherwise the faces with a node this rank owns or that this rank
 * owns, and their nodes. A face is owned by the owner of the body element it bounds; a node by its owner; with
 * `contact` (a pair whose slave surface this is, with a contact partition) by their contact owners instead
 * (contact_partition.h). */
sk_status sk_view_surface(const sk_model *model, const sk_surface *surface, const char *name, int whole,
                          const unsigned char *held, const sk_contact_pair *contact, sk_view_data *view);
/* A body as this rank sees it: its elements owned by this rank or touching a node it owns, and their nodes. */
sk_status sk_view_body(const sk_model *model, int body, sk_view_data *view);
/* A view of a whole surface (mesh node ids indexing X, dim per node) on one rank, every face and node owned: the
 * plugin test kit's. */
sk_status sk_view_fill_surface(sk_view_data *view, const sk_surface *surface, const char *name, int dim,
                               const double *X);
void sk_view_free(sk_view_data *view);
/* The local unknown of each of the view's dofs (after the system laid out its dofs). */
sk_status sk_view_localize(sk_view_data *view, const sk_system *sys);
/* The data behind an ABI view handed out by the host. */
static inline const sk_view_data *sk_view_data_of(const sk_view *view) { return (const sk_view_data *)view; }

/* The contact services over views (host_contact.c). */
extern const sk_contact_services sk_host_contact_table;

struct plugin_term;
/* The per-instance handle plugins pass to every api call. */
struct sk_host {
  sk_system *sys;
  struct plugin_term *term;
  const sk_cfg *params;    /* the instance's `parameters:` (may be NULL) */
  const char *name;        /* "contact pair 'floor'" */
};

/* The api table (host.c). */
const sk_host_api *sk_host_api_table(void);

/* qsort/bsearch order of ints, and the position of `value` in the ascending array `sorted` of `n` ints or -1
 * (views.c). */
int sk_compare_int(const void *a, const void *b);
int64_t sk_index_in_sorted(const int *sorted, int n, int value);

#endif
