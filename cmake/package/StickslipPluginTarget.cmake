# One definition of what makes a stickslip plugin module, used by the project's own plugins (plugins/CMakeLists.txt)
# and, installed beside stickslipConfig.cmake, by plugins built out of tree (stickslip_add_plugin).
#
# stickslip_plugin_target(target name): `target` (a MODULE library) becomes libstickslip-<name>.so, the file the
# driver loads for `plugin: <name>`: C17, only the entry symbol exported (hidden visibility, the entry is marked
# default), -Wl,--no-undefined (a plugin links libc/libm only; a call into the core is a link error, not a load-time
# failure), -Wall -Wextra.
function(stickslip_plugin_target target name)
  set_target_properties(${target} PROPERTIES OUTPUT_NAME "stickslip-${name}" PREFIX "lib" SUFFIX ".so"
    C_STANDARD 17 C_STANDARD_REQUIRED ON C_EXTENSIONS OFF C_VISIBILITY_PRESET hidden POSITION_INDEPENDENT_CODE ON)
  target_link_libraries(${target} PRIVATE m)
  target_link_options(${target} PRIVATE -Wl,--no-undefined)
  target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:C>:-Wall -Wextra>)
endfunction()
