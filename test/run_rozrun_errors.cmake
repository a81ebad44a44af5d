# SPDX-License-Identifier: Apache-2.0
# rozrun's errors for bad arguments: each exits 2 with a message naming the
# problem; and runs that latch faults exit 1 and name them.
# cmake -DROZRUN=... -DCTL=<controller dir> -DDEEP=<scratch dir> -P
include(${CMAKE_CURRENT_LIST_DIR}/checks.cmake)

expect_error("--robot;ur5" "--robot and --controller are required")
expect_error("--robot;ur10;--controller;${CTL}/sine.wasm" "no such built-in manifest; known: agibot_x2")
expect_error("--robot;ur5;--controller;${CTL}/nope.wasm" "cannot read")
expect_error("--robot;ur5;--controller;${CTL}/sine.wasm;--ticks;-3" "--ticks needs a non-negative integer")
expect_error("--robot;ur5;--controller;${CTL}/sine.wasm;--port;can0" "--port \"can0\"")
expect_error("--robot;ur5;--controller;${CTL}/sine.wasm;--param;dropp=1:2" "unknown parameter \"dropp\"")
expect_error("--robot;ur5;--controller;${CTL}/sine.wasm;--param;drop=x" "parameter drop = \"x\"")
expect_error("--robot;ur5;--controller;${CTL}/sine.wasm;--frobnicate" "unknown option")
# fault parameters: what is wrong with the value given
expect_error("--robot;diff_drive;--controller;${CTL}/sine.wasm;--param;nan=7@1:2"
             "parameter nan = \"7@1:2\": state 7 does not exist (3 states)")
expect_error("--robot;ur5;--controller;${CTL}/sine.wasm;--param;drop=300:100"
             "parameter drop = \"300:100\": FROM 300 after TO 100")
expect_error("--robot;ur5;--controller;${CTL}/sine.wasm;--param;drop=99999999999999999999999:"
             "FROM 99999999999999999999999 is too large")
# the scheduled interventions: malformed, out of the run, or in conflict;
# each message names the option and its value
set(S "--robot;ur5;--controller;${CTL}/sine.wasm;--ticks;300")
expect_error("${S};--estop-at;300" "--estop-at 300: after the run (--ticks 300 runs ticks 0..299)")
expect_error("${S};--clear-at;x" "--clear-at \"x\": expected TICK")
expect_error("${S};--clear-at;-1" "--clear-at \"-1\": expected TICK")
expect_error("${S};--estop-release-at;12abc" "--estop-release-at \"12abc\": expected TICK")
expect_error("${S};--clear-at;99999999999999999999999" "--clear-at \"99999999999999999999999\": the tick is too large")
expect_error("${S};--swap-at;50" "--swap-at \"50\": expected TICK:FILE")
expect_error("${S};--swap-at;50:" "--swap-at \"50:\": expected TICK:FILE")
# the deploy sequence (docs/deploy.md): each refusal names the file, the key
# and the channel or input
set(G "--robot;unitree_g1_12dof;--controller;${CTL}/sine.wasm;--ticks;300")
# deploy_error(NAME TEXT WANT): rozrun refuses a deploy sequence of [deploy]
# then TEXT, saying "deploy_NAME.toml: WANT"
function(deploy_error name text want)
  file(WRITE ${DEEP}/deploy_${name}.toml "[deploy]\n${text}")
  expect_error("${G};--deploy;${DEEP}/deploy_${name}.toml" "deploy_${name}.toml: ${want}")
endfunction()
set(stand_ok "pose = [-0.1, 0, 0, 0.3, -0.2, 0, -0.1, 0, 0, 0.3, -0.2, 0]\nkp = [100, 100, 100, 150, 40, 40, 100, 100, 100, 150, 40, 40]\nkd = [2, 2, 2, 4, 2, 2, 2, 2, 2, 4, 2, 2]\n")
deploy_error(knee "[deploy.stand]\npose = [-0.1, 0, 0, 4.0, -0.2, 0, -0.1, 0, 0, 0.3, -0.2, 0]\nkp = [100, 100, 100, 150, 40, 40, 100, 100, 100, 150, 40, 40]\nkd = [2, 2, 2, 4, 2, 2, 2, 2, 2, 4, 2, 2]\n"
             "deploy.stand.pose[3]: 4: outside \"left_knee_joint/position\"'s limits")
