# Installs the build tree into a fresh prefix, then configures, builds and runs the consumer
# project against it. Variables: BUILD_DIR (hbfriction build tree), SOURCE_DIR (this folder),
# WORK_DIR (scratch directory, wiped first).
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
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}" -B "${WORK_DIR}/build" -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run("${WORK_DIR}/build/consumer")
if(NOT EXISTS "${prefix}/bin/hbf")
  message(FATAL_ERROR "hbf was not installed into ${prefix}/bin")
endif()
file(REMOVE_RECURSE "${WORK_DIR}")
