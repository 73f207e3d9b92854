/* The host's broad phase over contact pairs created by `bodies:` (internal; docs/contact-services.md, "Pairs among
 * many bodies"): which pairs' bodies are near, so that only their terms are visited during a step attempt. */
#ifndef STICKSLIP_BROAD_PHASE_H
#define STICKSLIP_BROAD_PHASE_H

#include "system.h"

/* Registers a pair (its two bodies' boundary surfaces) with the system's broad phase, creating it; margin: the
 * inflation of the pair's boxes; *id: the pair's number in the broad phase (sk_term_plugin_broad_id). */
sk_status sk_broad_phase_add(sk_system *sys, const sk_contact_pair *pair, double margin, int *id);
/* At the start of an attempt, after the predictor: the bodies' boxes (their boundary nodes at the start of the step
 * and at the current iterate) and the sweep over them, O(boundary nodes + N log N + overlaps); the pairs whose
 * boxes, inflated by their margin, overlap are awake, the others asleep (sk_term_plugin_set_far), and sys->live
 * becomes the terms the attempt visits. The same answer on every rank. Collective. */
sk_status sk_broad_phase_begin(sk_system *sys);
/* At a converged point: a sleeping pair whose boxes now overlap is woken (its plugin's begin_step from this point,
 * sk_term_plugin_wake) and *accept set to 0, so that Newton runs again with it. Collective. */
sk_status sk_broad_phase_converged(sk_system *sys, int *accept);
/* 1 when the pair's boxes in the reference configuration, inflated by margin, do not overlap (check --explain).
 * Collective. */
int sk_broad_phase_apart_at_start(const sk_system *sys, const sk_contact_pair *pair, double margin);
void sk_broad_phase_free(sk_system *sys);

#endif
