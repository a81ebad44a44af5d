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
 *  - delayed frames: a gap as long as the delay where it starts, then
 *    fresh frames k ticks old, no fault (for k < stale_ticks); the
 *    controller and the filter see the state as it was k ticks ago, so
 *    position limits hold only to within the distance a joint covers in k
 *    ticks (the margin must cover the latency); frames overtaken in transit
 *    are dropped as replays;
 *  - duplicated (replayed) frames and frames failing their CRC: dropped and
 *    counted by the port's link checks (roz/hal/link.h), so they are missing
 *    frames: a short run is counted, a long one latches STALE;
 *  - command frames failing their CRC: dropped by the robot, which keeps its
 *    last good command; counted; the core cannot see it (the robot's own
 *    command timeout must cover a long run);
 *  - a peer that dies and comes back: STALE while it is gone, then the port
 *    reports the restart (ROZ_FAULT_LINK); a restart too quick for STALE is
 *    caught by its sequence going back; running again only after a clear;
 *  - NaN in a state channel: the paired velocity command stops (a limit
 *    stop, counted), a controller that passes the NaN on has its command
 *    refused (counted) and sent to the safe default, no fault; the joint
 *    resumes when the value is finite again.
 * Every written frame is checked against the manifest. Nothing asserts a
 * wall-clock time. */
#define _POSIX_C_SOURCE 200809L
/* white-box in part: reads the runtime's controller slots (a trapped
 * instance must never run again), which no public function exposes */
#define ROZ_PRIVATE_ACCESS
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
#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support_stats.h"
#include "support.h"
#include "support_runtime.h"
#include "ur5_manifest.h"

/* ---- the runtime on the loopback port ------------------------------------ */

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_test_clock_t clk;
static const roz_manifest_t *const m = &roz_manifest_ur5;
static uint32_t stale_ticks; /* 0: the default, 10 */
/* What the port got, frame by frame: the position limit may override the
 * rate cap (roz/filter.h), and an e-stop; nothing else may. */
static roz_test_frames_t frames;

#define V 0.628 /* constant_velocity: a fifth of 3.14 rad/s on every joint */

static void start_port(const roz_port_t *port, const char *controller)
{
    roz_runtime_config_t cfg;

    clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_runtime_config(&cfg, m, *port, &clk);
    assert_int_equal(cfg.stale_ticks, 10);
    if (stale_ticks != 0)
        cfg.stale_ticks = stale_ticks;
    roz_test_runtime_start(&rt, &cfg, controller);
    roz_test_frames_reset(&frames, &rt, m, 1);
}

static void start(const char *controller, const roz_loopback_fault_t *faults, size_t n)
{
    char err[160] = "";
    roz_port_t port = roz_loopback_port(&lb, NULL, NULL);

    if (roz_port_open(&port, m, NULL, err, sizeof err) != ROZ_OK)
        fail_msg("open: %s", err);
    for (size_t i = 0; i < n; i++)
        assert_int_equal(roz_loopback_inject(&lb, &faults[i]), ROZ_OK);
    start_port(&port, controller);
}

/* Within the manifest, and within max_rate of the frame before. */
static void check_frame(const double *cmd)
{
    roz_test_frames_check(&frames, cmd, (unsigned long long)RT_COUNT(&rt, ticks));
}

static int tick(void)
{
    int rc = roz_runtime_tick(&rt);
    check_frame(roz_runtime_last_commands(&rt));
    assert_int_equal(roz_loopback_counters(&lb).violations, 0);
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
    stale_ticks = 0;
    roz_runtime_deinit(&rt);
    return 0;
}

/* ---- loopback faults ------------------------------------------------------ */

/* Five dropped frames: stale reads, counted; no fault; the controller runs
 * every tick on the last frame it had. */
static void test_faults_short_drop_is_counted(void **st)
{
    roz_loopback_fault_t f = { ROZ_INJECT_DROP, 50, 55, -1, 0 };
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
    assert_int_equal(RT_COUNT(&rt, stale_reads), 5);
    assert_int_equal(roz_loopback_counters(&lb).frames_dropped, 5);
    assert_int_equal(RT_COUNT(&rt, controller_ticks), 100);
    assert_int_equal(RT_COUNT(&rt, writes), 100);
    assert_near(out()[0], V, 1e-12);
}

