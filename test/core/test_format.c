/* SPDX-License-Identifier: Apache-2.0 */
/* roz_format(), the formatter of every roz message: each conversion roz
 * uses gives the text the host's C library gives (glibc is the reference
 * here; the firmware images check the same text under newlib-nano, which
 * is why roz does not use the C library's), cutting and the returned
 * length behave as snprintf's, and an unsupported conversion shows itself
 * without taking an argument. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "roz/format.h"
#include "support.h"
#include "support_thin.h"

/* under an emulator, a THIN-th of the generated values (support_thin.h) */
#define THIN ROZ_TEST_THIN(8)

/* roz_format and snprintf on the same format and arguments, compared. */
#define SAME(...)                                                \
    do {                                                         \
        char want_[128], got_[128];                              \
        int wn_ = snprintf(want_, sizeof want_, __VA_ARGS__);    \
        int gn_ = roz_format(got_, sizeof got_, __VA_ARGS__);    \
        assert_string_equal(got_, want_);                        \
        assert_int_equal(gn_, wn_);                              \
    } while (0)

static void test_format_integers(void **st)
{
    (void)st;
    SAME("%d %i %u", -12, 0, 4294967295u);
    SAME("%lld %llu", (long long)INT64_MIN, (unsigned long long)UINT64_MAX);
    SAME("%ld %lu %lx", -7L, 123456789UL, 0xdeadbeefUL);
    SAME("%zu bytes, limit %u", (size_t)32776, 32768u);
    SAME("%016llx|%02x|%X", 0x1234abcdULL, 7u, 0xbeefu);
    SAME("[%5d][%-5d][%05d][%-3u][%*u]", -42, 42, -42, 7u, 6, 9u);
    SAME("%hhu %hd %jd %td", (unsigned char)255, (short)-3, (intmax_t)-9, (ptrdiff_t)5);
    SAME("%lld at tick %lld", 0LL, 9223372036854775807LL);
}

static void test_format_strings(void **st)
{
    (void)st;
    SAME("%s|%.3s|%.*s|%8s|%-8s|%c%%", "abc", "abcdef", 2, "xyz", "r", "l", 'q');
    SAME("%.*s", 0, "none");
}

static void test_format_g(void **st)
{
    static const double v[] = {
        0.0, -0.0, 1.0, -1.0, 0.5, 0.1, 0.2, 0.3, 1.5, 2.5, 3.14, 3.14159265358979,
        6.283185307179586, 8.0, 20.0, 100.0, 123456.0, 999999.0, 999999.5, 1e6, 1234567.0,
        1e-4, 1e-5, 0.000123456789, 12345.678, 1e21, 1e22, 1e100, 2.2250738585072014e-308,
        1.7976931348623157e308, 65535.0, 4294967295.0, 0.001, 5e-324 * 1e300, 1.0 / 3.0,
        2.0 / 3.0, 1e15, 1e16 + 2.0, 0.05, 0.025, 1.25e-3, 33.3, -2.5e-7,
    };
    (void)st;
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        SAME("%g", v[i]);
        SAME("%.3g|%.1g|%.10g|%.0g", v[i], v[i], v[i], v[i]);
        SAME("[%12g][%-12g][%012g]", v[i], v[i], v[i]);
    }
    SAME("%.2g %.2g %.1g %.1g %.3g", 0.125, 0.375, 2.5, 0.35, 1.0005);
    SAME("%.15g %.15g %.12g", 3.14159265358979, 0.1, 123456.789012345);
    SAME("%g %g %g", (double)NAN, (double)INFINITY, -(double)INFINITY);
    SAME("in %g..%g", 0.0, 20.0);
}

/* 20,000 values from a fixed generator, spread over 1e-12..1e18 and cut to
 * few decimal digits (ties are where rounding goes wrong), at 1..10
 * significant digits. */
