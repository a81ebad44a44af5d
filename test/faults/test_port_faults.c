/* SPDX-License-Identifier: Apache-2.0 */
/* Faults of the state stream, injected through the loopback port, and a
 * port whose producer thread stalls. Each has a documented outcome
 * (SAFETY.md):
 *  - a short gap (dropped frames, fewer than stale_ticks): counted as stale
 *    reads, the controller runs on the last frame, no fault;
 *  - a long gap (drop or freeze of stale_ticks frames or more, or a stalled
 *    producer): the STALE fault latches on the stale_ticks-th missing frame,
 *    commands ramp to the safe defaults under the rate caps, and stay there
 *    after the stream comes back until the application clears the fault;
 *  - delayed frames: fresh, no fault; the controller and the filter see the
 *    state as it was k ticks ago, so position limits hold only to within the
 *    distance a joint covers in k ticks (the margin must cover the latency);
 *  - duplicated frames (the frame before, delivered again as fresh): taken as
 *    fresh and not detected by the core (the port's sequence numbers must
 *    catch replays), counted by the port, no fault;
 *  - NaN in a state channel: the paired velocity command stops (a limit
 *    stop, counted), a controller that passes the NaN on has its command
 *    refused (counted) and sent to the safe default, no fault; the joint
 *    resumes when the value is finite again.
 * Every written frame is checked against the manifest. Nothing asserts a
 * wall-clock time. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "roz/buffer.h"
#include "roz/loopback.h"
#include "roz/runtime.h"
#include "support.h"
#include "ur5_manifest.h"

/* ---- the runtime on the loopback port ------------------------------------ */

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_test_clock_t clk;
static const roz_manifest_t *const m = &roz_manifest_ur5;
static double prev_cmd[ROZ_CFG_MAX_COMMANDS];
static int have_prev;
/* Limit stops per channel before this tick: the position limit may
 * override the rate cap (roz/filter.h), nothing else may. */
static uint32_t stops_before[ROZ_CFG_MAX_COMMANDS];

#define V 0.628 /* constant_velocity: a fifth of 3.14 rad/s on every joint */

static void start_port(const roz_port_t *port, const char *controller)
{
    roz_runtime_config_t cfg;
    size_t len;
    const uint8_t *w = roz_test_controller(controller, &len);

    clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = *port;
    cfg.clock = roz_test_clock;
    cfg.clock_ctx = &clk;
    assert_int_equal(cfg.stale_ticks, 10);
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_load(&rt, w, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    have_prev = 0;
    memset(stops_before, 0, sizeof stops_before);
}

static void start(const char *controller, const roz_loopback_fault_t *faults, size_t n)
{
    char err[160] = "";
    roz_port_t port = roz_loopback_port(&lb);

    if (roz_port_open(&port, m, NULL, err, sizeof err) != ROZ_OK)
        fail_msg("open: %s", err);
    for (size_t i = 0; i < n; i++)
        assert_int_equal(roz_loopback_inject(&lb, &faults[i]), ROZ_OK);
    start_port(&port, controller);
}

/* Within the manifest, and within max_rate of the frame before. */
static void check_frame(const double *cmd)
{
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        int limited = rt.filter.channel_limit_stops[i] != stops_before[i];
        stops_before[i] = rt.filter.channel_limit_stops[i];
        if (!isfinite(cmd[i]) || cmd[i] < c->min || cmd[i] > c->max)
            fail_msg("tick %llu: command %u = %g outside [%g, %g]",
                     (unsigned long long)rt.counters.ticks, i, cmd[i], c->min, c->max);
        if (have_prev && !limited && fabs(cmd[i] - prev_cmd[i]) > c->max_rate + 1e-12)
            fail_msg("tick %llu: command %u jumped %g -> %g", (unsigned long long)rt.counters.ticks,
                     i, prev_cmd[i], cmd[i]);
        prev_cmd[i] = cmd[i];
    }
    have_prev = 1;
}

static int tick(void)
{
    int rc = roz_runtime_tick(&rt);
    check_frame(roz_runtime_last_commands(&rt));
    assert_int_equal(lb.violations, 0);
    return rc;
}

static void ticks(int n)
{
    for (int i = 0; i < n; i++)
        tick();
}

static const double *out(void)
{
    return roz_runtime_last_commands(&rt);
}

static int teardown(void **st)
{
    (void)st;
    roz_runtime_deinit(&rt);
    return 0;
}

/* ---- loopback faults ------------------------------------------------------ */

/* Five dropped frames: stale reads, counted; no fault; the controller runs
 * every tick on the last frame it had. */
