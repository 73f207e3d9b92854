# `cmake --install`: a relocatable tree that runs with no build tree around.
#
#   bin/stickslip                              the driver (RUNPATH $ORIGIN/../lib)
#   lib/libstickslip_{core,sim,bridge}.so      the core the driver and the plugin kit link (RUNPATH $ORIGIN)
#   lib/libstickslip_gmsh.so                   gmsh, loaded only by the mesh generator's child (mesh_load.c)
#   lib/libstickslip_plugin_kit.so             the plugin test kit (mock host + FD check through the ABI)
#   lib/stickslip/plugins/libstickslip-*.so    the plugins, where the driver looks for them: <bin>/../lib/...
#   include/stickslip/plugin.h, plugin_types.h the plugin ABI (+ the contact/mesh/error headers the kit's header uses)
#   include/stickslip/kit/plugin_kit.h, sk_test.h
#   lib/cmake/stickslip/                       stickslipConfig.cmake (+ version): stickslip::plugin_headers,
#                                              stickslip::plugin_kit, stickslip::driver, stickslip_add_plugin()
#   lib/pkgconfig/stickslip.pc, stickslip-plugin-kit.pc
#   share/stickslip/{scenes,meshes,scripts}    the scenes (their relative mesh paths kept) and the plot scripts
#   share/stickslip/tools                      `stickslip compare` (Python), found relative to the driver
#   share/doc/stickslip/                       README and docs/
#
# Libraries go to `lib` under every prefix (not GNUInstallDirs' lib/<multiarch>): the driver finds its plugins at
# <bin>/../lib/stickslip/plugins, and one fixed layout keeps every path relative.
set(STICKSLIP_INSTALL_LIBDIR lib)
set(STICKSLIP_INSTALL_PLUGINDIR ${STICKSLIP_INSTALL_LIBDIR}/stickslip/plugins)
set(STICKSLIP_INSTALL_CMAKEDIR ${STICKSLIP_INSTALL_LIBDIR}/cmake/stickslip)

# Relocatable: every installed binary finds its libraries relative to itself; non-system dependency folders
# (a Trilinos outside /usr) stay on the path they were linked from.
set_target_properties(stickslip PROPERTIES INSTALL_RPATH "$ORIGIN/../${STICKSLIP_INSTALL_LIBDIR}"
  INSTALL_RPATH_USE_LINK_PATH ON)
foreach(lib stickslip_core stickslip_gmsh stickslip_bridge stickslip_sim stickslip_plugin_kit)
  set_target_properties(${lib} PROPERTIES INSTALL_RPATH "$ORIGIN" INSTALL_RPATH_USE_LINK_PATH ON)
endforeach()

install(TARGETS stickslip RUNTIME DESTINATION bin)
install(TARGETS stickslip_core stickslip_gmsh stickslip_bridge stickslip_sim stickslip_plugin_kit
  LIBRARY DESTINATION ${STICKSLIP_INSTALL_LIBDIR})
get_property(plugin_targets GLOBAL PROPERTY STICKSLIP_PLUGIN_TARGETS)
install(TARGETS ${plugin_targets} LIBRARY DESTINATION ${STICKSLIP_INSTALL_PLUGINDIR})

install(FILES
  ${PROJECT_SOURCE_DIR}/core/include/stickslip/plugin.h
  ${PROJECT_SOURCE_DIR}/core/include/stickslip/plugin_types.h
  ${PROJECT_SOURCE_DIR}/core/include/stickslip/contact.h
  ${PROJECT_SOURCE_DIR}/core/include/stickslip/mesh.h
  ${PROJECT_SOURCE_DIR}/core/include/stickslip/error.h
  DESTINATION include/stickslip)
install(FILES ${PROJECT_SOURCE_DIR}/tests/support/plugin_kit.h ${PROJECT_SOURCE_DIR}/tests/support/sk_test.h
  DESTINATION include/stickslip/kit)

include(CMakePackageConfigHelpers)
# 0.x: a minor release may change what a plugin sees, so only the same minor is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/package/stickslipConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_SOURCE_DIR}/cmake/package/stickslipConfig.cmake
  ${PROJECT_SOURCE_DIR}/cmake/package/StickslipPluginTarget.cmake
  ${PROJECT_BINARY_DIR}/package/stickslipConfigVersion.cmake DESTINATION ${STICKSLIP_INSTALL_CMAKEDIR})
foreach(pc stickslip stickslip-plugin-kit)
  configure_file(${PROJECT_SOURCE_DIR}/cmake/package/${pc}.pc.in ${PROJECT_BINARY_DIR}/package/${pc}.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/package/${pc}.pc DESTINATION ${STICKSLIP_INSTALL_LIBDIR}/pkgconfig)
endforeach()

install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes ${PROJECT_SOURCE_DIR}/meshes DESTINATION share/stickslip)
install(PROGRAMS ${PROJECT_SOURCE_DIR}/scripts/plot-history.sh ${PROJECT_SOURCE_DIR}/scripts/plot-snapshots.sh
  ${PROJECT_SOURCE_DIR}/scripts/plot_history.py ${PROJECT_SOURCE_DIR}/scripts/plot_snapshots.py
  DESTINATION share/stickslip/scripts)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION share/doc/stickslip)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION share/doc/stickslip)
# The example plugin as a project to copy: builds against this tree with CMake or pkg-config.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/plugins/example-spring DESTINATION share/doc/stickslip/examples)
# `stickslip compare` and its package (shared with the project's benchmark harness); the driver finds them at
# <bin>/../share/stickslip/tools.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/tools/ DESTINATION share/stickslip/tools USE_SOURCE_PERMISSIONS
  PATTERN __pycache__ EXCLUDE)
