/* SPDX-License-Identifier: Apache-2.0 */
/* strcmp() and strlen() in their smallest form, in place of newlib's
 * (whose ARMv7-M strcmp, tuned for speed, is 732 bytes; strlen 220). roz
 * calls them at start-up (the manifest's checks, the loader's import
 * names, the port's parameters) and for a fault's message, never in a
 * tick's ordinary work, so their speed does not count and their size
 * does: 928 bytes of flash on the G1 image. The same results
 * as the C standard's: the first differing bytes as unsigned char.
 * Compiled without builtins and loop idioms (CMakeLists.txt), so the
 * compiler cannot turn the loops back into calls to themselves. */
#include <stddef.h>
#include <string.h>

int strcmp(const char *a, const char *b)
{
    const unsigned char *x = (const unsigned char *)a;
    const unsigned char *y = (const unsigned char *)b;

    while (*x != 0u && *x == *y) {
        x++;
        y++;
    }
    return (int)*x - (int)*y;
}

size_t strlen(const char *s)
{
    const char *p = s;

    while (*p != '\0')
        p++;
    return (size_t)(p - s);
}
