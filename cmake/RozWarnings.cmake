# SPDX-License-Identifier: Apache-2.0
# Warning flags for roz's own targets; dependencies (wasm3) never get these.
function(roz_target_warnings target)
  target_compile_options(${target} PRIVATE
    $<$<C_COMPILER_ID:GNU,Clang,AppleClang>:
      -Wall -Wextra -Wundef -Wshadow -Wstrict-prototypes -Wmissing-prototypes
      -Wvla -Wpointer-arith -Wcast-qual -Wformat=2 -pedantic>
    $<$<C_COMPILER_ID:GNU>:-Wno-format-truncation>
    $<$<AND:$<BOOL:${ROZ_WERROR}>,$<C_COMPILER_ID:GNU,Clang,AppleClang>>:-Werror>)
endfunction()
