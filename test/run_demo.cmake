# SPDX-License-Identifier: Apache-2.0
# The demos end to end (the Makefile's demo and demo-loopback): rozrun writes
# a trace (and for the G1 a recording), the plot script turns it into a PNG.
#   cmake -DDEMO=g1|ur5 -DROZRUN=... -DCONTROLLER=... -DPYTHON=... -DPLOT=... -DOUT=...
#         [-DRENDER=tools/render_frames.py] -P
# DEMO=g1: the balancing stand in MuJoCo, pushed half-way; the G1 must be
# standing at the end (pelvis above 0.7 m, only its feet on the ground).
# DEMO=ur5: the sine controller on the loopback UR5.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
if(DEMO STREQUAL "g1")
  set(ticks 5000)
  set(cmd ${ROZRUN} --robot unitree_g1 --port mujoco --controller ${CONTROLLER}
          --ticks ${ticks} --param push=80,0,0@pelvis@2500:2550
          --trace ${OUT}/trace.csv --record ${OUT}/run.mcap)
  set(plot_args --span "5:5.1:push 80 N" --channels "(hip_pitch|knee|ankle_pitch)_joint/position")
  set(wants "ticks                  5000" "faults                 none"
            "ground contacts        [0-9]+: left_ankle_roll_link, right_ankle_roll_link\n"
            "base                   height 0\\.[7-9][0-9]* m \\(lowest 0\\.[7-9]"
            "recording              [^\n]*\\(5000 ticks, none dropped")
else()
  set(ticks 500)
  set(cmd ${ROZRUN} --robot ur5 --controller ${CONTROLLER} --port loopback
          --ticks ${ticks} --trace ${OUT}/trace.csv)
  set(plot_args "")
  set(wants "ticks                  500" "faults                 none" "rate caps")
endif()
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
file(STRINGS ${OUT}/trace.csv lines)
list(LENGTH lines n)
math(EXPR rows "${ticks} + 1")
if(NOT n EQUAL rows)
  message(FATAL_ERROR "trace has ${n} lines, expected a header and ${ticks} rows")
endif()
if(DEMO STREQUAL "g1")
  list(GET lines 0 header)
  if(NOT header MATCHES ",truth:base\\.z,")
    message(FATAL_ERROR "the trace of a mujoco run lacks the base's height (truth:base.z)")
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
  execute_process(COMMAND ${PYTHON} ${RENDER} ${OUT}/trace.csv ${OUT}/frames.png --at 0,5.2,10
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
