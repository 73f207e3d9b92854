/* A plugin library built against a future ABI (abi_version 999): the driver must refuse it with a clear message
 * (tests/cli/test_bad_input.py, case bad_abi_plugin). Everything else in the table is a harmless stub. */
#include "stickslip/plugin.h"

static sk_status create(const sk_host *host, const sk_pair *pair, sk_instance **instance) {
  (void)host;
  (void)pair;
  *instance = 0;
  return SK_OK;
}
static void destroy(sk_instance *instance) { (void)instance; }
static sk_status step(sk_instance *instance, const sk_state *state) {
  (void)instance;
  (void)state;
  return SK_OK;
}
static sk_status layout(sk_instance *instance, const sk_state *state, sk_layout *out) {
  (void)instance;
  (void)state;
  out->n_extra = 0;
  out->initial = 0;
  out->eliminated = 0;
  return SK_OK;
}
static sk_status assemble(sk_instance *instance, const sk_state *state, sk_sink *sink) {
  (void)instance;
  (void)state;
  (void)sink;
  return SK_OK;
}
static void reject(sk_instance *instance) { (void)instance; }
static sk_status report(sk_instance *instance, const sk_state *state, sk_contact_report *out) {
  (void)instance;
  (void)state;
  (void)out;
  return SK_OK;
}

static const char *const strategies[] = {"none", 0};
static const char *const parameters[] = {0};

static const sk_plugin table = {
    .abi_version = 999,
    .name = "bad-abi",
    .summary = "test plugin with a wrong ABI version",
    .caps = 0,
    .strategies = strategies,
    .parameters = parameters,
    .create = create,
    .destroy = destroy,
    .begin_step = step,
    .layout = layout,
    .residual = assemble,
    .jacobian = assemble,
    .commit_step = step,
    .reject_step = reject,
    .report = report,
};

__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void);
__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void) { return &table; }
