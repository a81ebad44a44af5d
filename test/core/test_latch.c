/* SPDX-License-Identifier: Apache-2.0 */
/* Faults, e-stop and clear against the tick's steps (SAFETY.md §4), on one
 * thread and deterministically: a test port and a test clock fire e-stop
 * presses and releases, clears and swaps at exact points inside a tick
 * (before the port's read, after it, inside process(), after the write)
 * while the controller traps, runs out of fuel or the state goes stale in
 * that tick. Asserted: no fault is lost, a trapped or budget-stopped
 * instance never runs again, no e-stop press is lost, a clear that saw
 * nothing changes nothing. Also: read() errors keep the last good state, a
 * first frame with a NaN held position sends nothing, the log callback
 * runs only in roz_runtime_log_drain(), a frame in which the robot reports
 * a fault of its own latches ROBOT naming the part and code, is taken as a
 * fresh frame, and holds the fault while it is reported (a level); STALE
 * names what the port says went silent. */
/* white-box in part: reads the runtime's controller slots (a trapped
 * instance must never run again), which no public function exposes */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/runtime.h"
#include "support_stats.h"
#include "support.h"
#include "support_runtime.h"
#include "support_wat.h"

/* ---- a small robot ------------------------------------------------------- */

/* command 0 holds joint 0's position (its safe default is that position; the
 * manifest default, 1.0, is far from it); command 1 a velocity of joint 1.
 * State 2 is the tick at which the controller acts, state 3 how. */
