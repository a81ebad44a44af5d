/* SPDX-License-Identifier: Apache-2.0 */
/*
 * bench/g1_latency: the time from a LowState_ leaving the robot to the
 * LowCmd_ that answers it, through roz: the port unitree/G1 takes the frame
 * (CRC, tick, conversion) on Cyclone's receive thread, a tick runs the G1 PD
 * controller under wasm3 (metered, behind the safety filter) as soon as the
 * frame is there, and the event-driven writer publishes the zeroed, filled,
 * CRC'd command; beside a raw Cyclone DDS ping-pong of the same sizes (a
 * LowState_ out, a LowCmd_ back from the echo's listener), interleaved in
 * the same run, on loopback.
 *
 * Two processes: this one plays the robot and times each round trip from
 * just before its dds_write() to its listener's call on the answer; a child
 * (this program again, --roz DOMAIN) runs roz and the raw echo. The child's
 * tick waits for a fresh frame by polling the port's counters with
 * sched_yield() (a firmware would tick from the frame's arrival the same
 * way), so both ways are event-driven. Prints p50, p99 and max of each and
 * the ratio. A benchmark, not a test: it never fails on a time.
 *
 *   roz_bench_g1_latency [ROUND_TRIPS] [DOMAIN] [--json FILE]
 */
#define _GNU_SOURCE
#include <errno.h>
#include <math.h>
#include <sched.h>
#include <semaphore.h>
#include <spawn.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/select.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <dds/dds.h>

#include "bench_json.h"
#include "roz/dds.h"
#include "roz/hal/clock.h"
#include "roz/hal/crc32.h"
#include "roz/hal/module.h"
#include "roz/runtime.h"
#include "roz/unitree_g1.h"
#include "unitree_g1_manifest.h"
#include "unitree_hg.h"

#ifndef ROZ_BENCH_CONTROLLER
#error "ROZ_BENCH_CONTROLLER: the G1 PD controller's .wasm, set by the build"
#endif

typedef unitree_hg_msg_dds__LowState_ lowstate_t;
typedef unitree_hg_msg_dds__LowCmd_ lowcmd_t;

extern char **environ;

static uint64_t now_ns(void)
{
    return roz_clock_monotonic_ns(NULL);
}

static void sleep_ms(unsigned ms)
{
    struct timespec ts = { (time_t)(ms / 1000u), (long)(ms % 1000u) * 1000000L };
    nanosleep(&ts, NULL);
}

/* ---- the child: roz, and the raw echo ----------------------------------------- */

static roz_unitree_g1_t g1;
static roz_runtime_t rt;
static dds_entity_t raw_echo_writer;

/* The raw echo: a LowCmd_ back for each raw LowState_, from the listener. */
static void on_raw_state(dds_entity_t rd, void *arg)
{
    lowstate_t s;
    lowcmd_t c;
    void *p[1] = { &s };
    dds_sample_info_t info[1];
    (void)arg;
    while (dds_take(rd, p, info, 1, 1) == 1) {
        if (!info[0].valid_data)
            continue;
        memset(&c, 0, sizeof c);
        c.reserve[0] = s.tick;
        (void)dds_write(raw_echo_writer, &c);
    }
}

