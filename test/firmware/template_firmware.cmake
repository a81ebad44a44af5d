# SPDX-License-Identifier: Apache-2.0
# cmake -DROZ_SOURCE_DIR=<roz> -DBOARD=netduinoplus2 -DQEMU=qemu-system-arm
#       -DHOST=roz_fw_host -DCONTROLLERS=<host build>/examples/controllers
#       -DROZGEN_EXECUTABLE=... -DROZ_WASM3_SDIST=... [-DGENERATOR=...]
#       -P template_firmware.cmake
#
# The firmware template as a user takes it: examples/firmware copied to a
# temporary folder outside the trees, with copies of the UR5's robot.toml and
# the two controllers the host build made; roz built for the board's CPU with
# the template's configuration (roz_options.cmake, ROZ_CONFIG_HEADER) and
# installed into a prefix there; the template configured with only that
# prefix (find_package(roz), the toolchain file from the package, no build
# type: it must default to MinSizeRel), built for BOARD, and each image
# booted in QEMU and checked against the host (run_firmware.cmake). The
# folder is removed when the test passes, kept for a look when it fails.
cmake_minimum_required(VERSION 3.25)

include(${CMAKE_CURRENT_LIST_DIR}/../checks.cmake)
generator_args(gen)
temp_folder(work fw_template)
keep_apart(checkout ${work} ${ROZ_SOURCE_DIR})

# the user's copy: the template, their robot and their controllers
file(MAKE_DIRECTORY ${work}/manifests ${work}/controllers)
file(COPY ${ROZ_SOURCE_DIR}/examples/firmware/ DESTINATION ${work}/fw)
file(COPY_FILE ${ROZ_SOURCE_DIR}/manifests/ur5.toml ${work}/manifests/ur5.toml)
foreach(wasm IN ITEMS sine_wat bad_infinite_loop)
  file(COPY_FILE ${CONTROLLERS}/${wasm}.wasm ${work}/controllers/${wasm}.wasm)
endforeach()

# roz for this firmware: the board's CPU, the template's sizes, installed
include(${work}/fw/boards/${BOARD}.cmake)
run(${CMAKE_COMMAND} -S ${ROZ_SOURCE_DIR} -B ${work}/roz-build ${gen}
    -C ${work}/fw/roz_options.cmake
    -DCMAKE_TOOLCHAIN_FILE=${ROZ_SOURCE_DIR}/cmake/toolchains/${FW_BOARD_CPU}.cmake
    -DCMAKE_BUILD_TYPE=MinSizeRel -DROZ_CONFIG_HEADER=${work}/fw/config/ur5_m4f.h
    -DROZ_WERROR=ON -DROZ_BUILD_TESTS=OFF -DROZ_BUILD_EXAMPLES=OFF -DROZ_BUILD_BENCH=OFF
    -DROZ_BUILD_TOOLS=OFF -DROZ_INSTALL=ON -DROZGEN_EXECUTABLE=${ROZGEN_EXECUTABLE}
    -DROZ_WASM3_SDIST=${ROZ_WASM3_SDIST} -DROZ_WASM3_SOURCE_DIR=${ROZ_WASM3_SOURCE_DIR})
run(${CMAKE_COMMAND} --build ${work}/roz-build)
run(${CMAKE_COMMAND} --install ${work}/roz-build --prefix ${work}/prefix)
file(REMOVE_RECURSE ${work}/roz-build)

# the template, from the prefix alone
run(${CMAKE_COMMAND} -S ${work}/fw -B ${work}/fw-build ${gen} -DFW_BOARD=${BOARD}
    -DCMAKE_PREFIX_PATH=${work}/prefix -DROZGEN_EXECUTABLE=${ROZGEN_EXECUTABLE}
    -DFW_MANIFESTS=${work}/manifests -DFW_CONTROLLERS=${work}/controllers)
file(STRINGS ${work}/fw-build/CMakeCache.txt cache
     REGEX "^(CMAKE_BUILD_TYPE|CMAKE_TOOLCHAIN_FILE|roz_DIR):")
set(want "CMAKE_BUILD_TYPE:STRING=MinSizeRel"
    "CMAKE_TOOLCHAIN_FILE:FILEPATH=${work}/prefix/lib/cmake/roz/toolchains/${FW_BOARD_CPU}.cmake"
    "roz_DIR:PATH=${work}/prefix/lib/cmake/roz")
list(SORT cache)
list(SORT want)
if(NOT cache STREQUAL want)
  message(FATAL_ERROR "the template did not build from the prefix, size-optimised:\n"
                      "  got:  ${cache}\n  want: ${want}")
endif()
run(${CMAKE_COMMAND} --build ${work}/fw-build)

foreach(image IN ITEMS ur5_sine ur5_hostile)
  set(fault "")
  if(image STREQUAL "ur5_hostile")
    set(fault "fuel exhausted at tick 150: 100002 units, budget 100000")
  endif()
  set(wasm sine_wat.wasm)
  if(image STREQUAL "ur5_hostile")
    set(wasm bad_infinite_loop.wasm)
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -DQEMU=${QEMU} -DMACHINE=${FW_BOARD_QEMU}
                          -DIMAGE=${work}/fw-build/roz_fw_${image}.elf -DHOST=${HOST} -DROBOT=ur5
                          -DWASM=${work}/controllers/${wasm} "-DFAULT=${fault}"
                          -P ${CMAKE_CURRENT_LIST_DIR}/run_firmware.cmake
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  message(STATUS "${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${image} on ${BOARD}, built from the template out of the tree: failed "
                        "(kept in ${work})")
  endif()
endforeach()
file(REMOVE_RECURSE ${work})
message(STATUS "the template, copied out and built against an installed roz, runs on ${BOARD} "
               "as the host does")
