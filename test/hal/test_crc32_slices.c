/* SPDX-License-Identifier: Apache-2.0 */
/* roz_crc32_words() built with the small-flash tables (ROZ_CFG_CRC32_SLICES
 * 0 and 1, set by the build of this test) against the bit-by-bit
 * definition: the library's own build (4 tables) is test_link's. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

/* this build's roz_crc32_words() under a name of its own, beside roz::hal's */
#define roz_crc32_words crc_under_test
#include "crc32.c"
#undef roz_crc32_words

#include "crc32_reference.h"

static void test_crc32_small_tables(void **st)
{
    static uint32_t w[522];
    uint32_t x = 977u;
    (void)st;
    for (size_t i = 0; i < 522; i++) {
        x = x * 1664525u + 1013904223u;
        w[i] = x;
    }
    for (size_t n = 0; n <= 522; n += 29)
        assert_int_equal(crc_under_test(w, n), roz_crc32_reference(w, n));
    w[0] = 0u; /* a word of zeros, and of ones */
    w[1] = 0xFFFFFFFFu;
    assert_int_equal(crc_under_test(w, 2), roz_crc32_reference(w, 2));
    assert_int_equal(crc_under_test(NULL, 0), 0xFFFFFFFFu);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crc32_small_tables),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
