/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/hal/clock.h
 * @brief Monotonic time for hosts (POSIX CLOCK_MONOTONIC), and a thread's
 *        CPU time (CLOCK_THREAD_CPUTIME_ID).
 */
#ifndef ROZ_HAL_CLOCK_H
#define ROZ_HAL_CLOCK_H

#include "roz/config.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Monotonic nanoseconds; @p ctx is unused (a roz_clock_fn).
 *  Context: any; RT-safe (vDSO). */
uint64_t roz_clock_monotonic_ns(void *ctx);

/** @brief Nanoseconds of CPU time the calling thread has used
 *  (CLOCK_THREAD_CPUTIME_ID): time other threads preempt it is not counted.
 *  The tick's deadline clock where the tick is not real-time
 *  (roz_runtime_config_t deadline_clock, docs/budget.md); @p ctx is unused.
 *  Context: any; RT-safe (a system call on Linux, no vDSO: under a
 *  microsecond, about ten times CLOCK_MONOTONIC's cost). */
uint64_t roz_clock_thread_cpu_ns(void *ctx);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_HAL_CLOCK_H */
