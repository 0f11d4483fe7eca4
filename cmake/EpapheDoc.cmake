# The API documentation: Doxygen over the installed headers (the HEADERS of every epaphe_add_package) with
# docs/developer/api-mainpage.md as the main page and the architecture and extending guides as related pages.
#   cmake --build build --target doc      ->  build/doc/html/index.html
# The test unit.doxygen (tests/CMakeLists.txt) runs the same configuration into a scratch directory and
# fails on any warning: an undocumented public class or function, a broken reference, a bad command.
# Doxygen is optional for the build: without it there is no `doc` target and unit.doxygen says so.
find_package(Doxygen QUIET)
set(EPAPHE_DOXYGEN "")  # unit.doxygen's doxygen: empty when there is none (the test is then skipped)
if(NOT DOXYGEN_FOUND)
  message(STATUS "Epaphe: doxygen not found, no 'doc' target (./epaphe setup installs Debian's doxygen)")
  return()
endif()

set(EPAPHE_DOXYGEN "${DOXYGEN_EXECUTABLE}")
get_property(_headers GLOBAL PROPERTY EPAPHE_INSTALLED_HEADERS)
# the pages: the main page and the two guides it links to; their links to other documents become the documents' paths
# (cmake/doxygen_md_filter.py)
set(_page_names api-mainpage.md architecture.md extending.md)
list(TRANSFORM _page_names PREPEND "${PROJECT_SOURCE_DIR}/docs/developer/" OUTPUT_VARIABLE _pages)
find_program(EPAPHE_PYTHON NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH)  # as tests/CMakeLists.txt
if(NOT EPAPHE_PYTHON)
  find_program(EPAPHE_PYTHON NAMES python3 REQUIRED)
endif()
list(JOIN _page_names " " _names)
set(EPAPHE_DOXYGEN_MD_FILTER "\"${EPAPHE_PYTHON} ${PROJECT_SOURCE_DIR}/cmake/doxygen_md_filter.py ${_names}\"")
set(EPAPHE_DOXYGEN_MAINPAGE "${PROJECT_SOURCE_DIR}/docs/developer/api-mainpage.md")
list(JOIN _headers "\" \\\n    \"" EPAPHE_DOXYGEN_HEADERS)
list(JOIN _pages "\" \\\n    \"" EPAPHE_DOXYGEN_PAGES)
set(EPAPHE_DOXYGEN_INPUT "\"${EPAPHE_DOXYGEN_PAGES}\" \\\n    \"${EPAPHE_DOXYGEN_HEADERS}\"")

# doc: the HTML in the build tree
set(EPAPHE_DOXYGEN_OUTPUT "${PROJECT_BINARY_DIR}/doc")
set(EPAPHE_DOXYGEN_WARN_LOG "")
configure_file(${PROJECT_SOURCE_DIR}/cmake/Doxyfile.in ${PROJECT_BINARY_DIR}/Doxyfile @ONLY)
add_custom_target(doc
  COMMAND ${DOXYGEN_EXECUTABLE} ${PROJECT_BINARY_DIR}/Doxyfile
  COMMAND ${CMAKE_COMMAND} -E echo "API documentation: ${EPAPHE_DOXYGEN_OUTPUT}/html/index.html"
  WORKING_DIRECTORY ${PROJECT_BINARY_DIR}
  DEPENDS ${_headers} ${_pages} ${PROJECT_BINARY_DIR}/Doxyfile ${PROJECT_SOURCE_DIR}/cmake/doxygen_md_filter.py
  COMMENT "Doxygen: the API documentation of the installed headers"
  VERBATIM)

# unit.doxygen's configuration: the same, into a scratch directory, warnings to a file
set(EPAPHE_DOXYGEN_OUTPUT "${PROJECT_BINARY_DIR}/tests/doxygen")
set(EPAPHE_DOXYGEN_WARN_LOG "${PROJECT_BINARY_DIR}/tests/doxygen/warnings.txt")
configure_file(${PROJECT_SOURCE_DIR}/cmake/Doxyfile.in ${PROJECT_BINARY_DIR}/tests/Doxyfile.check @ONLY)
