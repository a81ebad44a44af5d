# SPDX-License-Identifier: Apache-2.0
# rozrun and the robot a controller was built for, end to end:
#   cmake -DROZRUN=<rozrun> -DROZGEN=<rozgen> -DCTL=<example controllers>
#         -DPAN_TILT_CTL=<identity_pan_tilt_sweep.wasm> -DFIXTURES=<test/identity>
#         [-DOBJDUMP=<wasm-objdump>] [-DTOML=1] -P run_rozrun_identity.cmake
# - wasm-objdump -x lists the custom section "roz.manifest" of the pan-tilt
#   controller, holding the record rozgen's identity gives;
# - on a UR5 it is refused (exit 2), the message naming both robots and
#   hashes, and so is a swap to it during a run; with --allow-other-robot it
#   runs (exit 0) and the summary says so;
# - on its own robot.toml (read by the C loader) it runs, "this robot"; on the
#   same robot after an edit of its channel table it is refused as changed;
# - a controller without identity runs, with a note in the summary.

function(identity toml out_id out_hash)
  execute_process(COMMAND ${ROZGEN} --identity ${toml} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "^([a-z0-9_]+) ([0-9a-f]+)\n$")
    message(FATAL_ERROR "rozgen --identity ${toml}: exit ${rc}\n${out}${err}")
  endif()
  set(${out_id} ${CMAKE_MATCH_1} PARENT_SCOPE)
  set(${out_hash} ${CMAKE_MATCH_2} PARENT_SCOPE)
endfunction()

function(rozrun want_rc)
  execute_process(COMMAND ${ROZRUN} ${ARGN} --ticks 50 RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL want_rc)
    message(FATAL_ERROR "rozrun ${ARGN}: exit ${rc}, expected ${want_rc}\n${out}${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
  set(err "${err}" PARENT_SCOPE)
endfunction()

function(expect text what)
  string(FIND "${text}" "${what}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "expected \"${what}\" in:\n${text}")
  endif()
endfunction()

identity(${FIXTURES}/pan_tilt.toml pt_id pt_hash)
identity(${FIXTURES}/../../manifests/ur5.toml ur5_id ur5_hash)

# the section as wabt sees it: version 1, 8 bytes "pan_tilt", the hash LE
if(OBJDUMP)
  execute_process(COMMAND ${OBJDUMP} -x ${PAN_TILT_CTL} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "Custom:\n - name: \"roz.manifest\"")
    message(FATAL_ERROR "wasm-objdump -x ${PAN_TILT_CTL}: no custom section roz.manifest\n${out}")
  endif()
  execute_process(COMMAND ${OBJDUMP} -s -j roz.manifest ${PAN_TILT_CTL} OUTPUT_VARIABLE out)
  string(REGEX MATCHALL "[0-9a-f]+: ([0-9a-f ]+)  " rows "${out}")
  set(hex "")
  foreach(row IN LISTS rows)
    string(REGEX REPLACE "^[0-9a-f]+: " "" row "${row}")
    string(REPLACE " " "" row "${row}")
    string(APPEND hex "${row}")
  endforeach()
  set(le "")
  foreach(i RANGE 14 0 -2)
    string(SUBSTRING ${pt_hash} ${i} 2 byte)
    string(APPEND le ${byte})
  endforeach()
  # the section's name (length 12, "roz.manifest"), then the record
  string(HEX "roz.manifest" name_hex)
  string(HEX "pan_tilt" id_hex)
  set(want "0c${name_hex}0108${id_hex}${le}")
  if(NOT hex STREQUAL want)
    message(FATAL_ERROR "roz.manifest holds ${hex}, expected ${want}\n${out}")
  endif()
endif()

rozrun(2 --robot ur5 --controller ${PAN_TILT_CTL})
expect("${err}" "load: controller built for robot 'pan_tilt' (hash ${pt_hash}), this robot is 'ur5' (hash ${ur5_hash})")
expect("${err}" "--allow-other-robot runs it anyway")

rozrun(0 --robot ur5 --controller ${PAN_TILT_CTL} --allow-other-robot)
expect("${out}" "built for              pan_tilt (hash ${pt_hash}): another robot, allowed by --allow-other-robot")
expect("${out}" "faults                 none")

rozrun(0 --robot ur5 --controller ${CTL}/pd_hold.wasm)
expect("${out}" "built for              ur5 (hash ${ur5_hash}): this robot")

# a swap to it during a run is refused the same way; the UR5's controller stays
rozrun(0 --robot ur5 --controller ${CTL}/pd_hold.wasm --swap-at 20:${PAN_TILT_CTL})
expect("${err}" "refused, the running controller stays: load: controller built for robot 'pan_tilt' (hash ${pt_hash}), this robot is 'ur5' (hash ${ur5_hash})")
expect("${out}" "swaps 0, 1 refused")

rozrun(0 --robot ur5 --controller ${CTL}/sine.wasm)
expect("${out}" "built for              unknown: the controller carries no robot identity")

if(TOML)
  rozrun(0 --robot ${FIXTURES}/pan_tilt.toml --controller ${PAN_TILT_CTL})
  expect("${out}" "built for              pan_tilt (hash ${pt_hash}): this robot")
  identity(${FIXTURES}/pan_tilt_wider.toml wider_id wider_hash)
  rozrun(2 --robot ${FIXTURES}/pan_tilt_wider.toml --controller ${PAN_TILT_CTL})
  expect("${err}" "controller built for robot 'pan_tilt' (hash ${pt_hash}) before its channel table changed: this robot's table has hash ${wider_hash}")
  rozrun(0 --robot ${FIXTURES}/pan_tilt_wider.toml --controller ${PAN_TILT_CTL} --allow-other-robot)
  expect("${out}" "(hash ${pt_hash}): an older channel table, allowed by --allow-other-robot")
endif()
