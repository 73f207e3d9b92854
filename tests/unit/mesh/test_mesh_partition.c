/* sk_mesh_partition: every element assigned, balanced, deterministic, n_parts == 1 trivial. */
#include <stdlib.h>
#include <string.h>

#include "sk_test.h"
#include "stickslip/mesh.h"

static void check_partition(const char *path, const sk_mesh_param *params, int n_params, const char *const *names,
                            int n_bodies, int n_parts, double max_imbalance) {
  sk_mesh mesh;
  sk_status status = sk_mesh_load(path, params, n_params, 0, &mesh);
  if (status != SK_OK) fprintf(stderr, "%s\n", sk_error_message());
  SK_CHECK(status == SK_OK);
  if (status != SK_OK) return;
  const sk_group *bodies[4] = {NULL};
  int n_elems = 0;
  for (int b = 0; b < n_bodies; ++b) {
    SK_CHECK(sk_mesh_require_group(&mesh, names[b], mesh.dim, &bodies[b]) == SK_OK);
    if (!bodies[b]) {
      sk_mesh_free(&mesh);
      return;
    }
    n_elems += bodies[b]->n_elems;
  }
  int *part = malloc((size_t)n_elems * sizeof *part), *again = malloc((size_t)n_elems * sizeof *again);
  int *count = calloc((size_t)n_parts, sizeof *count);
  for (int e = 0; e < n_elems; ++e) part[e] = again[e] = -1;
  status = sk_mesh_partition(&mesh, bodies, n_bodies, n_parts, part);
  if (status != SK_OK) fprintf(stderr, "%s\n", sk_error_message());
  SK_CHECK(status == SK_OK);
  SK_CHECK(sk_mesh_partition(&mesh, bodies, n_bodies, n_parts, again) == SK_OK);
  SK_CHECK(memcmp(part, again, (size_t)n_elems * sizeof *part) == 0);
  int assigned = 1;
  for (int e = 0; e < n_elems; ++e) {
    assigned &= part[e] >= 0 && part[e] < n_parts;
    if (part[e] >= 0 && part[e] < n_parts) ++count[part[e]];
  }
  SK_CHECK(assigned);
  for (int p = 0; p < n_parts; ++p) {
    double share = (double)count[p] * n_parts / n_elems;
    if (share > 1 + max_imbalance || share < 1 - max_imbalance)
      fprintf(stderr, "%s: part %d has %d of %d elements\n", path, p, count[p], n_elems);
    SK_CHECK(share <= 1 + max_imbalance && share >= 1 - max_imbalance);
  }

  SK_CHECK(sk_mesh_partition(&mesh, bodies, n_bodies, 1, part) == SK_OK);
  int all_zero = 1;
  for (int e = 0; e < n_elems; ++e) all_zero &= part[e] == 0;
  SK_CHECK(all_zero);
  SK_CHECK(sk_mesh_partition(&mesh, bodies, n_bodies, 0, part) == SK_ERR_INPUT);
  SK_CHECK(sk_mesh_partition(&mesh, bodies, n_bodies, n_elems + 1, part) == SK_ERR_INPUT);
  free(part);
  free(again);
  free(count);
  sk_mesh_free(&mesh);
}

int main(void) {
  const char *body[] = {"body"};
  check_partition("meshes/block.geo", NULL, 0, body, 1, 2, 0.05);
  check_partition("meshes/block.geo", NULL, 0, body, 1, 3, 0.1);
  const sk_mesh_param coarse[] = {{"refine", 0.5}};
  check_partition("meshes/torus.geo", coarse, 1, body, 1, 2, 0.05);
  const char *two[] = {"lower", "upper"};
  check_partition("meshes/patch-test-2d.geo", NULL, 0, two, 2, 2, 0.15);
  const char *hertz[] = {"cylinder", "block"};
  check_partition("meshes/hertz-2d.geo", coarse, 1, hertz, 2, 2, 0.05);
  const char *quadratic_body[] = {"body"};
  const sk_mesh_param quadratic[] = {{"order", 2}, {"nx", 6}};
  check_partition("meshes/block-2d.geo", quadratic, 2, quadratic_body, 1, 2, 0.05);
  return sk_test_finish("test_mesh_partition");
}