/* Twenty dropped frames: STALE on the tenth, a ramp to the defaults, still
 * latched when frames return, running again only after a clear. */
static void test_faults_long_drop_latches_stale(void **st)
{
    roz_loopback_fault_t f = { ROZ_INJECT_DROP, 50, 70, -1, 0 };
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
    uint64_t ran = RT_COUNT(&rt, controller_ticks);
    ticks(40); /* frames are back from tick 70: the fault stays */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_int_equal(RT_COUNT(&rt, controller_ticks), ran);
    assert_true(out()[0] == 0.0);
    assert_int_equal(RT_COUNT(&rt, faults[2]), 1);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    assert_int_equal(RT_COUNT(&rt, rebuilds), 0); /* nothing wrong with the controller */
    assert_int_equal(tick(), ROZ_OK);
    assert_near(out()[0], 0.5, 1e-12);
    tick();
    assert_near(out()[0], V, 1e-12);
}

/* A frozen stream (0.4 s, shorter than the loopback's peer timeout): STALE;
 * a clear while it is still frozen latches again stale_ticks later; after
 * it thaws, a clear recovers. */
static void test_faults_freeze_needs_clear(void **st)
{
    roz_loopback_fault_t f = { ROZ_INJECT_FREEZE, 30, 70, -1, 0 };
    (void)st;
    start("constant_velocity", &f, 1);
    ticks(40);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    for (int t = 40; t < 49; t++)
        assert_int_equal(tick(), ROZ_OK);
    assert_int_equal(tick(), ROZ_EFAULT); /* still frozen: latched again */
    assert_int_equal(RT_COUNT(&rt, faults[2]), 2);
    ticks(40); /* thawed at 70 */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(50);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_near(out()[0], V, 1e-12);
}

/* Frames sent in [50, 150) arrive five ticks late: five ticks without a
 * fresh frame (counted, no fault), then the simulator's state of five
 * ticks before; at the end the four frames overtaken by the first prompt
 * one are dropped as replays. */
static void test_faults_delay_is_latency(void **st)
{
    enum { K = 5, N = 200 };
    roz_loopback_fault_t f = { ROZ_INJECT_DELAY, 50, 150, -1, K };
    static double truth[N][ROZ_CFG_MAX_STATES];
    (void)st;
    start("constant_velocity", &f, 1);
    for (int t = 0; t < N; t++) {
        assert_int_equal(tick(), ROZ_OK);
        roz_loopback_true_state(&lb, truth[t]);
        const double *seen = roz_runtime_last_state(&rt);
        int sent = t < 50 || t >= 150 ? t : (t < 50 + K ? 49 : t - K);
        for (uint16_t s = 0; s < m->n_states; s++)
            assert_true(seen[s] == truth[sent][s]);
    }
    assert_int_equal(RT_COUNT(&rt, stale_reads), K);
    assert_int_equal(roz_loopback_link(&lb).replays, K - 1);
    assert_int_equal(RT_COUNT(&rt, controller_ticks), N);
}

/* How far a joint passes its position limit when the filter brakes on
 * state that is k ticks old: within the margin with fresh state; with
 * latency, by at most k ticks of travel. */
static double max_position(uint32_t delay, int n)
{
    roz_loopback_fault_t f = { ROZ_INJECT_DELAY, 20, 0, -1, delay }; /* from tick 20 on */
    double q[ROZ_CFG_MAX_STATES], top = -INFINITY;
    stale_ticks = 20; /* the gap where the delay starts is 15 ticks long */
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
    const double margin = roz_manifest_limit_margin(p);
    const double hi = p->max - margin, dt = 1.0 / m->control_rate_hz;
    (void)st;
    double fresh = max_position(0, 1200);       /* 0.628 rad/s reaches 2*pi in 10 s */
    double late = max_position(15, 1200);       /* 15 ticks = 150 ms of latency */
    print_message("joint 0 stops at %.4f rad with fresh state, %.4f rad with 15 ticks of "
                  "latency; limit %.4f, margin %.2f\n", fresh, late, p->max, margin);
    assert_true(fresh <= hi + 1e-9 && fresh > hi - 0.01);
    assert_true(late > fresh);
    assert_true(late <= hi + 15 * V * dt + 1e-9);
}

