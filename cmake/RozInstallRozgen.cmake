# SPDX-License-Identifier: Apache-2.0
#
# Installs rozgen with roz, so that an installed roz builds robot tables with
# nothing from the tree it was built in (no virtual environment, no source):
#   <prefix>/lib/roz/python/  rozgen's package (codegen/rozgen) and its pinned,
#                             hash-checked run-time dependencies
#                             (codegen/requirements.txt: jinja2, markupsafe;
#                             codegen/requirements-nn.txt: numpy, onnx and
#                             theirs, for rozgen-nn), which pip puts there at
#                             install time
#   <prefix>/bin/rozgen       a launcher that runs rozgen from ../lib/roz/python
#                             (and bin/rozgen-urdf, rozgen's URDF importer, and
#                             bin/rozgen-nn, networks to roz_nn.h headers)
#                             with the Python it was installed for
#                             (ROZ_ROZGEN_PYTHON)
# The dependencies' wheels come from the folder ROZ_PYTHON_WHEELS without a
# network (tools/setup.sh fills .cache/wheels, the default when it exists),
# else from the package index. ROZ_INSTALL_ROZGEN=OFF leaves rozgen out: an
# installed roz then looks for rozgen on PATH (`pip install codegen/`).
#
# The Python tools come the same way (ROZ_INSTALL_TOOLS, with rozgen):
#   <prefix>/lib/roz/python/roz_tools/  tools/plot_trace.py (and its tracking.py),
#                                       tools/recording.py,
#                                       tools/live.py, tools/mcap_chunks.py,
#                                       tools/campaign.py (and its
#                                       campaign_report.py)
#   <prefix>/bin/roz-plot, roz-recording, roz-live, roz-campaign
#                                       launchers that run them, as bin/rozgen
#                                       runs rozgen
#   <prefix>/share/roz/layouts/         the Foxglove layouts of tools/layouts/
# with their pinned dependencies (tools/requirements-run.txt: matplotlib, mcap,
# foxglove-sdk and theirs) in lib/roz/python too.
option(ROZ_INSTALL_ROZGEN "Install rozgen and its pinned Python dependencies with roz" ON)
if(NOT ROZ_INSTALL_ROZGEN)
  return()
endif()
option(ROZ_INSTALL_TOOLS
       "Install roz-plot, roz-recording and roz-live (tools/) and their pinned Python dependencies" ON)

if(NOT DEFINED CACHE{ROZ_PYTHON_WHEELS} AND EXISTS ${PROJECT_SOURCE_DIR}/.cache/wheels)
  set(_roz_wheels ${PROJECT_SOURCE_DIR}/.cache/wheels)
else()
  set(_roz_wheels "")
endif()
set(ROZ_PYTHON_WHEELS "${_roz_wheels}" CACHE PATH
    "Folder with the wheels of codegen/requirements.txt, installed offline with rozgen (empty: the package index)")

# The interpreter the launcher names. A virtual environment's python lives in
# a build or source tree, so the default is the interpreter behind it.
if(NOT ROZ_ROZGEN_PYTHON)
  set(_roz_py "${ROZ_PYTHON}")
  if(NOT _roz_py)
    find_package(Python3 3.11 COMPONENTS Interpreter)
    set(_roz_py "${Python3_EXECUTABLE}")
  endif()
  if(_roz_py)
    execute_process(
      COMMAND ${_roz_py} -c "import sys; print(getattr(sys, '_base_executable', '') or sys.executable)"
      OUTPUT_VARIABLE _roz_py OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE _rc)
    if(NOT _rc EQUAL 0)
      set(_roz_py "")
    endif()
  endif()
  set(ROZ_ROZGEN_PYTHON "${_roz_py}" CACHE FILEPATH
      "Python 3.11 or later that runs the installed rozgen (not a virtual environment's)")
endif()
execute_process(COMMAND ${ROZ_ROZGEN_PYTHON} -c "import sys; sys.exit(sys.version_info < (3, 11))"
                RESULT_VARIABLE _rc OUTPUT_QUIET ERROR_QUIET)
if(NOT ROZ_ROZGEN_PYTHON OR NOT _rc EQUAL 0)
  message(FATAL_ERROR "ROZ_ROZGEN_PYTHON='${ROZ_ROZGEN_PYTHON}': the installed rozgen needs "
                      "Python 3.11 or later with pip. Name one with -DROZ_ROZGEN_PYTHON=..., or "
                      "pass -DROZ_INSTALL_ROZGEN=OFF and install rozgen yourself (pip install codegen/).")
endif()

set(_roz_pydir ${CMAKE_INSTALL_LIBDIR}/roz/python)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/codegen/rozgen DESTINATION ${_roz_pydir}
        FILES_MATCHING PATTERN "*.py" PATTERN "*.j2" PATTERN "__pycache__" EXCLUDE)

