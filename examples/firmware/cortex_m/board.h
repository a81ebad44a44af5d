/* SPDX-License-Identifier: Apache-2.0 */
/* What the start-up code, the clock and the C library's hooks give the
 * image's main(). */
#ifndef ROZ_FW_BOARD_H
#define ROZ_FW_BOARD_H

#include <stddef.h>
#include <stdint.h>

/** Starts SysTick on the processor clock, free-running. */
void fw_clock_start(void);

/** Monotonic nanoseconds from SysTick at the board's core clock
 *  (FW_CLOCK_HZ, cortex_m/clock_ns.h; roz_clock_fn). Under QEMU's
 *  -icount shift=0 one nanosecond is one instruction. */
uint64_t fw_clock_ns(void *ctx);

/** The heap's size and the most of it malloc ever took (its break). */
size_t fw_heap_size(void);
size_t fw_heap_high_water(void);

/** The main stack's size and the deepest it was used (painted at reset). */
size_t fw_stack_size(void);
size_t fw_stack_high_water(void);

#endif /* ROZ_FW_BOARD_H */
