/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port/loopback.h
 * @brief The loopback port: a deterministic simulator for any manifest, with
 *        fault injection. No OS, no threads: every read() advances simulated
 *        time by one control period (1 / control_rate_hz).
 *
 * docs/ports/loopback.md describes the port: the models bound to the
 * manifest's channels, the CRC'd, numbered frames between the port and its
 * simulated robot, and every fault it injects (roz_loopback_inject(), or
 * the parameters of roz_loopback_ops).
 */
#ifndef ROZ_PORT_LOOPBACK_H
#define ROZ_PORT_LOOPBACK_H

#include "roz/config.h"

#include <stdint.h>

#include "roz/hal/inject.h"
#include "roz/hal/link.h"
#include "roz/log.h"
#include "roz/port.h"
#include "roz/manifest.h"
#include "roz/private.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Time constant of position-commanded joints, seconds. */
#define ROZ_LOOPBACK_TAU_S 0.05
/** Most ticks a delay fault can hold frames back. */
#define ROZ_LOOPBACK_MAX_DELAY ROZ_INJECT_MAX_DELAY
/** Fault injections active at once. */
#define ROZ_LOOPBACK_MAX_FAULTS 8
/** Silence after which the port counts its peer as lost (roz/hal/link.h). */
#define ROZ_LOOPBACK_PEER_TIMEOUT_NS 500000000u
/** Words of a state frame image: sequence, count, two per value, CRC. */
#define ROZ_LOOPBACK_STATE_WORDS (3 + 2 * (ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1))
/** Words of a command frame image. */
#define ROZ_LOOPBACK_CMD_WORDS (3 + 2 * ROZ_CFG_MAX_COMMANDS)

/** One injected fault; `to` = 0 means forever. Its kind (roz/hal/inject.h)
 *  is one of ROZ_INJECT_DROP (frames sent in [from, to) are lost), _DELAY
 *  (they arrive `arg` ticks late), _FREEZE (the peer sends nothing), _NAN
 *  (state `channel` reads NaN), _RANGE (position state `channel` reads
 *  max + 0.5), _DUPLICATE (the last delivered frame again, in place of the
 *  new one), _CORRUPT (a bit of each state frame flips in transit),
 *  _CORRUPT_CMD (a bit of each command frame flips in transit), _RESTART
 *  (the peer is dead in [from, to) and boots again at `to`). */
typedef struct roz_loopback_fault {
    roz_inject_kind_t kind;
    uint64_t from, to;
    int32_t  channel; /**< NAN, RANGE: state index */
    uint32_t arg;     /**< DELAY: ticks, 1..ROZ_LOOPBACK_MAX_DELAY */
} roz_loopback_fault_t;

/** Model bound to one state channel at open. */
typedef struct roz_loopback_binding {
    uint8_t model;   /* private: enum in loopback.c */
    uint8_t axis;    /* private */
    int16_t joint;   /* private: index into joints[] */
} roz_loopback_binding_t;

/** One simulated joint. */
typedef struct roz_loopback_joint {
    int32_t pos_state, vel_state, eff_state;  /* -1 if absent */
    int32_t pos_cmd, vel_cmd, kp_cmd, kd_cmd, eff_cmd; /* -1 if absent */
    double  q, dq, tau;
} roz_loopback_joint_t;

/** A state frame in transit. */
typedef struct roz_loopback_frame {
    uint64_t sent;    /* tick it was sent */
    uint64_t arrives; /* tick it arrives; UINT64_MAX = lost */
    uint32_t image[ROZ_LOOPBACK_STATE_WORDS];
} roz_loopback_frame_t;

/** The port's data; caller-owned. Fields are private to the loopback port;
 *  tests read the counters. */
