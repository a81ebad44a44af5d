/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/hal/cmd_watchdog.h
 * @brief The command watchdog every hardware port runs between the tick and
 *        the thread that sends its commands.
 *
 * docs/ports/README.md ("The command watchdog") says what it does when the
 * tick stops writing, how commands resume (epochs, the start-up hold), and
 * which side calls what: the tick roz_cmd_watchdog_report() and
 * roz_cmd_watchdog_write(), the sender roz_cmd_watchdog_judge() and
 * roz_cmd_watchdog_next_ns().
 *
 * Portable: no OS, no heap, O(1); the two sides share 32-bit atomics only.
 */
#ifndef ROZ_HAL_CMD_WATCHDOG_H
#define ROZ_HAL_CMD_WATCHDOG_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/atomic.h"
#include "roz/port.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The parameter's key. */
#define ROZ_CMD_WATCHDOG_KEY "command_timeout_us"
/**
 * The default timeout, microseconds, unless the tick or the sender is so
 * slow that ROZ_CMD_WATCHDOG_DEFAULT_PERIODS of its periods are longer: 50
 * ms is 25 ticks at 500 Hz (the G1's rate), far above a loaded Linux
 * host's scheduling jitter (a few ms), so a healthy loop never trips it,
 * and short enough that a robot tracks a stale target for no longer than
 * a human reaction takes (~200 ms) at a fraction of it.
 */
#define ROZ_CMD_WATCHDOG_DEFAULT_US 50000u
/** The default is at least this many tick periods and sender periods. */
#define ROZ_CMD_WATCHDOG_DEFAULT_PERIODS 5u
/** A timeout is at least this many tick periods and sender periods: a
 *  shorter one fires between two writes of a healthy loop. */
#define ROZ_CMD_WATCHDOG_MIN_PERIODS 2u
/** The longest timeout, microseconds (60 s: tests whose steps wait on a
 *  loaded machine, bring-up on a hung robot; never a robot that stands or
 *  walks). There is no "off". */
#define ROZ_CMD_WATCHDOG_MAX_US 60000000u

/** What the sender sends. */
typedef enum roz_cmd_verdict {
    ROZ_CMD_SEND = 0, /**< the frame: the tick is alive */
    ROZ_CMD_SAFE,     /**< the port's safe command instead */
} roz_cmd_verdict_t;

/** The watchdog; caller-owned. Fields are private: the tick's, the
 *  sender's, and the atomics between them. */
typedef struct roz_cmd_watchdog {
    uint64_t timeout_ns;
    /* the sender's */
    uint32_t epoch;        /* trips so far: frames of an older epoch are not sent */
    uint64_t next_ns;      /* when the latest frame sent expires; 0: tripped */
    /* sender -> tick (release/acquire) */
    ROZ_ATOMIC(uint32_t) trips;
    ROZ_ATOMIC(uint32_t) resumed;  /* the last epoch a hold was sent in */
    ROZ_ATOMIC(uint32_t) stood_us; /* at the last trip: the frame's age */
    /* the tick's */
    uint32_t tick_reported; /* trips read() reported */
    int      tick_wrote;    /* a write since init */
    uint64_t tick_last_ns;  /* its time */
    uint32_t tick_gap_trips; /* trips when the tick's first write after them came */
    uint64_t tick_gap_ns;    /* the silence that write ended */
} roz_cmd_watchdog_t;

/**
 * @brief Read `command_timeout_us` from @p p: the default (see
 *        ROZ_CMD_WATCHDOG_DEFAULT_US) when absent; refused below
 *        ROZ_CMD_WATCHDOG_MIN_PERIODS tick or sender periods or above
 *        ROZ_CMD_WATCHDOG_MAX_US.
 * @param[in] control_rate_hz   the manifest's tick rate (> 0)
 * @param[in] sender_period_us  the sender's period; 0: it sends when the tick writes
 * @param[out] out_us           the timeout
 * @retval ROZ_OK     read (or the default)
 * @retval ROZ_EINVAL a bad value; @p err names the key, the value and the range
 * Context: a port's open(); not the tick.
 */
int roz_cmd_watchdog_param(const roz_params_t *p, uint32_t control_rate_hz,
                           uint32_t sender_period_us, uint32_t *out_us, char *err, size_t errlen);

/**
 * @brief Arm a watchdog (or forget its state): no trip, epoch 0.
 * @param[in] timeout_us the timeout (roz_cmd_watchdog_param())
 * Context: start-up (a port's open or activate), before either side runs.
 */
void roz_cmd_watchdog_init(roz_cmd_watchdog_t *wd, uint32_t timeout_us);

/**
 * @brief The tick writes a command frame at @p now_ns.
 * @param[out] epoch the frame's epoch, for roz_cmd_watchdog_judge()
 * @return 1 while the sender has tripped and sent no hold since: this frame
 *         must be the port's start-up hold, not the command (and be judged
 *         with hold = 1); 0 otherwise
 * Context: the tick (write()); RT-safe, wait-free.
 */
int roz_cmd_watchdog_write(roz_cmd_watchdog_t *wd, uint64_t now_ns, uint32_t *epoch);

/**
 * @brief Whether the sender tripped since the last report: once per trip.
 * @param[in]  now_ns     the tick's time now
 * @param[out] silent_us  how long the tick wrote nothing: until @p now_ns,
 *                        or, when it wrote since the trip (a write before
 *                        this read), until that write; saturated at
 *                        UINT32_MAX
 * @return 1 once for each trip (read() returns ROZ_EWATCHDOG), else 0
 * Context: the tick (read()); RT-safe, wait-free.
 */
int roz_cmd_watchdog_report(roz_cmd_watchdog_t *wd, uint64_t now_ns, uint32_t *silent_us);

/**
 * @brief Judge the latest frame before it is sent.
 * @param[in] epoch      the frame's epoch (roz_cmd_watchdog_write())
 * @param[in] hold       1 when the frame is the hold roz_cmd_watchdog_write()
 *                       asked for
 * @param[in] written_ns when the tick wrote it
 * @param[in] now_ns     the sender's time now
 * @retval ROZ_CMD_SEND  send the frame
 * @retval ROZ_CMD_SAFE  send the safe command: the frame is older than the
 *                       timeout (a trip, counted once, reported to the
 *                       tick), or was written before the last trip
 * Context: the sender (one thread); RT-safe, wait-free.
 */
roz_cmd_verdict_t roz_cmd_watchdog_judge(roz_cmd_watchdog_t *wd, uint32_t epoch, int hold,
                                         uint64_t written_ns, uint64_t now_ns);

/**
 * @brief When a sender that sends only when the tick writes must look again
 *        without being woken: the expiry of the last frame it sent; 0 while
 *        tripped (it repeats the safe command at its own pace); UINT64_MAX
 *        before any frame was judged.
 * Context: the sender.
 */
uint64_t roz_cmd_watchdog_next_ns(const roz_cmd_watchdog_t *wd);

/** @brief Trips so far. Context: any thread. */
uint32_t roz_cmd_watchdog_trips(const roz_cmd_watchdog_t *wd);

/** @brief How old the frame was when the sender last tripped, microseconds
 *  (0 before a trip). Context: any thread; after roz_cmd_watchdog_trips()
 *  returned the trip in question. */
uint32_t roz_cmd_watchdog_stood_us(const roz_cmd_watchdog_t *wd);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_HAL_CMD_WATCHDOG_H */
