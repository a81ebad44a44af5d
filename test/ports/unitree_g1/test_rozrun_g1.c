/* SPDX-License-Identifier: Apache-2.0 */
/* End to end: rozrun drives the fake G1 (fake_g1 publishing LowState_ every
 * 2 ms from its own thread) with the g1_stand controller through the port
 * unitree/G1, on loopback DDS:
 *   rozrun --robot unitree_g1 --port unitree/G1 --param network_interface=lo
 *          --param dds_domain=D --controller g1_stand.wasm --ticks 1500
 * (rozrun_stand.c). Under TSan (label threads) this is the tick on
 * rozrun's periodic thread, the port's writer thread and Cyclone's receive
 * thread running the port's state path, and the main thread reading the
 * port's counters, all at once.
 * Asserted: rozrun exits 0 with no fault latched and the state link taking
 * frames with no bad CRC; while it runs, the robot receives the stand's
 * commands (the knee's gain reaches the controller's 150, its target the
 * pose's 0.3) with no bad CRC; after it, the robot's last command is the
 * port's damping command (kp 0, kd the manifest's 8). The run is recorded
 * (--record, drained by rozrun's main thread while the port's threads run)
 * and replayed: rozrun --replay gives the same targets, applied commands and
 * faults bit for bit at each of the 1500 ticks, without the robot.
 * And a 23-DoF G1 (the fake reporting mode_machine 10) with the
 * unitree_g1_23dof manifest and g1_23dof_stand: no fault, no clamp, the
 * knee's gain reaches 150, the six slots the robot lacks stay mode 0 and
 * zero in every command seen.
 * And rozrun --realtime: the tick on SCHED_FIFO at its priority (80), and
 * every thread that carries the robot's commands and state one below it by
 * default (the port's command writer; Cyclone's receive, delivery and event
 * threads), read from /proc while it runs. */
#define _POSIX_C_SOURCE 200809L
#include <sched.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "fake_g1_client.h"
#include "proc_threads.h"
#include "roz/hal/thread.h"
#include "rozrun_stand.h"
#include "support.h"

#ifndef ROZRUN
#error "ROZRUN, CONTROLLER, CONTROLLER_23DOF, OUT: set by the build"
#endif

/* The knee's largest gain seen, and its target then. */
typedef struct {
    roz_fake_g1_t *fake;
    double         kp, q;
} knee_t;

static void watch_knee(void *ctx)
{
    knee_t *k = ctx;
    roz_fake_g1_cmd_t c;
    /* kp 200, the knee's hold gain, is only the exit's hold: not the stand's */
    if (roz_fake_g1_command(k->fake, &c) == 1 && c.kp[3] > k->kp && c.kp[3] != 200.0f) {
        k->kp = c.kp[3];
        k->q = c.q[3];
    }
}

