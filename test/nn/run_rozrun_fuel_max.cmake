# SPDX-License-Identifier: Apache-2.0
# rozrun --fuel-max: fuel_hungry.wasm declares 500,000 fuel units a tick, above
# the UR5's default ceiling (400,000: ROZ_CFG_FUEL_MAX_PER_SECOND / 100 Hz).
# Without the flag it is refused at load (exit 2) naming both figures; with
# --fuel-max 500000 (or off) it runs, granted its declaration, with no fault.
# cmake -DROZRUN=... -DWASM=<fuel_hungry.wasm> -P
include(${CMAKE_CURRENT_LIST_DIR}/../checks.cmake)
set(RUN --robot;ur5;--port;loopback;--controller;${WASM};--ticks;200)

# without the flag: refused, naming the ceiling and the declaration
expect_error("${RUN}" "fuel_per_tick_max 400000")
expect_error("${RUN}" "500000")

foreach(max IN ITEMS 500000 off)
  execute_process(COMMAND ${ROZRUN} ${RUN} --fuel-max ${max} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "--fuel-max ${max}: exit ${rc}, expected 0\n${out}${err}")
  endif()
  foreach(want "faults                 none" "budget 500000" "ticks                  200")
    expect_in("${out}" "${want}" "--fuel-max ${max}: the summary")
  endforeach()
  # it needed more than the default budget of 100,000 on every tick
  if(NOT out MATCHES "run max ([0-9]+)")
    message(FATAL_ERROR "--fuel-max ${max}: no run max in the summary:\n${out}")
  endif()
  if(CMAKE_MATCH_1 LESS_EQUAL 100000 OR CMAKE_MATCH_1 GREATER 500000)
    message(FATAL_ERROR "--fuel-max ${max}: run max ${CMAKE_MATCH_1}, expected 100001..500000")
  endif()
endforeach()

# a ceiling below the declaration, and a malformed one, are refused
expect_error("${RUN};--fuel-max;450000" "fuel_per_tick_max 450000")
expect_error("${RUN};--fuel-max;0" "--fuel-max must be in 1..")
