# SPDX-License-Identifier: Apache-2.0
#
# roz_generate(TARGET <target> MANIFESTS <robot.toml>... [REGISTRY]
#              [OUTPUT_DIR <dir>] [SOURCE_ROOT <dir>])
#
# Runs rozgen on each robot.toml at build time and adds the generated C tables
# (<id>_manifest.c) to <target>, with the folder holding <id>_manifest.h and
# <id>_channels.h on its PUBLIC include path. MANIFEST is accepted as a
# synonym of MANIFESTS. REGISTRY also generates roz_builtin_registry.c, the
# roz/builtin.h registry over these manifests. The manifests are checked at
# configure time, so a bad robot.toml stops cmake with rozgen's message.
#
# rozgen is looked up as ROZGEN_EXECUTABLE (cache variable; the `rozgen`
# console script of `pip install codegen/`).

find_program(ROZGEN_EXECUTABLE rozgen
  HINTS ${CMAKE_CURRENT_LIST_DIR}/../.venv/bin
  DOC "rozgen, roz's manifest code generator")

function(roz_generate)
  cmake_parse_arguments(PARSE_ARGV 0 arg "REGISTRY" "TARGET;OUTPUT_DIR;SOURCE_ROOT" "MANIFESTS;MANIFEST")
  if(NOT arg_TARGET)
    message(FATAL_ERROR "roz_generate: TARGET is required")
  endif()
  list(APPEND arg_MANIFESTS ${arg_MANIFEST})
  if(NOT arg_MANIFESTS)
    message(FATAL_ERROR "roz_generate: give at least one robot.toml with MANIFESTS")
  endif()
  if(NOT ROZGEN_EXECUTABLE)
    message(FATAL_ERROR "roz_generate: rozgen not found; install it (pip install codegen/) "
                        "or set ROZGEN_EXECUTABLE")
  endif()
  if(NOT arg_OUTPUT_DIR)
    set(arg_OUTPUT_DIR ${CMAKE_CURRENT_BINARY_DIR}/roz_generated/${arg_TARGET})
  endif()
  if(NOT arg_SOURCE_ROOT)
    set(arg_SOURCE_ROOT ${PROJECT_SOURCE_DIR})
  endif()

  set(inputs "")
  set(outputs "")
  set(sources "")
  foreach(toml IN LISTS arg_MANIFESTS)
    cmake_path(ABSOLUTE_PATH toml BASE_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR} NORMALIZE)
    # The output names depend on robot_id, which only rozgen knows for sure:
    # ask it once at configure time and reconfigure when the file changes.
    execute_process(COMMAND ${ROZGEN_EXECUTABLE} --json ${toml}
                    OUTPUT_VARIABLE json ERROR_VARIABLE err RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "roz_generate: ${toml} is not a valid manifest:\n${err}")
    endif()
    string(JSON id GET "${json}" robot_id)
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${toml})
    list(APPEND inputs ${toml})
    list(APPEND outputs ${arg_OUTPUT_DIR}/${id}_manifest.c ${arg_OUTPUT_DIR}/${id}_manifest.h
                        ${arg_OUTPUT_DIR}/${id}_channels.h)
    list(APPEND sources ${arg_OUTPUT_DIR}/${id}_manifest.c)
  endforeach()
  set(registry_flag "")
  if(arg_REGISTRY)
    set(registry_flag --registry)
    list(APPEND outputs ${arg_OUTPUT_DIR}/roz_builtin_registry.c)
    list(APPEND sources ${arg_OUTPUT_DIR}/roz_builtin_registry.c)
  endif()

  add_custom_command(
    OUTPUT ${outputs}
    COMMAND ${ROZGEN_EXECUTABLE} -o ${arg_OUTPUT_DIR} --source-root ${arg_SOURCE_ROOT}
            ${registry_flag} ${inputs}
    DEPENDS ${inputs} ${ROZGEN_EXECUTABLE}
    COMMENT "rozgen: generating manifest tables for ${arg_TARGET}"
    VERBATIM)
  target_sources(${arg_TARGET} PRIVATE ${sources})
  target_include_directories(${arg_TARGET} PUBLIC $<BUILD_INTERFACE:${arg_OUTPUT_DIR}>)
  if(TARGET roz::core)
    target_link_libraries(${arg_TARGET} PUBLIC roz::core)
  endif()
endfunction()
