# Trilinos from Debian 12 (trilinos-all-dev, 13.2). Provides stickslip::trilinos, an interface target carrying the
# packages the bridge uses (NOX, Amesos2, Belos, MueLu, Ifpack2, Tpetra, Teuchos) plus MPI's C++ bindings.
#
# Quirks of the Debian build, kept here so nothing else needs to know:
#  * The package configs list their third-party libraries by absolute path, among them libptscotch.so, which only
#    libptscotch-dev installs (trilinos-all-dev does not pull it in). A missing file there only shows up as an
#    obscure link error, so we check the TPL paths up front and name the package to install.
#  * The imported trilinos_* targets do not carry MPI, but the headers include mpi.h and the libraries call the MPI
#    C++ runtime: MPI::MPI_CXX is linked beside them.
#  * The headers emit warnings under -Wall -Wextra (unused parameters, deprecated Kokkos APIs): they are added as
#    SYSTEM include directories so -Werror applies to our code only.
#  * Tpetra is instantiated for Scalar=double, LO=int, GO=long long, Node=Serial only (TpetraCore_config.h); the
#    bridge's sources use exactly those types.
set(STICKSLIP_TRILINOS_PACKAGES NOX Amesos2 Amesos Epetra Belos MueLu Ifpack2 Tpetra Teuchos)
find_package(Trilinos 13.2 REQUIRED COMPONENTS ${STICKSLIP_TRILINOS_PACKAGES}
             PATHS /usr/lib/x86_64-linux-gnu/cmake/Trilinos)

set(stickslip_trilinos_libraries "")
set(stickslip_trilinos_includes "")
foreach(package ${STICKSLIP_TRILINOS_PACKAGES})
  list(APPEND stickslip_trilinos_libraries ${${package}_LIBRARIES})
  list(APPEND stickslip_trilinos_includes ${${package}_INCLUDE_DIRS} ${${package}_TPL_INCLUDE_DIRS})
  foreach(tpl_library ${${package}_TPL_LIBRARIES})
    if(IS_ABSOLUTE "${tpl_library}" AND NOT EXISTS "${tpl_library}")
      message(FATAL_ERROR "Trilinos ${package} names ${tpl_library}, which is not installed "
                          "(libptscotch.so comes from libptscotch-dev).")
    endif()
  endforeach()
endforeach()
list(REMOVE_DUPLICATES stickslip_trilinos_libraries)
list(REMOVE_DUPLICATES stickslip_trilinos_includes)

add_library(stickslip::trilinos INTERFACE IMPORTED)
target_include_directories(stickslip::trilinos SYSTEM INTERFACE ${stickslip_trilinos_includes})
target_link_libraries(stickslip::trilinos INTERFACE ${stickslip_trilinos_libraries} MPI::MPI_CXX)
message(STATUS "Trilinos ${Trilinos_VERSION} for the bridge: ${STICKSLIP_TRILINOS_PACKAGES}")
