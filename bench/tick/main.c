/* SPDX-License-Identifier: Apache-2.0 */
/*
 * bench/tick: what one control tick costs on the Unitree G1 manifest (145
 * commands, 97 states) with the PD controller of examples/controllers/g1_pd.c
 * and on the UR5 (6 commands, 12 states) with examples/controllers/pd_hold.c,
 *   - run by wasm3 inside the full runtime tick (loopback port), and
 *   - compiled natively against the same channel API (the same source, its
 *     imports bound to roz's ABI functions directly),
 * and the runtime's own overhead (tick minus process() minus the port's read
 * and write, timed apart: the loopback simulates the robot and moves CRC'd
 * frames both ways inside the tick), and the cost of the
 * per-tick budget: the G1 PD and a loop-heavy controller (bench/tick/
 * loop_heavy.c) under wasm3 with their fuel charges and the default budget,
 * against the same modules compiled without charges (a private loader for
 * benchmarks); and the
 * frame CRC every port computes (roz/hal/crc32.h) on G1-sized images,
 * against the bit-by-bit definition. Prints
 * medians, p99 and ratios side by side. A benchmark, not a test: it never
 * fails on a time.
 *
 *   roz_bench_tick [TICKS] [CONTROLLER.wasm] [--json FILE]
 *
 * CONTROLLER.wasm replaces the G1's controller; --json appends every figure
 * to FILE (bench/common/bench_json.h) for bench/report.py.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "roz/hal/clock.h"
#include "roz/hal/crc32.h"
#include "crc32_reference.h"
#include "roz/port/loopback.h"
#include "roz/ports.h"
#include "roz/runtime.h"
#include "bench_json.h"
#include "bench_native_abi.h"
#include "controller_bench.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"

/* ---- the native controllers (their imports: bench_native_abi.h) ---------- */

void roz_native_process(long long tick);
void roz_native_process_ur5(long long tick); /* pd_hold.c, renamed by the build */
void roz_native_process_g1_bulk(long long tick); /* g1_pd_bulk.c, likewise */

/* ---- helpers -------------------------------------------------------------- */

static volatile uint32_t crc_sink; /* keeps the timed CRCs */

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

typedef struct {
    double p50, p99, max;
} stats_t;

static stats_t stats(uint64_t *v, size_t n)
{
    qsort(v, n, sizeof v[0], cmp_u64);
    stats_t s = { v[n / 2] / 1000.0, v[(n * 99) / 100] / 1000.0, v[n - 1] / 1000.0 };
    return s;
}

static uint8_t *read_file(const char *path, size_t *len)
{
    return bench_read_file(path, ROZ_CFG_WASM_MAX_MODULE_BYTES, len);
}

static roz_runtime_t rt;
static roz_loopback_t lb;

/* The port's read() and write() in a tick, as the runtime's own monitor
 * timed them (its READ and WRITE sums before and after the tick): the
 * loopback simulates the robot and moves CRC'd frames both ways, which a
 * hardware port does on its own threads, not in the tick. A shim timing
 * them here would add its own four clock reads to the tick and count them
 * as the runtime's overhead. */
static uint64_t port_sum_ns(void)
{
    const roz_monitor_t *mon = roz_runtime_monitor(&rt);
    roz_monitor_stat_t r, w;
    if (roz_monitor_snapshot(mon, ROZ_MON_READ, &r) != ROZ_OK ||
        roz_monitor_snapshot(mon, ROZ_MON_WRITE, &w) != ROZ_OK)
        return 0;
    return r.sum_ns + w.sum_ns;
}

/* Loads `wasm` into `ctl`: with its fuel charges, a budget and a 1 s
 * deadline (read every ROZ_CFG_DEADLINE_CHECK_UNITS units, as usual), or
 * compiled without charges and with no budget at all. */
