/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/runtime.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- private ------------------------------------------------------------- */

static const char *const fault_names[ROZ_FAULT_KIND_COUNT] = {
    "trap", "overrun", "stale state", "e-stop", "controller e-stop request", "port link",
};

static uint64_t now(const roz_runtime_t *rt)
{
    return rt->cfg.clock != NULL ? rt->cfg.clock(rt->cfg.clock_ctx) : 0;
}

static void log_msg(const roz_runtime_t *rt, roz_log_level_t level, const char *msg)
{
    if (rt->cfg.log != NULL)
        rt->cfg.log(rt->cfg.log_ctx, level, msg);
}

/* Latch a fault (tick thread). The first fault's message is kept. */
static void latch(roz_runtime_t *rt, roz_fault_t fault, const char *msg)
{
    unsigned before = atomic_fetch_or(&rt->faults, (unsigned)fault);
    if (before & (unsigned)fault)
        return;
    for (int i = 0; i < ROZ_FAULT_KIND_COUNT; i++) {
        if ((unsigned)fault == 1u << i)
            rt->counters.faults[i]++;
    }
    if (before == 0)
        snprintf(rt->fault_msg, sizeof rt->fault_msg, "%s", msg);
    char line[ROZ_CFG_ERROR_LEN + 48];
    snprintf(line, sizeof line, "fault latched: %s", msg);
    log_msg(rt, ROZ_LOG_ERROR, line);
}

static roz_stop_t stop_mode(unsigned faults)
{
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

/* Loads a slot's instance. An instance that verifies runs on fuel alone:
 * verification judges by work done, never by the loader thread's clock (a
 * preempted loader must not refuse a good controller); the instance that
 * drives the robot also has the wall-clock deadline, where there is a clock. */
static int load_slot(roz_runtime_t *rt, roz_runtime_slot_t *s, const uint8_t *wasm, size_t len,
                     int for_verify)
{
    roz_budget_t budget = { rt->cfg.fuel_per_tick, rt->cfg.budget_ns, rt->cfg.clock,
                            rt->cfg.clock_ctx };
    int rc;

    if (for_verify || rt->cfg.clock == NULL)
        budget.deadline_ns = ROZ_BUDGET_OFF;

    roz_controller_unload(&s->ctrl);
    roz_abi_init(&s->abi, rt->cfg.manifest, s->target, &rt->metrics);
    s->abi.clock = rt->cfg.clock;
    s->abi.clock_ctx = rt->cfg.clock_ctx;
    s->wasm = wasm;
    s->wasm_len = len;
    rc = roz_controller_load(&s->ctrl, wasm, len, &s->abi);
    if (rc == ROZ_OK)
        rc = roz_controller_set_budget(&s->ctrl, &budget); /* checked at init */
    return rc;
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
            snprintf(rt->error, sizeof rt->error, "verify: %s", roz_controller_error(&s->ctrl));
            return ROZ_EFAULT;
        }
        /* (a fuel stop above is a failed verification as well; the
         * loader's clock is not a judge: dt is reported, never refused) */
        if (s->abi.counters.set_nonfinite != 0) {
            snprintf(rt->error, sizeof rt->error,
                     "verify: command.set with a non-finite value at tick %lld", (long long)t);
            return ROZ_EFAULT;
        }
        if (s->abi.estop_requested) {
            snprintf(rt->error, sizeof rt->error,
                     "verify: safety.request_estop at tick %lld", (long long)t);
            return ROZ_EFAULT;
        }
        rep->ticks_run = (uint32_t)t + 1;
    }
    return ROZ_OK;
}

/* ---- public -------------------------------------------------------------- */

void roz_runtime_config_default(roz_runtime_config_t *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->stale_ticks = 10;
    cfg->position_margin = ROZ_FILTER_DEFAULT_MARGIN;
    cfg->monitor_jitter = 1;
}

static int init(roz_runtime_t *rt, const roz_runtime_config_t *cfg);

