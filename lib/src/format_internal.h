/* SPDX-License-Identifier: Apache-2.0 */
/* What format.c and format_double.c share (private to the core). */
#ifndef ROZ_FORMAT_INTERNAL_H
#define ROZ_FORMAT_INTERNAL_H

#include <stddef.h>

/* The %g text of the `prec` significant digits ds, d.ddd x 10^e, into s
 * (at least 32 bytes; trailing zeros dropped, C's choice between the fixed
 * and the exponent form); returns its length, no NUL written. */
size_t roz__format_layout_g(char *s, const char *ds, int prec, int e);

#endif /* ROZ_FORMAT_INTERNAL_H */
