/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/recorder.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

#include "fault_text.h"
#include "recorder_push.h"

/* ---- types ----------------------------------------------------------------
 *
 * A slot: the scalars of the record, the first fault's numbers and text (set
 * only when the faults changed), then n_states + n_inputs + 2 x n_commands
 * doubles (state, inputs, targets, applied). The
 * tick fills a slot the drain does not own (head - tail < capacity) and
 * publishes it with a release store of head; the drain reads it after an
 * acquire load of head and hands it back with a release store of tail. The
 * slots themselves are plain memory: only one side owns a slot at a time. */

typedef struct slot {
    roz_record_t     rec; /* pointers not used: the arrays follow */
    roz__fault_raw_t fault;
    char             fault_text[ROZ_CFG_ERROR_LEN];
    roz_port_truth_t truth; /* with ROZ_RECORD_TRUTH */
} slot_t;

#define INPUT_FLAGS                                                                          \
    (ROZ_RECORD_ESTOP_PRESS | ROZ_RECORD_CLEAR | ROZ_RECORD_SWAP | ROZ_RECORD_STAGE)

/* ---- private ------------------------------------------------------------- */

static size_t head_bytes(void)
{
    return (sizeof(slot_t) + 7u) & ~(size_t)7u;
}

static slot_t *slot_at(const roz_recorder_t *r, uint32_t i)
{
    return (slot_t *)(void *)(r->slots + (size_t)(i & (r->capacity - 1u)) * r->slot_bytes);
}

static double *slot_values(slot_t *s)
{
    return (double *)(void *)((unsigned char *)s + head_bytes());
}

/* @p n values of @p src into a slot at @p v, NaN where the record has none
 * (src NULL); the place after them. */
static double *put_values(double *v, const double *src, uint16_t n)
{
    if (src != NULL) {
        memcpy(v, src, (size_t)n * sizeof v[0]);
    } else {
        for (uint16_t i = 0; i < n; i++)
            v[i] = NAN;
    }
    return v + n;
}

/* ---- the tick ------------------------------------------------------------- */

int roz__recorder_wants_fault(const roz_recorder_t *r, uint32_t faults)
{
    return !r->any || faults != r->last_faults;
}

void roz__recorder_push(roz_recorder_t *r, const roz_record_t *rec,
                        const roz__fault_raw_t *first)
{
    const roz_manifest_t *m = r->m;
    uint32_t flags = rec->flags;
    int changed = roz__recorder_wants_fault(r, rec->faults);
    uint32_t level = flags & ROZ_RECORD_ESTOP_LEVEL;
    int released = level != r->last_level;

    /* decimation: every Nth tick, and every tick where something happened */
    int due = r->phase == 0u;
    r->phase = due ? r->decimation - 1u : r->phase - 1u;
    r->last_level = level;
    if (!due && !changed && !released && (flags & INPUT_FLAGS) == 0u)
        return;

    uint32_t head = atomic_load_explicit(&r->head, memory_order_relaxed);
    uint32_t tail = atomic_load_explicit(&r->tail, memory_order_acquire);
    if (head - tail >= r->capacity) {
        /* last_faults stays: the next record that gets in carries the change */
        atomic_store_explicit(&r->dropped,
                              atomic_load_explicit(&r->dropped, memory_order_relaxed) + 1u,
                              memory_order_relaxed);
        return;
    }
    slot_t *s = slot_at(r, head);
    double *v = slot_values(s);
    s->rec = *rec;
    s->rec.fault_message = NULL;
    s->rec.truth = NULL;
    if (rec->truth != NULL)
        s->truth = *rec->truth;
    else
        s->rec.flags &= ~(uint32_t)ROZ_RECORD_TRUTH;
    if (changed) {
        s->rec.flags |= ROZ_RECORD_FAULT_CHANGED;
        /* the runtime's copy of its first fault, made for this record */
        s->fault.bit = first != NULL ? first->bit : 0u;
        for (int k = 0; k < 4; k++)
            s->fault.num[k] = first != NULL ? first->num[k] : 0u;
        size_t i = 0;
        for (; first != NULL && first->text != NULL && i + 1u < sizeof s->fault_text; i++) {
            char c = first->text[i];
            if (c == '\0')
                break;
            s->fault_text[i] = c;
        }
        s->fault_text[i] = '\0';
        r->last_faults = rec->faults;
        r->any = 1;
    }
    v = put_values(v, rec->state, m->n_states);
    v = put_values(v, rec->inputs, m->n_inputs);
    v = put_values(v, rec->target, m->n_commands);
    put_values(v, rec->applied, m->n_commands);
    atomic_store_explicit(&r->recorded,
                          atomic_load_explicit(&r->recorded, memory_order_relaxed) + 1u,
                          memory_order_relaxed);
    atomic_store_explicit(&r->head, head + 1u, memory_order_release);
}

