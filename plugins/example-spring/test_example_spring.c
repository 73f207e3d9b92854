/* example-spring through its ABI, with the shared plugin test kit: load the module as the driver does, create an
 * instance, compare J with central differences of F on every dof, check the declared pattern covers J, and that a
 * rank adds nothing for nodes it does not own. */
#include <stdio.h>
#include <string.h>

#include "plugin_kit.h"
#include "sk_test.h"

enum { DIM = 3, N_NODES = 5, N_DOFS = DIM * N_NODES };

int main(void) {
  const sk_plugin *p = kit_load_module(EXAMPLE_SPRING_PATH, "example-spring", "spring_point");
  if (!p) return sk_test_finish("example-spring");

  /* The table. */
  SK_CHECK(p->kinds == SK_KIND_PAIR);
  SK_CHECK(strcmp(p->strategies[0], "none") == 0 && p->strategies[1] == NULL);
  SK_CHECK(p->parameters[0] && p->parameters[1] && !p->parameters[2]);
  SK_CHECK(p->pattern && p->recover == NULL && p->integrator == NULL);

  /* A pair whose slave surface is one triangle of nodes 1, 3, 4 (node 0 and 2 are elsewhere). */
  double X[N_DOFS];
  for (int i = 0; i < N_DOFS; ++i) X[i] = 0.1 * i + (i % 4 == 0 ? 0.3 : 0.0);
  kit k;
  kit_init(&k, DIM, N_NODES, X);
  const int face[3] = {1, 3, 4};
  kit_surface(&k, 0, SK_TRI3, 3, 1, face);

  /* Bad parameters are refused. */
  kit_param(&k, "k", -1.0);
  SK_CHECK(kit_create(&k, p, 0) == SK_ERR_INPUT && k.instance == NULL);
  k.n_params = 0;
  kit_param(&k, "k", 5.0);
  kit_param(&k, "k3", 40.0);
  SK_CHECK(kit_create(&k, p, 0) == SK_OK && k.instance != NULL);
  if (!k.instance) return sk_test_finish("example-spring");

  double q[N_DOFS];
  for (int i = 0; i < N_DOFS; ++i) q[i] = X[i] + 0.05 * ((i * 7) % 5 - 2);
  kit_state(&k, X, q, 0.0, 1.0, NULL);
  SK_CHECK(kit_begin(&k) == SK_OK && k.layout.n_extra == 0);

  /* Jacobian against central differences of the residual, column by column; inside the declared pattern. */
  double scale;
  const double worst = kit_fd_check(&k, q, 1e-6, &scale);
  printf("max |J - J_fd| = %.3e (|J| %.3e)\n", worst, scale);
  SK_CHECK(worst < 1e-9 * scale); /* measured 7.5e-11 relative */
  SK_CHECK(k.outside_pattern == 0);
  double J[N_DOFS * N_DOFS], F[N_DOFS];
  SK_CHECK(kit_jacobian(&k, q, J, NULL) == SK_OK);
  SK_CHECK(J[3 * N_DOFS + 3] > 5.0); /* node 1's block is there (and stiffer than k: hardening) */
  SK_CHECK(J[0] == 0.0);             /* node 0 is not a slave node */

  /* Sign: a slave node pulled by +d gets F = +(k + k3|d|^2) d, i.e. a restoring force -F. */
  SK_CHECK(kit_residual(&k, q, F) == SK_OK);
  SK_CHECK(F[3] * (q[3] - X[3]) > 0.0);

  /* Report: the resultant force on the slave side is -sum F. */
  sk_contact_report r;
  SK_CHECK(kit_report(&k, &r) == SK_OK);
  SK_CHECK_CLOSE(r.force[0], -(F[3] + F[9] + F[12]), 1e-14);

  /* MPI rule: a rank that does not own node 3 (view node 1) adds nodes 1 and 4 but not node 3. */
  unsigned char *owned = (unsigned char *)k.view_list[0]->owned;
  owned[1] = 0;
  SK_CHECK(kit_residual(&k, q, F) == SK_OK);
  SK_CHECK(F[3] != 0.0 && F[12] != 0.0 && F[9] == 0.0 && F[10] == 0.0 && F[11] == 0.0);
  owned[1] = 1;

  SK_CHECK(kit_commit(&k) == SK_OK);
  kit_free(&k);
  return sk_test_finish("example-spring");
}
