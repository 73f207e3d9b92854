/* Deep penetration of a penalty pair (penetration.h): the constraint violation a penalty plugin reports is its
 * deepest penetration, which the host measures against the pair's slave faces (their mean edge h). */
#include "penetration.h"

#include <stdio.h>

#include "stickslip/scene.h"

void sk_penetration_watch_step(sk_penetration_watch *watch, const sk_system *sys, const sk_contact_totals *totals) {
  if (totals->penetration_term < 0) return;
  if (totals->penetration_ratio > watch->ratio_max) watch->ratio_max = totals->penetration_ratio;
  if (watch->warned || totals->penetration_ratio <= SK_PENETRATION_WARN_FRACTION) return;
  double h = 0.0;
  const sk_contact_pair *pair = sk_term_plugin_penalty_pair(sys->terms[totals->penetration_term], &h);
  if (!pair) return;
  watch->warned = 1;
  snprintf(watch->pair, sizeof watch->pair, "%s", pair->name);
  watch->step = sys->step;
  watch->t = sys->t;
  watch->h = h;
  watch->penetration = totals->penetration_ratio * h;
  sk_log_message(sys->rank, 1,
                 "contact pair '%s' (plugin %s): at step %lld (t = %g) the slave surface '%s' penetrates %.3g, %.0f %% "
                 "of its faces' mean edge %.3g (more than %.0f %%): the penalty is too soft for this load and the "
                 "results near the contact are wrong at the element scale. Raise the pair's penalty "
                 "(parameters.penalty) or use a plugin that enforces the contact exactly (nts-augmented, mortar-dual); "
                 "docs/user-guide.md#deep-penetration. Warned once per run",
                 pair->name, pair->plugin->name, (long long)sys->step, sys->t, pair->slave.name, watch->penetration,
                 100.0 * totals->penetration_ratio, h, 100.0 * SK_PENETRATION_WARN_FRACTION);
}

void sk_penetration_watch_write(const sk_penetration_watch *watch, sk_json *json) {
  sk_json_number(json, "penetration_ratio_max", watch->ratio_max);
  char text[256] = "none";
  if (watch->warned)
    snprintf(text, sizeof text, "contact pair '%s': penetration %.3g = %.0f %% of the slave faces' mean edge %.3g at "
             "step %lld (t = %g)", watch->pair, watch->penetration, 100.0 * watch->penetration / watch->h, watch->h,
             (long long)watch->step, watch->t);
  sk_json_string(json, "penetration_warning", text);
}
