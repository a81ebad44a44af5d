# SPDX-License-Identifier: Apache-2.0
# cmake -DWORK=dir -DSCRIPT=<roz>/test/firmware/build_firmware.cmake -P test_build_firmware.cmake
# build_firmware.cmake configures a board's tree again when its options
# change, from a fresh cache (an option dropped does not linger), and not
# when they do not: checked on a stand-in for examples/firmware that only
# configures, so it takes a second.
cmake_minimum_required(VERSION 3.25)

file(REMOVE_RECURSE ${WORK})
file(WRITE ${WORK}/src/examples/firmware/CMakeLists.txt
     "cmake_minimum_required(VERSION 3.25)\nproject(stand_in NONE)\n"
     "file(APPEND \"${WORK}/configures\" x)\nadd_custom_target(images ALL)\n")
set(tree ${WORK}/tree)

# runs the script with these options; returns the cache's line for VAR
# (empty: absent) and whether the tree was configured this time (the
# stand-in counts its configures in a file of its own)
function(build var out_value out_configured)
  set(n0 "")
  if(EXISTS ${WORK}/configures)
    file(READ ${WORK}/configures n0)
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -DROZ_SOURCE_DIR=${WORK}/src -DBINARY=${tree}
                          -DBOARD=mps2-an386 -DGENERATOR=${CMAKE_GENERATOR} ${ARGN}
                          -P ${SCRIPT}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "build_firmware.cmake failed (${rc}):\n${log}")
  endif()
  file(READ ${WORK}/configures n1)
  if(n1 STREQUAL n0)
    set(${out_configured} 0 PARENT_SCOPE)
  else()
    set(${out_configured} 1 PARENT_SCOPE)
  endif()
  file(STRINGS ${tree}/CMakeCache.txt line REGEX "^${var}:")
  set(${out_value} "${line}" PARENT_SCOPE)
endfunction()

function(expect what got want)
  if(NOT "${got}" STREQUAL "${want}")
    message(FATAL_ERROR "${what}: got '${got}', want '${want}'")
  endif()
endfunction()

build(ROZ_FW_ROZAOT v c)
expect("first run configures" "${c}" 1)
expect("no option yet" "${v}" "")
build(ROZ_FW_ROZAOT v c)
expect("the same options: not configured again" "${c}" 0)
build(ROZ_FW_ROZAOT v c -DEXTRA=-DROZ_FW_ROZAOT=/x/rozaot)
expect("an option added: configured again" "${c}" 1)
expect("the option in the cache" "${v}" "ROZ_FW_ROZAOT:UNINITIALIZED=/x/rozaot")
build(ROZ_FW_ROZAOT v c -DEXTRA=-DROZ_FW_ROZAOT=/x/rozaot)
expect("the same again: not configured" "${c}" 0)
build(ROZ_FW_ROZAOT v c)
expect("the option dropped: configured again" "${c}" 1)
expect("the dropped option gone from the cache" "${v}" "")
message(STATUS "build_firmware.cmake configures again exactly when its options change")
