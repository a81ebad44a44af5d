/* SPDX-License-Identifier: Apache-2.0 */
/* The per-tick budget: fuel (deterministic work units, charged before the
 * work runs; test_fuel.c pins the unit) and a wall-clock deadline read every
 * ROZ_CFG_DEADLINE_CHECK_UNITS units. A call-free infinite loop,
 * an import called forever and infinite recursion all stop within the budget;
 * a slow but finite controller passes just under its budget and stops just
 * over it, at the same fuel on every run; the fault latches, the safe defaults
 * go out, and the loop keeps ticking. And the C stack: a 120,000-op
 * straight-line function and an endless recursion run on a thread with a
 * 512 KiB stack, in every build (wasm3's ops must chain by tail calls, and
 * roz's guard must bound the recursion). And the deadline on the tick
 * thread's CPU time: a thread competing for the tick's CPU never makes a
 * controller well inside its deadline overrun, and an endless loop still
 * does. */
#define _GNU_SOURCE /* pthread_setaffinity_np: a competitor on the tick's CPU */
/* white-box in part: reads the runtime's controller slots (a trapped
 * instance must never run again), which no public function exposes */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/hal/clock.h"
#include "roz/runner.h"
#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support_stats.h"
#include "support.h"
#include "support_runtime.h"
#include "ur5_manifest.h"

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_test_clock_t clk;

/* A still clock: the deadline never passes, so only fuel can stop a call. */
static void start(uint64_t fuel, uint64_t clock_step)
{
    roz_runtime_config_t cfg;

    clk = (roz_test_clock_t){ 1000, clock_step };
    roz_test_loopback_config(&cfg, &lb, &roz_manifest_ur5, NULL, &clk);
    cfg.fuel_per_tick = fuel;
    roz_test_runtime_start(&rt, &cfg, NULL);
}

static int load(const char *name, roz_verify_report_t *rep)
{
    size_t len;
    const uint8_t *w = roz_test_controller(name, &len);
    return roz_runtime_load(&rt, w, len, rep);
}

static int teardown(void **st)
{
    (void)st;
    roz_runtime_deinit(&rt);
    return 0;
}

static void test_budget_default_per_rate(void **st)
{
    (void)st;
    start(0, 0);
    assert_int_equal(roz_runtime_config(&rt)->fuel_per_tick, ROZ_CFG_FUEL_PER_SECOND / 100);
    assert_int_equal(roz_runtime_config(&rt)->budget_ns, 5000000); /* half of the 10 ms period */
}

/* Each endless controller stops at exactly the fuel budget, at tick 150. */
static void test_budget_endless_controllers_stop(void **st)
{
    static const struct { const char *name; unsigned fault; const char *msg; } cases[] = {
        { "bad_infinite_loop", ROZ_FAULT_OVERRUN, "fuel exhausted at tick 150: 5002 units, budget 5000" },
        /* its loop body's run costs 12 units (call 9, drop, br back 2): the first it cannot pay
         * leaves it at 5003 */
        { "bad_import_loop", ROZ_FAULT_OVERRUN, "fuel exhausted at tick 150: 5003 units, budget 5000" },
        /* recursion: each call costs fuel; wasm3's stack check may come first */
        { "bad_recursion", ROZ_FAULT_OVERRUN | ROZ_FAULT_TRAP, "at tick 150" },
    };
    (void)st;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        print_message("case %s\n", cases[i].name);
        start(5000, 0);
        assert_int_equal(load(cases[i].name, NULL), ROZ_OK);
        for (int t = 0; t < 151; t++)
            roz_test_tick(&rt);
        unsigned f = roz_runtime_faults(&rt);
        assert_true(f != 0 && (f & ~cases[i].fault) == 0);
        if (strstr(roz_runtime_fault_message(&rt), cases[i].msg) == NULL)
            fail_msg("%s: \"%s\" lacks \"%s\"", cases[i].name, roz_runtime_fault_message(&rt),
                     cases[i].msg);
        /* the loop keeps going: defaults out every tick, nothing unsafe */
        for (int t = 0; t < 50; t++)
            assert_int_equal(roz_runtime_tick(&rt), ROZ_EFAULT);
        assert_int_equal(RT_COUNT(&rt, writes), 201);
        assert_int_equal(roz_loopback_counters(&lb).violations, 0);
        assert_true(roz_runtime_last_commands(&rt)[0] == 0.0);
        roz_runtime_deinit(&rt);
    }
}

