/* The mesh distributed after the partition (model.h: sk_model_distribute; docs/design.md, "What each rank holds").
 * Every rank reads the whole mesh and partitions it the same way (METIS is deterministic); then each keeps its
 * elements and their ghost layer, the nodes it holds in a local numbering (owned first, then ghosts, each by mesh id),
 * the faces of its groups and surfaces whose nodes it holds, and the whole sizes and indices plugins (views) and
 * output need. The whole mesh is freed on every rank (output is written in pieces, recorder.c). */
#include <stdlib.h>
#include <string.h>

#include "contact_partition.h"
#include "host.h"
#include "master_ghosts.h"
#include "stickslip/model.h"

static sk_status no_memory(const char *what) {
  return sk_error_set(SK_ERR_NOMEM, "out of memory distributing the model's %s", what);
}


/* The rank owning each face of a surface: the part of the body element whose face it is (whole mesh). */
static sk_status face_owners(const sk_model *m, const sk_surface *s, int *owner) {
  const sk_body *body = &m->bodies[s->body];
  const sk_group *g = body->group;
  /* elements incident to each surface node */
  int *count = calloc((size_t)s->n_nodes + 1, sizeof(int));
  if (!count) return no_memory("surface faces");
  for (int e = 0; e < g->n_elems; ++e)
    for (int a = 0; a < g->nen; ++a) {
      const int64_t k = sk_index_in_sorted(s->nodes, s->n_nodes, g->conn[(size_t)e * g->nen + a]);
      if (k >= 0) count[k + 1]++;
    }
  for (int k = 0; k < s->n_nodes; ++k) count[k + 1] += count[k];
  int *incident = malloc(sizeof(int) * (size_t)(count[s->n_nodes] > 0 ? count[s->n_nodes] : 1));
  int *fill = calloc((size_t)s->n_nodes + 1, sizeof(int));
  if (!incident || !fill) {
    free(count);
    free(incident);
    free(fill);
    return no_memory("surface faces");
  }
  for (int e = 0; e < g->n_elems; ++e)
    for (int a = 0; a < g->nen; ++a) {
      const int64_t k = sk_index_in_sorted(s->nodes, s->n_nodes, g->conn[(size_t)e * g->nen + a]);
      if (k >= 0) incident[count[k] + fill[k]++] = e;
    }
  for (int f = 0; f < s->n_faces; ++f) {
    const int *fc = s->conn + (size_t)f * s->nen;
    const int64_t k = sk_index_in_sorted(s->nodes, s->n_nodes, fc[0]);
    owner[f] = 0;
    for (int j = count[k]; j < count[k + 1]; ++j) {
      const int *ec = g->conn + (size_t)incident[j] * g->nen;
      int all = 1;
      for (int a = 0; a < s->nen && all; ++a) {
        int found = 0;
        for (int b = 0; b < g->nen && !found; ++b) found = ec[b] == fc[a];
        all = found;
      }
      if (all) {
        owner[f] = m->element_part[body->first_element + incident[j]];
        break;
      }
    }
  }
  free(count);
  free(incident);
  free(fill);
  return SK_OK;
}

/* The faces of a surface whose nodes this rank holds (local_of >= 0), in the local numbering, with their whole
 * indices, owners and the whole node indices. */
