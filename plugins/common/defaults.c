/* Ingredients of the defaults computed from the scene (defaults.h). */
#include "defaults.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>

const sk_scene_ext *sk_defaults_scene(const sk_host_api *api, sk_host *host) {
  if (!SK_HAS(api, get_extension) || !api->get_extension) return NULL;
  const sk_scene_ext *scene = api->get_extension(host, SK_EXT_SCENE);
  return scene && SK_HAS(scene, computed) ? scene : NULL;
}

static void describe_side(const sk_scene_side *side, const char *role, char *text, int size) {
  if (side->rigid)
    snprintf(text, (size_t)size, "rigid obstacle '%s'", side->name);
  else
    snprintf(text, (size_t)size, "%s body '%s' E %.4g nu %.4g", role, side->body_name, side->E, side->nu);
}

double sk_defaults_modulus(const sk_scene_info *info, char *text, int size) {
  double compliance = 0.0;
  const sk_scene_side *sides[2] = {info->slave, info->master};
  for (int s = 0; s < 2; ++s)
    if (sides[s] && !sides[s]->rigid && sides[s]->E > 0.0) compliance += (1.0 - sides[s]->nu * sides[s]->nu) / sides[s]->E;
  const double modulus = compliance > 0.0 ? 1.0 / compliance : INFINITY;
  if (text) {
    char slave[128], master[128] = "";
    describe_side(info->slave, "slave", slave, sizeof slave);
    if (info->master) describe_side(info->master, "master", master, sizeof master);
    snprintf(text, (size_t)size, "E* = %.4g (%s%s%s)", modulus, slave, info->master ? "; " : "", master);
  }
  return modulus;
}

double sk_defaults_size(const sk_scene_info *info, char *text, int size) {
  const sk_scene_side *s = info->slave;
  if (text)
    snprintf(text, (size_t)size, "h = %.4g (mean corner-to-corner edge of slave surface '%s', %lld faces of order %d)",
             s->h_mean, s->name, (long long)s->n_cells, s->order);
  return s->h_mean;
}

double sk_defaults_tributary(const sk_scene_info *info) {
  const sk_scene_side *s = info->slave;
  return s->n_nodes > 0 ? s->measure / (double)s->n_nodes : 0.0;
}

double sk_defaults_stiffness(const sk_scene_info *info, double c, int nodal, char *reason, int size) {
  char modulus_text[300], size_text[200];
  const double modulus = sk_defaults_modulus(info, modulus_text, sizeof modulus_text);
  const double h = sk_defaults_size(info, size_text, sizeof size_text);
  const double area = nodal ? sk_defaults_tributary(info) : 1.0;
  if (reason && nodal)
    snprintf(reason, (size_t)size, "%g E*/h A; %s, %s, A = %.4g (the mean tributary %s per slave node)", c,
             modulus_text, size_text, area, info->dim == 3 ? "area" : "length");
  else if (reason)
    snprintf(reason, (size_t)size, "%g E*/h; %s, %s", c, modulus_text, size_text);
  return c * modulus / h * area;
}

sk_status sk_defaults_param(const sk_host_api *api, sk_host *host, const sk_scene_ext *scene, const char *key,
                            double computed, const char *reason, double *out) {
  SK_TRY(api->param_double(host, key, !scene, NAN, out));
  if (isnan(*out)) {
    if (!(computed > 0.0) || !isfinite(computed))
      return api->error(host, SK_ERR_INPUT,
                        "parameter '%s' is not given and its default cannot be computed from the scene (%s gives "
                        "%g): give it",
                        key, reason, computed);
    *out = computed;
    scene->computed(host, key, computed, "%s", reason);
  } else if (!(*out > 0.0) || !isfinite(*out)) {
    return api->error(host, SK_ERR_INPUT, "parameter '%s' must be a finite number > 0, got %g", key, *out);
  }
  return SK_OK;
}

sk_status sk_defaults_length(const sk_host_api *api, sk_host *host, const char *key, double computed,
                             const char *reason, double *out) {
  SK_TRY(api->param_double(host, key, 0, NAN, out));
  if (isnan(*out)) {
    *out = computed;
    const sk_scene_ext *scene = sk_defaults_scene(api, host);
    if (scene) scene->computed(host, key, computed, "%s", reason);
  }
  return SK_OK;
}

sk_status sk_defaults_count(const sk_host_api *api, sk_host *host, const char *key, int computed, int use,
                            const char *reason, int *out) {
  SK_TRY(api->param_int(host, key, 0, INT_MIN, out)); /* INT_MIN: not given (no count is) */
  if (*out == INT_MIN) {
    *out = computed;
    const sk_scene_ext *scene = sk_defaults_scene(api, host);
    if (scene) scene->computed(host, key, use ? computed : 0, "%s", reason);
  }
  return SK_OK;
}

void sk_defaults_unused(const sk_host_api *api, sk_host *host, const char *key, const char *reason) {
  const sk_scene_ext *scene = sk_defaults_scene(api, host);
  if (scene) scene->computed(host, key, 0.0, "%s", reason);
}

sk_status sk_defaults_follow(const sk_host_api *api, sk_host *host, const sk_scene_ext *scene, const char *key,
                             double value, const char *other, int friction, double *out) {
  SK_TRY(api->param_double(host, key, 0, NAN, out));
  if (isnan(*out)) {
    *out = value;
    if (!friction) sk_defaults_unused(api, host, key, "unused: the pair is frictionless (mu 0)");
    else if (scene) scene->computed(host, key, value, "%s", other);
  } else if (!(*out > 0.0) || !isfinite(*out)) {
    return api->error(host, SK_ERR_INPUT, "parameter '%s' must be a finite number > 0, got %g", key, *out);
  }
  return SK_OK;
}

sk_status sk_defaults_penalties(const sk_host_api *api, sk_host *host, const double factor[3], int nodal, int friction,
                                double *eps_n, double *eps_t) {
  const sk_scene_ext *scene = sk_defaults_scene(api, host);
  double computed = 0.0;
  char reason[700] = "";
  if (scene) {
    const sk_scene_info *info = scene->info(host);
    computed = sk_defaults_stiffness(info, factor[info->slave->order == 2 ? 2 : 1], nodal, reason, sizeof reason);
  }
  SK_TRY(sk_defaults_param(api, host, scene, "penalty", computed, reason, eps_n));
  return sk_defaults_follow(api, host, scene, "penalty_tangential", *eps_n, "the normal penalty", friction, eps_t);
}
