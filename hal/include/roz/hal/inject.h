/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/hal/inject.h
 * @brief The simulators' fault injections: one list of kinds and one
 *        grammar for the parameters that ask for them (the loopback and
 *        mujoco ports, docs/ports/loopback.md and docs/ports/mujoco.md).
 *
 * A value is one entry or several separated by ';' (spaces around a ';'
 * are ignored). An entry is [HEAD@]FROM[:[TO]]: ticks [FROM, TO), TO
 * left out or empty = forever. Ticks are decimal digits only (no sign, no
 * space), at most 2^64 - 1; TO, when written, is after FROM (TO = FROM is
 * no tick at all, and 0 is a written TO, not forever); `restart` needs TO
 * (the robot boots again at TO). HEAD, before the entry's last '@', is the
 * kind's: K (delay, 1..ROZ_INJECT_MAX_DELAY ticks), CHANNEL (nan, range),
 * FX,FY,FZ@BODY (push); the port reads CHANNEL and FX,FY,FZ@BODY.
 */
#ifndef ROZ_HAL_INJECT_H
#define ROZ_HAL_INJECT_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Most ticks a delay injection holds frames back. */
#define ROZ_INJECT_MAX_DELAY 15
/** Longest HEAD of an entry, bytes, with its terminating NUL. */
#define ROZ_INJECT_HEAD_MAX 96

/** What an injection does, each over ticks [from, to); a port takes the
 *  kinds it can simulate (its parameters' keys are roz_inject_key()'s). */
typedef enum roz_inject_kind {
    ROZ_INJECT_DROP = 1,     /**< `drop`: frames sent in [from, to) are lost */
    ROZ_INJECT_DELAY,        /**< `delay`: frames arrive `arg` ticks late */
    ROZ_INJECT_FREEZE,       /**< `freeze`: the peer sends nothing */
    ROZ_INJECT_NAN,          /**< `nan`: state `channel` reads NaN */
    ROZ_INJECT_RANGE,        /**< `range`: position state `channel` reads max + 0.5 */
    ROZ_INJECT_DUPLICATE,    /**< `duplicate`: the last delivered frame again */
    ROZ_INJECT_CORRUPT,      /**< `corrupt`: a bit of each state frame flips */
    ROZ_INJECT_CORRUPT_CMD,  /**< `corrupt_cmd`: a bit of each command frame flips */
    ROZ_INJECT_RESTART,      /**< `restart`: the peer is dead and boots again at `to` */
    ROZ_INJECT_PUSH,         /**< `push`: a force on a body at its centre of mass */
    ROZ_INJECT_GANTRY,       /**< `gantry`: the floating base hung where it is */
    ROZ_INJECT_KIND_END      /**< one past the last kind */
} roz_inject_kind_t;

/** One entry of a value, as the grammar reads it. */
typedef struct roz_inject_entry {
    roz_inject_kind_t kind;
    uint64_t from, to;              /**< ticks [from, to); to = 0: forever */
    uint32_t arg;                   /**< delay: K, 1..ROZ_INJECT_MAX_DELAY */
    char     head[ROZ_INJECT_HEAD_MAX]; /**< nan, range: CHANNEL; push:
                                         FX,FY,FZ@BODY; else "" */
} roz_inject_entry_t;

/** What the port's callback returns for an entry: ROZ_OK, or one of these
 *  with @p why filled in (SYNTAX: the value is not in the kind's form, and
 *  the message adds the form). */
enum { ROZ_INJECT_BAD = -1, ROZ_INJECT_SYNTAX = -2 };

/** Called once per entry, in order: the port reads the head and injects. */
typedef int (*roz_inject_fn)(void *ctx, const roz_inject_entry_t *e, char *why, size_t whylen);

/** @brief The parameter key of @p kind ("drop"); NULL for none. Context: any. */
const char *roz_inject_key(roz_inject_kind_t kind);

/** @brief The kind whose key is @p key; 0 for none. Context: any. */
roz_inject_kind_t roz_inject_find(const char *key);

/**
 * @brief Parse @p value, the value of @p kind's parameter, calling @p fn
 *        for each entry.
 * @param[out] err  on a refusal: "parameter KEY = \"VALUE\": what is wrong"
 *                  and, for a value not in the form, "; expected FORM (...)"
 * @retval ROZ_OK every entry taken; ROZ_EINVAL refused (entries before the
 *         bad one were passed to @p fn)
 * Context: start-up; no heap.
 */
int roz_inject_parse(roz_inject_kind_t kind, const char *value, roz_inject_fn fn, void *ctx,
                     char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_HAL_INJECT_H */
