/* SPDX-License-Identifier: Apache-2.0 */
/* No heap after start: malloc, calloc, realloc and free are wrapped at link
 * time (support_heap.h), which covers roz and the statically linked wasm3, and
 * counted over 100,000 ticks of the G1 PD controller (145 commands, 97 states)
 * and of the UR5 sine controller, with faults and their clearing between. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_heap.h"
#include "support_stats.h"
#include "support_runtime.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"
#include "support_thin.h"

/* ticks a run: under an emulator a tenth (support_thin.h) */
#define TICKS (100000 / ROZ_TEST_THIN(10))

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_recorder_t rec;
static uint64_t rec_storage[(1u << 20) / 8u];
static uint64_t drained;

static int count_record(void *ctx, const roz_record_t *r)
{
    (void)ctx;
    (void)r;
    drained++;
    return 0;
}

/* With @p record, the flight recorder is on, drained every 16 ticks (as an
 * idle loop would): neither the tick nor the drain allocates. */
static void run_rec(const roz_manifest_t *m, const char *controller, int ticks, int record)
{
    roz_runtime_config_t cfg;
    roz_test_clock_t clk = { 1, 100 };

    roz_test_loopback_config(&cfg, &lb, m, NULL, &clk);
    if (record) {
        assert_int_equal(roz_recorder_init(&rec, m, rec_storage, sizeof rec_storage, 1), ROZ_OK);
        cfg.recorder = &rec;
    }
    roz_test_runtime_start(&rt, &cfg, controller);
    roz_test_tick(&rt); /* the swap-in happens here */

    drained = 0;
    roz_heap_count_start();
    for (int t = 0; t < ticks; t++) {
        roz_test_tick(&rt);
        if (t == ticks / 2)
            roz_runtime_estop(&rt); /* a fault and its defaults, still no heap */
        if (record && t % 16 == 15)
            (void)roz_recorder_drain(&rec, count_record, NULL, 0);
    }
    if (record)
        (void)roz_recorder_drain(&rec, count_record, NULL, 0);
    roz_heap_count_stop();
    if (record) {
        /* every tick recorded (the swap-in tick too), none dropped */
        assert_int_equal(roz_recorder_dropped(&rec), 0);
        assert_int_equal(drained, (uint64_t)ticks + 1u); /* and the swap-in tick */
    }
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    assert_true(RT_COUNT(&rt, controller_ticks) >= (uint64_t)ticks / 2);
    print_message("%s: %d ticks, %llu allocations, %llu frees\n", controller, ticks,
                  (unsigned long long)roz_heap_allocations(),
                  (unsigned long long)roz_heap_frees());
    assert_int_equal(roz_heap_allocations(), 0);
    assert_int_equal(roz_heap_frees(), 0);
    assert_int_equal(roz_loopback_counters(&lb).violations, 0);
    roz_runtime_deinit(&rt);
}

static void run(const roz_manifest_t *m, const char *controller, int ticks)
{
    run_rec(m, controller, ticks, 0);
}

static void test_alloc_g1_pd_recorded(void **st)
{
    (void)st;
    run_rec(&roz_manifest_unitree_g1, "g1_pd", TICKS, 1);
}

static void test_alloc_g1_pd(void **st)
{
    (void)st;
    run(&roz_manifest_unitree_g1, "g1_pd", TICKS);
}

static void test_alloc_ur5_sine(void **st)
{
    (void)st;
    run(&roz_manifest_ur5, "sine", TICKS);
}

/* The deploy sequence through every stage (zero, the move, the hold, the
 * controller behind the hand-over's gain hold, back to the stand, the
 * damping stop) on the G1: no heap in the tick either. */
static void test_alloc_g1_stages(void **st)
{
    static double stand[ROZ_CFG_MAX_COMMANDS];
    const roz_manifest_t *m = &roz_manifest_unitree_g1;
    roz_runtime_config_t cfg;
    roz_test_clock_t clk = { 1, 100 };
    char err[128];
    size_t len;
    (void)st;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        stand[i] = c->type == ROZ_IF_STIFFNESS ? 100.0 : c->type == ROZ_IF_DAMPING ? 2.0 : 0.0;
        stand[i] = stand[i] < c->min ? c->min : stand[i] > c->max ? c->max : stand[i];
    }
    roz_stages_config_t sc = { stand, 0.5, 8.0, -1, -1, -1, -1 };
    roz_test_loopback_config(&cfg, &lb, m, NULL, &clk);
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_stages_set(&rt, &sc, err, sizeof err), ROZ_OK);
    const uint8_t *w = roz_test_controller("g1_pd", &len);
    assert_int_equal(roz_runtime_load(&rt, w, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    static const roz_stage_t asks[] = { ROZ_STAGE_MOVE, ROZ_STAGE_RUN, ROZ_STAGE_MOVE,
                                        ROZ_STAGE_STOP, ROZ_STAGE_ZERO };
    roz_heap_count_start();
    for (int t = 0; t < 10000; t++) {
        if (t % 2000 == 0)
            assert_int_equal(roz_runtime_stage_request(&rt, asks[t / 2000]), ROZ_OK);
        roz_test_tick(&rt);
    }
    roz_heap_count_stop();
    assert_int_equal(roz_runtime_stages_counters(&rt)->transitions, 7);
    assert_int_equal(roz_runtime_stages_counters(&rt)->handovers, 1);
    assert_int_equal(roz_heap_allocations(), 0);
    assert_int_equal(roz_heap_frees(), 0);
    assert_int_equal(roz_loopback_counters(&lb).violations, 0);
    roz_runtime_deinit(&rt);
}

/* The wrapper is live: loading a controller does allocate (outside the tick). */
static void test_alloc_counter_works(void **st)
{
    size_t len;
    const uint8_t *w = roz_test_controller("hold", &len);
    roz_controller_t c;
    roz_abi_t abi;
    double target[ROZ_CFG_MAX_COMMANDS];
    (void)st;
    roz_controller_init(&c);
    roz_abi_init(&abi, &roz_manifest_ur5, target, NULL);
    roz_heap_count_start();
    assert_int_equal(roz_controller_load(&c, w, len, &abi), ROZ_OK);
    roz_heap_count_stop();
    assert_true(roz_heap_allocations() > 0);
    roz_controller_unload(&c);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_alloc_counter_works),
              cmocka_unit_test(test_alloc_g1_pd),
              cmocka_unit_test(test_alloc_ur5_sine),
              cmocka_unit_test(test_alloc_g1_stages),
              cmocka_unit_test(test_alloc_g1_pd_recorded))
