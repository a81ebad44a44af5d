# SPDX-License-Identifier: Apache-2.0
#
# wasm3 0.5.0, built from its C sources as its own static library target
# (roz_wasm3) with its own flags: never roz's warnings, never -Werror. roz
# links it PRIVATE, so no wasm3 header reaches roz's public headers.
#
# Where the sources come from, in order:
#   ROZ_WASM3_SOURCE_DIR  any wasm3 source tree (the folder holding wasm3.h)
#   ROZ_WASM3_SDIST       the pywasm3 0.5.0 source distribution, as fetched by
#                         tools/setup.sh; its sha256 is checked here and the
#                         build stops on a mismatch; its wasm3/ folder is the
#                         wasm3 0.5.0 core.
set(ROZ_WASM3_SOURCE_DIR "" CACHE PATH "wasm3 source tree (folder with wasm3.h); overrides ROZ_WASM3_SDIST")
set(ROZ_WASM3_SDIST "" CACHE FILEPATH "pywasm3-0.5.0.tar.gz (wasm3 0.5.0 sources, sha256-checked)")
set(ROZ_WASM3_SDIST_SHA256 5a47c8a39f7f6ae71b3316b2e5d86c9d0db6e771a65f09a86e4d4aa3a19aefcc)

# roz's own patches (cmake/wasm3/*.patch, one concern each, applied in name
# order) meter the work a controller does, guard wasm3 0.5.0's known
# memory-safety bugs and make its integer ops well-defined; each file's
# header says what it changes and why. They are applied to a copy in the
# build tree, never to the source it came from; the copy is keyed by a hash
# of the whole series, so editing a patch rebuilds wasm3.
file(GLOB _roz_patches CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/wasm3/*.patch)
list(SORT _roz_patches)
set(_roz_patch_cat "")
foreach(_p IN LISTS _roz_patches)
  file(SHA256 ${_p} _h)
  string(APPEND _roz_patch_cat "${_h}")
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_p})
endforeach()
string(SHA256 _roz_patch_sha "${_roz_patch_cat}")
string(SUBSTRING ${_roz_patch_sha} 0 12 _roz_patch_sha)
find_program(ROZ_PATCH_EXECUTABLE patch DOC "patch, to apply cmake/wasm3/*.patch")
if(NOT ROZ_PATCH_EXECUTABLE)
  message(FATAL_ERROR "the 'patch' program is needed to apply cmake/wasm3/*.patch "
                      "(Debian package patch; tools/setup.sh installs it)")
endif()

if(ROZ_WASM3_SOURCE_DIR)
  if(NOT EXISTS ${ROZ_WASM3_SOURCE_DIR}/wasm3.h)
    message(FATAL_ERROR "ROZ_WASM3_SOURCE_DIR: no wasm3.h in ${ROZ_WASM3_SOURCE_DIR}")
  endif()
  string(SHA256 _roz_key "${ROZ_WASM3_SOURCE_DIR}")
  string(SUBSTRING ${_roz_key} 0 12 _roz_key)
  set(_roz_root ${CMAKE_BINARY_DIR}/_deps/wasm3-tree-${_roz_key}-${_roz_patch_sha})
  if(NOT EXISTS ${_roz_root}/.roz-patched)
    file(REMOVE_RECURSE ${_roz_root})
    file(COPY ${ROZ_WASM3_SOURCE_DIR}/ DESTINATION ${_roz_root}/wasm3)
  endif()
  set(_roz_wasm3_license "")
elseif(ROZ_WASM3_SDIST)
  if(NOT EXISTS "${ROZ_WASM3_SDIST}")
    message(FATAL_ERROR "ROZ_WASM3_SDIST: ${ROZ_WASM3_SDIST} does not exist; run tools/setup.sh (or make setup) to fetch it")
  endif()
  file(SHA256 "${ROZ_WASM3_SDIST}" _roz_sha)
  if(NOT _roz_sha STREQUAL ROZ_WASM3_SDIST_SHA256)
    message(FATAL_ERROR "ROZ_WASM3_SDIST: ${ROZ_WASM3_SDIST} has sha256 ${_roz_sha}, "
                        "expected ${ROZ_WASM3_SDIST_SHA256}: refusing to build wasm3 from it. "
                        "Delete the file and run tools/setup.sh to fetch it again.")
  endif()
  set(_roz_unpack ${CMAKE_BINARY_DIR}/_deps/wasm3-0.5.0-${_roz_patch_sha})
  set(_roz_root ${_roz_unpack}/pywasm3-0.5.0)
  if(NOT EXISTS ${_roz_root}/.roz-patched)
    file(REMOVE_RECURSE ${_roz_unpack})
    file(ARCHIVE_EXTRACT INPUT "${ROZ_WASM3_SDIST}" DESTINATION ${_roz_unpack})
  endif()
  set(_roz_wasm3_license ${_roz_root}/LICENSE)
else()
  message(FATAL_ERROR "roz needs wasm3's sources: set ROZ_WASM3_SDIST to pywasm3-0.5.0.tar.gz "
                      "(tools/setup.sh fetches it into .cache/) or ROZ_WASM3_SOURCE_DIR to a wasm3 "
                      "source tree, or configure with -DROZ_WITH_WASM3=OFF")
endif()
if(NOT EXISTS ${_roz_root}/.roz-patched)
  foreach(_p IN LISTS _roz_patches)
    get_filename_component(_pn ${_p} NAME)
    # --fuzz=0: a hunk applies where it was written or the build stops
    execute_process(COMMAND ${ROZ_PATCH_EXECUTABLE} -p1 --forward --batch --fuzz=0
                            --no-backup-if-mismatch -i ${_p}
                    WORKING_DIRECTORY ${_roz_root} RESULT_VARIABLE _roz_rc
                    OUTPUT_VARIABLE _roz_out ERROR_VARIABLE _roz_out)
    if(NOT _roz_rc EQUAL 0)
      message(FATAL_ERROR "cmake/wasm3/${_pn} does not apply to the wasm3 sources in "
                          "${_roz_root}:\n${_roz_out}")
    endif()
  endforeach()
  file(TOUCH ${_roz_root}/.roz-patched)
endif()
set(_roz_wasm3_dir ${_roz_root}/wasm3)

file(GLOB _roz_wasm3_sources CONFIGURE_DEPENDS ${_roz_wasm3_dir}/*.c)
add_library(roz_wasm3 STATIC ${_roz_wasm3_sources})
add_library(roz::wasm3 ALIAS roz_wasm3)
set_target_properties(roz_wasm3 PROPERTIES C_STANDARD 11 C_EXTENSIONS ON
                                           POSITION_INDEPENDENT_CODE ${ROZ_PIC})
# Only roz's own sources include wasm3.h; consumers never see this folder.
target_include_directories(roz_wasm3 PUBLIC $<BUILD_INTERFACE:${_roz_wasm3_dir}>)
# wasm3's interpreter chains its ops by calls that must compile to tail
# calls, or every op executed nests a C stack frame (a long straight-line
# function then overflows any stack; roz's guard checks the depth only at
# function and loop entries). Optimise wasm3 with sibling calls in every
# build type, Debug included (-Os stays -Os).
set(ROZ_WASM3_OPT_FLAGS
  $<$<C_COMPILER_ID:GNU,Clang,AppleClang>:$<IF:$<CONFIG:MinSizeRel>,-Os,-O2> -foptimize-sibling-calls>)
target_compile_options(roz_wasm3 PRIVATE
  $<$<C_COMPILER_ID:GNU,Clang,AppleClang>:-w -fno-strict-aliasing> ${ROZ_WASM3_OPT_FLAGS}
  ${ROZ_SANITIZE_DEP_FLAGS})
target_link_libraries(roz_wasm3 PRIVATE m)
# wasm3's own configuration (m3_config.h), e.g. for a firmware
# "d_m3CodePageAlignSize=1024;d_m3VerboseErrorMessages=0": smaller code pages
# on the heap, no formatted error texts (roz reports wasm3's result strings,
# never those). PUBLIC: roz's controller.c reads wasm3's structs, whose
# layout some of these options change.
set(ROZ_WASM3_DEFINITIONS "" CACHE STRING "wasm3 configuration macros (d_m3*=value;...)")
target_compile_definitions(roz_wasm3 PUBLIC ${ROZ_WASM3_DEFINITIONS})
set(ROZ_WASM3_LICENSE_FILE "${_roz_wasm3_license}")
