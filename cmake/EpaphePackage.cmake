# epaphe_add_package(NAME <name> SOURCES <...> HEADERS <...> USES <epaphe packages> EXTERNAL <targets>)
#
# One library per package, named epaphe_<name>, aliased Epaphe::<name>, with an explicit list of
# the Epaphe packages it may use (USES) and of the external targets it links (EXTERNAL).
# Headers live in <package>/src and install to include/epaphe.
# Warnings on our code. GCC 12's -Wmaybe-uninitialized fires inside Tpetra's own templates
# (instantiated in our translation units, ETI being off): we keep it off.
set(EPAPHE_WARNING_FLAGS -Wall -Wextra -Wpedantic -Wno-maybe-uninitialized
    $<$<BOOL:${EPAPHE_WARNINGS_AS_ERRORS}>:-Werror>)

function(epaphe_add_package)
  cmake_parse_arguments(P "" "NAME" "SOURCES;HEADERS;USES;EXTERNAL" ${ARGN})
  set(_t epaphe_${P_NAME})
  if(P_SOURCES)
    add_library(${_t} ${P_SOURCES})
    set(_scope PUBLIC)
  else()
    add_library(${_t} INTERFACE)
    set(_scope INTERFACE)
  endif()
  add_library(Epaphe::${P_NAME} ALIAS ${_t})
  set_target_properties(${_t} PROPERTIES EXPORT_NAME ${P_NAME})
  target_include_directories(${_t} ${_scope}
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/src>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/epaphe>)
  foreach(_u ${P_USES})
    target_link_libraries(${_t} ${_scope} epaphe_${_u})
  endforeach()
  if(P_EXTERNAL)
    target_link_libraries(${_t} ${_scope} ${P_EXTERNAL})
  endif()
  if(P_SOURCES)
    target_compile_options(${_t} PRIVATE ${EPAPHE_WARNING_FLAGS})
    set_target_properties(${_t} PROPERTIES OUTPUT_NAME epaphe_${P_NAME})
  endif()
  install(TARGETS ${_t} EXPORT EpapheTargets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(FILES ${P_HEADERS} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/epaphe)
  # the installed headers, for the API documentation (cmake/EpapheDoc.cmake)
  list(TRANSFORM P_HEADERS PREPEND "${CMAKE_CURRENT_SOURCE_DIR}/")
  set_property(GLOBAL APPEND PROPERTY EPAPHE_INSTALLED_HEADERS ${P_HEADERS})
endfunction()
