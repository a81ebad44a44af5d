/* SPDX-License-Identifier: Apache-2.0 */
/* Fuel is work done (docs/budget.md). The modules are WAT written here and
 * assembled with wabt's wat2wasm (support_wat.h). The tests
 * prove that
 *  - the unit is what roz/controller.h says: exact fuel for small bodies
 *    (one unit an instruction, a call 8 more, a loop entry 6 more, a bulk
 *    memory op 2 more and one unit per 16 bytes, as for the locals and
 *    constants a called function sets up), the same on every run;
 *  - a loop whose body is 60,000 straight-line instructions is stopped by a
 *    100,000-unit budget in its second iteration (the old meter counted one
 *    unit per back-edge and let it run 6 billion instructions);
 *  - memory.fill pays for its bytes before it runs: 1 MiB fills stop at the
 *    first one the budget cannot pay, and one fill larger than the whole
 *    budget never starts;
 *  - with fuel off the deadline stops an endless loop after a bounded amount
 *    of work: the clock is read once every ROZ_CFG_DEADLINE_CHECK_UNITS;
 *  - a budget of 0 is refused, never "unmetered", and so is a runtime whose
 *    default fuel per tick would round to 0;
 *  - verification judges by fuel, not by the loader's clock: a loader clock
 *    that jumps 10 ms a reading does not refuse a good controller;
 *  - the C stack is checked at loop entry: a recursion through nested loops
 *    stops within a frame of ROZ_CFG_NATIVE_STACK_BYTES. */
#define _POSIX_C_SOURCE 200809L
/* white-box: this test reads the private fields of the module it tests */
#define ROZ_PRIVATE_ACCESS
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "roz/abi.h"
#include "roz/controller.h"
#include "roz/module.h"
#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_runtime.h"
#include "support_wat.h"
#include "ur5_manifest.h"

/* ---- modules from WAT ------------------------------------------------------- */

static char text[1536 * 1024];
static uint8_t wasm[1024 * 1024];

/* A module: the ABI imports roz's tests use, `decls`, and process(). */
static size_t module(const char *decls, const char *body)
{
    snprintf(text, sizeof text,
             "(module\n"
             " (import \"math\" \"sin\" (func $sin (param f64) (result f64)))\n"
             " (import \"command\" \"set\" (func $set (param i32 f64) (result i32)))\n"
             " (import \"math\" \"cos\" (func $cos (param f64) (result f64)))\n"
             " (import \"timing\" \"now_ns\" (func $now (result i64)))\n"
             " (import \"timing\" \"sim_time_ns\" (func $sim (result i64)))\n"
             " %s\n"
             " (func (export \"process\") (param $tick i64) (local $i i32)\n%s))\n",
             decls, body);
    return roz_test_wat(text, wasm, sizeof wasm);
}

static roz_controller_t ctl;
static roz_abi_t abi;
static double state[ROZ_CFG_MAX_STATES];
static double targets[ROZ_CFG_MAX_COMMANDS];

static void load(size_t len, uint64_t fuel, uint64_t deadline_ns, roz_clock_fn clock, void *ctx)
{
    roz_budget_t b = { fuel, deadline_ns, clock, ctx };
    roz_controller_init(&ctl);
    roz_abi_init(&abi, &roz_manifest_ur5, targets, NULL);
    roz_abi_begin_tick(&abi, 0, state);
    if (roz_controller_load(&ctl, wasm, len, &abi) != ROZ_OK)
        fail_msg("load: %s", roz_controller_error(&ctl));
    assert_int_equal(roz_controller_set_budget(&ctl, &b), ROZ_OK);
}

/* Fuel one call of process() uses, unmetered, loaded afresh each time. */
static uint64_t fuel_of(const char *decls, const char *body)
{
    size_t len = module(decls, body);
    load(len, ROZ_BUDGET_OFF, ROZ_BUDGET_OFF, NULL, NULL);
    assert_int_equal(roz_controller_process(&ctl, 0), ROZ_OK);
    uint64_t used = roz_controller_fuel_used(&ctl);
    assert_int_equal(roz_controller_process(&ctl, 1), ROZ_OK);
    assert_int_equal(roz_controller_fuel_used(&ctl), used); /* the same on every call */
    roz_controller_unload(&ctl);
    return used;
}

