/* The host's broad phase over contact pairs created by `bodies:` (internal; docs/contact-services.md, "Pairs among
 * many bodies"): which pairs' bodies are apart, so that their plugin is not called during a step attempt. */
#ifndef STICKSLIP_BROAD_PHASE_H
#define STICKSLIP_BROAD_PHASE_H

#include "system.h"

/* Registers a pair's two bodies (their boundary surfaces) with the system's broad phase, creating it; margin: the
 * inflation of the pair's boxes. */
sk_status sk_broad_phase_add(sk_system *sys, const sk_contact_pair *pair, double margin);
/* 1 when the two bodies' boxes (their boundary nodes at the start of the step and at the current iterate),
 * inflated by margin, do not overlap. The boxes and the sweep over them are made once per iterate, for all bodies:
 * O(boundary nodes + N log N + overlapping pairs); each call is then a lookup. The same answer on every rank. */
int sk_broad_phase_apart(sk_system *sys, int body_a, int body_b, double margin);
/* The same in the reference configuration, for one pair (check --explain). Collective. */
int sk_broad_phase_apart_at_start(const sk_system *sys, const sk_contact_pair *pair, double margin);
void sk_broad_phase_free(sk_system *sys);

#endif
