# SPDX-License-Identifier: Apache-2.0
# rozrun --operator end to end, in simulated time on the loopback port: the
# 12-joint G1's deployed policy under a scripted operator. The trace's
# input columns (the state the controller reads after the port's) follow
# the script at the inputs' rate cap, never faster: forward 0.5 m/s, a
# value beyond the limits (clamped to 0.8, counted), a non-finite one
# (refused, counted: the input keeps its value), stop; 1e308 and infinities
# likewise. A malformed or hostile file (times not finite, negative or
# going back, a number past a double, a row too long, a command channel or
# an unknown input named, a NUL byte, past 16 MiB) is refused before the
# robot moves, naming the file, line and column; so is a robot without
# inputs, and a --gamepad that is no evdev device.
#   cmake -DROZRUN=<rozrun> -DCTL=<controller dir> -DOUT=<work dir>
#         -DPYTHON=<python> -P run_rozrun_operator.cmake
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})

include(${CMAKE_CURRENT_LIST_DIR}/checks.cmake)

function(run name)
  execute_process(COMMAND ${ROZRUN} --controller ${CTL}/g1_12dof_deployed.wasm ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(${name}_rc ${rc} PARENT_SCOPE)
  set(${name}_out "${out}" PARENT_SCOPE)
  set(${name}_err "${err}" PARENT_SCOPE)
endfunction()

# ---- 1. the script, followed at the rate cap (0.002 m/s a 2 ms tick)
file(WRITE ${OUT}/walk.csv
"# forward, beyond the limits, a NaN, stop
time_s,operator/velocity.x,operator/yaw_rate
0,0.5,0
0.6,2.0,0.1
1.2,nan,0.1
1.3,0,0
")
run(walk --robot unitree_g1_12dof --ticks 1200 --operator ${OUT}/walk.csv
         --trace ${OUT}/walk_trace.csv)
if(NOT walk_rc EQUAL 0)
  message(FATAL_ERROR "walk: exit ${walk_rc}\n${walk_out}${walk_err}")
endif()
# every tick the scripted operator repeats its row: one clamp per tick of
# the 2.0 row (ticks 300..599), one refusal per tick of the NaN row (600..649)
expect_in("${walk_out}" "operator               4 rows from ${OUT}/walk.csv; inputs clamped 300, refused (non-finite) 50, gone stale 0" "walk summary")
expect_in("${walk_out}" "faults                 none" "walk summary")
execute_process(COMMAND ${PYTHON} -c "
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
vx = [float(r['input:operator/velocity.x']) for r in rows]
yaw = [float(r['input:operator/yaw_rate']) for r in rows]
vy = [float(r['input:operator/velocity.y']) for r in rows]
assert len(vx) == 1200, len(vx)
steps = max(max(abs(a - b) for a, b in zip(v, v[1:])) for v in (vx, yaw))
assert steps <= 0.004 + 1e-12, steps
assert max(abs(a - b) for a, b in zip(vx, vx[1:])) <= 0.002 + 1e-12
assert vx[0] == 0.002, vx[0]                       # from 0, at the cap
assert vx[249] == 0.5 and vx[299] == 0.5, (vx[249], vx[299])
assert vx[449] == 0.8 and vx[599] == 0.8, (vx[449], vx[599])  # clamped to the limit
assert abs(yaw[311] - 0.048) < 1e-9 and yaw[324] == 0.1, (yaw[311], yaw[324])  # 0.004 a tick
assert vx[649] == 0.8                              # the NaN refused: held
assert vx[650] < 0.8 and vx[1049] == 0.0 and vx[1199] == 0.0, (vx[650], vx[1049])
assert yaw[1199] == 0.0 and all(v == 0.0 for v in vy)
" ${OUT}/walk_trace.csv RESULT_VARIABLE py_rc OUTPUT_VARIABLE py_out ERROR_VARIABLE py_err)
if(NOT py_rc EQUAL 0)
  message(FATAL_ERROR "walk trace: ${py_out}${py_err}")
endif()

# ---- 2. refusals, naming file, line and column
function(refused name csv want)
  file(WRITE ${OUT}/${name}.csv "${csv}")
  run(${name} --robot unitree_g1_12dof --ticks 10 --operator ${OUT}/${name}.csv)
  if(NOT ${name}_rc EQUAL 2)
    message(FATAL_ERROR "${name}: exit ${${name}_rc}, expected 2\n${${name}_out}${${name}_err}")
  endif()
  expect_in("${${name}_err}" "rozrun: ${OUT}/${name}.csv:${want}" "${name} stderr")
endfunction()
refused(unknown "time_s,operator/velocity.x,operator/velocity.z\n0,0,0\n"
        "1:28: \"operator/velocity.z\" is not an input of robot unitree_g1_12dof (inputs: operator/velocity.x operator/velocity.y operator/yaw_rate)")
refused(header "time,operator/velocity.x\n0,0\n"
        "1:1: the header must start with \"time_s\"")
refused(number "time_s,operator/velocity.x\n0,0.1\n1, fast\n"
        "3:4: \"fast\" is not a number (column operator/velocity.x)")
refused(short "time_s,operator/velocity.x,operator/yaw_rate\n0,0.1\n"
        "2:6: 2 values for 3 columns")
refused(back "time_s,operator/velocity.x\n1,0.1\n0.5,0\n"
        "3:1: time_s 0.5: before the row above (1): rows go forward in time")
refused(twice "time_s,operator/yaw_rate,operator/yaw_rate\n"
        "1:26: input \"operator/yaw_rate\" named twice")
# hostile files: times not finite, negative or unsorted, a number past a
# double, a row too long, a command channel or an empty name for an input
refused(time_nan "time_s,operator/velocity.x\n0,0\nnan,0.1\n"
        "3:1: time_s nan: must be a finite number of seconds, from 0")
refused(time_inf "time_s,operator/velocity.x\ninf,0\n"
        "2:1: time_s inf: must be a finite number of seconds, from 0")
refused(time_negative "time_s,operator/velocity.x\n-0.5,0.1\n"
        "2:1: time_s -0.5: must be a finite number of seconds, from 0")
refused(past_double "time_s,operator/velocity.x\n0,1e400\n"
        "2:3: \"1e400\" is not a number (column operator/velocity.x)")
refused(long_row "time_s,operator/velocity.x\n0,0.1,0.2\n"
        "2:7: more values than the 2 columns of the header")
refused(command "time_s,left_knee_joint/position\n0,1\n"
        "1:8: \"left_knee_joint/position\" is not an input of robot unitree_g1_12dof")
refused(empty_name "time_s,,operator/velocity.x\n0,0,0\n"
        "1:8: \"\" is not an input of robot unitree_g1_12dof")
# a spreadsheet's UTF-8 byte order mark before the header is no refusal
# (and a file with a NUL byte, and one past 16 MiB, are refused)
execute_process(COMMAND ${PYTHON} -c "
import sys
open(sys.argv[1], 'wb').write(b'\\xef\\xbb\\xbftime_s,operator/velocity.x\\n0,0.1\\n')
open(sys.argv[2], 'wb').write(b'time_s,operator/velocity.x\\n0,\\x000.1\\n')
with open(sys.argv[3], 'wb') as f:
    f.write(b'time_s,operator/velocity.x\\n')
    f.write(b'0,0.1\\n' * (3 << 20))
" ${OUT}/bom.csv ${OUT}/nul.csv ${OUT}/huge.csv RESULT_VARIABLE py_rc)
if(NOT py_rc EQUAL 0)
  message(FATAL_ERROR "could not write bom.csv, nul.csv and huge.csv")
endif()
run(bom --robot unitree_g1_12dof --ticks 10 --operator ${OUT}/bom.csv)
if(NOT bom_rc EQUAL 0)
  message(FATAL_ERROR "bom: exit ${bom_rc}\n${bom_out}${bom_err}")
endif()
expect_in("${bom_out}" "operator               1 rows from ${OUT}/bom.csv" "bom summary")
foreach(name_want "nul;a NUL byte: not a CSV file" "huge;larger than 16 MiB")
  list(GET name_want 0 name)
  list(GET name_want 1 want)
  run(${name} --robot unitree_g1_12dof --ticks 10 --operator ${OUT}/${name}.csv)
  if(NOT ${name}_rc EQUAL 2)
    message(FATAL_ERROR "${name}: exit ${${name}_rc}, expected 2\n${${name}_out}${${name}_err}")
  endif()
  expect_in("${${name}_err}" "rozrun: --operator ${OUT}/${name}.csv: ${want}" "${name} stderr")
endforeach()
file(REMOVE ${OUT}/huge.csv)
# values past every limit, and infinities: clamped or refused, each counted,
# and the input the controller reads moves by its rate cap at most
file(WRITE ${OUT}/extreme.csv "time_s,operator/velocity.x,operator/yaw_rate
0,1e308,-inf
0.1,-1e308,inf
")
run(extreme --robot unitree_g1_12dof --ticks 100 --operator ${OUT}/extreme.csv
            --trace ${OUT}/extreme_trace.csv)
if(NOT extreme_rc EQUAL 0)
  message(FATAL_ERROR "extreme: exit ${extreme_rc}\n${extreme_out}${extreme_err}")
endif()
expect_in("${extreme_out}" "inputs clamped 100, refused (non-finite) 100, gone stale 0"
          "extreme summary")
execute_process(COMMAND ${PYTHON} -c "
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
vx = [float(r['input:operator/velocity.x']) for r in rows]
yaw = [float(r['input:operator/yaw_rate']) for r in rows]
assert len(vx) == 100, len(vx)
assert max(abs(a - b) for a, b in zip([0.0] + vx, vx)) <= 0.002 + 1e-12
assert abs(vx[49] - 0.1) < 1e-9 and abs(vx[99]) < 1e-9, (vx[49], vx[99])
assert all(v == 0.0 for v in yaw), set(yaw)
" ${OUT}/extreme_trace.csv RESULT_VARIABLE py_rc OUTPUT_VARIABLE py_out ERROR_VARIABLE py_err)
if(NOT py_rc EQUAL 0)
  message(FATAL_ERROR "extreme trace: ${py_out}${py_err}")
endif()

# ---- 3. a robot without inputs
file(WRITE ${OUT}/ur5.csv "time_s\n0\n")
execute_process(COMMAND ${ROZRUN} --robot ur5 --controller ${CTL}/sine.wasm --ticks 10
                        --operator ${OUT}/ur5.csv
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "ur5: exit ${rc}, expected 2\n${out}${err}")
endif()
expect_in("${err}" "robot ur5 has no operator inputs" "ur5 stderr")

# ---- 4. --gamepad: a file that is no evdev device is refused, named, before
# the robot moves (the device itself: test/gamepad/test_gamepad.c)
run(gamepad --robot unitree_g1_12dof --ticks 10 --gamepad /dev/null)
if(NOT gamepad_rc EQUAL 2)
  message(FATAL_ERROR "gamepad: exit ${gamepad_rc}, expected 2\n${gamepad_out}${gamepad_err}")
endif()
expect_in("${gamepad_err}" "--gamepad /dev/null" "gamepad stderr")
