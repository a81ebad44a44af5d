# SPDX-License-Identifier: Apache-2.0
# cmake -DQEMU=qemu-system-arm -DMACHINE=mps2-an386 -DIMAGE=image.elf
#       -DHOST=roz_fw_host -DROBOT=ur5 -DWASM=controller.wasm [-DFAULT=text]
#       [-DABSENT=symbol;... -DNM=arm-none-eabi-nm] -P run_firmware.cmake
# cmake "-DRUN=qemu-aarch64;-L;<sysroot>;<aarch64 tree>/roz_fw_host" -DMACHINE=aarch64
#       -DHOST=roz_fw_host -DROBOT=ur5 -DWASM=controller.wasm [-DFAULT=text]
#       -P run_firmware.cmake
#
# Boots the image in QEMU (-icount shift=0: one instruction per virtual
# nanosecond, the same run every time; semihosting carries its output and
# exit status) and runs the same controller, robot and tick count on the
# host. Passes when the image exits 0 (it ran as it expects: no fault and no
# value outside the manifest at the robot, or, given FAULT, a fault
# latched), and its report agrees with the host's line by line (verify,
# run, fault, violations, fingerprint), and, given FAULT, its fault message
# is exactly "fault: FAULT"; without FAULT there must be none. Given ABSENT,
# none of those symbols may be linked into the image (an image with its
# controller compiled ahead of time links no interpreter). Given RUN
# instead of QEMU and IMAGE, the target is a hosted program of another ISA
# (the application built for aarch64 Linux, under QEMU user mode) that
# takes ROBOT and WASM as the host's does (test/aarch64/).
cmake_minimum_required(VERSION 3.25)

if(ABSENT)
  execute_process(COMMAND ${NM} ${IMAGE} RESULT_VARIABLE rc OUTPUT_VARIABLE syms
                  ERROR_VARIABLE syms)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${NM} ${IMAGE} failed (${rc}): ${syms}")
  endif()
  foreach(sym IN LISTS ABSENT)
    if(syms MATCHES " ${sym}(\\.[^\n]*)?\n")
      message(FATAL_ERROR "${IMAGE} links ${sym}, which it must not")
    endif()
  endforeach()
endif()

if(RUN)
  set(target_cmd ${RUN} ${ROBOT} ${WASM})
  list(GET RUN -1 IMAGE)
else()
  set(target_cmd ${QEMU} -M ${MACHINE} -nographic -monitor none -serial none
                 -semihosting-config enable=on,target=native -icount shift=0 -kernel ${IMAGE})
endif()
execute_process(COMMAND ${target_cmd}
                RESULT_VARIABLE rc OUTPUT_VARIABLE fw ERROR_VARIABLE fw TIMEOUT 120)
message(STATUS "${MACHINE}:\n${fw}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${IMAGE} exited with ${rc} under ${MACHINE}")
endif()
if(NOT RUN AND NOT fw MATCHES "\nresult: as expected\n")
  message(FATAL_ERROR "${IMAGE}: no 'result: as expected' line")
endif()

execute_process(COMMAND ${HOST} ${ROBOT} ${WASM}
                RESULT_VARIABLE rc OUTPUT_VARIABLE host ERROR_VARIABLE host_err TIMEOUT 120)
message(STATUS "host:\n${host}${host_err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${HOST} ${ROBOT} ${WASM} exited with ${rc}")
endif()

# the lines both must print alike, in order
function(report text out)
  string(REGEX MATCHALL "(^|\n)(verify|run|fault|violations|fingerprint): [^\n]*" lines "${text}")
  list(TRANSFORM lines STRIP)
  set(${out} "${lines}" PARENT_SCOPE)
endfunction()
report("${fw}" fw_lines)
report("${host}" host_lines)
list(LENGTH fw_lines n)
if(n LESS 4)
  message(FATAL_ERROR "${IMAGE}: its report is incomplete (${n} lines)")
endif()
if(NOT fw_lines STREQUAL host_lines)
  string(REPLACE ";" "\n  " a "${fw_lines}")
  string(REPLACE ";" "\n  " b "${host_lines}")
  message(FATAL_ERROR "the image and the host disagree:\n${MACHINE}:\n  ${a}\nhost:\n  ${b}")
endif()
if(NOT fw MATCHES "\nfingerprint: [0-9a-f]+\n")
  message(FATAL_ERROR "${IMAGE}: no fingerprint")
endif()

string(FIND "${fw}" "\nfault: " has_fault)
if(FAULT)
  string(FIND "${fw}" "\nfault: ${FAULT}\n" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${IMAGE}: expected the fault message exactly 'fault: ${FAULT}'")
  endif()
elseif(NOT has_fault EQUAL -1)
  message(FATAL_ERROR "${IMAGE}: a fault latched where none may")
endif()
message(STATUS "${IMAGE}: as the host, bit for bit")
