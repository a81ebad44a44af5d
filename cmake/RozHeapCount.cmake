# SPDX-License-Identifier: Apache-2.0
# roz_count_heap(TARGET): the target's malloc, calloc, realloc and free go
# through test/support_heap.c, which counts them (test/support_heap.h).
# For the tests and benchmarks that prove the tick path never allocates.
function(roz_count_heap target)
  target_sources(${target} PRIVATE ${PROJECT_SOURCE_DIR}/test/support_heap.c)
  target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/test)
  target_link_options(${target} PRIVATE
    -Wl,--wrap=malloc -Wl,--wrap=calloc -Wl,--wrap=realloc -Wl,--wrap=free)
endfunction()
