/* SPDX-License-Identifier: Apache-2.0 */
/*
 * bench/periodic: the periodic runner (roz/runner.h) at 1 kHz running
 * the runtime's tick (the G1 PD on the loopback simulator), against a bare
 * clock_nanosleep(TIMER_ABSTIME) loop that does nothing else, in the same
 * run: wake-up latency (woken minus the deadline slept for) p50/p99/max,
 * and deadlines missed by more than a period. The two alternate in rounds
 * of 5 s so that whatever else the machine does hits both alike. Both run
 * at normal scheduling (no SCHED_FIFO, no mlockall): the figures are what
 * a process gets on this machine without real-time rights.
 *
 *   roz_bench_periodic [SECONDS] [--json FILE]
 *
 * SECONDS per side, default 60 (ROZ_BENCH_PERIODIC_SECONDS in make bench).
 * A benchmark, not a test: it prints, it never fails on a time.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "roz/hal/clock.h"
#include "roz/runner.h"
#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "bench_json.h"
#include "unitree_g1_manifest.h"

#define PERIOD_NS 1000000u /* 1 kHz */
#define ROUND_TICKS 5000u  /* 5 s */

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_runner_t runner;
static uint64_t *runner_lat, *bare_lat;
static size_t runner_n, bare_n, capacity;
static int tick_failed;

static int runner_tick(void *ctx)
{
    (void)ctx;
    uint64_t now = roz_clock_monotonic_ns(NULL);
    if (runner_n < capacity)
        runner_lat[runner_n++] = now > runner.deadline ? now - runner.deadline : 0;
    if (roz_runtime_tick(&rt) != ROZ_OK) {
        tick_failed = 1;
        return 1;
    }
    return 0;
}

/* The bare loop: the runner's schedule (absolute deadlines, skip ahead
 * when more than a period behind), nothing else. */
static uint64_t bare_round(size_t ticks)
{
    uint64_t next = roz_clock_monotonic_ns(NULL), missed = 0;
    for (size_t i = 0; i < ticks; i++) {
        struct timespec ts = { (time_t)(next / 1000000000u), (long)(next % 1000000000u) };
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR)
            ;
        uint64_t woke = roz_clock_monotonic_ns(NULL);
        if (bare_n < capacity)
            bare_lat[bare_n++] = woke > next ? woke - next : 0;
        next += PERIOD_NS;
        uint64_t done = roz_clock_monotonic_ns(NULL);
        if (done > next + PERIOD_NS) {
            missed++;
            next = done + PERIOD_NS;
        }
    }
    return missed;
}

int main(int argc, char **argv)
{
    bench_json_t json;
    argc = bench_json_args(&json, "periodic", argc, argv);
    if (argc < 0)
        return 2;
    unsigned long seconds = argc > 1 ? strtoul(argv[1], NULL, 10) : 60;
    const roz_manifest_t *m = &roz_manifest_unitree_g1;
    roz_runtime_config_t cfg;
    char err[128];
    FILE *f = fopen(ROZ_BENCH_CONTROLLER, "rb");
    static uint8_t wasm[ROZ_CFG_WASM_MAX_MODULE_BYTES];
    size_t len;

    if (seconds < 1)
        seconds = 1;
    if (f == NULL) {
        fprintf(stderr, "roz_bench_periodic: cannot read %s\n", ROZ_BENCH_CONTROLLER);
        return 2;
    }
    len = fread(wasm, 1, sizeof wasm, f);
    fclose(f);
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = roz_loopback_port(&lb, NULL, NULL);
    if (roz_port_open(&cfg.port, m, NULL, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "roz_bench_periodic: %s\n", err);
        return 2;
    }
    cfg.clock = roz_clock_monotonic_ns;
    cfg.monitor_jitter = 0;
    cfg.budget_ns = 1000000000; /* measure, don't fault */
    if (roz_runtime_init(&rt, &cfg) != ROZ_OK || roz_runtime_load(&rt, wasm, len, NULL) != ROZ_OK ||
        roz_runtime_start(&rt) != ROZ_OK) {
        fprintf(stderr, "roz_bench_periodic: runtime: %s\n", roz_runtime_error(&rt));
        return 2;
    }

    size_t ticks = (size_t)seconds * 1000u;
    capacity = ticks;
    runner_lat = calloc(ticks, sizeof(uint64_t));
    bare_lat = calloc(ticks, sizeof(uint64_t));
    if (runner_lat == NULL || bare_lat == NULL)
        return 2;
    uint64_t runner_missed = 0, bare_missed = 0;
    for (size_t done = 0; done < ticks; done += ROUND_TICKS) {
        size_t n = ticks - done < ROUND_TICKS ? ticks - done : ROUND_TICKS;
        bare_missed += bare_round(n);
        roz_runner_config_t rc = { .period_ns = PERIOD_NS, .max_ticks = n };
        if (roz_runner_start(&runner, &rc, runner_tick, NULL) != ROZ_OK) {
            fprintf(stderr, "roz_bench_periodic: cannot start the runner\n");
            return 2;
        }
        roz_runner_join(&runner);
        runner_missed += runner.missed;
        if (tick_failed) {
            fprintf(stderr, "roz_bench_periodic: a fault latched: %s\n",
                    roz_runtime_fault_message(&rt));
            return 1;
        }
    }
    size_t rn = runner_n, bn = bare_n;
    bench_stats_t sr = bench_stats(runner_lat, rn), sb = bench_stats(bare_lat, bn);
    printf("bench/periodic: 1 kHz for %lu s each, alternating rounds of %u ticks; normal "
           "scheduling\n",
           seconds, ROUND_TICKS);
    printf("%-40s %10s %10s %10s %8s\n", "wake-up latency", "p50 [us]", "p99 [us]", "max [us]",
           "missed");
    printf("%-40s %10.1f %10.1f %10.1f %8llu\n", "roz runner + G1 tick (loopback)", sr.p50, sr.p99,
           sr.max, (unsigned long long)runner_missed);
    printf("%-40s %10.1f %10.1f %10.1f %8llu\n", "bare clock_nanosleep(TIMER_ABSTIME)", sb.p50,
           sb.p99, sb.max, (unsigned long long)bare_missed);
    bench_json_value(&json, "seconds per side", (double)seconds, "s");
    bench_json_timing(&json, "wake-up latency, roz runner + G1 tick", sr);
    bench_json_timing(&json, "wake-up latency, bare clock_nanosleep loop", sb);
    bench_json_value(&json, "missed deadlines, roz runner", (double)runner_missed, "count");
    bench_json_value(&json, "missed deadlines, bare loop", (double)bare_missed, "count");
    bench_json_value(&json, "ticks, roz runner", (double)rn, "count");
    bench_json_value(&json, "ticks, bare loop", (double)bn, "count");
    bench_json_close(&json);
    roz_runtime_deinit(&rt);
    free(runner_lat);
    free(bare_lat);
    return 0;
}
