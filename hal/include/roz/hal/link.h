/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/hal/link.h
 * @brief The checks a port runs on every frame it receives from its peer
 *        (the robot), before the frame may reach the state buffer.
 *
 * A frame carries a CRC and a sequence number (the G1's LowState tick, a
 * ROS 2 header's sequence, the loopback's frame counter). roz_link_check()
 * takes the CRC's verdict and the sequence number and decides:
 *
 * | verdict            | when                                            | the port    |
 * |--------------------|-------------------------------------------------|-------------|
 * | ROZ_LINK_FIRST     | the first good frame since roz_link_init()       | accepts it; arms its safe start-up |
 * | ROZ_LINK_FRESH     | newer than the last accepted frame               | accepts it  |
 * | ROZ_LINK_BAD_CRC   | the CRC failed                                   | drops it    |
 * | ROZ_LINK_REPLAY    | the last accepted frame again, or a lone frame at most `window` behind (overtaken in transit), also after a silence | drops it |
 * | ROZ_LINK_RESTART   | newer, after the peer was silent for `lost_after_ns` or more; or more than `window` behind; or the ROZ_LINK_RESTART_RUN-th of older frames numbered one after the other with nothing newer between: the peer came back, or restarted and counts again from 0 | accepts it as the new peer's first frame and reports a link fault: read() returns ROZ_ELINK once, the runtime latches ROZ_FAULT_LINK (an immediate stop). A hardware port also starts its safe start-up layers (roz/hal/port.h) over for the new peer. |
 *
 * Not detected: a peer that restarts within `lost_after_ns` and numbers its
 * frames on from above its old sequence (it looks like one that skipped
 * frames). A replayed old frame never passes for fresh state, not even
 * after a silence; old frames replayed in order are reported as a restart.
 *
 * Sequence numbers are compared modulo 2^32 (serial number arithmetic), so
 * a counter wrapping around is not a restart. Dropped frames show as gaps,
 * counted in `missing`.
 *
 * One roz_link_t per direction and peer, used by one thread (the port's
 * receive thread or the tick). Portable: no OS, no heap, O(1).
 */
#ifndef ROZ_HAL_LINK_H
#define ROZ_HAL_LINK_H

#include "roz/config.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** A lone frame this far behind the last accepted one is a replay; further is a restart. */
#define ROZ_LINK_DEFAULT_WINDOW 64u
/** The largest window (half the sequence space, less a margin). */
#define ROZ_LINK_MAX_WINDOW 0x40000000u
/** Older frames numbered one after the other that make a restart. */
#define ROZ_LINK_RESTART_RUN 2u

typedef enum roz_link_verdict {
    ROZ_LINK_FIRST = 0, /**< accept: the first frame of this peer */
    ROZ_LINK_FRESH,     /**< accept */
    ROZ_LINK_BAD_CRC,   /**< drop */
    ROZ_LINK_REPLAY,    /**< drop */
    ROZ_LINK_RESTART,   /**< accept as the first frame of a restarted peer; report */
} roz_link_verdict_t;

/** Link state and counters; fields read-only outside link.c. */
typedef struct roz_link {
    uint64_t lost_after_ns; /**< silence after which the peer counts as lost */
    uint32_t window;        /**< see ROZ_LINK_DEFAULT_WINDOW */
    int      alive;         /**< a frame has been accepted since init */
    uint32_t last_seq;      /**< sequence of the last accepted frame */
    uint64_t last_ns;       /**< when it was accepted */
    uint32_t behind_run;    /**< older frames in order since the last accepted one */
    uint32_t behind_seq;    /**< the last of them */
    /* counters */
    uint64_t accepted;      /**< FIRST + FRESH + RESTART */
    uint64_t crc_errors;    /**< BAD_CRC */
    uint64_t replays;       /**< REPLAY */
    uint64_t restarts;      /**< RESTART: the sequence went back (beyond the window, or counting again) */
    uint64_t returns;       /**< RESTART: a newer frame after a silence */
    uint64_t missing;       /**< sequence numbers skipped between accepted frames */
} roz_link_t;

/**
 * @brief Start (or forget) a link.
 * @param lost_after_ns silence that makes the peer lost; 0 = never by time
 * @param window        see ROZ_LINK_DEFAULT_WINDOW; 0 = the default; at most
 *                      ROZ_LINK_MAX_WINDOW (larger is clamped)
 */
void roz_link_init(roz_link_t *l, uint64_t lost_after_ns, uint32_t window);

/**
 * @brief Judge one received frame.
 * @param crc_ok  whether the frame's CRC matched (a bad frame's sequence is
 *                not trusted and not looked at)
 * @param seq     the frame's sequence number
 * @param now_ns  the receive time, monotonic
 */
roz_link_verdict_t roz_link_check(roz_link_t *l, int crc_ok, uint32_t seq, uint64_t now_ns);

/** @brief Whether the peer has been silent for lost_after_ns at @p now_ns. */
int roz_link_lost(const roz_link_t *l, uint64_t now_ns);

/** @brief "first", "fresh", "bad crc", "replay", "restart". */
const char *roz_link_verdict_name(roz_link_verdict_t v);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_HAL_LINK_H */
