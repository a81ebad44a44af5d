# SPDX-License-Identifier: Apache-2.0
# cmake -DROZ_SOURCE_DIR=<roz> -DBINARY=dir -DBOARD=mps2-an386
#       -DROZGEN_EXECUTABLE=... -DROZ_WASM3_SDIST=... [-DGENERATOR=...]
#       [-DEXTRA=-DVAR=value] (one more configure argument)
#       -P build_firmware.cmake
# Configures (once) and builds the firmware images (examples/firmware) for
# one board, with roz from the checkout (add_subdirectory) and the
# template's default build type (MinSizeRel).
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
  run(${CMAKE_COMMAND} -S ${ROZ_SOURCE_DIR}/examples/firmware -B ${BINARY} ${gen}
      -DFW_BOARD=${BOARD} -DROZ_SOURCE_DIR=${ROZ_SOURCE_DIR} -DROZ_WERROR=ON
      -DROZGEN_EXECUTABLE=${ROZGEN_EXECUTABLE} -DROZ_WASM3_SDIST=${ROZ_WASM3_SDIST}
      -DROZ_WASM3_SOURCE_DIR=${ROZ_WASM3_SOURCE_DIR} ${EXTRA})
endif()
run(${CMAKE_COMMAND} --build ${BINARY})
message(STATUS "built the firmware images in ${BINARY}")
