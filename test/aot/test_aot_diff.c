/* SPDX-License-Identifier: Apache-2.0 */
/* The same bits on both engines: every example controller, every hostile
 * controller that loads, and the broken examples that load, run on wasm3
 * (the module file) and ahead of time (the same module through rozaot and
 * wasm2c, linked in), side by side on the same inputs. On every tick the
 * test compares what process() returned and its message, the fuel it used,
 * every target (bit for bit), the ABI's counters, the e-stop request and
 * the metrics emitted. Each controller runs three times: on a large budget; on a
 * fuel budget that runs out mid-tick (the stop must come at the same unit);
 * on a deadline read from a test clock (the deadline is checked at the same
 * slices). A trap ends a run, as the runtime never runs a trapped instance
 * again. Known differences, each checked as far as it holds: a nest of
 * calls too deep traps on both engines at its own depth (wasm3's C stack,
 * wasm2c's call depth), so its fuel is not compared; call_indirect's three
 * traps are one text in wasm2c. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/aot.h"
#include "roz/builtin.h"
#include "roz/controller.h"
#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_runtime.h"

/* ---- the controllers ------------------------------------------------------- */

enum {
    SAME = 0,
    DEPTH = 1,    /* too deep a nest of calls: each engine traps at its own depth */
    INDIRECT = 2, /* call_indirect's trap: one text in wasm2c */
    FUZZ = 3,     /* generated: may recurse too deep (DEPTH) or trap indirectly */
};

typedef struct {
    const char             *name;  /* <name>.wasm, and roz_aot_<name> */
    const char             *dir;   /* where the .wasm is */
    const char             *robot; /* built-in manifest */
    const roz_aot_module_t *aot;
    int                     known;
} case_t;

#define EX(n, robot)  { #n, ROZ_CONTROLLER_DIR, robot, &roz_aot_##n, SAME }
#define BAD(n, k)     { "bad_" #n, ROZ_CONTROLLER_DIR, "ur5", &roz_aot_bad_##n, k }
#define HOST(n, k)    { "hostile_" #n, ROZ_HOSTILE_DIR, "ur5", &roz_aot_hostile_##n, k }
#define FZ(n)         { "fuzz_" #n, ROZ_AOT_FUZZ_DIR, "ur5", &roz_aot_fuzz_##n, FUZZ }

ROZ_AOT_DECLARE(constant_velocity);
ROZ_AOT_DECLARE(constant_velocity_wat);
ROZ_AOT_DECLARE(sine);
ROZ_AOT_DECLARE(sine_wat);
ROZ_AOT_DECLARE(hold);
ROZ_AOT_DECLARE(pd_hold);
ROZ_AOT_DECLARE(reach);
ROZ_AOT_DECLARE(g1_stand);
ROZ_AOT_DECLARE(g1_stand_pd);
ROZ_AOT_DECLARE(g1_pd);
ROZ_AOT_DECLARE(g1_pd_bulk);
ROZ_AOT_DECLARE(g1_23dof_stand);
ROZ_AOT_DECLARE(g1_23dof_stand_pd);
ROZ_AOT_DECLARE(pm01_stand);
ROZ_AOT_DECLARE(pm01_stand_pd);
ROZ_AOT_DECLARE(x2_stand);
ROZ_AOT_DECLARE(x2_stand_pd);
ROZ_AOT_DECLARE(square);
ROZ_AOT_DECLARE(hover);
ROZ_AOT_DECLARE(aot_zero_pages);
ROZ_AOT_DECLARE(bad_busy);
ROZ_AOT_DECLARE(bad_estop_run);
ROZ_AOT_DECLARE(bad_grow_memory);
ROZ_AOT_DECLARE(bad_import_loop);
ROZ_AOT_DECLARE(bad_infinite_loop);
ROZ_AOT_DECLARE(bad_nonfinite);
ROZ_AOT_DECLARE(bad_oob_memory);
ROZ_AOT_DECLARE(bad_recursion);
ROZ_AOT_DECLARE(bad_slow);
ROZ_AOT_DECLARE(bad_trap_run);
ROZ_AOT_DECLARE(bad_trap_verify);
ROZ_AOT_DECLARE(hostile_bad_convert);
ROZ_AOT_DECLARE(hostile_div_zero);
ROZ_AOT_DECLARE(hostile_estop_spam);
ROZ_AOT_DECLARE(hostile_estop_verify);
ROZ_AOT_DECLARE(hostile_grow);
ROZ_AOT_DECLARE(hostile_grow_wrap);
ROZ_AOT_DECLARE(hostile_host_trap);
ROZ_AOT_DECLARE(hostile_indices);
ROZ_AOT_DECLARE(hostile_indirect_null);
ROZ_AOT_DECLARE(hostile_indirect_oob);
ROZ_AOT_DECLARE(hostile_indirect_type);
ROZ_AOT_DECLARE(hostile_loop_run);
ROZ_AOT_DECLARE(hostile_loop_verify);
ROZ_AOT_DECLARE(hostile_metric_spam);
ROZ_AOT_DECLARE(hostile_nonfinite_run);
ROZ_AOT_DECLARE(hostile_nonfinite_verify);
ROZ_AOT_DECLARE(hostile_oob_offset);
ROZ_AOT_DECLARE(hostile_oob_store);
ROZ_AOT_DECLARE(hostile_recursion);
ROZ_AOT_DECLARE(hostile_set_flood);
ROZ_AOT_DECLARE(hostile_stack_smash);
ROZ_AOT_DECLARE(hostile_trap_run);
ROZ_AOT_DECLARE(hostile_trap_verify);