static const roz_channel_t latch_commands[] = {
    { .name = "j0/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -3.0, .max = 3.0,
      .default_value = 1.0, .max_rate = 0.1, .position_state = 0 },
    { .name = "j1/velocity", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = -1.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = 1 },
};
static const roz_channel_t latch_states[] = {
    { .name = "j0/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -3.0, .max = 3.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "j1/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -3.0, .max = 3.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "trigger/effort", .type = ROZ_IF_EFFORT, .unit = "", .min = -1e9, .max = 1e9,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "action/effort", .type = ROZ_IF_EFFORT, .unit = "", .min = -10.0, .max = 10.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_manifest_t latch_manifest = {
    "latch_arm", "manipulator", 100, latch_commands, 2, latch_states, 4, NULL, NULL, 0, 0, NULL, NULL
};

enum { ACT_NONE = 0, ACT_TRAP = 1, ACT_FUEL = 2, ACT_ESTOP_REQUEST = 3 };

/* Counts its calls in its own memory and emits the count (a fresh instance
 * emits 1 first), reads the clock once (the test's hook inside process()),
 * then at tick state[2] does what state[3] says. Verification runs ticks
 * 0..99, so triggers from 100 on never fire there. */
static const char *const controller_wat =
    "(module\n"
    "  (import \"command\" \"set\" (func $set (param i32 f64) (result i32)))\n"
    "  (import \"state\" \"get\" (func $get (param i32) (result f64)))\n"
    "  (import \"timing\" \"now_ns\" (func $now (result i64)))\n"
    "  (import \"safety\" \"request_estop\" (func $estop))\n"
    "  (import \"telemetry\" \"emit_metric\" (func $emit (param f64)))\n"
    "  (global $n (mut i32) (i32.const 0))\n"
    "  (func (export \"process\") (param $tick i64)\n"
    "    (local $act f64)\n"
    "    (global.set $n (i32.add (global.get $n) (i32.const 1)))\n"
    "    (call $emit (f64.convert_i32_u (global.get $n)))\n"
    "    (drop (call $set (i32.const 0) (f64.const 0.5)))\n"
    "    (drop (call $set (i32.const 1) (f64.const 0.25)))\n"
    "    (drop (call $now))\n"
    "    (if (f64.eq (f64.convert_i64_s (local.get $tick)) (call $get (i32.const 2)))\n"
    "      (then\n"
    "        (local.set $act (call $get (i32.const 3)))\n"
    "        (if (f64.eq (local.get $act) (f64.const 1)) (then unreachable))\n"
    "        (if (f64.eq (local.get $act) (f64.const 2)) (then (loop $l (br $l))))\n"
    "        (if (f64.eq (local.get $act) (f64.const 3)) (then (call $estop)))))))\n";

static uint8_t wasm[4096];
static size_t wasm_len;

/* ---- hooks --------------------------------------------------------------- */

enum point { P_BEFORE_READ = 0, P_AFTER_READ, P_IN_PROCESS, P_AFTER_WRITE, P_COUNT };
enum event { E_NONE = 0, E_PRESS, E_RELEASE, E_EDGE, E_CLEAR, E_SWAP, E_COUNT };
static const char *const point_names[P_COUNT] = { "before read", "after read", "in process",
                                                  "after write" };
static const char *const event_names[E_COUNT] = { "-", "press", "release", "edge", "clear",
                                                  "swap" };

typedef struct hook {
    uint64_t   tick;  /* rt.counters.ticks during that tick */
    enum point at;
    enum event ev;
} hook_t;

static roz_runtime_t rt;
static roz_test_clock_t clk;
static double st[4];         /* the robot's state */
static int read_rc = 1;      /* what read() returns */
static hook_t hooks[4];
static int n_hooks;
static int in_hook, fired;
static int clear_rc[4];      /* what each E_CLEAR returned */
static int n_clears;
static int swap_rc;           /* what the last E_SWAP returned */
static uint64_t calls_at_read; /* the active instance's calls when read() ended */
static int after_read;

static void fire(enum point at)
{
    if (in_hook)
        return; /* a load's verification reads the clock too */
    in_hook = 1;
    for (int i = 0; i < n_hooks; i++) {
        if (hooks[i].tick != rt.counters.ticks || hooks[i].at != at)
            continue;
        fired++;
        switch (hooks[i].ev) {
        case E_PRESS:
            roz_runtime_estop_set(&rt, 1);
            break;
        case E_RELEASE:
            roz_runtime_estop_set(&rt, 0);
            break;
        case E_EDGE:
            roz_runtime_estop(&rt);
            break;
        case E_CLEAR:
            clear_rc[n_clears++] = roz_runtime_clear_faults(&rt);
            break;
        case E_SWAP:
            swap_rc = roz_runtime_load(&rt, wasm, wasm_len, NULL);
            break;
        default:
            break;
        }
    }
    in_hook = 0;
}

static int active_calls(uint64_t *calls)
{
    int a = atomic_load(&rt.active);
    if (a < 0)
        return 0;
    *calls = rt.slot[a].ctrl.calls;
    return 1;
}

static uint64_t hook_clock(void *ctx)
{
    uint64_t calls;
    /* the clock read inside process(): the active instance's call count
     * moved since read() ended (it counts before the engine runs) */
    if (after_read && active_calls(&calls) && calls != calls_at_read) {
        after_read = 0;
        fire(P_IN_PROCESS);
    }
    return roz_test_clock(ctx);
}

static int hp_read(void *self, double *state, size_t n)
{
    (void)self;
    fire(P_BEFORE_READ);
    int rc = read_rc;
    if (rc == 1 || rc == ROZ_EROBOT || rc == ROZ_EWATCHDOG)
        memcpy(state, st, n * sizeof st[0]);
    else if (rc < 0)
        for (size_t i = 0; i < n; i++)
            state[i] = NAN; /* undefined on error: the port scribbles */
    fire(P_AFTER_READ);
    after_read = active_calls(&calls_at_read);
    return rc;
}

static int hp_write(void *self, const double *cmd, size_t n)
{
    (void)self;
    (void)cmd;
    (void)n;
    after_read = 0;
    fire(P_AFTER_WRITE);
    return ROZ_OK;
}

/* what the robot reports when read() returns ROZ_EROBOT; why nothing is
 * fresh when read() returns 0 and the test says it knows (stale_why); after
 * ROZ_EWATCHDOG, the silence and the timeout */
static const char *stale_why;

static int hp_fault(void *self, roz_port_fault_t *out)
{
    (void)self;
    if (read_rc == ROZ_EWATCHDOG) {
        out->what = "command_timeout_us";
        out->kind = "the tick wrote no command for (us)";
        out->code = 61234;
        out->limit = 50000;
        return ROZ_OK;
    }
    if (read_rc == 0) {
        if (stale_why == NULL)
            return ROZ_ENOENT;
        out->what = "j0";
        out->kind = stale_why;
        out->code = 7;
        return ROZ_OK;
    }
    out->what = "j0";
    out->kind = "motor fault code";
    out->code = 0x21;
    return ROZ_OK;
}

static const roz_port_ops_t hook_ops = { .name = "hooks", .read = hp_read, .write = hp_write,
                                         .fault = hp_fault };

/* ---- helpers ------------------------------------------------------------- */

static double last_metric;    /* the last count the controller emitted */
static int expect_fresh;      /* the last call trapped or ran out: the next count is 1 */
static uint64_t reused;       /* calls on an instance after its trap */

static uint64_t dead_faults(void)
{
    return rt.counters.faults[0] + rt.counters.faults[1];
}

static int tick1(void)
{
    uint64_t before = dead_faults(), calls0 = rt.counters.controller_ticks;
    int rc = roz_runtime_tick(&rt);
    roz_metric_t m;
    while (roz_metric_ring_pop(&rt.metrics, &m)) {
        if (expect_fresh && m.value != 1.0)
            reused++;
        expect_fresh = 0;
        last_metric = m.value;
    }
    /* a trap or a budget stop in this tick's call: the instance is dead */
    if (rt.counters.controller_ticks != calls0 && dead_faults() != before &&
        (rt.slot[atomic_load(&rt.active)].ctrl.spent ||
         strstr(rt.slot[atomic_load(&rt.active)].ctrl.error, "unreachable") != NULL))
        expect_fresh = 1;
    return rc;
}

static void ticks(int n)
{
    for (int i = 0; i < n; i++)
        tick1();
}

static void setup_rt(void)
{
    roz_runtime_config_t cfg;

    memset(hooks, 0, sizeof hooks);
    n_hooks = 0;
    n_clears = 0;
    fired = 0;
    in_hook = 0;
    after_read = 0;
    read_rc = 1;
    stale_why = NULL;
    expect_fresh = 0;
    reused = 0;
    st[0] = 0.3;
    st[1] = 0.0;
    st[2] = -1.0;
    st[3] = ACT_NONE;
    clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_runtime_config(&cfg, &latch_manifest, (roz_port_t){ &hook_ops, NULL, 0 }, NULL);
    cfg.clock = hook_clock;
    cfg.clock_ctx = &clk;
    cfg.monitor_jitter = 0;
    roz_test_runtime_start(&rt, &cfg, NULL);
    if (wasm_len == 0)
        wasm_len = roz_test_wat(controller_wat, wasm, sizeof wasm);
    assert_int_equal(roz_runtime_load(&rt, wasm, wasm_len, NULL), ROZ_OK);
}

static int teardown(void **s)
{
    (void)s;
    roz_runtime_deinit(&rt);
    return 0;
}

/* The controller acts at its tick 100 + d; returns the runtime tick (the
 * value of rt.counters.ticks during it). Ticks up to just before it. */
static uint64_t arm(int action, int d)
{
    ticks(100 + d - (int)rt.ctrl_tick);
    st[2] = 100.0 + d;
    st[3] = action;
    return rt.counters.ticks + 1u;
}

/* ---- item 1: a trap while a clear is pending ----------------------------- */

/* The clear runs inside read() of the tick whose process() traps: it saw no
 * fault, so it clears nothing; the trapped instance never runs again. */
static void test_latch_trap_while_clear_pending(void **s)
{
    (void)s;
    setup_rt();
    uint64_t t = arm(ACT_TRAP, 0);
    hooks[n_hooks++] = (hook_t){ t, P_BEFORE_READ, E_CLEAR };
    ticks(1);
    assert_int_equal(fired, 1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_TRAP);
    uint64_t calls = rt.counters.controller_ticks;
    ticks(5);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_TRAP);
    assert_int_equal(rt.counters.controller_ticks, calls); /* process(101) never ran */
    assert_int_equal(reused, 0);
    /* a clear that saw the trap clears it, with a rebuilt instance */
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(2);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(RT_COUNT(&rt, rebuilds), 1);
    assert_true(last_metric == 2.0); /* a fresh instance: its second call */
    assert_int_equal(reused, 0);
}

/* A clear that saw an older fault does not clear a newer one of the same
 * kind, latched after it looked. */
static void test_latch_clear_keeps_newer_latch(void **s)
{
    (void)s;
    setup_rt();
    ticks(5);
    roz_runtime_estop(&rt);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    /* the clear looks (ESTOP, press 1), then a second press comes and the
     * tick sees it before the clear is applied */
    hooks[n_hooks++] = (hook_t){ rt.counters.ticks + 1u, P_AFTER_READ, E_CLEAR };
    ticks(1);
    roz_runtime_estop(&rt);
    ticks(1); /* boundary: the clear (seen press 1) and then press 2 */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    ticks(3);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* ---- item 2: the e-stop is a level; a press is never lost ----------------- */

static void test_latch_estop_then_clear_keeps_estop(void **s)
{
    (void)s;
    setup_rt();
    ticks(10);
    roz_runtime_estop(&rt);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK); /* saw nothing yet */
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    /* at once: the velocity at 0, the position held where the joint is */
    assert_true(roz_runtime_last_commands(&rt)[1] == 0.0);
    assert_true(roz_runtime_last_commands(&rt)[0] == 0.3);
    uint64_t calls = rt.counters.controller_ticks;
    ticks(5);
    assert_int_equal(rt.counters.controller_ticks, calls);
}

static void test_latch_estop_level_blocks_clear(void **s)
{
    (void)s;
    setup_rt();
    ticks(10);
    roz_runtime_estop_set(&rt, 1);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_ESTATE); /* still pressed */
    ticks(3);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    /* a press and release between two ticks still latches */
    roz_runtime_estop_set(&rt, 0);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    roz_runtime_estop_set(&rt, 1);
    roz_runtime_estop_set(&rt, 0);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* The input is checked before the port's read(): a press inside read()
 * latches at the start of the next tick, and that tick sends the safe
 * defaults; the controller does not run in it. */
static void test_latch_estop_before_controller(void **s)
{
    (void)s;
    setup_rt();
    ticks(10);
    roz_runtime_estop_set(&rt, 1);
    uint64_t calls = rt.counters.controller_ticks;
    ticks(1);
    assert_int_equal(rt.counters.controller_ticks, calls);
    assert_true(roz_runtime_last_commands(&rt)[1] == 0.0);
}

/* ---- every ordering, against every step ----------------------------------- */

static const char *fault_kind_name(int f)
{
    static const char *const names[] = { "none", "trap", "fuel", "stale" };
    return names[f];
}

/* Every violation is counted by kind and the first few printed, so a run
 * on broken code shows what breaks and how often. */
static const char *const violation_names[] = { "hooks", "fault not latched", "fault lost",
                                               "clear ignored", "clear that saw nothing changed something",
                                               "e-stop press lost", "e-stop not immediate",
                                               "trapped instance reused", "held e-stop cleared",
                                               "clear failed", "does not run again" };
#define N_VIOLATION_KINDS (sizeof violation_names / sizeof violation_names[0])
static int violations[N_VIOLATION_KINDS];
static int violation_kind;

#define VIOLATION(...)                                                    \
    do {                                                                  \
        if (violations[violation_kind]++ < 3)                             \
            print_message(__VA_ARGS__), print_message("\n");            \
        roz_runtime_deinit(&rt);                                          \
        return;                                                           \
    } while (0)
#define KIND(k) (violation_kind = (k))

static void run_case(int fault, const hook_t *h, int nh, char *what, size_t what_len)
{
    setup_rt();
    uint64_t t;
    if (fault == 3) {
        /* the state freezes for stale_ticks reads: STALE latches in tick t */
        ticks(100);
        t = rt.counters.ticks + 10u;
    } else {
        t = arm(fault == 1 ? ACT_TRAP : fault == 2 ? ACT_FUEL : ACT_NONE, 0);
    }
    for (int i = 0; i < nh; i++) {
        hooks[n_hooks] = h[i];
        hooks[n_hooks++].tick = t;
    }
    snprintf(what, what_len, "fault %s; %s @%s, %s @%s", fault_kind_name(fault),
             event_names[h[0].ev], point_names[h[0].at], event_names[h[1].ev],
             point_names[h[1].at]);
    if (fault == 3) {
        read_rc = 0;
        ticks(10);
        read_rc = 1;
    } else {
        ticks(1);
    }
    unsigned f_t = roz_runtime_faults(&rt);
    ticks(1); /* t + 1: hand-overs from tick t applied */
    unsigned f_t1 = roz_runtime_faults(&rt);
    const double *out = roz_runtime_last_commands(&rt);

    int pressed = 0, level = 0, cleared_after = 0, clear_before = 0;
    for (int i = 0; i < nh; i++) {
        if (h[i].ev == E_PRESS || h[i].ev == E_EDGE)
            pressed = 1;
        if (h[i].ev == E_PRESS)
            level = 1;
        if (h[i].ev == E_RELEASE)
            level = 0;
        /* a clear sees the tick's fault only after it latched: after
         * process() for a trap or a budget stop, after read() for stale */
        if (h[i].ev == E_CLEAR) {
            if (h[i].at == P_AFTER_WRITE)
                cleared_after = 1;
            else
                clear_before = 1;
        }
    }
    unsigned fbit = fault == 1 ? ROZ_FAULT_TRAP : fault == 2 ? ROZ_FAULT_OVERRUN
                  : fault == 3 ? ROZ_FAULT_STALE : 0u;
    if (KIND(0), fired != nh)
        VIOLATION("%s: %d of %d hooks fired", what, fired, nh);
    if (KIND(1), fbit != 0 && !(f_t & fbit))
        VIOLATION("%s: the fault did not latch in its tick (0x%x)", what, f_t);
    /* no lost fault: it stays unless a clear came after it latched */
    if (KIND(2), fbit != 0 && !cleared_after && !(f_t1 & fbit))
        VIOLATION("%s: the fault was lost (0x%x)", what, f_t1);
    if (KIND(3), fbit != 0 && cleared_after && (f_t1 & fbit))
        VIOLATION("%s: a clear after the fault did not clear it (0x%x)", what, f_t1);
    /* a clear that saw nothing changes nothing */
    if (KIND(4), fault == 0 && !pressed && f_t1 != 0)
        VIOLATION("%s: faults 0x%x", what, f_t1);
    (void)clear_before;
    /* no lost press; it takes effect at once */
    if (pressed) {
        if (KIND(5), !(f_t1 & ROZ_FAULT_ESTOP))
            VIOLATION("%s: the e-stop press was lost (0x%x)", what, f_t1);
        if (KIND(6), !(out[1] == 0.0 && out[0] == st[0]))
            VIOLATION("%s: not at the safe defaults at once (%g, %g)", what, out[0], out[1]);
    }
    if (KIND(7), reused != 0)
        VIOLATION("%s: a trapped instance ran again", what);
    /* a held e-stop is not cleared; once released every fault clears and a
     * controller runs again, never the dead instance */
    ticks(2);
    if (level) {
        int rc = roz_runtime_clear_faults(&rt);
        ticks(2);
        if (KIND(8), rc != ROZ_ESTATE || !(roz_runtime_faults(&rt) & ROZ_FAULT_ESTOP))
            VIOLATION("%s: a held e-stop was cleared (%d, 0x%x)", what, rc,
                     roz_runtime_faults(&rt));
        roz_runtime_estop_set(&rt, 0);
    }
    for (int i = 0; i < 3 && roz_runtime_faults(&rt) != 0; i++) {
        int rc = roz_runtime_clear_faults(&rt);
        if (KIND(9), rc != ROZ_OK)
            VIOLATION("%s: clear %d: %d (%s)", what, i, rc, roz_runtime_error(&rt));
        ticks(1);
    }
    uint64_t calls = rt.counters.controller_ticks;
    ticks(3);
    if (KIND(10), roz_runtime_faults(&rt) != 0 || rt.counters.controller_ticks != calls + 3u)
        VIOLATION("%s: does not run again after clearing (0x%x)", what, roz_runtime_faults(&rt));
    if (KIND(7), reused != 0)
        VIOLATION("%s: a trapped instance ran again", what);
    roz_runtime_deinit(&rt);
}

static void test_latch_every_ordering(void **s)
{
    char what[160];
    int cases = 0;
    (void)s;
    /* every fault kind x every ordered pair of events at every pair of
     * points (E_NONE: a single event) */
    for (int fault = 0; fault < 4; fault++) {
        for (int e1 = E_PRESS; e1 < E_COUNT; e1++) {
            for (int p1 = 0; p1 < P_COUNT; p1++) {
                for (int e2 = E_NONE; e2 < E_COUNT; e2++) {
                    for (int p2 = p1; p2 < (e2 == E_NONE ? p1 + 1 : P_COUNT); p2++) {
                        hook_t h[2] = { { 0, (enum point)p1, (enum event)e1 },
                                        { 0, (enum point)p2, (enum event)e2 } };
                        /* in process only happens when the controller runs */
                        if (fault == 3 && (p1 == P_IN_PROCESS || p2 == P_IN_PROCESS))
                            continue;
                        run_case(fault, h, e2 == E_NONE ? 1 : 2, what, sizeof what);
                        cases++;
                    }
                }
            }
        }
    }
    int total = 0;
    for (size_t k = 0; k < N_VIOLATION_KINDS; k++) {
        if (violations[k] != 0)
            print_message("%4d x %s\n", violations[k], violation_names[k]);
        total += violations[k];
    }
    print_message("%d orderings, %d violations\n", cases, total);
    assert_int_equal(total, 0);
}

/* ---- item 8: read() errors and the first frame ---------------------------- */

static void test_latch_read_error_keeps_state(void **s)
{
    (void)s;
    setup_rt();
    ticks(110);
    read_rc = ROZ_EIO; /* the port scribbles NaN over its buffer and fails */
    ticks(3);
    assert_true(roz_runtime_last_state(&rt)[0] == 0.3);
    assert_true(roz_runtime_last_state(&rt)[1] == 0.0);
    assert_int_equal(rt.counters.read_errors, 3);
    read_rc = 1;
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(reused, 0);
}

/* The robot reports a fault (a motor's code) in a fresh frame: the frame is
 * the state, ROBOT latches with the port's words and the code, the stop is
 * ramped; the report is a level: no clear takes while it lasts. */
/* STALE names what the port knows went silent (its fault() op), and
 * without an account says what it always said. */
static void test_latch_stale_names_the_part(void **s)
{
    (void)s;
    setup_rt();
    ticks(110);
    read_rc = 0;
    stale_why = "no reply for 20 ms (CAN id 3)";
    ticks(10);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_string_equal(roz_runtime_fault_message(&rt),
                        "no fresh state for 10 ticks: j0: no reply for 20 ms (CAN id 3)");
    read_rc = 1;
    stale_why = NULL;
    ticks(1);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    read_rc = 0;
    ticks(10);
    assert_string_equal(roz_runtime_fault_message(&rt), "no fresh state for 10 ticks");
}

static void test_latch_robot_fault(void **s)
{
    (void)s;
    setup_rt();
    ticks(110);
    uint64_t reads = rt.counters.read_errors, stale = rt.counters.stale_reads;
    st[0] = 0.5;
    read_rc = ROZ_EROBOT;
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ROBOT);
    assert_string_equal(roz_runtime_fault_message(&rt),
                        "robot fault: j0: motor fault code 33 (0x21)");
    assert_true(roz_runtime_last_state(&rt)[0] == 0.5);
    assert_int_equal(rt.counters.read_errors, reads);
    assert_int_equal(rt.counters.stale_reads, stale);
    assert_string_equal(roz_fault_name(ROZ_FAULT_ROBOT), "robot fault");
    assert_int_equal(ROZ_FAULT_ROBOT & ROZ_FAULT_IMMEDIATE_MASK, 0); /* ramped */
    /* still reported: the clear takes at the tick's start, and the same
     * tick's frame latches it again before the controller could run */
    uint64_t calls = rt.counters.controller_ticks;
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(2);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ROBOT);
    assert_int_equal(rt.counters.faults[6], 2);
    assert_int_equal(rt.counters.controller_ticks, calls);
    /* no longer reported: the clear takes */
    read_rc = 1;
    ticks(1);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* A fault the robot keeps reporting re-latches every frame, and every latch
 * takes a number of the latch sequence: after half its range an older fault
 * (here an e-stop press) must still clear once the robot stops reporting. */
