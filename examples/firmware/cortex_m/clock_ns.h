/* SPDX-License-Identifier: Apache-2.0 */
/* Processor cycles to nanoseconds at any core clock, exactly: the whole
 * seconds and the remainder are converted apart, so no per-cycle rounding
 * accumulates (at 168 MHz a whole-nanosecond step of 5 ns per 5.95 ns cycle
 * would run the clock 16 % slow) and the product never overflows. The
 * result is floor(cycles * 10^9 / hz) whenever that fits in 64 bits (584
 * years of nanoseconds; test_fw_clock, against a 128-bit reference). */
#ifndef ROZ_FW_CLOCK_NS_H
#define ROZ_FW_CLOCK_NS_H

#include <stdint.h>

static inline uint64_t fw_cycles_to_ns(uint64_t cycles, uint32_t hz)
{
    /* (cycles % hz) * 10^9 < 2^32 * 10^9 < 2^62 */
    return (cycles / hz) * 1000000000u + ((cycles % hz) * 1000000000u) / hz;
}

#endif /* ROZ_FW_CLOCK_NS_H */
