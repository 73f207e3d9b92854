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
    SK_CHECK(plugin->pattern && plugin->recover && plugin->update_active_set && plugin->points && plugin->converged);
    /* the strategies, the default first; the deprecated aliases last */
    static const char *const names[] = {"condensed", "augmented", "paper-reduced", "direct", "direct-endpoint",
                                        "reduced", "none"};
    for (int i = 0; i < 7; ++i) SK_CHECK(plugin->strategies[i] && strcmp(plugin->strategies[i], names[i]) == 0);
    SK_CHECK(plugin->strategies[7] == NULL);
    SK_CHECK((plugin->caps & SK_CAP_3D) && (plugin->caps & SK_CAP_2D) && (plugin->caps & SK_CAP_CONDENSATION) &&
             (plugin->caps & SK_CAP_MULTIPLIERS) && (plugin->caps & SK_CAP_ENERGY_MOMENTUM) &&
             (plugin->caps & SK_CAP_RIGID_OBSTACLE) && (plugin->caps & SK_CAP_DEFORMABLE_MASTER));
    void *module = dlopen(NTS_MODULE_PATH, RTLD_NOW | RTLD_LOCAL);
    SK_CHECK(module && dlsym(module, "nts_condense") == NULL && dlsym(module, "nts_paper_build") == NULL &&
             dlsym(module, "nts_element_eval") == NULL);
    if (module) dlclose(module);
  }
  return sk_test_finish("test_nts_module");
}
