# SPDX-License-Identifier: Apache-2.0
# Flags for roz's own targets; dependencies (wasm3) never get the warnings.
#
# ROZ_SANITIZE: "" (default), "address" (AddressSanitizer + UndefinedBehavior-
# Sanitizer, any report aborts) or "thread" (ThreadSanitizer). roz's targets
# get the full set. wasm3 runs a controller, which is hostile input, so in
# the address build it gets UBSan too, every report fatal: its integer ops
# and its compiler are patched to be well-defined (cmake/wasm3/20-*, 21-*)
# and test/hostile/test_wasm3_ub.c drives every op to its edges. No check is
# left out: clang's -fsanitize=function (a C check from clang 17, not in this
# toolchain's clang 14) would be the one to watch, as wasm3 calls its ops
# through one pointer type; alignment checks pass, its slots and code
# stream are aligned for what is read from them. The thread build gives
# wasm3 TSan only.
set(ROZ_SANITIZE "" CACHE STRING "Sanitizer build: empty, address or thread")
set_property(CACHE ROZ_SANITIZE PROPERTY STRINGS "" address thread)
if(ROZ_SANITIZE STREQUAL "address")
  set(ROZ_SANITIZE_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all
                         -fno-omit-frame-pointer)
  set(ROZ_SANITIZE_DEP_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all
                             -fno-omit-frame-pointer)
elseif(ROZ_SANITIZE STREQUAL "thread")
  set(ROZ_SANITIZE_FLAGS -fsanitize=thread -fno-omit-frame-pointer)
  # Without function entry/exit hooks for wasm3: TSan's exit hook after
  # every call would stop wasm3's ops chaining by tail calls, and every op
  # executed would nest a C stack frame (cmake/Wasm3.cmake). Its memory
  # accesses are still checked; only its frames leave TSan's stack traces.
  set(ROZ_SANITIZE_DEP_FLAGS ${ROZ_SANITIZE_FLAGS}
    "$<$<C_COMPILER_ID:Clang,AppleClang>:SHELL:-mllvm -tsan-instrument-func-entry-exit=0>"
    "$<$<C_COMPILER_ID:GNU>:--param=tsan-instrument-func-entry-exit=0>")
elseif(NOT ROZ_SANITIZE STREQUAL "")
  message(FATAL_ERROR "ROZ_SANITIZE must be empty, address or thread, not \"${ROZ_SANITIZE}\"")
else()
  set(ROZ_SANITIZE_FLAGS "")
  set(ROZ_SANITIZE_DEP_FLAGS "")
endif()

function(roz_target_warnings target)
  target_compile_options(${target} PRIVATE
    $<$<C_COMPILER_ID:GNU,Clang,AppleClang>:-Wall -Wextra -Wundef -Wshadow>
    # C only (the mujoco port has one C++ file)
    $<$<AND:$<COMPILE_LANGUAGE:C>,$<C_COMPILER_ID:GNU,Clang,AppleClang>>:
      -Wstrict-prototypes -Wmissing-prototypes>
    $<$<C_COMPILER_ID:GNU,Clang,AppleClang>:
      -Wvla -Wpointer-arith -Wcast-qual -Wformat=2 -pedantic>
    # Error messages are cut to their fixed buffers on purpose.
    $<$<C_COMPILER_ID:GNU>:-Wno-format-truncation>
    $<$<AND:$<BOOL:${ROZ_WERROR}>,$<C_COMPILER_ID:GNU,Clang,AppleClang>>:-Werror>
    ${ROZ_SANITIZE_FLAGS})
  if(ROZ_SANITIZE_FLAGS)
    target_link_options(${target} PUBLIC ${ROZ_SANITIZE_FLAGS})
  endif()
endfunction()
