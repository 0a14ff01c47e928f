# CTest's discovery of Catch tests splits a test name at ';' into names that match nothing,
# and those "pass" without running: fail when any test name contains one.
# (Catch2 v2 exits with the number of tests listed, so the status is not checked: the list is.)
execute_process(COMMAND ${TEST_EXECUTABLE} --list-test-names-only OUTPUT_VARIABLE names)
if(NOT names MATCHES "[A-Za-z]")
  message(FATAL_ERROR "${TEST_EXECUTABLE} --list-test-names-only listed no test")
endif()
string(FIND "${names}" ";" at)
if(NOT at EQUAL -1)
  string(REPLACE ";" "<SEMICOLON>" shown "${names}")
  message(FATAL_ERROR "a test name contains ';' (CTest would split it and run nothing):\n${shown}")
endif()
# A name that begins with '-' is read by Catch as an option (--out is its reporter's output
# file): the test then runs the whole suite under that one name.
if(names MATCHES "(^|\n)-")
  message(FATAL_ERROR "a test name begins with '-' (Catch reads it as an option and runs every test):\n${names}")
endif()
string(REGEX MATCHALL "\n" lines "${names}")
list(LENGTH lines count)
message(STATUS "${count} test names, none with ';' or a leading '-'")