static void test_faults_short_drop_is_counted(void **st)
{
    roz_loopback_fault_t f = { ROZ_LOOPBACK_DROP, 50, 55, -1, 0 };
    double held[ROZ_CFG_MAX_STATES];
    (void)st;
    start("constant_velocity", &f, 1);
    ticks(50);
    memcpy(held, roz_runtime_last_state(&rt), m->n_states * sizeof held[0]);
    for (int t = 50; t < 55; t++) {
        assert_int_equal(tick(), ROZ_OK);
        assert_memory_equal(roz_runtime_last_state(&rt), held, m->n_states * sizeof held[0]);
    }
    ticks(45);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(rt.counters.stale_reads, 5);
    assert_int_equal(lb.frames_dropped, 5);
    assert_int_equal(rt.counters.controller_ticks, 100);
    assert_int_equal(rt.counters.writes, 100);
    assert_near(out()[0], V, 1e-12);
}

/* Twenty dropped frames: STALE on the tenth, a ramp to the defaults, still
 * latched when frames return, running again only after a clear. */
static void test_faults_long_drop_latches_stale(void **st)
{
    roz_loopback_fault_t f = { ROZ_LOOPBACK_DROP, 50, 70, -1, 0 };
    (void)st;
    start("constant_velocity", &f, 1);
    ticks(50);
    for (int t = 50; t < 59; t++)
        assert_int_equal(tick(), ROZ_OK);
    assert_int_equal(tick(), ROZ_EFAULT); /* tick 59: the tenth missing frame */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_non_null(strstr(roz_runtime_fault_message(&rt), "no fresh state for 10 ticks"));
    assert_near(out()[0], V - 0.5, 1e-12); /* ramped by max_rate */
    tick();
    assert_true(out()[0] == 0.0);
    uint64_t ran = rt.counters.controller_ticks;
    ticks(40); /* frames are back from tick 70: the fault stays */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_int_equal(rt.counters.controller_ticks, ran);
    assert_true(out()[0] == 0.0);
    assert_int_equal(rt.counters.faults[2], 1);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    assert_int_equal(rt.counters.rebuilds, 0); /* nothing wrong with the controller */
    assert_int_equal(tick(), ROZ_OK);
    assert_near(out()[0], 0.5, 1e-12);
    tick();
    assert_near(out()[0], V, 1e-12);
}

/* A frozen stream: STALE; a clear while it is still frozen latches again
 * stale_ticks later; after it thaws, a clear recovers. */
static void test_faults_freeze_needs_clear(void **st)
{
    roz_loopback_fault_t f = { ROZ_LOOPBACK_FREEZE, 30, 80, -1, 0 };
    (void)st;
    start("constant_velocity", &f, 1);
    ticks(40);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    for (int t = 40; t < 49; t++)
        assert_int_equal(tick(), ROZ_OK);
    assert_int_equal(tick(), ROZ_EFAULT); /* still frozen: latched again */
    assert_int_equal(rt.counters.faults[2], 2);
    ticks(40); /* thawed at 80 */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(50);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_near(out()[0], V, 1e-12);
}

/* Delayed frames are fresh frames: no stale read, no fault; the snapshot
 * is the simulator's state of five ticks before. */
static void test_faults_delay_is_latency(void **st)
{
    enum { K = 5, N = 200 };
    roz_loopback_fault_t f = { ROZ_LOOPBACK_DELAY, 50, 150, -1, K };
    static double truth[N][ROZ_CFG_MAX_STATES];
    (void)st;
    start("constant_velocity", &f, 1);
    for (int t = 0; t < N; t++) {
        assert_int_equal(tick(), ROZ_OK);
        roz_loopback_true_state(&lb, truth[t]);
        const double *seen = roz_runtime_last_state(&rt);
        int lag = t >= 50 && t < 150 ? K : 0;
        for (uint16_t s = 0; s < m->n_states; s++)
            assert_true(seen[s] == truth[t - lag][s]);
    }
    assert_int_equal(rt.counters.stale_reads, 0);
    assert_int_equal(rt.counters.controller_ticks, N);
}

/* How far a joint passes its position limit when the filter brakes on
 * state that is k ticks old: within the margin with fresh state; with
 * latency, by at most k ticks of travel. */
static double max_position(uint32_t delay, int n)
{
    roz_loopback_fault_t f = { ROZ_LOOPBACK_DELAY, 20, 0, -1, delay }; /* from tick 20 on */
    double q[ROZ_CFG_MAX_STATES], top = -INFINITY;
    start("constant_velocity", &f, delay > 0 ? 1 : 0);
    for (int t = 0; t < n; t++) {
        assert_int_equal(tick(), ROZ_OK);
        roz_loopback_true_state(&lb, q);
        top = fmax(top, q[0]);
    }
    roz_runtime_deinit(&rt);
    return top;
}

