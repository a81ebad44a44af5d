# SPDX-License-Identifier: Apache-2.0
# The checks and steps the end-to-end test scripts (cmake -P) share; a
# script includes this file from its own folder, or the one above it:
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

# run(COMMAND...): runs it; fails, showing its output, unless it exits 0.
function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGV}\n${out}")
  endif()
endfunction()

# run_shown(COMMAND...): run(), its standard output shown as a status line
# (a program's report in the test's log) and its standard error on failure.
function(run_shown)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGV}\n${err}")
  endif()
endfunction()

# generator_args(VAR): VAR is -G GENERATOR where the script was given a
# GENERATOR (cmake's own choice otherwise), for a configure step.
function(generator_args var)
  set(args "")
  if(GENERATOR)
    set(args -G ${GENERATOR})
  endif()
  set(${var} ${args} PARENT_SCOPE)
endfunction()

# temp_folder(VAR NAME): VAR is a new folder's path, roz_NAME_<random> in
# TMPDIR (or /tmp), outside the trees a test builds from: a script works
# there as a user would, removes it when it passes and keeps it when it fails.
function(temp_folder var name)
  if(DEFINED ENV{TMPDIR})
    set(tmp $ENV{TMPDIR})
  else()
    set(tmp /tmp)
  endif()
  string(RANDOM LENGTH 8 ALPHABET abcdefghijklmnopqrstuvwxyz0123456789 tag)
  set(${var} ${tmp}/roz_${name}_${tag} PARENT_SCOPE)
endfunction()

# keep_apart(VAR DIR PATH...): VAR is the PATHs' real paths, each once;
# fails unless the temporary folder DIR is outside all of them.
function(keep_apart var dir)
  set(reals "")
  foreach(p IN LISTS ARGN)
    file(REAL_PATH ${p} real)
    list(APPEND reals ${real})
    cmake_path(IS_PREFIX real ${dir} under)
    if(under)
      message(FATAL_ERROR "the temporary folder ${dir} is inside ${real}, which the test must "
                          "stay out of; set TMPDIR elsewhere")
    endif()
  endforeach()
  list(REMOVE_DUPLICATES reals)
  set(${var} ${reals} PARENT_SCOPE)
endfunction()

# hiding_command(VAR DIRS): VAR is a command prefix that runs the command
# after it with each of DIRS (a list) hidden under an empty tmpfs mount (a
# folder inside one already hidden is gone: skipped), where this machine
# permits a mount namespace (unshare -m, else -rm); empty where it does not.
function(hiding_command var dirs)
  # sh -c "$script" sh N DIR1..DIRN COMMAND...
  # No semicolons: run() passes it on as a CMake list.
  set(script [=[
n=$1
shift
while [ "$n" -gt 0 ]
do
  if [ -d "$1" ]
  then mount -t tmpfs -o size=64k roz-hidden "$1" || exit 1
  fi
  shift
  n=$((n-1))
done
exec "$@"
]=])
  list(LENGTH dirs n)
  foreach(flags IN ITEMS -m -rm)
    execute_process(COMMAND unshare ${flags} sh -c "${script}" sh ${n} ${dirs} true
                    RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
    if(rc EQUAL 0)
      string(JOIN " " shown ${dirs})
      message(STATUS "hiding ${shown} (unshare ${flags})")
      set(${var} unshare ${flags} sh -c "${script}" sh ${n} ${dirs} PARENT_SCOPE)
      return()
    endif()
  endforeach()
  set(${var} "" PARENT_SCOPE)
endfunction()
