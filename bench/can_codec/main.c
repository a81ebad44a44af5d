/* SPDX-License-Identifier: Apache-2.0 */
/*
 * bench/can_codec: what the socketcan port costs.
 *   1. The MIT-mode codec (roz/port/mit_codec.h): packing a command and
 *      unpacking a reply, per joint, over varied values, in ns.
 *   2. The port on the example leg (examples/can_leg/leg.toml, 3 joints),
 *      fake actuators (test/fakes/can) on a socketpair, the writer at 2 ms,
 *      the tick at 500 Hz: what read() and write() cost the tick (timed
 *      here), and what a writer round and a reply cost the port's threads
 *      (its monitor's histograms); the bus figures the configuration gives.
 * Prints medians and p99. A benchmark, not a test: it never fails on a time.
 *
 *   roz_bench_can_codec [ITERATIONS] [TICKS] [--json FILE]
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "bench_json.h"
#include "can_leg_manifest.h"
#include "fake_can.h"
#include "roz/hal/clock.h"
#include "roz/port/mit_codec.h"
#include "roz/port/socketcan.h"

#define SAMPLES 4096

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static uint64_t pct(uint64_t *v, size_t n, double p)
{
    qsort(v, n, sizeof v[0], cmp_u64);
    size_t i = (size_t)(p / 100.0 * (double)(n - 1));
    return v[i];
}

static bench_json_t json;

/* p50, p99, max of `v` (`scale` ns per unit) for the JSON output */
static bench_stats_t pcts(uint64_t *v, size_t n, double scale)
{
    return (bench_stats_t){ pct(v, n, 50) * scale / 1000.0, pct(v, n, 99) * scale / 1000.0,
                            pct(v, n, 100) * scale / 1000.0 };
}

/* ---- 1. the codec ---------------------------------------------------------------- */

static void bench_codec(long iterations)
{
    static const roz_mit_ranges_t r = { { -12.5, 12.5 }, { -45, 45 }, { 0, 500 }, { 0, 5 },
                                        { -18, 18 } };
    static roz_mit_command_t cmds[256];
    static uint8_t replies[256][8];
    static uint64_t pack_ns[SAMPLES], unpack_ns[SAMPLES];
    uint64_t sink = 0, seed = 15;
    long batch = iterations / SAMPLES > 0 ? iterations / SAMPLES : 1;

    for (int i = 0; i < 256; i++) {
        seed = seed * 6364136223846793005u + 1442695040888963407u;
        double u = (double)(seed >> 11) / 9007199254740992.0;
        cmds[i] = (roz_mit_command_t){ -12.5 + 25 * u, 45 * (1 - 2 * u), 500 * u, 5 * u,
                                       18 * (2 * u - 1) };
        (void)roz_mit_codec_pack(&r, &cmds[i], replies[i]);
        replies[i][0] = (uint8_t)(i & 0x7F);
    }
    for (int s = 0; s < SAMPLES; s++) {
        uint8_t out[8];
        uint64_t t0 = roz_clock_monotonic_ns(NULL);
        for (long k = 0; k < batch; k++) {
            sink += roz_mit_codec_pack(&r, &cmds[(s + k) & 255], out);
            sink += out[7];
        }
        uint64_t t1 = roz_clock_monotonic_ns(NULL);
        roz_mit_reply_t rep;
        for (long k = 0; k < batch; k++) {
            (void)roz_mit_codec_unpack(&r, ROZ_MIT_REPLY_TEMP_ERROR, replies[(s + k) & 255], 8,
                                       &rep);
            sink += rep.position_code;
        }
        uint64_t t2 = roz_clock_monotonic_ns(NULL);
        pack_ns[s] = (t1 - t0) * 1000u / (uint64_t)batch; /* ps, for resolution */
        unpack_ns[s] = (t2 - t1) * 1000u / (uint64_t)batch;
    }
    uint64_t p50 = pct(pack_ns, SAMPLES, 50), u50 = pct(unpack_ns, SAMPLES, 50);
    printf("codec (%ld packs and unpacks; %llu)\n", batch * SAMPLES, (unsigned long long)(sink & 1));
    printf("  pack a command       median %6.1f ns   p99 %6.1f ns\n", p50 / 1000.0,
           pct(pack_ns, SAMPLES, 99) / 1000.0);
    printf("  unpack a reply       median %6.1f ns   p99 %6.1f ns\n", u50 / 1000.0,
           pct(unpack_ns, SAMPLES, 99) / 1000.0);
    printf("  per joint and round  median %6.1f ns\n", (p50 + u50) / 1000.0);
    bench_json_timing(&json, "codec: pack a command", pcts(pack_ns, SAMPLES, 0.001));
    bench_json_timing(&json, "codec: unpack a reply", pcts(unpack_ns, SAMPLES, 0.001));
}

/* ---- 2. the port on the leg --------------------------------------------------------- */

static roz_socketcan_t sc;
static fake_can_t bus;

#define LEG_RANGES(tmax)                                                                        \
    { { -12.5, 12.5 }, { -45.0, 45.0 }, { 0.0, 500.0 }, { 0.0, 5.0 }, { -(tmax), (tmax) } }
