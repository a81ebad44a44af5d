# SPDX-License-Identifier: Apache-2.0
#
# roz_add_aot_controller(<name> WASM <file.wasm> [DEPENDS <target>...])
#
# Compiles a controller module ahead of time into the static library
# roz_aot_<name>, which defines the roz_aot_module_t roz_aot_<name>
# (roz/aot.h: ROZ_AOT_DECLARE(<name>), roz_controller_load_aot(),
# roz_runtime_load_aot()). <name> must be a C identifier. Three steps, in
# ${CMAKE_CURRENT_BINARY_DIR}/roz_aot/<name>:
#   1. rozaot (tools/aot) loads the module as the runtime would (roz's
#      validator, then wasm3: a module roz refuses stops the build with the
#      runtime's message), inserts the fuel metering wasm3 charges and writes
#      the glue (<name>_glue.c);
#   2. wabt's wasm2c turns the metered module into C (<name>_aot.c/.h);
#   3. both are compiled with roz's settings for wasm2c's runtime
#      (roz/aot_generated.h: every memory access bounds-checked, call depth
#      bounded) and without fused multiply-add contraction.
# roz_add_wasm_controller(... AOT) calls this for the module it builds.
find_program(ROZ_WASM2C wasm2c DOC "wabt's wasm2c, for ahead-of-time controllers")

function(roz_add_aot_controller name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "WASM" "DEPENDS")
  if(NOT arg_WASM)
    message(FATAL_ERROR "roz_add_aot_controller(${name}): WASM is required")
  endif()
  if(NOT name MATCHES "^[A-Za-z][A-Za-z0-9_]*$")
    message(FATAL_ERROR "roz_add_aot_controller(${name}): the name must be a C identifier")
  endif()
  if(NOT ROZ_WASM2C)
    message(FATAL_ERROR "wasm2c (Debian package wabt) is needed to build ${name} ahead of time")
  endif()
  if(NOT TARGET rozaot OR NOT TARGET roz::aot)
    message(FATAL_ERROR "roz_add_aot_controller(${name}): the tool rozaot and the library "
                        "roz::aot are built with wasm3 on the host (ROZ_WITH_WASM3, ROZ_BUILD_TOOLS)")
  endif()
  cmake_path(ABSOLUTE_PATH arg_WASM BASE_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR} NORMALIZE)
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/roz_aot/${name})
  add_custom_command(OUTPUT ${dir}/${name}_metered.wasm ${dir}/${name}_glue.c
    COMMAND ${CMAKE_COMMAND} -E make_directory ${dir}
    COMMAND rozaot ${name} ${arg_WASM} ${dir}/${name}_metered.wasm ${dir}/${name}_glue.c
    DEPENDS ${arg_WASM} rozaot ${arg_DEPENDS}
    VERBATIM COMMENT "rozaot ${name}: validate and meter")
  add_custom_command(OUTPUT ${dir}/${name}_aot.c ${dir}/${name}_aot.h
    COMMAND ${ROZ_WASM2C} ${dir}/${name}_metered.wasm -n ${name} -o ${dir}/${name}_aot.c
    DEPENDS ${dir}/${name}_metered.wasm
    VERBATIM COMMENT "wasm2c ${name}")
  add_library(roz_aot_${name} STATIC ${dir}/${name}_aot.c ${dir}/${name}_glue.c)
  target_include_directories(roz_aot_${name} PRIVATE ${dir})
  target_link_libraries(roz_aot_${name} PUBLIC roz::aot)
  # wasm2c's C is its own; roz's warnings are not its contract
  target_compile_options(roz_aot_${name} PRIVATE
    $<$<C_COMPILER_ID:GNU,Clang,AppleClang>:-include roz/aot_generated.h -ffp-contract=off
      -fno-strict-aliasing -w> ${ROZ_SANITIZE_DEP_FLAGS})
endfunction()
