# stickslip's CMake package (installed by `cmake --install`; relocatable: every path is found from this file).
#
#   find_package(stickslip 0.1 REQUIRED)        # -DCMAKE_PREFIX_PATH=<the install prefix>
#   stickslip_add_plugin(my-contact my_contact.c)   # builds libstickslip-my-contact.so (target my-contact)
#   target_link_libraries(test_my_contact PRIVATE stickslip::plugin_kit)   # FD tests through the ABI
#
# Imported targets:
#   stickslip::plugin_headers   the plugin ABI headers (stickslip/plugin.h, plugin_types.h): all a plugin uses
#   stickslip::plugin_kit       the plugin test kit (stickslip/kit/plugin_kit.h, sk_test.h; libstickslip_plugin_kit)
#   stickslip::driver           the installed driver (bin/stickslip), e.g. for add_test(COMMAND stickslip::driver ...)
# Variables:
#   stickslip_PLUGIN_DIR        where the installed driver finds plugins (<prefix>/lib/stickslip/plugins)
#   stickslip_DRIVER            the driver's path
get_filename_component(_stickslip_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)

set(stickslip_PLUGIN_DIR "${_stickslip_prefix}/lib/stickslip/plugins")
set(stickslip_DRIVER "${_stickslip_prefix}/bin/stickslip")
set(stickslip_INCLUDE_DIR "${_stickslip_prefix}/include")

if(NOT TARGET stickslip::plugin_headers)
  add_library(stickslip::plugin_headers INTERFACE IMPORTED)
  set_target_properties(stickslip::plugin_headers PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${stickslip_INCLUDE_DIR}")

  add_library(stickslip::plugin_kit SHARED IMPORTED)
  set_target_properties(stickslip::plugin_kit PROPERTIES
    IMPORTED_LOCATION "${_stickslip_prefix}/lib/libstickslip_plugin_kit.so"
    INTERFACE_INCLUDE_DIRECTORIES "${stickslip_INCLUDE_DIR}/stickslip/kit"
    INTERFACE_LINK_LIBRARIES "stickslip::plugin_headers;m")

  add_executable(stickslip::driver IMPORTED)
  set_target_properties(stickslip::driver PROPERTIES IMPORTED_LOCATION "${stickslip_DRIVER}")
endif()

include("${CMAKE_CURRENT_LIST_DIR}/StickslipPluginTarget.cmake")

# stickslip_add_plugin(name sources...): a MODULE target `name` building libstickslip-<name>.so with the project's
# flags; `install(TARGETS name LIBRARY DESTINATION ${stickslip_PLUGIN_DIR})` puts it where the driver looks, or
# point STICKSLIP_PLUGIN_PATH at its build folder.
function(stickslip_add_plugin name)
  add_library(${name} MODULE ${ARGN})
  target_link_libraries(${name} PRIVATE stickslip::plugin_headers)
  stickslip_plugin_target(${name} ${name})
endfunction()

unset(_stickslip_prefix)
set(stickslip_FOUND TRUE)
