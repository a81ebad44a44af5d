# SPDX-License-Identifier: Apache-2.0
# The demos end to end (the Makefile's demo, demo-stand and demo-loopback):
# rozrun writes a trace (and in MuJoCo a recording), the plot script turns it
# into a PNG.
#   cmake -DDEMO=walk|stand|ur5 -DROZRUN=... -DCONTROLLER=... -DPYTHON=... -DPLOT=...
#         -DOUT=... [-DRENDER=tools/render_frames.py]
#         [-DOPERATOR=examples/operators/g1_walk.csv -DTRACKING=tools/tracking.py
#          -DBOUNDS=<tracking.py's bound options>] [-DMIN_PELVIS=<m>]
#         [-DRATE_CAPS=<n>] [-DSTAGES=<rozrun's deploy options>]
#         [-DWANTS=<more regexes the summary must match>] -P run_demo.cmake
# DEMO=walk: a walking controller (a trained policy, ROZ_G1_WALK_POLICY, or
# roz's own walker, g1_walker.c) on the 12-joint G1 in MuJoCo under the
# scripted operator (forward, stop, turn, stop), 21 s: the G1 up at the end,
# the operator's inputs in the trace and the recording, the commanded vs
# achieved velocity within BOUNDS (tools/tracking.py's options;
# test/CMakeLists.txt states them), the plot marking the operator's
# commands; with MIN_PELVIS, the pelvis never lower than that (m, the
# summary's lowest base height); with RATE_CAPS, the safety filter held back
# exactly that many command values (the summary's rate caps: 0 for a
# controller that keeps its commands under the manifest's rate caps); with
# STAGES, rozrun's options that run the controller inside its deploy sequence
# (--deploy, --stage-at, the gantry; make demo DEMO=policy passes the same,
# and may add --swap-at); with WANTS, more lines the summary must have.
# DEMO=stand: the balancing stand in MuJoCo, pushed half-way; the G1 must be
# standing at the end (pelvis above 0.7 m, only its feet on the ground).
# DEMO=ur5: the sine controller on the loopback UR5.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
set(frames_at "")
if(DEMO STREQUAL "walk")
  set(ticks 10500)
  set(cmd ${ROZRUN} --robot unitree_g1_12dof --port mujoco --controller ${CONTROLLER}
          --ticks ${ticks} --operator ${OPERATOR} ${STAGES}
          --trace ${OUT}/trace.csv --record ${OUT}/run.mcap)
  set(plot_args --operator ${OPERATOR} --channels "(hip_pitch|knee|ankle_pitch)_joint/position")
  set(wants "ticks                  10500" "faults                 none"
            "operator               5 rows from [^\n]*; inputs clamped 0, refused \\(non-finite\\) 0, gone stale 0"
            "base                   height 0\\.[6-9][0-9]* m \\(lowest 0\\.[6-9]"
            "0 values outside the manifest written"
            "recording              [^\n]*\\(10500 ticks, none dropped")
  set(frames_at 0,4,9,13,16,21)
elseif(DEMO STREQUAL "stand")
  set(ticks 5000)
  set(cmd ${ROZRUN} --robot unitree_g1 --port mujoco --controller ${CONTROLLER}
          --ticks ${ticks} --param push=80,0,0@pelvis@2500:2550
          --trace ${OUT}/trace.csv --record ${OUT}/run.mcap)
  set(plot_args --span "5:5.1:push 80 N" --channels "(hip_pitch|knee|ankle_pitch)_joint/position")
  set(wants "ticks                  5000" "faults                 none"
            "ground contacts        [0-9]+: left_ankle_roll_link, right_ankle_roll_link\n"
            "base                   height 0\\.[7-9][0-9]* m \\(lowest 0\\.[7-9]"
            "recording              [^\n]*\\(5000 ticks, none dropped")
  set(frames_at 0,5.2,10)
else()
  set(ticks 500)
  set(cmd ${ROZRUN} --robot ur5 --controller ${CONTROLLER} --port loopback
          --ticks ${ticks} --trace ${OUT}/trace.csv)
  set(plot_args "")
  set(wants "ticks                  500" "faults                 none" "rate caps")
endif()
list(APPEND wants ${WANTS})
execute_process(COMMAND ${cmd} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "rozrun exited ${rc}")
endif()
foreach(want IN LISTS wants)
  if(NOT out MATCHES "${want}")
    message(FATAL_ERROR "summary lacks \"${want}\"")
  endif()