/* ---- public --------------------------------------------------------------- */

size_t roz_recorder_slot_bytes(const roz_manifest_t *m)
{
    if (m == NULL)
        return 0;
    return head_bytes() +
           ((size_t)m->n_states + (size_t)m->n_inputs + 2u * (size_t)m->n_commands) *
               sizeof(double);
}

int roz_recorder_init(roz_recorder_t *r, const roz_manifest_t *m, void *storage, size_t bytes,
                      uint32_t decimation)
{
    if (r == NULL || m == NULL || storage == NULL || ((uintptr_t)storage & 7u) != 0u)
        return ROZ_EINVAL;
    size_t slot = roz_recorder_slot_bytes(m);
    size_t n = bytes / slot;
    if (n < 2u)
        return ROZ_EINVAL;
    uint32_t cap = 1u;
    while ((size_t)cap * 2u <= n && cap < (1u << 30))
        cap *= 2u;
    memset(r, 0, sizeof *r);
    r->m = m;
    r->slots = (unsigned char *)storage;
    r->slot_bytes = slot;
    r->capacity = cap;
    r->decimation = decimation == 0u ? 1u : decimation;
    atomic_init(&r->head, 0u);
    atomic_init(&r->tail, 0u);
    atomic_init(&r->dropped, 0u);
    atomic_init(&r->recorded, 0u);
    return ROZ_OK;
}

uint32_t roz_recorder_capacity(const roz_recorder_t *r)
{
    return r->capacity;
}

uint32_t roz_recorder_decimation(const roz_recorder_t *r)
{
    return r->decimation;
}

size_t roz_recorder_drain(roz_recorder_t *r, roz_record_sink_fn sink, void *ctx, size_t max)
{
    const roz_manifest_t *m = r->m;
    char msg[ROZ_CFG_ERROR_LEN + 64];
    size_t n = 0;
    uint32_t tail = atomic_load_explicit(&r->tail, memory_order_relaxed);
    uint32_t head = atomic_load_explicit(&r->head, memory_order_acquire);

    /* bounded by what was queued when the drain started */
    while (tail != head && (max == 0u || n < max)) {
        slot_t *s = slot_at(r, tail);
        double *v = slot_values(s);
        roz_record_t rec = s->rec;
        rec.state = v;
        rec.inputs = m->n_inputs > 0u ? v + m->n_states : NULL;
        rec.target = v + m->n_states + m->n_inputs;
        rec.applied = rec.target + m->n_commands;
        rec.truth = (rec.flags & ROZ_RECORD_TRUTH) ? &s->truth : NULL;
        if (rec.flags & ROZ_RECORD_FAULT_CHANGED) {
            msg[0] = '\0';
            if (rec.faults != 0u) {
                s->fault.text = s->fault_text;
                uint64_t num[4];
                for (int k = 0; k < 4; k++)
                    num[k] = s->fault.num[k];
                roz__fault_format(msg, sizeof msg, s->fault.bit, num, s->fault.text);
            }
            rec.fault_message = msg;
        }
        int stop = sink != NULL ? sink(ctx, &rec) : 0;
        tail++;
        atomic_store_explicit(&r->tail, tail, memory_order_release);
        n++;
        if (stop)
            break;
    }
    return n;
}

uint32_t roz_recorder_dropped(const roz_recorder_t *r)
{
    return atomic_load_explicit(&r->dropped, memory_order_relaxed);
}

uint32_t roz_recorder_recorded(const roz_recorder_t *r)
{
    return atomic_load_explicit(&r->recorded, memory_order_relaxed);
}

uint64_t roz_recorder_hash(const void *bytes, size_t len)
{
    const unsigned char *p = (const unsigned char *)bytes;
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i < len; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}
