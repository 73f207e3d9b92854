/* A plugin library built against plugin ABI 1 (the layout before ABI 2): the driver must refuse it with a clear
 * message naming its version (tests/cli/test_bad_input.py, case bad_abi_plugin). Only the head of the v1 table is
 * reproduced: the host reads the version first and stops there. */
#include <stdint.h>

typedef struct {
  uint32_t abi_version; /* v1: the first member, SK_PLUGIN_ABI_VERSION = 1 */
  const char *name;
  const char *summary;
  uint64_t caps;
  const void *strategies;
  const void *parameters;
  const void *calls[14];
} v1_plugin_head;

static const v1_plugin_head table = {.abi_version = 1, .name = "bad-abi", .summary = "test plugin built for ABI 1"};

__attribute__((visibility("default"))) const v1_plugin_head *stickslip_plugin_entry(void);
__attribute__((visibility("default"))) const v1_plugin_head *stickslip_plugin_entry(void) { return &table; }