static sk_status localize_surface(const sk_model *m, const int *local_of, sk_surface *s) {
  int *owner = malloc(sizeof(int) * (size_t)(s->n_faces > 0 ? s->n_faces : 1));
  int *new_face = malloc(sizeof(int) * (size_t)(s->n_faces > 0 ? s->n_faces : 1));
  if (!owner || !new_face) {
    free(owner);
    free(new_face);
    return no_memory("surfaces");
  }
  sk_status status = face_owners(m, s, owner);
  /* the whole surface's sizes (the scene's description, stickslip.scene.v1: the same on every rank) */
  if (!s->whole_sizes) {
    sk_surface_sizes(s, m->mesh.x, 3, &s->whole_h_min, &s->whole_h_mean, &s->whole_h_max, &s->whole_measure);
    s->whole_sizes = 1;
  }
  int kept = 0;
  for (int f = 0; f < s->n_faces; ++f) {
    int held = 1;
    for (int a = 0; a < s->nen && held; ++a) held = local_of[s->conn[(size_t)f * s->nen + a]] >= 0;
    new_face[f] = held ? kept++ : -1;
  }
  int *conn = malloc(sizeof(int) * (size_t)(kept > 0 ? kept : 1) * (size_t)s->nen);
  int *neighbors = malloc(sizeof(int) * (size_t)(kept > 0 ? kept : 1) * (size_t)s->n_edges);
  int64_t *face_index = malloc(sizeof(int64_t) * (size_t)(kept > 0 ? kept : 1));
  int *face_owner = malloc(sizeof(int) * (size_t)(kept > 0 ? kept : 1));
  int *nodes = malloc(sizeof(int) * (size_t)(s->n_nodes > 0 ? s->n_nodes : 1));
  int64_t *node_index = malloc(sizeof(int64_t) * (size_t)(s->n_nodes > 0 ? s->n_nodes : 1));
  if (status == SK_OK && (!conn || !neighbors || !face_index || !face_owner || !nodes || !node_index))
    status = no_memory("surfaces");
  if (status == SK_OK) {
    for (int f = 0; f < s->n_faces; ++f) {
      const int c = new_face[f];
      if (c < 0) continue;
      for (int a = 0; a < s->nen; ++a) conn[(size_t)c * s->nen + a] = local_of[s->conn[(size_t)f * s->nen + a]];
      for (int e = 0; e < s->n_edges; ++e) {
        const int other = s->face_neighbors[(size_t)f * s->n_edges + e];
        neighbors[(size_t)c * s->n_edges + e] = other >= 0 ? new_face[other] : -1;
      }
      face_index[c] = s->face_index ? s->face_index[f] : f;
      face_owner[c] = owner[f];
    }
    /* the held nodes of the surface, sorted by local id, with their index in the whole surface's node list */
    int n_nodes = 0;
    for (int k = 0; k < s->n_nodes; ++k)
      if (local_of[s->nodes[k]] >= 0) nodes[n_nodes++] = local_of[s->nodes[k]];
    qsort(nodes, (size_t)n_nodes, sizeof(int), sk_compare_int);
    for (int k = 0, j = 0; k < s->n_nodes; ++k) {
      (void)j;
      if (local_of[s->nodes[k]] < 0) continue;
      const int64_t at = sk_index_in_sorted(nodes, n_nodes, local_of[s->nodes[k]]);
      node_index[at] = s->node_index ? s->node_index[k] : k;
    }
    free(s->conn);
    free(s->face_neighbors);
    free(s->nodes);
    free(s->face_index);
    free(s->node_index);
    free(s->face_owner);
    s->conn = conn;
    s->face_neighbors = neighbors;
    s->face_index = face_index;
    s->face_owner = face_owner;
    s->nodes = nodes;
    s->node_index = node_index;
    s->n_faces = kept;
    s->n_nodes = n_nodes;
  } else {
    free(conn), free(neighbors), free(face_index), free(face_owner), free(nodes), free(node_index);
  }
  free(owner);
  free(new_face);
  return status;
}

/* The contact neighbourhoods (model.h: surface_ptr) from the whole mesh, in the local numbering (local_of) and
 * without the nodes this rank does not hold: per node, itself and the contact-surface nodes of the elements holding
 * it. */
