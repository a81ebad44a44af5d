# SPDX-License-Identifier: Apache-2.0
# The checks the end-to-end test scripts (cmake -P) share; a script
# includes this file from its own folder:
#   include(${CMAKE_CURRENT_LIST_DIR}/checks.cmake)

# expect_in(TEXT WANT WHAT): fails, showing TEXT, unless WANT is in it.
function(expect_in text want what)
  string(FIND "${text}" "${want}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${what} lacks \"${want}\":\n${text}")
  endif()
endfunction()

# expect(MESSAGE CONDITION...): fails with MESSAGE unless if(CONDITION) holds.
function(expect what)
  if(NOT (${ARGN}))
    message(FATAL_ERROR "${what}")
  endif()
endfunction()

# expect_error(ARGS WANT): ROZRUN ARGS (a list) exits 2, WANT in its stderr.
function(expect_error args want)
  execute_process(COMMAND ${ROZRUN} ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 2)
    message(FATAL_ERROR "rozrun ${args}: exit ${rc}, expected 2\n${out}${err}")
  endif()
  expect_in("${err}" "${want}" "rozrun ${args}: stderr")
endfunction()
