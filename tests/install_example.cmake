# Installs glint into a scratch prefix, builds docs/example against it with
# find_package(glint), runs it and checks that it wrote its image.
file(REMOVE_RECURSE ${WORK_DIR})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/docs/example -B ${WORK_DIR}/build -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/glint_example ${WORK_DIR}/example.png)
if(NOT EXISTS ${WORK_DIR}/example.png)
  message(FATAL_ERROR "the example wrote no image")
endif()
# Another compiler links the same installed library (no LTO bytecode alone).
if(CLANGXX)
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/docs/example -B ${WORK_DIR}/build-clang -G ${GENERATOR}
      -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CLANGXX})
  run(${CMAKE_COMMAND} --build ${WORK_DIR}/build-clang)
  run(${WORK_DIR}/build-clang/glint_example ${WORK_DIR}/example-clang.png)
  if(NOT EXISTS ${WORK_DIR}/example-clang.png)
    message(FATAL_ERROR "the example built with ${CLANGXX} wrote no image")
  endif()
  message(STATUS "the example links and runs with ${CLANGXX} too")
else()
  message(STATUS "no clang++: the example is built with one compiler only")
endif()
# The installed files and the example: no RUNPATH entry read against the
# working directory (see check_runpath.py).
if(PYTHON)
  run(${PYTHON} ${CHECK_RUNPATH} ${WORK_DIR})
endif()
