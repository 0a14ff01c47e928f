# Installs the hbfriction build tree into a fresh prefix, then configures, builds and runs a
# downstream project (find_package(hbfriction)) against it. Used by the tests
# install_and_find_package (tests/package) and embed_example (examples/embed).
# Variables:
#   BUILD_DIR     hbfriction build tree
#   SOURCE_DIR    the downstream project
#   EXECUTABLE    its program to run (built in its build tree's top folder)
#   WORK_DIR      scratch directory (wiped first, and at the end on success)
#   CXX_COMPILER  compiler of the hbfriction build (the downstream project uses the same)
#   CXX_FLAGS     optional compile flags for the downstream project (e.g. warnings as errors)
foreach(var BUILD_DIR SOURCE_DIR EXECUTABLE WORK_DIR CXX_COMPILER)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "install_and_run.cmake: ${var} is not set")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGN}\n${out}")
  endif()
  message(STATUS "${out}")
endfunction()
run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")
if(NOT EXISTS "${prefix}/bin/hbf")
  message(FATAL_ERROR "hbf was not installed into ${prefix}/bin")
endif()
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}" -B "${WORK_DIR}/build" -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX_COMPILER} "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run("${WORK_DIR}/build/${EXECUTABLE}")
file(REMOVE_RECURSE "${WORK_DIR}")
