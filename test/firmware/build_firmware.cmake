# SPDX-License-Identifier: Apache-2.0
# cmake -DROZ_SOURCE_DIR=<roz> -DBINARY=dir -DBOARD=mps2-an386
#       -DROZGEN_EXECUTABLE=... -DROZ_WASM3_SDIST=... [-DGENERATOR=...]
#       [-DEXTRA=-DVAR=value] (one more configure argument)
#       -P build_firmware.cmake
# Configures (once, and again when the options above change) and builds
# the firmware images (examples/firmware) for one board, with roz from the
# checkout (add_subdirectory) and the template's default build type
# (MinSizeRel).
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/../checks.cmake)
generator_args(gen)
set(options -DFW_BOARD=${BOARD} -DROZ_SOURCE_DIR=${ROZ_SOURCE_DIR} -DROZ_WERROR=ON
    -DROZGEN_EXECUTABLE=${ROZGEN_EXECUTABLE} -DROZ_WASM3_SDIST=${ROZ_WASM3_SDIST}
    -DROZ_WASM3_SOURCE_DIR=${ROZ_WASM3_SOURCE_DIR} ${EXTRA})
# configured again, from a fresh cache, when these options are not the ones
# it was configured with (an option dropped must not linger in the cache; a
# tree configured before a new option, such as rozaot's for the AOT images,
# would build without what it gives)
string(JOIN "\n" want ${gen} ${options})
set(stamp ${BINARY}/roz_fw_options.txt)
set(have "")
if(EXISTS ${stamp})
  file(READ ${stamp} have)
endif()
if(NOT EXISTS ${BINARY}/CMakeCache.txt OR NOT have STREQUAL want)
  set(fresh "")
  if(EXISTS ${BINARY}/CMakeCache.txt)
    set(fresh --fresh)
  endif()
  run(${CMAKE_COMMAND} ${fresh} -S ${ROZ_SOURCE_DIR}/examples/firmware -B ${BINARY} ${gen}
      ${options})
  file(WRITE ${stamp} "${want}")
endif()
run(${CMAKE_COMMAND} --build ${BINARY})
message(STATUS "built the firmware images in ${BINARY}")