static void test_faults_delay_and_position_limit(void **st)
{
    const roz_channel_t *p = &m->states[0];
    const double hi = p->max - ROZ_FILTER_DEFAULT_MARGIN, dt = 1.0 / m->control_rate_hz;
    (void)st;
    double fresh = max_position(0, 1200);       /* 0.628 rad/s reaches 2*pi in 10 s */
    double late = max_position(15, 1200);       /* 15 ticks = 150 ms of latency */
    print_message("joint 0 stops at %.4f rad with fresh state, %.4f rad with 15 ticks of "
                  "latency; limit %.4f, margin %.2f\n", fresh, late, p->max,
                  ROZ_FILTER_DEFAULT_MARGIN);
    assert_true(fresh <= hi + 1e-9 && fresh > hi - 0.01);
    assert_true(late > fresh);
    assert_true(late <= hi + 15 * V * dt + 1e-9);
}

/* A duplicated frame is taken as fresh: the core cannot tell a replay from
 * a robot at rest; the port counts it. No stale read, no fault. */
static void test_faults_duplicate_is_taken_as_fresh(void **st)
{
    roz_loopback_fault_t f = { ROZ_LOOPBACK_DUPLICATE, 50, 60, -1, 0 };
    double first[ROZ_CFG_MAX_STATES], q[ROZ_CFG_MAX_STATES];
    (void)st;
    start("constant_velocity", &f, 1);
    ticks(50);
    memcpy(first, roz_runtime_last_state(&rt), m->n_states * sizeof first[0]);
    for (int t = 50; t < 60; t++) {
        assert_int_equal(tick(), ROZ_OK);
        assert_memory_equal(roz_runtime_last_state(&rt), first, m->n_states * sizeof first[0]);
    }
    tick();
    roz_loopback_true_state(&lb, q);
    assert_memory_equal(roz_runtime_last_state(&rt), q, m->n_states * sizeof q[0]);
    assert_int_equal(lb.frames_duplicated, 10);
    assert_int_equal(rt.counters.stale_reads, 0);
    assert_int_equal(roz_runtime_faults(&rt), 0);

    /* even a replay without end raises no STALE (SAFETY.md: ports must
     * reject replays by sequence number) */
    roz_runtime_deinit(&rt);
    roz_loopback_fault_t forever = { ROZ_LOOPBACK_DUPLICATE, 10, 0, -1, 0 };
    start("constant_velocity", &forever, 1);
    ticks(200);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(lb.frames_duplicated, 190);
}

/* NaN on joint 3's position: its velocity command stops (a limit stop),
 * the others run on; no fault; joint 3 resumes, ramped, afterwards. */
