/* SPDX-License-Identifier: Apache-2.0 */
/* The flight recorder's ring (roz/recorder.h) behind the runtime on the
 * loopback: what a record holds against what the runtime did, wrap-around,
 * overflow (dropped and counted, the fault change carried to the next
 * record), decimation (events always kept), refusals, a simulator's truth
 * samples carried through the ring, the operator's inputs as the controller
 * read them, and a drain thread racing the tick (run under TSan: label
 * threads). */
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "roz/recorder.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_runtime.h"
#include "support_stats.h"
#include "unitree_g1_12dof_manifest.h"
#include "ur5_manifest.h"

#define MAX_TICKS 64
#define NC 6
#define NS 12

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_recorder_t rec;
static uint64_t storage[(1u << 20) / 8u];

/* what the runtime did at each tick, read between ticks */
static double want_state[MAX_TICKS][NS], want_applied[MAX_TICKS][NC];
static uint64_t want_fuel[MAX_TICKS];
static uint64_t want_counts[MAX_TICKS][4]; /* clamps, rate caps, limit stops, non-finite */

/* what the drain got */
typedef struct {
    roz_record_t r;
    double       state[NS], target[NC], applied[NC];
    char         msg[256];
    int          has_msg;
} got_t;
static got_t got[MAX_TICKS];
static size_t n_got;

static int sink(void *ctx, const roz_record_t *r)
{
    (void)ctx;
    assert_true(n_got < MAX_TICKS);
    got_t *g = &got[n_got++];
    assert_null(r->inputs); /* the UR5 has no operator inputs */
    g->r = *r;
    memcpy(g->state, r->state, sizeof g->state);
    memcpy(g->target, r->target, sizeof g->target);
    memcpy(g->applied, r->applied, sizeof g->applied);
    g->has_msg = r->fault_message != NULL;
    if (g->has_msg)
        snprintf(g->msg, sizeof g->msg, "%s", r->fault_message);
    return 0;
}

static const uint8_t *start(size_t slots, uint32_t decimation, size_t *len)
{
    roz_runtime_config_t cfg;
    static roz_test_clock_t clk;
    const uint8_t *w = roz_test_controller("sine", len);

    clk.now = 1;
    clk.step = 100;
    n_got = 0;
    assert_int_equal(roz_recorder_init(&rec, &roz_manifest_ur5, storage,
                                       slots * roz_recorder_slot_bytes(&roz_manifest_ur5),
                                       decimation),
                     ROZ_OK);
    roz_test_loopback_config(&cfg, &lb, &roz_manifest_ur5, NULL, &clk);
    cfg.recorder = &rec;
    roz_test_runtime_start(&rt, &cfg, "sine");
    return w;
}

static void tick(uint64_t t)
{
    roz_test_tick(&rt);
    if (t < MAX_TICKS) {
        memcpy(want_state[t], roz_runtime_last_state(&rt), sizeof want_state[t]);
        memcpy(want_applied[t], roz_runtime_last_commands(&rt), sizeof want_applied[t]);
        want_fuel[t] = RT_COUNT(&rt, last_fuel);
        /* as rozrun's summary counts them: clamps at command.set too */
        roz_runtime_stats_t st = roz_test_stats(&rt);
        want_counts[t][0] = st.filter.clamps + st.abi.set_clamped;
        want_counts[t][1] = st.filter.rate_caps;
        want_counts[t][2] = st.filter.limit_stops;
        want_counts[t][3] = st.filter.nonfinite;
    }
}