/* Just under and just over: the same controller, the same fuel, every run. */
static void test_budget_just_under_and_over(void **st)
{
    roz_verify_report_t rep, rep2;
    (void)st;
    start(UINT64_MAX, 0); /* unmetered: measure */
    assert_int_equal(load("bad_busy", &rep), ROZ_OK);
    uint64_t need = rep.fuel[0];
    print_message("busy.wat uses %llu units per tick\n", (unsigned long long)need);
    assert_true(need >= 1000);
    for (int t = 0; t < ROZ_RUNTIME_VERIFY_TICKS; t++)
        assert_int_equal(rep.fuel[t], need); /* same every tick */
    roz_runtime_deinit(&rt);

    /* exactly enough: verifies and runs */
    start(need, 0);
    assert_int_equal(load("bad_busy", &rep2), ROZ_OK);
    assert_int_equal(rep2.max_fuel, need);
    assert_int_equal(rep2.fuel_budget, need);
    for (int t = 0; t < 300; t++)
        roz_test_tick(&rt);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(RT_COUNT(&rt, max_fuel), need);
    roz_runtime_deinit(&rt);

    /* one unit short: verification refuses it, naming the fuel */
    start(need - 1, 0);
    assert_int_equal(load("bad_busy", &rep2), ROZ_EVERIFY);
    assert_non_null(strstr(roz_runtime_error(&rt), "fuel exhausted at tick 0"));
    assert_int_equal(rep2.fuel[0], need); /* stopped at the first unit over */
}

/* A controller stopped by its budget is rebuilt on clear, never reused. */
static void test_budget_rebuild_after_overrun(void **st)
{
    (void)st;
    start(5000, 0);
    assert_int_equal(load("bad_infinite_loop", NULL), ROZ_OK);
    for (int t = 0; t < 151; t++)
        roz_test_tick(&rt);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_OVERRUN);
    int active = atomic_load(&rt.active);
    assert_true(rt.slot[active].ctrl.spent);
    assert_int_equal(roz_controller_process(&rt.slot[active].ctrl, 0), ROZ_ESTATE);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    assert_int_equal(RT_COUNT(&rt, rebuilds), 1);
    roz_test_tick(&rt);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_not_equal(atomic_load(&rt.active), active);
    assert_true(roz_runtime_last_commands(&rt)[0] > 0.0); /* running again from tick 0 */
}

/* The wall-clock deadline, checked at the same points as the fuel. */
static void test_budget_deadline(void **st)
{
    (void)st;
    start(UINT64_MAX, 1000); /* unmetered fuel; the clock advances 1 us per reading */
    assert_int_equal(load("bad_infinite_loop", NULL), ROZ_OK);
    for (int t = 0; t < 151; t++)
        roz_test_tick(&rt);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_OVERRUN);
    assert_non_null(strstr(roz_runtime_fault_message(&rt), "deadline passed at tick 150"));
}

/* On the periodic runner with the real clock: the endless loop is stopped
 * every time and the runner completes its ticks. Figures are printed, not
 * asserted. */
static roz_runner_t runner;

static int tick(void *ctx)
{
    (void)ctx;
    roz_test_tick(&rt);
    return 0;
}

static void test_budget_loop_keeps_its_period(void **st)
{
    roz_runtime_config_t cfg;
    roz_runner_config_t rc = { .period_ns = 10000000, .max_ticks = 300 };
    (void)st;
    roz_test_loopback_config(&cfg, &lb, &roz_manifest_ur5, NULL, NULL);
    cfg.clock = roz_clock_monotonic_ns;
    cfg.fuel_per_tick = UINT64_MAX; /* the deadline alone must stop it */
    roz_test_runtime_start(&rt, &cfg, "bad_infinite_loop");
    assert_int_equal(roz_runner_start(&runner, &rc, tick, NULL), ROZ_OK);
    roz_runner_join(&runner);
    assert_int_equal(runner.ticks, 300);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_OVERRUN);
    assert_int_equal(RT_COUNT(&rt, writes), 300);
    assert_int_equal(roz_loopback_counters(&lb).violations, 0);
    print_message("300 ticks at 100 Hz: %llu deadlines missed, tick max %.1f us, "
                  "wake-up jitter max %.1f us\n",
                  (unsigned long long)runner.missed, roz_test_monitor(roz_runtime_monitor(&rt), ROZ_MON_TICK).max_ns / 1e3,
                  roz_test_monitor(&runner.monitor, ROZ_MON_JITTER).max_ns / 1e3);
}

