/* The built nts-augmented module, loaded as the driver loads it: dlopen, the one exported entry symbol (the kernel
 * and glue stay hidden), ABI version, name, strategies and table completeness. */
#include <dlfcn.h>
#include <string.h>

#include "sk_test.h"
#include "stickslip/plugin.h"

int main(void) {
  void *module = dlopen(NTS_MODULE_PATH, RTLD_NOW | RTLD_LOCAL);
  if (!module) fprintf(stderr, "dlopen %s: %s\n", NTS_MODULE_PATH, dlerror());
  SK_CHECK(module != NULL);
  if (!module) return sk_test_finish("test_nts_module");
  sk_plugin_entry_fn entry;
  *(void **)&entry = dlsym(module, SK_PLUGIN_ENTRY_SYMBOL);
  SK_CHECK(entry != NULL);
  SK_CHECK(dlsym(module, "nts_element_build") == NULL);
  SK_CHECK(dlsym(module, "nts_condense") == NULL);
  if (entry) {
    const sk_plugin *plugin = entry();
    SK_CHECK(plugin->abi_version == SK_PLUGIN_ABI_VERSION);
    SK_CHECK(strcmp(plugin->name, "nts-augmented") == 0);
    SK_CHECK(plugin->create && plugin->destroy && plugin->begin_step && plugin->layout && plugin->residual &&
             plugin->jacobian && plugin->recover && plugin->after_iteration && plugin->commit_step &&
             plugin->reject_step && plugin->report && plugin->points);
    SK_CHECK(strcmp(plugin->strategies[0], "reduced") == 0);
    SK_CHECK((plugin->caps & SK_CAP_3D) && (plugin->caps & SK_CAP_CONDENSATION) &&
             (plugin->caps & SK_CAP_ENERGY_MOMENTUM) && !(plugin->caps & SK_CAP_2D) &&
             !(plugin->caps & SK_CAP_RIGID_OBSTACLE));
  }
  dlclose(module);
  return sk_test_finish("test_nts_module");
}
