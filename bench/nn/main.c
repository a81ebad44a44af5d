/* SPDX-License-Identifier: Apache-2.0 */
/*
 * One inference of the G1 policy's shape (47 -> LSTM 64 -> 32 ELU -> 12),
 * in the same run: through roz_nn.h and the nn imports under wasm3
 * (metered), as plain wasm (roz_nn.h's loops compiled into the module),
 * and natively (the same header, its plain-C imports, -O2
 * -ffp-contract=off): p50 of CPU time per call, and the fuel of one
 * inference. The same shape deployed by rozgen-nn deploy (roz_policy.h
 * over the G1's deploy_real configuration: g1_deployed_full of
 * examples/controllers): its inference tick (every 10th tick: observations,
 * the network, 145 targets) under wasm3 and natively. Then what the nn
 * imports' work costs the host per fuel unit
 * (nn.matvec on the LSTM's matrices, nn.act on 64 elements), to set
 * against bench/fuel's cost of a unit of wasm.
 *
 *   roz_bench_nn [calls] [--json FILE]
 */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_json.h"
#include "roz/abi.h"
#include "roz/controller.h"
#include "roz/module.h"
#include "unitree_g1_channels.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"

#include "policy.h" /* natively: roz_nn.h's plain-C imports */

static roz_controller_t ctl;
static roz_abi_t abi;
static double state[ROZ_CFG_MAX_STATES];
static double targets[ROZ_CFG_MAX_COMMANDS];
static uint64_t t_ns[100000];
static volatile float sink;

static uint64_t cpu_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

/* p50 of `calls` timed calls of process() of the module at path on
 * manifest m: every call, or (every > 1) the calls of ticks k * every, k > 0
 * (a deployed policy's inference ticks; the others run untimed); *fuel that
 * of the last timed call (every inference costs the same). */
static bench_stats_t run_wasm(const char *path, const roz_manifest_t *m, int calls, int every,
                              uint64_t *fuel)
{
    static uint8_t wasm[1 << 20];
    size_t len = 0;
    roz_budget_t b = { 100000000, ROZ_BUDGET_OFF, NULL, NULL };
    char err[256];
    if (roz_module_read_file(path, wasm, sizeof wasm, &len, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "roz_bench_nn: %s\n", err);
        exit(1);
    }
    roz_controller_init(&ctl);
    roz_abi_init(&abi, m, targets, NULL);
    if (roz_controller_load(&ctl, wasm, len, &abi) != ROZ_OK ||
        roz_controller_set_budget(&ctl, &b) != ROZ_OK) {
        fprintf(stderr, "roz_bench_nn: %s: %s\n", path, roz_controller_error(&ctl));
        exit(1);
    }
    for (int t = 0, n = 0; n < calls; t++) {
        roz_abi_begin_tick(&abi, t, state);
        uint64_t t0 = cpu_ns();
        int rc = roz_controller_process(&ctl, t);
        uint64_t dt = cpu_ns() - t0;
        if (rc != ROZ_OK) {
            fprintf(stderr, "roz_bench_nn: %s: %s\n", path, roz_controller_error(&ctl));
            exit(1);
        }
        if (every == 1 || (t > 0 && t % every == 0)) {
            t_ns[n++] = dt;
            *fuel = roz_controller_fuel_used(&ctl);
        }
    }
    roz_controller_unload(&ctl);
    return bench_stats(t_ns, (size_t)calls);
}

/* The deployed controller built natively (g1_deployed_full.c): its imports */
int roz_state_get_all(double *values, int count)
{
    memcpy(values, state, sizeof values[0] * (size_t)count);
    return count;
}

int roz_command_set_all(const double *values, int count)
{
    memcpy(targets, values, sizeof values[0] * (size_t)count);
    return 0;
}

void roz_request_estop(void)
{
    fprintf(stderr, "roz_bench_nn: the native deployed controller asked for an e-stop\n");
    exit(1);
}

static bench_stats_t run_deployed_native(int calls)
{
    for (int t = 0, n = 0; n < calls; t++) {
        uint64_t t0 = cpu_ns();
        roz_native_process(t);
        uint64_t dt = cpu_ns() - t0;
        if (t > 0 && t % 10 == 0)
            t_ns[n++] = dt;
    }
    return bench_stats(t_ns, (size_t)calls);
}

static bench_stats_t run_native(int calls)
{
    for (int t = 0; t < calls; t++) {
        uint64_t t0 = cpu_ns();
        sink = bench_infer(t);
        t_ns[t] = cpu_ns() - t0;
    }
    return bench_stats(t_ns, (size_t)calls);
}

