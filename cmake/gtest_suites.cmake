# Run after a test binary is linked (tests/CMakeLists.txt, talkinghead_discover_tests): lists the binary's
# GoogleTest cases and writes CTEST_FILE, which registers one CTest test per test suite (every case of suite S runs
# in one process, --gtest_filter=S.*) and sets LIST_VAR to their names.
#
#   cmake -D EXECUTABLE=... -D WORKING_DIRECTORY=... -D CTEST_FILE=... -D LIST_VAR=... -D TIMEOUT=... -P gtest_suites.cmake
#
# A suite rather than a case per process: a sanitized binary that links the engine loads some two hundred shared
# libraries and spends most of a second starting and checking for leaks at exit, longer than most cases run.
execute_process(COMMAND "${EXECUTABLE}" --gtest_list_tests WORKING_DIRECTORY "${WORKING_DIRECTORY}"
                TIMEOUT ${TIMEOUT} OUTPUT_VARIABLE output RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${EXECUTABLE} --gtest_list_tests failed (${result}):\n${output}")
endif()
string(REPLACE ";" "" output "${output}")
string(REPLACE "\n" ";" lines "${output}")
set(suites "")
foreach(line IN LISTS lines)
  # A suite's line starts in the first column and ends with '.' (then, for typed tests, a comment).
  if(line MATCHES "^([^ #][^ ]*)\\.( *#.*)?$")
    list(APPEND suites "${CMAKE_MATCH_1}")
  endif()
endforeach()
list(REMOVE_DUPLICATES suites)
if(NOT suites)
  message(FATAL_ERROR "${EXECUTABLE} lists no tests")
endif()
set(script "set(${LIST_VAR} \"\")\n")
foreach(suite IN LISTS suites)
  string(APPEND script "add_test([==[${suite}]==] [==[${EXECUTABLE}]==] [==[--gtest_filter=${suite}.*]==])\n"
         "set_tests_properties([==[${suite}]==] PROPERTIES WORKING_DIRECTORY [==[${WORKING_DIRECTORY}]==])\n"
         "list(APPEND ${LIST_VAR} [==[${suite}]==])\n")
endforeach()
file(WRITE "${CTEST_FILE}" "${script}")
