# SPDX-License-Identifier: Apache-2.0
#
# roz_add_wasm_controller(<name> SOURCE <file.c|file.wat> [INCLUDES dir...] [DEPENDS file...])
# builds <name>.wasm into CMAKE_CURRENT_BINARY_DIR: C with clang
# --target=wasm32 (freestanding, no libc), WAT with wabt's wat2wasm. Adds it
# to the target roz_controllers (built by default).
find_program(ROZ_CLANG NAMES clang clang-14 DOC "clang, to compile C controllers to wasm32")
find_program(ROZ_WAT2WASM wat2wasm DOC "wabt's wat2wasm, to assemble WAT controllers")

if(NOT TARGET roz_controllers)
  add_custom_target(roz_controllers ALL)
endif()

function(roz_add_wasm_controller name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "SOURCE" "INCLUDES;DEPENDS")
  cmake_path(ABSOLUTE_PATH arg_SOURCE BASE_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR} NORMALIZE)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${name}.wasm)
  if(arg_SOURCE MATCHES "\\.wat$")
    if(NOT ROZ_WAT2WASM)
      message(FATAL_ERROR "wat2wasm (Debian package wabt) is needed to build ${arg_SOURCE}")
    endif()
    add_custom_command(OUTPUT ${out}
      COMMAND ${ROZ_WAT2WASM} ${arg_SOURCE} -o ${out}
      DEPENDS ${arg_SOURCE} VERBATIM COMMENT "wat2wasm ${name}.wasm")
  else()
    if(NOT ROZ_CLANG)
      message(FATAL_ERROR "clang (with lld) is needed to build ${arg_SOURCE} for wasm32")
    endif()
    set(incs "")
    foreach(d IN LISTS arg_INCLUDES)
      list(APPEND incs -I${d})
    endforeach()
    add_custom_command(OUTPUT ${out}
      COMMAND ${ROZ_CLANG} --target=wasm32 -O2 -nostdlib -fno-builtin -std=c11
              -Wall -Wextra -Werror ${incs}
              -Wl,--no-entry -Wl,--strip-all -Wl,-z,stack-size=16384
              -o ${out} ${arg_SOURCE}
      DEPENDS ${arg_SOURCE} ${arg_DEPENDS} VERBATIM COMMENT "clang wasm32 ${name}.wasm")
  endif()
  add_custom_target(roz_wasm_${name} DEPENDS ${out})
  add_dependencies(roz_controllers roz_wasm_${name})
endfunction()