static void test_latch_old_fault_clears_after_many_relatches(void **s)
{
    (void)s;
    setup_rt();
    ticks(110);
    roz_runtime_estop(&rt);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    /* half the range of latch numbers (the bits above the
     * ROZ_FAULT_KIND_COUNT fault bits) less 8 latches of the robot's report,
     * taken as one step of the sequence (ticking them all takes minutes
     * under ASan); then 16 real ones carry the e-stop's number past half
     * the range behind the newest. */
    rt.latch_seq = (rt.latch_seq + (1u << (31 - ROZ_FAULT_KIND_COUNT)) - 8u) &
                   (0xffffffffu >> ROZ_FAULT_KIND_COUNT);
    read_rc = ROZ_EROBOT;
    ticks(16);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP | ROZ_FAULT_ROBOT);
    read_rc = 1;
    ticks(1);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* The port's command watchdog fired (the tick was silent past the port's
 * timeout, and the port sent the robot its safe command): COMMAND_TIMEOUT
 * latches once with the silence and the timeout, as an immediate stop; the
 * read is no fresh frame; an event, so a clear takes at once. */
static void test_latch_command_timeout(void **s)
{
    (void)s;
    setup_rt();
    ticks(110);
    uint64_t stale = rt.counters.stale_reads;
    read_rc = ROZ_EWATCHDOG;
    ticks(1);
    read_rc = 1;
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_COMMAND_TIMEOUT);
    assert_string_equal(roz_runtime_fault_message(&rt),
                        "command timeout: the tick wrote no command for 61234 us, longer than "
                        "the port's command_timeout_us (50000): the port sent the robot its safe "
                        "command");
    assert_string_equal(roz_fault_name(ROZ_FAULT_COMMAND_TIMEOUT), "command timeout");
    assert_true((ROZ_FAULT_COMMAND_TIMEOUT & ROZ_FAULT_IMMEDIATE_MASK) != 0);
    assert_int_equal(rt.counters.stale_reads, stale + 1);
    assert_int_equal(rt.counters.faults[7], 1);
    ticks(5);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_COMMAND_TIMEOUT);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(rt.counters.faults[7], 1);
}

