/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/buffer.h"

#include <string.h>

/* The exchanged word holds the middle slot's index and, when the producer
 * put a new frame there the consumer has not taken yet, the FRESH flag. The
 * release half of each exchange publishes the slot's contents; the acquire
 * half makes them visible to whoever takes the slot. */
#define FRESH 4u
#define INDEX_MASK 3u

void roz_buffer_init(roz_buffer_t *b, double *slots, uint32_t n)
{
    memset(slots, 0, 3u * (size_t)n * sizeof slots[0]);
    b->slots = slots;
    b->n = n;
    for (int i = 0; i < 3; i++) {
        b->seq[i] = 0;
        b->stamp_ns[i] = 0;
    }
    b->back = 0;
    b->produced = 0;
    b->front = 1;
    b->consumed_seq = 0;
    atomic_init(&b->middle.word, 2u);
}

double *roz_buffer_write_begin(roz_buffer_t *b)
{
    return &b->slots[(size_t)b->back * b->n];
}

uint64_t roz_buffer_write_commit(roz_buffer_t *b, uint64_t stamp_ns)
{
    uint32_t old;

    b->produced++;
    b->seq[b->back] = b->produced;
    b->stamp_ns[b->back] = stamp_ns;
    old = (uint32_t)atomic_exchange_explicit(&b->middle.word, b->back | FRESH,
                                             memory_order_acq_rel);
    b->back = old & INDEX_MASK;
    return b->produced;
}

uint64_t roz_buffer_write(roz_buffer_t *b, const double *values, uint64_t stamp_ns)
{
    memcpy(roz_buffer_write_begin(b), values, (size_t)b->n * sizeof values[0]);
    return roz_buffer_write_commit(b, stamp_ns);
}

int roz_buffer_read(roz_buffer_t *b, roz_buffer_frame_t *out)
{
    if (atomic_load_explicit(&b->middle.word, memory_order_relaxed) & FRESH) {
        uint32_t old = (uint32_t)atomic_exchange_explicit(&b->middle.word, b->front,
                                                          memory_order_acq_rel);
        b->front = old & INDEX_MASK;
    }
    out->values = &b->slots[(size_t)b->front * b->n];
    out->seq = b->seq[b->front];
    out->stamp_ns = b->stamp_ns[b->front];
    out->fresh = out->seq > b->consumed_seq;
    if (out->seq == 0)
        return ROZ_ENOENT;
    b->consumed_seq = out->seq;
    return out->fresh ? 1 : 0;
}