/* Every field of a record against what the runtime did at that tick. */
static void test_recorder_fields(void **st)
{
    size_t len;
    const uint8_t *w = start(64, 1, &len);
    (void)st;

    for (uint64_t t = 0; t < 20; t++)
        tick(t);
    assert_int_equal(roz_recorder_drain(&rec, sink, NULL, 0), 20);
    for (size_t i = 0; i < 20; i++) {
        const roz_record_t *r = &got[i].r;
        assert_int_equal(r->tick, i);
        assert_int_equal(r->sim_ns, i * 10000000ull); /* 100 Hz */
        assert_int_equal(r->controller_tick, (int64_t)i);
        assert_int_equal(r->controller_hash, roz_recorder_hash(w, len));
        assert_int_equal(r->read_rc, 1);
        assert_int_equal(r->flags & (ROZ_RECORD_FRESH | ROZ_RECORD_RAN | ROZ_RECORD_WROTE |
                                     ROZ_RECORD_TARGETS),
                         ROZ_RECORD_FRESH | ROZ_RECORD_RAN | ROZ_RECORD_WROTE |
                             ROZ_RECORD_TARGETS);
        assert_int_equal(r->faults, 0);
        assert_int_equal(r->fuel, want_fuel[i]);
        assert_true(r->fuel > 0);
        assert_int_equal(r->clamps, want_counts[i][0]);
        assert_int_equal(r->rate_caps, want_counts[i][1]);
        assert_int_equal(r->limit_stops, want_counts[i][2]);
        assert_int_equal(r->nonfinite, want_counts[i][3]);
        assert_true(r->wall_ns > 0 && r->tick_ns > 0 && r->process_ns > 0);
        assert_memory_equal(got[i].state, want_state[i], sizeof want_state[i]);
        assert_memory_equal(got[i].applied, want_applied[i], sizeof want_applied[i]);
        /* the sine controller's targets: finite, clamped by the filter */
        for (int c = 0; c < NC; c++)
            assert_true(isfinite(got[i].target[c]));
        /* the first record says the faults (none) once */
        assert_int_equal(got[i].has_msg, i == 0);
    }
    assert_string_equal(got[0].msg, "");
    /* the sine controller starts faster than max_rate lets it: the counts
     * move, and the record follows them */
    print_message("recorder: after 20 ticks %llu clamps, %llu rate caps, %llu limit stops\n",
                  (unsigned long long)got[19].r.clamps, (unsigned long long)got[19].r.rate_caps,
                  (unsigned long long)got[19].r.limit_stops);
    assert_true(got[19].r.clamps + got[19].r.rate_caps + got[19].r.limit_stops > 0);
    assert_int_equal(roz_recorder_dropped(&rec), 0);
    assert_int_equal(roz_recorder_recorded(&rec), 20);
    /* the loopback gives no truth: none recorded */
    for (size_t i = 0; i < 20; i++) {
        assert_null(got[i].r.truth);
        assert_int_equal(got[i].r.flags & ROZ_RECORD_TRUTH, 0);
    }
    roz_runtime_deinit(&rt);
}

/* ---- a simulator's truth (roz_port_sim_t::truth) ------------------------- */

static roz_port_ops_t truth_ops;
static roz_port_sim_t truth_sim;
static roz_port_truth_t want_truth[MAX_TICKS];
static roz_port_truth_t got_truth[MAX_TICKS];
static uint64_t truth_calls;

/* A truth made of the tick's state: the recorder must carry each tick's own. */
static int fake_truth(const void *self, roz_port_truth_t *out)
{
    (void)self;
    const double *st = roz_runtime_last_state(&rt);
    memset(out, 0, sizeof *out);
    out->floating = 1;
    for (int k = 0; k < 3; k++)
        out->pos[k] = st[k];
    out->quat[0] = 1.0;
    out->roll = st[3];
    out->pitch = st[4];
    out->contacts = (uint32_t)truth_calls;
    out->n_bodies = (uint32_t)(truth_calls % (ROZ_PORT_TRUTH_MAX_BODIES + 1u));
    for (uint32_t k = 0; k < out->n_bodies; k++)
        out->bodies[k] = (int32_t)(k + 1u);
    if (truth_calls < MAX_TICKS)
        want_truth[truth_calls] = *out;
    truth_calls++;
    return ROZ_OK;
}

static int truth_sink(void *ctx, const roz_record_t *r)
{
    (void)ctx;
    assert_true(n_got < MAX_TICKS);
    assert_non_null(r->truth);
    assert_true(r->flags & ROZ_RECORD_TRUTH);
    got_truth[n_got++] = *r->truth;
    return 0;
}