static int teardown(void **st)
{
    (void)st;
    roz_controller_unload(&ctl);
    return 0;
}

/* ---- the unit ----------------------------------------------------------------- */

static void test_fuel_unit(void **st)
{
    (void)st;
    /* the body's end */
    assert_int_equal(fuel_of("", ""), 1);
    assert_int_equal(fuel_of("", "(nop) (nop) (nop)"), 4);
    /* f64.const, call (1 + 8), drop, end: a call does not end the run; sin's
     * own work on top (test_fuel_imports) */
    assert_int_equal(fuel_of("", "(drop (call $sin (f64.const 1)))"), 12 + 32);
    /* a callee with 4 i64 locals zeroes 32 bytes (2 units) and runs its end:
     * call (9), end (1), callee (2 + 1) */
    assert_int_equal(fuel_of("(func $f (local i64 i64 i64 i64))", "(call $f)"), 13);
    /* three constants, the fill (1 + 2), end, and 1600 / 16; process()'s
     * frame (its i32 local and the three constants, 16 bytes) 1 */
    assert_int_equal(fuel_of("(memory 1)",
                             "(memory.fill (i32.const 0) (i32.const 7) (i32.const 1600))"),
                     7 + 100 + 1);
    assert_int_equal(fuel_of("(memory 1)",
                             "(memory.copy (i32.const 0) (i32.const 4096) (i32.const 3200))"),
                     7 + 200 + 1);
    /* a loop entered once (1 + 6); its body's run, 8 instructions, 1 more
     * for the br_if back to the loop's start and the loop's end (a br_if
     * does not end a run), paid 10 times; the body's end (process()'s
     * frame, its local and two i32 constants, is 12 bytes: less than a
     * unit) */
    assert_int_equal(fuel_of("", "(loop $l\n"
                                 "  (local.set $i (i32.add (local.get $i) (i32.const 1)))\n"
                                 "  (br_if $l (i32.lt_u (local.get $i) (i32.const 10))))"),
                     7 + 10 * 10 + 1);
    /* both arms of an if pay for what they run: i32.const, if | const, drop,
     * else | end */
    uint64_t then_arm = fuel_of("", "(if (i32.const 1) (then (drop (i32.const 5))) "
                                    "(else (drop (i32.const 6)) (drop (i32.const 7))))");
    uint64_t else_arm = fuel_of("", "(if (i32.const 0) (then (drop (i32.const 5))) "
                                    "(else (drop (i32.const 6)) (drop (i32.const 7))))");
    print_message("if: then arm %llu units, else arm %llu\n", (unsigned long long)then_arm,
                  (unsigned long long)else_arm);
    assert_true(else_arm > then_arm);
}

/* ---- imports that do more than a call's work ------------------------------------- */

/* Charged before the work, in proportion to its worst case (bench/fuel's
 * host_* rows): sin and cos 32 units more than a call, 96 more again from
 * |x| = 2^24 on (the range reduction through 192 bits of 2/pi: 57 ns for
 * what 11 units stood for before), timing.now_ns 48 (the host's clock);
 * timing.sim_time_ns is a call's. The same on every target. */
static void test_fuel_imports(void **st)
{
    (void)st;
    /* each against the same body without the call (the frame's constants
     * cost the same): the call's 1 + 8 units and the import's own */
    static const struct { const char *fn, *arg; uint64_t own; } cases[] = {
        { "$sin", "1", 32 },           { "$sin", "-16777215", 32 },
        { "$sin", "16777216", 32 + 96 }, { "$sin", "1e22", 32 + 96 },
        { "$cos", "-3e300", 32 + 96 },   { "$cos", "0.5", 32 },
        { "$cos", "inf", 32 + 96 },      { "$sin", "nan", 32 + 96 },
    };
    char body[128], base[128];
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(body, sizeof body, "(drop (call %s (f64.const %s)))", cases[i].fn, cases[i].arg);
        snprintf(base, sizeof base, "(drop (f64.const %s))", cases[i].arg);
        uint64_t got = fuel_of("", body) - fuel_of("", base);
        if (got != 9 + cases[i].own)
            fail_msg("%s: %llu units more than without the call, want %llu", body,
                     (unsigned long long)got, (unsigned long long)(9 + cases[i].own));
    }
    assert_int_equal(fuel_of("", "(drop (call $now))"), 11 + 48);
    assert_int_equal(fuel_of("", "(drop (call $sim))"), 11);
}

