/* SPDX-License-Identifier: Apache-2.0 */
/* The threaded pieces together, for ThreadSanitizer: a port whose simulator
 * runs on its own thread and talks to the tick through two latest-value
 * buffers (state in, commands out), the tick on the periodic runner, and a
 * third thread swapping controllers, raising the e-stop and clearing faults
 * while it runs. Nothing here asserts a time: the run lasts until the tick
 * has read new frames and the simulator has taken commands after the last
 * swap, however slowly a loaded machine runs either thread. */
#define _POSIX_C_SOURCE 200809L
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
#include "roz/hal/clock.h"
#include "roz/runner.h"
#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support_stats.h"
#include "support.h"
#include "support_runtime.h"
#include "unitree_g1_manifest.h"

/* ---- a port with a simulator thread ---------------------------------------- */

ROZ_BUFFER_DEFINE(state_buf, ROZ_UNITREE_G1_N_STATES);
ROZ_BUFFER_DEFINE(cmd_buf, ROZ_UNITREE_G1_N_COMMANDS);
static roz_loopback_t sim;
static atomic_int sim_stop;
static atomic_ullong sim_violations;
static atomic_ullong sim_commands; /* commands the simulator took from the tick */
static atomic_ullong fresh_reads, tick_writes; /* the tick's reads of a new frame, its writes */

static void *sim_main(void *arg)
{
    double state[ROZ_UNITREE_G1_N_STATES];
    roz_buffer_frame_t f;
    roz_port_t p = roz_loopback_port(&sim, NULL, NULL);
    (void)arg;
    while (!atomic_load(&sim_stop)) {
        if (roz_buffer_read(&cmd_buf, &f) == 1) {
            roz_port_write(&p, f.values, ROZ_UNITREE_G1_N_COMMANDS);
            atomic_fetch_add(&sim_commands, 1u);
        }
        if (roz_port_read(&p, state, ROZ_UNITREE_G1_N_STATES) == 1)
            roz_buffer_write(&state_buf, state, roz_clock_monotonic_ns(NULL));
        atomic_store(&sim_violations, roz_loopback_counters(&sim).violations);
        struct timespec ts = { 0, 500000 };
        nanosleep(&ts, NULL);
    }
    return NULL;
}

static int tp_write(void *self, const double *cmd, size_t n)
{
    (void)self;
    (void)n;
    roz_buffer_write(&cmd_buf, cmd, 0);
    atomic_fetch_add(&tick_writes, 1u);
    return ROZ_OK;
}

static int tp_read(void *self, double *state, size_t n)
{
    int rc = roz_test_buffer_port_read(self, state, n);
    if (rc == 1)
        atomic_fetch_add(&fresh_reads, 1u);
    return rc;
}

static const roz_port_ops_t threaded_ops = { .name = "threaded-test",
                                             .read = tp_read,
                                             .write = tp_write };

/* ---- the test ------------------------------------------------------------ */

static roz_runtime_t rt;
static roz_runner_t runner;

static int tick(void *ctx)
{
    (void)ctx;
    roz_test_tick(&rt);
    return 0;
}

static void sleep_ms(long ms)
{
    struct timespec ts = { ms / 1000, (ms % 1000) * 1000000L };
    nanosleep(&ts, NULL);
}

static void test_threads_runtime_under_load(void **st)
{
    roz_runtime_config_t cfg;
    roz_runner_config_t rc = { .period_ns = 1000000, .max_ticks = 0 }; /* until stopped */
    char err[128];
    pthread_t th;
    size_t len_pd, len_stand, len_bad;
    const uint8_t *pd = roz_test_controller("g1_pd", &len_pd);
    const uint8_t *stand = roz_test_controller("g1_stand", &len_stand);
    const uint8_t *bad = roz_test_controller("bad_trap_verify", &len_bad);
    roz_port_t simport = roz_loopback_port(&sim, NULL, NULL);
    (void)st;

    assert_int_equal(roz_port_open(&simport, &roz_manifest_unitree_g1, NULL, err, sizeof err),
                     ROZ_OK);
    roz_buffer_init(&state_buf, state_buf_slots, ROZ_UNITREE_G1_N_STATES);
    roz_buffer_init(&cmd_buf, cmd_buf_slots, ROZ_UNITREE_G1_N_COMMANDS);
    atomic_store(&sim_stop, 0);
    atomic_store(&fresh_reads, 0u);
    atomic_store(&tick_writes, 0u);
    atomic_store(&sim_commands, 0u);
    assert_int_equal(pthread_create(&th, NULL, sim_main, NULL), 0);

    /* the port has no open op: nothing to open */
    roz_test_runtime_config(&cfg, &roz_manifest_unitree_g1,
                            (roz_port_t){ &threaded_ops, &state_buf, 0 }, NULL);
    cfg.clock = roz_clock_monotonic_ns;
    cfg.stale_ticks = 1000000; /* the simulator thread's pace is not the tick's */
    cfg.budget_ns = 500000000; /* sanitizers are slow; this test is about races */
    cfg.monitor_jitter = 0;
    roz_test_runtime_start(&rt, &cfg, "g1_pd");
    assert_int_equal(roz_runner_start(&runner, &rc, tick, NULL), ROZ_OK);

    int loads = 0, refused = 0;
    for (int round = 0; round < 12; round++) {
        sleep_ms(40);
        const uint8_t *w = round % 3 == 0 ? bad : (round % 3 == 1 ? stand : pd);
        size_t len = round % 3 == 0 ? len_bad : (round % 3 == 1 ? len_stand : len_pd);
        int r = roz_runtime_load(&rt, w, len, NULL);
        if (r == ROZ_OK)
            loads++;
        else if (r == ROZ_EVERIFY)
            refused++;
        if (round == 6)
            roz_runtime_estop(&rt);
        if (round == 8)
            assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    }
    /* after the last swap, the loop goes on until the tick has read 100 new
     * frames from the simulator's thread and the simulator has taken 100
     * commands from the tick's (a read that never reports a new frame, or a
     * command that never crosses, hangs here: 60 s the guard) */
    unsigned long long reads0 = atomic_load(&fresh_reads), cmds0 = atomic_load(&sim_commands);
    ROZ_TEST_WAIT(atomic_load(&fresh_reads) >= reads0 + 100u &&
                      atomic_load(&sim_commands) >= cmds0 + 100u,
                  sleep_ms(1), 60000);
    roz_runner_stop(&runner);
    roz_runner_join(&runner);
    atomic_store(&sim_stop, 1);
    pthread_join(th, NULL);

    print_message("ticks %llu, controller ticks %llu, loads %d, refused %d, swaps %llu\n",
                  (unsigned long long)runner.ticks,
                  (unsigned long long)RT_COUNT(&rt, controller_ticks), loads, refused,
                  (unsigned long long)RT_COUNT(&rt, swaps));
    assert_true(runner.ticks > 0);
    /* the controller drove on the frames read (the last load, g1_pd, took) */
    assert_true(RT_COUNT(&rt, controller_ticks) >= 100);
    assert_true(atomic_load(&tick_writes) >= atomic_load(&sim_commands));
    assert_true(refused > 0);
    assert_true(loads > 0);
    assert_int_equal(atomic_load(&sim_violations), 0);
    roz_runtime_deinit(&rt);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_threads_runtime_under_load))