/* ---- the C stack ------------------------------------------------------------ */

enum { STRAIGHT_OPS = 120000 };
static uint8_t straight[ROZ_CFG_WASM_MAX_MODULE_BYTES];

static size_t put_leb(uint8_t *p, uint32_t v)
{
    size_t n = 0;
    do {
        uint8_t b = v & 0x7fu;
        v >>= 7;
        p[n++] = (uint8_t)(b | (v != 0u ? 0x80u : 0u));
    } while (v != 0u);
    return n;
}

/* (func (export "process") (param $t i64)) whose body is STRAIGHT_OPS times
 * (local.set $t (i64.add (local.get $t) (i64.const 1))): no call, no loop. */
static size_t straight_module(void)
{
    static const uint8_t head[] = { 0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00,
                                    0x01, 0x05, 0x01, 0x60, 0x01, 0x7e, 0x00, /* type */
                                    0x03, 0x02, 0x01, 0x00,                   /* func */
                                    0x07, 0x0b, 0x01, 0x07, 'p', 'r', 'o', 'c', 'e', 's', 's',
                                    0x00, 0x00 };                             /* export */
    static const uint8_t op[] = { 0x20, 0x00, 0x42, 0x01, 0x7c, 0x21, 0x00 };
    uint32_t body = 1 + STRAIGHT_OPS * (uint32_t)sizeof op + 1; /* no locals, ops, end */
    uint8_t leb[5];
    size_t n = 0, lb_body = put_leb(leb, body);
    uint32_t section = 1 + (uint32_t)lb_body + body;

    memcpy(straight, head, sizeof head);
    n = sizeof head;
    straight[n++] = 0x0a; /* code */
    n += put_leb(&straight[n], section);
    straight[n++] = 0x01;
    n += put_leb(&straight[n], body);
    straight[n++] = 0x00;
    for (int i = 0; i < STRAIGHT_OPS; i++, n += sizeof op)
        memcpy(&straight[n], op, sizeof op);
    straight[n++] = 0x0b;
    return n;
}

static size_t straight_stack, recursion_stack;
static int straight_rc, recursion_rc;

static void *small_stack_thread(void *arg)
{
    size_t len, n = straight_module();
    const uint8_t *rec = roz_test_controller("bad_recursion", &len);
    (void)arg;
    start(UINT64_MAX, 0); /* unmetered: only the stacks bound it */
    straight_rc = roz_runtime_load(&rt, straight, n, NULL);
    for (int t = 0; t < 5 && straight_rc == ROZ_OK; t++)
        straight_rc = roz_runtime_tick(&rt);
    straight_stack = (size_t)RT_COUNT(&rt, max_stack);
    roz_runtime_deinit(&rt);
    start(UINT64_MAX, 0);
    recursion_rc = roz_runtime_load(&rt, rec, len, NULL);
    for (int t = 0; t < 160 && recursion_rc == ROZ_OK; t++) /* it recurses at tick 150 */
        roz_test_tick(&rt);
    recursion_stack = (size_t)RT_COUNT(&rt, max_stack);
    return NULL;
}

static void test_budget_stack_on_a_small_thread(void **st)
{
    pthread_attr_t attr;
    pthread_t th;
    (void)st;
    assert_int_equal(pthread_attr_init(&attr), 0);
    assert_int_equal(pthread_attr_setstacksize(&attr, 512 * 1024), 0);
    assert_int_equal(pthread_create(&th, &attr, small_stack_thread, NULL), 0);
    assert_int_equal(pthread_join(th, NULL), 0);
    pthread_attr_destroy(&attr);
    print_message("straight line of %d ops: %zu bytes of C stack; endless recursion: %zu "
                  "bytes, then \"%s\"\n", STRAIGHT_OPS, straight_stack, recursion_stack,
                  roz_runtime_fault_message(&rt));
    assert_int_equal(straight_rc, ROZ_OK);
    assert_true(straight_stack < 16384);
    assert_int_equal(recursion_rc, ROZ_OK);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_TRAP);
    assert_true(strstr(roz_runtime_fault_message(&rt), "stack") != NULL);
    assert_true(recursion_stack <= ROZ_CFG_NATIVE_STACK_BYTES + 4096);
}

/* A thread that spins on the tick's CPU until told to stop. */
static atomic_int compete_stop;