typedef struct roz_loopback {
    const roz_manifest_t  *ROZ_PRIVATE(m);
    double                 ROZ_PRIVATE(dt);
    uint64_t               ROZ_PRIVATE(period_ns);
    uint64_t               ROZ_PRIVATE(tick);         /* reads so far */
    roz_loopback_fault_t   ROZ_PRIVATE(faults)[ROZ_LOOPBACK_MAX_FAULTS];
    uint32_t               ROZ_PRIVATE(n_faults);

    /* the simulated robot (sim.c) and its end of the wire */
    roz_loopback_joint_t   ROZ_PRIVATE(joints)[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    uint16_t               ROZ_PRIVATE(n_joints);
    roz_loopback_binding_t ROZ_PRIVATE(bind)[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    int32_t                ROZ_PRIVATE(base_cmd)[4];  /* vx, vy, vz, yaw rate */
    int32_t                ROZ_PRIVATE(base_state)[4];/* x, y, z, yaw */
    double                 ROZ_PRIVATE(base)[4];
    /* the command the robot applies */
    double                 ROZ_PRIVATE(cmd)[ROZ_CFG_MAX_COMMANDS];
    int                    ROZ_PRIVATE(have_cmd);
    int                    ROZ_PRIVATE(peer_dead);
    uint32_t               ROZ_PRIVATE(peer_seq);     /* next state frame's sequence number */
    roz_link_t             ROZ_PRIVATE(peer_link);    /* the robot's checks on command frames */

    /* the wire: state frames in flight, by sent tick modulo the depth */
    roz_loopback_frame_t   ROZ_PRIVATE(flight)[ROZ_LOOPBACK_MAX_DELAY + 1];
    uint32_t               ROZ_PRIVATE(cmd_image)[ROZ_LOOPBACK_CMD_WORDS];
    uint32_t               ROZ_PRIVATE(cmd_seq);

    /* the port's end */
    roz_link_t             ROZ_PRIVATE(link);         /* the port's checks on state frames */
    /* the last frame accepted */
    uint32_t               ROZ_PRIVATE(last_image)[ROZ_LOOPBACK_STATE_WORDS];
    double                 ROZ_PRIVATE(rx)[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];

    /* counters (roz_loopback_counters_t says what each counts) */
    uint64_t               ROZ_PRIVATE(frames_sent);
    uint64_t               ROZ_PRIVATE(frames_delivered);
    uint64_t               ROZ_PRIVATE(frames_dropped);
    uint64_t               ROZ_PRIVATE(frames_duplicated);
    uint64_t               ROZ_PRIVATE(frames_corrupted);
    uint64_t               ROZ_PRIVATE(link_events);
    uint64_t               ROZ_PRIVATE(writes);
    uint64_t               ROZ_PRIVATE(writes_withheld);
    uint64_t               ROZ_PRIVATE(cmds_corrupted);
    uint64_t               ROZ_PRIVATE(cmds_lost);
    uint64_t               ROZ_PRIVATE(violations);
    uint64_t               ROZ_PRIVATE(first_write_tick);
} roz_loopback_t;

/** What the loopback counted since open (roz_loopback_counters()). */
typedef struct roz_loopback_counters {
    uint64_t tick;              /**< reads so far: the tick the next read simulates */
    uint32_t faults;            /**< fault injections in the table, spent ones included */
    uint64_t frames_sent;       /**< state frames the robot sent */
    uint64_t frames_delivered;  /**< accepted by the port */
    uint64_t frames_dropped;    /**< lost in transit (DROP) */
    uint64_t frames_duplicated; /**< delivered again (DUPLICATE) */
    uint64_t frames_corrupted;  /**< state frames with a bit flipped (CORRUPT) */
    uint64_t link_events;       /**< reads that returned ROZ_ELINK: the peer restarted */
    uint64_t writes;            /**< write() calls */
    uint64_t writes_withheld;   /**< before the peer's first state frame */
    uint64_t cmds_corrupted;    /**< command frames with a bit flipped (CORRUPT_CMD) */
    uint64_t cmds_lost;         /**< command frames sent to a dead peer */
    uint64_t violations;        /**< written values outside [min, max] or non-finite: stays 0 */
    uint64_t first_write_tick;  /**< tick the robot applied its first command, 0: none */
} roz_loopback_counters_t;

/** The ops table. Parameters: drop=FROM:TO, freeze=FROM[:TO], delay=K@FROM:TO,
 *  nan=CH@FROM:TO, range=CH@FROM:TO, duplicate=FROM:TO, corrupt=FROM:TO,
 *  corrupt_cmd=FROM:TO, restart=FROM:TO (TO may be empty: forever); CH is a
 *  state index or name. */
extern const roz_port_ops_t roz_loopback_ops;

/** @brief A roz_port_t over @p lb, not yet open (roz_port_open()). The
 *  simulator has nothing to log: @p log and @p log_ctx are taken for the
 *  one constructor shape every port has, and ignored.
 *  Context: start-up. */
static inline roz_port_t roz_loopback_port(roz_loopback_t *lb, roz_log_fn log, void *log_ctx)
{
    roz_port_t p = { &roz_loopback_ops, lb, 0 };
    (void)log;
    (void)log_ctx;
    return p;
}

/**
 * @brief Add a fault injection (before or while running; not thread-safe:
 *        call it from the tick's thread). When the table is full, the
 *        injections that are over (`to` reached) are forgotten first.
 * @retval ROZ_ENOSPC ROZ_LOOPBACK_MAX_FAULTS still active
 * @retval ROZ_EINVAL bad channel, kind or delay
 * Context: the tick's thread.
 */
int roz_loopback_inject(roz_loopback_t *lb, const roz_loopback_fault_t *f);

/** @brief The simulated robot's true state (n_states), before fault injection.
 *  Context: the tick's thread between ticks, or after it stopped. */
void roz_loopback_true_state(const roz_loopback_t *lb, double *state);

/** @brief The command the simulated robot applies (n_commands), or NULL
 *         before it received one (or since it restarted).
 * Context: the tick's thread between ticks, or after it stopped.
 */
const double *roz_loopback_last_command(const roz_loopback_t *lb);

/** @brief A copy of @p lb's counters (a value, so that a test reads one in
 *         an expression). Context: the tick's thread between ticks, or
 *         after it stopped. */
roz_loopback_counters_t roz_loopback_counters(const roz_loopback_t *lb);

/** @brief A copy of the port's checks on the state frames it received
 *         (roz/hal/link.h). Context: as roz_loopback_counters(). */
roz_link_t roz_loopback_link(const roz_loopback_t *lb);

/** @brief A copy of the simulated robot's checks on the command frames it
 *         received. Context: as roz_loopback_counters(). */
roz_link_t roz_loopback_peer_link(const roz_loopback_t *lb);

/** @brief Forget every fault injection, active or not: the wire is clean
 *         from the next read on. Context: the tick's thread. */
void roz_loopback_clear_faults(roz_loopback_t *lb);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_LOOPBACK_H */
