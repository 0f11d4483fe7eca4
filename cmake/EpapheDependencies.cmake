# Dependencies of every Epaphe package. Trilinos comes from cmake/setup-deps.sh
# (EPAPHE_DEPS_PREFIX, default /opt/epaphe-deps); pass -DTrilinos_DIR or CMAKE_PREFIX_PATH otherwise.
if(NOT Trilinos_DIR AND DEFINED ENV{EPAPHE_DEPS_PREFIX})
  set(_epaphe_deps "$ENV{EPAPHE_DEPS_PREFIX}")
elseif(NOT Trilinos_DIR)
  set(_epaphe_deps "/opt/epaphe-deps")
endif()
if(_epaphe_deps)
  list(APPEND CMAKE_PREFIX_PATH "${_epaphe_deps}/trilinos-13.2.0")
endif()

find_package(Trilinos 13.2 REQUIRED
  COMPONENTS Teuchos Kokkos KokkosKernels Tpetra Belos Anasazi Amesos2)
message(STATUS "Epaphe: Trilinos ${Trilinos_VERSION} from ${Trilinos_DIR}")
if(NOT "${Trilinos_TPL_LIST}" MATCHES "MUMPS")
  message(FATAL_ERROR "Epaphe needs Trilinos built with MUMPS (Amesos2 over MUMPS); run cmake/setup-deps.sh")
endif()

# Trilinos' imported targets, one interface target per group we use.
foreach(_pkg Teuchos Kokkos KokkosKernels Tpetra Belos Anasazi Amesos2)
  find_package(${_pkg} REQUIRED CONFIG HINTS "${Trilinos_DIR}/..")
endforeach()

find_package(MPI REQUIRED COMPONENTS C CXX)
find_package(OpenMP REQUIRED COMPONENTS CXX)

set(HDF5_PREFER_PARALLEL TRUE)
find_package(HDF5 REQUIRED COMPONENTS C)
