/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/runtime.h"

#include <math.h>
#include <string.h>

#include "roz/aot.h"
#include "roz/format.h"
#include "roz/text.h"

#include "fault_text.h"
#include "layout.h"
#include "recorder_push.h"
#include "seqlock.h"
#include "stages_internal.h"

/* ---- private ------------------------------------------------------------- */

static uint64_t now(const roz_runtime_t *rt)
{
    return rt->cfg.clock != NULL ? rt->cfg.clock(rt->cfg.clock_ctx) : 0;
}

/* The deadline's clock (roz_runtime_config_t deadline_clock, set). */
static uint64_t deadline_now(const roz_runtime_t *rt)
{
    return rt->cfg.deadline_clock(rt->cfg.deadline_clock_ctx);
}

/* ---- faults: one word, written by the tick ---------------------------------
 *
 * rt->faults holds the latched bits (low ROZ_FAULT_KIND_COUNT) and a latch
 * sequence number (the 32 - ROZ_FAULT_KIND_COUNT bits above, wrapping)
 * that every latch bumps; latch_stamp[] remembers the
 * number of each bit's latest latch. A clear hands the tick the word it saw;
 * the tick clears a bit only if its latest latch is no newer than that word:
 * a fault latched after the clear looked, even of the same kind, stays. */

#define SEQ_SHIFT  ROZ_FAULT_KIND_COUNT
#define FAULT_BITS ((1u << SEQ_SHIFT) - 1u)
#define SEQ_MASK   (0xffffffffu >> SEQ_SHIFT)
_Static_assert(ROZ_FAULT_KIND_COUNT <= 12, "the faults word keeps 20 bits of latch number");
#define STAMP_WINDOW ((SEQ_MASK + 1u) / 4u) /* how far a latched bit's number lags */

/* Log event codes (the ring carries numbers; log_drain formats them). */
enum { EV_FAULT = 1, EV_WAITING, EV_FIRST_FRAME_NONFINITE, EV_MONITOR };


static unsigned fault_index(unsigned bit)
{
    for (unsigned i = 0; i < ROZ_FAULT_KIND_COUNT; i++) {
        if (bit == 1u << i)
            return i;
    }
    return 0;
}

/* a is not newer than b, in serial arithmetic of SEQ_MASK's bits */
static int seq_le(uint32_t a, uint32_t b)
{
    return ((b - a) & SEQ_MASK) < (SEQ_MASK + 1u) / 2u;
}

/* Queue a log event (tick; wait-free; counts a drop when full). */
static void log_push(roz_runtime_t *rt, roz_log_level_t level, uint8_t code, uint16_t kind,
                     uint32_t latch, uint64_t a, uint64_t b, uint64_t c, uint64_t d)
{
    unsigned head = atomic_load_explicit(&rt->log_head, memory_order_relaxed);
    unsigned tail = atomic_load_explicit(&rt->log_tail, memory_order_acquire);

    if (rt->cfg.log == NULL)
        return;
    if (head - tail >= ROZ_RUNTIME_LOG_RING) {
        atomic_store_explicit(&rt->log_dropped,
                              atomic_load_explicit(&rt->log_dropped, memory_order_relaxed) + 1u,
                              memory_order_relaxed);
        return;
    }
    roz_runtime_log_event_t *e = &rt->log_ring[head & (ROZ_RUNTIME_LOG_RING - 1u)];
    e->level = (uint8_t)level;
    e->code = code;
    e->kind = kind;
    e->latch = latch;
    e->num[0] = a;
    e->num[1] = b;
    e->num[2] = c;
    e->num[3] = d;
    atomic_store_explicit(&rt->log_head, head + 1u, memory_order_release);
}

static void monitor_warn(void *ctx, roz_monitor_kind_t kind, uint64_t ns, uint64_t threshold_ns,
                         uint64_t exceeded)
{
    log_push(ctx, ROZ_LOG_WARN, EV_MONITOR, (uint16_t)kind, 0, ns, threshold_ns, exceeded, 0);
}

/* Write the first fault's record (tick), under its sequence counter: the
 * numbers and a byte copy of the controller's text, no formatting. */
static void record_first_fault(roz_runtime_t *rt, unsigned bit, uint32_t latch,
                               const uint32_t num[4], const char *text)
{
    roz_runtime_fault_rec_t *r = &rt->first_fault;
    unsigned s = atomic_load_explicit(&r->seq, memory_order_relaxed);
    size_t i = 0;

    atomic_store_explicit(&r->seq, s + 1u, memory_order_relaxed);
    atomic_thread_fence(memory_order_release);
    atomic_store_explicit(&r->bit, bit, memory_order_relaxed);
    atomic_store_explicit(&r->latch, latch, memory_order_relaxed);
    for (int k = 0; k < 4; k++)
        atomic_store_explicit(&r->num[k], num[k], memory_order_relaxed);
    if (text != NULL) {
        for (; i + 1u < sizeof r->text && text[i] != '\0'; i++)
            atomic_store_explicit(&r->text[i], (unsigned char)text[i], memory_order_relaxed);
    }
    atomic_store_explicit(&r->text[i], 0u, memory_order_relaxed);
    atomic_store_explicit(&r->seq, s + 2u, memory_order_release);
}

/* Latch a fault (tick thread), or refresh its latch number when it is
 * already latched (a new event of the same kind: a clear that saw the older
 * one must not clear it). The record is written before the bit is
 * published. num: N_A, N_B figures; text: the controller's message or NULL. */
static void latch(roz_runtime_t *rt, roz_fault_t fault, uint32_t a, uint32_t b, const char *text)
{
    unsigned word = atomic_load_explicit(&rt->faults, memory_order_relaxed);
    unsigned bits = word & FAULT_BITS, idx = fault_index((unsigned)fault);
    uint32_t num[4] = { (uint32_t)((uint64_t)rt->ctrl_tick & 0xffffffffu),
                        (uint32_t)((uint64_t)rt->ctrl_tick >> 32), a, b };

    rt->latch_seq = (rt->latch_seq + 1u) & SEQ_MASK;
    rt->latch_stamp[idx] = rt->latch_seq;
    /* The numbers are 23 bits and compared in serial arithmetic: a bit
     * latched more than half the range of latches ago (a persistent robot
     * fault re-latches every frame: 2^22 frames are 2.3 h at 500 Hz) would
     * look newer than any clear. Every other latched bit's number is kept
     * within a quarter of the range behind: no clear looks that far back (a
     * clear is applied at the next tick) (test_latch_old_fault_clears_
     * after_many_relatches). */
    for (unsigned i = 0; i < ROZ_FAULT_KIND_COUNT; i++) {
        uint32_t oldest = (rt->latch_seq - STAMP_WINDOW) & SEQ_MASK;
        if ((bits & (1u << i)) && i != idx && seq_le(rt->latch_stamp[i], oldest))
            rt->latch_stamp[i] = oldest;
    }
    if (bits == 0)
        record_first_fault(rt, (unsigned)fault, rt->latch_seq, num, text);
    atomic_store_explicit(&rt->faults, (bits | (unsigned)fault) | (rt->latch_seq << SEQ_SHIFT),
                          memory_order_release);
    if (bits & (unsigned)fault)
        return;
    rt->counters.faults[idx]++;
    log_push(rt, ROZ_LOG_ERROR, EV_FAULT, (uint16_t)idx, rt->latch_seq,
             (uint64_t)rt->ctrl_tick, a, b, 0);
}

static unsigned faults_now(const roz_runtime_t *rt)
{
    return atomic_load_explicit(&rt->faults, memory_order_acquire) & FAULT_BITS;
}

/* Apply a clear a supervisor asked for (tick): only the bits it saw, and of
 * those only the ones not latched again since it looked. */
static void apply_clear(roz_runtime_t *rt, unsigned seen)
{
    unsigned word = atomic_load_explicit(&rt->faults, memory_order_relaxed);
    unsigned bits = word & FAULT_BITS, clear = 0;
    uint32_t seen_seq = seen >> SEQ_SHIFT;

    for (unsigned i = 0; i < ROZ_FAULT_KIND_COUNT; i++) {
        unsigned bit = 1u << i;
        if ((seen & bits & bit) && seq_le(rt->latch_stamp[i], seen_seq))
            clear |= bit;
    }
    if (clear == 0)
        return;
    rt->rec_flags |= ROZ_RECORD_CLEAR;
    rt->rec_cleared = clear;
    if (clear & ROZ_FAULT_STALE)
        rt->stale_count = 0;
    bits &= ~clear;
    /* The first fault's record stays as it is: a reader that saw a fault
     * must find its message, and the record is rewritten only by the next
     * latch after all clear, before that latch is published. Readers show
     * "" while no fault is latched. */
    atomic_store_explicit(&rt->faults, bits | (word & ~FAULT_BITS), memory_order_release);
}