static void test_rozrun_g1_stand(void **st)
{
    roz_fake_g1_t fake;
    roz_fake_g1_cmd_t c;
    char err[256] = "", text[16384];
    static const char *const extra[] = { "--period-us", "2000", NULL };
    (void)st;

    if (roz_fake_g1_start(&fake, ROZ_TEST_DDS_DOMAIN, extra, err, sizeof err) != 0)
        fail_msg("%s", err);
    knee_t knee = { &fake, 0.0, 0.0 };
    roz_rozrun_stand(ROZRUN, "unitree_g1", "unitree/G1", CONTROLLER, ROZ_TEST_DDS_DOMAIN, 1500,
                     OUT, RECORDING, watch_knee, &knee, text, sizeof text);
    assert_non_null(strstr(text, "faults                 none"));
    assert_non_null(strstr(text, "port                   unitree/G1"));
    unsigned long long taken = 0, bad = 1;
    const char *link = strstr(text, "state link");
    assert_non_null(link);
    assert_int_equal(sscanf(link, "state link %llu frames taken, %llu bad CRC", &taken, &bad), 2);
    assert_true(taken > 100);
    assert_int_equal(bad, 0);

    /* the stand's gains and pose reached the robot */
    assert_true(knee.kp == 150.0);
    assert_true(knee.q > 0.0 && knee.q <= 0.3 + 1e-6);
    uint64_t good = 0, badcrc = 1;
    assert_int_equal(roz_fake_g1_commands(&fake, &good, &badcrc), 0);
    assert_true(good > 500);
    assert_int_equal(badcrc, 0);
    /* and its last command was the port's exit, the stop's hold (the
     * knee at its hold gain 200, every joint's kd the damping default 8):
     * acknowledged before rozrun exited, it may still be on its way through
     * the fake's own process on a loaded machine, so look again a while */
    for (int ms = 0; ms < 5000; ms += 20) {
        assert_int_equal(roz_fake_g1_command(&fake, &c), 1);
        if (c.kp[3] == 200.0f)
            break;
        roz_fake_g1_sleep_ms(20);
    }
    for (int j = 0; j < 29; j++) {
        assert_int_equal(c.mode[j], 1);
        if (!(c.kp[j] > 0.0 && c.kd[j] == 8.0 && c.tau[j] == 0.0 && c.dq[j] == 0.0))
            fail_msg("the last command, joint %d: kp %g kd %g tau %g dq %g q %g (want the "
                     "hold: the hold gain, kd 8, tau 0, dq 0)",
                     j, c.kp[j], c.kd[j], c.tau[j], c.dq[j], c.q[j]);
    }
    for (int j = 29; j < 35; j++)
        assert_int_equal(c.mode[j], 0);
    assert_int_equal(roz_fake_g1_stop(&fake), 0);
    assert_non_null(strstr(text, "recording              " RECORDING " (1500 ticks, none dropped)"));

    /* the recording replays bit for bit, without the robot */
    roz_rozrun_replay(ROZRUN, RECORDING, CONTROLLER, 1500, OUT ".replay", text, sizeof text);
}

/* A 23-DoF G1 (mode_machine 10) and its own stand: the 23 motors it has
 * are driven, the six slots it lacks stay mode 0 and zero throughout. */
typedef struct {
    roz_fake_g1_t *fake;
    double         kp;       /* the left knee's largest gain seen */
    int            gaps_bad; /* a command drove a slot the robot lacks */
} g1_23dof_watch_t;

static const int absent_slots[6] = { 13, 14, 20, 21, 27, 28 };

static void watch_23dof(void *ctx)
{
    g1_23dof_watch_t *w = ctx;
    roz_fake_g1_cmd_t c;
    if (roz_fake_g1_command(w->fake, &c) != 1)
        return;
    if (c.kp[3] > w->kp && c.kp[3] != 200.0f) /* 200: the exit's hold, not the stand */
        w->kp = c.kp[3];
    for (int k = 0; k < 6; k++) {
        int j = absent_slots[k];
        if (c.mode[j] != 0 || c.q[j] != 0.0 || c.dq[j] != 0.0 || c.kp[j] != 0.0 ||
            c.kd[j] != 0.0 || c.tau[j] != 0.0)
            w->gaps_bad++;
    }
}

static void test_rozrun_g1_23dof_stand(void **st)
{
    roz_fake_g1_t fake;
    roz_fake_g1_cmd_t c;
    char err[256] = "", text[16384];
    static const char *const extra[] = { "--period-us", "2000", "--mode-machine", "10", NULL };
    (void)st;

    if (roz_fake_g1_start(&fake, ROZ_TEST_DDS_DOMAIN, extra, err, sizeof err) != 0)
        fail_msg("%s", err);
    g1_23dof_watch_t w = { &fake, 0.0, 0 };
    roz_rozrun_stand(ROZRUN, "unitree_g1_23dof", "unitree/G1", CONTROLLER_23DOF,
                     ROZ_TEST_DDS_DOMAIN, 1000, OUT ".23dof", NULL, watch_23dof, &w, text,
                     sizeof text);
    assert_non_null(strstr(text, "faults                 none"));
    assert_non_null(strstr(text, "clamps                 0"));
    assert_true(w.kp == 150.0);
    assert_int_equal(w.gaps_bad, 0);
    assert_int_equal(roz_fake_g1_command(&fake, &c), 1);
    for (int j = 0; j < 29; j++) {
        int absent = 0;
        for (int k = 0; k < 6; k++)
            absent |= absent_slots[k] == j;
        assert_int_equal(c.mode[j], absent ? 0 : 1);
    }
    assert_int_equal(roz_fake_g1_stop(&fake), 0);
}

