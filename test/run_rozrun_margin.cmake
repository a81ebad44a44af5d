# SPDX-License-Identifier: Apache-2.0
# rozrun and per-channel limit margins, end to end.
#   cmake -DROZRUN=<rozrun> -DCTL=<controller dir> -DSRC=<repository> -P run_rozrun_margin.cmake
# A gripper with limits [0, 0.08] m (test/vectors/good/gripper.toml, default
# margin) driven open by constant_velocity for 4 s: it gets to 0.076 m (roz's
# old 0.05 margin stopped it at 0.03 m), and the summary warns that the
# controller kept pushing it against that limit, naming the channel, the
# limit and the margin. Its wrist, moving freely, gets no warning; nor does a
# run too short to reach the limit, nor the UR5's sine.
set(robot test/vectors/good/gripper.toml)
execute_process(COMMAND ${ROZRUN} --robot ${robot} --controller ${CTL}/constant_velocity.wasm
                        --ticks 400
                WORKING_DIRECTORY ${SRC} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(want "warning +gripper/velocity held back at a position limit for 2[0-9][0-9] ticks in a row \\(2\\.[0-9][0-9] s\\), 2[0-9][0-9] of 400 ticks in all: gripper/position at 0\\.076 m, limits \\[0, 0\\.08\\] m less a margin of 0\\.004 m\n")
if(NOT rc EQUAL 0 OR NOT out MATCHES "${want}" OR out MATCHES "wrist/velocity held"
   OR NOT out MATCHES "faults +none")
  message(FATAL_ERROR "rozrun --robot ${robot}, 400 ticks: exit ${rc}, want 0 and\n${want}\n"
                      "got:\n${out}${err}")
endif()

# 100 ticks: the gripper (0.02 m/s from 0.04 m) is still on its way
execute_process(COMMAND ${ROZRUN} --robot ${robot} --controller ${CTL}/constant_velocity.wasm
                        --ticks 100
                WORKING_DIRECTORY ${SRC} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR out MATCHES "warning" OR NOT out MATCHES "limit stops +0\n")
  message(FATAL_ERROR "rozrun --robot ${robot}, 100 ticks: exit ${rc}\n${out}${err}")
endif()

execute_process(COMMAND ${ROZRUN} --robot ur5 --controller ${CTL}/sine.wasm --ticks 500
                WORKING_DIRECTORY ${SRC} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR out MATCHES "held back")
  message(FATAL_ERROR "rozrun --robot ur5 sine: exit ${rc}\n${out}${err}")
endif()
