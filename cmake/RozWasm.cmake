# SPDX-License-Identifier: Apache-2.0
#
# roz_add_wasm_controller(<name> SOURCE <file.c|file.wat>
#                         [MANIFEST <robot.toml>...] [SOURCE_ROOT <dir>]
#                         [INCLUDES <dir>...] [DEPENDS <file>...] [AOT])
#
# Builds <name>.wasm into CMAKE_CURRENT_BINARY_DIR as the target
# roz_wasm_<name>, part of roz_controllers (built by default). C is compiled
# with clang --target=wasm32 (freestanding, no libc) against the controller
# SDK, the target roz::sdk (roz_controller.h); WAT is assembled with wabt's
# wat2wasm.
#
# MANIFEST runs rozgen on each robot.toml into
# ${CMAKE_CURRENT_BINARY_DIR}/roz_generated/wasm_<name> and puts that folder
# on the include path, so the source can include <robot_id>_channels.h; the
# controller is built after that step and again whenever the manifest
# changes. The generated files name the manifest relative to SOURCE_ROOT
# (default: the project's source folder), which must hold it. A C controller is also rebuilt when any header it includes changes
# (clang writes the list). INCLUDES adds include folders, DEPENDS files to
# rebuild on. AOT also compiles the module ahead of time into the library
# roz_aot_<name> (cmake/RozAot.cmake, roz_add_aot_controller()).
#
# Available after find_package(roz) and after add_subdirectory(roz).
find_program(ROZ_CLANG NAMES clang clang-14 DOC "clang, to compile C controllers to wasm32")
find_program(ROZ_WAT2WASM wat2wasm DOC "wabt's wat2wasm, to assemble WAT controllers")
if(NOT COMMAND roz__rozgen_command)
  include(${CMAKE_CURRENT_LIST_DIR}/RozGenerate.cmake)
endif()

function(roz_add_wasm_controller name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "AOT" "SOURCE;SOURCE_ROOT" "MANIFEST;INCLUDES;DEPENDS")
  if(NOT arg_SOURCE)
    message(FATAL_ERROR "roz_add_wasm_controller(${name}): SOURCE is required")
  endif()
  cmake_path(ABSOLUTE_PATH arg_SOURCE BASE_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR} NORMALIZE)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${name}.wasm)
  if(arg_SOURCE MATCHES "\\.wat$")
    if(NOT ROZ_WAT2WASM)
      message(FATAL_ERROR "wat2wasm (Debian package wabt) is needed to build ${arg_SOURCE}")
    endif()
    if(arg_MANIFEST)
      message(FATAL_ERROR "roz_add_wasm_controller(${name}): MANIFEST is for C controllers; "
                          "${arg_SOURCE} is WAT")
    endif()
    add_custom_command(OUTPUT ${out}
      COMMAND ${ROZ_WAT2WASM} ${arg_SOURCE} -o ${out}
      DEPENDS ${arg_SOURCE} ${arg_DEPENDS} VERBATIM COMMENT "wat2wasm ${name}.wasm")
  else()
    if(NOT ROZ_CLANG)
      message(FATAL_ERROR "clang (with lld) is needed to build ${arg_SOURCE} for wasm32")
    endif()
    if(NOT TARGET roz::sdk)
      message(FATAL_ERROR "roz_add_wasm_controller(${name}): the target roz::sdk (the "
                          "controller SDK) is missing; call find_package(roz) first")
    endif()
    set(generated "")
    set(incs "")
    if(arg_MANIFEST)
      set(gen_dir ${CMAKE_CURRENT_BINARY_DIR}/roz_generated/wasm_${name})
      if(NOT arg_SOURCE_ROOT)
        set(arg_SOURCE_ROOT ${PROJECT_SOURCE_DIR})
      endif()
      roz__rozgen_command(generated unused ${gen_dir} ${arg_SOURCE_ROOT} OFF ${arg_MANIFEST})
      list(APPEND incs -I${gen_dir})
    endif()
    foreach(d IN LISTS arg_INCLUDES)
      cmake_path(ABSOLUTE_PATH d BASE_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR} NORMALIZE)
      list(APPEND incs -I${d})
    endforeach()
    # The SDK's folder: the source tree's or the installed one.
    set(sdk "$<TARGET_PROPERTY:roz::sdk,INTERFACE_INCLUDE_DIRECTORIES>")
    add_custom_command(OUTPUT ${out}
      COMMAND ${ROZ_CLANG} --target=wasm32 -O2 -nostdlib -fno-builtin -std=c11
              -Wall -Wextra -Werror "-I$<JOIN:${sdk},;-I>" ${incs}
              -MD -MF ${out}.d -MT ${out}
              -Wl,--no-entry -Wl,--strip-all -Wl,-z,stack-size=16384
              -o ${out} ${arg_SOURCE}
      DEPENDS ${arg_SOURCE} ${generated} ${arg_DEPENDS}
      DEPFILE ${out}.d
      COMMAND_EXPAND_LISTS VERBATIM COMMENT "clang wasm32 ${name}.wasm")
  endif()
  add_custom_target(roz_wasm_${name} DEPENDS ${out})
  if(NOT TARGET roz_controllers)
    add_custom_target(roz_controllers ALL)
  endif()
  add_dependencies(roz_controllers roz_wasm_${name})
  if(arg_AOT AND TARGET rozaot AND TARGET roz::aot AND ROZ_WASM2C)  # cmake/RozAot.cmake
    roz_add_aot_controller(${name} WASM ${out} DEPENDS roz_wasm_${name})
  endif()
