/* Broad phase: an axis-aligned bounding-box tree over the faces of a surface.
 *
 * create() allocates everything the tree will ever need (2n - 1 nodes at most); the first update() splits the
 * faces at the median of their box centres along the longest axis (O(n log n), in place); later updates only refit
 * the boxes bottom-up (O(n)), so the per-step work allocates nothing. sk_search_rebuild() asks for a new split when
 * the surface has deformed so much that refitted boxes overlap badly. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact_internal.h"
#include "stickslip/contact.h"

enum {
  LEAF_SIZE = 4,     /* faces per leaf */
  QUERY_STACK = 128  /* median splits keep the depth below log2(n) + 2, far below this */
};

typedef struct {
  double lo[3], hi[3];
  int left, right;  /* children (internal nodes) */
  int first, count; /* range of `order` (leaves: count > 0) */
} bvh_node;

typedef struct {
  double centre[3];
  int face;
} split_item; /* box centre stored beside its face so the median selection walks contiguous memory */

struct sk_search {
  const sk_surface *surface;
  const sk_face_domain *domain;
  int built;
  double *face_box;  /* 6 per face: lo[3], hi[3] */
  split_item *items; /* scratch of the split, allocated once */
  int *order;        /* face ids, grouped by leaf */
  double *slot_box;  /* face boxes in `order` (leaf) order: queries read them contiguously */
  int n_nodes;
  bvh_node *nodes;   /* preorder: children come after their parent */
};

sk_status sk_search_create(const sk_surface *surface, sk_search **search) {
  *search = NULL;
  const sk_face_domain *domain = surface ? sk_face_domain_of(surface->face_type) : NULL;
  if (!domain) return sk_error_set(SK_ERR_INPUT, "contact search: surface %s has no supported face type",
                                   surface ? surface->name : "(null)");
  sk_search *s = calloc(1, sizeof *s);
  size_t n = surface->n_faces > 0 ? (size_t)surface->n_faces : 1;
  if (s) {
    s->face_box = malloc(6 * n * sizeof *s->face_box);
    s->order = malloc(n * sizeof *s->order);
    s->items = malloc(n * sizeof *s->items);
    s->slot_box = malloc(6 * n * sizeof *s->slot_box);
    s->nodes = malloc(2 * n * sizeof *s->nodes);
  }
  if (!s || !s->face_box || !s->order || !s->items || !s->slot_box || !s->nodes) {
    sk_search_destroy(s);
    return sk_error_set(SK_ERR_NOMEM, "contact search: out of memory for the tree of surface %s (%d faces)",
                        surface->name, surface->n_faces);
  }
  s->surface = surface;
  s->domain = domain;
  *search = s;
  return SK_OK;
}

void sk_search_destroy(sk_search *search) {
  if (!search) return;
  free(search->face_box);
  free(search->order);
  free(search->items);
  free(search->slot_box);
  free(search->nodes);
  free(search);
}

void sk_search_rebuild(sk_search *search) {
  if (search) search->built = 0;
}

/* Reorders items[first, last) so that the element at `nth` is the one a full sort by centre would put there
 * (quickselect, expected linear time). */
static void select_nth(split_item *items, int first, int last, int nth, int axis) {
  while (last - first > 1) {
    int mid = first + (last - first) / 2;
    double pivot = items[mid].centre[axis];
    int i = first, j = last - 1;
    while (i <= j) {
      while (items[i].centre[axis] < pivot) ++i;
      while (items[j].centre[axis] > pivot) --j;
      if (i <= j) {
        split_item tmp = items[i];
        items[i] = items[j];
        items[j] = tmp;
        ++i;
        --j;
      }
    }
    if (nth <= j) last = j + 1;
    else if (nth >= i) first = i;
    else return;
  }
}

static int build_node(sk_search *s, int first, int count) {
  int id = s->n_nodes++;
  bvh_node *node = &s->nodes[id];
  node->left = node->right = -1;
  node->first = first;
  node->count = count;
  if (count <= LEAF_SIZE) return id;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int k = first; k < first + count; ++k)
    for (int i = 0; i < 3; ++i) {
      double c = s->items[k].centre[i];
      lo[i] = fmin(lo[i], c);
      hi[i] = fmax(hi[i], c);
    }
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (hi[i] - lo[i] > hi[axis] - lo[axis]) axis = i;
  int half = count / 2;
  select_nth(s->items, first, first + count, first + half, axis);
  int left = build_node(s, first, half);
  int right = build_node(s, first + half, count - half);
  node = &s->nodes[id]; /* (the array never moves, but keep the access obvious) */
  node->left = left;
  node->right = right;
  node->count = 0;
  return id;
}