/* ---- straight-line code, bulk memory --------------------------------------------- */

#define LINE_REPS 15000 /* 4 instructions each: 60,000 in the loop body */

static void test_fuel_straight_line(void **st)
{
    static char body[LINE_REPS * 72 + 64];
    size_t n = (size_t)snprintf(body, sizeof body, "(loop $l\n");
    (void)st;
    for (int i = 0; i < LINE_REPS; i++)
        n += (size_t)snprintf(body + n, sizeof body - n,
                              "(local.set $i (i32.add (local.get $i) (i32.const 1)))\n");
    snprintf(body + n, sizeof body - n, "(br $l))");
    size_t len = module("", body);
    uint64_t used[2];
    for (int k = 0; k < 2; k++) {
        load(len, 100000, ROZ_BUDGET_OFF, NULL, NULL);
        assert_int_equal(roz_controller_process(&ctl, 0), ROZ_ETIMEDOUT);
        used[k] = roz_controller_fuel_used(&ctl);
        assert_true(strstr(roz_controller_error(&ctl), "fuel exhausted") != NULL);
        roz_controller_unload(&ctl);
    }
    print_message("60,000-instruction loop body, budget 100000: stopped at %llu units\n",
                  (unsigned long long)used[0]);
    assert_int_equal(used[0], used[1]);
    /* stopped at the first run (256 instructions at most) it could not pay */
    assert_true(used[0] > 100000 && used[0] <= 100000 + 256);
}

static void test_fuel_bulk_memory(void **st)
{
    (void)st;
    /* 1 MiB fills: 65,536 units each plus a few: the second cannot be paid */
    size_t len = module("(memory 16)", "(loop $l\n"
                                       "  (memory.fill (i32.const 0) (i32.const 1) "
                                       "(i32.const 1048576))\n"
                                       "  (br $l))");
    load(len, 100000, ROZ_BUDGET_OFF, NULL, NULL);
    assert_int_equal(roz_controller_process(&ctl, 0), ROZ_ETIMEDOUT);
    uint64_t used = roz_controller_fuel_used(&ctl);
    print_message("1 MiB fills, budget 100000: stopped at %llu units\n",
                  (unsigned long long)used);
    /* process()'s frame (its i32 local and three i32 constants: 1 unit), the loop
     * (7), one run of 8 (the back-edge 2) and its fill, the next run and its
     * fill */
    assert_int_equal(used, 1 + 7 + 2 * (8 + 65536));
    roz_controller_unload(&ctl);

    /* one fill bigger than the whole budget: refused before it starts, and
     * the set before it is the last thing the call did */
    len = module("(memory 16)", "(drop (call $set (i32.const 0) (f64.const 0.5)))\n"
                                "(memory.fill (i32.const 0) (i32.const 1) (i32.const 1048576))\n"
                                "(drop (call $set (i32.const 0) (f64.const 0.25)))");
    load(len, 1000, ROZ_BUDGET_OFF, NULL, NULL);
    assert_int_equal(roz_controller_process(&ctl, 0), ROZ_ETIMEDOUT);
    assert_true(targets[0] == 0.5);
    assert_int_equal(abi.counters.sets, 1);
}

/* ---- the deadline ------------------------------------------------------------ */

typedef struct {
    uint64_t now, step, reads;
} counting_clock_t;

static uint64_t counting_clock(void *ctx)
{
    counting_clock_t *c = ctx;
    c->reads++;
    c->now += c->step;
    return c->now;
}

/* An endless loop, loaded on fuel without limit and a 5 ms deadline read
 * from @p clk; returns the module's length (to load it again). */
static size_t load_endless(counting_clock_t *clk)
{
    size_t len = module("", "(loop $l (local.set $i (i32.add (local.get $i) (i32.const 1))) "
                            "(br $l))");
    load(len, ROZ_BUDGET_OFF, 5000000, counting_clock, clk);
    return len;
}