/* ns per fuel unit of the host's nn work: the LSTM's two products, then
 * each activation on 64 values, `reps` times */
static uint8_t mem[65536 * 2];
static void unit_costs(const bench_json_t *j, int reps)
{
    static const char *names[] = { "relu", "tanh", "sigmoid", "elu", "exp" };
    uint64_t t0, units = roz_abi_nn_matvec_units(256, 47) + roz_abi_nn_matvec_units(256, 64);
    for (size_t i = 0; i + 4 <= sizeof mem; i += 4) {
        float f = (float)(i % 397) * 0.005f - 1.0f;
        memcpy(mem + i, &f, 4);
    }
    roz_abi_init(&abi, &roz_manifest_ur5, targets, NULL);
    t0 = cpu_ns();
    for (int r = 0; r < reps; r++) {
        (void)roz_abi_nn_matvec(&abi, mem, sizeof mem, 0, 114000, 115000, 117000, 256, 47, 1);
        (void)roz_abi_nn_matvec(&abi, mem, sizeof mem, 48128, 114000, 115000, 117000, 256, 64, 3);
    }
    double ns = (double)(cpu_ns() - t0) / reps;
    printf("  nn.matvec 256x47 + 256x64 (%llu units): %.2f us, %.3f ns a unit\n",
           (unsigned long long)units, ns / 1000.0, ns / (double)units);
    bench_json_value(j, "nn.matvec, ns per unit", ns / (double)units, "ns");
    for (int k = 0; k < ROZ_ABI_NN_ACT_COUNT; k++) {
        uint64_t u = roz_abi_nn_act_units(k, 64);
        t0 = cpu_ns();
        for (int r = 0; r < reps * 4; r++) {
            (void)roz_abi_nn_act(&abi, mem, sizeof mem, k, 120000, 64);
            /* the same inputs each time: restore them */
            memcpy(mem + 120000, mem + 125000, 256);
        }
        ns = (double)(cpu_ns() - t0) / (reps * 4);
        printf("  nn.act %-7s x64 (%llu units): %.3f us, %.3f ns a unit\n", names[k],
               (unsigned long long)u, ns / 1000.0, ns / (double)u);
        char name[64];
        snprintf(name, sizeof name, "nn.act %s, ns per unit", names[k]);
        bench_json_value(j, name, ns / (double)u, "ns");
    }
}

/* The same work on the numbers that take a CPU's slow path (subnormal
 * floats, in or out; roz/abi.h's rule for tiny numbers): one row of 16,000
 * with W and x at 1e-20 (each product 1e-40, one chain of sums), and each
 * activation on subnormal inputs and on inputs whose exp or sigmoid is
 * subnormal (-87.5). */
static void tiny_costs(const bench_json_t *j, int reps)
{
    static const char *names[] = { "relu", "tanh", "sigmoid", "elu", "exp" };
    const int32_t cols = 16000;
    const float one_row[2] = { 0.5f, 1e-20f }, sub[2] = { 3e-39f, -87.5f };
    static const char *const row_names[2] = { "nn.matvec, one row, ns per unit",
                                              "nn.matvec, one row, subnormal products, ns per unit" };
    uint64_t units = roz_abi_nn_matvec_units(1, cols), t0;
    double ns;
    roz_abi_init(&abi, &roz_manifest_ur5, targets, NULL);
    for (int k = 0; k < 2; k++) {
        for (size_t i = 0; i + 4 <= sizeof mem; i += 4)
            memcpy(mem + i, &one_row[k], 4);
        t0 = cpu_ns();
        for (int r = 0; r < reps; r++)
            (void)roz_abi_nn_matvec(&abi, mem, sizeof mem, 0, 64000, 0, 128000, 1, cols, 0);
        ns = (double)(cpu_ns() - t0) / reps;
        printf("  nn.matvec 1x%d of %g (%llu units): %.2f us, %.3f ns a unit\n", (int)cols,
               (double)one_row[k], (unsigned long long)units, ns / 1000.0, ns / (double)units);
        bench_json_value(j, row_names[k], ns / (double)units, "ns");
    }
    for (int k = 0; k < ROZ_ABI_NN_ACT_COUNT; k++) {
        uint64_t u = roz_abi_nn_act_units(k, 64);
        double worst = 0.0;
        for (int s = 0; s < 2; s++) {
            for (uint32_t i = 0; i < 64; i++)
                memcpy(mem + 125000 + 4u * i, &sub[s], 4);
            t0 = cpu_ns();
            for (int r = 0; r < reps * 4; r++) {
                (void)roz_abi_nn_act(&abi, mem, sizeof mem, k, 120000, 64);
                memcpy(mem + 120000, mem + 125000, 256);
            }
            ns = (double)(cpu_ns() - t0) / (reps * 4);
            if (ns > worst)
                worst = ns;
        }
        printf("  nn.act %-7s x64 subnormal in or out (%llu units): %.3f us, %.3f ns a unit\n",
               names[k], (unsigned long long)u, worst / 1000.0, worst / (double)u);
        char name[80];
        snprintf(name, sizeof name, "nn.act %s, subnormal in or out, ns per unit", names[k]);
        bench_json_value(j, name, worst / (double)u, "ns");
    }
}

