/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/loopback.h
 * @brief The loopback port: a deterministic simulator for any manifest, with
 *        fault injection. No OS, no threads: every read() advances simulated
 *        time by one control period (1 / control_rate_hz).
 *
 * Models, bound by channel name at open (joint = the name before the last
 * '/'):
 * - MIT-mode joint (a joint with stiffness or damping commands, as on the
 *   humanoids): torque = kp*(q_cmd - q) + kd*(dq_cmd - dq) + effort_cmd,
 *   clamped to the effort command's limits, drives a unit-inertia joint with
 *   light viscous friction; states position, velocity and effort follow.
 * - position-commanded joint: a first-order lag (time constant
 *   ROZ_LOOPBACK_TAU_S) toward the target.
 * - velocity-commanded joint (a velocity command paired with a position
 *   state): the position integrates the velocity; the joint's velocity
 *   state reads it.
 * - effort-only joint: torque drives the unit-inertia joint.
 * - planar base (quadcopter, diff_drive): body-frame velocities
 *   (`X/velocity.x|y|z` or `X/linear.x|y`) and a yaw rate (`X/yaw_rate` or
 *   `X/angular.z`) integrate into world-frame `X/position.x|y|z` or
 *   `X/odom.x|y` and `X/yaw` or `X/odom.yaw`.
 * Every other state (an IMU, say) holds its manifest default: a robot at rest.
 *
 * Fault injection, for tests (also as parameters, see roz_loopback_ops):
 * drop (frames not delivered), delay (frames delivered k ticks late), freeze
 * (no new frames from a tick on), nan (a state channel reads NaN), range (a
 * position state reads 0.5 beyond its upper limit), duplicate (the frame
 * delivered before is delivered again and reported fresh, as a transport
 * without sequence numbers would).
 */
#ifndef ROZ_LOOPBACK_H
#define ROZ_LOOPBACK_H

#include "roz/config.h"

#include <stdint.h>

#include "roz/hal/port.h"
#include "roz/manifest.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Time constant of position-commanded joints, seconds. */
#define ROZ_LOOPBACK_TAU_S 0.05
/** Most ticks a delay fault can hold frames back. */
#define ROZ_LOOPBACK_MAX_DELAY 15
/** Fault injections active at once. */
#define ROZ_LOOPBACK_MAX_FAULTS 8

typedef enum roz_loopback_fault_kind {
    ROZ_LOOPBACK_DROP = 1,   /**< frames in [from, to) are not delivered */
    ROZ_LOOPBACK_DELAY,      /**< frames in [from, to) arrive `arg` ticks late */
    ROZ_LOOPBACK_FREEZE,     /**< no new frame from `from` until `to` */
    ROZ_LOOPBACK_NAN,        /**< state `channel` reads NaN in [from, to) */
    ROZ_LOOPBACK_RANGE,      /**< position state `channel` reads max + 0.5 in [from, to) */
    ROZ_LOOPBACK_DUPLICATE,  /**< reads in [from, to) deliver the previous frame again, as fresh */
} roz_loopback_fault_kind_t;

/** One injected fault; `to` = 0 means forever. */
typedef struct roz_loopback_fault {
    roz_loopback_fault_kind_t kind;
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

/** The port's data; caller-owned. Fields are private to loopback.c. */
typedef struct roz_loopback {
    const roz_manifest_t  *m;
    double                 dt;
    uint64_t               tick;         /* reads so far */
    roz_loopback_joint_t   joints[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    uint16_t               n_joints;
    roz_loopback_binding_t bind[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    int32_t                base_cmd[4];  /* vx, vy, vz, yaw rate */
    int32_t                base_state[4];/* x, y, z, yaw */
    double                 base[4];
    double                 cmd[ROZ_CFG_MAX_COMMANDS];
    int                    have_cmd;
    double                 hist[ROZ_LOOPBACK_MAX_DELAY + 1][ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    double                 last_out[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    int                    delivered_any;
    roz_loopback_fault_t   faults[ROZ_LOOPBACK_MAX_FAULTS];
    uint32_t               n_faults;
    /* counters */
    uint64_t               frames_delivered, frames_dropped, writes;
    uint64_t               frames_duplicated; /* of frames_delivered, repeats (DUPLICATE) */
    uint64_t               violations;      /* written values outside [min, max] or non-finite: must stay 0 */
    uint64_t               first_write_tick; /* tick of the first write, 0 = none */
} roz_loopback_t;

/** The ops table. Parameters: drop=FROM:TO, freeze=FROM[:TO], delay=K@FROM:TO,
 *  nan=CH@FROM:TO, range=CH@FROM:TO, duplicate=FROM:TO (TO may be empty:
 *  forever); CH is a state index or name. */
extern const roz_port_ops_t roz_loopback_ops;

/** @brief A roz_port_t over @p lb. */
static inline roz_port_t roz_loopback_port(roz_loopback_t *lb)
{
    roz_port_t p = { &roz_loopback_ops, lb };
    return p;
}

/**
 * @brief Add a fault injection (before or while running; not thread-safe:
 *        call it from the tick's thread).
 * @retval ROZ_ENOSPC ROZ_LOOPBACK_MAX_FAULTS already set
 * @retval ROZ_EINVAL bad channel, kind or delay
 */
int roz_loopback_inject(roz_loopback_t *lb, const roz_loopback_fault_t *f);

/** @brief The simulator's true state (n_states), before fault injection. */
void roz_loopback_true_state(const roz_loopback_t *lb, double *state);

/** @brief The last command written (n_commands), or NULL before any write. */
const double *roz_loopback_last_command(const roz_loopback_t *lb);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_LOOPBACK_H */
