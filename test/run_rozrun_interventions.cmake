# SPDX-License-Identifier: Apache-2.0
# rozrun's scheduled interventions (--estop-at, --estop-release-at,
# --clear-at, --swap-at) end to end, in simulated time, read back from the
# trace's faults and events columns: an e-stop latches and stays latched
# through a clear while pressed, and is cleared after release; a swap
# shows at its tick and the new controller starts at its own tick 0; a
# refused swap leaves the old controller running, row for row; a clear
# rebuilds a controller that trapped; the same options give the same trace,
# byte for byte. Optionally plots a trace with events.
#   cmake -DROZRUN=<rozrun> -DCTL=<controller dir> -DOUT=<work dir>
#         [-DPYTHON=<python> -DPLOT=<tools/plot_trace.py>] -P run_rozrun_interventions.cmake
cmake_minimum_required(VERSION 3.25) # quoted arguments of if() are strings (CMP0054)
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
# first: its run() gives way to this script's own below
include(${CMAKE_CURRENT_LIST_DIR}/checks.cmake)

# Runs rozrun with a trace; sets <name>_rc, <name>_out, <name>_err and
# <name>_csv (the trace's path) in the caller.
function(run name)
  execute_process(COMMAND ${ROZRUN} --robot ur5 ${ARGN} --trace ${OUT}/${name}.csv
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(${name}_rc ${rc} PARENT_SCOPE)
  set(${name}_out "${out}" PARENT_SCOPE)
  set(${name}_err "${err}" PARENT_SCOPE)
  set(${name}_csv ${OUT}/${name}.csv PARENT_SCOPE)
endfunction()

# Row <tick> of a trace: <prefix>_row (the line), <prefix>_faults,
# <prefix>_events, <prefix>_target0 and <prefix>_applied0 (command 0's;
# ur5 has 6 commands: target columns 2..7, applied 8..13).
function(row csv tick prefix)
  file(STRINGS ${csv} lines)
  math(EXPR at "${tick} + 1")
  list(GET lines ${at} line)
  if(NOT line MATCHES "^${tick},")
    message(FATAL_ERROR "${csv}: row ${tick} is \"${line}\"")
  endif()
  if(NOT line MATCHES ",([0-9]+),([^,]*)$")
    message(FATAL_ERROR "${csv}: row ${tick} has no faults and events columns: ${line}")
  endif()
  set(${prefix}_faults ${CMAKE_MATCH_1} PARENT_SCOPE)
  set(${prefix}_events "${CMAKE_MATCH_2}" PARENT_SCOPE)
  string(REPLACE "," ";" fields "${line}")
  list(GET fields 2 target0)
  list(GET fields 8 applied0)
  list(SUBLIST fields 2 6 targets)
  list(SUBLIST fields 8 6 applied)
  set(${prefix}_row "${line}" PARENT_SCOPE)
  set(${prefix}_target0 ${target0} PARENT_SCOPE)
  set(${prefix}_applied0 ${applied0} PARENT_SCOPE)
  set(${prefix}_targets "${targets}" PARENT_SCOPE)
  set(${prefix}_applied "${applied}" PARENT_SCOPE)
endfunction()

# ---- 1. e-stop: latched at its tick, held through a clear while pressed,
#         cleared after the release; the run ends with nothing latched
run(estop --controller ${CTL}/sine.wasm --ticks 300 --estop-at 100 --clear-at 120
          --estop-release-at 150 --clear-at 200)
expect("e-stop run: exit ${estop_rc}, expected 0\n${estop_out}${estop_err}" estop_rc EQUAL 0)
expect_in("${estop_out}" "faults                 none latched at the end (cleared during the run: e-stop 1 time)" "e-stop summary")
expect_in("${estop_out}" "e-stop 1 pressed, 1 released; clears 2 (1 while pressed, 0 refused)" "e-stop summary")
expect_in("${estop_err}" "tick 120: clear: the e-stop input is still pressed, so e-stop stays latched" "e-stop stderr")
expect_in("${estop_err}" "tick 200: clear: e-stop cleared" "e-stop stderr")
file(STRINGS ${estop_csv} header LIMIT_COUNT 1)
expect("trace header: ${header}" header MATCHES ",state:wrist_3_joint/velocity,faults,events$")
row(${estop_csv} 99 r)
expect("row 99 before the press: ${r_row}" r_faults EQUAL 0 AND r_events MATCHES "^$")
row(${estop_csv} 100 r)
expect("row 100, the press: ${r_row}" r_faults EQUAL 8 AND r_events STREQUAL "estop fault:e-stop")
foreach(v IN LISTS r_applied) # an e-stop sends the safe defaults at once
  expect("row 100 applies ${v}, expected the safe default 0: ${r_row}" v STREQUAL "0")
endforeach()
row(${estop_csv} 120 r)
expect("row 120, a clear while pressed: ${r_row}" r_faults EQUAL 8 AND r_events STREQUAL "clear-while-pressed")
row(${estop_csv} 150 r)
expect("row 150, the release: ${r_row}" r_faults EQUAL 8 AND r_events STREQUAL "estop-release")
row(${estop_csv} 199 r)
expect("row 199, released but not cleared: ${r_row}" r_faults EQUAL 8 AND r_applied0 STREQUAL "0")
row(${estop_csv} 200 r)
expect("row 200, the clear: ${r_row}" r_faults EQUAL 0 AND r_events STREQUAL "clear cleared:e-stop")
row(${estop_csv} 201 r)
expect("row 201, the controller drives again: ${r_row}" r_faults EQUAL 0 AND NOT r_applied0 STREQUAL "0")

# an e-stop never released stays latched through every clear: exit 1
run(held --controller ${CTL}/sine.wasm --ticks 200 --estop-at 50 --clear-at 100 --clear-at 150)
expect("held e-stop: exit ${held_rc}, expected 1\n${held_out}${held_err}" held_rc EQUAL 1)
expect_in("${held_out}" "latched: e-stop" "held e-stop summary")
row(${held_csv} 150 r)
expect("row 150 of the held e-stop: ${r_row}" r_faults EQUAL 8 AND r_events STREQUAL "clear-while-pressed")
row(${held_csv} 199 r)
expect("row 199 of the held e-stop: ${r_row}" r_faults EQUAL 8)

# ---- 2. swaps: the new controller drives from its tick, starting at its own
#         tick 0 (sine_wat is sine's bit-for-bit twin: row 100 repeats row 0)
run(swap --controller ${CTL}/sine.wasm --ticks 300 --swap-at 100:${CTL}/sine_wat.wasm
         --swap-at 200:${CTL}/constant_velocity.wasm)
expect("swap run: exit ${swap_rc}\n${swap_out}${swap_err}" swap_rc EQUAL 0)
expect_in("${swap_out}" "swaps 2, 0 refused" "swap summary")
expect_in("${swap_err}" "tick 100: swap: ${CTL}/sine_wat.wasm verified" "swap stderr")
expect_in("${swap_err}" "it drives from tick 100" "swap stderr")
row(${swap_csv} 0 r0)
row(${swap_csv} 99 r)
expect("row 99 runs sine at its tick 99: ${r_row}" NOT r_targets STREQUAL r0_targets AND r_events MATCHES "^$")
row(${swap_csv} 100 r)
expect("row 100, the swap: ${r_row}" r_events STREQUAL "swap" AND r_faults EQUAL 0)
expect("row 100's targets are row 0's: ${r_targets} vs ${r0_targets}" r_targets STREQUAL r0_targets)
row(${swap_csv} 200 r)
# constant_velocity: a fifth of each upper limit (UR5: 3.14 rad/s)
expect("row 200, constant_velocity: ${r_row}" r_events STREQUAL "swap" AND r_target0 STREQUAL "0.628")

# ---- 3. refused swaps (one fails verification, one fails to load) leave the
#         old controller running: the trace is a plain run's, row for row,
#         but for the two events
run(plain --controller ${CTL}/sine.wasm --ticks 300)
run(refused --controller ${CTL}/sine.wasm --ticks 300
            --swap-at 150:${CTL}/bad_trap_verify.wasm --swap-at 200:${CTL}/bad_unknown_import.wasm)
expect("refused run: exit ${refused_rc}\n${refused_out}${refused_err}" refused_rc EQUAL 0)
expect_in("${refused_out}" "swaps 0, 2 refused" "refused summary")
expect_in("${refused_err}" "tick 150: swap: ${CTL}/bad_trap_verify.wasm refused, the running controller stays: verify: trap at tick 3" "refused stderr")
expect_in("${refused_err}" "refused, the running controller stays: load: unknown import env.open_valve" "refused stderr")
row(${refused_csv} 150 r)
expect("row 150: ${r_row}" r_events STREQUAL "verify-refused" AND r_faults EQUAL 0)
row(${refused_csv} 200 r)
expect("row 200: ${r_row}" r_events STREQUAL "load-refused" AND r_faults EQUAL 0)
file(READ ${plain_csv} plain)
file(READ ${refused_csv} refused)
string(REPLACE "verify-refused\n" "\n" refused "${refused}")
string(REPLACE "load-refused\n" "\n" refused "${refused}")
expect("a refused swap changed the run: ${refused_csv} differs from ${plain_csv} beyond its events" plain STREQUAL refused)

# ---- 4. a clear rebuilds a controller that trapped: a fresh instance runs
#         from the clear (and, starting at its own tick 0, traps 150 ticks on)
run(trap --controller ${CTL}/bad_trap_run.wasm --ticks 400 --clear-at 200)
expect("trap run: exit ${trap_rc}, expected 1\n${trap_out}${trap_err}" trap_rc EQUAL 1)
expect_in("${trap_out}" "clears 1 (0 while pressed, 0 refused); swaps 0, 0 refused; rebuilds 1" "trap summary")
expect_in("${trap_err}" "tick 200: clear: trap cleared; the controller's instance that trapped" "trap stderr")
row(${trap_csv} 150 r)
expect("row 150, the trap: ${r_row}" r_faults EQUAL 1 AND r_events STREQUAL "fault:trap")
row(${trap_csv} 200 r)
expect("row 200, the clear: ${r_row}" r_faults EQUAL 0 AND r_events STREQUAL "clear rebuild cleared:trap" AND r_applied0 STREQUAL "0.1")
row(${trap_csv} 350 r)
expect("row 350, the rebuilt instance's own tick 150: ${r_row}" r_faults EQUAL 1 AND r_events STREQUAL "fault:trap")

# ---- 5. deterministic: every option at once, twice, the same bytes
foreach(k IN ITEMS 1 2)
  run(all_${k} --controller ${CTL}/sine.wasm --ticks 400 --param drop=30:45 --estop-at 60
               --clear-at 80 --estop-release-at 90 --clear-at 100 --swap-at 120:${CTL}/pd_hold.wasm
               --swap-at 160:${CTL}/bad_trap_verify.wasm --swap-at 200:${CTL}/bad_trap_run.wasm
               --clear-at 360 --swap-at 360:${CTL}/constant_velocity.wasm)
  expect("all options, run ${k}: exit ${all_${k}_rc}\n${all_${k}_out}${all_${k}_err}" all_${k}_rc EQUAL 0)
endforeach()
file(SHA256 ${all_1_csv} h1)
file(SHA256 ${all_2_csv} h2)
expect("two runs with the same options wrote different traces (${all_1_csv}, ${all_2_csv})" h1 STREQUAL h2)
# at tick 360 the swap comes before the clear: the clear is for the new
# controller, not a rebuild of the one that trapped at 350
row(${all_1_csv} 350 r)
expect("row 350: ${r_row}" r_events STREQUAL "fault:trap")
row(${all_1_csv} 360 r)
expect("row 360: ${r_row}" r_events STREQUAL "swap clear cleared:trap" AND r_target0 STREQUAL "0.628")

# ---- 6. the plot marks them
if(PYTHON AND PLOT)
  execute_process(COMMAND ${PYTHON} ${PLOT} ${estop_csv} ${OUT}/estop.png RESULT_VARIABLE rc
                  ERROR_VARIABLE err)
  file(SIZE ${OUT}/estop.png size)
  expect("plot of a trace with events: exit ${rc}, ${size} bytes\n${err}" rc EQUAL 0 AND size GREATER 20000)
endif()
