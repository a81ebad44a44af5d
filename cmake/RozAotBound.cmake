# SPDX-License-Identifier: Apache-2.0
# cmake -DFILE=<name>_aot.c -P RozAotBound.cmake (roz_add_aot_controller(),
# after wasm2c): every memory access of an ahead-of-time controller is
# checked against the size of its linear memory, which wasm2c's C reads from
# the memory object at each access -- and, since a store into the memory
# may alias that object, reads again after every store. In roz the size of
# a loaded controller's memory never changes (memory.grow fails; the load
# fails before any data is written when the build gave it less: roz/aot.h),
# so the bound is the constant its declaration gives: this script writes it
# into wasm2c's bounds check. The checks stay, every one of them; a C file
# not shaped as expected stops the build.
file(READ ${FILE} c)
set(check "if (UNLIKELY(offset + (uint64_t)len > mem->size))")
string(FIND "${c}" "${check}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${FILE}: wasm2c's bounds check is not the one roz expects "
                      "(another wabt than 1.0.32?): '${check}' not found")
endif()
string(REGEX MATCHALL "wasm_rt_allocate_memory\\(&instance->[A-Za-z0-9_]+, [0-9]+, " allocs "${c}")
list(LENGTH allocs n)
if(n EQUAL 0)
  set(bytes 0) # no memory: no access to check
elseif(n EQUAL 1)
  string(REGEX MATCH ", ([0-9]+), $" m "${allocs}")
  math(EXPR bytes "${CMAKE_MATCH_1} * 65536")
else()
  message(FATAL_ERROR "${FILE}: ${n} memories; a controller has at most one")
endif()
string(REPLACE "${check}" "if (UNLIKELY(offset + (uint64_t)len > ${bytes}ull))" c "${c}")
file(WRITE ${FILE} "${c}")