/* rozrun's threads by name, as last seen while it ran. */
#define MAX_SEEN 32
typedef struct {
    int  n;
    char name[MAX_SEEN][16];
    int  policy[MAX_SEEN], prio[MAX_SEEN];
} threads_seen_t;

static void keep_thread(void *ctx, const char *name, int policy, int prio)
{
    threads_seen_t *w = ctx;
    int k = 0;
    while (k < w->n && strcmp(w->name[k], name) != 0)
        k++;
    if (k == MAX_SEEN)
        return;
    if (k == w->n)
        snprintf(w->name[w->n++], sizeof w->name[0], "%s", name);
    w->policy[k] = policy;
    w->prio[k] = prio;
}

static void watch_threads(void *ctx)
{
    long pid = roz_rozrun_pid();
    if (pid != 0)
        roz_test_proc_threads(pid, keep_thread, ctx);
}

/* The policy of the thread named @p name (-1: never seen), its priority in
 * @p prio. */
static int seen(const threads_seen_t *w, const char *name, int *prio)
{
    for (int k = 0; k < w->n; k++) {
        if (strcmp(w->name[k], name) == 0) {
            *prio = w->prio[k];
            return w->policy[k];
        }
    }
    return -1;
}

static void *no_work(void *arg)
{
    return arg;
}

static void test_rozrun_g1_realtime(void **st)
{
    roz_fake_g1_t fake;
    static threads_seen_t w;
    char err[256] = "", text[16384], dom[32];
    static const char *const extra[] = { "--period-us", "2000", NULL };
    roz_thread_config_t fifo = { ROZ_THREAD_FIFO, 80, 0, 0 };
    unsigned long th;
    (void)st;

    int may_fifo = roz_thread_start(&th, &fifo, "probe", no_work, NULL, err, sizeof err) == ROZ_OK;
    if (may_fifo)
        roz_thread_join(th);
    if (roz_fake_g1_start(&fake, ROZ_TEST_DDS_DOMAIN, extra, err, sizeof err) != 0)
        fail_msg("%s", err);
    snprintf(dom, sizeof dom, "dds_domain=%u", (unsigned)ROZ_TEST_DDS_DOMAIN);
    const char *argv[] = { ROZRUN, "--robot", "unitree_g1", "--port", "unitree/G1",
                           "--param", "network_interface=lo", "--param", dom,
                           "--param", "peer_timeout_ms=5000",
                           "--param", "command_timeout_us=60000000",
                           "--controller", CONTROLLER, "--ticks", "1000", "--realtime",
                           "--budget-us", "off", "--stale-ticks", "250", NULL };
    int rc = roz_rozrun_spawn(argv, OUT ".realtime", watch_threads, &w, text, sizeof text);
    assert_int_equal(roz_fake_g1_stop(&fake), 0);
    assert_int_equal(rc, 0);
    assert_non_null(strstr(text, "faults                 none"));
    for (int k = 0; k < w.n; k++)
        print_message("thread %-15s policy %d priority %d\n", w.name[k], w.policy[k], w.prio[k]);

    static const char *const below[] = { "command_writer", "recv", "dq.user", "tev", NULL };
    int prio = -1;
    if (!may_fifo) {
        print_message("SCHED_FIFO not permitted here: every thread at normal priority\n");
        assert_non_null(strstr(text, "normal (SCHED_FIFO not permitted)"));
        assert_int_equal(seen(&w, "runner", &prio), SCHED_OTHER);
        for (size_t i = 0; below[i] != NULL; i++)
            assert_int_equal(seen(&w, below[i], &prio), SCHED_OTHER);
        return;
    }
    assert_non_null(strstr(text, "SCHED_FIFO, memory locked"));
    assert_int_equal(seen(&w, "runner", &prio), SCHED_FIFO);
    assert_int_equal(prio, 80);
    for (size_t i = 0; below[i] != NULL; i++) {
        int policy = seen(&w, below[i], &prio);
        if (policy != SCHED_FIFO || prio != 79)
            fail_msg("thread %s: policy %d priority %d, want SCHED_FIFO 79", below[i], policy,
                     prio);
    }
    /* no second receive thread that no setting reaches */
    assert_int_equal(seen(&w, "recvUC", &prio), -1);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_rozrun_g1_stand),
              cmocka_unit_test(test_rozrun_g1_23dof_stand),
              cmocka_unit_test(test_rozrun_g1_realtime))
