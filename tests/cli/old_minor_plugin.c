/* A plugin built against plugin ABI 2.0 (minor 0), before the second-order element types: the host must refuse to
 * attach it to a view of tri6/quad8/tet10/hex20 cells, naming the view and asking for a rebuild
 * (tests/cli/test_bad_input.py, case old_minor_plugin). The host stops before create(), so the entries only need to
 * exist (the loader checks the required ones); any call returns an error. */
#include "stickslip/plugin.h"

static sk_status refuse(void) { return SK_ERR_INTERNAL; }
static sk_status create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **instance) {
  (void)api, (void)host, (void)attach, (void)instance;
  return refuse();
}
static void destroy(sk_instance *in) { (void)in; }
static sk_status step(sk_instance *in, const sk_state *st) { return (void)in, (void)st, refuse(); }
static sk_status layout(sk_instance *in, const sk_state *st, sk_layout *l) {
  return (void)in, (void)st, (void)l, refuse();
}
static sk_status assemble(sk_instance *in, const sk_state *st, sk_sink *s) {
  return (void)in, (void)st, (void)s, refuse();
}
static void reject(sk_instance *in) { (void)in; }
static sk_status report(sk_instance *in, const sk_state *st, sk_contact_report *r) {
  return (void)in, (void)st, (void)r, refuse();
}

static const char *const strategies[] = {"none", NULL};
static const sk_plugin table = {
    .abi_major = SK_ABI_MAJOR, .abi_minor = 0, .struct_size = sizeof(sk_plugin),
    .name = "old-minor", .summary = "test plugin built for ABI 2.0", .kinds = SK_KIND_PAIR,
    .caps = SK_CAP_2D | SK_CAP_3D | SK_CAP_QUASISTATIC | SK_CAP_RIGID_OBSTACLE | SK_CAP_DEFORMABLE_MASTER,
    .strategies = strategies, .create = create, .destroy = destroy, .begin_step = step, .layout = layout,
    .residual = assemble, .jacobian = assemble, .commit_step = step, .reject_step = reject, .report = report};

__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void);
__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void) { return &table; }
