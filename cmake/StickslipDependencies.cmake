# Debian's packages only (scripts/install-deps.sh installs them). Trilinos quirks live in StickslipTrilinos.cmake.
find_package(MPI REQUIRED COMPONENTS C CXX)
find_package(PkgConfig REQUIRED)
pkg_check_modules(YAML REQUIRED IMPORTED_TARGET yaml-0.1)

find_path(GMSH_INCLUDE_DIR gmshc.h REQUIRED)
find_library(GMSH_LIBRARY NAMES gmsh REQUIRED)
add_library(stickslip::gmsh INTERFACE IMPORTED)
target_include_directories(stickslip::gmsh INTERFACE ${GMSH_INCLUDE_DIR})
target_link_libraries(stickslip::gmsh INTERFACE ${GMSH_LIBRARY})

find_path(METIS_INCLUDE_DIR metis.h REQUIRED)
find_library(METIS_LIBRARY NAMES metis REQUIRED)
add_library(stickslip::metis INTERFACE IMPORTED)
target_include_directories(stickslip::metis INTERFACE ${METIS_INCLUDE_DIR})
target_link_libraries(stickslip::metis INTERFACE ${METIS_LIBRARY})

include(StickslipTrilinos)