#if defined(ROZ_AOT_FUZZ_SEEDS)
#if ROZ_AOT_FUZZ_SEEDS != 16
#error "the fuzzed corpus here lists seeds 1..16"
#endif
ROZ_AOT_DECLARE(fuzz_1);
ROZ_AOT_DECLARE(fuzz_2);
ROZ_AOT_DECLARE(fuzz_3);
ROZ_AOT_DECLARE(fuzz_4);
ROZ_AOT_DECLARE(fuzz_5);
ROZ_AOT_DECLARE(fuzz_6);
ROZ_AOT_DECLARE(fuzz_7);
ROZ_AOT_DECLARE(fuzz_8);
ROZ_AOT_DECLARE(fuzz_9);
ROZ_AOT_DECLARE(fuzz_10);
ROZ_AOT_DECLARE(fuzz_11);
ROZ_AOT_DECLARE(fuzz_12);
ROZ_AOT_DECLARE(fuzz_13);
ROZ_AOT_DECLARE(fuzz_14);
ROZ_AOT_DECLARE(fuzz_15);
ROZ_AOT_DECLARE(fuzz_16);
#define FUZZ_CASES FZ(1), FZ(2), FZ(3), FZ(4), FZ(5), FZ(6), FZ(7), FZ(8), FZ(9), FZ(10), \
                   FZ(11), FZ(12), FZ(13), FZ(14), FZ(15), FZ(16),
#else
#define FUZZ_CASES
#endif

#if defined(ROZ_AOT_NN)
ROZ_AOT_DECLARE(ur5_bc);
ROZ_AOT_DECLARE(g1_policy);
#define NN_CASES EX(ur5_bc, "ur5"), EX(g1_policy, "unitree_g1"),
#else
#define NN_CASES
#endif

static const case_t cases[] = {
    EX(constant_velocity, "ur5"), EX(constant_velocity_wat, "ur5"), EX(sine, "ur5"),
    EX(sine_wat, "ur5"), EX(hold, "ur5"), EX(pd_hold, "ur5"), EX(reach, "ur5"),
    NN_CASES EX(g1_stand, "unitree_g1"), EX(g1_stand_pd, "unitree_g1"),
    EX(g1_pd, "unitree_g1"), EX(g1_pd_bulk, "unitree_g1"),
    EX(g1_23dof_stand, "unitree_g1_23dof"), EX(g1_23dof_stand_pd, "unitree_g1_23dof"),
    EX(pm01_stand, "engineai_pm01"), EX(pm01_stand_pd, "engineai_pm01"),
    EX(x2_stand, "agibot_x2"), EX(x2_stand_pd, "agibot_x2"), EX(square, "diff_drive"),
    EX(hover, "quadcopter"),
    BAD(busy, SAME), BAD(estop_run, SAME), BAD(grow_memory, SAME), BAD(import_loop, SAME),
    BAD(infinite_loop, SAME), BAD(nonfinite, SAME), BAD(oob_memory, SAME),
    BAD(recursion, DEPTH), BAD(slow, SAME), BAD(trap_run, SAME), BAD(trap_verify, SAME),
    HOST(bad_convert, SAME), HOST(div_zero, SAME), HOST(estop_spam, SAME),
    HOST(estop_verify, SAME), HOST(grow, SAME), HOST(grow_wrap, SAME), HOST(host_trap, SAME),
    HOST(indices, SAME), HOST(indirect_null, INDIRECT), HOST(indirect_oob, INDIRECT),
    HOST(indirect_type, INDIRECT), HOST(loop_run, SAME), HOST(loop_verify, SAME),
    HOST(metric_spam, SAME), HOST(nonfinite_run, SAME), HOST(nonfinite_verify, SAME),
    HOST(oob_offset, SAME), HOST(oob_store, SAME), HOST(recursion, DEPTH),
    HOST(set_flood, SAME), HOST(stack_smash, SAME), HOST(trap_run, SAME),
    HOST(trap_verify, SAME),
    FUZZ_CASES
};

