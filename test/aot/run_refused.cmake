# SPDX-License-Identifier: Apache-2.0
# rozaot on a module roz refuses: a non-zero exit, the file and the reason
# named, and nothing written for wasm2c.
file(REMOVE ${OUT}.wasm ${OUT}.c)
execute_process(COMMAND ${ROZAOT} refused ${WASM} ${OUT}.wasm ${OUT}.c
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "rozaot compiled a module roz refuses: ${WASM}")
endif()
if(NOT err MATCHES "bad_unknown_import.wasm: refused: unknown import env.open_valve")
  message(FATAL_ERROR "rozaot's message does not name the file and the import: ${err}")
endif()
if(EXISTS ${OUT}.wasm OR EXISTS ${OUT}.c)
  message(FATAL_ERROR "rozaot wrote output for a refused module")
endif()