static void test_format_g_many(void **st)
{
    uint64_t r = 0x9e3779b97f4a7c15u;
    (void)st;
    for (int i = 0; i < 20000 / THIN; i++) {
        r = r * 6364136223846793005u + 1442695040888963407u;
        double m = (double)(r >> 40) / (double)(1u << 24);          /* 0..1 */
        int e = (int)((r >> 8) % 31u) - 12;                          /* -12..18 */
        double x = m;
        for (int k = 0; k < (e < 0 ? -e : e); k++)
            x = e < 0 ? x / 10.0 : x * 10.0;
        if (i % 2 == 0) /* a value with few digits: 0.025, 1.5e-05, ... */
            x = (double)(r % 100000u) / 1000.0 * (e < 0 ? 1e-3 : 1e3);
        int prec = 1 + (int)((r >> 3) % 10u);
        SAME("%.*g", prec, x);
        SAME("%g", -x);
    }
}

/* The C library's shortest round-trip %g (rozgen's fmt.shortest_g), the
 * reference for roz_format_double(). */
static void shortest_libc(double x, char out[48])
{
    if (isnan(x)) {
        strcpy(out, "nan");
        return;
    }
    if (isinf(x)) {
        strcpy(out, x > 0 ? "inf" : "-inf");
        return;
    }
    for (int p = 1; p <= 17; p++) {
        snprintf(out, 48, "%.*g", p, x);
        if (strtod(out, NULL) == x)
            break;
    }
    const char *e = strchr(out, 'e');
    if (e != NULL && atoi(e + 1) >= 0 && atoi(e + 1) < 16)
        snprintf(out, 48, "%.*g", atoi(e + 1) + 1, x);
}

/* roz_format_double() against the C library: chosen values (16 and 17
 * digits, ties, integral values written out, the extremes), then 50,000
 * from a fixed generator, raw bit patterns among them. */
static void test_format_double(void **st)
{
    static const double v[] = { 0.0, -0.0, 1.0, 0.1, 0.3, 6.283185307179586, -3.14, 12.5,
                                1500.0, 1e15, 1e16, 1e17, 123456789012345678.0, 0.025, 2.5,
                                5e-324, 2.2250738585072014e-308, 1.7976931348623157e308,
                                9.999999999999999e22, 1e23, 1e-5, 1e-4, 4.35, -1.2, 2047.0 };
    uint64_t r = 0x2545f4914f6cdd1du;
    char a[48], b[48];
    (void)st;
    for (int i = 0; i < 50000 / THIN + (int)(sizeof v / sizeof v[0]); i++) {
        double x;
        if (i < (int)(sizeof v / sizeof v[0])) {
            x = v[i];
        } else {
            r ^= r << 13;
            r ^= r >> 7;
            r ^= r << 17;
            if (i % 3 == 0)
                memcpy(&x, &r, sizeof x);
            else if (i % 3 == 1)
                x = (double)(int64_t)(r % 2000000u) / 1000.0;
            else
                x = ldexp((double)(r >> 11), (int)(r % 120u) - 100);
        }
        int n = roz_format_double(a, sizeof a, x);
        assert_int_equal(n, (int)strlen(a));
        shortest_libc(x, b);
        if (strcmp(a, b) != 0)
            fail_msg("%.17g: roz_format_double gives %s, the C library %s", x, a, b);
    }
    assert_int_equal(roz_format_double(a, 4, 6.283185307179586), 17);
    assert_string_equal(a, "6.2");
}

static void test_format_cut(void **st)
{
    char b[8];
    (void)st;
    /* as snprintf: the length of the whole text, the buffer cut and ended */
    assert_int_equal(roz_format(b, sizeof b, "%s=%llu", "counter", 12345ULL), 13);
    assert_string_equal(b, "counter");
    assert_int_equal(roz_format(b, 1, "abc"), 3);
    assert_string_equal(b, "");
    assert_int_equal(roz_format(NULL, 0, "%d", 100), 3);
}

/* Not in roz's subset: shown as %?, and no argument is taken, so what
 * follows still prints right. */
static void test_format_unsupported(void **st)
{
    char b[64];
    (void)st;
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat"
#pragma GCC diagnostic ignored "-Wformat-extra-args"
    roz_format(b, sizeof b, "%f then %d", 7);
#pragma GCC diagnostic pop
    assert_string_equal(b, "%? then 7");
}

ROZ_TEST_MAIN(cmocka_unit_test(test_format_integers),
              cmocka_unit_test(test_format_strings),
              cmocka_unit_test(test_format_g),
              cmocka_unit_test(test_format_g_many),
              cmocka_unit_test(test_format_double),
              cmocka_unit_test(test_format_cut),
              cmocka_unit_test(test_format_unsupported))
