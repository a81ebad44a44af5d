# SPDX-License-Identifier: Apache-2.0
#
# roz_generate(TARGET <target> MANIFESTS <robot.toml>... [REGISTRY]
#              [OUTPUT_DIR <dir>] [SOURCE_ROOT <dir>])
#
# Runs rozgen on each robot.toml at build time and adds the generated C tables
# (<id>_manifest.c) to <target>, with the folder holding <id>_manifest.h and
# <id>_channels.h (and <id>_channels.rs, for Rust controllers) on its PUBLIC
# include path. That folder is OUTPUT_DIR,
# by default ${CMAKE_CURRENT_BINARY_DIR}/roz_generated/<target>. MANIFEST is
# accepted as a synonym of MANIFESTS. REGISTRY also generates
# roz_builtin_registry.c, the roz/builtin.h registry over these manifests.
# The manifests are checked at configure time, so a bad robot.toml stops
# cmake with rozgen's message.
#
# rozgen is the cache variable ROZGEN_EXECUTABLE (ROZGEN_DEPENDS: more files
# its output depends on, e.g. its sources in a source tree). find_package(roz) sets it to
# the rozgen installed with roz (<prefix>/bin/rozgen); otherwise it is looked
# up on PATH. Set it yourself to use another one.

find_program(ROZGEN_EXECUTABLE rozgen DOC "rozgen, roz's manifest code generator")

# roz__rozgen_command(<outputs_var> <sources_var> <output_dir> <source_root>
#                     <registry: ON|OFF> <robot.toml>...)
# The custom command that runs rozgen on the manifests into <output_dir>:
# sets <outputs_var> to every file it writes and <sources_var> to the .c
# files among them. Shared by roz_generate() and roz_add_wasm_controller().
function(roz__rozgen_command outputs_var sources_var output_dir source_root registry)
  set(tomls ${ARGN})
  if(NOT ROZGEN_EXECUTABLE)
    message(FATAL_ERROR
      "rozgen not found, and it is needed to generate the tables of ${tomls}.\n"
      "An installed roz has it in <prefix>/bin (cmake --install puts it there; "
      "find_package(roz) finds it beside the package). In a roz source tree, "
      "tools/setup.sh installs it in .venv/bin. Otherwise put rozgen on PATH or "
      "pass -DROZGEN_EXECUTABLE=/path/to/rozgen.")
  endif()
  set(inputs "")
  set(outputs "")
  set(sources "")
  foreach(toml IN LISTS tomls)
    cmake_path(ABSOLUTE_PATH toml BASE_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR} NORMALIZE)
    # The output names depend on robot_id, which only rozgen knows for sure:
    # ask it once at configure time and reconfigure when the file changes.
    execute_process(COMMAND ${ROZGEN_EXECUTABLE} --json ${toml}
                    OUTPUT_VARIABLE json ERROR_VARIABLE err RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${toml} is not a valid manifest (${ROZGEN_EXECUTABLE}):\n${err}")
    endif()
    string(JSON id GET "${json}" robot_id)
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${toml})
    list(APPEND inputs ${toml})
    list(APPEND outputs ${output_dir}/${id}_manifest.c ${output_dir}/${id}_manifest.h
                        ${output_dir}/${id}_channels.h ${output_dir}/${id}_channels.rs)
    list(APPEND sources ${output_dir}/${id}_manifest.c)
  endforeach()
  set(registry_flag "")
  if(registry)
    set(registry_flag --registry)
    list(APPEND outputs ${output_dir}/roz_builtin_registry.c)
    list(APPEND sources ${output_dir}/roz_builtin_registry.c)
  endif()
  cmake_path(RELATIVE_PATH output_dir BASE_DIRECTORY ${CMAKE_BINARY_DIR} OUTPUT_VARIABLE shown)
  add_custom_command(
    OUTPUT ${outputs}
    COMMAND ${ROZGEN_EXECUTABLE} -o ${output_dir} --source-root ${source_root}
            ${registry_flag} ${inputs}
    DEPENDS ${inputs} ${ROZGEN_EXECUTABLE} ${ROZGEN_DEPENDS}
    COMMENT "rozgen: generating ${shown}"
    VERBATIM)
  set(${outputs_var} ${outputs} PARENT_SCOPE)
  set(${sources_var} ${sources} PARENT_SCOPE)
endfunction()

function(roz_generate)
  cmake_parse_arguments(PARSE_ARGV 0 arg "REGISTRY" "TARGET;OUTPUT_DIR;SOURCE_ROOT" "MANIFESTS;MANIFEST")
  if(NOT arg_TARGET)
    message(FATAL_ERROR "roz_generate: TARGET is required")
  endif()
  list(APPEND arg_MANIFESTS ${arg_MANIFEST})
  if(NOT arg_MANIFESTS)
    message(FATAL_ERROR "roz_generate: give at least one robot.toml with MANIFESTS")
  endif()
  if(NOT arg_OUTPUT_DIR)
    set(arg_OUTPUT_DIR ${CMAKE_CURRENT_BINARY_DIR}/roz_generated/${arg_TARGET})
  endif()
  if(NOT arg_SOURCE_ROOT)
    set(arg_SOURCE_ROOT ${PROJECT_SOURCE_DIR})
  endif()
  roz__rozgen_command(outputs sources ${arg_OUTPUT_DIR} ${arg_SOURCE_ROOT}
                      "${arg_REGISTRY}" ${arg_MANIFESTS})
  target_sources(${arg_TARGET} PRIVATE ${sources})
  target_include_directories(${arg_TARGET} PUBLIC $<BUILD_INTERFACE:${arg_OUTPUT_DIR}>)
  if(TARGET roz::core)
    target_link_libraries(${arg_TARGET} PUBLIC roz::core)
  endif()
endfunction()
