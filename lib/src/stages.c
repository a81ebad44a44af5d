/* SPDX-License-Identifier: Apache-2.0 */
/* The deploy sequence and the hand-over's gain hold (roz/stages.h). */
#include "roz/stages.h"

#include <math.h>
#include <string.h>

#include "roz/error.h"
#include "roz/format.h"

#include "stages_internal.h"

/* ---- private ------------------------------------------------------------- */

static const char *const names[ROZ_STAGE_COUNT] = { "none", "zero", "move", "hold", "run", "stop" };

static int finite(double v)
{
    return v - v == 0.0; /* NaN unless finite */
}

static double clamp(const roz_channel_t *c, double v)
{
    return v < c->min ? c->min : v > c->max ? c->max : v;
}

/* A position command's measured position, within the command; NaN unknown. */
static double measured(const roz_stages_t *s, uint16_t i, const double *state)
{
    const roz_channel_t *c = &s->m->commands[i];
    if (c->type != ROZ_IF_POSITION || c->position_state < 0 ||
        c->position_state >= (int32_t)s->m->n_states)
        return NAN;
    double q = state[c->position_state];
    return finite(q) ? clamp(c, q) : NAN;
}

/* Whether @p to may follow @p from (requests and inputs alike). */
static int allowed(int from, int to, int have_controller)
{
    switch (to) {
    case ROZ_STAGE_STOP: return from != ROZ_STAGE_STOP;
    case ROZ_STAGE_MOVE: return from == ROZ_STAGE_ZERO || from == ROZ_STAGE_RUN;
    case ROZ_STAGE_RUN:  return from == ROZ_STAGE_HOLD && have_controller;
    case ROZ_STAGE_ZERO: return from == ROZ_STAGE_STOP;
    default:             return 0; /* HOLD follows MOVE's end; NONE never */
    }
}

static int pressed(const roz_stages_t *s, int32_t k, const double *inputs)
{
    return k >= 0 && k < (int32_t)s->m->n_inputs && inputs[k] >= ROZ_STAGES_PRESSED;
}

/* What ZERO (@p damping 0) and STOP send channel @p i that is not a
 * position command: no stiffness, no torque, no velocity, within the
 * channel. */
static double limp(const roz_channel_t *c, double damping)
{
    switch (c->type) {
    case ROZ_IF_DAMPING:   return clamp(c, damping);
    case ROZ_IF_VELOCITY:
    case ROZ_IF_EFFORT:
    case ROZ_IF_STIFFNESS: return clamp(c, 0.0);
    default:               return c->default_value;
    }
}

/* Enter @p to: MOVE records where it starts from. A position command
 * blends from the measured position (from the command on the wire, @p out,
 * when unpaired or unknown; NULL before the first command went out: the
 * port's start-up, zero torque), so the stand's gains apply from the first
 * tick without a torque step (kp * (target - measured) starts at 0), as
 * Unitree's deploy does; every other channel takes the stand's value at
 * once, the filter's rate cap its only ramp. */
static void enter(roz_stages_t *s, int to, const double *state, const double *out)
{
    if (to == ROZ_STAGE_MOVE) {
        for (uint16_t i = 0; i < s->m->n_commands; i++) {
            const roz_channel_t *c = &s->m->commands[i];
            double q = measured(s, i, state);
            double was = out != NULL ? out[i] : limp(c, 0.0);
            s->from[i] = c->type != ROZ_IF_POSITION ? s->stand[i] : finite(q) ? q : was;
        }
        s->elapsed = 0;
    }
    s->stage = to;
    s->counters.transitions++;
    atomic_store_explicit(&s->published, to, memory_order_relaxed);
}

/* ---- public -------------------------------------------------------------- */

const char *roz_stage_name(int stage)
{
    return stage >= 0 && stage < ROZ_STAGE_COUNT ? names[stage] : NULL;
}

int roz_stage_from_name(const char *name)
{
    for (int i = 0; name != NULL && i < ROZ_STAGE_COUNT; i++)
        if (strcmp(name, names[i]) == 0)
            return i;
    return -1;
}

int roz_stages_check(const roz_manifest_t *m, const roz_stages_config_t *c, char *err,
                     size_t errlen)
{
    char dummy[1];
    if (err == NULL || errlen == 0) {
        err = dummy;
        errlen = sizeof dummy;
    }
    err[0] = '\0';
    if (m == NULL || c == NULL || c->stand == NULL) {
        roz_format(err, errlen, "no stand commands given");
        return ROZ_EINVAL;
    }
    if (!(c->move_s > 0.0 && c->move_s <= 60.0)) {
        roz_format(err, errlen, "move_s: %g: must be above 0 s and at most 60 s", c->move_s);
        return ROZ_EINVAL;
    }
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *ch = &m->commands[i];
        double v = c->stand[i];
        if (!finite(v) || v < ch->min || v > ch->max) {
            roz_format(err, errlen, "stand[%u] \"%s\": %g: outside its limits [%g, %g]",
                       (unsigned)i, ch->name, v, ch->min, ch->max);
            return ROZ_EINVAL;
        }
        if (ch->type == ROZ_IF_DAMPING &&
            (!finite(c->stop_damping) || c->stop_damping < ch->min || c->stop_damping > ch->max)) {
            roz_format(err, errlen, "stop_damping: %g: outside \"%s\"'s limits [%g, %g]",
                       c->stop_damping, ch->name, ch->min, ch->max);
            return ROZ_EINVAL;
        }
    }
    const int32_t in[4] = { c->start, c->run, c->stand_input, c->stop };
    static const char *const key[4] = { "start", "run", "stand", "stop" };
    for (int k = 0; k < 4; k++) {
        if (in[k] < -1 || in[k] >= (int32_t)m->n_inputs) {
            roz_format(err, errlen, "%s: input %ld: the manifest has %u inputs", key[k],
                       (long)in[k], (unsigned)m->n_inputs);
            return ROZ_EINVAL;
        }
    }
    return ROZ_OK;
}

