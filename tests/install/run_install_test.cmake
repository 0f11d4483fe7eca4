# Installs the build tree into a scratch prefix, runs the installed epaphe-run on an installed deck
# and reads its result with the installed Python package, then configures, builds and runs
# tests/install against the prefix with find_package(Epaphe).
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/run")
# Every step runs in ${WORK}/run (no epaphe package there: Python cannot import one from the current
# directory) and is stopped after 30 min (the consumer's build against Trilinos' headers takes a few).
function(step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE r OUTPUT_VARIABLE o ERROR_VARIABLE e
                  WORKING_DIRECTORY "${WORK}/run" TIMEOUT 1800)
  message("${o}")
  if(NOT r EQUAL 0)
    message(FATAL_ERROR "failed (${r}): ${ARGN}\n${e}")
  endif()
endfunction()
step(${CMAKE_COMMAND} --install "${EPAPHE_BUILD}" --prefix "${WORK}/prefix")
# Where the install put the Python package: the one directory under the prefix holding
# epaphe/__init__.py (docs/user/python.md names <prefix>/lib/python3/dist-packages); PYTHONPATH names it
# alone below, never the source tree.
file(GLOB_RECURSE _inits LIST_DIRECTORIES false "${WORK}/prefix/*/__init__.py")
list(FILTER _inits INCLUDE REGEX "/epaphe/__init__\\.py$")
list(LENGTH _inits _n)
if(NOT _n EQUAL 1)
  message(FATAL_ERROR "the install put ${_n} Python packages 'epaphe' under ${WORK}/prefix (${_inits}), expected "
                      "one: see the install(DIRECTORY python/epaphe ...) rule in drivers/CMakeLists.txt")
endif()
get_filename_component(_site "${_inits}" DIRECTORY)
get_filename_component(_site "${_site}" DIRECTORY)
message("the installed Python package: ${_site}/epaphe")
# The Python package from the prefix, with Debian's python3: it imports from there (not from the
# source tree), without matplotlib, and reads the installed epaphe-run's schema; the installed
# drivers find it.
step(${CMAKE_COMMAND} -E env "PYTHONPATH=${_site}" ${PYTHON} -c [=[
import os, sys
import epaphe
from epaphe import deck, exact, measures, results, schema, study
assert os.path.realpath(epaphe.__file__).startswith(os.path.realpath(sys.argv[1])), epaphe.__file__
assert "matplotlib" not in sys.modules, "import epaphe imported matplotlib"
s = epaphe.Schema(os.path.join(sys.argv[2], "bin", "epaphe-run"))
assert s.param("Time->Time step").type == "double", s.param("Time->Time step")
print("import epaphe:", epaphe.__file__, "-", len(s.params), "deck parameters")
]=] "${_site}" "${WORK}/prefix")
foreach(_driver epaphe-plot epaphe-sweep epaphe-rotor epaphe-frf)
  step(${CMAKE_COMMAND} -E env --unset=PYTHONPATH "${WORK}/prefix/bin/${_driver}" --help)
endforeach()
# The installed epaphe-run on the installed bar-on-wall.xml (V1, 2,000 steps), its result read with
# the installed package: check_installed_run.py says what it asserts (V1's contact times, force and
# rebound; records, time span, finite energies). No LD_LIBRARY_PATH: the binary's run path must do.
file(GLOB_RECURSE _deck LIST_DIRECTORIES false "${WORK}/prefix/*/epaphe/inputs/bar-on-wall.xml")
list(LENGTH _deck _n)
if(NOT _n EQUAL 1)
  message(FATAL_ERROR "the install has ${_n} epaphe/inputs/bar-on-wall.xml under ${WORK}/prefix (${_deck}), expected "
                      "one (<prefix>/share/epaphe/inputs): see install(DIRECTORY inputs/ ...) in the top-level "
                      "CMakeLists.txt")
endif()
step(${CMAKE_COMMAND} -E env --unset=LD_LIBRARY_PATH --unset=PYTHONPATH
     "${WORK}/prefix/bin/epaphe-run" "${_deck}" --threads 1 --output "${WORK}/run/bar-on-wall.h5")
step(${CMAKE_COMMAND} -E env "PYTHONPATH=${_site}" ${PYTHON} -s "${SOURCE}/check_installed_run.py"
     "${_site}" "${WORK}/prefix" "${WORK}/run/bar-on-wall.h5")
step(${CMAKE_COMMAND} -S "${SOURCE}" -B "${WORK}/build" "-DCMAKE_PREFIX_PATH=${WORK}/prefix"
     "-DTrilinos_DIR=${Trilinos_DIR}" "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_C_COMPILER=${C}"
     -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
step(${CMAKE_COMMAND} --build "${WORK}/build")
step("${WORK}/build/consumer")
step("${WORK}/build/consumer_online")
# A contact law and observers of the consumer's own on a deck that names them (consumer_extension.cpp
# asserts that the law made the run's forces and that the observers saw every step).
step("${WORK}/build/consumer_extension" "${SOURCE}/custom-law.xml" "${WORK}/run/custom-law.h5")
# Epaphe's libraries are static: the shared ones the online consumer needs are Trilinos' it uses.
execute_process(COMMAND ldd "${WORK}/build/consumer_online" OUTPUT_VARIABLE _ldd TIMEOUT 60)
if(_ldd MATCHES "libtpetra|libamesos2|libanasazi|libbelos")
  message(FATAL_ERROR "consumer_online links Tpetra or a solver on it (Epaphe::dynamics must not):\n${_ldd}")
endif()
message("consumer_online: no Tpetra, Amesos2, Anasazi or Belos library linked")
