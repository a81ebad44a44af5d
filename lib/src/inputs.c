/* SPDX-License-Identifier: Apache-2.0 */
/* Operator inputs (roz/inputs.h). */
#include "roz/inputs.h"

#include <math.h>
#include <string.h>

#include "roz/error.h"

static void store(roz_input_slot_t *s, double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    atomic_store_explicit(&s->lo, (uint32_t)b, memory_order_relaxed);
    atomic_store_explicit(&s->hi, (uint32_t)(b >> 32), memory_order_relaxed);
}

static uint64_t bits_of(double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}

static double double_of(uint64_t b)
{
    double x;
    memcpy(&x, &b, sizeof x);
    return x;
}

void roz_inputs_init(roz_inputs_t *in, const roz_manifest_t *m)
{
    in->ch = m->inputs;
    in->rule = m->input_rules;
    in->n = m->inputs != NULL && m->input_rules != NULL ? m->n_inputs : 0u;
    memset(&in->counters, 0, sizeof in->counters);
    for (uint16_t k = 0; k < in->n; k++) {
        roz_input_slot_t *s = &in->slot[k];
        uint64_t b = bits_of(in->ch[k].default_value);
        atomic_init(&s->lo, (uint32_t)b);
        atomic_init(&s->hi, (uint32_t)(b >> 32));
        atomic_init(&s->seq, 0u);
        s->seen = 0;
        s->fresh = 0;
        s->taken_ns = 0;
        s->target = in->ch[k].default_value;
        s->value = in->ch[k].default_value;
    }
}

int roz_inputs_set(roz_inputs_t *in, uint32_t k, double value)
{
    if (in == NULL || k >= in->n)
        return ROZ_EINVAL;
    roz_input_slot_t *s = &in->slot[k];
    uint32_t seq = atomic_load_explicit(&s->seq, memory_order_relaxed);
    /* claim: even -> odd; another writer in the middle of its set wins */
    if ((seq & 1u) != 0u ||
        !atomic_compare_exchange_strong_explicit(&s->seq, &seq, seq + 1u, memory_order_acquire,
                                                 memory_order_relaxed))
        return ROZ_ESTATE;
    atomic_thread_fence(memory_order_release); /* the odd seq before the words */
    store(s, value);
    /* release: a tick that sees the even seq sees these words */
    atomic_store_explicit(&s->seq, seq + 2u, memory_order_release);
    return ROZ_OK;
}

/* The inputs whose source is a field of device @p d, from @p r (a remote)
 * or @p t (a twist). */
static int set_device(roz_inputs_t *in, roz_operator_device_t d, const roz_operator_remote_t *r,
                      const roz_operator_twist_t *t)
{
    int rc = ROZ_OK;
    for (uint16_t k = 0; k < in->n; k++) {
        const roz_input_rule_t *c = &in->rule[k];
        if (roz_operator_field_device(c->source) != d)
            continue;
        double v = d == ROZ_OPERATOR_DEVICE_REMOTE ? roz_operator_remote_field(r, c->source)
                                                   : roz_operator_twist_field(t, c->source);
        if (roz_inputs_set(in, k, c->scale * v) != ROZ_OK)
            rc = ROZ_ESTATE;
    }
    return rc;
}

int roz_inputs_remote(roz_inputs_t *in, const roz_operator_remote_t *r)
{
    return set_device(in, ROZ_OPERATOR_DEVICE_REMOTE, r, NULL);
}

int roz_inputs_twist(roz_inputs_t *in, const roz_operator_twist_t *t)
{
    return set_device(in, ROZ_OPERATOR_DEVICE_TWIST, NULL, t);
}

void roz_inputs_tick(roz_inputs_t *in, uint64_t now_ns, double *out)
{
    for (uint16_t k = 0; k < in->n; k++) {
        const roz_channel_t *c = &in->ch[k];
        roz_input_slot_t *s = &in->slot[k];
        uint32_t seq = atomic_load_explicit(&s->seq, memory_order_acquire);
        uint64_t stale_ns = (uint64_t)in->rule[k].stale_after_ms * 1000000u;
        int taken = 0;
        double v = 0.0;

        if (seq != s->seen && (seq & 1u) == 0u) {
            uint64_t lo = atomic_load_explicit(&s->lo, memory_order_relaxed);
            uint64_t hi = atomic_load_explicit(&s->hi, memory_order_relaxed);
            atomic_thread_fence(memory_order_acquire); /* the words before the re-check */
            /* unchanged while read: a whole value (else: at the next tick) */
            taken = atomic_load_explicit(&s->seq, memory_order_relaxed) == seq;
            v = double_of(lo | hi << 32);
        }
        if (taken) {
            s->seen = seq;
            if (!isfinite(v)) {
                in->counters.nonfinite++; /* refused: the input keeps its target */
            } else {
                if (v < c->min || v > c->max) {
                    in->counters.clamped++;
                    v = v < c->min ? c->min : c->max;
                }
                s->target = v;
                s->fresh = 1;
                s->taken_ns = now_ns;
            }
        }
        if (s->fresh && now_ns > s->taken_ns && now_ns - s->taken_ns > stale_ns) {
            s->fresh = 0;
            s->target = c->default_value;
            in->counters.stale++;
        }
        /* at most max_rate a tick (above 0 on every input: the manifest's
         * rule), landing on the target exactly */
        double d = s->target - s->value;
        if (c->max_rate > 0.0 && fabs(d) > c->max_rate) {
            s->value += d > 0.0 ? c->max_rate : -c->max_rate;
            in->counters.rate_caps++;
        } else {
            s->value = s->target;
        }
        out[k] = s->value;
    }
}
