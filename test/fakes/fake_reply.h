/* SPDX-License-Identifier: Apache-2.0 */
/* The fake robots' replies on their line protocol (stdout, one line each):
 * what the fakes share, header-only. */
#ifndef ROZ_FAKE_REPLY_H
#define ROZ_FAKE_REPLY_H

#include <stdarg.h>
#include <stdio.h>

/* One reply line, flushed at once; 0, or -1 when stdout failed. */
__attribute__((format(printf, 1, 2)))
static int reply(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vprintf(fmt, ap);
    va_end(ap);
    if (n < 0 || putchar('\n') == EOF || fflush(stdout) != 0)
        return -1;
    return 0;
}

#endif /* ROZ_FAKE_REPLY_H */
