# Every ctest gets a TIMEOUT, so that a test that hangs fails instead of stalling a run until CI's
# own limit. Call epaphe_test_timeouts() at the end of each CMakeLists.txt that adds tests (CMake
# 3.25 sets test properties only in the directory that made the test).
#
# The timeout is EPAPHE_TEST_TIMEOUT_FACTOR times the test's measured time in tests/test-times.txt
# ("name seconds" per line, written by tools/update-test-times from a run's CTestCostData.txt), and
# at least EPAPHE_TEST_TIMEOUT_FLOOR seconds (a loaded 2-core machine running two tests at once
# slows a short test by more than the factor), at least 600 s for the tests of `--rest`. A test with no measured time gets a label default:
# 1800 s for benchmark, long, study and finding, 300 s otherwise. A TIMEOUT set explicitly is kept.
# unit.test-timeouts checks that every test has one, and names those with no measured time.
set(EPAPHE_TEST_TIMEOUT_FACTOR 4)
set(EPAPHE_TEST_TIMEOUT_FLOOR 60)
file(STRINGS ${PROJECT_SOURCE_DIR}/tests/test-times.txt _epaphe_test_times REGEX "^[^#].* [0-9.]+$")
set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tests/test-times.txt)
set_property(GLOBAL PROPERTY EPAPHE_TEST_TIMES "${_epaphe_test_times}")

function(epaphe_test_timeouts)
  get_property(_times GLOBAL PROPERTY EPAPHE_TEST_TIMES)
  get_property(_tests DIRECTORY PROPERTY TESTS)
  foreach(_t IN LISTS _tests)
    get_test_property(${_t} TIMEOUT _explicit)
    if(_explicit)
      continue()
    endif()
    set(_timeout "")
    foreach(_line IN LISTS _times)
      if(_line MATCHES "^([^ ]+) ([0-9]+)(\\.[0-9]*)?$" AND CMAKE_MATCH_1 STREQUAL _t)
        math(EXPR _timeout "${EPAPHE_TEST_TIMEOUT_FACTOR} * (${CMAKE_MATCH_2} + 1)")
        if(_timeout LESS EPAPHE_TEST_TIMEOUT_FLOOR)
          set(_timeout ${EPAPHE_TEST_TIMEOUT_FLOOR})
        endif()
        # the --rest tests time whole scenes (benchmark.step took 40 s alone, 282 s beside other work):
        # at least 600 s
        get_test_property(${_t} LABELS _labels)
        if(_labels MATCHES "benchmark|long|study|finding" AND _timeout LESS 600)
          set(_timeout 600)
        endif()
        break()
      endif()
    endforeach()
    if(_timeout STREQUAL "")
      get_test_property(${_t} LABELS _labels)
      if(_labels MATCHES "benchmark|long|study|finding")
        set(_timeout 1800)
      else()
        set(_timeout 300)
      endif()
    endif()
    set_tests_properties(${_t} PROPERTIES TIMEOUT ${_timeout})
  endforeach()
endfunction()