int roz_runtime_layout_check(const roz_runtime_layout_t *caller, char *err, size_t errlen)
{
    static const roz_runtime_layout_t mine = ROZ_RUNTIME_LAYOUT_INIT;
    static const struct {
        const char *name;
        size_t      at;
    } fields[] = {
        { "the layout version", offsetof(roz_runtime_layout_t, version) },
        { "ROZ_CFG_MAX_COMMANDS", offsetof(roz_runtime_layout_t, max_commands) },
        { "ROZ_CFG_MAX_STATES", offsetof(roz_runtime_layout_t, max_states) },
        { "ROZ_CFG_ERROR_LEN", offsetof(roz_runtime_layout_t, error_len) },
        { "ROZ_CFG_TELEMETRY_RING", offsetof(roz_runtime_layout_t, telemetry_ring) },
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
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
        uint32_t theirs, ours;
        memcpy(&theirs, (const char *)caller + fields[i].at, sizeof theirs);
        memcpy(&ours, (const char *)&mine + fields[i].at, sizeof ours);
        if (theirs != ours) {
            if (err != NULL && errlen > 0)
                snprintf(err, errlen,
                         "%s is %lu in the application, %lu in libroz_core: build both with the "
                         "same ROZ_CONFIG_FILE (and compiler settings)",
                         fields[i].name, (unsigned long)theirs, (unsigned long)ours);
            return ROZ_ECONFIG;
        }
    }
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
    memset(rt, 0, sizeof *rt);
    rt->cfg = *cfg;
    if (roz_filter_init(&rt->filter, m) != ROZ_OK ||
        roz_filter_set_margin(&rt->filter, cfg->position_margin) != ROZ_OK)
        return ROZ_EINVAL;
    uint64_t period_ns = 1000000000ull / m->control_rate_hz;
    if (rt->cfg.budget_ns == 0)
        rt->cfg.budget_ns = period_ns / 2u;
    if (rt->cfg.fuel_per_tick == 0) {
        rt->cfg.fuel_per_tick = (uint64_t)ROZ_CFG_FUEL_PER_SECOND / m->control_rate_hz;
        /* a default that rounds to nothing is refused, never "unmetered" */
        if (rt->cfg.fuel_per_tick == 0)
            return ROZ_EINVAL;
    }
    roz_monitor_init(&rt->monitor, "roz runtime", period_ns, cfg->log, cfg->log_ctx);
    rt->monitor.threshold_ns[ROZ_MON_PROCESS] = rt->cfg.budget_ns;
    for (int i = 0; i < 2; i++) {
        roz_controller_init(&rt->slot[i].ctrl);
        roz_abi_init(&rt->slot[i].abi, m, rt->slot[i].target, &rt->metrics);
    }
    atomic_init(&rt->active, -1);
    atomic_init(&rt->pending, -1);
    atomic_init(&rt->faults, 0u);
    atomic_init(&rt->estop_input, 0u);
    atomic_init(&rt->clear_request, 0u);
    roz_buffer_init(&rt->snapshot, rt->snapshot_slots, m->n_states > 0 ? m->n_states : 1u);
    for (uint16_t i = 0; i < m->n_states; i++)
        rt->state[i] = m->states[i].default_value;
    for (uint16_t i = 0; i < m->n_commands; i++)
        rt->out[i] = m->commands[i].default_value;
    return ROZ_OK;
}