#define TICKS 200

/* ---- the two engines ---------------------------------------------------------- */

typedef struct {
    roz_controller_t  c;
    roz_abi_t         abi;
    double            target[ROZ_CFG_MAX_COMMANDS];
    roz_metric_ring_t metrics;
    roz_test_clock_t  clock;
} engine_t;

static engine_t w3, aot;
static int last_rc; /* what the last tick of the last run returned */

static const uint8_t *read_module(const char *dir, const char *name, size_t *len)
{
    static uint8_t bytes[1 << 20];
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.wasm", dir, name);
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        fail_msg("%s: cannot open", path);
    *len = fread(bytes, 1, sizeof bytes, f);
    fclose(f);
    return bytes;
}

/* Deterministic states: each channel moves inside its limits, differently. */
static void states_at(const roz_manifest_t *m, int64_t t, double *s)
{
    for (uint16_t i = 0; i < m->n_states; i++) {
        const roz_channel_t *ch = &m->states[i];
        double mid = 0.5 * (ch->min + ch->max), half = 0.25 * (ch->max - ch->min);
        if (!isfinite(half) || half > 10.0)
            half = 10.0;
        if (!isfinite(mid))
            mid = 0.0;
        s[i] = mid + half * sin(0.013 * (double)t * (double)(i + 1) + 0.7 * (double)i);
    }
}

enum { LARGE, FUEL, DEADLINE };

static void start(engine_t *e, const roz_manifest_t *m, int mode, uint64_t fuel)
{
    memset(e, 0, sizeof *e);
    roz_abi_init(&e->abi, m, e->target, &e->metrics);
    roz_controller_init(&e->c);
    e->clock = (roz_test_clock_t){ 1000000, 1000 };
    (void)mode;
    (void)fuel;
}

static void set_budget(engine_t *e, int mode, uint64_t fuel)
{
    /* "unmetered": a budget no well-behaved controller reaches, which still
     * stops the endless ones */
    roz_budget_t b = { 2000000, ROZ_BUDGET_OFF, NULL, NULL };
    if (mode == FUEL)
        b.fuel = fuel;
    if (mode == DEADLINE) {
        b.fuel = ROZ_BUDGET_OFF;
        b.deadline_ns = 40000; /* 40 clock reads: past a few deadline slices */
        b.clock = roz_test_clock;
        b.clock_ctx = &e->clock;
    }
    assert_int_equal(roz_controller_set_budget(&e->c, &b), ROZ_OK);
}