static int meter_load(roz_controller_t *ctl, roz_abi_t *abi, double *target, const double *state,
                      const roz_manifest_t *m, const uint8_t *wasm, size_t len, int charged)
{
    /* a second's fuel: the loop-heavy controller needs more than a tick's
     * default, and the cost of a charge does not depend on the budget */
    roz_budget_t b = { (uint64_t)ROZ_CFG_FUEL_PER_SECOND, 1000000000, roz_clock_monotonic_ns,
                       NULL };
    int rc;

    roz_controller_init(ctl);
    roz_abi_init(abi, m, target, NULL);
    roz_abi_begin_tick(abi, 0, state);
    if (!charged)
        return roz__controller_load_unmetered(ctl, wasm, len, abi);
    rc = roz_controller_load(ctl, wasm, len, abi);
    return rc == ROZ_OK ? roz_controller_set_budget(ctl, &b) : rc;
}

/* process() of the same module charged and uncharged, `calls` times each,
 * alternating rounds of 100 so drift on the machine hits both alike. */
static int meter_pair(const roz_manifest_t *m, const uint8_t *wasm, size_t len, size_t calls,
                      uint64_t *charged_ns, uint64_t *bare_ns, uint64_t *units)
{
    static roz_controller_t ctl[2];
    static roz_abi_t abi[2];
    static double target[2][ROZ_CFG_MAX_COMMANDS], state[ROZ_CFG_MAX_STATES];
    uint64_t *out[2] = { bare_ns, charged_ns };

    for (uint16_t i = 0; i < m->n_states; i++)
        state[i] = m->states[i].default_value;
    for (int k = 0; k < 2; k++) {
        if (meter_load(&ctl[k], &abi[k], target[k], state, m, wasm, len, k) != ROZ_OK)
            return -1;
        for (int i = 0; i < 1000; i++) {
            if (roz_controller_process(&ctl[k], i) != ROZ_OK)
                return -1;
        }
    }
    for (size_t r = 0; r < calls; r += 100) {
        for (int k = 0; k < 2; k++) {
            for (size_t i = r; i < r + 100 && i < calls; i++) {
                roz_abi_begin_tick(&abi[k], (int64_t)i, state);
                uint64_t t0 = roz_clock_monotonic_ns(NULL);
                int rc = roz_controller_process(&ctl[k], (int64_t)i);
                out[k][i] = roz_clock_monotonic_ns(NULL) - t0;
                if (rc != ROZ_OK)
                    return -1;
            }
        }
    }
    *units = roz_controller_fuel_used(&ctl[1]);
    roz_controller_unload(&ctl[0]);
    roz_controller_unload(&ctl[1]);
    return 0;
}

/* The runtime's tick on robot `m` with `wasm` on the (timed) loopback, and
 * the same controller compiled natively on the same snapshots; prints the
 * figures and adds them to `j` as "<robot_id><tag>: ...". Returns the number of
 * targets where wasm3 and native differ, or -1 when the run failed. */