/* A NaN held position in the first frame: its command would have nothing to
 * hold but the manifest default (1.0, far from the joint at 0.3). Nothing is
 * sent until the position is known; then it holds it. */
static void test_latch_nan_first_frame(void **s)
{
    (void)s;
    setup_rt();
    st[0] = NAN;
    ticks(5);
    assert_int_equal(rt.counters.writes, 0);
    assert_int_equal(rt.counters.waiting_ticks, 5);
    st[0] = 0.3;
    ticks(1);
    assert_int_equal(rt.counters.writes, 1);
    assert_near(roz_runtime_last_commands(&rt)[0], 0.4, 1e-12); /* 0.3 + one rate cap */
    /* later NaNs are the filter's: it holds the last command */
    st[0] = NAN;
    ticks(1);
    assert_true(isfinite(roz_runtime_last_commands(&rt)[0]));
    assert_true(fabs(roz_runtime_last_commands(&rt)[0] - 0.4) <= 0.1 + 1e-12);
}

/* ---- item 7: the log callback runs in log_drain only ---------------------- */

static int log_calls;
static char log_last[256];
static int log_in_tick;
static int ticking;

static void log_sink(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    (void)level;
    log_calls++;
    if (ticking)
        log_in_tick++;
    snprintf(log_last, sizeof log_last, "%s", msg);
}

