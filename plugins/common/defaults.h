/* Defaults computed from the scene (the host's extension stickslip.scene.v1, ABI 2.7): the arithmetic the plugins'
 * rules share. A rule belongs to its formulation and is stated on its page (docs/plugins/<name>.md, "Defaults");
 * these helpers only compute its ingredients and report the value, so every plugin prints the same kind of reason.
 * Host-free: they see the ABI structs only. */
#ifndef STICKSLIP_PLUGIN_DEFAULTS_H
#define STICKSLIP_PLUGIN_DEFAULTS_H

#include "stickslip/plugin.h"

/* The scene extension of a host, or NULL (a host before ABI 2.7). */
const sk_scene_ext *sk_defaults_scene(const sk_host_api *api, sk_host *host);

/* E* of the pair: 1 / ((1 - nu_s^2)/E_s + (1 - nu_m^2)/E_m), a rigid obstacle adding 0; `text` (may be NULL) says
 * where it comes from: "E* = 1099 (slave body 'block' E 1000 nu 0.3, rigid obstacle 'floor')". */
double sk_defaults_modulus(const sk_scene_info *info, char *text, int size);

/* h of the slave surface: its mean corner-to-corner edge length; `text` (may be NULL): "h = 0.25 (mean corner-to-corner
 * edge of slave surface 'zmin', 32 faces of order 1)". */
double sk_defaults_size(const sk_scene_info *info, char *text, int size);

/* The slave surface's mean reference area (3D) or length (2D) per node: measure / nodes. */
double sk_defaults_tributary(const sk_scene_info *info);

/* c E* / h (a stiffness per area: a pressure per length), or with `nodal` c E* / h A (a nodal stiffness: force per
 * length, A = sk_defaults_tributary), with its reason "c E* / h; E* = ..., h = ..." into `reason` (may be NULL). */
double sk_defaults_stiffness(const sk_scene_info *info, double c, int nodal, char *reason, int size);

/* Parameter `key`: the scene's value when it gives one (checked > 0 and finite), else `computed` (> 0), which is
 * reported to the host with `reason` (printed by --explain). `scene` NULL (an older host): the key is required. */
sk_status sk_defaults_param(const sk_host_api *api, sk_host *host, const sk_scene_ext *scene, const char *key,
                            double computed, const char *reason, double *out);

/* A length parameter `key` >= 0 (a search margin): the scene's value, or `computed` (>= 0; 0 is a value here), which
 * is reported to the host with `reason` (stickslip.scene.v1), so that `check --explain` prints its number. */
sk_status sk_defaults_length(const sk_host_api *api, sk_host *host, const char *key, double computed,
                             const char *reason, double *out);

/* A count parameter `key` (Gauss points, a rule's points): the scene's value, or `computed`, which is reported to the
 * host with `reason` (stickslip.scene.v1), so that `check --explain` prints the number the pair uses; a pair that
 * does not `use` it reports it as unused (0, `reason` saying why). */
sk_status sk_defaults_count(const sk_host_api *api, sk_host *host, const char *key, int computed, int use,
                            const char *reason, int *out);

/* A parameter this pair does not use (`reason` says why, starting "unused: "): reported to the host as 0, so that
 * `check --explain` says so in place of the rule. */
void sk_defaults_unused(const sk_host_api *api, sk_host *host, const char *key, const char *reason);

/* A tangential parameter `key` whose default is another parameter's value (`other` names it, e.g. "the normal
 * penalty"): the scene's value (checked > 0), else `value`, reported to the host when `friction` (the pair has
 * mu > 0), else reported as unused (sk_defaults_unused). Never required. */
sk_status sk_defaults_follow(const sk_host_api *api, sk_host *host, const sk_scene_ext *scene, const char *key,
                             double value, const char *other, int friction, double *out);

/* The penalties of a penalty formulation: `penalty` the scene's, or factor[order of the slave faces] E* / h (times A
 * when `nodal`: a nodal stiffness); `penalty_tangential` the scene's or the normal one, reported only with
 * `friction` (unused without). */
sk_status sk_defaults_penalties(const sk_host_api *api, sk_host *host, const double factor[3], int nodal, int friction,
                                double *eps_n, double *eps_t);

#endif