static void *compete(void *arg)
{
    (void)arg;
    while (!atomic_load_explicit(&compete_stop, memory_order_relaxed))
        ;
    return NULL;
}

/* Ticks @p ctrl with a deadline of @p budget_ns and the fuel off, on this
 * thread pinned to one CPU with a competitor pinned there too; the deadline
 * on the thread's CPU time (@p cpu_time) or the wall clock. Returns the
 * ticks run before the first fault (at most @p ticks); *faults the faults
 * then. */
static int contended(const char *ctrl, int cpu_time, uint64_t budget_ns, int ticks,
                     unsigned *faults)
{
    roz_runtime_config_t cfg;
    cpu_set_t was, one;
    pthread_t th;
    int cpu = 0, t = 0;

    assert_int_equal(pthread_getaffinity_np(pthread_self(), sizeof was, &was), 0);
    while (cpu < CPU_SETSIZE && !CPU_ISSET(cpu, &was))
        cpu++;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    roz_test_loopback_config(&cfg, &lb, &roz_manifest_ur5, NULL, NULL);
    cfg.clock = roz_clock_monotonic_ns;
    if (cpu_time)
        cfg.deadline_clock = roz_clock_thread_cpu_ns;
    cfg.fuel_per_tick = ROZ_BUDGET_OFF; /* the deadline alone */
    cfg.budget_ns = budget_ns;
    roz_test_runtime_start(&rt, &cfg, ctrl);
    assert_int_equal(pthread_setaffinity_np(pthread_self(), sizeof one, &one), 0);
    atomic_store(&compete_stop, 0);
    assert_int_equal(pthread_create(&th, NULL, compete, NULL), 0);
    assert_int_equal(pthread_setaffinity_np(th, sizeof one, &one), 0);
    for (; t < ticks; t++) {
        roz_test_tick(&rt);
        if (roz_runtime_faults(&rt) != 0)
            break;
    }
    atomic_store(&compete_stop, 1);
    pthread_join(th, NULL);
    assert_int_equal(pthread_setaffinity_np(pthread_self(), sizeof was, &was), 0);
    *faults = roz_runtime_faults(&rt);
    return t;
}

/* The deadline on the thread's CPU time counts the controller, not the
 * time the scheduler gives a competitor: what the code decides, asserted
 * with a budget far from what the controller costs (busy.wat: a few
 * microseconds a tick, a few hundred under a sanitizer; the budget 50 ms,
 * longer than any scheduler slice), so no load of the machine changes the
 * verdict; an endless loop is over any budget. */
static void test_budget_deadline_counts_the_controller(void **st)
{
    unsigned faults;
    (void)st;
    int ran = contended("bad_busy", 1, 50000000, 20000, &faults);
    if (faults != 0)
        print_message("%s\n", roz_runtime_fault_message(&rt));
    assert_int_equal(faults, 0);
    assert_int_equal(ran, 20000);
    roz_runtime_deinit(&rt);
    /* for comparison, not asserted (it depends on the scheduler): 500 us on
     * the wall clock, where a competitor's slice counts */
    ran = contended("bad_busy", 0, 500000, 20000, &faults);
    print_message("500 us on the wall clock: %s after %d ticks\n",
                  faults != 0 ? "an overrun latched" : "no fault", ran);
    roz_runtime_deinit(&rt);
    /* really over its deadline: stopped on the thread's CPU time too */
    ran = contended("bad_infinite_loop", 1, 50000000, 20000, &faults);
    assert_int_equal(faults, ROZ_FAULT_OVERRUN);
    assert_int_equal(ran, 150); /* it loops from tick 150 on */
    assert_non_null(strstr(roz_runtime_fault_message(&rt), "deadline passed at tick 150"));
}

ROZ_TEST_MAIN(cmocka_unit_test_teardown(test_budget_default_per_rate, teardown),
              cmocka_unit_test(test_budget_endless_controllers_stop),
              cmocka_unit_test_teardown(test_budget_just_under_and_over, teardown),
              cmocka_unit_test_teardown(test_budget_rebuild_after_overrun, teardown),
              cmocka_unit_test_teardown(test_budget_deadline, teardown),
              cmocka_unit_test_teardown(test_budget_loop_keeps_its_period, teardown),
              cmocka_unit_test_teardown(test_budget_stack_on_a_small_thread, teardown),
              cmocka_unit_test_teardown(test_budget_deadline_counts_the_controller, teardown))
