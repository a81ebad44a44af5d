/* SPDX-License-Identifier: Apache-2.0 */
#define _GNU_SOURCE
#include "alloc_ticks.h"

#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdlib.h>
#include <time.h>

#include <cmocka.h>

#include "libc_heap.h"
#include "roz/error.h"
#include "roz/runtime.h"
#include "support.h"

/* ---- the run -------------------------------------------------------------------- */

static roz_runtime_t rt;

typedef struct {
    int         ticks;
    _Atomic int done;
} run_t;

static void *tick_main(void *arg)
{
    run_t *r = arg;
    int rc = roz_runtime_tick(&rt); /* the controller's swap-in, before counting */
    roz_libc_heap_count_thread(1);
    for (int t = 0; t < r->ticks; t++) {
        rc = roz_runtime_tick(&rt); /* ROZ_EFAULT once a fault latched */
        atomic_store_explicit(&r->done, t + 1, memory_order_release);
    }
    roz_libc_heap_count_thread(0);
    (void)rc;
    return NULL;
}

static void sleep_1ms(void)
{
    struct timespec ts = { 0, 1000000L };
    while (nanosleep(&ts, &ts) != 0)
        ;
}

void roz_alloc_run(const roz_alloc_case_t *c)
{
    static run_t r;
    roz_runtime_config_t cfg;
    roz_alloc_port_counts_t c0, c1;
    pthread_t th;
    size_t len;

    const uint8_t *w = roz_test_controller(c->controller, &len);
    roz_runtime_config_default(&cfg);
    cfg.manifest = c->m;
    cfg.port = c->port;
    cfg.stale_ticks = 10u * (uint32_t)c->ticks; /* back to back: most reads are not fresh */
    cfg.monitor_jitter = 0;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_load(&rt, w, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    /* the robot's samples arrive */
    for (int i = 0; i < 10000; i++) {
        c->counters(&c0);
        if (c0.received >= 10)
            break;
        sleep_1ms();
    }
    assert_true(c0.received >= 10);

    /* the counters themselves: an allocation made while ticking is seen */
    roz_libc_heap_reset();
    roz_libc_heap_count_thread(1);
    void *volatile probe = malloc(8);
    free(probe);
    roz_libc_heap_count_thread(0);
    assert_int_equal(roz_libc_heap_counts().allocations, 1);
    assert_int_equal(roz_libc_heap_counts().frees, 1);

    r.ticks = c->ticks;
    atomic_store(&r.done, 0);
    roz_libc_heap_reset();
    assert_int_equal(pthread_create(&th, NULL, tick_main, &r), 0);
    while (atomic_load_explicit(&r.done, memory_order_acquire) < c->ticks / 2)
        sleep_1ms();
    c->midway();
    assert_int_equal(pthread_join(th, NULL), 0);

    roz_libc_heap_counts_t heap = roz_libc_heap_counts();
    uint64_t allocs = heap.allocations, frees = heap.frees, others = heap.others;
    c->counters(&c1);
    print_message("%s through %s: %d ticks: %llu allocations and %llu frees on the tick thread; "
                  "%llu elsewhere (Cyclone's threads, the test); %llu frames in, %llu "
                  "published\n",
                  c->m->robot_id, c->port.ops->name, c->ticks, (unsigned long long)allocs,
                  (unsigned long long)frees, (unsigned long long)others,
                  (unsigned long long)(c1.frames - c0.frames), (unsigned long long)c1.published);
    assert_int_equal(allocs, 0);
    assert_int_equal(frees, 0);
    /* the port was busy meanwhile, and so was Cyclone */
    assert_true(c1.frames - c0.frames > 10);
    assert_true(c1.writes >= (uint64_t)c->ticks);
    assert_true(c1.published > 100);
    assert_true(others > 0);
    roz_runtime_stats_t rs;
    assert_int_equal(roz_runtime_stats(&rt, &rs), ROZ_OK);
    assert_true(rs.runtime.controller_ticks > (uint64_t)c->ticks / 4);
    assert_true(roz_runtime_faults(&rt) & c->fault);
    roz_runtime_deinit(&rt);
}
