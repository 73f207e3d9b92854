/* The built penalty-nts module, loaded as the driver loads it (the plugin test kit): the entry symbol, ABI 2, name,
 * the entries it fills and those it leaves NULL, hidden internals. The path comes from CMake. */
#include <dlfcn.h>
#include <string.h>

#include "plugin_kit.h"
#include "sk_test.h"

int main(void) {
  const sk_plugin *plugin = kit_load_module(PNTS_MODULE_PATH, "penalty-nts", "evaluate_point");
  if (plugin) {
    SK_CHECK(plugin->kinds == SK_KIND_PAIR);
    SK_CHECK(plugin->pattern && plugin->update_active_set && plugin->points);
    SK_CHECK(plugin->converged); /* searches again when a node slid beyond its candidate faces */
    SK_CHECK(plugin->recover == NULL && plugin->integrator == NULL);
    int n_params = 0;
    while (plugin->parameters[n_params]) ++n_params;
    SK_CHECK(n_params == 7);
    SK_CHECK(strncmp(plugin->parameters[6], "self_exclusion:", 15) == 0);
    SK_CHECK(plugin->caps & SK_CAP_SELF_CONTACT); /* a pair whose master is its slave (docs/plugins/penalty-nts.md) */
  }
  /* the covariant kernel is linked in statically, and not exported */
  void *module = dlopen(PNTS_MODULE_PATH, RTLD_NOW | RTLD_LOCAL);
  SK_CHECK(module && dlsym(module, "cov_friction") == NULL);
  if (module) dlclose(module);
  return sk_test_finish("penalty-nts module");
}
