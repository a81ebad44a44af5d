/* SPDX-License-Identifier: Apache-2.0 */
/* The firmware clock's cycles-to-nanoseconds conversion
 * (examples/firmware/cortex_m/clock_ns.h) at the MPS2 boards' 25 MHz, the
 * STM32F405's 168 MHz and odd frequencies: exact against a 128-bit
 * reference, so no rounding per cycle accumulates into drift. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include "clock_ns.h"
#include "support.h"

__extension__ typedef unsigned __int128 u128;

static uint64_t reference(uint64_t cycles, uint32_t hz)
{
    return (uint64_t)(((u128)cycles * 1000000000u) / hz);
}

/* every count in [0, n), then counts spread over the range in which the
 * nanoseconds still fit 64 bits */
static void check(uint32_t hz)
{
    u128 most = ((u128)UINT64_MAX * hz) / 1000000000u;
    uint64_t limit = most > UINT64_MAX ? UINT64_MAX : (uint64_t)most;

    for (uint64_t c = 0; c < 200000u; c++)
        assert_int_equal(fw_cycles_to_ns(c, hz), reference(c, hz));
    for (uint64_t c = 1; c <= (limit - 7u) / 3u; c = c * 3u + 7u)
        assert_int_equal(fw_cycles_to_ns(c, hz), reference(c, hz));
    assert_int_equal(fw_cycles_to_ns(limit, hz), reference(limit, hz));
}

static void test_fw_clock_25mhz(void **state)
{
    (void)state;
    check(25000000u);
    assert_int_equal(fw_cycles_to_ns(1, 25000000u), 40u);
    assert_int_equal(fw_cycles_to_ns(25000000u, 25000000u), 1000000000u);
}

static void test_fw_clock_168mhz_no_drift(void **state)
{
    (void)state;
    check(168000000u);
    /* a cycle is 5.952 ns: whole nanoseconds per cycle (5) would make an
     * hour of cycles 504 s short */
    assert_int_equal(fw_cycles_to_ns(1, 168000000u), 5u);
    assert_int_equal(fw_cycles_to_ns(168000000ull * 3600u, 168000000u), 3600000000000ull);
    assert_int_equal(fw_cycles_to_ns(168000000ull * 3600u + 1u, 168000000u), 3600000000005ull);
}

static void test_fw_clock_odd_frequencies(void **state)
{
    (void)state;
    check(7372800u);    /* a UART crystal */
    check(72000001u);   /* prime-ish, not a divisor of 10^9 */
    check(1u);
    check(4294967295u); /* the most a board file may name */
    assert_int_equal(fw_cycles_to_ns(7372800u, 7372800u), 1000000000u);
    assert_int_equal(fw_cycles_to_ns(3, 7372800u), 406u); /* 406.9 */
}

/* the clock never goes back: each count's nanoseconds at least the last's */
static void test_fw_clock_monotonic(void **state)
{
    (void)state;
    uint64_t last = 0;
    for (uint64_t c = 0; c < 1000000u; c++) {
        uint64_t ns = fw_cycles_to_ns(c, 168000000u);
        assert_true(ns >= last);
        last = ns;
    }
}

ROZ_TEST_MAIN(cmocka_unit_test(test_fw_clock_25mhz),
              cmocka_unit_test(test_fw_clock_168mhz_no_drift),
              cmocka_unit_test(test_fw_clock_odd_frequencies),
              cmocka_unit_test(test_fw_clock_monotonic))