endfunction()

# roz_add_policy_controller(<name> POLICY <file> ROBOT <name|robot.toml>
#                           [CONFIG <deploy.yaml>] [SPEC <layers>]
#                           [COMMAND <vx,vy,wz>])
#
# A learned policy deployed as `rozgen-nn deploy` does it (docs/policies.md):
# the policy file (.pt, .onnx, .npz with SPEC) and its deploy configuration
# (unitree_rl_gym's YAML; without CONFIG, the ONNX file's metadata), checked
# against ROBOT (a built-in manifest's name or a robot.toml), become
# ${CMAKE_CURRENT_BINARY_DIR}/<name>.c (generated) and <name>.wasm, built by
# roz_add_wasm_controller() as the target roz_wasm_<name>. COMMAND is the
# constant velocity command when the robot has no command channels. rozgen-nn
# is ROZGEN_NN_EXECUTABLE (default: beside rozgen, else on PATH); it needs
# numpy and PyYAML (pip install rozgen[nn]).
function(roz_add_policy_controller name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "POLICY;ROBOT;CONFIG;SPEC;COMMAND" "")
  if(NOT arg_POLICY OR NOT arg_ROBOT)
    message(FATAL_ERROR "roz_add_policy_controller(${name}): POLICY and ROBOT are required")
  endif()
  if(NOT ROZGEN_NN_EXECUTABLE)
    set(_hint "")
    if(ROZGEN_EXECUTABLE)
      cmake_path(GET ROZGEN_EXECUTABLE PARENT_PATH _hint)
    endif()
    find_program(ROZGEN_NN_EXECUTABLE rozgen-nn HINTS ${_hint}
                 DOC "rozgen-nn, roz's policy exporter and deployer")
    if(NOT ROZGEN_NN_EXECUTABLE)
      message(FATAL_ERROR "roz_add_policy_controller(${name}): rozgen-nn not found; "
                          "pip install rozgen[nn] or pass -DROZGEN_NN_EXECUTABLE=...")
    endif()
  endif()
  set(args "")
  set(deps "")
  foreach(f IN ITEMS POLICY CONFIG)
    if(arg_${f})
      cmake_path(ABSOLUTE_PATH arg_${f} BASE_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR} NORMALIZE)
      list(APPEND deps ${arg_${f}})
    endif()
  endforeach()
  if(arg_CONFIG)
    list(APPEND args --config ${arg_CONFIG})
  endif()
  if(arg_ROBOT MATCHES "\\.toml$")
    cmake_path(ABSOLUTE_PATH arg_ROBOT BASE_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR} NORMALIZE)
    list(APPEND deps ${arg_ROBOT})
  endif()
  if(arg_SPEC)
    list(APPEND args --spec ${arg_SPEC})
  endif()
  if(arg_COMMAND)
    list(APPEND args --command ${arg_COMMAND})
  endif()
  set(src ${CMAKE_CURRENT_BINARY_DIR}/roz_generated/policy_${name}/${name}.c)
  add_custom_command(OUTPUT ${src}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/roz_generated/policy_${name}
    COMMAND ${ROZGEN_NN_EXECUTABLE} deploy ${arg_POLICY} ${args} --robot ${arg_ROBOT}
            --no-wasm --source ${src} -o ${CMAKE_CURRENT_BINARY_DIR}/${name}.wasm
    DEPENDS ${deps} ${ROZGEN_NN_EXECUTABLE} ${ROZGEN_DEPENDS}
    VERBATIM COMMENT "rozgen-nn deploy ${name}.c")
  roz_add_wasm_controller(${name} SOURCE ${src})
endfunction()
