/* The built nts-augmented module, loaded as the driver loads it (the plugin test kit): ABI 2, name, entries,
 * capabilities, hidden kernel symbols. The path comes from CMake. */
#include <dlfcn.h>
#include <string.h>

#include "plugin_kit.h"
#include "sk_test.h"

int main(void) {
  const sk_plugin *plugin = kit_load_module(NTS_MODULE_PATH, "nts-augmented", "nts_element_build");
  if (plugin) {
    SK_CHECK(plugin->kinds == SK_KIND_PAIR);
    SK_CHECK(plugin->pattern && plugin->recover && plugin->update_active_set && plugin->points);
    SK_CHECK(strcmp(plugin->strategies[0], "reduced") == 0);
    SK_CHECK((plugin->caps & SK_CAP_3D) && (plugin->caps & SK_CAP_CONDENSATION) &&
             (plugin->caps & SK_CAP_MULTIPLIERS) && (plugin->caps & SK_CAP_ENERGY_MOMENTUM) &&
             !(plugin->caps & SK_CAP_2D) && !(plugin->caps & SK_CAP_RIGID_OBSTACLE));
    void *module = dlopen(NTS_MODULE_PATH, RTLD_NOW | RTLD_LOCAL);
    SK_CHECK(module && dlsym(module, "nts_condense") == NULL);
    if (module) dlclose(module);
  }
  return sk_test_finish("test_nts_module");
}