static sk_status surface_graph(sk_model *m, const int *local_of, int n_local) {
  const int n = m->n_nodes;
  unsigned char *on_surface = calloc((size_t)n + 1, 1);
  int64_t *count = calloc((size_t)n_local + 1, sizeof(int64_t));
  if (!on_surface || !count) {
    free(on_surface);
    free(count);
    return no_memory("contact neighbourhoods");
  }
  for (int k = 0; k < m->n_pairs; ++k) {
    const sk_contact_pair *pair = &m->pairs[k];
    for (int j = 0; j < pair->slave.n_nodes; ++j) on_surface[pair->slave.nodes[j]] = 1;
    for (int j = 0; !pair->has_obstacle && j < pair->master.n_nodes; ++j) on_surface[pair->master.nodes[j]] = 1;
  }
  /* counts: each held node once, plus per element with a surface node, its held surface nodes */
  for (int pass = 0; pass < 2; ++pass) {
    int64_t *fill = pass ? calloc((size_t)n_local + 1, sizeof(int64_t)) : NULL;
    if (pass && !fill) {
      free(on_surface);
      free(count);
      return no_memory("contact neighbourhoods");
    }
    for (int a = 0; a < n; ++a)
      if (local_of[a] >= 0) {
        if (pass) m->surface_cols[count[local_of[a]] + fill[local_of[a]]++] = local_of[a];
        else count[local_of[a] + 1]++;
      }
    for (int b = 0; b < m->n_bodies; ++b) {
      const sk_group *g = m->bodies[b].group;
      for (int e = 0; e < g->n_elems; ++e) {
        const int *conn = g->conn + (size_t)e * g->nen;
        int any = 0;
        for (int a = 0; a < g->nen && !any; ++a) any = on_surface[conn[a]];
        if (!any) continue;
        for (int a = 0; a < g->nen; ++a) {
          const int row = local_of[conn[a]];
          if (row < 0) continue;
          for (int c = 0; c < g->nen; ++c) {
            if (!on_surface[conn[c]] || local_of[conn[c]] < 0 || conn[c] == conn[a]) continue;
            if (pass) m->surface_cols[count[row] + fill[row]++] = local_of[conn[c]];
            else count[row + 1]++;
          }
        }
      }
    }
    if (!pass) {
      for (int r = 0; r < n_local; ++r) count[r + 1] += count[r];
      m->surface_cols = malloc(sizeof(int) * (size_t)(count[n_local] > 0 ? count[n_local] : 1));
      if (!m->surface_cols) {
        free(on_surface);
        free(count);
        return no_memory("contact neighbourhoods");
      }
    }
    free(fill);
  }
  /* sorted, unique (the node itself first stays among them) */
  int64_t used = 0;
  int64_t *ptr = malloc(sizeof(int64_t) * ((size_t)n_local + 1));
  if (!ptr) {
    free(on_surface);
    free(count);
    return no_memory("contact neighbourhoods");
  }
  ptr[0] = 0;
  for (int r = 0; r < n_local; ++r) {
    int *row = m->surface_cols + count[r];
    const int64_t len = count[r + 1] - count[r];
    qsort(row, (size_t)len, sizeof(int), sk_compare_int);
    for (int64_t k = 0; k < len; ++k)
      if (k == 0 || row[k] != row[k - 1]) m->surface_cols[used++] = row[k];
    ptr[r + 1] = used;
  }
  m->surface_ptr = ptr;
  free(on_surface);
  free(count);
  return SK_OK;
}

/* The elements of group g that are held (flag), conn renumbered; returns the kept count (-1: out of memory). */
static int localize_group(sk_group *g, const int *local_of, const unsigned char *held) {
  int kept = 0;
  for (int e = 0; e < g->n_elems; ++e) {
    if (!held[e]) continue;
    for (int a = 0; a < g->nen; ++a) g->conn[(size_t)kept * g->nen + a] = local_of[g->conn[(size_t)e * g->nen + a]];
    ++kept;
  }
  g->n_elems = kept;
  int *shrunk = realloc(g->conn, sizeof(int) * (size_t)(kept > 0 ? kept : 1) * (size_t)g->nen);
  if (shrunk) g->conn = shrunk;
  return kept;
}

/* Master faces ghosted by swept boxes (master_ghosts.h; unless STICKSLIP_MASTER_GHOSTING=replicated): every
 * deformable, distinct master surface. */
