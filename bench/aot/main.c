/* SPDX-License-Identifier: Apache-2.0 */
/*
 * process() of the same controllers on both engines and natively, in the
 * same run: the G1 PD (examples/controllers/g1_pd.c: 58 state.get and 145
 * command.set a tick), the same through the bulk pair (g1_pd_bulk.c), and
 * one inference of the G1 policy's shape (bench/nn/policy.c: roz_nn.h and
 * the nn imports). Each is run
 *   - ahead of time: the module through rozaot and wasm2c, linked in
 *     (roz_controller_load_aot), with its fuel charges;
 *   - on wasm3, the module file, with its fuel charges;
 *   - natively: the same source compiled for the host against roz's ABI
 *     functions directly (no fuel, no sandbox).
 * The three take turns on every call, on the same states; time per call (the monotonic clock)
 * (p50, p99), the ratios to native, the fuel per call (the same on both
 * engines, checked), and whether the targets agree.
 *
 *   roz_bench_aot [calls] [--json FILE]
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_json.h"
#include "bench_native_abi.h" /* the native controllers' imports */
#include "roz/abi.h"
#include "roz/aot.h"
#include "roz/controller.h"
#include "roz/module.h"
#include "unitree_g1_manifest.h"

#include "policy.h" /* natively: roz_nn.h's plain-C imports */

ROZ_AOT_DECLARE(g1_pd);
ROZ_AOT_DECLARE(g1_pd_bulk);
ROZ_AOT_DECLARE(bench_nn_policy);

void roz_native_process(long long tick);         /* g1_pd.c */
void roz_native_process_g1_bulk(long long tick); /* g1_pd_bulk.c, renamed by the build */

static void native_policy(long long tick)
{
    roz_emit_metric((double)bench_infer(tick));
}

/* ---- the runs ------------------------------------------------------------------ */

static uint64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

typedef struct {
    const char             *name;
    const char             *wasm_path;
    const roz_aot_module_t *aot;
    void (*native)(long long);
} work_t;

static roz_controller_t c_w3, c_aot;
static roz_abi_t abi_w3, abi_aot;
static double t_w3[ROZ_CFG_MAX_COMMANDS], t_aot[ROZ_CFG_MAX_COMMANDS], t_nat[ROZ_CFG_MAX_COMMANDS];
static double state[ROZ_CFG_MAX_STATES];
static uint64_t ns_w3[100000], ns_aot[100000], ns_nat[100000];
static uint8_t wasm[1 << 20];

