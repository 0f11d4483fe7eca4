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
step(${CMAKE_COMMAND} -S "${SOURCE}" -B "${WORK}/build" "-DCMAKE_PREFIX_PATH=${WORK}/prefix"
     "-DTrilinos_DIR=${Trilinos_DIR}" "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_C_COMPILER=${C}"
     -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
step(${CMAKE_COMMAND} --build "${WORK}/build")
step("${WORK}/build/consumer")
