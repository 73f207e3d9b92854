/* Self contact in the node-to-surface plugins (penalty-nts, nts-augmented): a pair whose slave and master are the
 * same surface. The rule that keeps a point off the faces it cannot touch, and the one parameter that sets it,
 * `self_exclusion` (docs/contact-services.md#self-contact). Built into stickslip_plugin_common; it calls the host
 * only through its tables. */
#ifndef STICKSLIP_PLUGIN_COMMON_SELF_CONTACT_H
#define STICKSLIP_PLUGIN_COMMON_SELF_CONTACT_H

#include "stickslip/plugin.h"

/* The help line of the parameter, the same in every plugin that takes it. */
#define SELF_EXCLUSION_HELP                                                                                          \
  "self_exclusion: self contact only: a face with a node within this distance of the slave node in the reference "  \
  "configuration is not a candidate of that node (length) [computed from the scene: the largest face of the "        \
  "surface, so the faces at the node and their neighbours]"

/* The parameter `self_exclusion` of a self-contact pair on `surface`: the scene's value (checked > 0), else the
 * diagonal of the reference box of the surface's largest face (this rank's faces), reported to the host. */
sk_status self_contact_exclusion(const sk_host_api *api, sk_host *host, const sk_view *surface, double *out);
/* A pair that is not self contact does not use `self_exclusion`: reported to the host as 0, "unused", so that
 * `check --explain` says so in place of the rule. */
void self_contact_exclusion_unused(const sk_host_api *api, sk_host *host);

/* Filters the candidate faces of a point of `surface` at reference position X (dim coordinates) in place: drops the
 * faces with a node within `exclusion` of X (its own faces and their neighbours) and those X lies behind in the
 * reference configuration (negative gap: the body's material between them). Returns the number kept (first in
 * faces), or -1 with *status set when the projection fails. */
int self_contact_filter(const sk_contact_services *cs, const sk_view *surface, const double *X, double exclusion,
                        int *faces, int count, sk_status *status);

#endif