static void test_fuel_deadline_interval(void **st)
{
    counting_clock_t clk = { 1000000, 1000, 0 }; /* 1 us a reading */
    (void)st;
    (void)load_endless(&clk);
    assert_int_equal(roz_controller_process(&ctl, 0), ROZ_ETIMEDOUT);
    assert_true(strstr(roz_controller_error(&ctl), "deadline passed") != NULL);
    uint64_t used = roz_controller_fuel_used(&ctl);
    print_message("5 ms deadline, clock +1 us a reading: %llu readings, %llu units\n",
                  (unsigned long long)clk.reads, (unsigned long long)used);
    /* one reading to set the deadline, then one per slice until it passed;
     * a slice ends with the charge that overdraws it (a run, 5 units here) */
    assert_int_equal(clk.reads, 5002);
    assert_true(used > 5001ull * ROZ_CFG_DEADLINE_CHECK_UNITS);
    assert_true(used <= 5001ull * (ROZ_CFG_DEADLINE_CHECK_UNITS + 5));
}

/* The deadline from a start the caller read: no reading of its own, and a
 * start already a budget ago stops the call at the first check. */
static void test_fuel_deadline_from_the_start(void **st)
{
    counting_clock_t clk = { 1000000, 1000, 0 }; /* 1 us a reading */
    (void)st;
    size_t len = load_endless(&clk);
    assert_int_equal(roz_controller_process_from(&ctl, 0, clk.now), ROZ_ETIMEDOUT);
    assert_int_equal(clk.reads, 5001); /* one per slice; none to set the deadline */
    assert_true(strstr(roz_controller_error(&ctl), "deadline passed at tick 0") != NULL);

    roz_controller_unload(&ctl);
    clk.reads = 0;
    load(len, ROZ_BUDGET_OFF, 5000000, counting_clock, &clk);
    assert_int_equal(roz_controller_process_from(&ctl, 7, clk.now - 5000000), ROZ_ETIMEDOUT);
    assert_int_equal(clk.reads, 1);
    assert_true(roz_controller_fuel_used(&ctl) <= ROZ_CFG_DEADLINE_CHECK_UNITS + 5);
    assert_true(strstr(roz_controller_error(&ctl), "deadline passed at tick 7") != NULL);
}

/* ---- budgets that allow nothing ----------------------------------------------- */

static void test_fuel_zero_is_refused(void **st)
{
    roz_budget_t b;
    (void)st;
    size_t len = module("", "");
    load(len, ROZ_BUDGET_OFF, ROZ_BUDGET_OFF, NULL, NULL);
    b = (roz_budget_t){ 0, ROZ_BUDGET_OFF, NULL, NULL };
    assert_int_equal(roz_controller_set_budget(&ctl, &b), ROZ_EINVAL);
    b = (roz_budget_t){ 1000, 0, roz_test_clock, NULL };
    assert_int_equal(roz_controller_set_budget(&ctl, &b), ROZ_EINVAL);
    b = (roz_budget_t){ 1000, 5000000, NULL, NULL }; /* a deadline needs a clock */
    assert_int_equal(roz_controller_set_budget(&ctl, &b), ROZ_EINVAL);
    /* the budget before stays: unmetered, so this runs */
    assert_int_equal(roz_controller_process(&ctl, 0), ROZ_OK);
    b = (roz_budget_t){ 1, ROZ_BUDGET_OFF, NULL, NULL }; /* one unit: the end costs it */
    assert_int_equal(roz_controller_set_budget(&ctl, &b), ROZ_OK);
    assert_int_equal(roz_controller_process(&ctl, 1), ROZ_OK);

    /* a rate whose default fuel per tick rounds to 0 */
    static roz_manifest_t fast;
    static roz_runtime_t rt;
    static roz_loopback_t lb;
    roz_runtime_config_t cfg;
    fast = roz_manifest_ur5;
    fast.control_rate_hz = (uint32_t)ROZ_CFG_FUEL_PER_SECOND + 1u;
    roz_test_loopback_config(&cfg, &lb, &fast, NULL, NULL);
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_EINVAL);
    roz_port_close(&cfg.port);
}

/* ---- verification judges by fuel ----------------------------------------------- */

