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
