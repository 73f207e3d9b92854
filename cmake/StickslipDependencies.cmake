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

# MUMPS, the MPI build (libmumps-dev; not libdmumps_seq, whose mpi.h stub lives under mumps_seq/): the bridge calls
# dmumps_c itself (core/solver/mumps_solver.cpp). Trilinos's Amesos links the same library.
find_path(MUMPS_INCLUDE_DIR dmumps_c.h REQUIRED)
find_library(DMUMPS_LIBRARY NAMES dmumps REQUIRED)
add_library(stickslip::mumps INTERFACE IMPORTED)
target_include_directories(stickslip::mumps SYSTEM INTERFACE ${MUMPS_INCLUDE_DIR})
target_link_libraries(stickslip::mumps INTERFACE ${DMUMPS_LIBRARY} MPI::MPI_C)

include(StickslipTrilinos)