static long tick_bench(const roz_manifest_t *m, const char *tag, const uint8_t *wasm, size_t len,
                       const char *path, void (*native)(long long), size_t ticks,
                       const bench_json_t *j)
{
    roz_runtime_config_t cfg;
    char err[128], name[96];

    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = roz_loopback_port(&lb, NULL, NULL);
    if (roz_port_open(&cfg.port, m, NULL, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "bench: %s\n", err);
        return -1;
    }
    cfg.clock = roz_clock_monotonic_ns;
    cfg.monitor_jitter = 0;
    cfg.budget_ns = 1000000000; /* measure, don't fault */
    if (roz_runtime_init(&rt, &cfg) != ROZ_OK || roz_runtime_load(&rt, wasm, len, NULL) != ROZ_OK ||
        roz_runtime_start(&rt) != ROZ_OK) {
        fprintf(stderr, "bench: runtime: %s\n", roz_runtime_error(&rt));
        return -1;
    }

    uint64_t *tick_ns = calloc(ticks, sizeof(uint64_t));
    uint64_t *wasm_ns = calloc(ticks, sizeof(uint64_t));
    uint64_t *native_ns = calloc(ticks, sizeof(uint64_t));
    uint64_t *overhead_ns = calloc(ticks, sizeof(uint64_t));
    uint64_t *port_tick_ns = calloc(ticks, sizeof(uint64_t));
    static double native_target[ROZ_CFG_MAX_COMMANDS];
    if (!tick_ns || !wasm_ns || !native_ns || !overhead_ns || !port_tick_ns)
        return -1;
    roz_abi_init(&native_abi, m, native_target, NULL);

    /* warm-up */
    for (int i = 0; i < 1000; i++) {
        if (roz_runtime_tick(&rt) != ROZ_OK)
            break; /* the latch shows in the figures' check below */
    }
    long mismatches = 0;
    for (size_t i = 0; i < ticks; i++) {
        uint64_t p0 = port_sum_ns();
        uint64_t t0 = roz_clock_monotonic_ns(NULL);
        int trc = roz_runtime_tick(&rt);
        uint64_t t1 = roz_clock_monotonic_ns(NULL);
        uint64_t port_ns = port_sum_ns() - p0;
        roz_runtime_stats_t st;
        if (trc != ROZ_OK || roz_runtime_stats(&rt, &st) != ROZ_OK) {
            fprintf(stderr, "roz_bench_tick: a fault latched: %s\n", roz_runtime_fault_message(&rt));
            return -1;
        }
        tick_ns[i] = t1 - t0;
        wasm_ns[i] = st.last_process_ns;
        port_tick_ns[i] = port_ns;
        overhead_ns[i] = tick_ns[i] > wasm_ns[i] + port_ns ? tick_ns[i] - wasm_ns[i] - port_ns : 0;

        /* the same controller, native, on the same snapshot */
        roz_abi_begin_tick(&native_abi, (int64_t)i, roz_runtime_last_state(&rt));
        t0 = roz_clock_monotonic_ns(NULL);
        native((long long)i);
        t1 = roz_clock_monotonic_ns(NULL);
        native_ns[i] = t1 - t0;
        const double *wt = roz_runtime_last_targets(&rt);
        for (uint16_t c = 0; c < m->n_commands; c++)
            mismatches += wt[c] != native_target[c];
    }
    stats_t st = stats(tick_ns, ticks), sw = stats(wasm_ns, ticks), sn = stats(native_ns, ticks),
            so = stats(overhead_ns, ticks), sp = stats(port_tick_ns, ticks);
    double period_us = 1e6 / m->control_rate_hz;

    printf("bench/tick: %s%s, %u commands, %u states, %zu ticks, controller %s\n", m->robot_id,
           tag,
           (unsigned)m->n_commands, (unsigned)m->n_states, ticks, path);
    printf("%-34s %10s %10s %10s\n", "", "p50 [us]", "p99 [us]", "max [us]");
    printf("%-34s %10.2f %10.2f %10.2f\n", "process(), wasm3", sw.p50, sw.p99, sw.max);
    printf("%-34s %10.2f %10.2f %10.2f\n", "process(), native", sn.p50, sn.p99, sn.max);
    printf("%-34s %10.2f %10.2f %10.2f\n", "runtime (tick - process - port)", so.p50, so.p99,
           so.max);
    printf("%-34s %10.2f %10.2f %10.2f\n", "port read + write (loopback sim)", sp.p50, sp.p99,
           sp.max);
    printf("%-34s %10.2f %10.2f %10.2f\n", "whole tick, wasm3", st.p50, st.p99, st.max);
    printf("ratios: wasm3/native process() p50 %.1fx, p99 %.1fx; whole tick p50 is %.2f%% of the "
           "%.0f us period\n",
           sn.p50 > 0 ? sw.p50 / sn.p50 : 0.0, sn.p99 > 0 ? sw.p99 / sn.p99 : 0.0,
           100.0 * st.p50 / period_us, period_us);
    printf("outputs: wasm3 and native targets %s (%ld differing values)\n\n",
           mismatches == 0 ? "identical" : "DIFFER", mismatches);
    static const char *const what[5] = { "process(), wasm3", "process(), native",
                                         "runtime (tick - process - port)",
                                         "port read + write (loopback sim)", "whole tick, wasm3" };
    const stats_t *all[5] = { &sw, &sn, &so, &sp, &st };
    for (int k = 0; k < 5; k++) {
        snprintf(name, sizeof name, "%s%s: %s", m->robot_id, tag, what[k]);
        bench_json_timing(j, name, (bench_stats_t){ all[k]->p50, all[k]->p99, all[k]->max });
    }
    snprintf(name, sizeof name, "%s%s: wasm3 and native targets differing", m->robot_id, tag);
    bench_json_value(j, name, (double)mismatches, "values");
    roz_runtime_deinit(&rt);
    free(tick_ns);
    free(wasm_ns);
    free(native_ns);
    free(overhead_ns);
    free(port_tick_ns);
    return mismatches;
}