void roz__stages_init(roz_stages_t *s, const roz_manifest_t *m)
{
    memset(s, 0, sizeof *s);
    s->m = m;
    s->stage = ROZ_STAGE_NONE;
    s->taken = -1;
    atomic_init(&s->request, -1);
    atomic_init(&s->published, ROZ_STAGE_NONE);
    for (uint16_t i = 0; i < m->n_commands; i++) {
        s->target[i] = m->commands[i].default_value;
        s->held[i] = NAN;
    }
}

void roz__stages_configure(roz_stages_t *s, const roz_stages_config_t *c, uint32_t rate_hz)
{
    s->cfg = *c;
    memcpy(s->stand, c->stand, (size_t)s->m->n_commands * sizeof s->stand[0]);
    s->cfg.stand = s->stand;
    double ticks = c->move_s * (double)rate_hz + 0.5;
    s->move_ticks = ticks < 1.0 ? 1u : (uint32_t)ticks;
    s->stage = ROZ_STAGE_ZERO;
    atomic_store(&s->published, ROZ_STAGE_ZERO);
}

int roz__stages_step(roz_stages_t *s, const double *inputs, const double *state,
                     const double *out, int have_controller, int faulted, int *entered)
{
    int from = s->stage, to = -1;
    *entered = 0;
    if (from == ROZ_STAGE_NONE)
        return from;
    int req = atomic_load_explicit(&s->request, memory_order_relaxed) != -1
                  ? atomic_exchange(&s->request, -1)
                  : -1;
    s->taken = req;
    if (req != -1) {
        if (allowed(from, req, have_controller) && (!faulted || req == ROZ_STAGE_STOP))
            to = req;
        else
            s->counters.refused++;
    }
    if (to == -1) {
        /* the buttons, as levels (Unitree's deploy reads them so): stop from
         * anywhere, start in ZERO, run in HOLD, stand in RUN */
        if (pressed(s, s->cfg.stop, inputs) && from != ROZ_STAGE_STOP)
            to = ROZ_STAGE_STOP;
        else if (faulted)
            to = -1;
        else if (from == ROZ_STAGE_ZERO && pressed(s, s->cfg.start, inputs))
            to = ROZ_STAGE_MOVE;
        else if (from == ROZ_STAGE_HOLD && have_controller && pressed(s, s->cfg.run, inputs))
            to = ROZ_STAGE_RUN;
        else if (from == ROZ_STAGE_RUN && pressed(s, s->cfg.stand_input, inputs))
            to = ROZ_STAGE_MOVE;
        else if (from == ROZ_STAGE_MOVE && s->elapsed >= s->move_ticks)
            to = ROZ_STAGE_HOLD;
    }
    if (to != -1) {
        enter(s, to, state, out);
        *entered = 1;
    }
    return s->stage;
}

const double *roz__stages_commands(roz_stages_t *s, const double *state)
{
    const roz_manifest_t *m = s->m;
    double alpha;

    if (s->stage == ROZ_STAGE_HOLD)
        return s->stand;
    if (s->stage == ROZ_STAGE_MOVE) {
        alpha = (double)s->elapsed / (double)s->move_ticks;
        for (uint16_t i = 0; i < m->n_commands; i++)
            s->target[i] = s->from[i] + alpha * (s->stand[i] - s->from[i]);
        if (s->elapsed < s->move_ticks)
            s->elapsed++;
        return s->target;
    }
    /* ZERO and STOP: no stiffness and no torque; STOP damps */
    double damping = s->stage == ROZ_STAGE_STOP ? s->cfg.stop_damping : 0.0;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        double v = limp(c, damping);
        if (c->type == ROZ_IF_POSITION) {
            v = c->position_state >= 0 ? measured(s, i, state) : c->default_value;
            if (!finite(v))
                v = s->target[i]; /* unknown: as last sent */
        }
        s->target[i] = v;
    }
    return s->target;
}

void roz__stages_handover(roz_stages_t *s, const double *out, uint32_t rate_hz)
{
    const roz_manifest_t *m = s->m;
    uint64_t ticks = (uint64_t)ROZ_CFG_HANDOVER_MS * rate_hz / 1000u;

    s->hold_left = ticks > UINT32_MAX ? UINT32_MAX : (uint32_t)ticks;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        roz_interface_t t = m->commands[i].type;
        s->held[i] = t == ROZ_IF_STIFFNESS || t == ROZ_IF_DAMPING ? out[i] : NAN;
    }
    if (s->hold_left != 0)
        s->counters.handovers++;
}

const double *roz__stages_hold_gains(roz_stages_t *s, const double *target)
{
    const roz_manifest_t *m = s->m;

    if (s->hold_left == 0)
        return target;
    memcpy(s->target, target, (size_t)m->n_commands * sizeof s->target[0]);
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (!finite(s->held[i]))
            continue;
        if (target[i] >= s->held[i]) {
            s->held[i] = NAN; /* the incoming controller commands its own */
            continue;
        }
        s->target[i] = s->held[i];
        s->counters.handover_raised++;
    }
    if (--s->hold_left == 0)
        for (uint16_t i = 0; i < m->n_commands; i++)
            s->held[i] = NAN;
    return s->target;
}
