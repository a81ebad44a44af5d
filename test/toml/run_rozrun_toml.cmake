# SPDX-License-Identifier: Apache-2.0
# rozrun --robot path/to/robot.toml: a robot.toml read at run time.
#   cmake -DROZRUN=<rozrun> -DCTL=<controller dir> -DSRC=<repository> -P run_rozrun_toml.cmake
# A valid file runs (exit 0); a bad one exits 2 with rozgen's messages (the
# .expected file of the fixture, byte for byte); a missing one says so.
execute_process(COMMAND ${ROZRUN} --robot examples/my_arm/robot.toml
                        --controller ${CTL}/constant_velocity.wasm --ticks 100
                WORKING_DIRECTORY ${SRC} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "robot +my_arm \\(manipulator, 100 Hz, 2 commands, 2 states\\)"
   OR NOT out MATCHES "ticks +100 " OR NOT out MATCHES "faults +none")
  message(FATAL_ERROR "rozrun with examples/my_arm/robot.toml: exit ${rc}\n${out}${err}")
endif()

foreach(fixture IN ITEMS limits-order unknown-key toml-syntax)
  set(toml manifests/invalid/${fixture}.toml)
  execute_process(COMMAND ${ROZRUN} --robot ${toml} --controller ${CTL}/constant_velocity.wasm
                          --ticks 100
                  WORKING_DIRECTORY ${SRC} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  file(READ ${SRC}/manifests/invalid/${fixture}.expected want)
  if(fixture STREQUAL "toml-syntax")
    # the same place; the wording of TOML errors is each reader's own
    string(REGEX REPLACE "invalid TOML: .*" "invalid TOML: " want "${want}")
    string(REGEX REPLACE "invalid TOML: .*" "invalid TOML: " err "${err}")
  endif()
  if(NOT rc EQUAL 2 OR NOT err STREQUAL want)
    message(FATAL_ERROR "rozrun --robot ${toml}: exit ${rc} (want 2)\n"
                        "stderr:\n${err}\nwant:\n${want}")
  endif()
endforeach()

execute_process(COMMAND ${ROZRUN} --robot no/such/robot.toml --controller ${CTL}/constant_velocity.wasm
                WORKING_DIRECTORY ${SRC} RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err STREQUAL "no/such/robot.toml: cannot read: No such file or directory\n")
  message(FATAL_ERROR "rozrun --robot no/such/robot.toml: exit ${rc}\n${err}")
endif()
