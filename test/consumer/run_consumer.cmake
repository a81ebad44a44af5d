# SPDX-License-Identifier: Apache-2.0
# cmake -DMODE=find_package|add_subdirectory|small_config -DROZ_SOURCE_DIR=...
#       -DROZ_BINARY_DIR=... -DWORK_DIR=... -DROZGEN_EXECUTABLE=... [-DGENERATOR=...]
#       -P run_consumer.cmake
#
# Builds the consumer project (CMakeLists.txt here) in WORK_DIR and runs it.
#
# find_package: the installed package must stand alone. It works in a
# temporary folder outside the trees instead of WORK_DIR (removed when the
# test passes, kept for a look when it fails). The build is installed
# into a staging prefix there, which is then moved (a prefix
# must not care where it is); no text file in it may name the source tree, the
# build tree or the virtual environment rozgen came from. Then, with only the
# prefix (this script again, with PHASE=installed): no ROZGEN_EXECUTABLE, a
# PATH without the virtual environment, and, where a mount namespace is
# permitted (unshare -m, or -rm), the source tree, the build tree and the
# virtual environment hidden under empty tmpfs mounts, the consumer is
# configured (it must find <prefix>/bin/rozgen), built and run (its C
# controller, and its Rust one where rustc has the wasm32 target); the installed
# rozrun runs the consumer's controller on the consumer's robot.toml (with a
# trace and a recording, which the installed roz-plot and roz-recording read
# and plot; and, with the mujoco port, on the built-in G1 in physics from the
# installed model), and the installed roz_manifest_json and rozgen --json must
# print the same manifest.
cmake_minimum_required(VERSION 3.25)

# (the second half's copy of this script has a copy of checks.cmake above it)
include(${CMAKE_CURRENT_LIST_DIR}/../checks.cmake)
generator_args(gen)