/* Every tick's truth sample, through a ring of 8 drained every 5 ticks. */
static void test_recorder_truth(void **st)
{
    roz_runtime_config_t cfg;
    static roz_test_clock_t clk;
    (void)st;

    clk.now = 1;
    clk.step = 100;
    n_got = 0;
    truth_calls = 0;
    assert_int_equal(roz_recorder_init(&rec, &roz_manifest_ur5, storage,
                                       8 * roz_recorder_slot_bytes(&roz_manifest_ur5), 1),
                     ROZ_OK);
    roz_test_loopback_config(&cfg, &lb, &roz_manifest_ur5, NULL, &clk);
    truth_ops = *cfg.port.ops;
    truth_sim.truth = fake_truth;
    truth_ops.sim = &truth_sim;
    cfg.port.ops = &truth_ops;
    cfg.recorder = &rec;
    roz_test_runtime_start(&rt, &cfg, "sine");
    for (uint64_t t = 0; t < 40; t++) {
        roz_test_tick(&rt);
        if (t % 5u == 4u)
            (void)roz_recorder_drain(&rec, truth_sink, NULL, 0);
    }
    assert_int_equal(truth_calls, 40);
    assert_int_equal(n_got, 40);
    assert_int_equal(roz_recorder_dropped(&rec), 0);
    for (size_t i = 0; i < 40; i++)
        assert_memory_equal(&got_truth[i], &want_truth[i], sizeof got_truth[i]);
    assert_true(got_truth[39].n_bodies == 39u % (ROZ_PORT_TRUTH_MAX_BODIES + 1u));
    roz_runtime_deinit(&rt);
}

/* A ring of 4 drained every 3 ticks: every record, in order, across wraps. */
static void test_recorder_wrap(void **st)
{
    size_t len;
    (void)st;
    start(5, 1, &len); /* room for 5: 4 are used */
    assert_int_equal(roz_recorder_capacity(&rec), 4);
    for (uint64_t t = 0; t < 30; t++) {
        tick(t);
        if (t % 3 == 2)
            (void)roz_recorder_drain(&rec, sink, NULL, 0);
    }
    (void)roz_recorder_drain(&rec, sink, NULL, 0);
    assert_int_equal(n_got, 30);
    for (size_t i = 0; i < 30; i++) {
        assert_int_equal(got[i].r.tick, i);
        assert_memory_equal(got[i].state, want_state[i], sizeof want_state[i]);
        assert_memory_equal(got[i].applied, want_applied[i], sizeof want_applied[i]);
    }
    assert_int_equal(roz_recorder_dropped(&rec), 0);
    /* max bounds a drain */
    for (uint64_t t = 30; t < 33; t++)
        tick(t);
    assert_int_equal(roz_recorder_drain(&rec, sink, NULL, 2), 2);
    assert_int_equal(roz_recorder_drain(&rec, sink, NULL, 0), 1);
    roz_runtime_deinit(&rt);
}

/* A full ring drops and counts, never blocks; the e-stop that latched in a
 * dropped record is carried by the next one that gets in. */
static void test_recorder_overflow(void **st)
{
    size_t len;
    (void)st;
    start(4, 1, &len);
    for (uint64_t t = 0; t < 10; t++) {
        if (t == 6)
            roz_runtime_estop(&rt);
        tick(t);
    }
    assert_int_equal(roz_recorder_dropped(&rec), 6);
    assert_int_equal(roz_recorder_drain(&rec, sink, NULL, 0), 4);
    for (size_t i = 0; i < 4; i++)
        assert_int_equal(got[i].r.tick, i);
    tick(10);
    assert_int_equal(roz_recorder_drain(&rec, sink, NULL, 0), 1);
    const got_t *g = &got[4];
    assert_int_equal(g->r.tick, 10);
    assert_int_equal(g->r.faults, ROZ_FAULT_ESTOP);
    assert_true(g->r.flags & ROZ_RECORD_FAULT_CHANGED);
    assert_string_equal(g->msg, "e-stop input");
    assert_int_equal(g->r.flags & ROZ_RECORD_RAN, 0); /* latched: the controller is held */
    assert_int_equal(g->r.controller_tick, -1);
    assert_int_equal(g->r.fuel, 0);
    assert_int_equal(roz_recorder_dropped(&rec), 6);
    assert_int_equal(roz_recorder_recorded(&rec), 5);
    roz_runtime_deinit(&rt);
}

