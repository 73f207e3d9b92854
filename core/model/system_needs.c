/* What the scene needs computed (term.h: sk_need): every term declares its needs when it is created; the system
 * builds what some term declares and nothing else, and --explain prints the declarations. There is no separate list
 * of skips: a skip is a need that no term declares. */
#define _GNU_SOURCE
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "system.h"

static const char *const need_names[SK_NEED_COUNT] = {"mass", "friction", "master-unknowns", "stiffness-update",
                                                         "idle-calls"};

/* Who acts on a need no term declares: the host skips the mass itself; friction, master unknowns and multipliers
 * are the plugin's own terms, skipped inside the plugin (the host sees the declaration and explains it). */
static const char *const skipped_by[SK_NEED_COUNT] = {
    "not built: no element mass matrices, no assembled mass",
    "no tangential terms, no slip history, no friction output (skipped inside the plugin)",
    "the pair couples no master dofs (rigid obstacle)",
    "linear bodies keep the element stiffness of set-up (internal force K u, no Gauss loop per iterate)",
    "on a step where no slave point's swept box meets the master's (no candidate, so no projection either: "
    "sk_layout.idle), no active-set, residual, Jacobian or recover call; inactive multipliers' rows z = 0 by the host"};
/* the needs the host skips itself, which the test switch can force */
static const unsigned char host_skips[SK_NEED_COUNT] = {1, 0, 0, 1, 1};

const char *sk_need_name(sk_need need) { return need >= 0 && need < SK_NEED_COUNT ? need_names[need] : "?"; }

void sk_needs_declare(sk_needs *needs, sk_need need, int needed, const char *fmt, ...) {
  needs->applies[need] = 1;
  needs->needed[need] = needed != 0;
  va_list args;
  va_start(args, fmt);
  vsnprintf(needs->why[need], sizeof needs->why[need], fmt, args);
  va_end(args);
}

int sk_skip_forced(const char *name) {
  const char *list = getenv("STICKSLIP_NO_SKIP");
  if (!list || !*list) return 0;
  const size_t len = strlen(name);
  for (const char *p = list; *p;) {
    const size_t word = strcspn(p, ",");
    if ((word == len && strncmp(p, name, len) == 0) || (word == 3 && strncmp(p, "all", 3) == 0)) return 1;
    p += word;
    if (*p == ',') ++p;
  }
  return 0;
}

int sk_need_forced(sk_need need) {
  if (need < 0 || need >= SK_NEED_COUNT || !host_skips[need]) return 0;
  return sk_skip_forced(sk_need_name(need));
}

int sk_system_needs(const sk_system *sys, sk_need need) {
  if (sk_need_forced(need)) return 1;
  for (int k = 0; k < sys->n_terms; ++k)
    if (sys->terms[k]->needs.needed[need]) return 1;
  return 0;
}

sk_status sk_system_settle_needs(sk_system *sys) {
  if (sk_system_needs(sys, SK_NEED_MASS)) SK_TRY(sk_model_build_mass(sys->model));
  return SK_OK;
}

void sk_system_explain(const sk_system *sys, FILE *out) {
  fprintf(out, "what each term needs (declared at set-up; a need no term declares is skipped):\n");
  for (int k = 0; k < sys->n_terms; ++k) {
    const sk_term *term = sys->terms[k];
    int any = 0;
    for (int n = 0; n < SK_NEED_COUNT; ++n) any |= term->needs.applies[n];
    if (!any) continue;
    fprintf(out, "  %s (%s)\n", term->name, term->ops->kind);
    for (int n = 0; n < SK_NEED_COUNT; ++n)
      if (term->needs.applies[n])
        fprintf(out, "    %-16s %-5s %s\n", need_names[n], term->needs.needed[n] ? "yes" : "no", term->needs.why[n]);
  }
  fprintf(out, "what the scene computes:\n");
  for (int n = 0; n < SK_NEED_COUNT; ++n) {
    int declared = 0, applies = 0;
    for (int k = 0; k < sys->n_terms; ++k) {
      declared += sys->terms[k]->needs.needed[n];
      applies += sys->terms[k]->needs.applies[n];
    }
    if (!applies) continue;
    if (declared)
      fprintf(out, "  %-16s computed (declared by %d term%s)\n", need_names[n], declared, declared == 1 ? "" : "s");
    else if (sk_need_forced((sk_need)n))
      fprintf(out, "  %-16s computed although no term needs it (test switch STICKSLIP_NO_SKIP)\n", need_names[n]);
    else
      fprintf(out, "  %-16s skipped: %s\n", need_names[n], skipped_by[n]);
  }
  /* not a term's need: the linear solver's set-up depends only on the pattern (core/solver) */
  if (sys->forget_setup)
    fprintf(out, "  %-16s computed for every linear solve (test switch STICKSLIP_NO_SKIP)\n", "symbolic-setup");
  else
    fprintf(out, "  %-16s skipped: while the pattern holds (same active couplings), a solve reuses the symbolic "
            "factorisation and the preconditioner hierarchy; set up again on a new pattern\n", "symbolic-setup");
}
