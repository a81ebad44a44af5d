# SPDX-License-Identifier: Apache-2.0
# rozrun --realtime with scheduled interventions: the e-stop input is set by
# the periodic tick thread (exactly at its tick), clears and swaps run on
# the main thread as a loader would, concurrently with the ticks (under
# ThreadSanitizer in the TSan build). Where a clear or swap lands depends on
# scheduling, so this checks what must hold wherever it lands: the press at
# its tick, the fault held until the clear, the clear after its tick and
# after the release, the swap after its tick, and nothing left undone.
#   cmake -DROZRUN=<rozrun> -DCTL=<controller dir> -DOUT=<work dir> -P run_rozrun_realtime.cmake
cmake_minimum_required(VERSION 3.25) # quoted arguments of if() are strings (CMP0054)
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
set(csv ${OUT}/realtime.csv)
execute_process(COMMAND ${ROZRUN} --robot ur5 --controller ${CTL}/sine.wasm --realtime --ticks 200
                        --estop-at 20 --estop-release-at 40 --clear-at 60
                        --swap-at 80:${CTL}/constant_velocity.wasm --trace ${csv}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR err MATCHES "not carried out")
  message(FATAL_ERROR "realtime run: exit ${rc}, expected 0 with every intervention done\n${out}${err}")
endif()
if(NOT out MATCHES "e-stop 1 pressed, 1 released; clears 1 \\(0 while pressed, 0 refused\\); swaps 1, 0 refused")
  message(FATAL_ERROR "realtime summary:\n${out}${err}")
endif()

file(STRINGS ${csv} lines)
list(LENGTH lines n)
if(NOT n EQUAL 201)
  message(FATAL_ERROR "${csv}: ${n} lines, expected a header and 200 rows (none dropped)")
endif()
set(cleared -1)
set(swapped -1)
foreach(tick RANGE 0 199)
  math(EXPR at "${tick} + 1")
  list(GET lines ${at} line)
  if(NOT line MATCHES "^${tick},[^,]*,([^,]*),.*,([0-9]+),([^,]*)$")
    message(FATAL_ERROR "${csv}: row ${tick}: ${line}")
  endif()
  set(target0 ${CMAKE_MATCH_1})
  set(faults ${CMAKE_MATCH_2})
  set(events "${CMAKE_MATCH_3}")
  # the e-stop input: exactly at its ticks
  if(tick EQUAL 20 AND NOT events STREQUAL "estop fault:e-stop")
    message(FATAL_ERROR "row 20, the press: ${line}")
  endif()
  if(tick EQUAL 40 AND NOT events STREQUAL "estop-release")
    message(FATAL_ERROR "row 40, the release: ${line}")
  endif()
  if(events MATCHES "(^| )clear( |$)")
    set(cleared ${tick})
    if(tick LESS 60 OR NOT events MATCHES "cleared:e-stop")
      message(FATAL_ERROR "row ${tick}: a clear before its tick 60, or one that cleared nothing: ${line}")
    endif()
  endif()
  if(events MATCHES "(^| )swap( |$)")
    set(swapped ${tick})
    if(tick LESS 80)
      message(FATAL_ERROR "row ${tick}: a swap before its tick 80: ${line}")
    endif()
  endif()
  # latched from the press until the clear, and at no other time
  if(tick GREATER_EQUAL 20 AND cleared EQUAL -1)
    set(want 8)
  else()
    set(want 0)
  endif()
  if(NOT faults EQUAL want)
    message(FATAL_ERROR "row ${tick}: faults ${faults}, expected ${want}: ${line}")
  endif()
  # from the swap on, constant_velocity drives (a fifth of 3.14 rad/s)
  if(NOT swapped EQUAL -1 AND NOT target0 STREQUAL "0.628")
    message(FATAL_ERROR "row ${tick}, after the swap at ${swapped}: ${line}")
  endif()
endforeach()
if(cleared EQUAL -1 OR swapped EQUAL -1)
  message(FATAL_ERROR "the clear (row ${cleared}) or the swap (row ${swapped}) is not in ${csv}")
endif()
message(STATUS "realtime: cleared at tick ${cleared} (asked for 60), swapped at ${swapped} (asked for 80)")

# --realtime without the privilege fails closed: with SCHED_FIFO and locked
# memory refused (no CAP_SYS_NICE or CAP_IPC_LOCK, RLIMIT_RTPRIO and
# RLIMIT_MEMLOCK 0), rozrun says so before the first tick and judges the
# deadline on the controller's CPU time, never the wall clock at normal
# priority (where a loaded machine latched spurious overruns). ThreadSanitizer
# makes mlockall() a no-op that succeeds: there only SCHED_FIFO is refused.
find_program(SETPRIV setpriv)
find_program(PRLIMIT prlimit)
if(SETPRIV AND PRLIMIT)
  # dropping capabilities takes CAP_SETPCAP (root); a user without it has
  # none of the two to drop, and the limits alone refuse
  set(drop ${SETPRIV} --inh-caps=-all --bounding-set=-sys_nice,-ipc_lock)
  execute_process(COMMAND ${drop} true RESULT_VARIABLE can_drop OUTPUT_QUIET ERROR_QUIET)
  if(NOT can_drop EQUAL 0)
    set(drop)
  endif()
  execute_process(COMMAND ${PRLIMIT} --rtprio=0 --memlock=0 ${drop}
                          ${ROZRUN} --robot ur5 --controller ${CTL}/sine.wasm --realtime --ticks 50
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0
     OR NOT err MATCHES "--realtime: SCHED_FIFO( and locked memory)? refused: the tick runs at normal priority, and its deadline counts the controller's CPU time"
     OR NOT out MATCHES "scheduling +normal \\(SCHED_FIFO not permitted\\), memory (not )?locked, [0-9]+ deadlines missed; the deadline on the controller's CPU time")
    message(FATAL_ERROR "--realtime refused: exit ${rc}\n${out}${err}")
  endif()
  message(STATUS "realtime refused: said at start, the deadline on the CPU time")
else()
  message(STATUS "realtime refused: not checked (no setpriv or prlimit)")
endif()