static void test_faults_nan_position_stops_its_joint(void **st)
{
    roz_loopback_fault_t f = { ROZ_LOOPBACK_NAN, 50, 60, 3, 0 };
    (void)st;
    start("constant_velocity", &f, 1);
    ticks(50);
    assert_near(out()[3], V, 1e-12);
    tick();
    assert_true(out()[3] == 0.0); /* position unknown: stop now */
    assert_near(out()[2], V, 1e-12);
    ticks(9);
    assert_true(out()[3] == 0.0);
    assert_true(rt.filter.channel_limit_stops[3] >= 10);
    tick();
    assert_near(out()[3], 0.5, 1e-12);
    tick();
    assert_near(out()[3], V, 1e-12);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* A controller that computes from a NaN state passes NaN on: command.set
 * refuses it (counted) and the channel goes to its safe default; no fault. */
static void test_faults_nan_state_into_controller(void **st)
{
    roz_loopback_fault_t f = { ROZ_LOOPBACK_NAN, 50, 60, 7, 0 }; /* joint 1's velocity */
    (void)st;
    start("pd_hold", &f, 1);
    ticks(50);
    int a = atomic_load(&rt.active);
    assert_int_equal(rt.slot[a].abi.counters.set_nonfinite, 0);
    ticks(10);
    assert_int_equal(rt.slot[a].abi.counters.set_nonfinite, 10);
    assert_true(out()[1] == 0.0);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    ticks(100);
    assert_true(fabs(out()[1]) > 0.0); /* holding its pose again */
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* ---- a port whose producer thread stalls ---------------------------------- */

ROZ_BUFFER_DEFINE(state_buf, ROZ_UR5_N_STATES);
static atomic_int stall, stalled, stop_producer;
static atomic_ullong produced;
static uint64_t seen;

static void nap(void)
{
    struct timespec ts = { 0, 100000 };
    nanosleep(&ts, NULL);
}

/* The producer: a frame every ~0.2 ms (joints at rest, positions creeping),
 * none while `stall` is set. */
static void *producer(void *arg)
{
    double st[ROZ_UR5_N_STATES];
    uint64_t k = 0;
    (void)arg;
    while (!atomic_load(&stop_producer)) {
        if (atomic_load(&stall)) {
            atomic_store(&stalled, 1);
        } else {
            atomic_store(&stalled, 0);
            for (int s = 0; s < ROZ_UR5_N_STATES; s++)
                st[s] = s < 6 ? 1e-6 * (double)k : 0.0;
            roz_buffer_write(&state_buf, st, ++k);
            atomic_fetch_add(&produced, 1);
        }
        nap();
        nap();
    }
    return NULL;
}

static int tp_read(void *self, double *state, size_t n)
{
    roz_buffer_frame_t f;
    (void)self;
    int rc = roz_buffer_read(&state_buf, &f);
    if (rc >= 0)
        memcpy(state, f.values, n * sizeof state[0]);
    return rc;
}

static int tp_write(void *self, const double *cmd, size_t n)
{
    (void)self;
    (void)n;
    check_frame(cmd);
    return ROZ_OK;
}

static const roz_port_ops_t stalling_ops = { .name = "stalling-test", .read = tp_read,
                                             .write = tp_write };

/* Tick once a new frame has been produced (so the tick sees a fresh one). */
static int tick_fresh(void)
{
    while (atomic_load(&produced) == seen)
        nap();
    seen = atomic_load(&produced);
    return roz_runtime_tick(&rt);
}

static void test_faults_stalled_port_thread(void **st)
{
    pthread_t th;
    roz_port_t port = { &stalling_ops, NULL };
    (void)st;
    roz_buffer_init(&state_buf, state_buf_slots, ROZ_UR5_N_STATES);
    atomic_store(&stall, 0);
    atomic_store(&stalled, 0);
    atomic_store(&stop_producer, 0);
    atomic_store(&produced, 0);
    seen = 0;
    start_port(&port, "constant_velocity");
    assert_int_equal(pthread_create(&th, NULL, producer, NULL), 0);

    /* 1. running on fresh frames */
    for (int t = 0; t < 30; t++)
        assert_int_equal(tick_fresh(), ROZ_OK);
    assert_near(out()[0], V, 1e-12);

    /* 2. the producer stops: STALE within stale_ticks (+1 for a frame that
     *    may have landed just before it stopped), ramped stop */
    atomic_store(&stall, 1);
    while (!atomic_load(&stalled))
        nap();
    int n = 0;
    while (roz_runtime_faults(&rt) == 0 && n < 20) {
        roz_runtime_tick(&rt);
        n++;
    }
    print_message("STALE latched after %d ticks without the producer\n", n);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_true(n >= 10 && n <= 11);
    roz_runtime_tick(&rt);
    assert_true(out()[0] == 0.0);
    uint64_t ran = rt.counters.controller_ticks;

    /* 3. it resumes: fresh frames, but the fault stays latched */
    atomic_store(&stall, 0);
    for (int t = 0; t < 20; t++)
        assert_int_equal(tick_fresh(), ROZ_EFAULT);
    assert_int_equal(rt.counters.controller_ticks, ran);
    assert_true(out()[0] == 0.0);

    /* 4. the application clears it: running again */
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    for (int t = 0; t < 5; t++)
        assert_int_equal(tick_fresh(), ROZ_OK);
    assert_int_equal(rt.counters.controller_ticks, ran + 5);
    assert_near(out()[0], V, 1e-12);

    atomic_store(&stop_producer, 1);
    pthread_join(th, NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_teardown(test_faults_short_drop_is_counted, teardown),
        cmocka_unit_test_teardown(test_faults_long_drop_latches_stale, teardown),
        cmocka_unit_test_teardown(test_faults_freeze_needs_clear, teardown),
        cmocka_unit_test_teardown(test_faults_delay_is_latency, teardown),
        cmocka_unit_test_teardown(test_faults_delay_and_position_limit, teardown),
        cmocka_unit_test_teardown(test_faults_duplicate_is_taken_as_fresh, teardown),
        cmocka_unit_test_teardown(test_faults_nan_position_stops_its_joint, teardown),
        cmocka_unit_test_teardown(test_faults_nan_state_into_controller, teardown),
        cmocka_unit_test_teardown(test_faults_stalled_port_thread, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
