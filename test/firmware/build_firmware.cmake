# SPDX-License-Identifier: Apache-2.0
# cmake -DROZ_SOURCE_DIR=<roz> -DBINARY=dir -DBOARD=mps2-an386
#       -DROZGEN_EXECUTABLE=... -DROZ_WASM3_SDIST=... [-DGENERATOR=...]
#       [-DEXTRA=-DVAR=value] (one more configure argument)
#       -P build_firmware.cmake
# Configures (once) and builds the firmware images (examples/firmware) for
# one board, with roz from the checkout (add_subdirectory) and the
# template's default build type (MinSizeRel).
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/../checks.cmake)
generator_args(gen)
if(NOT EXISTS ${BINARY}/CMakeCache.txt)
  run(${CMAKE_COMMAND} -S ${ROZ_SOURCE_DIR}/examples/firmware -B ${BINARY} ${gen}
      -DFW_BOARD=${BOARD} -DROZ_SOURCE_DIR=${ROZ_SOURCE_DIR} -DROZ_WERROR=ON
      -DROZGEN_EXECUTABLE=${ROZGEN_EXECUTABLE} -DROZ_WASM3_SDIST=${ROZ_WASM3_SDIST}
      -DROZ_WASM3_SOURCE_DIR=${ROZ_WASM3_SOURCE_DIR} ${EXTRA})
endif()
run(${CMAKE_COMMAND} --build ${BINARY})
message(STATUS "built the firmware images in ${BINARY}")
