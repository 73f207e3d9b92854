/* The host table: what plugins reach of the core (plugin.h). */
#include <stdarg.h>
#include <stdio.h>

#include "stickslip/config.h"
#include "stickslip/scene.h"

static int host_owns_node(const sk_host *host, int node) {
  const sk_model *model = host->core;
  if (model->n_ranks == 1) return 1;
  return model->node_owner[node] == model->rank;
}

static sk_status host_param_double(const sk_host *host, const sk_params *params, const char *key, int required,
                                   double dflt, double *out) {
  (void)host;
  return sk_cfg_double((const sk_cfg *)params, key, required, dflt, out);
}

static sk_status host_param_int(const sk_host *host, const sk_params *params, const char *key, int required,
                                int dflt, int *out) {
  (void)host;
  return sk_cfg_int((const sk_cfg *)params, key, required, dflt, out);
}

static sk_status host_param_string(const sk_host *host, const sk_params *params, const char *key, int required,
                                   const char *dflt, const char **out) {
  (void)host;
  return sk_cfg_string((const sk_cfg *)params, key, required, dflt, out);
}

static sk_status host_error(const sk_host *host, sk_status code, const char *fmt, ...) {
  (void)host;
  char message[1024];
  va_list args;
  va_start(args, fmt);
  vsnprintf(message, sizeof message, fmt, args);
  va_end(args);
  return sk_error_set(code, "%s", message);
}

int sk_log_verbosity = 0;

static void host_log(const sk_host *host, int level, const char *fmt, ...) {
  const sk_model *model = host->core;
  if (model->rank != 0 || level > 1 + sk_log_verbosity) return;
  va_list args;
  va_start(args, fmt);
  fprintf(stderr, level == 1 ? "warning: " : "");
  vfprintf(stderr, fmt, args);
  fputc('\n', stderr);
  va_end(args);
}

static const void *host_get_extension(const sk_host *host, const char *id) {
  (void)host;
  (void)id;
  return NULL;
}


void sk_host_init(sk_host *host, sk_model *model) {
  host->abi_version = SK_PLUGIN_ABI_VERSION;
  host->dim = model->dim;
  host->n_nodes = model->n_nodes;
  host->n_dofs = model->n_dofs;
  host->X = model->X;
  host->lumped_mass = model->time.scheme == SK_SCHEME_QUASISTATIC ? NULL : model->lumped_mass;
  host->rank = model->rank;
  host->n_ranks = model->n_ranks;
  host->contact = sk_core_contact_services();
  host->core = model;
  host->owns_node = host_owns_node;
  host->param_double = host_param_double;
  host->param_int = host_param_int;
  host->param_string = host_param_string;
  host->error = host_error;
  host->log = host_log;
  host->get_extension = host_get_extension;
}