static void face_box(const sk_search *s, int face, const double *q0, const double *q1, double margin, double *box) {
  const sk_surface *surface = s->surface;
  const int dim = surface->dim;
  const int *conn = surface->conn + (size_t)face * surface->nen;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  const double *qs[2] = {q0, q1};
  for (int t = 0; t < 2; ++t) {
    if (!qs[t]) continue;
    for (int a = 0; a < surface->nen; ++a) {
      const double *x = qs[t] + (size_t)conn[a] * dim;
      for (int i = 0; i < 3; ++i) {
        double v = i < dim ? x[i] : 0.0;
        lo[i] = fmin(lo[i], v);
        hi[i] = fmax(hi[i], v);
      }
    }
  }
  /* A quadratic face can bulge past its nodes: sum |N_a| <= lebesgue bounds how far from the box centre. Nodes
   * moving linearly from q0 to q1 stay inside the union box, so the face does at every instant of the step. */
  for (int i = 0; i < 3; ++i) {
    double centre = 0.5 * (lo[i] + hi[i]), half = 0.5 * (hi[i] - lo[i]) * s->domain->lebesgue + margin;
    box[i] = centre - half;
    box[3 + i] = centre + half;
  }
}

void sk_search_update(sk_search *search, const double *q0, const double *q1, double margin) {
  if (!search || (!q0 && !q1)) return;
  const int n = search->surface->n_faces;
  for (int f = 0; f < n; ++f) face_box(search, f, q0, q1, margin, search->face_box + 6 * (size_t)f);
  if (n == 0) return;
  if (!search->built) {
    for (int f = 0; f < n; ++f) {
      const double *b = search->face_box + 6 * (size_t)f;
      for (int i = 0; i < 3; ++i) search->items[f].centre[i] = 0.5 * (b[i] + b[3 + i]);
      search->items[f].face = f;
    }
    search->n_nodes = 0;
    build_node(search, 0, n);
    for (int k = 0; k < n; ++k) search->order[k] = search->items[k].face;
    search->built = 1;
  }
  /* Children follow their parent in preorder, so a reverse sweep refits bottom-up. */
  for (int id = search->n_nodes - 1; id >= 0; --id) {
    bvh_node *node = &search->nodes[id];
    for (int i = 0; i < 3; ++i) {
      node->lo[i] = INFINITY;
      node->hi[i] = -INFINITY;
    }
    if (node->count > 0) {
      for (int k = node->first; k < node->first + node->count; ++k) {
        double *b = search->slot_box + 6 * (size_t)k;
        memcpy(b, search->face_box + 6 * (size_t)search->order[k], 6 * sizeof *b);
        for (int i = 0; i < 3; ++i) {
          node->lo[i] = fmin(node->lo[i], b[i]);
          node->hi[i] = fmax(node->hi[i], b[3 + i]);
        }
      }
    } else {
      const bvh_node *l = &search->nodes[node->left], *r = &search->nodes[node->right];
      for (int i = 0; i < 3; ++i) {
        node->lo[i] = fmin(l->lo[i], r->lo[i]);
        node->hi[i] = fmax(l->hi[i], r->hi[i]);
      }
    }
  }
}

static int compare_faces(const void *a, const void *b) {
  const int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

static int overlaps(const double *lo, const double *hi, const double *box_lo, const double *box_hi) {
  return lo[0] <= box_hi[0] && box_lo[0] <= hi[0] && lo[1] <= box_hi[1] && box_lo[1] <= hi[1] &&
         lo[2] <= box_hi[2] && box_lo[2] <= hi[2];
}

int sk_search_query(const sk_search *search, const double lo[3], const double hi[3], int *faces, int max_faces) {
  if (!search || !search->built) return 0;
  int stack[QUERY_STACK], top = 0, found = 0;
  stack[top++] = 0;
  while (top > 0) {
    const bvh_node *node = &search->nodes[stack[--top]];
    if (!overlaps(lo, hi, node->lo, node->hi)) continue;
    if (node->count > 0) {
      for (int k = node->first; k < node->first + node->count; ++k) {
        const double *b = search->slot_box + 6 * (size_t)k;
        if (!overlaps(lo, hi, b, b + 3)) continue;
        if (found < max_faces && faces) faces[found] = search->order[k];
        ++found;
      }
    } else if (top + 2 <= QUERY_STACK) {
      stack[top++] = node->right;
      stack[top++] = node->left;
    }
  }
  /* In face order, not the tree's: a tree built at other positions (a restart's, against the set-up's refitted
   * since) splits the faces otherwise, and a plugin breaking a tie between candidates by their order would then
   * take another face (docs/contact-services.md). */
  const int written = found < max_faces ? found : max_faces;
  if (faces && written > 16) qsort(faces, (size_t)written, sizeof *faces, compare_faces);
  for (int i = 1; faces && written <= 16 && i < written; ++i)
    for (int j = i; j > 0 && faces[j - 1] > faces[j]; --j) {
      const int t = faces[j];
      faces[j] = faces[j - 1];
      faces[j - 1] = t;
    }
  return found;
}

int sk_search_brute_force(const sk_search *search, const double lo[3], const double hi[3], int *faces,
                          int max_faces) {
  if (!search || !search->built) return 0;
  int found = 0;
  for (int f = 0; f < search->surface->n_faces; ++f) {
    const double *b = search->face_box + 6 * (size_t)f;
    if (!overlaps(lo, hi, b, b + 3)) continue;
    if (found < max_faces && faces) faces[found] = f;
    ++found;
  }
  return found;
}
