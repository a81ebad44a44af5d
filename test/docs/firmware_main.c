/* SPDX-License-Identifier: Apache-2.0 */
/* The firmware block of docs/firmware.md, compiled as printed (this
 * directory's CMakeLists.txt cuts it out into firmware_snippet.c) and run:
 * the smallest controller, 100 periods on the loopback, no fault, one frame
 * a period; then the e-stop pressed (the fault cannot be cleared), released
 * and cleared. A page whose block stops compiling or running fails this
 * test. */
#include <stdio.h>

#include "roz/hal/clock.h"
#include "roz/runtime.h"

/* the application's own header would declare them */
int controller_start(const uint8_t *wasm, size_t wasm_len, roz_clock_fn clock, char *err,
                     size_t errlen);
void controller_period(void);
void estop_isr(int pressed);
void controller_supervise(int operator_acknowledged);

#include "firmware_snippet.c"

/* (module (func (export "process") (param i64))) */
static const uint8_t idle_wasm[] = {
    0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00, 0x01, 0x05, 0x01, 0x60, 0x01,
    0x7e, 0x00, 0x03, 0x02, 0x01, 0x00, 0x07, 0x0b, 0x01, 0x07, 0x70, 0x72, 0x6f,
    0x63, 0x65, 0x73, 0x73, 0x00, 0x00, 0x0a, 0x04, 0x01, 0x02, 0x00, 0x0b,
};

int main(void)
{
    char err[160] = "";

    if (controller_start(idle_wasm, sizeof idle_wasm, roz_clock_monotonic_ns, err, sizeof err)
        != 0) {
        fprintf(stderr, "docs firmware: controller_start: %s\n", err);
        return 1;
    }
    for (int t = 0; t < 100; t++)
        controller_period();
    roz_runtime_stats_t st;
    if (roz_runtime_stats(&rt, &st) != ROZ_OK || roz_runtime_faults(&rt) != 0 ||
        st.runtime.writes != 100 || roz_loopback_counters(&sim).violations != 0) {
        fprintf(stderr, "docs firmware: faults 0x%x, %llu frames\n", roz_runtime_faults(&rt),
                (unsigned long long)st.runtime.writes);
        return 1;
    }
    /* the e-stop: pressed, the fault cannot be cleared; released, it can */
    estop_isr(1);
    controller_period();
    controller_supervise(1);
    controller_period();
    if (!(roz_runtime_faults(&rt) & ROZ_FAULT_ESTOP)) {
        fprintf(stderr, "docs firmware: ESTOP cleared while pressed\n");
        return 1;
    }
    estop_isr(0);
    controller_supervise(1);
    for (int t = 0; t < 3; t++)
        controller_period();
    if (roz_runtime_faults(&rt) != 0) {
        fprintf(stderr, "docs firmware: faults 0x%x after release and clear\n",
                roz_runtime_faults(&rt));
        return 1;
    }
    printf("docs firmware: 100 periods, no fault; e-stop held, released, cleared\n");
    return 0;
}