/* The whole tick on every port of this build that runs here without a peer
 * (the registry, roz/ports.h: ROZ_PORT_CAP_SIMULATOR), the UR5 holding
 * with `wasm`: what a port's read() and write() add to the same runtime
 * and controller. Adds "ports: <id>: whole tick" to `j`. Returns the
 * number of ports that failed to run. */
static int ports_bench(const uint8_t *wasm, size_t len, size_t ticks, const bench_json_t *j)
{
    const roz_manifest_t *m = &roz_manifest_ur5;
    uint64_t *tick_ns = calloc(ticks, sizeof(uint64_t));
    int failed = 0;
    if (tick_ns == NULL)
        return 1;
    printf("\nthe whole tick on every simulator port of this build (UR5, %s):\n",
           "pd_hold under wasm3");
    printf("%-34s %10s %10s %10s %10s\n", "port", "p50 [us]", "p99 [us]", "max [us]", "faults");
    for (size_t i = 0; i < ROZ_PORTS_COUNT; i++) {
        const roz_port_entry_t *e = &roz_ports[i];
        if ((e->ops->caps & ROZ_PORT_CAP_SIMULATOR) == 0)
            continue;
        size_t size = (e->size + e->align - 1) / e->align * e->align;
        void *self = aligned_alloc(e->align, size);
        char err[256] = "";
        if (self == NULL) {
            failed++;
            continue;
        }
        memset(self, 0, size);
        roz_runtime_config_t cfg;
        roz_runtime_config_default(&cfg);
        cfg.manifest = m;
        cfg.port = e->construct(self, NULL, NULL);
        cfg.clock = roz_clock_monotonic_ns;
        cfg.monitor_jitter = 0;
        cfg.budget_ns = 1000000000; /* measure, don't fault */
        if (roz_port_open(&cfg.port, m, NULL, err, sizeof err) != ROZ_OK) {
            printf("%-34s cannot open: %s\n", e->id, err);
            free(self);
            failed++;
            continue;
        }
        if (roz_runtime_init(&rt, &cfg) != ROZ_OK ||
            roz_runtime_load(&rt, wasm, len, NULL) != ROZ_OK ||
            roz_port_activate(&cfg.port) != ROZ_OK || roz_runtime_start(&rt) != ROZ_OK) {
            printf("%-34s runtime: %s\n", e->id, roz_runtime_error(&rt));
            roz_port_close(&cfg.port);
            free(self);
            failed++;
            continue;
        }
        for (size_t t = 0; t < ticks; t++) {
            uint64_t t0 = roz_clock_monotonic_ns(NULL);
            int rc = roz_runtime_tick(&rt); /* a latched fault is counted below */
            (void)rc;
            tick_ns[t] = roz_clock_monotonic_ns(NULL) - t0;
        }
        stats_t s = stats(tick_ns, ticks);
        unsigned faults = roz_runtime_faults(&rt);
        printf("%-34s %10.2f %10.2f %10.2f %10s\n", e->id, s.p50, s.p99, s.max,
               faults == 0 ? "none" : "LATCHED");
        char jn[96];
        snprintf(jn, sizeof jn, "ports: %s: whole tick, UR5 pd_hold", e->id);
        bench_json_timing(j, jn, (bench_stats_t){ s.p50, s.p99, s.max });
        roz_runtime_deinit(&rt);
        roz_port_close(&cfg.port);
        free(self);
        failed += faults != 0;
    }
    free(tick_ns);
    return failed;
}