/* A replayed frame (the last one again, in place of a new one) is caught by
 * the port's sequence check: dropped and counted, so it is a missing frame;
 * a replay without end is a stale stream. */
static void test_faults_duplicate_is_rejected(void **st)
{
    roz_loopback_fault_t f = { ROZ_INJECT_DUPLICATE, 50, 55, -1, 0 };
    double first[ROZ_CFG_MAX_STATES], q[ROZ_CFG_MAX_STATES];
    (void)st;
    start("constant_velocity", &f, 1);
    ticks(50);
    memcpy(first, roz_runtime_last_state(&rt), m->n_states * sizeof first[0]);
    for (int t = 50; t < 55; t++) {
        assert_int_equal(tick(), ROZ_OK);
        assert_memory_equal(roz_runtime_last_state(&rt), first, m->n_states * sizeof first[0]);
    }
    tick();
    roz_loopback_true_state(&lb, q);
    assert_memory_equal(roz_runtime_last_state(&rt), q, m->n_states * sizeof q[0]);
    assert_int_equal(roz_loopback_counters(&lb).frames_duplicated, 5);
    assert_int_equal(roz_loopback_link(&lb).replays, 5);
    assert_int_equal(RT_COUNT(&rt, stale_reads), 5);
    assert_int_equal(roz_runtime_faults(&rt), 0);

    roz_runtime_deinit(&rt);
    roz_loopback_fault_t forever = { ROZ_INJECT_DUPLICATE, 10, 0, -1, 0 };
    start("constant_velocity", &forever, 1);
    ticks(19);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(tick(), ROZ_EFAULT); /* tick 19: the tenth replay */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    ticks(100);
    assert_true(out()[0] == 0.0);
    assert_int_equal(roz_loopback_link(&lb).replays, 110); /* even after 0.5 s of silence */
    assert_int_equal(roz_loopback_link(&lb).returns, 0);
}

/* State frames failing their CRC: dropped and counted; five are a short
 * gap, twenty latch STALE, and only a clear resumes. */