# ---- find_package, second half: only the prefix ------------------------------
if(PHASE STREQUAL "installed")
  set(prefix ${WORK_DIR}/prefix)
  string(REPLACE "|" ";" HIDDEN "${HIDDEN}")
  foreach(hidden IN LISTS HIDDEN)
    if(EXISTS ${hidden}/CMakeLists.txt OR EXISTS ${hidden}/CMakeCache.txt
       OR EXISTS ${hidden}/bin/python)
      message(FATAL_ERROR "${hidden} was to be hidden, yet it is still there")
    endif()
  endforeach()
  run_shown(${CMAKE_COMMAND} -S ${WORK_DIR}/src -B ${WORK_DIR}/build ${gen}
      -DROZ_CONSUMER_MODE=find_package -DCMAKE_PREFIX_PATH=${prefix})
  file(STRINGS ${WORK_DIR}/build/CMakeCache.txt used REGEX "^ROZGEN_EXECUTABLE:")
  if(NOT used STREQUAL "ROZGEN_EXECUTABLE:FILEPATH=${prefix}/bin/rozgen")
    message(FATAL_ERROR "the consumer did not use the installed rozgen: ${used}")
  endif()
  run_shown(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
  run_shown(${WORK_DIR}/build/consumer ${WORK_DIR}/build/reach.wasm)
  if(EXISTS ${WORK_DIR}/build/reach_rs.wasm) # built where rustc has the wasm32 target
    run_shown(${WORK_DIR}/build/consumer ${WORK_DIR}/build/reach_rs.wasm)
  endif()
  if(EXISTS ${prefix}/include/roz/port/unitree_g1.h)
    run_shown(${WORK_DIR}/build/consumer_g1) # the DDS ports came with the package
  endif()
  if(EXISTS ${prefix}/include/roz/port/engineai_pm01.h)
    run_shown(${WORK_DIR}/build/consumer_ros2) # and the ROS 2 topic ports
  endif()
  if(CMAKE_HOST_SYSTEM_NAME STREQUAL "Linux") # roz::gamepad, built on every Linux
    if(NOT EXISTS ${prefix}/include/roz/gamepad.h OR NOT EXISTS ${WORK_DIR}/build/consumer_gamepad)
      message(FATAL_ERROR "the package lacks roz::gamepad (roz/gamepad.h, the target)")
    endif()
    run_shown(${WORK_DIR}/build/consumer_gamepad)
  endif()
  run_shown(${prefix}/bin/rozrun --robot ${WORK_DIR}/src/robot.toml
      --controller ${WORK_DIR}/build/reach.wasm --ticks 100
      --trace ${WORK_DIR}/run.csv --record ${WORK_DIR}/run.mcap)
  # The Python tools, from the prefix alone, on what that run wrote.
  run_shown(${prefix}/bin/roz-plot ${WORK_DIR}/run.csv ${WORK_DIR}/run.png)
  run_shown(${prefix}/bin/roz-recording check ${WORK_DIR}/run.mcap)
  run_shown(${prefix}/bin/roz-recording plot ${WORK_DIR}/run.mcap ${WORK_DIR}/run_mcap.png)
  # roz-live's layout of that run, with the installed foxglove-sdk
  run_shown(${prefix}/bin/roz-live layout ${WORK_DIR}/run.mcap ${WORK_DIR}/layout.json)
  file(READ ${WORK_DIR}/layout.json layout)
  if(NOT layout MATCHES "\"/roz/target\\.[a-z_0-9]+\"" OR NOT EXISTS ${prefix}/share/roz/layouts/ur5.json)
    message(FATAL_ERROR "the installed roz-live wrote no layout, or the install has no "
                        "share/roz/layouts/ur5.json:\n${layout}")
  endif()
  foreach(png IN ITEMS run.png run_mcap.png)
    file(READ ${WORK_DIR}/${png} magic LIMIT 8 HEX)
    if(NOT magic STREQUAL "89504e470d0a1a0a")
      message(FATAL_ERROR "the installed tools wrote no PNG ${png} (${magic})")
    endif()
  endforeach()
  run_shown(${prefix}/bin/roz_manifest_info ur5)
  # the mujoco port's built-in models, from the prefix alone (share/roz/models)
  if(EXISTS ${prefix}/share/roz/models/unitree_g1/scene.xml)
    execute_process(COMMAND ${prefix}/bin/rozrun --robot unitree_g1 --port mujoco --ticks 50
                            --controller ${WORK_DIR}/build/reach.wasm --allow-other-robot
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT err MATCHES "${prefix}/bin/../share/roz/models/unitree_g1/scene.xml"
       OR NOT out MATCHES "physics +0\\.098 s simulated.*faults +none|faults +none.*physics +0\\.098 s simulated")
      message(FATAL_ERROR "the installed rozrun on the built-in G1 in physics (${rc}):\n"
                          "${out}\n${err}")
    endif()
    foreach(f IN ITEMS unitree_g1/LICENSE universal_robots_ur5e/LICENSE
                       universal_robots_ur5e/ur5e.xml diff_drive.xml quadcopter.xml)
      if(NOT EXISTS ${prefix}/share/roz/models/${f})
        message(FATAL_ERROR "the install has no share/roz/models/${f}")
      endif()
    endforeach()
    message(STATUS "installed rozrun runs the built-in G1 on the installed model")
  endif()
  foreach(tool IN ITEMS roz_manifest_json rozgen)
    set(json_flag "")
    if(tool STREQUAL "rozgen")
      set(json_flag --json)
    endif()
    execute_process(COMMAND ${prefix}/bin/${tool} ${json_flag} ${WORK_DIR}/src/robot.toml
                    RESULT_VARIABLE rc OUTPUT_VARIABLE json_${tool} ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${tool} on the consumer's robot.toml failed (${rc}):\n${err}")
    endif()
  endforeach()
  if(NOT json_roz_manifest_json STREQUAL json_rozgen OR json_rozgen STREQUAL "")
    message(FATAL_ERROR "roz_manifest_json and rozgen --json disagree:\n"
                        "${json_roz_manifest_json}\n---\n${json_rozgen}")
  endif()
  # rozgen-urdf: a robot.toml from a URDF, which the installed rozgen accepts
  run_shown(${prefix}/bin/rozgen-urdf ${WORK_DIR}/src/lift.urdf -o ${WORK_DIR}/lift.toml)
  run_shown(${prefix}/bin/rozgen --check --strict ${WORK_DIR}/lift.toml)
  # rozgen-nn: headers from policy files torch wrote (a TorchScript archive
  # in legged_gym's exporter shape, an ONNX export), with numpy and onnx
  # from the prefix alone
  run_shown(${prefix}/bin/rozgen-nn pt --weights ${WORK_DIR}/src/lstm_exporter.pt -o ${WORK_DIR}/pt_net.h)
  run_shown(${prefix}/bin/rozgen-nn onnx --weights ${WORK_DIR}/src/gru.onnx -o ${WORK_DIR}/onnx_net.h)
  file(READ ${WORK_DIR}/pt_net.h pt_net)
  file(READ ${WORK_DIR}/onnx_net.h onnx_net)
  if(NOT pt_net MATCHES "ROZ_NN_LSTM_DEFINE\\(policy_l0, 6, 12"
     OR NOT onnx_net MATCHES "ROZ_NN_GRU_DEFINE\\(policy_l0, 5, 10")
    message(FATAL_ERROR "the installed rozgen-nn wrote unexpected headers:\n${pt_net}\n${onnx_net}")
  endif()
  message(STATUS "installed rozrun, roz_manifest_json, roz_manifest_info, rozgen, rozgen-urdf, "
                 "rozgen-nn, roz-plot, roz-recording and roz-live work")
  return()
endif()

# ---- the consumer's sources ---------------------------------------------------
if(MODE STREQUAL "find_package")
  # Outside the build tree, so that the build tree can be hidden from it.
  temp_folder(WORK_DIR consumer)
endif()
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/src)
foreach(f IN ITEMS CMakeLists.txt main.c reach.c reach.rs g1_link.c ros2_link.c gamepad_link.c
                  small_config.h)
  file(COPY ${CMAKE_CURRENT_LIST_DIR}/${f} DESTINATION ${WORK_DIR}/src)
endforeach()
file(COPY_FILE ${ROZ_SOURCE_DIR}/examples/my_arm/robot.toml ${WORK_DIR}/src/robot.toml)
file(COPY_FILE ${ROZ_SOURCE_DIR}/manifests/unitree_g1.toml ${WORK_DIR}/src/big_robot.toml)
file(COPY_FILE ${ROZ_SOURCE_DIR}/codegen/tests/data/urdf/lift.urdf ${WORK_DIR}/src/lift.urdf)
foreach(f IN ITEMS lstm_exporter.pt gru.onnx)
  file(COPY_FILE ${ROZ_SOURCE_DIR}/codegen/tests/data/nn/${f} ${WORK_DIR}/src/${f})
endforeach()

if(MODE STREQUAL "add_subdirectory" OR MODE STREQUAL "small_config")
  run_shown(${CMAKE_COMMAND} -S ${WORK_DIR}/src -B ${WORK_DIR}/build ${gen}
      -DROZGEN_EXECUTABLE=${ROZGEN_EXECUTABLE} -DROZ_CONSUMER_MODE=${MODE}
      -DROZ_SOURCE_DIR=${ROZ_SOURCE_DIR} -DROZ_WASM3_SDIST=${ROZ_WASM3_SDIST}
      -DROZ_WASM3_SOURCE_DIR=${ROZ_WASM3_SOURCE_DIR})
  run_shown(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
  run_shown(${WORK_DIR}/build/consumer ${WORK_DIR}/build/reach.wasm)
  if(EXISTS ${WORK_DIR}/build/reach_rs.wasm)
    run_shown(${WORK_DIR}/build/consumer ${WORK_DIR}/build/reach_rs.wasm)
  endif()
  if(MODE STREQUAL "small_config")
    # 145 commands in a 16-command build: the generated table must not compile
    execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build --target too_big
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(rc EQUAL 0 OR NOT "${out}${err}" MATCHES "more than ROZ_CFG_MAX_COMMANDS")
      message(FATAL_ERROR "a 145-command manifest compiled against ROZ_CFG_MAX_COMMANDS 16:\n${out}${err}")
    endif()
    message(STATUS "too_big refused at compile time, as it must be")
  endif()
  return()
elseif(NOT MODE STREQUAL "find_package")
  message(FATAL_ERROR "MODE must be find_package, add_subdirectory or small_config")
endif()

# ---- find_package, first half: install, move, scan ------------------------------
run_shown(${CMAKE_COMMAND} --install ${ROZ_BINARY_DIR} --prefix ${WORK_DIR}/stage)
file(RENAME ${WORK_DIR}/stage ${WORK_DIR}/prefix)

# What must be out of reach: the trees and the virtual environment (the folder
# above rozgen's bin/), under their own names and their real paths.
cmake_path(GET ROZGEN_EXECUTABLE PARENT_PATH venv)
cmake_path(GET venv PARENT_PATH venv)
keep_apart(HIDDEN ${WORK_DIR} ${ROZ_SOURCE_DIR} ${ROZ_BINARY_DIR} ${venv})
set(needles ${ROZ_SOURCE_DIR} ${ROZ_BINARY_DIR} ${venv} ${HIDDEN} ${WORK_DIR}/stage)
list(REMOVE_DUPLICATES needles)
file(GLOB_RECURSE installed LIST_DIRECTORIES false ${WORK_DIR}/prefix/*)
set(scanned 0)
foreach(f IN LISTS installed)
  file(READ ${f} magic LIMIT 8 HEX)
  if(magic MATCHES "^7f454c46" OR magic MATCHES "^213c617263683e") # ELF, ar: debug info
    continue()
  endif()
  file(READ ${f} text)
  foreach(n IN LISTS needles)
    string(FIND "${text}" "${n}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "${f} names ${n}: an installed roz must not depend on the tree it "
                          "was built in")
    endif()
  endforeach()
  math(EXPR scanned "${scanned} + 1")
endforeach()
foreach(must IN ITEMS bin/rozgen bin/rozrun bin/roz_manifest_json bin/roz_manifest_info
                      bin/rozgen-urdf bin/rozgen-nn bin/roz-plot bin/roz-recording bin/roz-live
                      share/roz/layouts/ur5.json
                      include/roz/sdk/roz_controller.h lib/cmake/roz/RozWasm.cmake)
  if(NOT EXISTS ${WORK_DIR}/prefix/${must})
    message(FATAL_ERROR "the install has no ${must}")
  endif()
endforeach()
message(STATUS "installed, moved; ${scanned} text files name none of: ${needles}")

# The second half runs a copy of this script: the original is in the source
# tree, which it hides.
file(COPY ${CMAKE_CURRENT_LIST_FILE} DESTINATION ${WORK_DIR}/test/consumer)
file(COPY ${CMAKE_CURRENT_LIST_DIR}/../checks.cmake DESTINATION ${WORK_DIR}/test)
set(path "")
string(REPLACE ":" ";" path_in "$ENV{PATH}")
foreach(p IN LISTS path_in)
  set(keep TRUE)
  foreach(n IN LISTS needles)
    cmake_path(IS_PREFIX n "${p}" under)
    if(under)
      set(keep FALSE)
    endif()
  endforeach()
  if(keep)
    list(APPEND path ${p})
  endif()
endforeach()
string(REPLACE ";" ":" path "${path}")
set(inner ${CMAKE_COMMAND} -E env --unset=VIRTUAL_ENV --unset=PYTHONPATH --unset=ROZGEN_EXECUTABLE
          PATH=${path}
          ${CMAKE_COMMAND} -DPHASE=installed -DWORK_DIR=${WORK_DIR} -DGENERATOR=${GENERATOR})
set(copy ${WORK_DIR}/test/consumer/run_consumer.cmake)
hiding_command(hide "${HIDDEN}")
if(hide)
  string(JOIN "|" hidden_arg ${HIDDEN})
  run_shown(${hide} ${inner} -DHIDDEN=${hidden_arg} -P ${copy})
else()
  message(STATUS "no mount namespace here (unshare -m and -rm refused): the trees stay "
                 "visible; the scan above and the sanitised environment remain")
  run_shown(${inner} -P ${copy})
endif()
file(REMOVE_RECURSE ${WORK_DIR})
