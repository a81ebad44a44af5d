# SPDX-License-Identifier: Apache-2.0
# rozrun on a robot that falls, end to end in MuJoCo's simulated time: the
# G1 on the example balancing stand, pushed over at 3 s (400 N forward for
# 0.1 s at the pelvis). The built-in manifest's fall rule latches FALL: the
# summary says "faults latched: fall" with the tilt, --summary-json lists
# it, the trace marks the tick, and rozrun exits 1. A stumble (112 N) ends
# with no fault and exit 0.
#   cmake -DROZRUN=<rozrun> -DCTL=<controller dir> -DOUT=<work dir> -P run_rozrun_fall.cmake
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})

include(${CMAKE_CURRENT_LIST_DIR}/checks.cmake)

function(run name push)
  execute_process(COMMAND ${ROZRUN} --robot unitree_g1 --port mujoco --ticks 2500
                          --controller ${CTL}/g1_stand.wasm --param push=${push}
                          --summary-json ${OUT}/${name}.json --trace ${OUT}/${name}.csv
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(${name}_rc ${rc} PARENT_SCOPE)
  set(${name}_out "${out}${err}" PARENT_SCOPE)
endfunction()

run(fell "400,0,0@pelvis@1500:1550")
if(NOT fell_rc EQUAL 1)
  message(FATAL_ERROR "pushed over: exit ${fell_rc}, expected 1\n${fell_out}")
endif()
expect_in("${fell_out}" "latched: fall (first: fall: the base tilted" "the summary")
file(READ ${OUT}/fell.json json)
string(JSON latched GET "${json}" faults latched)
if(NOT latched STREQUAL "[ \"fall\" ]")
  message(FATAL_ERROR "--summary-json: faults latched ${latched}, expected [\"fall\"]")
endif()
expect_in("${json}" "fall: the base tilted" "--summary-json")
file(READ ${OUT}/fell.csv trace)
expect_in("${trace}" "fault:fall" "the trace")

run(stumbled "112,0,0@pelvis@1500:1550")
if(NOT stumbled_rc EQUAL 0)
  message(FATAL_ERROR "a stumble: exit ${stumbled_rc}, expected 0\n${stumbled_out}")
endif()
expect_in("${stumbled_out}" "faults                 none" "the summary")
