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
 * (this program again, --roz DOMAIN) runs the raw echo and two roz sides,
 * each its own unitree/G1 port, runtime and controller: one with the plain
 * event-driven writer (woken by the tick's write), one whose writer spins
 * for the tick's command after each state frame (`command_writer_spin_us`),
 * the second in domain DOMAIN + 1 (the G1's topic names are fixed). The
 * three paths are interleaved round trip by round trip. The child's tick
 * waits for a fresh frame by polling the port's link counters (published
 * after the frame is in the port's buffer) with sched_yield() (a firmware
 * would tick from the frame's arrival the same way), so every path is
 * event-driven. The robot's process runs on CPU 0 and the child on CPU 1
 * (ROZ_BENCH_PIN=0: anywhere), as two machines would: on a small virtual
 * machine, threads free to move spend more on waking each other across
 * CPUs than on the work, and the figures then vary run to run by half.
 * Figures are given only if no roz tick ran under a fault
 * (a faulted tick answers with the safe command, without the controller).
 * Prints p50, p99 and max of each and the ratios. A benchmark, not a test:
 * it never fails on a time.
 *
 *   roz_bench_g1_latency [ROUND_TRIPS] [DOMAIN] [--json FILE]
 */
#define _GNU_SOURCE
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <semaphore.h>
#include <spawn.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <dds/dds.h>

#include "bench_json.h"
#include "roz/port/dds.h"
#include "roz/hal/clock.h"
#include "roz/hal/crc32.h"
#include "roz/module.h"
#include "roz/runtime.h"
#include "roz/port/unitree_g1.h"
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

#define SPIN_US "200" /* the spinning side's command_writer_spin_us */

/* One roz side: a port, a runtime, the G1 PD. */
typedef struct {
    roz_unitree_g1_t g1;
    roz_runtime_t rt;
    roz_port_t port;
    uint64_t seen, ticks, faulted;
} roz_side_t;

static roz_side_t sides[2];
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

static int side_start(roz_side_t *z, uint32_t domain, const char *spin_us, const uint8_t *wasm,
                      size_t len)
{
    char err[300] = "", dom[16];
    snprintf(dom, sizeof dom, "%u", (unsigned)domain);
    /* the robot here sends a frame only when the last one was answered,
     * with pauses (start-up, a busy machine): long peer and command
     * timeouts keep a pause from reading as a robot that vanished or a
     * tick that stopped */
    roz_param_t items[] = { { "network_interface", "lo" },
                            { "dds_domain", dom },
                            { "command_writer_period_us", "0" },
                            { "command_writer_spin_us", spin_us },
                            { "enable_monitor", "false" },
                            { "peer_timeout_ms", "5000" },
                            { "command_timeout_us", "5000000" } };
    roz_params_t params = { items, sizeof items / sizeof items[0] };
    z->port = roz_unitree_g1_port(&z->g1, NULL, NULL);
    if (roz_port_open(&z->port, &roz_manifest_unitree_g1, &params, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "roz side: %s\n", err);
        return -1;
    }
    roz_runtime_config_t cfg;
    roz_runtime_config_default(&cfg);
    cfg.manifest = &roz_manifest_unitree_g1;
    cfg.port = z->port;
    cfg.clock = roz_clock_monotonic_ns;
    cfg.monitor_jitter = 0;
    /* the deadline is checked as always, at 100 ms instead of half the
     * period: a process() preempted on a busy machine must not latch
     * BUDGET and end the run without figures */
    cfg.budget_ns = 100000000u;
    if (roz_runtime_init(&z->rt, &cfg) != ROZ_OK ||
        roz_runtime_load(&z->rt, wasm, len, NULL) != ROZ_OK ||
        roz_port_activate(&z->port) != ROZ_OK || roz_runtime_start(&z->rt) != ROZ_OK) {
        fprintf(stderr, "roz side: cannot start\n");
        return -1;
    }
    return 0;
}

/* A tick for each frame the port has taken since the last look. */
static int side_poll(roz_side_t *z)
{
    roz_link_t lk;
    roz_unitree_g1_link(&z->g1, &lk);
    if (lk.accepted == z->seen)
        return 0;
    z->seen = lk.accepted;
    z->ticks++;
    if (roz_runtime_tick(&z->rt) != ROZ_OK)
        z->faulted++;
    return 1;
}

static void side_stop(roz_side_t *z)
{
    (void)roz_port_deactivate(&z->port);
    roz_runtime_deinit(&z->rt);
    roz_port_close(&z->port);
}

static atomic_int stdin_closed;

static void *wait_eof(void *arg)
{
    char b;
    (void)arg;
    while (read(0, &b, 1) > 0)
        ;
    atomic_store(&stdin_closed, 1);
    return NULL;
}

/* Pins this process (threads created after inherit it) to @p cpu when the
 * machine has more than one and the variable ROZ_BENCH_PIN is not 0. */
static void pin_to(int cpu)
{
    const char *v = getenv("ROZ_BENCH_PIN");
    if ((v != NULL && strcmp(v, "0") == 0) || sysconf(_SC_NPROCESSORS_ONLN) < 2)
        return;
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    (void)sched_setaffinity(0, sizeof set, &set);
}

static int child_main(uint32_t domain)
{
    pin_to(1);
    static uint8_t wasm[ROZ_CFG_WASM_MAX_MODULE_BYTES];
    char err[300] = "";
    size_t len = 0;

    if (roz_module_read_file(ROZ_BENCH_CONTROLLER, wasm, sizeof wasm, &len, err, sizeof err) !=
        ROZ_OK) {
        fprintf(stderr, "roz side: %s\n", err);
        return 1;
    }
    if (side_start(&sides[0], domain, "0", wasm, len) != 0 ||
        side_start(&sides[1], domain + 1u, SPIN_US, wasm, len) != 0)
        return 1;

    /* the raw echo, in the first side's participant (the same configuration) */
    dds_entity_t part = roz_unitree_g1_participant(&sides[0].g1)->participant;
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

    /* tick on each fresh frame, until the parent closes our stdin (a
     * thread of its own waits for that, so the loop makes no system call
     * but the yield) */
    pthread_t eof;
    if (pthread_create(&eof, NULL, wait_eof, NULL) != 0) {
        fprintf(stderr, "roz side: no thread\n");
        return 1;
    }
    puts("ready");
    fflush(stdout);
    while (!atomic_load_explicit(&stdin_closed, memory_order_relaxed)) {
        if (!(side_poll(&sides[0]) | side_poll(&sides[1])))
            sched_yield();
    }
    pthread_join(eof, NULL);
    /* the parent's verdict on the figures: ticks, and ticks under a fault */
    for (int k = 0; k < 2; k++)
        printf("side %d ticks %llu faulted %llu %s\n", k, (unsigned long long)sides[k].ticks,
               (unsigned long long)sides[k].faulted,
               sides[k].faulted ? roz_runtime_fault_message(&sides[k].rt) : "-");
    fflush(stdout);
    side_stop(&sides[1]);
    side_stop(&sides[0]);
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

/* One way to the child and back: a writer and the reader of its answers. */
typedef struct {
    const char *name;
    dds_entity_t w, r;
    uint64_t *ns;
    size_t n;
} path_t;

static int open_path(path_t *x, const roz_dds_participant_t *p, const char *state_topic,
                     const char *cmd_topic)
{
    dds_qos_t *wq = dds_create_qos(), *rq = dds_create_qos();
    dds_qset_reliability(wq, DDS_RELIABILITY_RELIABLE, DDS_MSECS(1));
    dds_qset_history(wq, DDS_HISTORY_KEEP_LAST, 1);
    dds_qset_reliability(rq, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_history(rq, DDS_HISTORY_KEEP_LAST, 1);
    dds_listener_t *l = dds_create_listener(NULL);
    dds_lset_data_available(l, on_answer);
    dds_entity_t t = dds_create_topic(p->participant, &unitree_hg_msg_dds__LowState__desc,
                                      state_topic, NULL, NULL);
    dds_entity_t u = dds_create_topic(p->participant, &unitree_hg_msg_dds__LowCmd__desc,
                                      cmd_topic, NULL, NULL);
    x->w = dds_create_writer(p->participant, t, wq, NULL);
    x->r = dds_create_reader(p->participant, u, rq, l);
    dds_delete_listener(l);
    dds_delete_qos(wq);
    dds_delete_qos(rq);
    return x->w > 0 && x->r > 0 ? 0 : -1;
}

static int path_matched(const path_t *x)
{
    dds_publication_matched_status_t pm;
    dds_subscription_matched_status_t sm;
    return dds_get_publication_matched_status(x->w, &pm) == DDS_RETCODE_OK &&
           dds_get_subscription_matched_status(x->r, &sm) == DDS_RETCODE_OK &&
           pm.current_count > 0 && sm.current_count > 0;
}

enum { RAW, ROZ, ROZ_SPIN, PATHS };

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
    if (domain >= ROZ_DDS_MAX_DOMAIN) {
        fprintf(stderr, "domain %u: the bench uses it and the next (at most %u)\n",
                (unsigned)domain, ROZ_DDS_MAX_DOMAIN - 1u);
        return 2;
    }
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
    pin_to(0);
    char line[300] = "";
    FILE *from = fdopen(out[0], "r");
    if (fgets(line, sizeof line, from) == NULL || strncmp(line, "ready", 5) != 0) {
        fprintf(stderr, "the roz side did not start\n");
        return 1;
    }

    /* the robot: bench/state and rt/lowstate out in the first domain,
     * rt/lowstate in the second; the answers back on the matching topics */
    roz_dds_participant_t p[2];
    char err[300] = "";
    for (int k = 0; k < 2; k++) {
        if (roz_dds_participant_open(&p[k], "lo", domain + (uint32_t)k, NULL, NULL, NULL, err,
                                     sizeof err) != ROZ_OK) {
            fprintf(stderr, "%s\n", err);
            return 1;
        }
    }
    path_t path[PATHS] = {
        [RAW] = { "raw Cyclone ping-pong", 0, 0, NULL, 0 },
        [ROZ] = { "roz: unitree/G1, G1 PD under wasm3", 0, 0, NULL, 0 },
        [ROZ_SPIN] = { "roz: unitree/G1, G1 PD under wasm3, writer spin", 0, 0, NULL, 0 },
    };
    if (open_path(&path[RAW], &p[0], "bench/state", "bench/cmd") != 0 ||
        open_path(&path[ROZ], &p[0], "rt/lowstate", "rt/lowcmd") != 0 ||
        open_path(&path[ROZ_SPIN], &p[1], "rt/lowstate", "rt/lowcmd") != 0) {
        fprintf(stderr, "no reader or writer\n");
        return 1;
    }
    /* every way matched, then the other side's matches too */
    for (int i = 0; i < 20000; i++) {
        int all = 1;
        for (int k = 0; k < PATHS; k++)
            all &= path_matched(&path[k]);
        if (all)
            break;
        sleep_ms(1);
    }
    sleep_ms(200);

    /* warm-up: roz's first frame and write (the start-up hold), caches;
     * until every path has answered 200 times in a row (at most 10 s) */
    static lowstate_t s;
    uint64_t ns;
    uint32_t tick = 0;
    int streak = 0;
    uint64_t warm_until = now_ns() + 10000000000ull;
    while (streak < 200 && now_ns() < warm_until) {
        fill_state(&s, tick++);
        int ok = 1;
        for (int k = 0; k < PATHS; k++)
            ok &= round_trip(path[k].w, &s, &ns) == 0;
        streak = ok ? streak + 1 : 0;
    }
    size_t lost = 0;
    for (int k = 0; k < PATHS; k++)
        path[k].ns = calloc(n, sizeof(uint64_t));
    for (size_t i = 0; i < n; i++) {
        fill_state(&s, tick++);
        for (int k = 0; k < PATHS; k++) {
            if (round_trip(path[k].w, &s, &ns) == 0)
                path[k].ns[path[k].n++] = ns;
            else
                lost++;
        }
    }
    close(in[1]);

    /* the child's account: a tick under a fault answered without the controller */
    int valid = streak >= 200;
    for (int k = 0; k < 2; k++) {
        unsigned long long ticks = 0, faulted = 0;
        if (fgets(line, sizeof line, from) == NULL ||
            sscanf(line, "side %*d ticks %llu faulted %llu", &ticks, &faulted) != 2) {
            fprintf(stderr, "the roz side gave no account of its ticks\n");
            valid = 0;
        } else if (faulted != 0) {
            fprintf(stderr, "roz side %d (%llu of %llu ticks under a fault): %s", k, faulted,
                    ticks, line);
            valid = 0;
        }
    }
    int status = 0;
    waitpid(pid, &status, 0);
    for (int k = 0; k < 2; k++)
        roz_dds_participant_close(&p[k]);
    for (int k = 0; k < PATHS; k++)
        if (path[k].n < 10)
            valid = 0;
    if (!valid) {
        fprintf(stderr, "no figures: the warm-up did not settle, a path answered too few round "
                        "trips, or roz ticked under a fault\n");
        return 1;
    }
    bench_stats_t st[PATHS];
    for (int k = 0; k < PATHS; k++)
        stats(path[k].ns, path[k].n, &st[k].p50, &st[k].p99, &st[k].max);
    printf("G1 latency: a LowState_ out to the LowCmd_ that answers it, loopback, %zu round "
           "trips each way, interleaved (%zu lost)\n",
           n, lost);
    static const char *const label[PATHS] = {
        "raw Cyclone ping-pong (2092 B out, 1004 B back)",
        "roz: unitree/G1, G1 PD under wasm3, event",
        "roz: the same, writer spin " SPIN_US " us",
    };
    for (int k = 0; k < PATHS; k++)
        printf("  %-48s p50 %8.1f us   p99 %8.1f us   max %8.1f us\n", label[k], st[k].p50,
               st[k].p99, st[k].max);
    for (int k = ROZ; k < PATHS; k++)
        printf("  ratio %-42s p50 %8.2f       p99 %8.2f\n", k == ROZ ? "roz / raw" : "roz, spin / raw",
               st[k].p50 / st[RAW].p50, st[k].p99 / st[RAW].p99);
    for (int k = 0; k < PATHS; k++)
        bench_json_timing(&json, path[k].name, st[k]);
    bench_json_value(&json, "writer spin (us)", atof(SPIN_US), "us");
    bench_json_value(&json, "lost round trips", (double)lost, "count");
    bench_json_close(&json);
    for (int k = 0; k < PATHS; k++)
        free(path[k].ns);
    return 0;
}