/* Copy the first fault's record (readers): 1 if consistent, 0 if the tick
 * kept rewriting it. */
static int read_first_fault(const roz_runtime_t *rt, unsigned *bit, uint32_t *latch,
                            uint64_t num[4], char *text, size_t text_len)
{
    const roz_runtime_fault_rec_t *r = &rt->first_fault;

    for (int tries = 0; tries < 1000; tries++) {
        unsigned s1 = atomic_load_explicit(&r->seq, memory_order_acquire);
        if (s1 & 1u)
            continue;
        *bit = atomic_load_explicit(&r->bit, memory_order_relaxed);
        *latch = atomic_load_explicit(&r->latch, memory_order_relaxed);
        for (int k = 0; k < 4; k++)
            num[k] = atomic_load_explicit(&r->num[k], memory_order_relaxed);
        size_t cap = text_len - 1u < sizeof r->text - 1u ? text_len - 1u : sizeof r->text - 1u;
        size_t i = 0;
        for (; i < cap; i++) {
            char c = (char)atomic_load_explicit(&r->text[i], memory_order_relaxed);
            if (c == '\0')
                break;
            text[i] = c;
        }
        text[i] = '\0';
        atomic_thread_fence(memory_order_acquire);
        if (atomic_load_explicit(&r->seq, memory_order_relaxed) == s1)
            return 1;
    }
    return 0;
}

/* The stop the latched faults ask for: a fallen robot's damping over every
 * other (a hold pushes into the ground), then an immediate one, then a
 * ramp. */
static roz_stop_t stop_mode(unsigned faults)
{
    if (faults & ROZ_FAULT_FALL)
        return ROZ_STOP_FALLEN;
    if (faults & ROZ_FAULT_IMMEDIATE_MASK)
        return ROZ_STOP_IMMEDIATE;
    return faults != 0 ? ROZ_STOP_CONTROLLED : ROZ_STOP_NONE;
}

/* The state a verification runs against: the tick's latest snapshot, or the
 * manifest defaults before the first frame. */
static void verify_state(roz_runtime_t *rt, double *state)
{
    const roz_manifest_t *m = rt->cfg.manifest;
    roz_buffer_frame_t f;

    if (roz_buffer_read(&rt->snapshot, &f) >= 0) {
        memcpy(state, f.values, (size_t)m->n_states * sizeof state[0]);
        return;
    }
    for (uint16_t i = 0; i < m->n_states; i++)
        state[i] = m->states[i].default_value;
}

/* Verification reads the inputs at their defaults (the tick owns their
 * values). */
static void verify_inputs(const roz_manifest_t *m, double *state)
{
    for (uint16_t k = 0; k < m->n_inputs; k++)
        state[m->n_states + k] = m->inputs[k].default_value;
}

/* Loads a slot's instance. An instance that verifies runs on fuel alone:
 * verification judges by work done, never by the loader thread's clock (a
 * preempted loader must not refuse a good controller); the instance that
 * drives the robot also has the wall-clock deadline, where there is a clock. */
static int load_slot(roz_runtime_t *rt, roz_runtime_slot_t *s, const uint8_t *wasm, size_t len,
                     const roz_aot_module_t *aot, int for_verify)
{
    roz_budget_t budget = { s->fuel, rt->cfg.budget_ns, rt->cfg.clock, rt->cfg.clock_ctx };
    if (rt->cfg.deadline_clock != NULL) {
        budget.clock = rt->cfg.deadline_clock;
        budget.clock_ctx = rt->cfg.deadline_clock_ctx;
    }
    int rc;

    if (for_verify || budget.clock == NULL)
        budget.deadline_ns = ROZ_BUDGET_OFF;

    roz_controller_unload(&s->ctrl);
    atomic_store(&s->dead, 0);
    roz_abi_init(&s->abi, rt->cfg.manifest, s->target, &rt->metrics);
    s->abi.clock = rt->cfg.clock;
    s->abi.clock_ctx = rt->cfg.clock_ctx;
    s->wasm = wasm;
    s->wasm_len = len;
    s->aot = aot;
    if (aot != NULL) {
        /* compiled into the image (roz/aot.h); wasm holds its roz.* sections */
        s->hash = aot->hash;
        rc = aot->load(&s->ctrl, aot, &s->abi);
    } else {
        s->hash = roz_recorder_hash(wasm, len);
        rc = rt->load_wasm(&s->ctrl, wasm, len, &s->abi, rt->cfg.load_scratch);
    }
    if (rc == ROZ_OK)
        rc = roz_controller_set_budget(&s->ctrl, &budget); /* checked at init */
    return rc;
}

/* The fuel per tick a module gets: what it declares it needs (roz.fuel),
 * up to the configured ceiling, else the runtime's budget. The declaration
 * is per module, so a heavy policy gets its inference ticks' fuel without
 * raising the budget of any other controller this runtime loads; the
 * ceiling is the integrator's (it bounds a tick's time with the fuel). */
static int grant_fuel(roz_runtime_t *rt, const uint8_t *wasm, size_t len, uint64_t *declared,
                      uint64_t *fuel)
{
    char why[ROZ_CFG_ERROR_LEN];

    *fuel = rt->cfg.fuel_per_tick;
    if (roz_identity_read_fuel(wasm, len, declared, why, sizeof why) != ROZ_OK) {
        roz_format(rt->error, sizeof rt->error, "load: %s", why);
        return ROZ_EINVAL;
    }
    if (*declared == 0 || rt->cfg.fuel_per_tick == ROZ_BUDGET_OFF)
        return ROZ_OK;
    if (rt->cfg.fuel_per_tick_max != ROZ_BUDGET_OFF && *declared > rt->cfg.fuel_per_tick_max) {
        roz_format(rt->error, sizeof rt->error,
                   "load: the controller declares %llu fuel units per tick (roz.fuel), more "
                   "than this runtime allows (fuel_per_tick_max %llu)",
                   (unsigned long long)*declared, (unsigned long long)rt->cfg.fuel_per_tick_max);
        return ROZ_EINVAL;
    }
    *fuel = *declared;
    return ROZ_OK;
}

/* Runs a freshly loaded slot for ROZ_RUNTIME_VERIFY_TICKS ticks against a
 * fixed state, its outputs discarded. */
static int verify_slot(roz_runtime_t *rt, roz_runtime_slot_t *s, const double *state,
                       roz_verify_report_t *rep)
{
    memset(rep, 0, sizeof *rep);
    rep->fuel_budget = s->ctrl.budget.fuel;
    s->abi.state = state;
    for (int64_t t = 0; t < ROZ_RUNTIME_VERIFY_TICKS; t++) {
        s->abi.tick = t;
        uint64_t t0 = now(rt);
        int rc = roz_controller_process(&s->ctrl, t);
        uint64_t dt = now(rt) - t0;
        rep->total_process_ns += dt;
        if (dt > rep->max_process_ns)
            rep->max_process_ns = dt;
        rep->nonfinite = s->abi.counters.set_nonfinite;
        rep->bad_index = s->abi.counters.set_bad_index + s->abi.counters.get_bad_index;
        rep->clamped = s->abi.counters.set_clamped;
        rep->fuel[t] = roz_controller_fuel_used(&s->ctrl);
        if (rep->fuel[t] > rep->max_fuel)
            rep->max_fuel = rep->fuel[t];
        if (roz_controller_stack_used(&s->ctrl) > rep->max_stack)
            rep->max_stack = roz_controller_stack_used(&s->ctrl);
        if (rc != ROZ_OK) {
            roz_format(rt->error, sizeof rt->error, "verify: %s", roz_controller_error(&s->ctrl));
            return ROZ_EVERIFY;
        }
        /* (a fuel stop above is a failed verification as well; the
         * loader's clock is not a judge: dt is reported, never refused) */
        if (s->abi.counters.set_nonfinite != 0) {
            roz_format(rt->error, sizeof rt->error,
                       "verify: command.set with a non-finite value at tick %lld", (long long)t);
            return ROZ_EVERIFY;
        }
        if (s->abi.estop_requested) {
            roz_format(rt->error, sizeof rt->error,
                       "verify: safety.request_estop at tick %lld", (long long)t);
            return ROZ_EVERIFY;
        }
        rep->ticks_run = (uint32_t)t + 1;
    }
    return ROZ_OK;
}