endforeach()
if(DEFINED RATE_CAPS AND NOT out MATCHES "rate caps +${RATE_CAPS}\n")
  string(REGEX MATCH "rate caps +[0-9]+" caps "${out}")
  message(FATAL_ERROR "the safety filter rate-capped other than ${RATE_CAPS} values: ${caps}")
endif()
if(MIN_PELVIS)
  if(NOT out MATCHES "base +height [0-9.]+ m \\(lowest ([0-9.]+)\\)")
    message(FATAL_ERROR "summary lacks the base's lowest height")
  endif()
  if(CMAKE_MATCH_1 LESS MIN_PELVIS)
    message(FATAL_ERROR "the pelvis went down to ${CMAKE_MATCH_1} m, below ${MIN_PELVIS} m")
  endif()
  message(STATUS "pelvis never below ${CMAKE_MATCH_1} m (bound ${MIN_PELVIS} m)")
endif()
file(STRINGS ${OUT}/trace.csv lines)
list(LENGTH lines n)
math(EXPR rows "${ticks} + 1")
if(NOT n EQUAL rows)
  message(FATAL_ERROR "trace has ${n} lines, expected a header and ${ticks} rows")
endif()
list(GET lines 0 header)
if(NOT DEMO STREQUAL "ur5" AND NOT header MATCHES ",truth:base\\.z,")
  message(FATAL_ERROR "the trace of a mujoco run lacks the base's height (truth:base.z)")
endif()
if(DEMO STREQUAL "walk")
  foreach(input operator/velocity.x operator/velocity.y operator/yaw_rate)
    if(NOT header MATCHES ",input:${input}")
      message(FATAL_ERROR "the trace lacks the operator's input ${input}")
    endif()
  endforeach()
  # the recording carries the inputs, every tick (a replay feeds them back)
  get_filename_component(tools ${PLOT} DIRECTORY)
  execute_process(COMMAND ${PYTHON} ${tools}/recording.py check ${OUT}/run.mcap
                  RESULT_VARIABLE rc OUTPUT_VARIABLE checked ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT checked MATCHES "/roz/inputs 10500,")
    message(FATAL_ERROR "the recording lacks the operator's inputs: ${checked}${err}")
  endif()
  # the figures, and the bounds when given (exit 1 names the one broken)
  execute_process(COMMAND ${PYTHON} ${TRACKING} ${OUT}/trace.csv --operator ${OPERATOR} ${BOUNDS}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE track ERROR_VARIABLE err)
  message(STATUS "commanded vs achieved (tools/tracking.py ${BOUNDS}):\n${track}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "tracking outside its bounds: ${err}")
  endif()
endif()
execute_process(COMMAND ${PYTHON} ${PLOT} ${OUT}/trace.csv ${OUT}/plot.png ${plot_args}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "plot failed")
endif()
file(READ ${OUT}/plot.png head LIMIT 8 HEX)
file(SIZE ${OUT}/plot.png size)
if(NOT head STREQUAL "89504e470d0a1a0a" OR size LESS 20000)
  message(FATAL_ERROR "plot.png is not a real PNG (${size} bytes)")
endif()
message(STATUS "demo ${DEMO}: ${n} trace lines, plot ${size} bytes")
# Frames of the robot, rendered offscreen: exit 3 says there is no offscreen
# OpenGL here (the demo goes on without them); anything else must work.
if(RENDER)
  execute_process(COMMAND ${PYTHON} ${RENDER} ${OUT}/trace.csv ${OUT}/frames.png --at ${frames_at}
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(rc EQUAL 3)
    message(STATUS "demo ${DEMO}: frames not rendered: ${err}")
  elseif(NOT rc EQUAL 0)
    message(FATAL_ERROR "render_frames failed (${rc}): ${err}")
  else()
    file(READ ${OUT}/frames.png head LIMIT 8 HEX)
    file(SIZE ${OUT}/frames.png size)
    if(NOT head STREQUAL "89504e470d0a1a0a" OR size LESS 50000)
      message(FATAL_ERROR "frames.png is not a real PNG (${size} bytes)")
    endif()
    message(STATUS "demo ${DEMO}: frames ${size} bytes")
  endif()
endif()
