# ctest guard: the ctest entries of hemirad_tests must be exactly doctest's own test cases. A case
# name that CMake splits (a ';') becomes entries that match no case; doctest's count catches both ways.
# Usage: cmake -DTESTS=<hemirad_tests> -DBUILD_DIR=<tests build dir> -DSELF=<this test's name> -P check_test_count.cmake
execute_process(COMMAND "${TESTS}" --count OUTPUT_VARIABLE countOutput RESULT_VARIABLE countStatus)
if(NOT countStatus EQUAL 0 OR NOT countOutput MATCHES "current filters: ([0-9]+)")
  message(FATAL_ERROR "hemirad_tests --count failed (${countStatus}): ${countOutput}")
endif()
set(doctestCases ${CMAKE_MATCH_1})

execute_process(COMMAND "${CMAKE_CTEST_COMMAND}" -N WORKING_DIRECTORY "${BUILD_DIR}"
                OUTPUT_VARIABLE listing RESULT_VARIABLE listStatus)
if(NOT listStatus EQUAL 0)
  message(FATAL_ERROR "ctest -N failed (${listStatus}): ${listing}")
endif()
string(REGEX MATCHALL "Test +#[0-9]+: [^\n]*" entries "${listing}")
set(ctestEntries 0)
foreach(entry IN LISTS entries)
  if(NOT entry MATCHES ": ${SELF}$")
    math(EXPR ctestEntries "${ctestEntries} + 1")
  endif()
endforeach()

if(NOT ctestEntries EQUAL doctestCases)
  message(FATAL_ERROR "ctest has ${ctestEntries} hemirad_tests entries but doctest has ${doctestCases} test cases: "
                      "a test case name with ';' (or another character CMake splits on) does not run")
endif()
message(STATUS "${ctestEntries} ctest entries = ${doctestCases} doctest test cases")