/* Runs one controller on both engines; returns the most fuel a tick used. */
static uint64_t run(const case_t *k, int mode, uint64_t fuel)
{
    const roz_manifest_t *m = roz_builtin_find(k->robot);
    static double state[ROZ_CFG_MAX_STATES];
    size_t len;
    const uint8_t *wasm = read_module(k->dir, k->name, &len);
    uint64_t most = 0;

    last_rc = ROZ_ETRAP;
    assert_non_null(m);
    start(&w3, m, mode, fuel);
    start(&aot, m, mode, fuel);
    if (roz_controller_load(&w3.c, wasm, len, &w3.abi) != ROZ_OK)
        fail_msg("%s: wasm3: %s", k->name, roz_controller_error(&w3.c));
    if (roz_controller_load_aot(&aot.c, k->aot, &aot.abi) != ROZ_OK)
        fail_msg("%s: aot: %s", k->name, roz_controller_error(&aot.c));
    set_budget(&w3, mode, fuel);
    set_budget(&aot, mode, fuel);
    for (int64_t t = 0; t < TICKS; t++) {
        states_at(m, t, state);
        roz_abi_begin_tick(&w3.abi, t, state);
        roz_abi_begin_tick(&aot.abi, t, state);
        int rw = roz_controller_process(&w3.c, t);
        int ra = roz_controller_process(&aot.c, t);
        const char *ew = roz_controller_error(&w3.c), *ea = roz_controller_error(&aot.c);
        if (rw != ra)
            fail_msg("%s mode %d tick %lld: wasm3 returned %d (%s), aot %d (%s)", k->name, mode,
                     (long long)t, rw, ew, ra, ea);
        if (rw == ROZ_ETRAP && k->known == FUZZ) {
            /* a generated module may recurse past either engine's depth */
            int deep = strstr(ew, "stack") != NULL || strstr(ea, "stack") != NULL;
            int indirect = strstr(ea, "indirect call") != NULL;
            if (deep || indirect)
                break;
        }
        if (rw == ROZ_ETRAP && k->known != SAME && k->known != FUZZ) {
            /* the known differences: both trapped here, as they should */
            if (k->known == DEPTH && strstr(ea, "stack overflow") == NULL)
                fail_msg("%s: aot trapped with %s, wasm3 with %s", k->name, ea, ew);
            break;
        }
        uint64_t fw = roz_controller_fuel_used(&w3.c), fa = roz_controller_fuel_used(&aot.c);
        if (fw != fa)
            fail_msg("%s mode %d tick %lld: fuel %llu on wasm3, %llu ahead of time", k->name,
                     mode, (long long)t, (unsigned long long)fw, (unsigned long long)fa);
        if (rw != ROZ_OK && strcmp(ew, ea) != 0)
            fail_msg("%s mode %d tick %lld: wasm3 \"%s\", aot \"%s\"", k->name, mode,
                     (long long)t, ew, ea);
        if (fw > most)
            most = fw;
        if (memcmp(w3.target, aot.target, m->n_commands * sizeof(double)) != 0)
            fail_msg("%s mode %d tick %lld: targets differ", k->name, mode, (long long)t);
        if (memcmp(&w3.abi.counters, &aot.abi.counters, sizeof w3.abi.counters) != 0)
            fail_msg("%s mode %d tick %lld: ABI counters differ", k->name, mode, (long long)t);
        assert_int_equal(roz_abi_estop_requested(&w3.abi), roz_abi_estop_requested(&aot.abi));
        roz_metric_t mw, ma;
        for (;;) {
            int gw = roz_metric_ring_pop(&w3.metrics, &mw), ga = roz_metric_ring_pop(&aot.metrics, &ma);
            assert_int_equal(gw, ga);
            if (!gw)
                break;
            assert_int_equal(mw.tick, ma.tick);
            assert_memory_equal(&mw.value, &ma.value, sizeof mw.value);
        }
        last_rc = rw;
        if (rw != ROZ_OK)
            break;
    }
    roz_controller_unload(&w3.c);
    roz_controller_unload(&aot.c);
    return most;
}

static void test_aot_diff_every_controller(void **state)
{
    (void)state;
    int deadlines = 0;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        uint64_t most = run(&cases[i], LARGE, 0);
        /* a budget below the heaviest tick's: the stop comes mid-tick */
        if (most > 2) {
            (void)run(&cases[i], FUEL, most * 2 / 3);
            if (last_rc != ROZ_ETIMEDOUT && last_rc != ROZ_ETRAP)
                fail_msg("%s: a budget of %llu units never stopped it", cases[i].name,
                         (unsigned long long)(most * 2 / 3));
        }
        (void)run(&cases[i], DEADLINE, 0);
        deadlines += last_rc == ROZ_ETIMEDOUT;
    }
    /* the endless loops, at least, ran into the deadline */
    assert_true(deadlines >= 4);
}

/* ---- through the runtime ------------------------------------------------------ */

