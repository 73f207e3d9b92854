/* Deep penetration of a penalty pair: a warning once per run and its record in summary.json (penetration.c). */
#ifndef SK_PENETRATION_H
#define SK_PENETRATION_H

#include "../model/system.h"
#include "stickslip/output.h"

/* The fraction of the slave surface's mean edge h above which a penalty pair's penetration is warned about
 * (docs/user-guide.md#deep-penetration): with the default penalty 10 E* / h it means a contact pressure above E*. */
#define SK_PENETRATION_WARN_FRACTION 0.1

typedef struct {
  double ratio_max;  /* the largest penetration / h of the run */
  char pair[64];     /* of the first step above the fraction: the pair, its step and time, penetration and h */
  int64_t step;
  double t, penetration, h;
  int warned;
} sk_penetration_watch;

/* After a converged step: the first time a penalty pair penetrates more than the fraction, one warning on rank 0's
 * stderr naming the pair, the step and what to do. */
void sk_penetration_watch_step(sk_penetration_watch *watch, const sk_system *sys, const sk_contact_totals *totals);
/* summary.json: penetration_ratio_max and penetration_warning (the pair and step, or "none"). */
void sk_penetration_watch_write(const sk_penetration_watch *watch, sk_json *json);

#endif
