/* SPDX-License-Identifier: Apache-2.0 */
/* A firmware image's main(): the board's clock and semihosting around the
 * portable application (../app/fw_app.c). Which robot and controller is the
 * build's choice (examples/firmware/CMakeLists.txt):
 *   FW_MANIFEST_HEADER  rozgen's header of the robot's table
 *   FW_MANIFEST         its roz_manifest_t
 *   FW_CONTROLLER       the controller's file name, for the report
 *   FW_USE_CLOCK        1: the runtime runs with SysTick as its clock;
 *                       0: none, so fuel alone bounds a controller
 *   FW_EXPECT_FAULT     1: the image is hostile, a fault must latch
 *   FW_BOARD            "cortex-m4f (mps2-an386)", ...
 * The controller's bytes are a C array generated from its .wasm at build
 * time (fw_wasm, fw_wasm_len); with FW_AOT 1 (fw_app.h) the controller is
 * compiled in instead, FW_AOT_MODULE its roz_aot_module_t (roz_aot_<name>). Exit status: 0 when the run went as the
 * image expects (no fault, no value outside the manifest at the robot;
 * or, hostile, a fault latched and every tick still ran), 1 otherwise. */
#include <stddef.h>
#include <stdint.h>

#include "board.h"
#include "fw_app.h"
#include "roz/format.h"
#include "semihosting.h"
#include FW_MANIFEST_HEADER

#if FW_AOT
extern const roz_aot_module_t FW_AOT_MODULE; /* ROZ_AOT_DECLARE()'s */
#define FW_IMAGE_CODE NULL, 0, &FW_AOT_MODULE
#else
extern const uint8_t fw_wasm[];
extern const size_t fw_wasm_len;
#define FW_IMAGE_CODE fw_wasm, fw_wasm_len, NULL
#endif

/* The validator's scratch: one static buffer, loads run one at a time. */
static roz_load_scratch_t scratch;

static void print_line(const char *line)
{
    fw_semihost_write(line);
    fw_semihost_write("\n");
}

int main(void)
{
    fw_platform_t pf = { FW_BOARD, fw_clock_ns, NULL, print_line, &scratch };
    fw_image_t img = { FW_CONTROLLER, &FW_MANIFEST, FW_IMAGE_CODE, FW_TICKS, FW_USE_CLOCK };
    fw_result_t res;
    char line[160];
    int ok;

    fw_clock_start();
    if (fw_app_run(&img, &pf, &res) != 0)
        return 1;
    roz_format(line, sizeof line, "memory: heap high-water %lu of %lu bytes, stack high-water "
               "%lu of %lu bytes", (unsigned long)fw_heap_high_water(),
               (unsigned long)fw_heap_size(), (unsigned long)fw_stack_high_water(),
               (unsigned long)fw_stack_size());
    print_line(line);
#if FW_EXPECT_FAULT
    ok = res.faults != 0u && res.fault_tick != UINT32_MAX && res.violations == 0u;
#else
    ok = res.faults == 0u && res.violations == 0u;
#endif
    print_line(ok ? "result: as expected" : "result: NOT as expected");
    return ok ? 0 : 1;
}
