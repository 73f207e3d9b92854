/* The built mortar-dual module, loaded as the driver loads it (the plugin test kit): ABI 2, its name, the entries,
 * capabilities and strategies (saddle-point the default, condensed), hidden kernel symbols; an instance of the
 * loaded table created for each strategy and basis on a 2D pair (condensed with the standard basis refused: D is
 * not diagonal). The path comes from CMake. */
#include <dlfcn.h>
#include <string.h>

#include "plugin_kit.h"
#include "sk_test.h"

static sk_status create_2d(const sk_plugin *plugin, int strategy, const char *basis) {
  static const double X[] = {0.0, 0.0, 0.5, 0.0, 1.0, 0.0, 1.1, -0.01, 0.4, -0.01, -0.1, -0.01};
  static const int slave[] = {0, 1, 1, 2}, master[] = {3, 4, 4, 5};
  kit k;
  kit_init(&k, 2, 6, X);
  kit_surface(&k, 0, SK_LINE2, 2, 2, slave);
  kit_surface(&k, 1, SK_LINE2, 2, 2, master);
  kit_param_text(&k, "basis", basis);
  sk_status st = kit_create(&k, plugin, strategy);
  if (st == SK_OK) { /* the step's layout: one z per slave node and dimension */
    kit_state(&k, X, X, 0.0, 1.0, NULL);
    st = kit_begin(&k);
    SK_CHECK(k.layout.n_extra == 3 * 2);
    SK_CHECK(strategy == 0 || k.n_pairs == 6); /* condensed: every z paired with its slave row */
  }
  kit_free(&k);
  return st;
}

int main(void) {
  const sk_plugin *plugin = kit_load_module(MORTAR_MODULE_PATH, "mortar-dual", "mortar_pair_set");
  if (plugin) {
    SK_CHECK(plugin->kinds == SK_KIND_PAIR);
    SK_CHECK(plugin->pattern && plugin->update_active_set && plugin->points && plugin->converged &&
             plugin->commit_step && plugin->reject_step);
    SK_CHECK(plugin->strategies[0] && strcmp(plugin->strategies[0], "saddle-point") == 0);
    SK_CHECK(plugin->strategies[1] && strcmp(plugin->strategies[1], "condensed") == 0);
    SK_CHECK(plugin->strategies[2] == NULL);
    SK_CHECK((plugin->caps & SK_CAP_2D) && (plugin->caps & SK_CAP_3D) && (plugin->caps & SK_CAP_CONDENSATION) &&
             (plugin->caps & SK_CAP_MULTIPLIERS) && (plugin->caps & SK_CAP_FRICTION) &&
             (plugin->caps & SK_CAP_RIGID_OBSTACLE) && (plugin->caps & SK_CAP_DEFORMABLE_MASTER) &&
             (plugin->caps & SK_CAP_DYNAMICS));
    for (int strategy = 0; strategy < 2; ++strategy)
      for (int b = 0; b < 2; ++b) {
        const char *basis = b ? "standard" : "dual";
        const sk_status st = create_2d(plugin, strategy, basis);
        printf("  strategy %s, basis %s: %s\n", plugin->strategies[strategy], basis,
               st == SK_OK ? "ok" : sk_error_message());
        SK_CHECK(st == (strategy == 1 && b == 1 ? SK_ERR_INPUT : SK_OK));
      }
    void *module = dlopen(MORTAR_MODULE_PATH, RTLD_NOW | RTLD_LOCAL);
    SK_CHECK(module && dlsym(module, "mortar_pair_set") == NULL && dlsym(module, "mortar_ncp") == NULL);
    if (module) dlclose(module);
  }
  return sk_test_finish("test_mortar_module");
}