int roz_runtime_load(roz_runtime_t *rt, const uint8_t *wasm, size_t len,
                     roz_verify_report_t *report)
{
    double *vstate = rt->verify_state;
    roz_verify_report_t local;
    roz_runtime_slot_t *s;
    int spare, rc;

    if (atomic_load(&rt->pending) != -1) {
        snprintf(rt->error, sizeof rt->error, "a controller swap is already pending");
        return ROZ_ESTATE;
    }
    spare = atomic_load(&rt->active) == 0 ? 1 : 0;
    s = &rt->slot[spare];
    if (report == NULL)
        report = &local;
    memset(report, 0, sizeof *report);
    rt->error[0] = '\0';

    /* 1. a separate instance for verification; its telemetry is discarded */
    rc = load_slot(rt, s, wasm, len, 1);
    s->abi.metrics = NULL;
    if (rc != ROZ_OK) {
        snprintf(rt->error, sizeof rt->error, "load: %s", roz_controller_error(&s->ctrl));
        rt->counters.swaps_refused++;
        return rc;
    }
    verify_state(rt, vstate);
    rc = verify_slot(rt, s, vstate, report);
    roz_controller_unload(&s->ctrl);
    if (rc != ROZ_OK) {
        rt->counters.swaps_refused++;
        return rc;
    }
    /* 2. a fresh instance to drive the robot from tick 0 */
    rc = load_slot(rt, s, wasm, len, 0);
    if (rc != ROZ_OK) {
        snprintf(rt->error, sizeof rt->error, "load: %s", roz_controller_error(&s->ctrl));
        rt->counters.swaps_refused++;
        return rc;
    }
    atomic_store(&rt->pending, spare);
    return ROZ_OK;
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
    const roz_manifest_t *m = rt->cfg.manifest;
    uint64_t t_start = now(rt), t0, t1;
    unsigned faults;
    roz_stop_t stop;
    int rc, active;

    rt->counters.ticks++;
    if (rt->cfg.monitor_jitter)
        roz_monitor_periodic(&rt->monitor, t_start);

    /* Hand-overs from other threads, at the tick boundary. The clear request
     * is taken first: clear_faults() schedules a rebuilt controller before
     * it asks for the clear, so seeing the request means seeing the swap. */
    unsigned clear = atomic_exchange(&rt->clear_request, 0u);
    int pending = atomic_load(&rt->pending);
    if (pending != -1) {
        atomic_store(&rt->active, pending);
        atomic_store(&rt->pending, -1);
        rt->ctrl_tick = 0;
        rt->counters.swaps++;
    }
    if (clear != 0u) {
        atomic_store(&rt->faults, 0u);
        rt->fault_msg[0] = '\0';
        rt->stale_count = 0;
    }
    active = atomic_load(&rt->active);

    /* 1. state snapshot */
    t0 = now(rt);
    rc = rt->cfg.port.ops->read(rt->cfg.port.self, rt->state, m->n_states);
    t1 = now(rt);
    roz_monitor_record(&rt->monitor, ROZ_MON_READ, t1 - t0, t1);
    if (rc == 1) {
        rt->have_state = 1;
        rt->stale_count = 0;
        roz_buffer_write(&rt->snapshot, rt->state, t1);
    } else {
        if (rc < 0 && rc != ROZ_ENOENT)
            rt->counters.read_errors++;
        if (!rt->have_state) {
            /* Waiting for the robot's first frame (a DDS peer may take a
             * while to be discovered) is not a fault: nothing is sent
             * meanwhile, and staleness counts from the first frame. Said
             * once, as a warning, when it lasts stale_ticks. */
            if (rt->counters.waiting_ticks + 1u == rt->cfg.stale_ticks) {
                char msg[96];
                snprintf(msg, sizeof msg,
                         "no state from the port yet after %u ticks; nothing is sent",
                         (unsigned)rt->cfg.stale_ticks);
                log_msg(rt, ROZ_LOG_WARN, msg);
            }
        } else {
            rt->counters.stale_reads++;
            if (rt->stale_count < UINT32_MAX)
                rt->stale_count++;
            if (rt->stale_count >= rt->cfg.stale_ticks) {
                char msg[96];
                snprintf(msg, sizeof msg, "no fresh state for %u ticks",
                         (unsigned)rt->stale_count);
                latch(rt, ROZ_FAULT_STALE, msg);
            }
            if (rc == ROZ_ELINK)
                latch(rt, ROZ_FAULT_LINK,
                      "port link fault: the robot restarted or came back after it was lost");
        }
    }
    if (atomic_load(&rt->estop_input) != 0u)
        latch(rt, ROZ_FAULT_ESTOP, "e-stop input");
    if (!rt->have_state) {
        /* Nothing is sent before the first state frame. */
        rt->counters.waiting_ticks++;
        return atomic_load(&rt->faults) != 0u ? ROZ_EFAULT : ROZ_OK;
    }

    /* 2. the controller, unless a fault is latched */
    faults = atomic_load(&rt->faults);
    stop = stop_mode(faults);
    double *target = NULL;
    if (active >= 0) {
        roz_runtime_slot_t *s = &rt->slot[active];
        target = s->target;
        if (stop == ROZ_STOP_NONE) {
            s->abi.state = rt->state;
            s->abi.tick = rt->ctrl_tick;
            t0 = now(rt);
            rc = roz_controller_process(&s->ctrl, rt->ctrl_tick);
            t1 = now(rt);
            rt->last_process_ns = t1 - t0;
            roz_monitor_record(&rt->monitor, ROZ_MON_PROCESS, t1 - t0, t1);
            rt->ctrl_tick++;
            rt->counters.controller_ticks++;
            rt->counters.last_fuel = roz_controller_fuel_used(&s->ctrl);
            if (rt->counters.last_fuel > rt->counters.max_fuel)
                rt->counters.max_fuel = rt->counters.last_fuel;
            if (roz_controller_stack_used(&s->ctrl) > rt->counters.max_stack)
                rt->counters.max_stack = roz_controller_stack_used(&s->ctrl);
            if (rc == ROZ_ETIMEDOUT) {
                latch(rt, ROZ_FAULT_OVERRUN, roz_controller_error(&s->ctrl));
            } else if (rc != ROZ_OK) {
                latch(rt, ROZ_FAULT_TRAP, roz_controller_error(&s->ctrl));
            } else if (rt->cfg.budget_ns != UINT64_MAX && t1 - t0 > rt->cfg.budget_ns) {
                char msg[128];
                snprintf(msg, sizeof msg, "process() took %llu us at tick %lld, budget %llu us",
                         (unsigned long long)((t1 - t0) / 1000u), (long long)(rt->ctrl_tick - 1),
                         (unsigned long long)(rt->cfg.budget_ns / 1000u));
                latch(rt, ROZ_FAULT_OVERRUN, msg);
            }
            if (s->abi.estop_requested) {
                /* The request is now a latched fault; consume it, or it would
                 * latch again on the first tick after the application clears. */
                s->abi.estop_requested = 0;
                latch(rt, ROZ_FAULT_ESTOP_REQUEST, "the controller called safety.request_estop");
            }
            stop = stop_mode(atomic_load(&rt->faults));
        }
    } else if (stop == ROZ_STOP_NONE) {
        /* No controller yet: hold the safe defaults, ramped. */
        stop = ROZ_STOP_CONTROLLED;
    }

    /* 3. the safety filter: the last word */
    roz_filter_apply(&rt->filter, target, rt->state, stop, rt->out);

    /* 4. the port */
    t0 = now(rt);
    rc = rt->cfg.port.ops->write(rt->cfg.port.self, rt->out, m->n_commands);
    t1 = now(rt);
    roz_monitor_record(&rt->monitor, ROZ_MON_WRITE, t1 - t0, t1);
    if (rc < 0)
        rt->counters.write_errors++;
    else
        rt->counters.writes++;
    roz_monitor_record(&rt->monitor, ROZ_MON_TICK, t1 - t_start, t1);
    return atomic_load(&rt->faults) != 0u ? ROZ_EFAULT : ROZ_OK;
}