/* The robot the module was built for, against ours: a controller for
 * another robot or channel table is refused unless the configuration allows
 * it. The scan refused a malformed identity already. */
static int check_identity(roz_runtime_t *rt, const uint8_t *wasm, size_t len,
                          roz_identity_t *id, roz_identity_match_t *match)
{
    char why[ROZ_CFG_ERROR_LEN];

    if (roz_identity_read(wasm, len, id, why, sizeof why) != ROZ_OK) {
        roz_format(rt->error, sizeof rt->error, "load: %s", why);
        return ROZ_EINVAL;
    }
    *match = roz_identity_check(id, rt->cfg.manifest, why, sizeof why);
    if ((*match == ROZ_IDENTITY_OTHER_ROBOT || *match == ROZ_IDENTITY_TABLE_CHANGED) &&
        !rt->cfg.allow_foreign_controller) {
        roz_format(rt->error, sizeof rt->error, "load: %s", why);
        return ROZ_EINVAL;
    }
    return ROZ_OK;
}

/* ---- private: the tick's steps -------------------------------------------- */

/* The first frame is usable when every position paired with a position
 * command is finite: that command's safe default holds the position, and
 * before any command went out there is no last value to hold instead (the
 * manifest default may be far from the joint). Returns the first bad state
 * index, or -1. */
static int first_frame_bad(const roz_runtime_t *rt, const double *state)
{
    const roz_manifest_t *m = rt->cfg.manifest;

    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        if (c->type == ROZ_IF_POSITION && c->position_state != ROZ_CHANNEL_UNPAIRED &&
            !isfinite(state[c->position_state]))
            return (int)c->position_state;
    }
    return -1;
}

static void abi_add(roz_abi_counters_t *sum, const roz_abi_counters_t *c)
{
    sum->sets += c->sets;
    sum->set_clamped += c->set_clamped;
    sum->set_bad_index += c->set_bad_index;
    sum->set_nonfinite += c->set_nonfinite;
    sum->get_bad_index += c->get_bad_index;
    sum->estop_requests += c->estop_requests;
    sum->metrics += c->metrics;
    sum->nn_calls += c->nn_calls;
    sum->nn_refused += c->nn_refused;
}

/* A controller swapped in starts from the hold: each position command
 * paired with a position state targets that state's last good value, inside
 * the channel, not its default (the G1's 0 rad would pull every joint to
 * zero through the rate cap); a non-finite one leaves the default
 * (test_runtime_swap_starts_at_the_hold). */
static void hold_targets(roz_runtime_t *rt, roz_runtime_slot_t *s)
{
    const roz_manifest_t *m = rt->cfg.manifest;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        if (c->type != ROZ_IF_POSITION || c->position_state < 0 ||
            c->position_state >= (int32_t)m->n_states)
            continue;
        double q = rt->state[c->position_state];
        if (q - q == 0.0) /* finite */
            s->target[i] = q < c->min ? c->min : q > c->max ? c->max : q;
    }
}

/* 0. Hand-overs from other threads, at the tick boundary, each taken with an
 * exchange. The clear request is taken first: a clear that rebuilt the
 * controller scheduled it before it asked for the clear, so seeing the
 * request means seeing the swap. Returns the slot that drives, -1 none. */
static int tick_handovers(roz_runtime_t *rt)
{
    /* a load first: on most ticks there is nothing to take, and an
     * exchange is a locked instruction */
    unsigned clear = atomic_load(&rt->clear_request) != 0u ? atomic_exchange(&rt->clear_request, 0u)
                                                           : 0u;
    int pending = atomic_load(&rt->pending);
    if (pending != -1) {
        int old = atomic_load(&rt->active);
        if (old >= 0)
            abi_add(&rt->abi_retired, &rt->slot[old].abi.counters);
        /* active first, pending released after it: a loader that sees no
         * swap pending then sees the new active slot, and never takes the
         * slot being installed for its spare (only a loader sets pending,
         * and only while it is -1: nothing is lost between the two) */
        hold_targets(rt, &rt->slot[pending]);
        /* the incoming controller starts under the gains on the wire
         * (roz/stages.h: the hand-over), when one drove them */
        int stage = rt->stages.stage;
        if (old >= 0 && rt->counters.writes > 0 &&
            (stage == ROZ_STAGE_NONE || stage == ROZ_STAGE_RUN))
            roz__stages_handover(&rt->stages, rt->out, rt->cfg.manifest->control_rate_hz);
        atomic_store(&rt->active, pending);
        atomic_store(&rt->pending, -1);
        rt->ctrl_tick = 0;
        rt->counters.swaps++;
        rt->rec_flags |= ROZ_RECORD_SWAP;
    }
    if (clear != 0u)
        apply_clear(rt, clear);
    return atomic_load(&rt->active);
}

/* 1. The e-stop input, before anything runs: a press since the last tick
 * (even one already released), or the input held. */
static void tick_estop(roz_runtime_t *rt)
{
    unsigned press = atomic_load(&rt->estop_press) != 0u ? atomic_exchange(&rt->estop_press, 0u)
                                                         : 0u; /* as the clear request */
    unsigned level = atomic_load(&rt->estop_level) | atomic_load(&rt->remote_estop);
    if (press != 0u)
        rt->rec_flags |= ROZ_RECORD_ESTOP_PRESS;
    if (level != 0u)
        rt->rec_flags |= ROZ_RECORD_ESTOP_LEVEL;
    if (press != 0u || (level != 0u && !(faults_now(rt) & ROZ_FAULT_ESTOP)))
        latch(rt, ROZ_FAULT_ESTOP, 0, 0, NULL);
}

/* The port's account of its last read (fault() op), "<what>: <kind>" in
 * @p text, copied; "" when it has none. */
static void port_account(roz_runtime_t *rt, roz_port_fault_t *f, char *text, size_t cap)
{
    roz_text_t t;

    roz_text_init(&t, text, cap);
    if (rt->cfg.port.ops->fault != NULL &&
        rt->cfg.port.ops->fault(rt->cfg.port.self, f) == ROZ_OK && f->what != NULL) {
        roz_text_put(&t, f->what);
        roz_text_put(&t, ": ");
        roz_text_put(&t, f->kind != NULL ? f->kind : "code");
    }
}

/* The robot reported a fault (read() returned ROZ_EROBOT): latch ROBOT with
 * the port's account of it, "<what>: <kind>" and the code, copied, not
 * formatted. */
static void latch_robot(roz_runtime_t *rt)
{
    roz_port_fault_t f = { NULL, NULL, 0, 0 };
    char text[ROZ_CFG_ERROR_LEN];

    port_account(rt, &f, text, sizeof text);
    latch(rt, ROZ_FAULT_ROBOT, f.code, 0, text);
}

/* No fresh state for stale_ticks: STALE, with the port's account of why when
 * it has one (a hardware port knows which of its actuators went silent). */
static void latch_stale(roz_runtime_t *rt)
{
    roz_port_fault_t f = { NULL, NULL, 0, 0 };
    char text[ROZ_CFG_ERROR_LEN];

    port_account(rt, &f, text, sizeof text);
    latch(rt, ROZ_FAULT_STALE, rt->stale_count, f.code, text);
}

/* The port's command watchdog fired (read() returned ROZ_EWATCHDOG): latch
 * COMMAND_TIMEOUT with how long the tick was silent and the timeout. */
static void latch_command_timeout(roz_runtime_t *rt)
{
    roz_port_fault_t f = { NULL, NULL, 0, 0 };

    if (rt->cfg.port.ops->fault != NULL)
        (void)rt->cfg.port.ops->fault(rt->cfg.port.self, &f);
    latch(rt, ROZ_FAULT_COMMAND_TIMEOUT, f.code, f.limit, NULL);
}

/* 2. State: read into a scratch frame (the port leaves it undefined on
 * error): the snapshot's spare slot, the tick's own until it is published,
 * so a fresh frame is copied once, into the state the controller and filter
 * see; that is the last good one. Counts staleness and latches STALE and
 * LINK; a frame that reports a robot fault is a fresh frame, and latches
 * ROBOT. @p t0: the tick's start, which is also read()'s (the hand-overs
 * and the e-stop's look between them take a few ns; a clock read more
 * would cost more than they do). */
