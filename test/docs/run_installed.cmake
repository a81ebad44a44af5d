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

include(${CMAKE_CURRENT_LIST_DIR}/../checks.cmake)

# set after test/ is configured (cmake/RozInstallRozgen.cmake): read at run time
file(STRINGS ${ROZ_BINARY_DIR}/CMakeCache.txt python REGEX "^ROZ_ROZGEN_PYTHON:")
string(REGEX REPLACE "^[^=]*=" "" PYTHON "${python}")
if(NOT PYTHON)
  message(FATAL_ERROR "no ROZ_ROZGEN_PYTHON in ${ROZ_BINARY_DIR}/CMakeCache.txt")
endif()

temp_folder(dir getting_started)

keep_apart(hidden ${dir} ${ROZ_SOURCE_DIR} ${ROZ_BINARY_DIR} ${VENV})

file(REMOVE_RECURSE ${dir})
run_shown(${CMAKE_COMMAND} --install ${ROZ_BINARY_DIR} --prefix ${dir}/prefix)
file(COPY ${CMAKE_CURRENT_LIST_DIR}/doc_blocks.py DESTINATION ${dir})
cmake_path(GET PAGE PARENT_PATH page_dir)
file(COPY ${ROZ_SOURCE_DIR}/${PAGE} DESTINATION ${dir}/pages/${page_dir})

set(forbid "")
foreach(h IN LISTS hidden)
  list(APPEND forbid --forbid ${h})
endforeach()
set(blocks ${PYTHON} ${dir}/doc_blocks.py --source ${dir}/pages --work ${dir}/work
           --installed ${dir}/prefix ${forbid} ${PAGE})

hiding_command(hide "${hidden}")
if(hide)
  run_shown(${hide} ${blocks})
else()
  message(STATUS "no mount namespace here (unshare -m and -rm refused): the trees stay "
                 "visible; PATH and the blocks' texts are still checked")
  run_shown(${blocks})
endif()
file(REMOVE_RECURSE ${dir})
