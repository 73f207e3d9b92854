/* The built covariant-penalty module, loaded as the driver loads it (the plugin test kit): the entry symbol, ABI 2,
 * name, the entries it fills and those it leaves NULL, the kernels linked in and hidden. */
#include <dlfcn.h>
#include <string.h>

#include "plugin_kit.h"
#include "sk_test.h"

int main(void) {
  const sk_plugin *plugin = kit_load_module(CP_MODULE_PATH, "covariant-penalty", "cp_point_eval");
  if (plugin) {
    SK_CHECK(plugin->kinds == SK_KIND_PAIR);
    SK_CHECK(plugin->pattern && plugin->update_active_set && plugin->points && plugin->report);
    SK_CHECK(plugin->converged); /* searches again when a point slid beyond its candidate faces */
    SK_CHECK(plugin->recover == NULL && plugin->integrator == NULL);
    SK_CHECK((plugin->caps & SK_CAP_3D) && !(plugin->caps & SK_CAP_2D) && (plugin->caps & SK_CAP_NEEDS_CURVATURE));
    int n_params = 0;
    while (plugin->parameters[n_params]) ++n_params;
    SK_CHECK(n_params == 10);
  }
  /* the shared covariant kernel is linked in statically, and not exported */
  void *module = dlopen(CP_MODULE_PATH, RTLD_NOW | RTLD_LOCAL);
  SK_CHECK(module && dlsym(module, "cov_kinematics_eval") == NULL && dlsym(module, "cp_ray") == NULL);
  if (module) dlclose(module);
  return sk_test_finish("covariant-penalty module");
}
