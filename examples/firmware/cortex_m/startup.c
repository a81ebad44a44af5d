/* SPDX-License-Identifier: Apache-2.0 */
/* Start-up for ARMv7-M and ARMv8-M Mainline (Cortex-M4F, M7, M33; on the
 * M33 in the Secure state it resets in) under the boards' linker scripts
 * (boards/): the vector table, the reset handler (FPU on, .data
 * copied, .bss zeroed, the stack painted), fault handlers that say what
 * happened and stop the run, and SysTick as the clock. */
#include <stdint.h>
#include <string.h>

#include "board.h"
#include "clock_ns.h"
#include "semihosting.h"

/* The core's clock, from the board file (boards/<board>.cmake). */
#ifndef FW_CLOCK_HZ
#error "FW_CLOCK_HZ: the board's core clock in Hz (set by the board file)"
#endif

extern uint32_t __stack_top[], __stack_bottom[];
extern uint32_t _sidata[], _sdata[], _edata[], _sbss[], _ebss[];

int main(void);
void Reset_Handler(void);
void Fault_Handler(void);
void SysTick_Handler(void);

#define PAINT 0xa5a5a5a5u

#define SCB_HFSR  (*(volatile uint32_t *)0xe000ed2cu)
#define SCB_CFSR  (*(volatile uint32_t *)0xe000ed28u)
#define SYST_CSR  (*(volatile uint32_t *)0xe000e010u)
#define SYST_RVR  (*(volatile uint32_t *)0xe000e014u)
#define SYST_CVR  (*(volatile uint32_t *)0xe000e018u)

/* ---- the vector table -------------------------------------------------------- */

__attribute__((section(".vectors"), used))
static void (*const vectors[16])(void) = {
    (void (*)(void))(uintptr_t)__stack_top,
    Reset_Handler,
    Fault_Handler, /* NMI */
    Fault_Handler, /* HardFault */
    Fault_Handler, /* MemManage */
    Fault_Handler, /* BusFault */
    Fault_Handler, /* UsageFault */
    Fault_Handler, /* SecureFault (ARMv8-M; reserved on ARMv7-M) */
    0, 0, 0,
    Fault_Handler, /* SVCall */
    Fault_Handler, /* DebugMon */
    0,
    Fault_Handler, /* PendSV */
    SysTick_Handler,
};

/* ---- reset ---------------------------------------------------------------------- */

__attribute__((noreturn, naked)) void Reset_Handler(void)
{
    /* CP10 and CP11 (the FPU) full access, before any floating-point
     * instruction; then C can run. */
    __asm__ volatile("movw r0, #0xed88\n"
                     "movt r0, #0xe000\n"
                     "ldr r1, [r0]\n"
                     "orr r1, r1, #(0xf << 20)\n"
                     "str r1, [r0]\n"
                     "dsb\n"
                     "isb\n"
                     "b fw_reset_c\n");
}

__attribute__((noreturn, used)) void fw_reset_c(void);
__attribute__((noreturn, used)) void fw_reset_c(void)
{
    memcpy(_sdata, _sidata, (size_t)((char *)_edata - (char *)_sdata));
    memset(_sbss, 0, (size_t)((char *)_ebss - (char *)_sbss));
    /* paint the stack below this frame, for the high-water mark */
    uintptr_t here = (uintptr_t)__builtin_frame_address(0) - 64u;
    for (uint32_t *p = __stack_bottom; (uintptr_t)p < here; p++)
        *p = PAINT;
    fw_semihost_exit(main());
}

size_t fw_stack_size(void)
{
    return (size_t)((char *)__stack_top - (char *)__stack_bottom);
}

size_t fw_stack_high_water(void)
{
    const uint32_t *p = __stack_bottom;
    while (p < __stack_top && *p == PAINT)
        p++;
    return (size_t)((const char *)__stack_top - (const char *)p);
}

/* ---- faults ---------------------------------------------------------------------- */

static void hex32(char *out, uint32_t v)
{
    for (int i = 0; i < 8; i++)
        out[i] = "0123456789abcdef"[(v >> (28 - 4 * i)) & 0xfu];
    out[8] = '\0';
}

void Fault_Handler(void)
{
    char h[9];
    uint32_t ipsr;

    __asm__ volatile("mrs %0, ipsr" : "=r"(ipsr));
    fw_semihost_write("fault: exception ");
    hex32(h, ipsr & 0x1ffu);
    fw_semihost_write(h);
    fw_semihost_write(", HFSR ");
    hex32(h, SCB_HFSR);
    fw_semihost_write(h);
    fw_semihost_write(", CFSR ");
    hex32(h, SCB_CFSR);
    fw_semihost_write(h);
    fw_semihost_write("\n");
    fw_semihost_exit(3);
}

/* ---- the clock ------------------------------------------------------------------- */

/* SysTick counts the processor clock down from 2^24 - 1; each wrap is
 * counted here. */
static volatile uint32_t wraps;

void SysTick_Handler(void)
{
    wraps++;
}

void fw_clock_start(void)
{
    SYST_RVR = 0x00ffffffu;
    SYST_CVR = 0;
    SYST_CSR = 0x7u; /* enable, interrupt, processor clock */
}

uint64_t fw_clock_ns(void *ctx)
{
    uint32_t w1, w2, v;

    (void)ctx;
    do { /* a wrap between the two reads is seen in `wraps` */
        w1 = wraps;
        v = SYST_CVR;
        w2 = wraps;
    } while (w1 != w2);
    uint64_t cycles = ((uint64_t)w1 << 24) + (0x00ffffffu - v);
    return fw_cycles_to_ns(cycles, (uint32_t)FW_CLOCK_HZ);
}
