# Installs the build tree into a scratch prefix, then configures, builds and runs tests/install
# against it with find_package(Epaphe).
file(REMOVE_RECURSE "${WORK}")
function(step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE r OUTPUT_VARIABLE o ERROR_VARIABLE e)
  message("${o}")
  if(NOT r EQUAL 0)
    message(FATAL_ERROR "failed (${r}): ${ARGN}\n${e}")
  endif()
endfunction()
step(${CMAKE_COMMAND} --install "${EPAPHE_BUILD}" --prefix "${WORK}/prefix")
# The Python package from the prefix, as README ("Python") says, with Debian's python3: it imports
# from there (not from the source tree), without matplotlib, and reads the installed epaphe-run's
# schema; the installed drivers find it.
set(_site "${WORK}/prefix/lib/python3/dist-packages")
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
foreach(_driver epaphe-plot epaphe-sweep epaphe-rotor)
  step("${WORK}/prefix/bin/${_driver}" --help)
endforeach()
step(${CMAKE_COMMAND} -S "${SOURCE}" -B "${WORK}/build" "-DCMAKE_PREFIX_PATH=${WORK}/prefix"
     "-DTrilinos_DIR=${Trilinos_DIR}" "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_C_COMPILER=${C}"
     -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
step(${CMAKE_COMMAND} --build "${WORK}/build")
step("${WORK}/build/consumer")
step("${WORK}/build/consumer_online")
# Epaphe's libraries are static: the shared ones the online consumer needs are Trilinos' it uses.
execute_process(COMMAND ldd "${WORK}/build/consumer_online" OUTPUT_VARIABLE _ldd)
if(_ldd MATCHES "libtpetra|libamesos2|libanasazi|libbelos")
  message(FATAL_ERROR "consumer_online links Tpetra or a solver on it (Epaphe::dynamics must not):\n${_ldd}")
endif()
message("consumer_online: no Tpetra, Amesos2, Anasazi or Belos library linked")
