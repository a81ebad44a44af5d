/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/format.h
 * @brief The bounded text formatter every roz message is written with.
 *
 * roz formats its messages (load errors, faults, warnings, parameter
 * errors) itself instead of through the C library's snprintf: the text is
 * then the same on every target (a bare-metal C library such as newlib-nano
 * prints no `%lld`, `%zu` or `%g`, and mis-reads the arguments after one),
 * and a firmware that prints nothing else links no printf at all. The
 * conversions it takes: roz_format().
 */
#ifndef ROZ_FORMAT_H
#define ROZ_FORMAT_H

#include "roz/config.h"

#include <stdarg.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__) || defined(__clang__)
#define ROZ_FORMAT_CHECK(f, a) __attribute__((format(printf, f, a)))
#else
#define ROZ_FORMAT_CHECK(f, a)
#endif

/**
 * @brief Format into @p buf, at most @p len bytes with the terminating NUL:
 *        text past the end is cut; with @p len >= 1 the buffer is always
 *        terminated. No allocation, no locale, bounded stack.
 *
 * The conversions are a subset of C's, with C's meaning:
 *  - `%d %i %u %x %X` with the length modifiers `hh h l ll z j t`,
 *  - `%s`, `%.*s` / `%.Ns` (at most N characters), `%c`, `%p`, `%%`,
 *  - `%g` with an optional precision (significant digits, 6 by default, at
 *    most 15: a larger one prints 15):
 *    as C prints it (correctly rounded) where the value times 10^(digits -
 *    1 - its decimal exponent) is a product with a power of ten up to 10^22,
 *    i.e. with 6 digits for values from 1e-17 to 1e27; beyond, the last
 *    digit of a value within one rounding of a half-way point may differ
 *    (the same on every target: it is computed in IEEE double arithmetic),
 *    (with ROZ_CFG_FORMAT_DOUBLE 0, the value's bits instead:
 *    "f64:3ff0000000000000"),
 *  - flags `-` (left-justify) and `0` (pad with zeros), a width (a number
 *    or `*`).
 * Anything else (`%f`, `%e`, `%a`, `%n`, `+`, ` `, `#`, ...) prints as `%?`
 * and consumes no argument, so a mistake shows in the text instead of
 * shifting the arguments after it; build with -Wformat to catch it first.
 *
 * @return the length the whole text would have (as snprintf), so a result
 *         >= @p len means it was cut.
 * Context: any thread; reentrant. Not for the tick path (roz formats nothing
 * there).
 */
int roz_format(char *buf, size_t len, const char *fmt, ...) ROZ_FORMAT_CHECK(3, 4);

/** @brief roz_format() with a va_list. Context: as roz_format(). */
int roz_vformat(char *buf, size_t len, const char *fmt, va_list ap) ROZ_FORMAT_CHECK(3, 0);

/**
 * @brief The shortest text that reads back as @p x: `%g` with the fewest
 *        significant digits (1..17) that give @p x again, correctly rounded
 *        (half to even) from its exact value; an integral value below 1e16
 *        is written out without an exponent ("1500", not "1.5e+03");
 *        "nan", "inf", "-inf", "-0". The numbers of rozgen's messages
 *        (codegen/rozgen/fmt.py, shortest_g), the same on every target.
 * @return the length of the whole text (as roz_format()).
 * Context: any thread; reentrant; about 1 KiB of stack. Not for the tick path.
 * With ROZ_CFG_FORMAT_DOUBLE 0: the bits, as `%g` then prints them.
 */
int roz_format_double(char *buf, size_t len, double x);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_FORMAT_H */
