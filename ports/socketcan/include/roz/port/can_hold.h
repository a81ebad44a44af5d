/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port/can_hold.h
 * @brief What the socketcan port sends a joint when the tick has gone
 *        silent (the command watchdog's hold) and when it comes back (the
 *        hold after a trip). Pure and portable: no OS header, no heap.
 *
 * The watchdog's hold is the built-in humanoids' stop, as the filter and
 * the DDS ports send it (SAFETY.md, "Stops in physics"): each joint at its
 * hold gains, the stiffness and damping channels' defaults, its setpoint
 * moved so that it keeps the torque of the last command that went out
 * (roz/hold.h, within its band), no velocity, no feed-forward torque. Every
 * value is inside the joint's channel, as the manifest says.
 */
#ifndef ROZ_PORT_CAN_HOLD_H
#define ROZ_PORT_CAN_HOLD_H

#include "roz/manifest.h"
#include "roz/port/can_config.h"
#include "roz/port/mit_codec.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A joint's last command frame, in the joint's frame. */
typedef struct roz_can_last {
    int    sent;      /**< a command went out since the actuator became ready */
    double position;  /**< its position target */
    double stiffness; /**< its kp (0 for a joint without a stiffness command) */
    double measured;  /**< the joint's measured position when it went out */
} roz_can_last_t;

/**
 * @brief The command watchdog's hold for joint @p jt, in the actuator's
 *        frame (direction and zero offset applied).
 * @param m        the manifest the joint's channels belong to
 * @param jt       the joint
 * @param last     its last command frame
 * @param measured its measured position now, in the joint's frame
 * @param[out] out the frame's values
 * The setpoint is roz_hold_setpoint()'s from the last command and the
 * position measured when it went out (@p measured when that is not
 * finite): the torque kept under the hold gain, within the band of that
 * position; with no command sent yet or no position command, the measured
 * position; the last position sent while the position is unknown. With
 * neither, no stiffness.
 * Context: any; RT-safe.
 */
void roz_can_watchdog_hold(const roz_manifest_t *m, const roz_can_joint_t *jt,
                           const roz_can_last_t *last, double measured, roz_mit_command_t *out);

/** @brief The damping of joint @p jt's holds: its damping channel's
 *  default, inside the channel; 0 without one. Context: any; RT-safe. */
double roz_can_hold_damping(const roz_manifest_t *m, const roz_can_joint_t *jt);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_CAN_HOLD_H */