static void test_latch_log_drained_outside_tick(void **s)
{
    roz_runtime_config_t cfg;
    (void)s;
    setup_rt();
    cfg = rt.cfg;
    cfg.log = log_sink;
    cfg.budget_ns = UINT64_MAX; /* the monitor warns above the period */
    roz_runtime_deinit(&rt);
    roz_test_runtime_start(&rt, &cfg, NULL);
    assert_int_equal(roz_runtime_load(&rt, wasm, wasm_len, NULL), ROZ_OK);
    log_calls = log_in_tick = 0;
    uint64_t t = arm(ACT_TRAP, 0);
    (void)t;
    clk.step = 20000000; /* every step of the tick over its threshold */
    ticking = 1;
    ticks(1);
    ticking = 0;
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_TRAP);
    assert_int_equal(log_calls, 0);
    size_t n = roz_runtime_log_drain(&rt);
    assert_true(n >= 2);
    assert_int_equal(log_in_tick, 0);
    assert_int_equal((int)n, log_calls);
    /* a full ring drops and counts, and says so at the next drain */
    ticking = 1;
    for (int i = 0; i < 3 * ROZ_RUNTIME_LOG_RING; i++) {
        clk.now += 2000000000ull; /* past the monitor's one-second throttle */
        tick1();
    }
    ticking = 0;
    assert_true(roz_runtime_log_dropped(&rt) > 0);
    log_calls = 0;
    roz_runtime_log_drain(&rt);
    assert_non_null(strstr(log_last, "log events dropped"));
    assert_int_equal(log_in_tick, 0);
    char msg[256];
    assert_int_equal(roz_runtime_fault_message_copy(&rt, msg, sizeof msg), ROZ_OK);
    assert_non_null(strstr(msg, "unreachable"));
}

ROZ_TEST_MAIN(cmocka_unit_test_teardown(test_latch_trap_while_clear_pending, teardown),
              cmocka_unit_test_teardown(test_latch_clear_keeps_newer_latch, teardown),
              cmocka_unit_test_teardown(test_latch_estop_then_clear_keeps_estop, teardown),
              cmocka_unit_test_teardown(test_latch_estop_level_blocks_clear, teardown),
              cmocka_unit_test_teardown(test_latch_estop_before_controller, teardown),
              cmocka_unit_test_teardown(test_latch_every_ordering, teardown),
              cmocka_unit_test_teardown(test_latch_read_error_keeps_state, teardown),
              cmocka_unit_test_teardown(test_latch_nan_first_frame, teardown),
              cmocka_unit_test_teardown(test_latch_robot_fault, teardown),
              cmocka_unit_test_teardown(test_latch_old_fault_clears_after_many_relatches, teardown),
              cmocka_unit_test_teardown(test_latch_stale_names_the_part, teardown),
              cmocka_unit_test_teardown(test_latch_command_timeout, teardown),
              cmocka_unit_test_teardown(test_latch_log_drained_outside_tick, teardown))
