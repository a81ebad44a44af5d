# SPDX-License-Identifier: Apache-2.0
# rozaot checks a module against the limits of the build it compiles it
# into, not only its own: LIMITS_C (roz_add_aot_controller()'s template)
# preprocessed with a firmware's configuration (CONFIG_DIR/CONFIG: one page
# of memory, no bulk imports), then three modules. The host's rozaot
# accepts all three without those limits.
set(limits ${OUT}/target_limits.txt)
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${CC} -E -P -DROZ_CONFIG_FILE="${CONFIG}" -I${CONFIG_DIR} -I${INCLUDE}
                        -I${BUILD_INCLUDE} ${LIMITS_C} -o ${limits}
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "preprocessing the limits with ${CONFIG}: ${err}")
endif()

# run(<wasm> <expected message, or "" for accepted>)
function(run wasm expect)
  get_filename_component(stem ${wasm} NAME_WE)
  set(o ${OUT}/${stem})
  file(REMOVE ${o}.wasm ${o}.c)
  # without the firmware's limits: the host's own, which accept it
  execute_process(COMMAND ${ROZAOT} ${stem} ${wasm} ${o}.wasm ${o}.c
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "rozaot refused ${wasm} with the host's limits: ${err}")
  endif()
  file(REMOVE ${o}.wasm ${o}.c)
  execute_process(COMMAND ${ROZAOT} --limits ${limits} ${stem} ${wasm} ${o}.wasm ${o}.c
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(expect STREQUAL "")
    if(NOT rc EQUAL 0 OR NOT EXISTS ${o}.c)
      message(FATAL_ERROR "rozaot refused ${wasm} within ${CONFIG}'s limits: ${err}")
    endif()
    return()
  endif()
  if(rc EQUAL 0)
    message(FATAL_ERROR "rozaot compiled ${wasm}, which ${CONFIG}'s build refuses")
  endif()
  string(FIND "${err}" "${stem}.wasm: refused for the build it is compiled into: ${expect}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "rozaot's message for ${wasm} does not say why: ${err}")
  endif()
  if(EXISTS ${o}.wasm OR EXISTS ${o}.c)
    message(FATAL_ERROR "rozaot wrote output for ${wasm}, refused")
  endif()
endfunction()

run(${TWO_PAGES} "linear memory too large: 2 pages of 64 KiB, more than ROZ_CFG_WASM_MAX_PAGES (1)")
run(${BULK} "import state.get_all: left out of this build of roz (ROZ_CFG_BULK_IMPORTS is 0)")
run(${FITS} "")
