/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/hal/link.h"

#include <string.h>

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
    l->behind_run = 0;
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
    uint32_t behind = l->last_seq - seq;
    if (behind == 0u) {
        /* the last frame again: a duplicate */
        l->behind_run = 0;
        l->replays++;
        return ROZ_LINK_REPLAY;
    }
    if (behind <= l->window) {
        /* Older frames, one after the other, with nothing newer between:
         * a peer counting again from below its old sequence (it restarted),
         * or old frames replayed in order. Either way not the stream the
         * port was following. A lone older frame is one overtaken in
         * transit. */
        l->behind_run = l->behind_run > 0u && seq == l->behind_seq + 1u ? l->behind_run + 1u : 1u;
        l->behind_seq = seq;
        if (l->behind_run >= ROZ_LINK_RESTART_RUN) {
            l->restarts++;
            return accept(l, ROZ_LINK_RESTART, seq, now_ns);
        }
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
