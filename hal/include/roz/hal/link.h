/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/hal/link.h
 * @brief The checks a port runs on every frame it receives from its peer
 *        (the robot), before the frame may reach the state buffer.
 *
 * docs/ports/README.md ("Link checks") gives the verdicts of
 * roz_link_check() (first, fresh, bad CRC, replay, restart), what the port
 * does with each, and what a sequence number cannot tell apart.
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