/* Two runtimes on two loopback simulators, one loading the module file
 * (wasm3), the other the compiled controller: the verification report,
 * and on every tick what roz_runtime_tick() returned, the faults, the
 * targets, the commands the port got and the fault message. At a fault
 * both clear it (the runtime rebuilds the trapped instance, here from the
 * compiled controller) and run on. */
typedef struct {
    roz_runtime_t    rt;
    roz_loopback_t   lb;
    roz_test_clock_t clk;
} rig_t;

static rig_t rig_w3, rig_aot;

static void rig_start(rig_t *r, const roz_manifest_t *m)
{
    roz_runtime_config_t cfg;
    memset(r, 0, sizeof *r);
    r->clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_loopback_config(&cfg, &r->lb, m, NULL, &r->clk);
    roz_test_runtime_start(&r->rt, &cfg, NULL);
}

static void runtime_pair(const case_t *k)
{
    const roz_manifest_t *m = roz_builtin_find(k->robot);
    size_t len;
    const uint8_t *wasm = read_module(k->dir, k->name, &len);
    roz_verify_report_t vw, va;
    char mw[ROZ_CFG_ERROR_LEN], ma[ROZ_CFG_ERROR_LEN];

    rig_start(&rig_w3, m);
    rig_start(&rig_aot, m);
    int lw = roz_runtime_load(&rig_w3.rt, wasm, len, &vw);
    int la = roz_runtime_load_aot(&rig_aot.rt, k->aot, &va);
    if (lw != la)
        fail_msg("%s: load %d on wasm3 (%s), %d ahead of time (%s)", k->name, lw,
                 roz_runtime_error(&rig_w3.rt), la, roz_runtime_error(&rig_aot.rt));
    if (lw != ROZ_OK) {
        const char *ew = roz_runtime_error(&rig_w3.rt), *ea = roz_runtime_error(&rig_aot.rt);
        if (k->known == SAME || (strstr(ew, "stack") == NULL && strstr(ea, "indirect call") == NULL))
            assert_string_equal(ew, ea);
    } else {
        assert_int_equal(vw.max_fuel, va.max_fuel);
        assert_memory_equal(vw.fuel, va.fuel, sizeof vw.fuel);
        assert_int_equal(vw.identity_match, va.identity_match);
        assert_int_equal(vw.fuel_declared, va.fuel_declared);
    }
    for (int64_t t = 0; t < TICKS; t++) {
        int rw = roz_runtime_tick(&rig_w3.rt), ra = roz_runtime_tick(&rig_aot.rt);
        unsigned fw = roz_runtime_faults(&rig_w3.rt), fa = roz_runtime_faults(&rig_aot.rt);
        if (rw != ra || fw != fa)
            fail_msg("%s tick %lld: tick %d / %d, faults %#x / %#x (wasm3 / ahead of time)",
                     k->name, (long long)t, rw, ra, fw, fa);
        const double *tw = roz_runtime_last_targets(&rig_w3.rt);
        const double *ta = roz_runtime_last_targets(&rig_aot.rt);
        if ((tw == NULL) != (ta == NULL) ||
            (tw != NULL && memcmp(tw, ta, m->n_commands * sizeof(double)) != 0))
            fail_msg("%s tick %lld: targets differ", k->name, (long long)t);
        if (memcmp(roz_runtime_last_commands(&rig_w3.rt), roz_runtime_last_commands(&rig_aot.rt),
                   m->n_commands * sizeof(double)) != 0)
            fail_msg("%s tick %lld: applied commands differ", k->name, (long long)t);
        if (fw != 0) {
            assert_int_equal(roz_runtime_fault_message_copy(&rig_w3.rt, mw, sizeof mw), ROZ_OK);
            assert_int_equal(roz_runtime_fault_message_copy(&rig_aot.rt, ma, sizeof ma), ROZ_OK);
            if (k->known == SAME || (k->known == FUZZ && strstr(mw, "stack") == NULL &&
                                     strstr(ma, "indirect call") == NULL))
                assert_string_equal(mw, ma);
            int cw = roz_runtime_clear_faults(&rig_w3.rt), ca = roz_runtime_clear_faults(&rig_aot.rt);
            assert_int_equal(cw, ca);
        }
    }
    roz_runtime_deinit(&rig_w3.rt);
    roz_runtime_deinit(&rig_aot.rt);
}

static void test_aot_diff_runtime(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        if (cases[i].known == SAME || cases[i].known == FUZZ)
            runtime_pair(&cases[i]);
}

