/* The built penalty-nts module, loaded as the driver loads it: dlopen, the one exported entry symbol, ABI version,
 * name and table completeness. The path comes from CMake ($<TARGET_FILE:plugin_penalty-nts>). */
#include <dlfcn.h>
#include <string.h>

#include "sk_test.h"
#include "stickslip/plugin.h"

int main(void) {
  void *module = dlopen(PNTS_MODULE_PATH, RTLD_NOW | RTLD_LOCAL);
  if (!module) fprintf(stderr, "dlopen %s: %s\n", PNTS_MODULE_PATH, dlerror());
  SK_CHECK(module != NULL);
  if (!module) return sk_test_finish("penalty-nts module");
  sk_plugin_entry_fn entry;
  *(void **)&entry = dlsym(module, SK_PLUGIN_ENTRY_SYMBOL);
  SK_CHECK(entry != NULL);
  /* Hidden visibility: internal functions are not exported. */
  SK_CHECK(dlsym(module, "evaluate_point") == NULL);
  if (entry) {
    const sk_plugin *plugin = entry();
    SK_CHECK(plugin->abi_version == SK_PLUGIN_ABI_VERSION);
    SK_CHECK(strcmp(plugin->name, "penalty-nts") == 0);
    SK_CHECK(plugin->create && plugin->destroy && plugin->begin_step && plugin->layout && plugin->residual &&
             plugin->jacobian && plugin->after_iteration && plugin->commit_step && plugin->reject_step &&
             plugin->report && plugin->points);
    SK_CHECK(plugin->recover == NULL); /* never eliminates unknowns */
    int n_params = 0;
    while (plugin->parameters[n_params]) ++n_params;
    SK_CHECK(n_params == 6);
  }
  dlclose(module);
  return sk_test_finish("penalty-nts module");
}
