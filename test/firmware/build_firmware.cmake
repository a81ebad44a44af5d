# SPDX-License-Identifier: Apache-2.0
# cmake -DSOURCE=examples/firmware -DBINARY=dir -DTOOLCHAIN=file
#       -DROZGEN_EXECUTABLE=... -DROZ_WASM3_SDIST=... [-DGENERATOR=...]
#       [-DEXTRA=-DVAR=value] (one more configure argument)
#       -P build_firmware.cmake
# Configures (once) and builds the firmware images for one Cortex-M core.
cmake_minimum_required(VERSION 3.25)

function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGV}\n${out}")
  endif()
endfunction()

set(gen "")
if(GENERATOR)
  set(gen -G ${GENERATOR})
endif()
if(NOT EXISTS ${BINARY}/CMakeCache.txt)
  run(${CMAKE_COMMAND} -S ${SOURCE} -B ${BINARY} ${gen} -DCMAKE_BUILD_TYPE=MinSizeRel
      -DCMAKE_TOOLCHAIN_FILE=${TOOLCHAIN} -DROZ_WERROR=ON
      -DROZGEN_EXECUTABLE=${ROZGEN_EXECUTABLE} -DROZ_WASM3_SDIST=${ROZ_WASM3_SDIST}
      -DROZ_WASM3_SOURCE_DIR=${ROZ_WASM3_SOURCE_DIR} ${EXTRA})
endif()
run(${CMAKE_COMMAND} --build ${BINARY})
message(STATUS "built the firmware images in ${BINARY}")