/* Decimation 5: ticks 0, 5, 10, 15, and the ticks of an e-stop press and of a
 * clear (their inputs and fault changes are never decimated away); a held
 * input's release too. */
static void test_recorder_decimation(void **st)
{
    size_t len;
    (void)st;
    start(64, 5, &len);
    for (uint64_t t = 0; t < 20; t++) {
        if (t == 7)
            roz_runtime_estop(&rt);
        if (t == 12)
            assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
        if (t == 16)
            roz_runtime_estop_set(&rt, 1); /* pressed at 16: recorded */
        if (t == 17)
            roz_runtime_estop_set(&rt, 0); /* released at 17: recorded, no press */
        tick(t);
    }
    (void)roz_recorder_drain(&rec, sink, NULL, 0);
    static const uint64_t want[] = { 0, 5, 7, 10, 12, 15, 16, 17 };
    assert_int_equal(n_got, sizeof want / sizeof want[0]);
    for (size_t i = 0; i < n_got; i++)
        assert_int_equal(got[i].r.tick, want[i]);
    assert_true(got[2].r.flags & ROZ_RECORD_ESTOP_PRESS);
    assert_string_equal(got[2].msg, "e-stop input");
    assert_true(got[4].r.flags & ROZ_RECORD_CLEAR);
    assert_int_equal(got[4].r.cleared, ROZ_FAULT_ESTOP);
    assert_int_equal(got[4].r.faults, 0);
    assert_true(got[4].has_msg);
    assert_string_equal(got[4].msg, "");
    assert_false(got[3].has_msg);
    assert_true(got[6].r.flags & ROZ_RECORD_ESTOP_LEVEL);
    assert_false(got[7].r.flags & (ROZ_RECORD_ESTOP_LEVEL | ROZ_RECORD_ESTOP_PRESS));
    roz_runtime_deinit(&rt);
}

static void test_recorder_refusals(void **st)
{
    roz_runtime_config_t cfg;
    roz_test_clock_t clk = { 1, 100 };
    size_t slot = roz_recorder_slot_bytes(&roz_manifest_ur5);
    (void)st;

    assert_true(slot >= (NS + 2 * NC) * sizeof(double));
    assert_int_equal(roz_recorder_init(&rec, &roz_manifest_ur5, storage, slot, 1), ROZ_EINVAL);
    assert_int_equal(roz_recorder_init(&rec, &roz_manifest_ur5, (char *)storage + 4, 8 * slot, 1),
                     ROZ_EINVAL);
    assert_int_equal(roz_recorder_init(&rec, NULL, storage, 8 * slot, 1), ROZ_EINVAL);
    /* a recorder set up for another manifest is refused by the runtime */
    assert_int_equal(roz_recorder_init(&rec, &roz_manifest_ur5, storage, 8 * slot, 1), ROZ_OK);
    roz_test_loopback_config(&cfg, &lb, &roz_manifest_ur5, NULL, &clk);
    roz_manifest_t other = roz_manifest_ur5;
    cfg.manifest = &other;
    cfg.recorder = &rec;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_EINVAL);
    roz_port_close(&cfg.port);
}

/* ---- a drain thread racing the tick ------------------------------------- */

static atomic_int done;
static uint64_t seen, bad, last_tick;

static int check_sink(void *ctx, const roz_record_t *r)
{
    (void)ctx;
    /* a torn slot would mix two ticks' fields */
    if (r->sim_ns != r->tick * 10000000ull || (seen > 0 && r->tick <= last_tick) ||
        (r->flags & ROZ_RECORD_RAN && r->controller_tick != (int64_t)r->tick))
        bad++;
    last_tick = r->tick;
    seen++;
    return 0;
}

static void *drainer(void *arg)
{
    (void)arg;
    while (!atomic_load(&done))
        (void)roz_recorder_drain(&rec, check_sink, NULL, 0);
    (void)roz_recorder_drain(&rec, check_sink, NULL, 0);
    return NULL;
}