static const fake_actuator_cfg_t leg_actuators[3] = {
    { 1, 1, FAKE_TEMP_ERROR, LEG_RANGES(18.0) },
    { 2, 2, FAKE_TEMP_ERROR, LEG_RANGES(18.0) },
    { 3, 0, FAKE_TEMP_ERROR, LEG_RANGES(24.0) },
};

static void print_kind(const char *what, const roz_monitor_t *m, roz_monitor_kind_t kind)
{
    roz_monitor_stat_t st;
    if (roz_monitor_snapshot(m, kind, &st) != ROZ_OK)
        return;
    printf("  %-20s median %6.1f us   p99 %6.1f us   (%llu)\n", what,
           roz_monitor_stat_percentile(&st, 50) / 1000.0,
           roz_monitor_stat_percentile(&st, 99) / 1000.0, (unsigned long long)st.count);
}

static int bench_port(int ticks)
{
    static uint64_t read_ns[SAMPLES], write_ns[SAMPLES];
    const roz_manifest_t *m = &roz_manifest_can_leg;
    double state[ROZ_CAN_LEG_N_STATES], cmd[ROZ_CAN_LEG_N_COMMANDS];
    roz_param_t items[] = { { "command_writer_period_us", "2000" } };
    roz_params_t params = { items, 1 };
    roz_socketcan_info_t info;
    char err[300];
    int fds[2], n = 0;

    if (ticks > SAMPLES)
        ticks = SAMPLES;
    if (socketpair(AF_UNIX, SOCK_SEQPACKET, 0, fds) != 0 ||
        fake_can_start(&bus, fds[1], leg_actuators, 3, 0.002, 0) != 0) {
        fprintf(stderr, "roz_bench_can_codec: no socketpair\n");
        return 1;
    }
    roz_port_t port = roz_socketcan_port(&sc, NULL, NULL);
    roz_socketcan_set_fd(&sc, fds[0]);
    if (roz_port_open(&port, m, &params, err, sizeof err) != ROZ_OK ||
        roz_port_activate(&port) != ROZ_OK) {
        fprintf(stderr, "roz_bench_can_codec: %s\n", err);
        return 1;
    }
    for (uint16_t i = 0; i < m->n_commands; i++)
        cmd[i] = m->commands[i].default_value;
    for (int t = 0; t < ticks + 50; t++) {
        uint64_t t0 = roz_clock_monotonic_ns(NULL);
        int rc = roz_port_read(&port, state, m->n_states);
        uint64_t t1 = roz_clock_monotonic_ns(NULL);
        (void)roz_port_write(&port, cmd, m->n_commands);
        uint64_t t2 = roz_clock_monotonic_ns(NULL);
        if (t >= 50 && rc >= 0) { /* after the start-up */
            read_ns[n] = t1 - t0;
            write_ns[n] = t2 - t1;
            n++;
        }
        struct timespec ts = { 0, 2000000 };
        nanosleep(&ts, NULL);
    }
    roz_socketcan_info(&sc, &info);
    printf("\nthe port on the 3-joint leg, socketpair, writer every 2 ms, %d ticks at 500 Hz\n", n);
    printf("  bus (1 Mbit/s)       %u group%s, worst-case load %.1f %% a round\n",
           (unsigned)info.groups, info.groups == 1 ? "" : "s", 100.0 * info.bus_load);
    if (n > 0) {
        printf("  read() in the tick   median %6.2f us   p99 %6.2f us\n",
               pct(read_ns, (size_t)n, 50) / 1000.0, pct(read_ns, (size_t)n, 99) / 1000.0);
        printf("  write() in the tick  median %6.2f us   p99 %6.2f us\n",
               pct(write_ns, (size_t)n, 50) / 1000.0, pct(write_ns, (size_t)n, 99) / 1000.0);
        bench_json_timing(&json, "leg port: read() in the tick", pcts(read_ns, (size_t)n, 1.0));
        bench_json_timing(&json, "leg port: write() in the tick", pcts(write_ns, (size_t)n, 1.0));
    }
    print_kind("writer round", roz_socketcan_monitor(&sc), ROZ_MON_COMMAND_WRITER);
    print_kind("writer wake jitter", roz_socketcan_monitor(&sc), ROZ_MON_JITTER);
    print_kind("a reply, received", roz_socketcan_monitor(&sc), ROZ_MON_STATE_HANDLER);
    roz_socketcan_counters_t c;
    roz_link_t l;
    roz_socketcan_counters(&sc, &c);
    roz_socketcan_link(&sc, &l);
    printf("  frames               %llu sent, %llu replies taken, %llu replays, %llu missing\n",
           (unsigned long long)c.frames_sent, (unsigned long long)c.replies,
           (unsigned long long)l.replays, (unsigned long long)l.missing);
    (void)roz_port_deactivate(&port);
    roz_port_close(&port);
    fake_can_stop(&bus);
    close(fds[0]);
    close(fds[1]);
    return 0;
}

int main(int argc, char **argv)
{
    argc = bench_json_args(&json, "can_codec", argc, argv);
    if (argc < 0)
        return 2;
    long iterations = argc > 1 ? atol(argv[1]) : 4000000;
    int ticks = argc > 2 ? atoi(argv[2]) : 2000;
    bench_codec(iterations > 0 ? iterations : 4000000);
    int rc = bench_port(ticks > 0 ? ticks : 2000);
    bench_json_close(&json);
    return rc;
}