static int run(const work_t *w, int calls, const bench_json_t *j)
{
    const roz_manifest_t *m = &roz_manifest_unitree_g1;
    roz_budget_t b = { 100000000, ROZ_BUDGET_OFF, NULL, NULL };
    size_t len = 0;
    char err[256];
    long differ = 0;
    uint64_t fuel_w3 = 0, fuel_aot = 0;

    if (roz_module_read_file(w->wasm_path, wasm, sizeof wasm, &len, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "roz_bench_aot: %s\n", err);
        return -1;
    }
    roz_abi_init(&abi_w3, m, t_w3, NULL);
    roz_abi_init(&abi_aot, m, t_aot, NULL);
    roz_abi_init(&native_abi, m, t_nat, NULL);
    roz_controller_init(&c_w3);
    roz_controller_init(&c_aot);
    if (roz_controller_load(&c_w3, wasm, len, &abi_w3) != ROZ_OK ||
        roz_controller_set_budget(&c_w3, &b) != ROZ_OK ||
        roz_controller_load_aot(&c_aot, w->aot, &abi_aot) != ROZ_OK ||
        roz_controller_set_budget(&c_aot, &b) != ROZ_OK) {
        fprintf(stderr, "roz_bench_aot: %s: %s%s\n", w->name, roz_controller_error(&c_w3),
                roz_controller_error(&c_aot));
        return -1;
    }
    for (int t = 0; t < calls; t++) {
        for (uint16_t i = 0; i < m->n_states; i++)
            state[i] = 0.1 * sin(0.01 * (double)t + (double)i);
        roz_abi_begin_tick(&abi_w3, t, state);
        roz_abi_begin_tick(&abi_aot, t, state);
        roz_abi_begin_tick(&native_abi, t, state);
        uint64_t t0 = now_ns();
        int ra = roz_controller_process(&c_aot, t);
        uint64_t t1 = now_ns();
        int rw = roz_controller_process(&c_w3, t);
        uint64_t t2 = now_ns();
        w->native(t);
        uint64_t t3 = now_ns();
        if (ra != ROZ_OK || rw != ROZ_OK) {
            fprintf(stderr, "roz_bench_aot: %s: %s%s\n", w->name, roz_controller_error(&c_w3),
                    roz_controller_error(&c_aot));
            return -1;
        }
        ns_aot[t] = t1 - t0;
        ns_w3[t] = t2 - t1;
        ns_nat[t] = t3 - t2;
        fuel_w3 = roz_controller_fuel_used(&c_w3);
        fuel_aot = roz_controller_fuel_used(&c_aot);
        if (fuel_w3 != fuel_aot) {
            fprintf(stderr, "roz_bench_aot: %s: fuel %llu on wasm3, %llu ahead of time\n",
                    w->name, (unsigned long long)fuel_w3, (unsigned long long)fuel_aot);
            return -1;
        }
        for (uint16_t c = 0; c < m->n_commands; c++)
            differ += (t_aot[c] != t_w3[c]) + (t_aot[c] != t_nat[c] && !isnan(t_nat[c]));
    }
    roz_controller_unload(&c_w3);
    roz_controller_unload(&c_aot);
    bench_stats_t sa = bench_stats(ns_aot, (size_t)calls), sw = bench_stats(ns_w3, (size_t)calls),
                  sn = bench_stats(ns_nat, (size_t)calls);
    printf("%s (%llu fuel units a call, the same on both engines):\n", w->name,
           (unsigned long long)fuel_aot);
    printf("  %-24s %8.2f us p50 %8.2f us p99  %5.2fx native\n", "ahead of time (wasm2c)",
           sa.p50, sa.p99, sn.p50 > 0 ? sa.p50 / sn.p50 : 0.0);
    printf("  %-24s %8.2f us p50 %8.2f us p99  %5.2fx native\n", "wasm3", sw.p50, sw.p99,
           sn.p50 > 0 ? sw.p50 / sn.p50 : 0.0);
    printf("  %-24s %8.2f us p50 %8.2f us p99\n", "native C", sn.p50, sn.p99);
    printf("  targets: %s\n", differ == 0 ? "identical on all three" : "DIFFER");
    char name[128];
    snprintf(name, sizeof name, "%s: process(), ahead of time", w->name);
    bench_json_timing(j, name, sa);
    snprintf(name, sizeof name, "%s: process(), wasm3", w->name);
    bench_json_timing(j, name, sw);
    snprintf(name, sizeof name, "%s: process(), native", w->name);
    bench_json_timing(j, name, sn);
    snprintf(name, sizeof name, "%s: fuel per call", w->name);
    bench_json_value(j, name, (double)fuel_aot, "units");
    snprintf(name, sizeof name, "%s: targets differing", w->name);
    bench_json_value(j, name, (double)differ, "values");
    return differ == 0 ? 0 : 1;
}

int main(int argc, char **argv)
{
    bench_json_t j;
    argc = bench_json_args(&j, "aot", argc, argv);
    if (argc < 0)
        return 2;
    int calls = argc > 1 ? atoi(argv[1]) : 20000;
    if (calls < 100 || calls > 100000)
        calls = 20000;
    static const work_t work[] = {
        { "G1 PD", ROZ_BENCH_G1_PD, &roz_aot_g1_pd, roz_native_process },
        { "G1 PD (bulk)", ROZ_BENCH_G1_PD_BULK, &roz_aot_g1_pd_bulk, roz_native_process_g1_bulk },
        { "G1 policy (nn)", ROZ_BENCH_NN_POLICY, &roz_aot_bench_nn_policy, native_policy },
    };
    int bad = 0;
    printf("bench/aot: process(), time per call (monotonic clock), %d calls, the three in turn\n", calls);
    for (size_t k = 0; k < sizeof work / sizeof work[0]; k++) {
        int rc = run(&work[k], calls, &j);
        if (rc < 0)
            return 2;
        bad += rc;
    }
    bench_json_close(&j);
    return bad == 0 ? 0 : 1;
}