void roz_runtime_estop(roz_runtime_t *rt)
{
    atomic_store(&rt->estop_input, 1u);
}

int roz_runtime_clear_faults(roz_runtime_t *rt)
{
    unsigned faults = atomic_load(&rt->faults);
    int active = atomic_load(&rt->active);

    atomic_store(&rt->estop_input, 0u);
    if (active >= 0 && ((faults & ROZ_FAULT_TRAP) || rt->slot[active].ctrl.spent)) {
        /* A trapped or budget-stopped instance is not reused: its memory may
         * be half-updated. Rebuild and re-verify it. */
        const roz_runtime_slot_t *s = &rt->slot[active];
        int rc = roz_runtime_load(rt, s->wasm, s->wasm_len, NULL);
        if (rc != ROZ_OK)
            return rc;
        rt->counters.rebuilds++;
    }
    atomic_store(&rt->clear_request, 1u);
    return ROZ_OK;
}

unsigned roz_runtime_faults(const roz_runtime_t *rt)
{
    return atomic_load(&rt->faults);
}

const char *roz_fault_name(unsigned fault_bit)
{
    for (int i = 0; i < ROZ_FAULT_KIND_COUNT; i++) {
        if (fault_bit == 1u << i)
            return fault_names[i];
    }
    return "?";
}

const char *roz_runtime_fault_message(const roz_runtime_t *rt)
{
    return rt->fault_msg;
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
    int active = atomic_load(&rt->active);
    return active >= 0 ? rt->slot[active].target : NULL;
}

void roz_runtime_deinit(roz_runtime_t *rt)
{
    for (int i = 0; i < 2; i++)
        roz_controller_unload(&rt->slot[i].ctrl);
    atomic_store(&rt->active, -1);
    atomic_store(&rt->pending, -1);
}
