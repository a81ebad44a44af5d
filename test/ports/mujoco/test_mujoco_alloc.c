/* SPDX-License-Identifier: Apache-2.0 */
/* No heap through the tick on the mujoco port: the G1 on the example stand
 * controller, every allocation of the process counted while it ticks
 * (libc_heap.h: libmujoco's, a shared library's, are seen too). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "libc_heap.h"
#include "roz/builtin.h"
#include "roz/port/mujoco.h"
#include "roz/recorder.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_runtime.h"

/* ---- the run -------------------------------------------------------------------- */

static roz_mujoco_t mj;
static roz_runtime_t rt;

static int truths;

static int truth_seen(void *ctx, const roz_record_t *r)
{
    (void)ctx;
    truths += r->truth != NULL && r->truth->floating == 1u && r->truth->pos[2] > 0.5;
    return 0;
}

static void test_mujoco_alloc_none_in_the_tick(void **state)
{
    (void)state;
    const roz_manifest_t *m = roz_builtin_find("unitree_g1");
    assert_non_null(m);
    roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
    char err[512] = "";
    uint64_t before = roz_libc_heap_counts().total;
    /* a push and the gantry on the way: their paths count too */
    roz_param_t items[2] = { { "push", "0,40,0@torso_link@100:150" }, { "gantry", "300:350" } };
    roz_params_t params = { items, 2 };
    if (roz_port_open(&p, m, &params, err, sizeof err) != ROZ_OK)
        fail_msg("%s", err);
    uint64_t at_open = roz_libc_heap_counts().total - before;

    roz_runtime_config_t cfg;
    roz_test_clock_t clk;
    roz_test_physics_config(&cfg, m, p, &clk);
    /* the recorder on: the tick copies the port's truth sample too (its
     * drain, which names the bodies, runs after the counted ticks) */
    static roz_recorder_t rec;
    static uint64_t ring[(4u << 20) / 8u];
    assert_int_equal(roz_recorder_init(&rec, m, ring, sizeof ring, 1), ROZ_OK);
    cfg.recorder = &rec;
    roz_test_runtime_start(&rt, &cfg, "g1_stand");
    { int rc_ = roz_runtime_tick(&rt); (void)rc_; } /* the controller's swap-in, before counting */

    /* the counter itself sees an allocation */
    roz_libc_heap_reset();
    roz_libc_heap_count_all(1);
    void *volatile probe = malloc(8);
    free(probe);
    roz_libc_heap_count_all(0);
    assert_int_equal(roz_libc_heap_counts().allocations, 1);

    const int ticks = 500;
    roz_libc_heap_reset();
    roz_libc_heap_count_all(1);
    for (int t = 0; t < ticks; t++)
        { int rc_ = roz_runtime_tick(&rt); (void)rc_; }
    roz_libc_heap_count_all(0);
    roz_libc_heap_counts_t heap = roz_libc_heap_counts();
    uint64_t a = heap.allocations, f = heap.frees;
    roz_mujoco_base_t b;
    roz_mujoco_base(&mj, &b);
    print_message("G1 on mujoco: open made %llu heap calls; %d ticks (%llu physics steps): %llu "
                  "allocations, %llu frees\n", (unsigned long long)at_open, ticks,
                  (unsigned long long)b.steps, (unsigned long long)a, (unsigned long long)f);
    assert_int_equal(a, 0);
    assert_int_equal(f, 0);
    assert_true(b.steps >= 2u * ticks);
    assert_true(at_open > 0);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(roz_recorder_dropped(&rec), 0);
    assert_int_equal(roz_recorder_drain(&rec, truth_seen, NULL, 0), ticks + 1);
    assert_int_equal(truths, ticks + 1);
    roz_runtime_deinit(&rt);
    roz_port_close(&p);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_mujoco_alloc_none_in_the_tick))