static void test_faults_corrupt_state(void **st)
{
    const roz_loopback_fault_t f[] = { { ROZ_INJECT_CORRUPT, 50, 55, -1, 0 },
                                       { ROZ_INJECT_CORRUPT, 100, 120, -1, 0 } };
    (void)st;
    start("constant_velocity", f, 2);
    ticks(100);
    assert_int_equal(roz_loopback_link(&lb).crc_errors, 5);
    assert_int_equal(RT_COUNT(&rt, stale_reads), 5);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_near(out()[0], V, 1e-12);
    ticks(9);
    assert_int_equal(tick(), ROZ_EFAULT); /* tick 109 */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    ticks(30); /* good frames again from 120: still latched */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_true(out()[0] == 0.0);
    assert_int_equal(roz_loopback_counters(&lb).frames_corrupted, 25);
    assert_int_equal(roz_loopback_link(&lb).crc_errors, 25);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(2);
    assert_near(out()[0], V, 1e-12);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* Command frames failing their CRC: the robot drops them and keeps its last
 * good command; it never applies a corrupted value. The core cannot see it. */
static void test_faults_corrupt_command(void **st)
{
    roz_loopback_fault_t f = { ROZ_INJECT_CORRUPT_CMD, 50, 70, -1, 0 };
    double good[ROZ_CFG_MAX_COMMANDS];
    (void)st;
    start("constant_velocity", &f, 1);
    ticks(50);
    memcpy(good, roz_loopback_last_command(&lb), m->n_commands * sizeof good[0]);
    roz_runtime_estop(&rt); /* the stop is corrupted in transit too */
    for (int t = 50; t < 70; t++) {
        tick();
        assert_memory_equal(roz_loopback_last_command(&lb), good, m->n_commands * sizeof good[0]);
    }
    assert_int_equal(roz_loopback_counters(&lb).cmds_corrupted, 20);
    assert_int_equal(roz_loopback_peer_link(&lb).crc_errors, 20);
    tick(); /* tick 70: the stop gets through */
    assert_true(roz_loopback_last_command(&lb)[0] == 0.0);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
}

/* The robot dies at tick 100 and boots again at 200 (1 s later): STALE at
 * 109, commands to the dead robot are lost, the port reports the restart
 * (LINK) at 200; the robot, which forgot its command, gets only the stopped
 * output until the application clears both faults. */
static void test_faults_peer_restart(void **st)
{
    roz_loopback_fault_t f = { ROZ_INJECT_RESTART, 100, 200, -1, 0 };
    double where[ROZ_CFG_MAX_STATES], q[ROZ_CFG_MAX_STATES];
    (void)st;
    start("constant_velocity", &f, 1);
    ticks(100);
    roz_loopback_true_state(&lb, where);
    ticks(9);
    assert_int_equal(tick(), ROZ_EFAULT); /* tick 109 */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    ticks(90);
    assert_int_equal(roz_loopback_counters(&lb).cmds_lost, 100);
    roz_loopback_true_state(&lb, q);
    for (uint16_t s = 0; s < m->n_states; s++) /* stopped where it died */
        assert_true(m->states[s].type == ROZ_IF_POSITION ? q[s] == where[s] : q[s] == 0.0);
    assert_int_equal(tick(), ROZ_EFAULT); /* tick 200: back, sequence 0 */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE | ROZ_FAULT_LINK);
    assert_int_equal(roz_loopback_link(&lb).restarts, 1);
    assert_int_equal(RT_COUNT(&rt, faults[5]), 1);
    uint64_t ran = RT_COUNT(&rt, controller_ticks);
    for (int t = 201; t < 250; t++) {
        assert_int_equal(tick(), ROZ_EFAULT);
        for (uint16_t i = 0; i < m->n_commands; i++)
            assert_true(roz_loopback_last_command(&lb)[i] == 0.0);
    }
    assert_int_equal(RT_COUNT(&rt, controller_ticks), ran);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(2);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_near(roz_loopback_last_command(&lb)[0], V, 1e-12);
}

/* A restart quicker than stale_ticks (dead for 5 ticks) is caught by the
 * robot's sequence going back to 0: LINK alone. */
static void test_faults_quick_restart(void **st)
{
    roz_loopback_fault_t f = { ROZ_INJECT_RESTART, 300, 305, -1, 0 };
    (void)st;
    start("constant_velocity", &f, 1);
    ticks(305);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(tick(), ROZ_EFAULT); /* tick 305 */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_LINK);
    assert_true(out()[0] == 0.0); /* an immediate stop: no ramp from 0.628 */
    assert_int_equal(roz_loopback_link(&lb).restarts, 1);
    assert_non_null(strstr(roz_runtime_fault_message(&rt), "port link fault"));
    ticks(20);
    assert_true(out()[0] == 0.0);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(2);
    assert_near(out()[0], V, 1e-12);
}

/* The limit of the sequence check: a robot that restarts early, its old
 * sequence (19) within the replay window, counts again from 0; its frames
 * are taken for replays (they could be) until its sequence passes the old
 * one. No frame passes meanwhile, so STALE latches on the tenth tick without
 * one (29) and stops the robot; the restart itself is not reported. A
 * quicker one (dead 1 tick at tick 8: 9 ticks without a fresh frame) would
 * go unnoticed: link.h, SAFETY.md. */