static void test_fuel_verify_ignores_the_loader_clock(void **st)
{
    static roz_runtime_t rt;
    static roz_loopback_t lb;
    roz_test_clock_t clk = { 1000, 10000000 }; /* 10 ms a reading */
    roz_runtime_config_t cfg;
    roz_verify_report_t rep;
    size_t len;
    const uint8_t *w = roz_test_controller("sine", &len);
    (void)st;

    roz_test_loopback_config(&cfg, &lb, &roz_manifest_ur5, NULL, &clk);
    roz_test_runtime_start(&rt, &cfg, NULL);
    if (roz_runtime_load(&rt, w, len, &rep) != ROZ_OK)
        fail_msg("refused: %s", roz_runtime_error(&rt));
    /* every verify call "took" 10 ms or more on the loader's clock, twice
     * the 5 ms budget, and that is reported, not held against it */
    assert_int_equal(rep.ticks_run, ROZ_RUNTIME_VERIFY_TICKS);
    assert_true(rep.max_process_ns >= 10000000);
    roz_runtime_deinit(&rt);
    roz_port_close(&cfg.port);
}

/* ---- the C stack at loop entry ---------------------------------------------------- */

static size_t loops_len;
static int loops_rc;
static size_t loops_stack;

static void *loop_recursion_thread(void *arg)
{
    (void)arg;
    load(loops_len, ROZ_BUDGET_OFF, ROZ_BUDGET_OFF, NULL, NULL);
    loops_rc = roz_controller_process(&ctl, 0);
    loops_stack = roz_controller_stack_used(&ctl);
    return NULL;
}

static void test_fuel_stack_at_loop_entry(void **st)
{
    /* every level enters 90 nested loops, then calls itself: most of the C
     * stack it takes is op_Loop frames, which the old guard never saw */
    static char body[90 * 16 + 256];
    size_t n = 0;
    pthread_attr_t attr;
    pthread_t th;
    (void)st;
    for (int i = 0; i < 90; i++)
        n += (size_t)snprintf(body + n, sizeof body - n, "(loop ");
    n += (size_t)snprintf(body + n, sizeof body - n, "(call $deep)");
    for (int i = 0; i < 90; i++)
        n += (size_t)snprintf(body + n, sizeof body - n, ")");
    static char decls[sizeof body + 64];
    snprintf(decls, sizeof decls, "(func $deep %s)", body);
    loops_len = module(decls, "(call $deep)");
    assert_int_equal(pthread_attr_init(&attr), 0);
    assert_int_equal(pthread_attr_setstacksize(&attr, ROZ_CFG_NATIVE_STACK_BYTES + 256 * 1024),
                     0);
    assert_int_equal(pthread_create(&th, &attr, loop_recursion_thread, NULL), 0);
    assert_int_equal(pthread_join(th, NULL), 0);
    pthread_attr_destroy(&attr);
    print_message("recursion through 90 nested loops: stopped %zu bytes deep (limit %u): %s\n",
                  loops_stack, (unsigned)ROZ_CFG_NATIVE_STACK_BYTES, roz_controller_error(&ctl));
    assert_int_equal(loops_rc, ROZ_ETRAP);
    assert_true(strstr(roz_controller_error(&ctl), "native stack limit") != NULL);
    assert_true(loops_stack > ROZ_CFG_NATIVE_STACK_BYTES);
    assert_true(loops_stack <= ROZ_CFG_NATIVE_STACK_BYTES + 1024); /* one frame over */
}

ROZ_TEST_MAIN(cmocka_unit_test_teardown(test_fuel_unit, teardown),
              cmocka_unit_test_teardown(test_fuel_straight_line, teardown),
              cmocka_unit_test_teardown(test_fuel_bulk_memory, teardown),
              cmocka_unit_test_teardown(test_fuel_deadline_interval, teardown),
              cmocka_unit_test_teardown(test_fuel_deadline_from_the_start, teardown),
              cmocka_unit_test_teardown(test_fuel_imports, teardown),
              cmocka_unit_test_teardown(test_fuel_zero_is_refused, teardown),
              cmocka_unit_test_teardown(test_fuel_verify_ignores_the_loader_clock, teardown),
              cmocka_unit_test_teardown(test_fuel_stack_at_loop_entry, teardown))
