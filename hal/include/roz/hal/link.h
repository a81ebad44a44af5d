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
 * | ROZ_LINK_REPLAY    | not newer and at most `window` behind: the last frame again, a replay, a frame overtaken in transit; also after a silence | drops it |
 * | ROZ_LINK_RESTART   | newer, after the peer was silent for `lost_after_ns` or more; or more than `window` behind: the peer came back, or restarted | accepts it as the new peer's first frame and reports a link fault: read() returns ROZ_ELINK once, the runtime latches ROZ_FAULT_LINK (an immediate stop). A hardware port also starts its safe start-up layers (roz/port.h) over for the new peer. |
 *
 * What the sequence cannot tell apart, and how it errs:
 * - A peer that restarts within `lost_after_ns` with its old sequence at
 *   most `window` (counting from 0: in its first `window` frames) is taken
 *   for a replay until its sequence passes the old one: its frames are
 *   dropped meanwhile, so the runtime's STALE fault stops the robot unless
 *   the restart and the dropped frames together last less than stale_ticks.
 *   (Taking older frames in order for a restart instead would let replayed
 *   old frames pass, and stop the robot on two frames overtaken in transit.)
 * - A peer that restarts within `lost_after_ns` and numbers its frames on
 *   from above its old sequence looks like one that skipped frames.
 * - Old frames replayed in order from more than `window` back look like a
 *   restarted peer: LINK latches, and after the application clears it they
 *   are its stream. Replay by an attacker needs an authenticated transport.
 * A port whose robot reports a boot counter or session id should check it.
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

#include "roz/atomic.h"
#include "roz/error.h"
#include "roz/port.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A frame this far behind the last accepted one is a replay; further is a restart. */
#define ROZ_LINK_DEFAULT_WINDOW 64u
/** The largest window (half the sequence space, less a margin). */
#define ROZ_LINK_MAX_WINDOW 0x40000000u

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
    /* counters */
    uint64_t accepted;      /**< FIRST + FRESH + RESTART */
    uint64_t crc_errors;    /**< BAD_CRC */
    uint64_t replays;       /**< REPLAY */
    uint64_t restarts;      /**< RESTART: the sequence went back beyond the window */
    uint64_t returns;       /**< RESTART: a newer frame after a silence */
    uint64_t missing;       /**< sequence numbers skipped between accepted frames */
} roz_link_t;

/**
 * @brief Start (or forget) a link.
 * @param lost_after_ns silence that makes the peer lost; 0 = never by time
 * @param window        see ROZ_LINK_DEFAULT_WINDOW; 0 = the default; at most
 *                      ROZ_LINK_MAX_WINDOW (larger is clamped)
 * Context: start-up (the port's open).
 */
void roz_link_init(roz_link_t *l, uint64_t lost_after_ns, uint32_t window);

/**
 * @brief Judge one received frame.
 * @param crc_ok  whether the frame's CRC matched (a bad frame's sequence is
 *                not trusted and not looked at)
 * @param seq     the frame's sequence number
 * @param now_ns  the receive time, monotonic
 * Context: the port's receive path (one thread); RT-safe; O(1).
 */
roz_link_verdict_t roz_link_check(roz_link_t *l, int crc_ok, uint32_t seq, uint64_t now_ns);

/** @brief Whether the peer has been silent for lost_after_ns at @p now_ns.
 *  Context: the thread that calls roz_link_check(); RT-safe. */
int roz_link_lost(const roz_link_t *l, uint64_t now_ns);

/** 32-bit words of a roz_link_t's fields in a roz_link_shared_t. */
#define ROZ_LINK_SHARED_WORDS 22

/**
 * A consistent copy of a roz_link_t for other threads, when the checks run
 * on a port's receive thread: that thread publishes after each check, any
 * thread reads. Published under a sequence counter (odd while the writer
 * updates) as relaxed atomic 32-bit words (64-bit atomics are not lock-free
 * on 32-bit microcontrollers), so a reader never races and never blocks the
 * writer.
 */
typedef struct roz_link_shared {
    ROZ_ATOMIC(uint32_t) seq;
    ROZ_ATOMIC(uint32_t) words[ROZ_LINK_SHARED_WORDS];
} roz_link_shared_t;

/** @brief Zero the copy (before either thread uses it). */
void roz_link_shared_init(roz_link_shared_t *s);

/** @brief Publish @p l. Context: the one thread that runs the checks;
 *  RT-safe, wait-free. */
void roz_link_shared_publish(roz_link_shared_t *s, const roz_link_t *l);

/**
 * @brief Copy the last published state into @p out.
 * @retval ROZ_OK     a consistent copy
 * @retval ROZ_ESTATE the writer kept updating it (1000 tries); @p out holds
 *                    the last try
 * Context: any thread; never blocks the writer.
 */
int roz_link_shared_read(const roz_link_shared_t *s, roz_link_t *out);

/** @brief "first", "fresh", "bad crc", "replay", "restart".
 *  Context: any. */
const char *roz_link_verdict_name(roz_link_verdict_t v);

/** @brief @p l's counters as a port reports them (roz_port_link_counters()),
 *  with @p malformed: the frames the port dropped before the link checks
 *  because they had not the expected shape (0 for a port with a CRC).
 *  Context: any. */
static inline void roz_link_port_counters(const roz_link_t *l, uint64_t malformed,
                                          roz_port_link_counters_t *out)
{
    out->accepted = l->accepted;
    out->crc_errors = l->crc_errors;
    out->replays = l->replays;
    out->missing = l->missing;
    out->restarts = l->restarts;
    out->returns = l->returns;
    out->malformed = malformed;
}

#ifdef __cplusplus
}
#endif

#endif /* ROZ_HAL_LINK_H */