int main(int argc, char **argv)
{
    bench_json_t json;
    argc = bench_json_args(&json, "tick", argc, argv);
    if (argc < 0)
        return 2;
    size_t ticks = argc > 1 ? strtoul(argv[1], NULL, 10) : 20000;
    const char *path = argc > 2 ? argv[2] : ROZ_BENCH_CONTROLLER;
    const roz_manifest_t *m = &roz_manifest_unitree_g1;
    size_t len, ur5_len;

    if (ticks < 100)
        ticks = 100;
    uint8_t *wasm = read_file(path, &len);
    uint8_t *ur5_wasm = read_file(ROZ_BENCH_UR5_CONTROLLER, &ur5_len);
    if (wasm == NULL || ur5_wasm == NULL) {
        fprintf(stderr, "bench: cannot read %s\n", wasm == NULL ? path : ROZ_BENCH_UR5_CONTROLLER);
        return 2;
    }
    size_t bulk_len;
    uint8_t *bulk_wasm = read_file(ROZ_BENCH_BULK_CONTROLLER, &bulk_len);
    if (bulk_wasm == NULL) {
        fprintf(stderr, "bench: cannot read %s\n", ROZ_BENCH_BULK_CONTROLLER);
        return 2;
    }
    long mismatches = tick_bench(m, "", wasm, len, path, roz_native_process, ticks, &json);
    long bulk_mismatches = tick_bench(m, " (bulk)", bulk_wasm, bulk_len, ROZ_BENCH_BULK_CONTROLLER,
                                      roz_native_process_g1_bulk, ticks, &json);
    long ur5_mismatches = tick_bench(&roz_manifest_ur5, "", ur5_wasm, ur5_len,
                                     ROZ_BENCH_UR5_CONTROLLER, roz_native_process_ur5, ticks, &json);
    int ports_failed = ports_bench(ur5_wasm, ur5_len, ticks, &json);
    free(ur5_wasm);
    free(bulk_wasm);
    if (mismatches < 0 || ur5_mismatches < 0 || bulk_mismatches < 0)
        return 2;
    mismatches += ur5_mismatches + bulk_mismatches;

    /* metering: the same controllers under wasm3 with their fuel charges
     * (the default budget) and compiled without them (the private
     * benchmark loader; no budget at all), alternating rounds so drift on
     * the machine hits both alike */
    printf("\nbudget metering: fuel charged per run of instructions (a budget, and the "
           "deadline read every %d units, set to 1 s so a preempted call does not fault the "
           "run) vs the same module compiled without charges:\n",
           ROZ_CFG_DEADLINE_CHECK_UNITS);
    printf("%-34s %10s %10s %10s %10s\n", "", "units/call", "p50 [us]", "p99 [us]", "ratio p50");
    static const char *const meter_names[2] = { "G1 PD (host calls)", "loop-heavy (29x29 loops)" };
    const char *meter_paths[2] = { path, ROZ_BENCH_LOOP_HEAVY };
    size_t calls = ticks;
    uint64_t *metered = calloc(calls, sizeof(uint64_t)), *bare = calloc(calls, sizeof(uint64_t));
    if (!metered || !bare)
        return 2;
    for (int k = 0; k < 2; k++) {
        size_t mlen;
        uint8_t *mw = k == 0 ? wasm : read_file(meter_paths[k], &mlen);
        if (mw == NULL) {
            fprintf(stderr, "bench: cannot read %s\n", meter_paths[k]);
            return 2;
        }
        if (k == 0)
            mlen = len;
        uint64_t units = 0;
        if (meter_pair(m, mw, mlen, calls, metered, bare, &units) != 0) {
            fprintf(stderr, "bench: %s: metering runs failed\n", meter_paths[k]);
            return 2;
        }
        stats_t sm = stats(metered, calls), sb = stats(bare, calls);
        printf("%-34s %10llu %10.2f %10.2f\n", meter_names[k], (unsigned long long)units, sm.p50,
               sm.p99);
        printf("%-34s %10s %10.2f %10.2f %9.3fx  (aim: <= 1.10x)\n", "  the same, no charges", "-",
               sb.p50, sb.p99, sb.p50 > 0 ? sm.p50 / sb.p50 : 0.0);
        char jn[96];
        snprintf(jn, sizeof jn, "metering: %s, charged", meter_names[k]);
        bench_json_timing(&json, jn, (bench_stats_t){ sm.p50, sm.p99, sm.max });
        snprintf(jn, sizeof jn, "metering: %s, no charges", meter_names[k]);
        bench_json_timing(&json, jn, (bench_stats_t){ sb.p50, sb.p99, sb.max });
        snprintf(jn, sizeof jn, "metering: %s, units per call", meter_names[k]);
        bench_json_value(&json, jn, (double)units, "units");
        if (k != 0)
            free(mw);
    }
    free(metered);
    free(bare);

    /* the frame CRC: a G1 LowState_ (522 words) and LowCmd_ (250 words) */
    static uint32_t image[522];
    static const size_t words[2] = { 522, 250 };
    static const char *const names[2] = { "LowState_ (522 words)", "LowCmd_ (250 words)" };
    enum { REPS = 2000 };
    uint64_t *ct = calloc(REPS, sizeof(uint64_t)), *cb = calloc(REPS, sizeof(uint64_t));
    if (!ct || !cb)
        return 2;
    for (size_t i = 0; i < 522; i++)
        image[i] = (uint32_t)(i * 2654435761u);
    printf("\nframe CRC-32 (roz_crc32_words, sliced by four, vs the bit-by-bit definition):\n");
    printf("%-34s %10s %10s %10s\n", "", "table [us]", "bits [us]", "ratio");
    for (int k = 0; k < 2; k++) {
        for (size_t r = 0; r < REPS; r++) {
            uint64_t t0 = roz_clock_monotonic_ns(NULL);
            crc_sink ^= roz_crc32_words(image, words[k]);
            uint64_t t1 = roz_clock_monotonic_ns(NULL);
            crc_sink ^= roz_crc32_reference(image, words[k]);
            uint64_t t2 = roz_clock_monotonic_ns(NULL);
            ct[r] = t1 - t0;
            cb[r] = t2 - t1;
        }
        stats_t sct = stats(ct, REPS), scb = stats(cb, REPS);
        char jn[96];
        snprintf(jn, sizeof jn, "CRC-32 %s, table", names[k]);
        bench_json_timing(&json, jn, (bench_stats_t){ sct.p50, sct.p99, sct.max });
        snprintf(jn, sizeof jn, "CRC-32 %s, bit by bit", names[k]);
        bench_json_timing(&json, jn, (bench_stats_t){ scb.p50, scb.p99, scb.max });
        printf("%-34s %10.2f %10.2f %9.1fx  (p50)\n", names[k], sct.p50, scb.p50,
               sct.p50 > 0 ? scb.p50 / sct.p50 : 0.0);
    }
    free(ct);
    free(cb);
    free(wasm);
    bench_json_close(&json);
    return mismatches == 0 && ports_failed == 0 ? 0 : 1;
}