deploy_error(kp "[deploy.stand]\npose = [-0.1, 0, 0, 0.3, -0.2, 0, -0.1, 0, 0, 0.3, -0.2, 0]\nkp = [100, 100, 100, 150, 40, 400, 100, 100, 100, 150, 40, 40]\nkd = [2, 2, 2, 4, 2, 2, 2, 2, 2, 4, 2, 2]\n"
             "deploy.stand.kp[5]: 400: outside \"left_ankle_roll_joint/stiffness\"'s limits")
deploy_error(short "[deploy.stand]\npose = [0.0]\nkp = [100]\nkd = [2]\n"
             "deploy.stand.pose: 1 values for 12 joints")
deploy_error(move "move_s = 0\n[deploy.stand]\n${stand_ok}"
             "move_s: 0: must be above 0 s")
deploy_error(input "[deploy.inputs]\nrun = \"remote/a\"\n[deploy.stand]\n${stand_ok}"
             "deploy.inputs.run: \"remote/a\": no such input in the manifest of unitree_g1_12dof")
deploy_error(key "move_time = 2\n[deploy.stand]\n${stand_ok}"
             "deploy.move_time: not a key of the deploy sequence")
deploy_error(robot "robot = \"unitree_g1\"\n[deploy.stand]\n${stand_ok}"
             "deploy.robot: written for another robot than unitree_g1_12dof")
deploy_error(joint "[deploy.stand]\njoints = [\"left_hip_pitch_joint\", \"tail_joint\"]\npose = [0, 0]\nkp = [1, 1]\nkd = [1, 1]\n"
             "deploy.stand.joints[1]: \"tail_joint/position\": no such command in unitree_g1_12dof")
deploy_error(some "[deploy.stand]\njoints = [\"left_hip_pitch_joint\"]\npose = [0]\nkp = [1]\nkd = [1]\n"
             "deploy.stand.joints: \"left_hip_roll_joint/position\" is not in the stand")
expect_error("${G};--stage-at;10:run" "--stage-at needs --deploy")
expect_error("${G};--stage-at;10:walk" "--stage-at \"10:walk\": expected TICK:STAGE")
# the same messages whatever the depth of the path: here as built, then
# from a folder 1,000 characters deep (a clone can sit anywhere)
set(deep ${DEEP})
foreach(i RANGE 1 10)
  string(APPEND deep "/folder_${i}_of_a_clone_that_sits_at_a_deep_path_on_some_machine_somewhere")
endforeach()
file(MAKE_DIRECTORY ${deep})
file(COPY ${CTL}/sine.wasm ${CTL}/hold.wasm DESTINATION ${deep})
foreach(dir IN ITEMS "${CTL}" "${deep}")
  expect_error("${S};--swap-at;0:${dir}/sine.wasm" "--swap-at 0:${dir}/sine.wasm: tick 0 runs --controller")
  expect_error("${S};--swap-at;50:${dir}/nope.wasm" "--swap-at 50:${dir}/nope.wasm: cannot read")
  expect_error("${S};--swap-at;50:${dir}/sine.wasm;--swap-at;50:${dir}/hold.wasm"
               "--swap-at 50:${dir}/hold.wasm: --swap-at 50:${dir}/sine.wasm is at the same tick; one swap a tick")
  expect_error("--robot;ur5;--controller;${dir}/nope.wasm" "cannot read ${dir}/nope.wasm")
endforeach()
expect_error("${S};--clear-at;70;--clear-at;70" "--clear-at 70: given twice")
expect_error("${S};--estop-release-at;40" "--estop-release-at 40: the e-stop is not pressed then")
expect_error("${S};--estop-at;40;--estop-at;60" "--estop-at 60: the e-stop is still pressed then (--estop-at 40, no release between)")
expect_error("${S};--estop-at;40;--estop-release-at;40" "--estop-release-at 40: --estop-at 40 is at the same tick")
expect_error("${S};--estop-at;40;--estop-release-at;50;--estop-release-at;60" "--estop-release-at 60: the e-stop is not pressed then")
expect_error("${S};--estop-at" "--estop-at needs a value")
expect_error("--robot;ur5;--controller;${CTL}/bad_unknown_import.wasm" "unknown import env.open_valve")
expect_error("--robot;ur5;--controller;${CTL}/bad_trap_verify.wasm" "verify: trap at tick 3")
# simulated time: the fuel alone decides, so two runs write the same trace,
# byte for byte; --budget-us off/N is accepted, 0 refused
foreach(k IN ITEMS 1 2)
  execute_process(COMMAND ${ROZRUN} --robot ur5 --controller ${CTL}/sine.wasm --ticks 300
                          --trace ${CMAKE_CURRENT_BINARY_DIR}/rozrun_det_${k}.csv
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "deterministic run ${k}: exit ${rc}\n${err}")
  endif()