static void tick_read(roz_runtime_t *rt, uint64_t t0)
{
    const roz_manifest_t *m = rt->cfg.manifest;
    double *frame = roz_buffer_write_begin(&rt->snapshot);
    int rc = rt->cfg.port.ops->read(rt->cfg.port.self, frame, m->n_states);
    uint64_t t1 = now(rt);
    int bad = -1;

    roz_monitor_record(&rt->monitor, ROZ_MON_READ, t1 - t0, t1);
    rt->rec_read_rc = rc;
    if (rc == ROZ_EROBOT) {
        latch_robot(rt);
        rc = 1;
    } else if (rc == ROZ_EWATCHDOG) {
        latch_command_timeout(rt); /* no frame in this read */
    }
    if (rc == 1 && !rt->have_state) {
        bad = first_frame_bad(rt, frame);
        if (bad >= 0 && !rt->nonfinite_warned) {
            rt->nonfinite_warned = 1;
            log_push(rt, ROZ_LOG_WARN, EV_FIRST_FRAME_NONFINITE, 0, 0, (uint64_t)bad, 0, 0, 0);
        }
    }
    if (rc == 1 && bad < 0) {
        memcpy(rt->state, frame, (size_t)m->n_states * sizeof rt->state[0]);
        rt->have_state = 1;
        rt->stale_count = 0;
        roz_buffer_write_commit(&rt->snapshot, t1);
        rt->rec_flags |= ROZ_RECORD_FRESH;
        return;
    }
    if (rc < 0 && rc != ROZ_ENOENT)
        rt->counters.read_errors++;
    if (!rt->have_state) {
        /* Waiting for the robot's first usable frame (a DDS peer may take a
         * while to be discovered) is not a fault: nothing is sent meanwhile,
         * and staleness counts from the first frame. Said once, as a
         * warning, when it lasts stale_ticks. */
        if (rt->counters.waiting_ticks + 1u == rt->cfg.stale_ticks)
            log_push(rt, ROZ_LOG_WARN, EV_WAITING, 0, 0, rt->cfg.stale_ticks, 0, 0, 0);
        return;
    }
    rt->counters.stale_reads++;
    if (rt->stale_count < UINT32_MAX)
        rt->stale_count++;
    if (rt->stale_count >= rt->cfg.stale_ticks && !(faults_now(rt) & ROZ_FAULT_STALE))
        latch_stale(rt);
    if (rc == ROZ_ELINK)
        latch(rt, ROZ_FAULT_LINK, 0, 0, NULL);
}

/* The fall rule on this tick's state (roz/fall.h): FALL latches, with the
 * tilt and the rule's angle in mrad, when the robot is down and it is not
 * latched yet (a level: re-latched at once after a clear while down). */
static void tick_fall(roz_runtime_t *rt)
{
    if (!roz_fall_tick(&rt->fall, rt->state) || (faults_now(rt) & ROZ_FAULT_FALL))
        return;
    const roz_fall_rule_t *r = rt->cfg.manifest->fall;
    double tilt = roz_fall_tilt(r, rt->state);
    latch(rt, ROZ_FAULT_FALL, tilt == tilt ? (uint32_t)(tilt * 1000.0 + 0.5) : 0u,
          (uint32_t)(r->max_tilt * 1000.0 + 0.5), NULL);
}

/* One process() call of the driving slot and what it latches. */
static void tick_process(roz_runtime_t *rt, roz_runtime_slot_t *s)
{
    /* its first tick (after start, or a swap): what it does not write
     * holds where the joints are now, this tick's snapshot
     * (test_runtime_first_tick_holds) */
    if (rt->ctrl_tick == 0)
        hold_targets(rt, s);
    s->abi.state = rt->state;
    s->abi.tick = rt->ctrl_tick;
    rt->rec_flags |= ROZ_RECORD_RAN;
    rt->rec_ctrl_tick = rt->ctrl_tick;
    uint64_t t0 = now(rt);
    /* the deadline counts from d0, on the budget's clock (load_slot()) */
    uint64_t d0 = rt->cfg.deadline_clock != NULL ? deadline_now(rt) : t0;
    int rc = roz_controller_process_from(&s->ctrl, rt->ctrl_tick, d0);
    uint64_t t1 = now(rt);
    uint64_t d1 = rt->cfg.deadline_clock != NULL ? deadline_now(rt) : t1;
    rt->last_process_ns = t1 - t0;
    roz_monitor_record(&rt->monitor, ROZ_MON_PROCESS, t1 - t0, t1);
    rt->counters.controller_ticks++;
    rt->counters.last_fuel = roz_controller_fuel_used(&s->ctrl);
    if (rt->counters.last_fuel > rt->counters.max_fuel)
        rt->counters.max_fuel = rt->counters.last_fuel;
    if (roz_controller_stack_used(&s->ctrl) > rt->counters.max_stack)
        rt->counters.max_stack = roz_controller_stack_used(&s->ctrl);
    if (rc != ROZ_OK) {
        /* unusable from now on, marked before the fault is published: a
         * clear that sees the fault sees this */
        atomic_store(&s->dead, 1);
        latch(rt, rc == ROZ_ETIMEDOUT ? ROZ_FAULT_OVERRUN : ROZ_FAULT_TRAP, 0, 0,
              roz_controller_error(&s->ctrl));
    } else if (rt->cfg.budget_ns != ROZ_BUDGET_OFF && d1 - d0 > rt->cfg.budget_ns) {
        uint64_t us = (d1 - d0) / 1000u, budget_us = rt->cfg.budget_ns / 1000u;
        latch(rt, ROZ_FAULT_OVERRUN, us > UINT32_MAX ? UINT32_MAX : (uint32_t)us,
              budget_us > UINT32_MAX ? UINT32_MAX : (uint32_t)budget_us, NULL);
    }
    if (s->abi.estop_requested) {
        /* The request is now a latched fault; consume it, or it would latch
         * again on the first tick after the application clears. */
        s->abi.estop_requested = 0;
        latch(rt, ROZ_FAULT_ESTOP_REQUEST, 0, 0, NULL);
    }
    rt->ctrl_tick++;
}

/* 3. The deploy sequence's stage (roz/stages.h), then the controller
 * unless a stage drives or a fault is latched; an instance that trapped or
 * was stopped by its budget never runs again. Sets *target to what drove
 * (the stage's commands, the driving slot's targets; NULL: none) and *sent
 * to what the filter takes (the targets under the hand-over's gain hold),
 * and returns how the filter must stop. */
static roz_stop_t tick_controller(roz_runtime_t *rt, int active, const double **target,
                                  const double **sent)
{
    const roz_manifest_t *m = rt->cfg.manifest;
    int entered;

    if (active >= 0 && atomic_load(&rt->slot[active].dead) && faults_now(rt) == 0u)
        latch(rt, ROZ_FAULT_TRAP, 0, 0,
              "the controller's instance trapped or ran out of budget before; "
              "clearing the faults rebuilds it");
    roz_stop_t stop = stop_mode(faults_now(rt));
    int stage = roz__stages_step(&rt->stages, rt->state + m->n_states, rt->state,
                                 rt->counters.writes > 0 ? rt->out : NULL, active >= 0,
                                 stop != ROZ_STOP_NONE, &entered);
    if (entered || rt->stages.taken != -1)
        rt->rec_flags |= ROZ_RECORD_STAGE; /* replay gives the request back */
    *target = NULL;
    *sent = NULL;
    if (stage != ROZ_STAGE_NONE && stage != ROZ_STAGE_RUN) {
        /* the sequence drives, through the filter like a controller */
        *target = stop == ROZ_STOP_NONE ? roz__stages_commands(&rt->stages, rt->state)
                                        : rt->stages.target;
        *sent = *target;
        return stop;
    }
    if (active < 0) /* no controller yet: hold the safe defaults, ramped */
        return stop == ROZ_STOP_NONE ? ROZ_STOP_CONTROLLED : stop;
    if (entered) {
        /* RUN: the controller starts at tick 0 under the stand's gains */
        rt->ctrl_tick = 0;
        roz__stages_handover(&rt->stages, rt->out, m->control_rate_hz);
    }
    *target = rt->slot[active].target;
    *sent = *target;
    if (stop != ROZ_STOP_NONE)
        return stop;
    tick_process(rt, &rt->slot[active]);
    *sent = roz__stages_hold_gains(&rt->stages, *target);
    return stop_mode(faults_now(rt));
}

