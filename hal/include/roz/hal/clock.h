/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/hal/clock.h
 * @brief Monotonic time for hosts (POSIX CLOCK_MONOTONIC).
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

#ifdef __cplusplus
}
#endif

#endif /* ROZ_HAL_CLOCK_H */
