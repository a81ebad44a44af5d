/* SPDX-License-Identifier: Apache-2.0 */
/* No heap through the tick on the mujoco port: the G1 on the example stand
 * controller, every allocation of the process counted while it ticks (this
 * file defines malloc and its kin over glibc's own, so libmujoco's, a shared
 * library's, are seen too; test/ports/common/alloc_ticks.c does the same for
 * Cyclone's, around a port with threads of its own). */
#define _GNU_SOURCE
#include <errno.h>
#include <malloc.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "roz/builtin.h"
#include "roz/port/mujoco.h"
#include "roz/recorder.h"
#include "roz/runtime.h"
#include "support.h"

/* ---- every allocation of the process ------------------------------------------ */

void *__libc_malloc(size_t n);
void *__libc_calloc(size_t n, size_t size);
void *__libc_realloc(void *p, size_t n);
void *__libc_memalign(size_t align, size_t n);
void __libc_free(void *p);

static _Atomic int counting;
static _Atomic uint64_t allocations, frees, all_allocations;

static void count(void)
{
    atomic_fetch_add_explicit(&all_allocations, 1u, memory_order_relaxed);
    if (atomic_load_explicit(&counting, memory_order_relaxed))
        atomic_fetch_add_explicit(&allocations, 1u, memory_order_relaxed);
}

void *malloc(size_t n)
{
    count();
    return __libc_malloc(n);
}

void *calloc(size_t n, size_t size)
{
    count();
    return __libc_calloc(n, size);
}

void *realloc(void *p, size_t n)
{
    count();
    return __libc_realloc(p, n);
}

void *memalign(size_t align, size_t n)
{
    count();
    return __libc_memalign(align, n);
}

void *aligned_alloc(size_t align, size_t n)
{
    count();
    return __libc_memalign(align, n);
}

int posix_memalign(void **out, size_t align, size_t n)
{
    count();
    void *p = __libc_memalign(align, n);
    if (p == NULL)
        return ENOMEM;
    *out = p;
    return 0;
}

void free(void *p)
{
    if (p != NULL && atomic_load_explicit(&counting, memory_order_relaxed))
        atomic_fetch_add_explicit(&frees, 1u, memory_order_relaxed);
    __libc_free(p);
}

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
    uint64_t before = atomic_load(&all_allocations);
    /* a push and the gantry on the way: their paths count too */
    roz_param_t items[2] = { { "push", "0,40,0@torso_link@100:150" }, { "gantry", "300:350" } };
    roz_params_t params = { items, 2 };
    if (roz_port_open(&p, m, &params, err, sizeof err) != ROZ_OK)
        fail_msg("%s", err);
    uint64_t at_open = atomic_load(&all_allocations) - before;

    roz_runtime_config_t cfg;
    roz_test_clock_t clk = { 0, 1000 };
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = p;
    cfg.clock = roz_test_clock;
    cfg.clock_ctx = &clk;
    cfg.budget_ns = UINT64_MAX;
    cfg.monitor_jitter = 0;
    /* the recorder on: the tick copies the port's truth sample too (its
     * drain, which names the bodies, runs after the counted ticks) */
    static roz_recorder_t rec;
    static uint64_t ring[(4u << 20) / 8u];
    assert_int_equal(roz_recorder_init(&rec, m, ring, sizeof ring, 1), ROZ_OK);
    cfg.recorder = &rec;
    size_t len;
    const uint8_t *w = roz_test_controller("g1_stand", &len);
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_load(&rt, w, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    { int rc_ = roz_runtime_tick(&rt); (void)rc_; } /* the controller's swap-in, before counting */

    /* the counter itself sees an allocation */
    atomic_store(&allocations, 0u);
    atomic_store(&counting, 1);
    void *volatile probe = malloc(8);
    free(probe);
    atomic_store(&counting, 0);
    assert_int_equal(atomic_load(&allocations), 1);

    const int ticks = 500;
    atomic_store(&allocations, 0u);
    atomic_store(&frees, 0u);
    atomic_store(&counting, 1);
    for (int t = 0; t < ticks; t++)
        { int rc_ = roz_runtime_tick(&rt); (void)rc_; }
    atomic_store(&counting, 0);
    uint64_t a = atomic_load(&allocations), f = atomic_load(&frees);
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mujoco_alloc_none_in_the_tick),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
