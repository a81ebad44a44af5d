# SPDX-License-Identifier: Apache-2.0
# cmake -DROZ_SOURCE_DIR=... -DROZ_BINARY_DIR=... -DVENV=... -DPAGE=docs/x.md
#       -P run_installed.cmake
#
# The docs_getting_started test: PAGE's getting_started blocks, run as a user
# runs them after `make install`. The build is installed into a temporary
# prefix outside the trees; doc_blocks.py and PAGE are copied beside it, and
# run there by the Python the installed tools run on (ROZ_ROZGEN_PYTHON,
# outside the virtual environment) with
# --installed: an empty working folder, the prefix's bin/ on PATH and
# nothing of the source tree, the build tree or VENV on it. Where a mount
# namespace is permitted, those three are hidden under empty tmpfs mounts as
# well (as test/consumer/run_consumer.cmake hides them), so a block that
# reached into them fails. The folder is removed when the test passes, kept
# for a look when it fails.
cmake_minimum_required(VERSION 3.25)

function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGV}\n${err}")
  endif()
endfunction()

# set after test/ is configured (cmake/RozInstallRozgen.cmake): read at run time
file(STRINGS ${ROZ_BINARY_DIR}/CMakeCache.txt python REGEX "^ROZ_ROZGEN_PYTHON:")
string(REGEX REPLACE "^[^=]*=" "" PYTHON "${python}")
if(NOT PYTHON)
  message(FATAL_ERROR "no ROZ_ROZGEN_PYTHON in ${ROZ_BINARY_DIR}/CMakeCache.txt")
endif()

if(DEFINED ENV{TMPDIR})
  set(tmp $ENV{TMPDIR})
else()
  set(tmp /tmp)
endif()
string(RANDOM LENGTH 8 ALPHABET abcdefghijklmnopqrstuvwxyz0123456789 tag)
set(dir ${tmp}/roz_getting_started_${tag})

set(hidden "")
foreach(d IN ITEMS ${ROZ_SOURCE_DIR} ${ROZ_BINARY_DIR} ${VENV})
  file(REAL_PATH ${d} real)
  list(APPEND hidden ${real})
  cmake_path(IS_PREFIX real ${dir} under)
  if(under)
    message(FATAL_ERROR "${dir} is inside ${real}, which the test hides; set TMPDIR elsewhere")
  endif()
endforeach()
list(REMOVE_DUPLICATES hidden)

file(REMOVE_RECURSE ${dir})
run(${CMAKE_COMMAND} --install ${ROZ_BINARY_DIR} --prefix ${dir}/prefix)
file(COPY ${CMAKE_CURRENT_LIST_DIR}/doc_blocks.py DESTINATION ${dir})
cmake_path(GET PAGE PARENT_PATH page_dir)
file(COPY ${ROZ_SOURCE_DIR}/${PAGE} DESTINATION ${dir}/pages/${page_dir})

set(forbid "")
foreach(h IN LISTS hidden)
  list(APPEND forbid --forbid ${h})
endforeach()
set(blocks ${PYTHON} ${dir}/doc_blocks.py --source ${dir}/pages --work ${dir}/work
           --installed ${dir}/prefix ${forbid} ${PAGE})

# sh -c "$script" sh N DIR1..DIRN COMMAND...: each DIR under an empty tmpfs
# (one inside another already hidden is gone: skipped), then COMMAND.
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
list(LENGTH hidden n_hidden)
set(ns "")
foreach(flags IN ITEMS -m -rm)
  execute_process(COMMAND unshare ${flags} sh -c "${script}" sh ${n_hidden} ${hidden} true
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(rc EQUAL 0)
    set(ns ${flags})
    break()
  endif()
endforeach()
if(ns)
  string(JOIN " " shown ${hidden})
  message(STATUS "hiding ${shown} (unshare ${ns})")
  run(unshare ${ns} sh -c "${script}" sh ${n_hidden} ${hidden} ${blocks})
else()
  message(STATUS "no mount namespace here (unshare -m and -rm refused): the trees stay "
                 "visible; PATH and the blocks' texts are still checked")
  run(${blocks})
endif()
file(REMOVE_RECURSE ${dir})