int main(int argc, char **argv)
{
    bench_json_t j;
    argc = bench_json_args(&j, "nn", argc, argv);
    if (argc < 0)
        return 1;
    int calls = argc > 1 ? atoi(argv[1]) : 5000;
    if (calls < 100 || calls > 100000)
        calls = 5000;
    uint64_t fuel_sdk = 0, fuel_plain = 0;
    bench_stats_t nat = run_native(calls);
    bench_stats_t sdk = run_wasm(ROZ_BENCH_NN_POLICY, &roz_manifest_ur5, calls, 1, &fuel_sdk);
    bench_stats_t plain = run_wasm(ROZ_BENCH_NN_POLICY_PLAIN, &roz_manifest_ur5, calls / 10 + 100, 1, &fuel_plain);
    bench_stats_t nat2 = run_native(calls); /* again, after: the host's speed drifts */
    if (nat2.p50 < nat.p50)
        nat = nat2;
    /* the deployed controller: a standing G1's state (the IMU level) */
    uint64_t fuel_dep = 0;
    memset(state, 0, sizeof state);
    state[ROZ_UNITREE_G1_STATE_BASE_IMU_ORIENTATION_W] = 1.0;
    bench_stats_t dep_nat = run_deployed_native(calls);
    bench_stats_t dep = run_wasm(ROZ_BENCH_NN_DEPLOYED, &roz_manifest_unitree_g1, calls, 10,
                                 &fuel_dep);
    bench_stats_t dep_nat2 = run_deployed_native(calls);
    if (dep_nat2.p50 < dep_nat.p50)
        dep_nat = dep_nat2;
    printf("G1 policy inference (47 -> LSTM 64 -> 32 ELU -> 12), p50 CPU time, %d calls:\n",
           calls);
    printf("  native C (roz_nn.h, plain loops)   %8.2f us\n", nat.p50);
    printf("  wasm3, roz_nn.h + nn imports       %8.2f us  (%.2fx native)  %llu fuel units\n",
           sdk.p50, sdk.p50 / nat.p50, (unsigned long long)fuel_sdk);
    printf("  wasm3, the same loops in wasm      %8.2f us  (%.2fx native)  %llu fuel units\n",
           plain.p50, plain.p50 / nat.p50, (unsigned long long)fuel_plain);
    printf("The same shape deployed (rozgen-nn deploy, roz_policy.h on the G1), an inference tick:\n");
    printf("  native C                           %8.2f us\n", dep_nat.p50);
    printf("  wasm3 + nn imports                 %8.2f us  (%.2fx native)  %llu fuel units\n",
           dep.p50, dep.p50 / dep_nat.p50, (unsigned long long)fuel_dep);
    bench_json_timing(&j, "deployed inference tick, native C", dep_nat);
    bench_json_timing(&j, "deployed inference tick, wasm3 + nn imports", dep);
    bench_json_value(&j, "deployed inference tick fuel", (double)fuel_dep, "units");
    bench_json_timing(&j, "policy inference, native C", nat);
    bench_json_timing(&j, "policy inference, wasm3 + nn imports", sdk);
    bench_json_timing(&j, "policy inference, wasm3, plain wasm", plain);
    bench_json_value(&j, "policy inference fuel, nn imports", (double)fuel_sdk, "units");
    bench_json_value(&j, "policy inference fuel, plain wasm", (double)fuel_plain, "units");
    printf("What the nn imports' work costs per fuel unit (CPU time):\n");
    unit_costs(&j, calls / 5 + 50);
    tiny_costs(&j, calls / 50 + 20);
    bench_json_close(&j);
    return 0;
}