/* Every instance of a compiled controller in use: the next load is refused
 * with a message, and an unload frees one. */
static void test_aot_instances_bounded(void **state)
{
    (void)state;
    const roz_manifest_t *m = roz_builtin_find("ur5");
    static engine_t e[ROZ_CFG_AOT_INSTANCES + 1];
    for (int i = 0; i <= ROZ_CFG_AOT_INSTANCES; i++) {
        start(&e[i], m, LARGE, 0);
        int rc = roz_controller_load_aot(&e[i].c, &roz_aot_pd_hold, &e[i].abi);
        assert_int_equal(rc, i < ROZ_CFG_AOT_INSTANCES ? ROZ_OK : ROZ_ENOMEM);
    }
    assert_non_null(strstr(roz_controller_error(&e[ROZ_CFG_AOT_INSTANCES].c), "ROZ_CFG_AOT_INSTANCES"));
    roz_controller_unload(&e[0].c);
    assert_int_equal(roz_controller_load_aot(&e[ROZ_CFG_AOT_INSTANCES].c, &roz_aot_pd_hold,
                                             &e[ROZ_CFG_AOT_INSTANCES].abi),
                     ROZ_OK);
    for (int i = 0; i <= ROZ_CFG_AOT_INSTANCES; i++)
        roz_controller_unload(&e[i].c);
}

/* A build that gave a controller less memory than it declares: the start
 * stops before any data segment is written (the compiled bounds checks take
 * the declared size), with a message, and the instance is free again. */
static void test_aot_memory_short(void **state)
{
    (void)state;
    const roz_manifest_t *m = roz_builtin_find("unitree_g1");
    static engine_t e;
    roz_aot_module_t shortened = roz_aot_g1_pd_bulk; /* a data segment at 1024 */
    shortened.memory = NULL;
    shortened.pages = 0;
    start(&e, m, LARGE, 0);
    assert_int_equal(roz_controller_load_aot(&e.c, &shortened, &e.abi), ROZ_EINVAL);
    assert_non_null(strstr(roz_controller_error(&e.c),
                           "its memory or table is larger than the build gave it"));
    assert_false(roz_controller_loaded(&e.c));
    assert_int_equal(roz_controller_load_aot(&e.c, &roz_aot_g1_pd_bulk, &e.abi), ROZ_OK);
    roz_controller_unload(&e.c);
}

/* A memory of no pages: the start needs no storage, and the one access
 * traps out of bounds as on wasm3. */
static void test_aot_zero_pages(void **state)
{
    (void)state;
    const roz_manifest_t *m = roz_builtin_find("ur5");
    static double states[ROZ_CFG_MAX_STATES];
    size_t len;
    const uint8_t *wasm = read_module(ROZ_AOT_FUZZ_DIR, "aot_zero_pages", &len);
    start(&w3, m, LARGE, 0);
    start(&aot, m, LARGE, 0);
    assert_int_equal(roz_controller_load(&w3.c, wasm, len, &w3.abi), ROZ_OK);
    assert_int_equal(roz_controller_load_aot(&aot.c, &roz_aot_aot_zero_pages, &aot.abi), ROZ_OK);
    engine_t *e[2] = { &w3, &aot };
    for (int k = 0; k < 2; k++) {
        set_budget(e[k], LARGE, 0);
        roz_abi_begin_tick(&e[k]->abi, 0, states);
        assert_int_equal(roz_controller_process(&e[k]->c, 0), ROZ_OK);
        assert_true(e[k]->target[0] == 0.5);
        roz_abi_begin_tick(&e[k]->abi, 1, states);
        assert_int_equal(roz_controller_process(&e[k]->c, 1), ROZ_ETRAP);
    }
    assert_string_equal(roz_controller_error(&w3.c), roz_controller_error(&aot.c));
    assert_non_null(strstr(roz_controller_error(&aot.c), "out of bounds memory access"));
    roz_controller_unload(&w3.c);
    roz_controller_unload(&aot.c);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_aot_diff_every_controller),
              cmocka_unit_test(test_aot_diff_runtime),
              cmocka_unit_test(test_aot_instances_bounded),
              cmocka_unit_test(test_aot_memory_short),
              cmocka_unit_test(test_aot_zero_pages))
