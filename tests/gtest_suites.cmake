# Included by ctest (TEST_INCLUDE_FILES, tests/CMakeLists.txt motionmap_discover_tests) in the
# sanitizer build: one ctest test per GoogleTest suite of ${_mm_exe}, run with
# --gtest_filter=Suite.*, in the environment ${_mm_env}. The suites are listed when ctest starts,
# so a test added to the executable is run without re-running cmake.
if(NOT EXISTS "${_mm_exe}")
  # Not built yet (ctest before the build): one test that fails, named for it, as
  # gtest_discover_tests does.
  add_test("${_mm_target}_NOT_BUILT" "${_mm_target}_NOT_BUILT")
  return()
endif()
execute_process(COMMAND "${_mm_exe}" --gtest_list_tests
                OUTPUT_VARIABLE _mm_list ERROR_VARIABLE _mm_err RESULT_VARIABLE _mm_rc
                TIMEOUT 60)
if(NOT _mm_rc EQUAL 0)
  message(FATAL_ERROR "${_mm_exe} --gtest_list_tests failed (${_mm_rc}):\n${_mm_err}")
endif()
# A suite's line is its name and a dot at the line's start ("Suite." or "Prefix/Suite."), perhaps
# followed by a "# TypeParam" comment; the tests are indented below it.
string(REPLACE ";" "," _mm_list "${_mm_list}")
string(REPLACE "\n" ";" _mm_lines "${_mm_list}")
set(_mm_suites 0)
foreach(_mm_line IN LISTS _mm_lines)
  if(_mm_line MATCHES "^([A-Za-z_][A-Za-z0-9_/]*)\\.( .*)?$")
    set(_mm_suite "${CMAKE_MATCH_1}")
    add_test("${_mm_suite}" "${_mm_exe}" "--gtest_filter=${_mm_suite}.*")
    if(_mm_env)
      set_tests_properties("${_mm_suite}" PROPERTIES ENVIRONMENT "${_mm_env}")
    endif()
    math(EXPR _mm_suites "${_mm_suites} + 1")
  endif()
endforeach()
if(_mm_suites EQUAL 0)
  message(FATAL_ERROR "${_mm_exe} --gtest_list_tests listed no test suite")
endif()