static int child_main(uint32_t domain)
{
    static uint8_t wasm[ROZ_CFG_WASM_MAX_MODULE_BYTES];
    char err[300] = "", dom[16];
    size_t len = 0;

    snprintf(dom, sizeof dom, "%u", (unsigned)domain);
    roz_param_t items[] = { { "network_interface", "lo" }, { "dds_domain", dom },
                            { "command_writer_period_us", "0" }, { "enable_monitor", "false" } };
    roz_params_t params = { items, 4 };
    roz_port_t port = roz_unitree_g1_port(&g1, NULL, NULL);
    if (roz_module_read_file(ROZ_BENCH_CONTROLLER, wasm, sizeof wasm, &len, err, sizeof err) !=
            ROZ_OK ||
        roz_port_open(&port, &roz_manifest_unitree_g1, &params, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "roz side: %s\n", err);
        return 1;
    }
    roz_runtime_config_t cfg;
    roz_runtime_config_default(&cfg);
    cfg.manifest = &roz_manifest_unitree_g1;
    cfg.port = port;
    cfg.clock = roz_clock_monotonic_ns;
    cfg.monitor_jitter = 0;
    if (roz_runtime_init(&rt, &cfg) != ROZ_OK || roz_runtime_load(&rt, wasm, len, NULL) != ROZ_OK ||
        roz_port_activate(&port) != ROZ_OK || roz_runtime_start(&rt) != ROZ_OK) {
        fprintf(stderr, "roz side: cannot start\n");
        return 1;
    }

    /* the raw echo, in roz's participant (the same configuration) */
    dds_entity_t part = g1.part.participant;
    dds_entity_t ts = dds_create_topic(part, &unitree_hg_msg_dds__LowState__desc, "bench/state",
                                       NULL, NULL);
    dds_entity_t tc = dds_create_topic(part, &unitree_hg_msg_dds__LowCmd__desc, "bench/cmd", NULL,
                                       NULL);
    dds_qos_t *wq = dds_create_qos(), *rq = dds_create_qos();
    dds_qset_reliability(wq, DDS_RELIABILITY_RELIABLE, DDS_MSECS(1));
    dds_qset_history(wq, DDS_HISTORY_KEEP_LAST, 1);
    dds_qset_reliability(rq, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_history(rq, DDS_HISTORY_KEEP_LAST, 1);
    raw_echo_writer = dds_create_writer(part, tc, wq, NULL);
    dds_listener_t *l = dds_create_listener(NULL);
    dds_lset_data_available(l, on_raw_state);
    dds_entity_t rd = dds_create_reader(part, ts, rq, l);
    dds_delete_listener(l);
    dds_delete_qos(wq);
    dds_delete_qos(rq);
    if (raw_echo_writer < 0 || rd < 0) {
        fprintf(stderr, "raw echo: no reader or writer\n");
        return 1;
    }

    /* tick on each fresh frame, until the parent closes our stdin (polled
     * between frames: a read of 0 bytes = EOF) */
    puts("ready");
    fflush(stdout);
    roz_unitree_g1_counters_t c;
    uint64_t seen = 0, ticks_faulted = 0;
    for (;;) {
        roz_unitree_g1_counters(&g1, &c);
        if (c.frames != seen) {
            seen = c.frames;
            if (roz_runtime_tick(&rt) != ROZ_OK)
                ticks_faulted++;
            continue;
        }
        fd_set fds;
        FD_ZERO(&fds);
        FD_SET(0, &fds);
        struct timeval tv = { 0, 0 };
        if (select(1, &fds, NULL, NULL, &tv) > 0) {
            char b;
            if (read(0, &b, 1) <= 0)
                break;
        }
        sched_yield();
    }
    if (ticks_faulted != 0)
        fprintf(stderr, "roz side: %llu ticks under a fault (%s)\n",
                (unsigned long long)ticks_faulted, roz_runtime_fault_message(&rt));
    (void)roz_port_deactivate(&port);
    roz_runtime_deinit(&rt);
    roz_port_close(&port);
    return 0;
}

/* ---- the robot: this process ------------------------------------------------ */

static _Atomic uint64_t answers, answer_ns;
static sem_t answered; /* the robot's main thread sleeps until an answer */

static void on_answer(dds_entity_t rd, void *arg)
{
    lowcmd_t c;
    void *p[1] = { &c };
    dds_sample_info_t info[1];
    (void)arg;
    uint64_t t = now_ns();
    while (dds_take(rd, p, info, 1, 1) == 1) {
        if (!info[0].valid_data)
            continue;
        atomic_store(&answer_ns, t);
        atomic_fetch_add(&answers, 1u);
        sem_post(&answered);
    }
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static void stats(uint64_t *v, size_t n, double *p50, double *p99, double *max)
{
    qsort(v, n, sizeof v[0], cmp_u64);
    *p50 = v[n / 2] / 1000.0;
    *p99 = v[(n * 99) / 100] / 1000.0;
    *max = v[n - 1] / 1000.0;
}

/* One round trip: write, sleep until the answer (a hang guard of 1 s). */
static int round_trip(dds_entity_t wr, const lowstate_t *s, uint64_t *out_ns)
{
    while (sem_trywait(&answered) == 0)
        ; /* a late answer of a round trip given up on */
    uint64_t before = atomic_load(&answers);
    uint64_t t0 = now_ns();
    if (dds_write(wr, s) != DDS_RETCODE_OK)
        return -1;
    struct timespec until;
    clock_gettime(CLOCK_MONOTONIC, &until);
    until.tv_sec += 1;
    while (atomic_load(&answers) == before) {
        if (sem_clockwait(&answered, CLOCK_MONOTONIC, &until) != 0 && errno == ETIMEDOUT)
            return -1;
    }
    *out_ns = atomic_load(&answer_ns) - t0;
    return 0;
}

static void fill_state(lowstate_t *s, uint32_t tick)
{
    memset(s, 0, sizeof *s);
    s->mode_machine = 5;
    s->tick = tick;
    s->imu_state.quaternion[0] = 1.0f;
    for (int j = 0; j < 29; j++)
        s->motor_state[j].q = 0.01f * (float)(j % 5) + 0.0001f * (float)(tick % 100u);
    s->crc = roz_crc32_words((const uint32_t *)(const void *)s, sizeof *s / 4u - 1u);
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "--roz") == 0)
        return child_main((uint32_t)strtoul(argv[2], NULL, 10));
    bench_json_t json;
    argc = bench_json_args(&json, "g1_latency", argc, argv);
    if (argc < 0)
        return 2;
    size_t n = argc > 1 ? strtoul(argv[1], NULL, 10) : 5000;
    uint32_t domain = argc > 2 ? (uint32_t)strtoul(argv[2], NULL, 10) : 77;
    if (n < 100)
        n = 100;
    sem_init(&answered, 0, 0);

    /* the child, its stdin a pipe we close to stop it */
    int in[2], out[2];
    char dom[16], self[4096], flag[] = "--roz";
    snprintf(dom, sizeof dom, "%u", (unsigned)domain);
    snprintf(self, sizeof self, "%s", argv[0]);
    char *cargv[] = { self, flag, dom, NULL };
    posix_spawn_file_actions_t fa;
    pid_t pid;
    if (pipe(in) != 0 || pipe(out) != 0)
        return 1;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, in[0], 0);
    posix_spawn_file_actions_adddup2(&fa, out[1], 1);
    posix_spawn_file_actions_addclose(&fa, in[1]);
    posix_spawn_file_actions_addclose(&fa, out[0]);
    if (posix_spawn(&pid, self, &fa, NULL, cargv, environ) != 0) {
        fprintf(stderr, "cannot start the roz side\n");
        return 1;
    }
    close(in[0]);
    close(out[1]);
    char line[32] = "";
    FILE *from = fdopen(out[0], "r");
    if (fgets(line, sizeof line, from) == NULL || strncmp(line, "ready", 5) != 0) {
        fprintf(stderr, "the roz side did not start\n");
        return 1;
    }

    /* the robot: rt/lowstate out, rt/lowcmd in; bench/state out, bench/cmd in */
    roz_dds_participant_t p;
    char err[300] = "";
    if (roz_dds_participant_open(&p, "lo", domain, NULL, NULL, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "%s\n", err);
        return 1;
    }
    dds_qos_t *wq = dds_create_qos(), *rq = dds_create_qos();
    dds_qset_reliability(wq, DDS_RELIABILITY_RELIABLE, DDS_MSECS(1));
    dds_qset_history(wq, DDS_HISTORY_KEEP_LAST, 1);
    dds_qset_reliability(rq, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_history(rq, DDS_HISTORY_KEEP_LAST, 1);
    dds_listener_t *l = dds_create_listener(NULL);
    dds_lset_data_available(l, on_answer);
    dds_entity_t ws[2], rs[2];
    const char *state_topics[2] = { "rt/lowstate", "bench/state" };
    const char *cmd_topics[2] = { "rt/lowcmd", "bench/cmd" };
    for (int k = 0; k < 2; k++) {
        dds_entity_t t = dds_create_topic(p.participant, &unitree_hg_msg_dds__LowState__desc,
                                          state_topics[k], NULL, NULL);
        dds_entity_t u = dds_create_topic(p.participant, &unitree_hg_msg_dds__LowCmd__desc,
                                          cmd_topics[k], NULL, NULL);
        ws[k] = dds_create_writer(p.participant, t, wq, NULL);
        rs[k] = dds_create_reader(p.participant, u, rq, l);
    }
    dds_delete_listener(l);
    dds_delete_qos(wq);
    dds_delete_qos(rq);
    /* both ways matched, both paths */
    for (int i = 0; i < 20000; i++) {
        dds_publication_matched_status_t pm0, pm1;
        dds_subscription_matched_status_t sm0, sm1;
        dds_get_publication_matched_status(ws[0], &pm0);
        dds_get_publication_matched_status(ws[1], &pm1);
        dds_get_subscription_matched_status(rs[0], &sm0);
        dds_get_subscription_matched_status(rs[1], &sm1);
        if (pm0.current_count && pm1.current_count && sm0.current_count && sm1.current_count)
            break;
        sleep_ms(1);
    }
    sleep_ms(200); /* the other side's matches too */

    /* warm-up: roz's first frame and write (the start-up hold), caches */
    static lowstate_t s;
    uint64_t ns;
    uint32_t tick = 0;
    for (int i = 0; i < 200; i++) {
        fill_state(&s, tick++);
        (void)round_trip(ws[0], &s, &ns);
        (void)round_trip(ws[1], &s, &ns);
    }
    uint64_t *raw = calloc(n, sizeof *raw), *roz = calloc(n, sizeof *roz);
    size_t nr = 0, nz = 0, lost = 0;
    for (size_t i = 0; i < n; i++) {
        fill_state(&s, tick++);
        if (round_trip(ws[1], &s, &ns) == 0)
            raw[nr++] = ns;
        else
            lost++;
        if (round_trip(ws[0], &s, &ns) == 0)
            roz[nz++] = ns;
        else
            lost++;
    }
    close(in[1]);
    int status = 0;
    waitpid(pid, &status, 0);
    roz_dds_participant_close(&p);
    if (nr < 10 || nz < 10) {
        fprintf(stderr, "too few answers (%zu raw, %zu roz)\n", nr, nz);
        return 1;
    }
    double r50, r99, rmax, z50, z99, zmax;
    stats(raw, nr, &r50, &r99, &rmax);
    stats(roz, nz, &z50, &z99, &zmax);
    printf("G1 latency: a LowState_ out to the LowCmd_ that answers it, loopback, %zu round "
           "trips each (%zu lost)\n",
           nr, lost);
    printf("  %-44s p50 %8.1f us   p99 %8.1f us   max %8.1f us\n",
           "raw Cyclone ping-pong (2092 B out, 1004 B back)", r50, r99, rmax);
    printf("  %-44s p50 %8.1f us   p99 %8.1f us   max %8.1f us\n",
           "roz: unitree/G1, G1 PD under wasm3, event", z50, z99, zmax);
    printf("  ratio roz / raw                              p50 %8.2f       p99 %8.2f\n",
           z50 / r50, z99 / r99);
    bench_json_timing(&json, "raw Cyclone ping-pong", (bench_stats_t){ r50, r99, rmax });
    bench_json_timing(&json, "roz: unitree/G1, G1 PD under wasm3", (bench_stats_t){ z50, z99, zmax });
    bench_json_value(&json, "lost round trips", (double)lost, "count");
    bench_json_close(&json);
    free(raw);
    free(roz);
    return 0;
}