/* 5. The port. */
static void tick_write(roz_runtime_t *rt, uint64_t t_start)
{
    uint64_t t0 = now(rt);
    int rc = rt->cfg.port.ops->write(rt->cfg.port.self, rt->out, rt->cfg.manifest->n_commands);
    uint64_t t1 = now(rt);
    roz_monitor_record(&rt->monitor, ROZ_MON_WRITE, t1 - t0, t1);
    if (rc < 0)
        rt->counters.write_errors++;
    else
        rt->counters.writes++;
    roz_monitor_record(&rt->monitor, ROZ_MON_TICK, t1 - t_start, t1);
    rt->rec_flags |= ROZ_RECORD_WROTE;
}

/* 7. The flight recorder's record of this tick (copies, no formatting). */
static void tick_record(roz_runtime_t *rt, int active, const double *target, uint64_t t_start)
{
    roz_record_t rec;
    uint64_t period_ns = 1000000000ull / rt->cfg.manifest->control_rate_hz;
    int ran = (rt->rec_flags & ROZ_RECORD_RAN) != 0u;

    rec.tick = rt->counters.ticks - 1u;
    rec.controller_tick = ran ? rt->rec_ctrl_tick : -1;
    rec.sim_ns = rec.tick * period_ns;
    rec.wall_ns = t_start;
    rec.fuel = ran ? rt->counters.last_fuel : 0u;
    rec.process_ns = ran ? rt->last_process_ns : 0u;
    rec.tick_ns = now(rt) - t_start;
    rec.controller_hash = active >= 0 ? rt->slot[active].hash : 0u;
    rec.faults = faults_now(rt);
    rec.cleared = rt->rec_cleared;
    rec.read_rc = rt->rec_read_rc;
    rec.flags = rt->rec_flags | (target != NULL ? (uint32_t)ROZ_RECORD_TARGETS : 0u);
    /* the filter's counters as rozrun's summary counts them, clamps at
     * command.set included (test_recorder_fields) */
    uint64_t set_clamped = rt->abi_retired.set_clamped;
    if (active >= 0)
        set_clamped += rt->slot[active].abi.counters.set_clamped;
    rec.clamps = rt->filter.counters.clamps + set_clamped;
    rec.rate_caps = rt->filter.counters.rate_caps;
    rec.limit_stops = rt->filter.counters.limit_stops;
    rec.nonfinite = rt->filter.counters.nonfinite;
    rec.state = rt->state;
    /* the inputs the controller read, after the port's states: replay
     * feeds them back (docs/recording.md) */
    rec.inputs = rt->cfg.manifest->n_inputs > 0u ? rt->state + rt->cfg.manifest->n_states : NULL;
    rec.target = target;
    rec.applied = rt->out;
    rec.fault_message = NULL;
    rec.truth = NULL;
    rec.stage = rt->stages.stage;
    rec.stage_request = rt->stages.taken;
    /* a simulator's truth (roz/port.h): plain numbers copied, after the
     * tick's read() and write(); test_recorder_truth and test_mujoco_alloc
     * (no heap) prove it */
    roz_port_truth_t truth;
    if (roz_port_has_truth(&rt->cfg.port) && roz_port_truth(&rt->cfg.port, &truth) == ROZ_OK) {
        rec.truth = &truth;
        rec.flags |= ROZ_RECORD_TRUTH;
    }
    /* the first fault's numbers and text, copied for the recorder only
     * when the faults changed since its last record (the tick is the
     * record's only writer: plain loads of its own data) */
    roz__fault_raw_t first;
    char first_text[ROZ_CFG_ERROR_LEN];
    const roz__fault_raw_t *fr = NULL;
    if (roz__recorder_wants_fault(rt->cfg.recorder, rec.faults)) {
        const roz_runtime_fault_rec_t *f = &rt->first_fault;
        first.bit = atomic_load_explicit(&f->bit, memory_order_relaxed);
        for (int k = 0; k < 4; k++)
            first.num[k] = atomic_load_explicit(&f->num[k], memory_order_relaxed);
        size_t i = 0;
        for (; i + 1u < sizeof first_text; i++) {
            first_text[i] = (char)atomic_load_explicit(&f->text[i], memory_order_relaxed);
            if (first_text[i] == '\0')
                break;
        }
        first_text[i] = '\0';
        first.text = first_text;
        fr = &first;
    }
    roz__recorder_push(rt->cfg.recorder, &rec, fr);
}

/* The stats are published from where the tick keeps them, field by field
 * into their words: no copy of the whole struct to build first. The fields
 * tile the struct, so every published word is one of them. */
#define STATS_FIELD_END(f) (offsetof(roz_runtime_stats_t, f) + sizeof(((roz_runtime_stats_t *)0)->f))
_Static_assert(offsetof(roz_runtime_stats_t, runtime) == 0u &&
                   offsetof(roz_runtime_stats_t, filter) == STATS_FIELD_END(runtime) &&
                   offsetof(roz_runtime_stats_t, abi) == STATS_FIELD_END(filter) &&
                   offsetof(roz_runtime_stats_t, controller_tick) == STATS_FIELD_END(abi) &&
                   offsetof(roz_runtime_stats_t, last_process_ns) ==
                       STATS_FIELD_END(controller_tick) &&
                   sizeof(roz_runtime_stats_t) == STATS_FIELD_END(last_process_ns),
               "roz_runtime_stats_t's fields follow each other with no gap");
_Static_assert(sizeof(roz_runtime_counters_t) % 8u == 0u && sizeof(roz_filter_counters_t) % 8u == 0u &&
                   sizeof(roz_abi_counters_t) % 8u == 0u,
               "the counters are whole 64-bit words");

/* Field f of the stats, from src, into its words. */
#define PUBLISH(rt, f, src)                                                                    \
    roz__seq_store((rt)->stats_words + offsetof(roz_runtime_stats_t, f) / 4u, (src),           \
                   sizeof(((roz_runtime_stats_t *)0)->f) / 4u)

/* 6. What the tick counted, for roz_runtime_stats() on any thread. */
static void tick_publish(roz_runtime_t *rt)
{
    int active = atomic_load_explicit(&rt->active, memory_order_relaxed);
    roz_abi_counters_t abi = rt->abi_retired;
    int64_t controller_tick = rt->ctrl_tick;

    if (active >= 0)
        abi_add(&abi, &rt->slot[active].abi.counters);
    roz__seq_begin(&rt->stats_seq);
    PUBLISH(rt, runtime, &rt->counters);
    PUBLISH(rt, filter, &rt->filter.counters);
    PUBLISH(rt, abi, &abi);
    PUBLISH(rt, controller_tick, &controller_tick);
    PUBLISH(rt, last_process_ns, &rt->last_process_ns);
    roz__seq_end(&rt->stats_seq);
}

/* ---- public -------------------------------------------------------------- */

void roz_runtime_config_default(roz_runtime_config_t *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->stale_ticks = 10;
    cfg->monitor_jitter = 1;
}

static int init(roz_runtime_t *rt, const roz_runtime_config_t *cfg);

int roz_runtime_layout_check(const roz_runtime_layout_t *caller, char *err, size_t errlen)
{
    static const roz_runtime_layout_t mine = ROZ_RUNTIME_LAYOUT_INIT;
    static const roz__layout_field_t fields[] = {
        { "the layout version", offsetof(roz_runtime_layout_t, version) },
        { "ROZ_CFG_MAX_COMMANDS", offsetof(roz_runtime_layout_t, max_commands) },
        { "ROZ_CFG_MAX_STATES", offsetof(roz_runtime_layout_t, max_states) },
        { "ROZ_CFG_ERROR_LEN", offsetof(roz_runtime_layout_t, error_len) },
        { "ROZ_CFG_TELEMETRY_RING", offsetof(roz_runtime_layout_t, telemetry_ring) },
        { "ROZ_CONTROLLER_SCRATCH_BYTES (the ROZ_CFG_WASM_MAX_* validator limits)",
          offsetof(roz_runtime_layout_t, scratch_bytes) },
        { "sizeof(roz_runtime_t)", offsetof(roz_runtime_layout_t, runtime_bytes) },
        { "sizeof(roz_runtime_config_t)", offsetof(roz_runtime_layout_t, config_bytes) },
        { "sizeof(roz_controller_t)", offsetof(roz_runtime_layout_t, controller_bytes) },
        { "sizeof(roz_filter_t)", offsetof(roz_runtime_layout_t, filter_bytes) },
        { "sizeof(roz_abi_t)", offsetof(roz_runtime_layout_t, abi_bytes) },
    };

    if (caller == NULL)
        return ROZ_EINVAL;
    /* the options first: they say what to change; a size alone differs
     * when another option or a compiler setting changed the layout */
    if (roz__layout_compare(caller, &mine, fields, sizeof fields / sizeof fields[0],
                            "and compiler settings", err, errlen) != ROZ_OK)
        return ROZ_ECONFIG;
    if (err != NULL && errlen > 0)
        err[0] = '\0';
    return ROZ_OK;
}

