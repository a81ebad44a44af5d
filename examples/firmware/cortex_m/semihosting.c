/* SPDX-License-Identifier: Apache-2.0 */
#include "semihosting.h"

#include <stdint.h>

#define SYS_WRITE0        0x04u
#define SYS_EXIT          0x18u
#define SYS_EXIT_EXTENDED 0x20u
#define ADP_Stopped_ApplicationExit 0x20026u

static uint32_t semihost(uint32_t op, const void *arg)
{
    register uint32_t r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void fw_semihost_write(const char *s)
{
    (void)semihost(SYS_WRITE0, s);
}

void fw_semihost_exit(int status)
{
    /* a 32-bit target passes the reason and the status in a block */
    const uint32_t block[2] = { ADP_Stopped_ApplicationExit, (uint32_t)status };
    (void)semihost(SYS_EXIT_EXTENDED, block);
    /* a host without the extension: plain exit (status lost) */
    (void)semihost(SYS_EXIT, (const void *)(uintptr_t)ADP_Stopped_ApplicationExit);
    for (;;) {
    }
}
