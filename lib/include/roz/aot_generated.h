/* SPDX-License-Identifier: Apache-2.0 */
/* Included first (-include) by roz_add_aot_controller() into the C that
 * wasm2c wrote for a controller, never by anything else: wasm2c's runtime
 * header with roz's settings. Memory is checked on every access (no guard
 * pages: a Cortex-M has no MMU, and roz traps instead of taking a signal);
 * calls nest at most ROZ_CFG_AOT_CALL_DEPTH deep, counted per thread (two
 * threads may run compiled controllers at once: a runtime verifies on its
 * loader thread while the tick runs). */
#ifndef ROZ_AOT_GENERATED_H
#define ROZ_AOT_GENERATED_H

#include "roz/config.h"

#define WASM_RT_MEMCHECK_SIGNAL_HANDLER 0
#define WASM_RT_USE_STACK_DEPTH_COUNT 1
#define WASM_RT_MAX_CALL_STACK_DEPTH ROZ_CFG_AOT_CALL_DEPTH
#include "wasm-rt.h"

/* bare-metal C libraries have no thread-local storage, and one thread */
#if defined(__arm__) && !defined(__linux__)
#define ROZ_AOT_THREAD_LOCAL
#elif defined(__cplusplus)
#define ROZ_AOT_THREAD_LOCAL thread_local
#else
#define ROZ_AOT_THREAD_LOCAL _Thread_local
#endif
extern ROZ_AOT_THREAD_LOCAL uint32_t roz__aot_depth;
#define wasm_rt_call_stack_depth roz__aot_depth

#endif /* ROZ_AOT_GENERATED_H */