int roz_runtime_init_layout(roz_runtime_t *rt, const roz_runtime_config_t *cfg,
                            const roz_runtime_layout_t *caller)
{
    char why[ROZ_CFG_ERROR_LEN];

    if (roz_runtime_layout_check(caller, why, sizeof why) != ROZ_OK) {
        /* *rt may be smaller than the library thinks: write nothing there;
         * cfg is safe to read only if its own layout is the same */
        if (caller != NULL && cfg != NULL &&
            caller->config_bytes == (uint32_t)sizeof(roz_runtime_config_t) && cfg->log != NULL)
            cfg->log(cfg->log_ctx, ROZ_LOG_ERROR, why);
        return ROZ_ECONFIG;
    }
    return init(rt, cfg);
}

/* roz_runtime_init() with a caller whose layout is the library's. */
static int init(roz_runtime_t *rt, const roz_runtime_config_t *cfg)
{
    const roz_manifest_t *m;

    if (rt == NULL || cfg == NULL || cfg->manifest == NULL || cfg->port.ops == NULL ||
        cfg->port.ops->read == NULL || cfg->port.ops->write == NULL || cfg->stale_ticks == 0)
        return ROZ_EINVAL;
    /* a port never opened would run its read() on an instance never set up */
    if (!cfg->port.opened) {
        if (cfg->log != NULL)
            cfg->log(cfg->log_ctx, ROZ_LOG_ERROR,
                     "roz_runtime_init: the port is not open: call roz_port_open() first");
        return ROZ_ESTATE;
    }
    m = cfg->manifest;
    /* the recorder's slots are sized for its manifest */
    if (cfg->recorder != NULL && cfg->recorder->m != m)
        return ROZ_EINVAL;
#if !ROZ_CFG_FALL
    /* never a fall rule silently ignored (roz/config.h) */
    if (m->fall != NULL) {
        if (cfg->log != NULL)
            cfg->log(cfg->log_ctx, ROZ_LOG_ERROR,
                     "roz_runtime_init: the manifest has a fall rule ([manifest.fall]) and "
                     "this build of roz leaves fall detection out (ROZ_CFG_FALL 0)");
        return ROZ_EINVAL;
    }
#endif
    memset(rt, 0, sizeof *rt);
    rt->cfg = *cfg;
    if (roz_filter_init(&rt->filter, m) != ROZ_OK)
        return ROZ_EINVAL;
    roz_fall_init(&rt->fall, m);
    uint64_t period_ns = 1000000000ull / m->control_rate_hz;
    if (rt->cfg.budget_ns == 0)
        rt->cfg.budget_ns = period_ns / 2u;
    if (rt->cfg.fuel_per_tick == 0) {
        rt->cfg.fuel_per_tick = (uint64_t)ROZ_CFG_FUEL_PER_SECOND / m->control_rate_hz;
        /* a default that rounds to nothing is refused, never "unmetered" */
        if (rt->cfg.fuel_per_tick == 0)
            return ROZ_EINVAL;
    }
    if (rt->cfg.fuel_per_tick_max == 0)
        rt->cfg.fuel_per_tick_max = (uint64_t)ROZ_CFG_FUEL_MAX_PER_SECOND / m->control_rate_hz;
    /* the monitor's warnings are queued as numbers, formatted by log_drain */
    roz_monitor_init(&rt->monitor, "roz runtime", period_ns, NULL, NULL);
    roz_monitor_set_warn(&rt->monitor, monitor_warn, rt);
    roz_monitor_set_threshold(&rt->monitor, ROZ_MON_PROCESS,
                              rt->cfg.budget_ns == ROZ_BUDGET_OFF ? 0 : rt->cfg.budget_ns);
    /* A simulator's read() is where its time passes (the mujoco port steps
     * its physics there, as a robot's time passes between a command and the
     * next state), so its length is computation, not a transport's delay:
     * the read threshold, meant for a wire, would warn on every tick. The
     * read stays measured; a simulator slower than real time still warns
     * through the tick threshold (the period). Stepping in write() instead
     * would stop time whenever no command is written (before the first
     * state, under a latency fault). test_runtime_simulator_read_not_warned. */
    if (roz_port_caps(&rt->cfg.port) & ROZ_PORT_CAP_SIMULATOR)
        roz_monitor_set_threshold(&rt->monitor, ROZ_MON_READ, 0);
    for (int i = 0; i < 2; i++) {
        roz_controller_init(&rt->slot[i].ctrl);
        roz_abi_init(&rt->slot[i].abi, m, rt->slot[i].target, &rt->metrics);
        atomic_init(&rt->slot[i].dead, 0);
    }
    atomic_init(&rt->active, -1);
    atomic_init(&rt->pending, -1);
    atomic_init(&rt->faults, 0u);
    atomic_init(&rt->clear_request, 0u);
    atomic_init(&rt->estop_level, 0u);
    atomic_init(&rt->estop_press, 0u);
    atomic_init(&rt->remote_estop, 0u);
    atomic_store(&rt->loader_busy, 0u);
    atomic_init(&rt->first_fault.seq, 0u);
    atomic_init(&rt->first_fault.bit, 0u);
    atomic_init(&rt->first_fault.latch, 0u);
    for (int k = 0; k < 4; k++)
        atomic_init(&rt->first_fault.num[k], 0u);
    for (size_t i = 0; i < sizeof rt->first_fault.text; i++)
        atomic_init(&rt->first_fault.text[i], 0u);
    atomic_init(&rt->log_head, 0u);
    atomic_init(&rt->log_tail, 0u);
    atomic_init(&rt->log_dropped, 0u);
    atomic_init(&rt->swaps_refused, 0u);
    atomic_init(&rt->rebuilds, 0u);
    atomic_init(&rt->stats_seq, 0u);
    for (size_t i = 0; i < ROZ_RUNTIME_STATS_WORDS; i++)
        atomic_init(&rt->stats_words[i], 0u);
    roz_buffer_init(&rt->snapshot, rt->snapshot_slots, m->n_states > 0 ? m->n_states : 1u);
    for (uint16_t i = 0; i < m->n_states; i++)
        rt->state[i] = m->states[i].default_value;
    roz_inputs_init(&rt->inputs, m);
    roz__stages_init(&rt->stages, m);
    verify_inputs(m, rt->state);
    for (uint16_t i = 0; i < m->n_commands; i++)
        rt->out[i] = m->commands[i].default_value;
    return ROZ_OK;
}

/* Load, verify and schedule a controller; the caller holds loader_busy. */
static int load_locked(roz_runtime_t *rt, const uint8_t *wasm, size_t len,
                       const roz_aot_module_t *aot, roz_verify_report_t *report)
{
    double *vstate = rt->verify_state;
    roz_verify_report_t local;
    roz_runtime_slot_t *s;
    roz_identity_t identity;
    roz_identity_match_t match = ROZ_IDENTITY_NONE;
    uint64_t declared = 0;
    int spare, rc;

    if (atomic_load(&rt->pending) != -1) {
        roz_format(rt->error, sizeof rt->error, "a controller swap is already pending");
        return ROZ_ESTATE;
    }
    /* the tick changes active only by taking pending, which only the holder
     * of loader_busy sets, and stores active before it clears pending: with
     * none pending, the spare slot is the tick's to ignore */
    spare = atomic_load(&rt->active) == 0 ? 1 : 0;
    s = &rt->slot[spare];
    if (report == NULL)
        report = &local;
    memset(report, 0, sizeof *report);
    rt->error[0] = '\0';

    /* 0. its fuel: declared, within the ceiling, or the default */
    rc = grant_fuel(rt, wasm, len, &declared, &s->fuel);
    if (rc != ROZ_OK) {
        report->fuel_declared = declared;
        atomic_fetch_add(&rt->swaps_refused, 1u);
        return rc;
    }
    /* 1. a separate instance for verification; its telemetry is discarded */
    rc = load_slot(rt, s, wasm, len, aot, 1);
    s->abi.metrics = NULL;
    if (rc != ROZ_OK) {
        roz_format(rt->error, sizeof rt->error, "load: %s", roz_controller_error(&s->ctrl));
        atomic_fetch_add(&rt->swaps_refused, 1u);
        return rc;
    }
    /* 2. built for this robot? (before it runs at all) */
    rc = check_identity(rt, wasm, len, &identity, &match);
    if (rc != ROZ_OK) {
        report->identity = identity;
        report->identity_match = match;
        roz_controller_unload(&s->ctrl);
        atomic_fetch_add(&rt->swaps_refused, 1u);
        return rc;
    }
    verify_state(rt, vstate);
    verify_inputs(rt->cfg.manifest, vstate);
    rc = verify_slot(rt, s, vstate, report);
    report->fuel_declared = declared;
    report->identity = identity;
    report->identity_match = match;
    roz_controller_unload(&s->ctrl);
    if (rc != ROZ_OK) {
        atomic_fetch_add(&rt->swaps_refused, 1u);
        return rc;
    }
    /* 3. a fresh instance to drive the robot from tick 0 */
    rc = load_slot(rt, s, wasm, len, aot, 0);
    if (rc != ROZ_OK) {
        roz_format(rt->error, sizeof rt->error, "load: %s", roz_controller_error(&s->ctrl));
        atomic_fetch_add(&rt->swaps_refused, 1u);
        return rc;
    }
    /* published complete: the tick takes it with an exchange (acquire) */
    atomic_store(&rt->pending, spare);
    return ROZ_OK;
}

