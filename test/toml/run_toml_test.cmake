# SPDX-License-Identifier: Apache-2.0
# toml-test, the official TOML test suite, against roz's reader:
#   cmake -DTOML_TEST=<toml-test> -DDECODER=<roz_toml_decoder> -DSKIP_FILE=<toml-test.skip>
#         -P run_toml_test.cmake
# Every valid case must decode to the expected JSON and every invalid one be
# refused, except the cases of the skip list (printed first). Skipped (by
# the ctest property SKIP_REGULAR_EXPRESSION) when tools/setup.sh could not
# build toml-test, which needs Go.
if(NOT EXISTS "${TOML_TEST}")
  message("toml-test is not installed at ${TOML_TEST}: run tools/setup.sh (it needs Go 1.19+)")
  return()
endif()

file(STRINGS ${SKIP_FILE} lines)
set(skip_args "")
set(skip_list "")
foreach(line IN LISTS lines)
  string(REGEX REPLACE "#.*$" "" line "${line}")
  string(STRIP "${line}" line)
  if(NOT line STREQUAL "")
    list(APPEND skip_args -skip ${line})
    string(APPEND skip_list "\n  ${line}")
  endif()
endforeach()
if(skip_list STREQUAL "")
  set(skip_list " (none)")
endif()
message("toml-test skip list (${SKIP_FILE}):${skip_list}")

# -timeout: a case's own hang guard; toml-test's 1 s default failed cases of
# the sanitizer builds on a loaded machine, and 30 s still catches a loop
execute_process(COMMAND ${TOML_TEST} -toml 1.0.0 -color never -timeout 30s ${skip_args} -- ${DECODER}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "toml-test: cases failed outside the skip list (exit ${rc})")
endif()
