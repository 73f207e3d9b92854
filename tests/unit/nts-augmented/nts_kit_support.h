/* Shared by the nts-augmented tests that drive the plugin through the plugin kit (test_nts_assembled, test_nts_self):
 * a step started at a generic point of the extras, in a wanted friction state. */
#ifndef NTS_KIT_SUPPORT_H
#define NTS_KIT_SUPPORT_H

#include "plugin_kit.h"
#include "sk_test.h"

const sk_plugin *stickslip_plugin_entry(void);

enum { FRICTIONLESS = 0, STICK = 1, SLIP = 2 };

/* Creates the instance (mu 0.5 and epsilon_t 100 with friction), begins the step from q_n to q, puts the extras at
 * a generic point (lambda_n compressive: -100 in stick, whose cone mu |lambda_n| holds the trial, -1 otherwise; f off
 * the closest point; lambda_aug arbitrary) and lets update_active_set pick the states. */
static inline void nts_kit_start(kit *k, const double *q_n, const double *q, int strategy, double alpha,
                                 int friction) {
  if (friction != FRICTIONLESS) {
    kit_param(k, "mu", 0.5);
    kit_param(k, "epsilon_t", 100.0);
  }
  SK_CHECK(kit_create(k, stickslip_plugin_entry(), strategy) == SK_OK);
  kit_integrator(k, alpha, alpha != 1.0);
  kit_state(k, q_n, q, 0.0, 1.0, NULL);
  SK_CHECK(kit_begin(k) == SK_OK);
  const int stride = k->dim == 3 ? 5 : 3;
  for (int64_t j = 0; j < k->layout.n_extra; ++j) {
    const int slot = (int)(j % stride);
    if (slot == 0) k->extra[j] = friction == STICK ? -100.0 : -1.0;
    else if (slot <= stride / 2) k->extra[j] += 0.01 + 0.01 * slot;
    else k->extra[j] = 0.1 * slot - 0.25;
  }
  int changed = 0;
  SK_CHECK(kit_update_active_set(k, q, &changed) == SK_OK);
}

#endif
