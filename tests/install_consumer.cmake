# Installs the built project into a scratch prefix, then configures, builds and runs examples/
# as a separate project that only knows that prefix. Run by ctest (tests/CMakeLists.txt).
file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")

function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGV}\n${out}")
  endif()
endfunction()

run(${CMAKE_COMMAND} --install "${BINARY_DIR}" --prefix "${prefix}" --config "${CONFIG}")
# A sanitized library needs a sanitized consumer (the runtime must be linked first).
set(flags "")
if(SANITIZE)
  set(flags -DCMAKE_CXX_FLAGS=-fsanitize=${SANITIZE} -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=${SANITIZE})
endif()
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/examples" -B "${WORK_DIR}/build"
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=${CONFIG} ${flags})
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build" --parallel 2)
# The example writes a box, reads it back and checks it: exit 0 means a valid closed mesh.
run("${WORK_DIR}/build/01_check_mesh" "${WORK_DIR}/box.stl")
# The installed command line runs from the prefix alone (RPATH $ORIGIN/../lib).
run("${prefix}/bin/tpmsfill" check "${WORK_DIR}/box.stl")
message(STATUS "consumer project built and ran against ${prefix}")