int roz_runtime_load(roz_runtime_t *rt, const uint8_t *wasm, size_t len,
                     roz_verify_report_t *report)
{
    if (atomic_exchange(&rt->loader_busy, 1u)) {
        if (report != NULL)
            memset(report, 0, sizeof *report);
        return ROZ_ESTATE; /* rt->error belongs to the running load */
    }
    rt->load_wasm = roz_controller_load_in;
    int rc = load_locked(rt, wasm, len, NULL, report);
    atomic_store(&rt->loader_busy, 0u);
    return rc;
}

int roz_runtime_load_aot(roz_runtime_t *rt, const roz_aot_module_t *aot,
                         roz_verify_report_t *report)
{
    if (aot == NULL)
        return ROZ_EINVAL;
    if (atomic_exchange(&rt->loader_busy, 1u)) {
        if (report != NULL)
            memset(report, 0, sizeof *report);
        return ROZ_ESTATE;
    }
    /* the identity and the declared fuel are read from its roz.* sections */
    int rc = load_locked(rt, aot->sections, aot->sections_len, aot, report);
    atomic_store(&rt->loader_busy, 0u);
    return rc;
}

int roz_runtime_start(roz_runtime_t *rt)
{
    if (rt->started)
        return ROZ_ESTATE;
    rt->started = 1;
    return ROZ_OK;
}

int roz_runtime_tick(roz_runtime_t *rt)
{
    uint64_t t_start;
    const double *target, *sent;

    if (!rt->started)
        return ROZ_ESTATE; /* not armed: the port is not touched */
    t_start = now(rt);
    rt->counters.ticks++;
    if (rt->cfg.monitor_jitter)
        roz_monitor_periodic(&rt->monitor, t_start);
    rt->rec_flags = 0u;
    rt->rec_cleared = 0u;
    rt->stages.taken = -1;
    int active = tick_handovers(rt);
    tick_estop(rt);
    tick_read(rt, t_start);
    /* the operator's inputs, after the port's states, by the tick's own
     * time (simulated time in a simulation); a build for no inputs
     * (ROZ_CFG_MAX_INPUTS 0) links none of their code */
    if (ROZ_CFG_MAX_INPUTS > 0)
        roz_inputs_tick(&rt->inputs,
                        rt->counters.ticks * (1000000000ull / rt->cfg.manifest->control_rate_hz),
                        rt->state + rt->cfg.manifest->n_states);
    target = NULL;
    if (rt->have_state) {
        tick_fall(rt);
        roz_stop_t stop = tick_controller(rt, active, &target, &sent);
        /* 4. the safety filter: the last word */
        roz_filter_apply(&rt->filter, sent, rt->state, stop, rt->out);
        tick_write(rt, t_start);
    } else {
        /* nothing is sent before the first usable state frame */
        rt->counters.waiting_ticks++;
        if (active >= 0)
            target = rt->slot[active].target;
    }
    rt->last_target = target;
    tick_publish(rt);
    if (rt->cfg.recorder != NULL)
        tick_record(rt, active, target, t_start);
    return faults_now(rt) != 0u ? ROZ_EFAULT : ROZ_OK;
}

void roz_runtime_estop_set(roz_runtime_t *rt, int pressed)
{
    /* the press first: a press and release between two ticks still latches */
    if (pressed)
        atomic_store(&rt->estop_press, 1u);
    atomic_store(&rt->estop_level, pressed ? 1u : 0u);
}

void roz_runtime_estop(roz_runtime_t *rt)
{
    atomic_store(&rt->estop_press, 1u);
}

int roz_runtime_input_set(roz_runtime_t *rt, uint32_t k, double value)
{
    return rt != NULL ? roz_inputs_set(&rt->inputs, k, value) : ROZ_EINVAL;
}

int roz_runtime_operator_remote(roz_runtime_t *rt, const roz_operator_remote_t *r)
{
    if (rt == NULL || r == NULL)
        return ROZ_EINVAL;
    /* the remote's e-stop chord: a press (the press first: a chord held for
     * less than a tick still latches) and a level of its own, beside the
     * e-stop input's: a clear does not take while the last frame held it;
     * a release or a silent remote clears nothing */
    uint16_t chord = rt->cfg.manifest->remote_estop;
    if (chord != 0u) {
        unsigned held = (r->buttons & chord) == chord;
        if (held)
            atomic_store(&rt->estop_press, 1u);
        atomic_store(&rt->remote_estop, held);
    }
    return roz_inputs_remote(&rt->inputs, r);
}

int roz_runtime_operator_twist(roz_runtime_t *rt, const roz_operator_twist_t *t)
{
    return rt != NULL && t != NULL ? roz_inputs_twist(&rt->inputs, t) : ROZ_EINVAL;
}

static int sink_remote(void *ctx, const roz_operator_remote_t *r)
{
    return roz_runtime_operator_remote(ctx, r);
}

static int sink_twist(void *ctx, const roz_operator_twist_t *t)
{
    return roz_runtime_operator_twist(ctx, t);
}

roz_operator_sink_t roz_runtime_operator_sink(roz_runtime_t *rt)
{
    roz_operator_sink_t s = { sink_remote, sink_twist, rt };
    return s;
}

const roz_inputs_counters_t *roz_runtime_input_counters(const roz_runtime_t *rt)
{
    return &rt->inputs.counters;
}

int roz_runtime_stages_set(roz_runtime_t *rt, const roz_stages_config_t *c, char *err,
                           size_t errlen)
{
    if (rt->started)
        return ROZ_ESTATE;
    int rc = roz_stages_check(rt->cfg.manifest, c, err, errlen);
    if (rc == ROZ_OK)
        roz__stages_configure(&rt->stages, c, rt->cfg.manifest->control_rate_hz);
    return rc;
}

int roz_runtime_stage_request(roz_runtime_t *rt, roz_stage_t stage)
{
    if (stage != ROZ_STAGE_MOVE && stage != ROZ_STAGE_RUN && stage != ROZ_STAGE_STOP &&
        stage != ROZ_STAGE_ZERO)
        return ROZ_EINVAL;
    if (atomic_load(&rt->stages.published) == ROZ_STAGE_NONE)
        return ROZ_ESTATE;
    atomic_store(&rt->stages.request, (int)stage);
    return ROZ_OK;
}

const roz_stages_config_t *roz_runtime_stages_config(const roz_runtime_t *rt)
{
    return rt->stages.stage != ROZ_STAGE_NONE ? &rt->stages.cfg : NULL;
}

roz_stage_t roz_runtime_stage(const roz_runtime_t *rt)
{
    return (roz_stage_t)atomic_load(&rt->stages.published);
}

const roz_stages_counters_t *roz_runtime_stages_counters(const roz_runtime_t *rt)
{
    return &rt->stages.counters;
}

