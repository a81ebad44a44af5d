/* SPDX-License-Identifier: Apache-2.0 */
/*
 * bench/alloc: heap calls in the tick path over many ticks (10^6 by
 * default): the runtime's tick with the G1 PD and with the UR5's PD hold
 * on the loopback simulator, malloc/calloc/realloc/free wrapped by the
 * linker and counted only while ticks run (test/support_heap.h) (a load, counted too, shows the
 * counter is live). The figure must be 0; test_alloc proves it over 10^5
 * ticks in the test suite, this is the long count for BENCHMARKS.md.
 *
 *   roz_bench_alloc [TICKS] [--json FILE]
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>

#include "roz/hal/clock.h"
#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "bench_json.h"
#include "support_heap.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"

static roz_runtime_t rt;
static roz_loopback_t lb;
static uint8_t wasm[ROZ_CFG_WASM_MAX_MODULE_BYTES];

/* Heap calls while loading (must be > 0: the counter works) and over
 * `ticks` ticks (must be 0); -1 when the run failed. */
static int run(const roz_manifest_t *m, const char *path, unsigned long ticks,
               unsigned long long *load_calls, unsigned long long *tick_calls)
{
    roz_runtime_config_t cfg;
    char err[128];
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        fprintf(stderr, "roz_bench_alloc: cannot read %s\n", path);
        return -1;
    }
    size_t len = fread(wasm, 1, sizeof wasm, f);
    fclose(f);
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = roz_loopback_port(&lb, NULL, NULL);
    if (roz_port_open(&cfg.port, m, NULL, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "roz_bench_alloc: %s\n", err);
        return -1;
    }
    cfg.clock = roz_clock_monotonic_ns;
    cfg.monitor_jitter = 0;
    cfg.budget_ns = ROZ_BUDGET_OFF; /* count heap calls; no deadline to miss when preempted */
    roz_heap_count_start();
    int rc = roz_runtime_init(&rt, &cfg);
    if (rc == ROZ_OK)
        rc = roz_runtime_load(&rt, wasm, len, NULL);
    roz_heap_count_stop();
    *load_calls = roz_heap_allocations() + roz_heap_frees();
    if (rc != ROZ_OK || roz_runtime_start(&rt) != ROZ_OK || roz_runtime_tick(&rt) != ROZ_OK) {
        fprintf(stderr, "roz_bench_alloc: runtime: %s\n", roz_runtime_error(&rt));
        return -1;
    }
    roz_heap_count_start();
    for (unsigned long t = 0; t < ticks; t++) {
        if (roz_runtime_tick(&rt) != ROZ_OK) {
            roz_heap_count_stop();
            fprintf(stderr, "roz_bench_alloc: a fault latched: %s\n",
                    roz_runtime_fault_message(&rt));
            return -1;
        }
    }
    roz_heap_count_stop();
    *tick_calls = roz_heap_allocations() + roz_heap_frees();
    roz_runtime_deinit(&rt);
    return 0;
}

int main(int argc, char **argv)
{
    bench_json_t json;
    argc = bench_json_args(&json, "alloc", argc, argv);
    if (argc < 0)
        return 2;
    unsigned long ticks = argc > 1 ? strtoul(argv[1], NULL, 10) : 1000000ul;
    static const char *const names[2] = { "unitree_g1, g1_pd", "ur5, pd_hold" };
    const roz_manifest_t *ms[2] = { &roz_manifest_unitree_g1, &roz_manifest_ur5 };
    const char *paths[2] = { ROZ_BENCH_CONTROLLER, ROZ_BENCH_UR5_CONTROLLER };
    char name[96];

    printf("bench/alloc: heap calls (malloc, calloc, realloc, free) in the tick path\n");
    for (int k = 0; k < 2; k++) {
        unsigned long long load_calls, tick_calls;
        if (run(ms[k], paths[k], ticks, &load_calls, &tick_calls) != 0)
            return 2;
        printf("%-20s %lu ticks: %llu heap calls (the load made %llu: the counter is live)\n",
               names[k], ticks, tick_calls, load_calls);
        snprintf(name, sizeof name, "%s: heap calls in %lu ticks", names[k], ticks);
        bench_json_value(&json, name, (double)tick_calls, "count");
        snprintf(name, sizeof name, "%s: heap calls of the load", names[k]);
        bench_json_value(&json, name, (double)load_calls, "count");
    }
    bench_json_close(&json);
    return 0;
}
