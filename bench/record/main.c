/* SPDX-License-Identifier: Apache-2.0 */
/*
 * bench/record: what the flight recorder costs. For the UR5 (sine) and the
 * Unitree G1 (PD), on the loopback: the whole tick with the recorder on and
 * off, in the same run (two runtimes ticked alternately, so both see the
 * same machine load); the bytes a tick takes in the ring and in the MCAP
 * file; and how fast a drain empties the ring, into a sink that only counts
 * and into the MCAP file (CDR, chunking, stdio), uncompressed and with zstd
 * (the drain compresses, off the tick). A benchmark, not a test:
 * it never fails on a time.
 *
 *   roz_bench_record [TICKS] [DIR]   (the recordings are written in DIR)
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_json.h"
#include "roz/hal/clock.h"
#include "roz/module.h"
#include "roz/port/loopback.h"
#include "roz/record_file.h"
#include "roz/runtime.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"

#define RING_TICKS 256u
#define DRAIN_EVERY 64u

static roz_runtime_t rt_off, rt_on;
static roz_loopback_t lb_off, lb_on;
static roz_recorder_t rec;
static roz_record_file_t file;
static bench_json_t json;
static uint8_t wasm[ROZ_CFG_WASM_MAX_MODULE_BYTES];

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static double pct(uint64_t *v, size_t n, double p)
{
    qsort(v, n, sizeof v[0], cmp_u64);
    return (double)v[(size_t)(p / 100.0 * (double)(n - 1))] / 1000.0;
}

static int setup(roz_runtime_t *rt, roz_loopback_t *lb, const roz_manifest_t *m,
                 roz_recorder_t *r, size_t len)
{
    char err[256];
    roz_runtime_config_t cfg;
    roz_port_t port = roz_loopback_port(lb, NULL, NULL);
    if (roz_port_open(&port, m, NULL, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "bench: %s\n", err);
        return -1;
    }
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = port;
    cfg.clock = roz_clock_monotonic_ns;
    cfg.budget_ns = ROZ_BUDGET_OFF;
    cfg.monitor_jitter = 0;
    cfg.recorder = r;
    if (roz_runtime_init(rt, &cfg) != ROZ_OK || roz_runtime_load(rt, wasm, len, NULL) != ROZ_OK ||
        roz_runtime_start(rt) != ROZ_OK) {
        fprintf(stderr, "bench: runtime: %s\n", roz_runtime_error(rt));
        return -1;
    }
    return 0;
}

static int count_sink(void *ctx, const roz_record_t *r)
{
    (void)r;
    (*(uint64_t *)ctx)++;
    return 0;
}

static int bench(const roz_manifest_t *m, const char *ctl, size_t ticks, const char *dir,
                 int compression)
{
    char path[512], err[256], label[96];
    size_t len;
    uint64_t *t_off = malloc(ticks * sizeof *t_off), *t_on = malloc(ticks * sizeof *t_on);
    size_t bytes = RING_TICKS * roz_recorder_slot_bytes(m);
    void *ring = malloc(bytes);

    if (t_off == NULL || t_on == NULL || ring == NULL)
        return -1;
    snprintf(path, sizeof path, "%s/%s.wasm", ROZ_BENCH_CONTROLLERS, ctl);
    if (roz_module_read_file(path, wasm, sizeof wasm, &len, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "bench: %s\n", err);
        return -1;
    }
    if (roz_recorder_init(&rec, m, ring, bytes, 1) != ROZ_OK ||
        setup(&rt_off, &lb_off, m, NULL, len) != 0 || setup(&rt_on, &lb_on, m, &rec, len) != 0)
        return -1;
    snprintf(label, sizeof label, "%s%s", m->robot_id,
             compression == ROZ_MCAP_COMPRESS_ZSTD ? " (zstd)" : "");
    snprintf(path, sizeof path, "%s/bench_record_%s%s.mcap", dir, m->robot_id,
             compression == ROZ_MCAP_COMPRESS_ZSTD ? "_zstd" : "");
    roz_record_file_options_t fo = { ctl, 0, compression };
    if (roz_record_file_open(&file, path, &rt_on, &rec, &fo, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "bench: %s\n", err);
        return -1;
    }
    uint64_t drain_ns = 0, drained = 0;
    for (size_t i = 0; i < ticks; i++) {
        uint64_t a = roz_clock_monotonic_ns(NULL);
        int rc1 = roz_runtime_tick(&rt_off);
        uint64_t b = roz_clock_monotonic_ns(NULL);
        int rc2 = roz_runtime_tick(&rt_on);
        uint64_t c = roz_clock_monotonic_ns(NULL);
        if (rc1 != ROZ_OK || rc2 != ROZ_OK) {
            fprintf(stderr, "bench: a fault latched\n");
            return -1;
        }
        t_off[i] = b - a;
        t_on[i] = c - b;
        if (i % DRAIN_EVERY == DRAIN_EVERY - 1u) {
            uint64_t d0 = roz_clock_monotonic_ns(NULL);
            int n = roz_record_file_drain(&file);
            drain_ns += roz_clock_monotonic_ns(NULL) - d0;
            if (n < 0) {
                fprintf(stderr, "bench: %s\n", roz_record_file_error(&file));
                return -1;
            }
            drained += (uint64_t)n;
        }
    }
    if (roz_record_file_close(&file, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "bench: %s\n", err);
        return -1;
    }
    FILE *f = fopen(path, "rb");
    long size = 0;
    if (f != NULL && fseek(f, 0, SEEK_END) == 0)
        size = ftell(f);
    if (f != NULL)
        fclose(f);
    /* the drain alone: the ring filled by ticks, emptied into a counter */
    uint64_t sink_ns = 0, counted = 0;
    for (size_t i = 0; i < ticks; i++) {
        if (roz_runtime_tick(&rt_on) != ROZ_OK)
            return -1;
        if (i % DRAIN_EVERY == DRAIN_EVERY - 1u) {
            uint64_t d0 = roz_clock_monotonic_ns(NULL);
            (void)roz_recorder_drain(&rec, count_sink, &counted, 0);
            sink_ns += roz_clock_monotonic_ns(NULL) - d0;
        }
    }
    /* the machine-readable figures first: bench_stats() sorts its copy */
    {
        char name[128];
        uint64_t *copy = malloc(ticks * sizeof copy[0]);
        if (copy == NULL)
            return -1;
        memcpy(copy, t_off, ticks * sizeof copy[0]);
        snprintf(name, sizeof name, "%s: whole tick, recorder off", label);
        bench_json_timing(&json, name, bench_stats(copy, ticks));
        memcpy(copy, t_on, ticks * sizeof copy[0]);
        snprintf(name, sizeof name, "%s: whole tick, recorder on", label);
        bench_json_timing(&json, name, bench_stats(copy, ticks));
        free(copy);
        snprintf(name, sizeof name, "%s: ring bytes per tick", label);
        bench_json_value(&json, name, (double)roz_recorder_slot_bytes(m), "bytes");
        snprintf(name, sizeof name, "%s: MCAP bytes per tick", label);
        bench_json_value(&json, name, (double)size / (double)roz_record_file_ticks(&file),
                         "bytes");
        snprintf(name, sizeof name, "%s: drain into the MCAP file", label);
        bench_json_value(&json, name, drain_ns ? 1e9 * (double)drained / (double)drain_ns : 0.0,
                         "ticks/s");
        snprintf(name, sizeof name, "%s: drain into a counting sink", label);
        bench_json_value(&json, name, sink_ns ? 1e9 * (double)counted / (double)sink_ns : 0.0,
                         "ticks/s");
        snprintf(name, sizeof name, "%s: records dropped", label);
        bench_json_value(&json, name, (double)roz_recorder_dropped(&rec), "count");
    }
    double off50 = pct(t_off, ticks, 50), off99 = pct(t_off, ticks, 99);
    double on50 = pct(t_on, ticks, 50), on99 = pct(t_on, ticks, 99);
    printf("%s, %u commands, %u states, %zu ticks, controller %s\n", label,
           (unsigned)m->n_commands, (unsigned)m->n_states, ticks, ctl);
    printf("  whole tick, recorder off      p50 %7.2f us   p99 %7.2f us\n", off50, off99);
    printf("  whole tick, recorder on       p50 %7.2f us   p99 %7.2f us   (+%.2f us p50, "
           "%.2fx)\n", on50, on99, on50 - off50, on50 / off50);
    printf("  bytes per tick                ring %lu, MCAP file %.0f (%ld bytes for %llu "
           "ticks)\n", (unsigned long)roz_recorder_slot_bytes(m),
           (double)size / (double)roz_record_file_ticks(&file), size,
           (unsigned long long)roz_record_file_ticks(&file));
    printf("  drain into the MCAP file      %.0f ticks/s, %.1f MB/s\n",
           drain_ns ? 1e9 * (double)drained / (double)drain_ns : 0.0,
           drain_ns ? 1e3 * (double)size / (double)drain_ns : 0.0);
    printf("  drain into a counting sink    %.0f ticks/s\n",
           sink_ns ? 1e9 * (double)counted / (double)sink_ns : 0.0);
    printf("  dropped                       %lu\n", (unsigned long)roz_recorder_dropped(&rec));
    roz_runtime_deinit(&rt_off);
    roz_runtime_deinit(&rt_on);
    free(t_off);
    free(t_on);
    free(ring);
    return 0;
}

int main(int argc, char **argv)
{
    argc = bench_json_args(&json, "record", argc, argv);
    if (argc < 0)
        return 1;
    size_t ticks = argc > 1 ? (size_t)strtoul(argv[1], NULL, 10) : 20000u;
    const char *dir = argc > 2 ? argv[2] : ".";
    if (ticks < DRAIN_EVERY)
        ticks = DRAIN_EVERY;
    printf("bench/record: the flight recorder on the loopback (figures, not a test)\n");
    /* uncompressed, then zstd when this build has it (the drain compresses:
     * the tick only fills the ring) */
    for (int z = 0; z < 2; z++) {
        int c = z ? ROZ_MCAP_COMPRESS_ZSTD : ROZ_MCAP_COMPRESS_NONE;
        if (!roz_mcap_compression_supported(c))
            continue;
        if (bench(&roz_manifest_ur5, "sine", ticks, dir, c) != 0 ||
            bench(&roz_manifest_unitree_g1, "g1_pd", ticks, dir, c) != 0)
            return 1;
    }
    bench_json_close(&json);
    return 0;
}