static void test_faults_early_restart_is_stale(void **st)
{
    roz_loopback_fault_t f = { ROZ_INJECT_RESTART, 20, 25, -1, 0 };
    (void)st;
    start("constant_velocity", &f, 1);
    ticks(29);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(tick(), ROZ_EFAULT); /* tick 29 */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    ticks(30);
    assert_int_equal(roz_loopback_link(&lb).replays, 20); /* sequence 0..19 at ticks 25..44 */
    assert_int_equal(roz_loopback_link(&lb).restarts + roz_loopback_link(&lb).returns, 0);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
}

/* NaN on joint 3's position: its velocity command stops (a limit stop),
 * the others run on; no fault; joint 3 resumes, ramped, afterwards. */
static void test_faults_nan_position_stops_its_joint(void **st)
{
    roz_loopback_fault_t f = { ROZ_INJECT_NAN, 50, 60, 3, 0 };
    (void)st;
    start("constant_velocity", &f, 1);
    ticks(50);
    assert_near(out()[3], V, 1e-12);
    tick();
    assert_true(out()[3] == 0.0); /* position unknown: stop now */
    assert_near(out()[2], V, 1e-12);
    ticks(9);
    assert_true(out()[3] == 0.0);
    assert_true(roz_test_channel(&rt, 3).limit_stops >= 10);
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
    roz_loopback_fault_t f = { ROZ_INJECT_NAN, 50, 60, 7, 0 }; /* joint 1's velocity */
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

static int tp_write(void *self, const double *cmd, size_t n)
{
    (void)self;
    (void)n;
    check_frame(cmd);
    return ROZ_OK;
}

static const roz_port_ops_t stalling_ops = { .name = "stalling-test",
                                             .read = roz_test_buffer_port_read,
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
    roz_port_t port = { &stalling_ops, &state_buf, 0 };
    char err[64];
    (void)st;
    assert_int_equal(roz_port_open(&port, m, NULL, err, sizeof err), ROZ_OK); /* no open op */
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
        roz_test_tick(&rt);
        n++;
    }
    print_message("STALE latched after %d ticks without the producer\n", n);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_true(n >= 10 && n <= 11);
    roz_test_tick(&rt);
    assert_true(out()[0] == 0.0);
    uint64_t ran = RT_COUNT(&rt, controller_ticks);

    /* 3. it resumes: fresh frames, but the fault stays latched */
    atomic_store(&stall, 0);
    for (int t = 0; t < 20; t++)
        assert_int_equal(tick_fresh(), ROZ_EFAULT);
    assert_int_equal(RT_COUNT(&rt, controller_ticks), ran);
    assert_true(out()[0] == 0.0);

    /* 4. the application clears it: running again */
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    for (int t = 0; t < 5; t++)
        assert_int_equal(tick_fresh(), ROZ_OK);
    assert_int_equal(RT_COUNT(&rt, controller_ticks), ran + 5);
    assert_near(out()[0], V, 1e-12);

    atomic_store(&stop_producer, 1);
    pthread_join(th, NULL);
}

ROZ_TEST_MAIN(cmocka_unit_test_teardown(test_faults_short_drop_is_counted, teardown),
              cmocka_unit_test_teardown(test_faults_long_drop_latches_stale, teardown),
              cmocka_unit_test_teardown(test_faults_freeze_needs_clear, teardown),
              cmocka_unit_test_teardown(test_faults_delay_is_latency, teardown),
              cmocka_unit_test_teardown(test_faults_delay_and_position_limit, teardown),
              cmocka_unit_test_teardown(test_faults_duplicate_is_rejected, teardown),
              cmocka_unit_test_teardown(test_faults_corrupt_state, teardown),
              cmocka_unit_test_teardown(test_faults_corrupt_command, teardown),
              cmocka_unit_test_teardown(test_faults_peer_restart, teardown),
              cmocka_unit_test_teardown(test_faults_quick_restart, teardown),
              cmocka_unit_test_teardown(test_faults_early_restart_is_stale, teardown),
              cmocka_unit_test_teardown(test_faults_nan_position_stops_its_joint, teardown),
              cmocka_unit_test_teardown(test_faults_nan_state_into_controller, teardown),
              cmocka_unit_test_teardown(test_faults_stalled_port_thread, teardown))
