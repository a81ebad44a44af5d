/* SPDX-License-Identifier: Apache-2.0 */
/* What the nn imports' work costs this core, per fuel unit: nn.matvec and
 * each nn.act kind on ordinary values and on the worst ones (tiny and
 * subnormal numbers, arguments past the activations' cut-offs), timed by
 * the board's clock. Under QEMU with -icount shift=0 a nanosecond is an
 * instruction, so the figures are instructions per unit: compare them with
 * what a unit of wasm costs here (the process cost per fuel unit of a
 * firmware image's report; docs/budget.md, "Fuel per target"). Built with
 * -DROZ_FW_VARIANT=policy (roz_fw_nn_cost.elf), run by tools/fw_run.sh. */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "board.h"
#include "roz/abi.h"
#include "roz/format.h"
#include "semihosting.h"

static roz_abi_t abi; /* the imports only count their calls in it */
static uint8_t mem[48 * 1024];

static void say(const char *line)
{
    fw_semihost_write(line);
    fw_semihost_write("\n");
}

static void fill(uint32_t at, uint32_t n, float lo, float hi)
{
    for (uint32_t i = 0; i < n; i++) {
        float f = lo + (hi - lo) * (float)i / (float)(n > 1 ? n - 1 : 1);
        memcpy(mem + at + 4u * i, &f, 4);
    }
}

/* instructions (ns under -icount shift=0) per unit, in hundredths */
static unsigned long per_unit(uint64_t ns, uint64_t units)
{
    return (unsigned long)((ns * 100u + units / 2u) / units);
}

static void report(const char *what, uint64_t ns, uint64_t units)
{
    char line[160];
    unsigned long c = per_unit(ns, units);
    roz_format(line, sizeof line, "nn cost: %-34s %8lu units %10lu instr  %lu.%02lu a unit",
               what, (unsigned long)units, (unsigned long)ns, c / 100u, c % 100u);
    say(line);
}

static void matvec(const char *what, int32_t rows, int32_t cols, float lo, float hi)
{
    uint32_t x = 4u * (uint32_t)(rows * cols), y = x + 4u * (uint32_t)cols;
    fill(0, (uint32_t)(rows * cols), lo, hi);
    fill(x, (uint32_t)cols, lo, hi);
    uint64_t t0 = fw_clock_ns(NULL);
    (void)roz_abi_nn_matvec(&abi, mem, sizeof mem, 0, x, 0, y, rows, cols, 0);
    report(what, fw_clock_ns(NULL) - t0, roz_abi_nn_matvec_units(rows, cols));
}

static void act(const char *what, int kind, float lo, float hi)
{
    const int32_t n = 256;
    fill(0, (uint32_t)n, lo, hi);
    uint64_t t0 = fw_clock_ns(NULL);
    (void)roz_abi_nn_act(&abi, mem, sizeof mem, kind, 0, n);
    report(what, fw_clock_ns(NULL) - t0, roz_abi_nn_act_units(kind, n));
}

int main(void)
{
    static const char *const names[ROZ_ABI_NN_ACT_COUNT] = { "relu", "tanh", "sigmoid", "elu",
                                                             "exp" };
    char what[48];
    fw_clock_start();
    say("nn cost: " FW_BOARD);
    matvec("matvec 64 x 64", 64, 64, -1.0f, 1.0f);
    matvec("matvec 1 x 4096 (one row)", 1, 4096, -1.0f, 1.0f);
    matvec("matvec 64 x 64, 1e-20 (read as 0)", 64, 64, 1e-20f, 2e-20f);
    matvec("matvec 64 x 64, 2^-51 (products 2^-102)", 64, 64, 0x1p-51f, 0x1.8p-51f);
    for (int k = 0; k < ROZ_ABI_NN_ACT_COUNT; k++) {
        roz_format(what, sizeof what, "act %s on [-4, 4]", names[k]);
        act(what, k, -4.0f, 4.0f);
        roz_format(what, sizeof what, "act %s on [-100, 100]", names[k]);
        act(what, k, -100.0f, 100.0f);
        roz_format(what, sizeof what, "act %s on [-1e-3, 1e-3]", names[k]);
        act(what, k, -1e-3f, 1e-3f);
        roz_format(what, sizeof what, "act %s on subnormals", names[k]);
        act(what, k, -1e-39f, 1e-39f);
    }
    say("result: as expected");
    return 0;
}