static sk_status plan_master_ghosts(sk_model *m) {
  SK_TRY(sk_master_ghosting_check_setting());
  if (!sk_master_ghosting_on() || m->n_ranks < 2) return SK_OK;
  sk_status status = SK_OK;
  for (int k = 0; k < m->n_pairs && status == SK_OK; ++k) {
    sk_contact_pair *pair = &m->pairs[k];
    if (pair->has_obstacle || pair->self_contact) continue;
    int *owner = malloc(sizeof(int) * (size_t)(pair->slave.n_faces > 0 ? pair->slave.n_faces : 1));
    if (!owner) return no_memory("master ghost boxes");
    status = face_owners(m, &pair->slave, owner);
    if (status == SK_OK) status = sk_master_ghosts_plan(m, pair, owner);
    free(owner);
  }
  return status;
}

sk_status sk_model_distribute(sk_model *m) {
  const int n_global = m->n_nodes, dim = m->dim;
  unsigned char *role = malloc((size_t)(n_global > 0 ? n_global : 1));
  int *local_of = malloc(sizeof(int) * (size_t)(n_global > 0 ? n_global : 1));
  unsigned char *held = malloc((size_t)(m->n_elements > 0 ? m->n_elements : 1));
  if (!role || !local_of || !held) {
    free(role), free(local_of), free(held);
    return no_memory("nodes");
  }
  sk_status status = sk_contact_partition_plan(m);
  if (status == SK_OK) status = plan_master_ghosts(m);
  if (status == SK_OK) status = sk_model_node_roles(m, role);
  /* the elements this rank holds: its own and those holding a node it owns (one ghost layer) */
  for (int b = 0; b < m->n_bodies; ++b) {
    const sk_group *g = m->bodies[b].group;
    for (int e = 0; e < g->n_elems; ++e) {
      const int *conn = g->conn + (size_t)e * g->nen;
      int h = m->element_part[m->bodies[b].first_element + e] == m->rank;
      for (int a = 0; a < g->nen && !h; ++a) h = m->node_owner[conn[a]] == m->rank;
      held[m->bodies[b].first_element + e] = (unsigned char)h;
    }
  }
  /* local numbering: owned nodes by mesh id, then ghosts by mesh id */
  int n_local = 0;
  for (int pass = 0; pass < 2; ++pass)
    for (int a = 0; a < n_global; ++a)
      if (role[a] == (pass == 0 ? SK_NODE_OWNED : SK_NODE_GHOST)) local_of[a] = n_local++;
  for (int a = 0; a < n_global; ++a)
    if (!role[a]) local_of[a] = -1;
  if (status == SK_OK) status = surface_graph(m, local_of, n_local);
  /* each body's whole counts and node indices (its sorted node list) */
  for (int b = 0; b < m->n_bodies && status == SK_OK; ++b) {
    sk_body *body = &m->bodies[b];
    int n_nodes = 0, *nodes = NULL;
    status = sk_group_nodes(body->group, &nodes, &n_nodes);
    if (status != SK_OK) break;
    body->n_elems_global = body->group->n_elems;
    body->n_nodes_global = n_nodes;
    body->node_index = malloc(sizeof(int64_t) * (size_t)(n_local > 0 ? n_local : 1));
    if (!body->node_index) status = no_memory("bodies");
    for (int a = 0; status == SK_OK && a < n_local; ++a) body->node_index[a] = -1;
    for (int k = 0; status == SK_OK && k < n_nodes; ++k)
      if (local_of[nodes[k]] >= 0) body->node_index[local_of[nodes[k]]] = k;
    free(nodes);
  }
  /* the pairs' surfaces (their owners from the whole mesh) */
  for (int k = 0; k < m->n_pairs && status == SK_OK; ++k) {
    sk_contact_pair *pair = &m->pairs[k];
    status = localize_surface(m, local_of, &pair->slave);
    if (status == SK_OK && pair->self_contact) pair->master = pair->slave;
    else if (status == SK_OK && !pair->has_obstacle) status = localize_surface(m, local_of, &pair->master);
  }
  /* the elements: part and whole index per held element, each body's first one */
  int n_elements = 0;
  for (int e = 0; e < m->n_elements; ++e) n_elements += held[e];
  int *element_part = malloc(sizeof(int) * (size_t)(n_elements > 0 ? n_elements : 1));
  int *element_index = malloc(sizeof(int) * (size_t)(n_elements > 0 ? n_elements : 1));
  int *whole_first = malloc(sizeof(int) * (size_t)(m->n_bodies > 0 ? m->n_bodies : 1));
  if (status == SK_OK && (!element_part || !element_index || !whole_first)) status = no_memory("elements");
  for (int b = 0, count = 0; b < m->n_bodies && status == SK_OK; ++b) {
    sk_body *body = &m->bodies[b];
    whole_first[b] = body->first_element;
    body->first_element = count;
    for (int e = 0; e < body->group->n_elems; ++e)
      if (held[whole_first[b] + e]) {
        element_part[count] = m->element_part[whole_first[b] + e];
        element_index[count++] = e;
      }
  }
  /* the groups: a body's held elements, and the faces (or points) whose nodes this rank holds */
  for (int gi = 0; gi < m->mesh.n_groups && status == SK_OK; ++gi) {
    sk_group *g = &m->mesh.groups[gi];
    int body = -1;
    for (int b = 0; b < m->n_bodies && body < 0; ++b)
      if (m->bodies[b].group == g) body = b;
    unsigned char *keep = body >= 0 ? held + whole_first[body] : malloc((size_t)(g->n_elems > 0 ? g->n_elems : 1));
    if (!keep) {
      status = no_memory("groups");
      break;
    }
    if (body < 0)
      for (int e = 0; e < g->n_elems; ++e) {
        int h = 1;
        for (int a = 0; a < g->nen && h; ++a) h = local_of[g->conn[(size_t)e * g->nen + a]] >= 0;
        keep[e] = (unsigned char)h;
      }
    localize_group(g, local_of, keep);
    if (body < 0) free(keep);
  }
  /* Dirichlet conditions: their held nodes */
  for (int k = 0; k < m->n_dirichlet && status == SK_OK; ++k) {
    sk_dirichlet *bc = &m->dirichlet[k];
    int kept = 0;
    for (int j = 0; j < bc->n_nodes; ++j)
      if (local_of[bc->nodes[j]] >= 0) bc->nodes[kept++] = local_of[bc->nodes[j]];
    bc->n_nodes = kept;
  }
  /* the nodes */
  double *X = malloc(sizeof(double) * (size_t)(n_local > 0 ? n_local : 1) * (size_t)dim);
  double *x = malloc(sizeof(double) * 3 * (size_t)(n_local > 0 ? n_local : 1));
  int64_t *gid = malloc(sizeof(int64_t) * (size_t)(n_local > 0 ? n_local : 1));
  int *owner = malloc(sizeof(int) * (size_t)(n_local > 0 ? n_local : 1));
  if (status == SK_OK && (!X || !x || !gid || !owner)) status = no_memory("nodes");
  if (status == SK_OK) {
    for (int a = 0; a < n_global; ++a) {
      const int l = local_of[a];
      if (l < 0) continue;
      for (int i = 0; i < dim; ++i) X[(size_t)l * dim + i] = m->X[(size_t)a * dim + i];
      for (int i = 0; i < 3; ++i) x[3 * (size_t)l + i] = m->mesh.x ? m->mesh.x[3 * (size_t)a + i] : 0.0;
      gid[l] = m->node_gid[a];
      owner[l] = m->node_owner[a];
    }
    free(m->X);
    free(m->mesh.x);
    free(m->node_gid);
    free(m->node_owner);
    free(m->element_part);
    free(m->element_index);
    m->X = X;
    m->mesh.x = x;
    m->node_gid = gid;
    m->node_owner = owner;
    m->mesh.n_nodes = m->n_nodes = n_local;
    m->n_dofs = n_local * dim;
    m->element_part = element_part;
    m->element_index = element_index;
    m->n_elements = n_elements;
    element_part = element_index = NULL;
    X = x = NULL;
    gid = NULL;
    owner = NULL;
    status = sk_model_index_nodes(m);
  }
  if (status == SK_OK) status = sk_model_build_graph(m);
  if (status == SK_OK) status = sk_master_ghosts_hold(m);
  free(X), free(x), free(gid), free(owner);
  free(role);
  free(local_of);
  free(held);
  free(element_part);
  free(element_index);
  free(whole_first);
  return status;
}