# The launcher finds the package relative to itself, so the prefix can move.
cmake_path(ABSOLUTE_PATH CMAKE_INSTALL_BINDIR BASE_DIRECTORY /prefix OUTPUT_VARIABLE _bin)
cmake_path(ABSOLUTE_PATH _roz_pydir BASE_DIRECTORY /prefix OUTPUT_VARIABLE _py)
file(RELATIVE_PATH ROZ_ROZGEN_PYDIR_FROM_BIN ${_bin} ${_py})
# rozgen-urdf (URDF to robot.toml) needs nothing more than rozgen; rozgen-nn
# (policy files to roz_nn.h headers) needs codegen/requirements-nn.txt too.
# roz__install_launcher(TEMPLATE NAME): bin/NAME, TEMPLATE (here) configured
# with the caller's @VARIABLES@.
function(roz__install_launcher template name)
  configure_file(${CMAKE_CURRENT_LIST_DIR}/${template} ${PROJECT_BINARY_DIR}/roz_install/${name} @ONLY)
  install(PROGRAMS ${PROJECT_BINARY_DIR}/roz_install/${name} DESTINATION ${CMAKE_INSTALL_BINDIR})
endfunction()
foreach(_cmd IN ITEMS "rozgen;cli" "rozgen-urdf;urdf" "rozgen-nn;nn")
  list(GET _cmd 0 ROZ_ROZGEN_COMMAND)
  list(GET _cmd 1 ROZ_ROZGEN_MODULE)
  roz__install_launcher(rozgen.py.in ${ROZ_ROZGEN_COMMAND})
endforeach()

set(_roz_requirements "-r \"${PROJECT_SOURCE_DIR}/codegen/requirements.txt\" -r \"${PROJECT_SOURCE_DIR}/codegen/requirements-nn.txt\"")
set(_roz_requirements_what "codegen/requirements.txt, codegen/requirements-nn.txt")
if(ROZ_INSTALL_TOOLS)
  # recording.py finds plot_trace.py beside itself, as in tools/.
  install(FILES ${PROJECT_SOURCE_DIR}/tools/plot_trace.py ${PROJECT_SOURCE_DIR}/tools/recording.py
                ${PROJECT_SOURCE_DIR}/tools/live.py ${PROJECT_SOURCE_DIR}/tools/mcap_chunks.py
                ${PROJECT_SOURCE_DIR}/tools/campaign.py ${PROJECT_SOURCE_DIR}/tools/campaign_report.py
                ${PROJECT_SOURCE_DIR}/tools/tracking.py
          DESTINATION ${_roz_pydir}/roz_tools)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/tools/layouts/ DESTINATION ${CMAKE_INSTALL_DATADIR}/roz/layouts
          FILES_MATCHING PATTERN "*.json")
  foreach(_tool IN ITEMS "roz-plot;plot_trace.py" "roz-recording;recording.py" "roz-live;live.py"
                       "roz-campaign;campaign.py")
    list(GET _tool 0 ROZ_TOOL_NAME)
    list(GET _tool 1 ROZ_TOOL_FILE)
    roz__install_launcher(roz_tool.py.in ${ROZ_TOOL_NAME})
  endforeach()
  string(APPEND _roz_requirements " -r \"${PROJECT_SOURCE_DIR}/tools/requirements-run.txt\"")
  string(APPEND _roz_requirements_what ", tools/requirements-run.txt")
endif()

# The dependencies: pip, at install time, into the same folder (DESTDIR is
# honoured). What pip wrote is added to install_manifest.txt.
set(_roz_index_args "")
if(ROZ_PYTHON_WHEELS)
  set(_roz_index_args "--no-index --find-links \"${ROZ_PYTHON_WHEELS}\"")
endif()
set(_roz_install_deps [=[
  set(_dest "@_roz_pydir@")
  if(NOT IS_ABSOLUTE "${_dest}")
    set(_dest "${CMAKE_INSTALL_PREFIX}/${_dest}")
  endif()
  set(_dest "$ENV{DESTDIR}${_dest}")
  message(STATUS "Installing: the Python dependencies (@_roz_requirements_what@) to ${_dest}")
  execute_process(
    COMMAND "@ROZ_ROZGEN_PYTHON@" -m pip install --quiet --disable-pip-version-check
            --root-user-action=ignore --no-cache-dir --no-compile --no-deps --only-binary :all:
            --require-hashes --upgrade @_roz_index_args@
            --target "${_dest}" @_roz_requirements@
    RESULT_VARIABLE _rc ERROR_VARIABLE _err)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "installing the Python dependencies with @ROZ_ROZGEN_PYTHON@ -m pip "
      "failed:\n${_err}\nWheels came from: @ROZ_PYTHON_WHEELS@ (empty: the package index). "
      "Run tools/setup.sh (it downloads them into .cache/wheels) and configure with "
      "-DROZ_PYTHON_WHEELS=<that folder>, or -DROZ_INSTALL_ROZGEN=OFF.")
  endif()
  file(GLOB _tops LIST_DIRECTORIES true "${_dest}/*")
  foreach(_top IN LISTS _tops)
    cmake_path(GET _top FILENAME _name)
    if(_name STREQUAL "rozgen" OR _name STREQUAL "roz_tools") # install() listed roz's own
    elseif(IS_DIRECTORY "${_top}")
      file(GLOB_RECURSE _files LIST_DIRECTORIES false "${_top}/*")
      list(APPEND CMAKE_INSTALL_MANIFEST_FILES ${_files})
    else()
      list(APPEND CMAKE_INSTALL_MANIFEST_FILES "${_top}")
    endif()
  endforeach()
]=])
string(CONFIGURE "${_roz_install_deps}" _roz_install_deps @ONLY)
install(CODE "${_roz_install_deps}")
