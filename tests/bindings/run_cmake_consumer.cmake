# cmake -DPREFIX=... -DSOURCE_DIR=... -DWORK_DIR=... -DFIXTURES=... -P run_cmake_consumer.cmake
# Configures and builds tests/bindings/cmake_consumer against the installed package, then runs
# its C program.
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR} -G Ninja
  -DCMAKE_PREFIX_PATH=${PREFIX} -DFIXTURES=${FIXTURES} -DCMAKE_BUILD_TYPE=Release
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the consumer failed")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building the consumer failed")
endif()
execute_process(COMMAND ${WORK_DIR}/version RESULT_VARIABLE rc OUTPUT_VARIABLE out)
message(STATUS "${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "^ppohdem [0-9]")
  message(FATAL_ERROR "the consumer's C program failed")
endif()
