# SPDX-License-Identifier: Apache-2.0
# cmake -DMODE=find_package|add_subdirectory -DROZ_SOURCE_DIR=... -DROZ_BINARY_DIR=...
#       -DWORK_DIR=... -DROZGEN_EXECUTABLE=... [-DGENERATOR=...] -P run_consumer.cmake
function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGV}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/src)
file(COPY ${CMAKE_CURRENT_LIST_DIR}/CMakeLists.txt ${CMAKE_CURRENT_LIST_DIR}/main.c
     DESTINATION ${WORK_DIR}/src)
file(COPY ${CMAKE_CURRENT_LIST_DIR}/small_config.h DESTINATION ${WORK_DIR}/src)
file(COPY_FILE ${ROZ_SOURCE_DIR}/examples/my_arm/robot.toml ${WORK_DIR}/src/robot.toml)
file(COPY_FILE ${ROZ_SOURCE_DIR}/manifests/unitree_g1.toml ${WORK_DIR}/src/big_robot.toml)

set(gen "")
if(GENERATOR)
  set(gen -G ${GENERATOR})
endif()
set(common -S ${WORK_DIR}/src -B ${WORK_DIR}/build ${gen} -DROZGEN_EXECUTABLE=${ROZGEN_EXECUTABLE})
if(MODE STREQUAL "find_package")
  run(${CMAKE_COMMAND} --install ${ROZ_BINARY_DIR} --prefix ${WORK_DIR}/prefix)
  run(${CMAKE_COMMAND} ${common} -DROZ_CONSUMER_MODE=find_package
      -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix)
elseif(MODE STREQUAL "add_subdirectory" OR MODE STREQUAL "small_config")
  run(${CMAKE_COMMAND} ${common} -DROZ_CONSUMER_MODE=${MODE}
      -DROZ_SOURCE_DIR=${ROZ_SOURCE_DIR} -DROZ_WASM3_SDIST=${ROZ_WASM3_SDIST}
      -DROZ_WASM3_SOURCE_DIR=${ROZ_WASM3_SOURCE_DIR})
else()
  message(FATAL_ERROR "MODE must be find_package, add_subdirectory or small_config")
endif()
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/consumer)
if(MODE STREQUAL "small_config")
  # 145 commands in a 16-command build: the generated table must not compile
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build --target too_big
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0 OR NOT "${out}${err}" MATCHES "more than ROZ_CFG_MAX_COMMANDS")
    message(FATAL_ERROR "a 145-command manifest compiled against ROZ_CFG_MAX_COMMANDS 16:\n${out}${err}")
  endif()
  message(STATUS "too_big refused at compile time, as it must be")
endif()