static void test_recorder_threads(void **st)
{
    size_t len;
    pthread_t th;
    const char *env = getenv("ROZ_RECORDER_STRESS_TICKS");
    uint64_t ticks = env != NULL ? strtoull(env, NULL, 10) : 100000u;
    (void)st;

    start(16, 1, &len);
    seen = bad = 0;
    atomic_store(&done, 0);
    assert_int_equal(pthread_create(&th, NULL, drainer, NULL), 0);
    for (uint64_t t = 0; t < ticks; t++) {
        roz_test_tick(&rt);
        if (t % 8u == 7u)
            sched_yield(); /* let the drain in: full and empty rings both happen */
    }
    atomic_store(&done, 1);
    pthread_join(th, NULL);
    print_message("recorder: %llu ticks, %llu drained, %u dropped\n", (unsigned long long)ticks,
                  (unsigned long long)seen, (unsigned)roz_recorder_dropped(&rec));
    assert_int_equal(bad, 0);
    assert_int_equal(seen + roz_recorder_dropped(&rec), ticks);
    assert_int_equal(seen, roz_recorder_recorded(&rec));
    assert_true(seen > 0);
    roz_runtime_deinit(&rt);
}

/* A robot with operator inputs: each record carries them as the controller
 * read them (after their rate cap), between the states and the targets of
 * its slot; a robot without them records none (inputs NULL). */
static double in_got[MAX_TICKS][3], in_want[MAX_TICKS][3];
static size_t n_in;

static int inputs_sink(void *ctx, const roz_record_t *r)
{
    const roz_manifest_t *m = &roz_manifest_unitree_g1_12dof;
    (void)ctx;
    assert_true(n_in < MAX_TICKS);
    assert_non_null(r->inputs);
    memcpy(in_got[n_in], r->inputs, sizeof in_got[n_in]);
    /* the slot's arrays follow one another: states, inputs, targets, applied */
    assert_true(r->inputs == r->state + m->n_states && r->target == r->inputs + m->n_inputs);
    assert_true(r->applied == r->target + m->n_commands);
    n_in++;
    return 0;
}

static void test_recorder_inputs(void **st)
{
    const roz_manifest_t *m = &roz_manifest_unitree_g1_12dof;
    roz_runtime_config_t cfg;
    static roz_test_clock_t clk;
    (void)st;

    assert_int_equal(m->n_inputs, 3);
    clk.now = 1;
    clk.step = 100;
    n_in = 0;
    assert_int_equal(roz_recorder_init(&rec, m, storage, 64 * roz_recorder_slot_bytes(m), 1),
                     ROZ_OK);
    roz_test_loopback_config(&cfg, &lb, m, NULL, &clk);
    cfg.recorder = &rec;
    roz_test_runtime_start(&rt, &cfg, NULL);
    assert_int_equal(roz_runtime_input_set(&rt, 0, 0.5), ROZ_OK);
    assert_int_equal(roz_runtime_input_set(&rt, 2, -0.3), ROZ_OK);
    for (int t = 0; t < 20; t++) {
        roz_test_tick(&rt);
        memcpy(in_want[t], roz_runtime_last_state(&rt) + m->n_states, sizeof in_want[t]);
    }
    assert_int_equal(roz_recorder_drain(&rec, inputs_sink, NULL, 0), 20);
    for (int t = 0; t < 20; t++)
        assert_memory_equal(in_got[t], in_want[t], sizeof in_got[t]);
    assert_true(in_got[0][0] == 0.002 && in_got[0][2] == -0.004); /* at the rate caps */
    assert_true(in_got[19][0] > 0.039 && in_got[19][1] == 0.0);
    roz_runtime_deinit(&rt);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_recorder_fields),     cmocka_unit_test(test_recorder_wrap),
              cmocka_unit_test(test_recorder_overflow),   cmocka_unit_test(test_recorder_decimation),
              cmocka_unit_test(test_recorder_refusals),   cmocka_unit_test(test_recorder_threads),
              cmocka_unit_test(test_recorder_truth),      cmocka_unit_test(test_recorder_inputs))
