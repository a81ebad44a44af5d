# SPDX-License-Identifier: Apache-2.0
# rozrun --deploy switched by buttons, end to end in simulated time on the
# loopback port: the 12-joint G1's robot.toml with four button inputs (0 or
# 1), a deploy file naming them, and a scripted operator pressing Start, A, B
# and Select as Unitree's deploy uses them. The summary's deploy line counts
# the stage changes (move, hold, run, move, hold, stop), the trace shows the
# damping stop on the wire at the end (kp 0, kd 8).
#   cmake -DROZRUN=<rozrun> -DCTL=<controller dir> -DSRC=<source dir>
#         -DOUT=<work dir> -P run_rozrun_deploy.cmake
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})

file(READ ${SRC}/manifests/unitree_g1_12dof.toml robot)
foreach(button start a b select)
  string(APPEND robot "\n[[manifest.inputs]]\nname = \"remote/${button}\"\n"
         "interface_type = \"position\"\nunit = \"\"\nlimits = [0.0, 1.0]\ndefault = 0.0\n"
         "max_rate_of_change = 1.0\nstale_after_ms = 500\n")
endforeach()
file(WRITE ${OUT}/g1_buttons.toml "${robot}")
file(WRITE ${OUT}/deploy.toml "[deploy]
move_s = 1.0
[deploy.inputs]
start = \"remote/start\"
run = \"remote/a\"
stand = \"remote/b\"
stop = \"remote/select\"
[deploy.stand]
pose = [-0.1, 0, 0, 0.3, -0.2, 0, -0.1, 0, 0, 0.3, -0.2, 0]
kp = [100, 100, 100, 150, 40, 40, 100, 100, 100, 150, 40, 40]
kd = [2, 2, 2, 4, 2, 2, 2, 2, 2, 4, 2, 2]
")
# Start at 0.2 s, A at 1.6 s (the move took 1 s), B at 3 s, Select at 5 s
file(WRITE ${OUT}/buttons.csv "time_s,remote/start,remote/a,remote/b,remote/select
0,0,0,0,0
0.2,1,0,0,0
0.3,0,0,0,0
1.6,0,1,0,0
1.7,0,0,0,0
3.0,0,0,1,0
3.1,0,0,0,0
5.0,0,0,0,1
")
# the controller was built for the table without the buttons: allowed
execute_process(COMMAND ${ROZRUN} --robot ${OUT}/g1_buttons.toml --allow-other-robot
                        --controller ${CTL}/g1_12dof_deployed.wasm --ticks 3000 --deploy ${OUT}/deploy.toml
                        --operator ${OUT}/buttons.csv --trace ${OUT}/trace.csv
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "rozrun: exit ${rc}\n${out}${err}")
endif()
foreach(want "deploy                 stage stop at the end; 6 stage changes, 0 requests refused; hand-overs 1"
             "faults                 none")
  string(FIND "${out}" "${want}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the summary lacks \"${want}\":\n${out}")
  endif()
endforeach()
# the last tick: the knee's stiffness 0 and damping 8 on the wire
file(STRINGS ${OUT}/trace.csv lines)
list(GET lines 0 header)
list(GET lines -1 last)
string(REPLACE "," ";" header "${header}")
string(REPLACE "," ";" last "${last}")
foreach(pair "applied:left_knee_joint/stiffness=0" "applied:left_knee_joint/damping=8")
  string(REPLACE "=" ";" pair "${pair}")
  list(GET pair 0 col)
  list(GET pair 1 want)
  list(FIND header "${col}" i)
  if(i EQUAL -1)
    message(FATAL_ERROR "the trace has no column ${col}: ${header}")
  endif()
  list(GET last ${i} v)
  if(NOT v EQUAL want)
    message(FATAL_ERROR "${col} at the last tick: ${v}, expected ${want}")
  endif()
endforeach()
