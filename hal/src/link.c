/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/hal/link.h"

#include <string.h>

#include "roz/error.h"

void roz_link_init(roz_link_t *l, uint64_t lost_after_ns, uint32_t window)
{
    memset(l, 0, sizeof *l);
    l->lost_after_ns = lost_after_ns;
    l->window = window == 0u ? ROZ_LINK_DEFAULT_WINDOW
                             : (window > ROZ_LINK_MAX_WINDOW ? ROZ_LINK_MAX_WINDOW : window);
}

int roz_link_lost(const roz_link_t *l, uint64_t now_ns)
{
    return l->alive && l->lost_after_ns != 0u && now_ns - l->last_ns >= l->lost_after_ns;
}

static roz_link_verdict_t accept(roz_link_t *l, roz_link_verdict_t v, uint32_t seq, uint64_t now_ns)
{
    l->alive = 1;
    l->last_seq = seq;
    l->last_ns = now_ns;
    l->accepted++;
    return v;
}

roz_link_verdict_t roz_link_check(roz_link_t *l, int crc_ok, uint32_t seq, uint64_t now_ns)
{
    if (!crc_ok) {
        l->crc_errors++;
        return ROZ_LINK_BAD_CRC;
    }
    if (!l->alive)
        return accept(l, ROZ_LINK_FIRST, seq, now_ns);
    int lost = roz_link_lost(l, now_ns);
    /* serial number arithmetic: the signed distance modulo 2^32 */
    uint32_t ahead = seq - l->last_seq;
    if (ahead != 0u && ahead < 0x80000000u) {
        if (lost) {
            l->returns++;
            return accept(l, ROZ_LINK_RESTART, seq, now_ns);
        }
        l->missing += ahead - 1u;
        return accept(l, ROZ_LINK_FRESH, seq, now_ns);
    }
    /* Not newer: the last frame again, a replay, or a frame overtaken in
     * transit; dropped even after a silence, so an old frame never passes
     * for a peer that came back. Older frames in order are dropped too: a
     * peer that restarted and counts again from below its old sequence
     * cannot be told from old frames replayed in order or overtaken ones,
     * so it is taken for a replay until it passes its old sequence. */
    if (l->last_seq - seq <= l->window) {
        l->replays++;
        return ROZ_LINK_REPLAY;
    }
    l->restarts++;
    return accept(l, ROZ_LINK_RESTART, seq, now_ns);
}

const char *roz_link_verdict_name(roz_link_verdict_t v)
{
    switch (v) {
    case ROZ_LINK_FIRST:   return "first";
    case ROZ_LINK_FRESH:   return "fresh";
    case ROZ_LINK_BAD_CRC: return "bad crc";
    case ROZ_LINK_REPLAY:  return "replay";
    case ROZ_LINK_RESTART: return "restart";
    }
    return "unknown";
}

/* ---- the copy for other threads -------------------------------------------- */

/* The fields, each as two 32-bit words (low, high). */
enum { W_LOST, W_WINDOW, W_ALIVE, W_LAST_SEQ, W_LAST_NS, W_ACCEPTED, W_CRC, W_REPLAYS, W_RESTARTS,
       W_RETURNS, W_MISSING, W_COUNT };
_Static_assert(2 * W_COUNT == ROZ_LINK_SHARED_WORDS, "roz_link_shared_t carries every field");

void roz_link_shared_init(roz_link_shared_t *s)
{
    atomic_init(&s->seq, 0u);
    for (int i = 0; i < ROZ_LINK_SHARED_WORDS; i++)
        atomic_init(&s->words[i], 0u);
}

void roz_link_shared_publish(roz_link_shared_t *s, const roz_link_t *l)
{
    const uint64_t w[W_COUNT] = { l->lost_after_ns, l->window, (uint64_t)l->alive, l->last_seq,
                                  l->last_ns, l->accepted, l->crc_errors, l->replays,
                                  l->restarts, l->returns, l->missing };
    uint32_t q = atomic_load_explicit(&s->seq, memory_order_relaxed);

    atomic_store_explicit(&s->seq, q + 1u, memory_order_relaxed);
    atomic_thread_fence(memory_order_release);
    for (int i = 0; i < W_COUNT; i++) {
        atomic_store_explicit(&s->words[2 * i], (uint32_t)w[i], memory_order_relaxed);
        atomic_store_explicit(&s->words[2 * i + 1], (uint32_t)(w[i] >> 32), memory_order_relaxed);
    }
    atomic_store_explicit(&s->seq, q + 2u, memory_order_release);
}

int roz_link_shared_read(const roz_link_shared_t *s, roz_link_t *out)
{
    uint64_t w[W_COUNT];
    for (int tries = 0; tries < 1000; tries++) {
        uint32_t q0 = atomic_load_explicit(&s->seq, memory_order_acquire);
        for (int i = 0; i < W_COUNT; i++)
            w[i] = atomic_load_explicit(&s->words[2 * i], memory_order_relaxed) |
                   (uint64_t)atomic_load_explicit(&s->words[2 * i + 1], memory_order_relaxed)
                       << 32;
        atomic_thread_fence(memory_order_acquire);
        uint32_t q1 = atomic_load_explicit(&s->seq, memory_order_relaxed);
        memset(out, 0, sizeof *out);
        out->lost_after_ns = w[W_LOST];
        out->window = (uint32_t)w[W_WINDOW];
        out->alive = (int)w[W_ALIVE];
        out->last_seq = (uint32_t)w[W_LAST_SEQ];
        out->last_ns = w[W_LAST_NS];
        out->accepted = w[W_ACCEPTED];
        out->crc_errors = w[W_CRC];
        out->replays = w[W_REPLAYS];
        out->restarts = w[W_RESTARTS];
        out->returns = w[W_RETURNS];
        out->missing = w[W_MISSING];
        if (q0 == q1 && (q0 & 1u) == 0u)
            return ROZ_OK;
    }
    return ROZ_ESTATE;
}
