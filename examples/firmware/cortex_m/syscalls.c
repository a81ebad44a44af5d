/* SPDX-License-Identifier: Apache-2.0 */
/* The C library's hooks newlib-nano needs here: the heap (the region the
 * linker script reserves, never more: malloc gets NULL past it, and wasm3
 * reports out of memory), and exit. Nothing else is used: roz formats with
 * roz_format() and the images print through semihosting. */
#include <errno.h>
#include <stddef.h>
#include <stdint.h>

#include "board.h"
#include "semihosting.h"

extern char __heap_start[], __heap_end[];
static char *brk = __heap_start;
static size_t high;

void *_sbrk(ptrdiff_t inc);
void *_sbrk(ptrdiff_t inc)
{
    char *old = brk;

    if (inc > __heap_end - brk || inc < __heap_start - brk) {
        errno = ENOMEM;
        return (void *)-1;
    }
    brk += inc;
    if ((size_t)(brk - __heap_start) > high)
        high = (size_t)(brk - __heap_start);
    return old;
}

size_t fw_heap_size(void)
{
    return (size_t)(__heap_end - __heap_start);
}

size_t fw_heap_high_water(void)
{
    return high;
}

void _exit(int status);
void _exit(int status)
{
    fw_semihost_exit(status);
}