endforeach()
file(SHA256 ${CMAKE_CURRENT_BINARY_DIR}/rozrun_det_1.csv h1)
file(SHA256 ${CMAKE_CURRENT_BINARY_DIR}/rozrun_det_2.csv h2)
if(NOT h1 STREQUAL h2)
  message(FATAL_ERROR "two simulated-time runs wrote different traces")
endif()
expect_error("--robot;ur5;--controller;${CTL}/sine.wasm;--budget-us;0" "--budget-us must be in 1..10000000, or off")
execute_process(COMMAND ${ROZRUN} --robot ur5 --controller ${CTL}/sine.wasm --ticks 20 --budget-us off
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "--budget-us off: exit ${rc}\n${err}")
endif()
# a budget of 0 allows nothing: refused, never "unmetered" (that is --fuel off)
expect_error("--robot;ur5;--controller;${CTL}/sine.wasm;--fuel;0" "--fuel must be in 1..")
execute_process(COMMAND ${ROZRUN} --robot ur5 --controller ${CTL}/sine.wasm --ticks 20 --fuel off
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "units; budget off")
  message(FATAL_ERROR "--fuel off: exit ${rc}\n${out}${err}")
endif()
execute_process(COMMAND ${ROZRUN} --help RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT out MATCHES "usage: rozrun")
  message(FATAL_ERROR "--help")
endif()
# --port NAME --help adds the port's own section, from the port's info
execute_process(COMMAND ${ROZRUN} --port loopback --help RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT out MATCHES "usage: rozrun"
   OR NOT out MATCHES "Port loopback: a deterministic simulator"
   OR NOT out MATCHES "\n    corrupt_cmd +FROM:TO\n")
  message(FATAL_ERROR "--port loopback --help:\n${out}")
endif()
# a run whose controller traps exits 1 and names the fault
execute_process(COMMAND ${ROZRUN} --robot ur5 --controller ${CTL}/bad_trap_run.wasm --ticks 300
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1 OR NOT out MATCHES "latched: trap")
  message(FATAL_ERROR "trap run: exit ${rc}\n${out}${err}")
endif()
# a .wat controller is assembled with wat2wasm
execute_process(COMMAND ${ROZRUN} --robot ur5 --controller ${WAT} --ticks 50
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR ".wat run: exit ${rc}\n${out}${err}")
endif()
# the robot dies and boots again: exit 1, both faults named, the link counted
execute_process(COMMAND ${ROZRUN} --robot ur5 --controller ${CTL}/sine.wasm --ticks 400
                        --param restart=150:300 --param corrupt=50:55
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1 OR NOT out MATCHES "latched: stale state port link"
   OR NOT out MATCHES "5 bad CRC, 0 replays, [0-9]+ missing, 1 peer restarts")
  message(FATAL_ERROR "restart run: exit ${rc}\n${out}${err}")
endif()
# a trace that cannot be written is an error, exit 3, whatever the run did
if(EXISTS /dev/full)
  foreach(n IN ITEMS 3 300) # failing at close, and while running
    execute_process(COMMAND ${ROZRUN} --robot ur5 --controller ${CTL}/sine.wasm --ticks ${n}
                            --trace /dev/full
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 3 OR NOT err MATCHES "cannot write trace /dev/full: No space left on device"
       OR NOT out MATCHES "trace                  /dev/full is incomplete")
      message(FATAL_ERROR "--trace /dev/full, ${n} ticks: exit ${rc}, expected 3\n${out}${err}")
    endif()
  endforeach()
endif()
# the summary says plainly how long the runtime waited for state, and why
# nothing was sent meanwhile
execute_process(COMMAND ${ROZRUN} --robot ur5 --controller ${CTL}/sine.wasm --ticks 50
                        --param freeze=0:20
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "waiting for state      20 ticks before the port's first usable state frame \\(tick 20\\); nothing is sent until the robot's state is known"
   OR NOT out MATCHES "commands written       30 frames")
  message(FATAL_ERROR "waiting 20 ticks: exit ${rc}\n${out}${err}")
endif()
execute_process(COMMAND ${ROZRUN} --robot ur5 --controller ${CTL}/sine.wasm --ticks 50
                        --param freeze=0
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT out MATCHES "waiting for state      all 50 ticks: the port never gave a usable state frame, so nothing was sent"
   OR NOT out MATCHES "commands written       0 frames")
  message(FATAL_ERROR "never any state: exit ${rc}\n${out}${err}")
endif()
