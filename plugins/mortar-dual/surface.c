/* mortar-dual glue: the slave surface's topology around its nodes (the stars the averaged normals need) and its
 * tributary measures. */
#include <stdlib.h>
#include <string.h>

#include "mortar.h"

/* Node -> faces and node -> nodes of those faces (CSR), for a view. */
sk_status mortar_build_stars(sk_instance *inst, const sk_view *v, int **face_ptr, int **faces, int **node_ptr,
                             int **nodes) {
  const int nn = v->n_nodes, nen = v->nen;
  int *fp = mortar_alloc_zero((size_t)nn + 1, sizeof(int)), *fl = mortar_alloc_zero((size_t)v->n_cells * nen, sizeof(int));
  if (!fp || !fl) {
    free(fp);
    free(fl);
    return mortar_nomem(inst, "");
  }
  for (int f = 0; f < v->n_cells; ++f)
    for (int a = 0; a < nen; ++a) ++fp[v->conn[(int64_t)f * nen + a] + 1];
  for (int k = 0; k < nn; ++k) fp[k + 1] += fp[k];
  int *fill = mortar_alloc_zero((size_t)nn, sizeof(int));
  if (!fill) {
    free(fp);
    free(fl);
    return mortar_nomem(inst, "");
  }
  for (int f = 0; f < v->n_cells; ++f)
    for (int a = 0; a < nen; ++a) {
      const int k = v->conn[(int64_t)f * nen + a];
      fl[fp[k] + fill[k]++] = f;
    }
  *face_ptr = fp;
  *faces = fl;
  if (!node_ptr) {
    free(fill);
    return SK_OK;
  }
  /* nodes of the faces around each node, unique, the node itself included */
  int *np = mortar_alloc_zero((size_t)nn + 1, sizeof(int)), *nl = mortar_alloc_zero((size_t)fp[nn] * nen, sizeof(int));
  if (!np || !nl) {
    free(fill);
    free(np);
    free(nl);
    return mortar_nomem(inst, "");
  }
  int n = 0;
  for (int k = 0; k < nn; ++k) {
    np[k] = n;
    for (int e = fp[k]; e < fp[k + 1]; ++e)
      for (int a = 0; a < nen; ++a) {
        const int b = v->conn[(int64_t)fl[e] * nen + a];
        int seen = 0;
        for (int s = np[k]; s < n && !seen; ++s) seen = nl[s] == b;
        if (!seen) nl[n++] = b;
      }
  }
  np[nn] = n;
  free(fill);
  *node_ptr = np;
  *nodes = nl;
  return SK_OK;
}

/* Checks that the faces around every node of a needed slave face are in the view on this rank (the averaged normal
 * of such a node and its derivative need them all): face counts per node, maximised over ranks. */
sk_status mortar_check_stars(sk_instance *inst) {
  const sk_view *v = inst->slave;
  double *count = mortar_alloc_zero((size_t)v->n_nodes_global, sizeof(double));
  if (!count) return mortar_nomem(inst, "");
  for (int k = 0; k < v->n_nodes; ++k) count[v->node_index[k]] = inst->star_face_ptr[k + 1] - inst->star_face_ptr[k];
  double *local = mortar_alloc_zero((size_t)v->n_nodes_global, sizeof(double));
  if (!local) {
    free(count);
    return mortar_nomem(inst, "");
  }
  memcpy(local, count, sizeof(double) * (size_t)v->n_nodes_global);
  sk_status st = inst->api->reduce(inst->host, 1, count, (int)v->n_nodes_global);
  int64_t bad = -1;
  for (int f = 0; st == SK_OK && f < v->n_cells && bad < 0; ++f)
    if (inst->face_needed[f])
      for (int a = 0; a < v->nen; ++a) {
        const int k = v->conn[(int64_t)f * v->nen + a];
        if (local[v->node_index[k]] < count[v->node_index[k]]) bad = v->node_id[k];
      }
  free(count);
  free(local);
  SK_TRY(st);
  if (bad >= 0)
    return inst->api->error(inst->host, SK_ERR_INPUT,
                            "mortar-dual: the slave view of this rank lacks faces around node %lld, whose averaged "
                            "normal enters this rank's contact terms: the host must ghost two layers of slave faces",
                            (long long)bad);
  return SK_OK;
}

/* The slave surface's tributary measures int N_j at positions x (dim per view node), complete at the nodes of needed
 * faces (check_stars makes sure): at X, A_j of [C1], [U1]; at x, the current ones of the output. */
void mortar_tributary_measures(const sk_instance *inst, const double *x, double *measure) {
  const sk_view *v = inst->slave;
  memset(measure, 0, sizeof(double) * (size_t)v->n_nodes);
  for (int f = 0; f < v->n_cells; ++f) {
    double X[3 * MORTAR_MAX_NEN] = {0}, n[3 * MORTAR_MAX_NEN] = {0};
    for (int a = 0; a < v->nen; ++a)
      for (int i = 0; i < v->dim; ++i) X[3 * a + i] = x[(int64_t)v->conn[(int64_t)f * v->nen + a] * v->dim + i];
    mortar_pair p;
    mortar_basis_coeffs A;
    mortar_integrals I;
    mortar_pair_set(&p, inst->dim, &inst->st, NULL, X, NULL, n, 0);
    /* TRI6's and QUAD8's vertex functions integrate to 0 and a negative value: their measures are those of the
     * transformed functions, int N~_j = int Phi_j = sum_k D_jk of their dual basis (with either multiplier basis) */
    const mortar_basis b = mortar_transformed_face(v->cell_type) ? MORTAR_DUAL_TRANSFORMED : MORTAR_STANDARD;
    mortar_basis_coefficients(&p, b, &A);
    mortar_integrals_zero(&I, &p);
    mortar_slave_integrals(&p, &A, b, inst->n_d_points, inst->d_xi, inst->d_w, &I);
    for (int a = 0; a < v->nen; ++a)
      for (int k = 0; k < v->nen; ++k) measure[v->conn[(int64_t)f * v->nen + a]] += I.D[a][k].v;
  }
}

void mortar_reference_measures(sk_instance *inst) {
  mortar_tributary_measures(inst, inst->slave->X, inst->A_node);
  for (int oi = 0; oi < inst->n_owned; ++oi) inst->owned[oi].A_ref = inst->A_node[inst->owned[oi].node];
}