int roz_runtime_clear_faults(roz_runtime_t *rt)
{
    /* what this clear saw: the bits and the latch number they carry */
    unsigned seen = atomic_load(&rt->faults);
    int rc = ROZ_OK;

    if ((seen & FAULT_BITS) == 0u)
        return ROZ_OK; /* saw nothing: changes nothing */
    if (atomic_exchange(&rt->loader_busy, 1u))
        return ROZ_ESTATE;
    /* pending before active: with no swap pending, active is the tick's */
    int no_swap = atomic_load(&rt->pending) == -1;
    int active = atomic_load(&rt->active);
    if (no_swap && active >= 0 && atomic_load(&rt->slot[active].dead)) {
        /* A trapped or budget-stopped instance is not reused: its memory may
         * be half-updated. Rebuild and re-verify it into the spare slot; the
         * tick swaps it in, complete, before it applies this clear. (With a
         * swap pending, the pending controller replaces it.) */
        const roz_runtime_slot_t *s = &rt->slot[active];
        rc = load_locked(rt, s->wasm, s->wasm_len, s->aot, NULL);
        if (rc == ROZ_OK)
            atomic_fetch_add(&rt->rebuilds, 1u);
    }
    atomic_store(&rt->loader_busy, 0u);
    if (rc != ROZ_OK)
        return rc;
    if ((atomic_load(&rt->estop_level) | atomic_load(&rt->remote_estop)) != 0u) {
        seen &= ~(unsigned)ROZ_FAULT_ESTOP; /* held: the fault stays */
        rc = ROZ_ESTATE;
    }
    atomic_store(&rt->clear_request, seen);
    return rc;
}

unsigned roz_runtime_faults(const roz_runtime_t *rt)
{
    return faults_now(rt);
}

int roz_runtime_fault_message_copy(const roz_runtime_t *rt, char *buf, size_t len)
{
    char text[ROZ_CFG_ERROR_LEN];
    uint64_t num[4];
    uint32_t latch_no;
    unsigned bit;

    if (buf == NULL || len == 0)
        return ROZ_EINVAL;
    if (faults_now(rt) == 0u) {
        buf[0] = '\0';
        return ROZ_OK;
    }
    if (!read_first_fault(rt, &bit, &latch_no, num, text, sizeof text)) {
        buf[0] = '\0';
        return ROZ_ESTATE;
    }
    roz__fault_format(buf, len, bit, num, text);
    return ROZ_OK;
}

const char *roz_runtime_fault_message(roz_runtime_t *rt)
{
    (void)roz_runtime_fault_message_copy(rt, rt->fault_msg, sizeof rt->fault_msg);
    return rt->fault_msg;
}

size_t roz_runtime_log_drain(roz_runtime_t *rt)
{
    char line[ROZ_CFG_ERROR_LEN + 96], msg[ROZ_CFG_ERROR_LEN + 64];
    size_t n = 0;

    for (;;) {
        unsigned tail = atomic_load_explicit(&rt->log_tail, memory_order_relaxed);
        unsigned head = atomic_load_explicit(&rt->log_head, memory_order_acquire);
        if (tail == head)
            break;
        roz_runtime_log_event_t e = rt->log_ring[tail & (ROZ_RUNTIME_LOG_RING - 1u)];
        atomic_store_explicit(&rt->log_tail, tail + 1u, memory_order_release);
        n++;
        switch (e.code) {
        case EV_FAULT: {
            unsigned bit = 1u << e.kind, rbit;
            uint64_t num[4] = { e.num[0] & 0xffffffffu, e.num[0] >> 32, e.num[1], e.num[2] };
            char text[ROZ_CFG_ERROR_LEN];
            uint64_t rnum[4];
            uint32_t rlatch;
            /* the controller's text is kept for the first fault only */
            if (read_first_fault(rt, &rbit, &rlatch, rnum, text, sizeof text) && rbit == bit &&
                rlatch == e.latch)
                roz__fault_format(msg, sizeof msg, bit, num, text);
            else
                roz__fault_format(msg, sizeof msg, bit, num, NULL);
            roz_format(line, sizeof line, "fault latched: %s", msg);
            break;
        }
        case EV_WAITING:
            roz_format(line, sizeof line,
                       "no state from the port yet after %llu ticks; nothing is sent",
                       (unsigned long long)e.num[0]);
            break;
        case EV_FIRST_FRAME_NONFINITE:
            roz_format(line, sizeof line,
                       "the first state frame has a non-finite %s, which a position command "
                       "holds; nothing is sent until it is finite",
                       rt->cfg.manifest->states[e.num[0]].name);
            break;
        case EV_MONITOR:
            roz_monitor_format_warning(line, sizeof line, rt->monitor.name,
                                       (roz_monitor_kind_t)e.kind, e.num[0], e.num[1], e.num[2]);
            break;
        default:
            roz_format(line, sizeof line, "event %u", (unsigned)e.code);
            break;
        }
        if (rt->cfg.log != NULL)
            rt->cfg.log(rt->cfg.log_ctx, (roz_log_level_t)e.level, line);
    }
    /* what the port's threads kept for the log (roz/port.h drain) */
    if (rt->cfg.port.ops != NULL)
        n += roz_port_drain(&rt->cfg.port);
    for (unsigned i = 0; i < ROZ_RUNTIME_WATCHED; i++)
        if (rt->watched[i] != NULL)
            n += roz_monitor_drain(rt->watched[i]);
    uint32_t dropped = atomic_load(&rt->log_dropped);
    if (dropped != rt->log_dropped_seen) {
        roz_format(line, sizeof line, "%lu log events dropped (the log ring was full)",
                   (unsigned long)(dropped - rt->log_dropped_seen));
        rt->log_dropped_seen = dropped;
        if (rt->cfg.log != NULL)
            rt->cfg.log(rt->cfg.log_ctx, ROZ_LOG_WARN, line);
    }
    return n;
}

int roz_runtime_watch_monitor(roz_runtime_t *rt, roz_monitor_t *m)
{
    if (rt == NULL || m == NULL)
        return ROZ_EINVAL;
    for (unsigned i = 0; i < ROZ_RUNTIME_WATCHED; i++) {
        if (rt->watched[i] == m)
            return ROZ_OK;
        if (rt->watched[i] == NULL) {
            rt->watched[i] = m;
            return ROZ_OK;
        }
    }
    return ROZ_ENOSPC;
}

uint32_t roz_runtime_log_dropped(const roz_runtime_t *rt)
{
    return atomic_load(&rt->log_dropped);
}

int roz_runtime_stats(const roz_runtime_t *rt, roz_runtime_stats_t *out)
{
    uint32_t w[ROZ_RUNTIME_STATS_WORDS];

    if (rt == NULL || out == NULL)
        return ROZ_EINVAL;
    for (unsigned tries = 0; tries < 1000u; tries++) {
        uint32_t q = roz__seq_read_begin(&rt->stats_seq);
        roz__seq_load(w, rt->stats_words, ROZ_RUNTIME_STATS_WORDS);
        if (!roz__seq_read_ok(&rt->stats_seq, q))
            continue;
        memcpy(out, w, sizeof *out);
        out->runtime.swaps_refused = atomic_load(&rt->swaps_refused);
        out->runtime.rebuilds = atomic_load(&rt->rebuilds);
        return ROZ_OK;
    }
    memset(out, 0, sizeof *out);
    return ROZ_ESTATE;
}

int roz_runtime_channel_counters(const roz_runtime_t *rt, size_t channel,
                                 roz_filter_channel_counters_t *out)
{
    return roz_filter_channel_counters_get(&rt->filter, channel, out);
}

const roz_monitor_t *roz_runtime_monitor(const roz_runtime_t *rt)
{
    return &rt->monitor;
}

int roz_runtime_metric_pop(roz_runtime_t *rt, roz_metric_t *out)
{
    return roz_metric_ring_pop(&rt->metrics, out);
}

uint32_t roz_runtime_metrics_dropped(const roz_runtime_t *rt)
{
    return roz_metric_ring_dropped(&rt->metrics);
}

const roz_runtime_config_t *roz_runtime_config(const roz_runtime_t *rt)
{
    return &rt->cfg;
}

const char *roz_runtime_error(const roz_runtime_t *rt)
{
    return rt->error;
}

const double *roz_runtime_last_commands(const roz_runtime_t *rt)
{
    return rt->out;
}

const double *roz_runtime_last_state(const roz_runtime_t *rt)
{
    return rt->state;
}

const double *roz_runtime_last_targets(const roz_runtime_t *rt)
{
    return rt->last_target;
}

void roz_runtime_deinit(roz_runtime_t *rt)
{
    for (int i = 0; i < 2; i++)
        roz_controller_unload(&rt->slot[i].ctrl);
    atomic_store(&rt->active, -1);
    atomic_store(&rt->pending, -1);
}
