# SPDX-License-Identifier: Apache-2.0
# roz_add_library(): every library roz builds of its own sources, in one
# shape (as Zephyr's zephyr_library()):
#
#   roz_add_library(roz_<name> [SOURCES src...] [INCLUDE_DIRS dir...]
#                   [PIC ON|OFF])
#
# makes the static library roz_<name> and its ALIAS roz::<name> (the name
# find_package(roz) gives it too: EXPORT_NAME <name>), C11 without
# extensions, position-independent as PIC says (default ROZ_PIC: on hosts,
# off on bare metal), the public include directories (relative ones are
# under the calling folder) for the build tree and include/ once installed,
# and roz's warnings (roz_target_warnings). Link libraries, definitions and
# extra options stay with the caller's target_*() calls. Other target kinds
# (roz_add_port(), roz_idl_library()) build on this one.
include_guard(GLOBAL)

function(roz_add_library name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "PIC" "SOURCES;INCLUDE_DIRS")
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "roz_add_library(${name}): unknown arguments ${arg_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT name MATCHES "^roz_(.+)$")
    message(FATAL_ERROR "roz_add_library(${name}): the name must start with roz_")
  endif()
  set(export_name ${CMAKE_MATCH_1})
  if(NOT DEFINED arg_PIC)
    set(arg_PIC ${ROZ_PIC})
  endif()

  add_library(${name} STATIC ${arg_SOURCES})
  add_library(roz::${export_name} ALIAS ${name})
  set_target_properties(${name} PROPERTIES C_STANDARD 11 C_STANDARD_REQUIRED ON
                        C_EXTENSIONS OFF EXPORT_NAME ${export_name}
                        POSITION_INDEPENDENT_CODE ${arg_PIC})
  if(arg_INCLUDE_DIRS)
    set(dirs "")
    foreach(dir IN LISTS arg_INCLUDE_DIRS)
      get_filename_component(dir ${dir} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
      list(APPEND dirs $<BUILD_INTERFACE:${dir}>)
    endforeach()
    target_include_directories(${name} PUBLIC ${dirs}
                               $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  endif()
  roz_target_warnings(${name})
endfunction()
