/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/hal/joints.h
 * @brief A robot's joints and IMU bound to a manifest's channels, and the
 *        command frames every hardware port builds from them (the start-up
 *        hold, clamping). Pure functions: no heap, no I/O.
 *
 * The channels a port serves per `[hardware]` joint J: states
 * `J/position`, `J/velocity`, `J/effort`; commands `J/position`,
 * `J/velocity`, `J/effort`, `J/stiffness`, `J/damping`; each optional, but a
 * joint needs one. The IMU's states (roz_joints_bind() with an IMU):
 * `base_imu/orientation.{x,y,z,w}`, `base_imu/angular_velocity.{x,y,z}`,
 * `base_imu/linear_acceleration.{x,y,z}`, geometry_msgs order. Binding
 * refuses a channel of the wrong interface type, and a manifest channel the
 * port has no place for; every error names the port and the channel or
 * joint.
 */
#ifndef ROZ_HAL_JOINTS_H
#define ROZ_HAL_JOINTS_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/manifest.h"

#ifdef __cplusplus
extern "C" {
#endif

/** IMU values: orientation x, y, z, w; angular velocity x, y, z; linear
 *  acceleration x, y, z. */
#define ROZ_IMU_VALUES 10

/** One joint's channels: manifest state or command indices, -1 for none. */
typedef struct roz_joint_channels {
    int16_t q_state, dq_state, tau_state;
    int16_t q_cmd, dq_cmd, tau_cmd, kp_cmd, kd_cmd;
} roz_joint_channels_t;

/**
 * @brief Bind joints @p names (n, the manifest's `[hardware] joints` in
 *        the port's order) and, when @p imu is not NULL, the IMU to @p m's
 *        channels; every channel of @p m must find its place.
 * @param[out] out  n joints' channels
 * @param[out] imu  NULL: the robot has no IMU; else ROZ_IMU_VALUES state
 *                  indices (-1: not in the manifest)
 * @param robot     how an error names the robot ("the G1", "this robot")
 * @retval ROZ_OK
 * @retval ROZ_ENOENT a joint without any channel (@p err names it)
 * @retval ROZ_EINVAL a channel of another type than the port serves, or one
 *         without a place (@p err names @p port and the channel)
 * Context: a port's open(); not the tick.
 */
int roz_joints_bind(const roz_manifest_t *m, const char *port, const char *robot,
                    const char *const *names, uint16_t n, roz_joint_channels_t *out,
                    int16_t *imu, char *err, size_t errlen);

/**
 * @brief A [hardware] joint the robot has not: "<port>: [hardware]
 *        joints[<k>] "<joint>" is not one of the robot's joints (the
 *        port's header lists them<how>)" into @p err.
 * @retval ROZ_ENOENT (what the caller returns)
 * Context: a port's open() and its rules; not the tick.
 */
int roz_joints_not_the_robots(const char *port, unsigned k, const char *joint, const char *how,
                              char *err, size_t errlen);

/**
 * @brief The range every joint's damping channel allows: [lo, hi] the
 *        intersection (0, 0 when there is none).
 * @return how many damping channels there are
 * Context: a port's open(); pure.
 */
int roz_joints_damping_range(const roz_manifest_t *m, const roz_joint_channels_t *j, uint16_t n,
                             double *lo, double *hi);

/** @brief @p v clamped to channel @p c; NaN becomes the channel's default.
 *  Context: any; pure, RT-safe. */
double roz_channel_clamp(const roz_channel_t *c, double v);

/** @brief @p v clamped to channel @p c (roz_channel_clamp()) and narrowed
 *  to float toward the inside: the float is never outside [min, max] as a
 *  double compares it (2.8798 narrows to 2.87979984, not 2.87980008).
 *  Context: any; pure, RT-safe. */
float roz_channel_clamp_float(const roz_channel_t *c, double v);

/**
 * @brief The start-up hold as a command frame (n_commands, manifest order):
 *        each joint's position command holds @p q (n joints' measured
 *        positions), its damping command is @p kd, every other command 0;
 *        each value clamped to its channel.
 * Context: the tick; pure, RT-safe.
 */
void roz_joints_hold(const roz_manifest_t *m, const roz_joint_channels_t *j, uint16_t n,
                     const double *q, double kd, double *cmd);

/**
 * @brief The stop's hold as a command frame (roz/hold.h): from @p last, the
 *        controller's last command (n_commands), and @p q, the n joints'
 *        measured positions: each joint's stiffness command its hold gain
 *        (its default), its position command the setpoint that keeps the
 *        torque of @p last under that gain within the band of the measured
 *        position, its damping command @p kd, every other command 0; each
 *        value clamped to its channel. The hold a port sends when the tick
 *        comes back after its command watchdog tripped.
 * Context: the tick; pure, RT-safe.
 */
void roz_joints_hold_keep(const roz_manifest_t *m, const roz_joint_channels_t *j, uint16_t n,
                          const double *last, const double *q, double kd, double *cmd);

/**
 * @brief One joint's hold setpoint (roz_hold_setpoint()) from what last
 *        went out to it: @p last_q its position command's value (ignored
 *        without a position command: the hold is @p measured), @p last_kp
 *        its stiffness's, @p measured its measured position; under the hold
 *        gain (its stiffness command's default), within the band of its
 *        position command, inside that command's limits (its position
 *        state's without one). NaN when no hold can be computed (nothing
 *        measured and no position command): the port then sends no
 *        stiffness. The ports' watchdogs and exits use it.
 * Context: any; pure, RT-safe.
 */
double roz_joints_hold_setpoint(const roz_manifest_t *m, const roz_joint_channels_t *j,
                                double last_q, double last_kp, double measured);

/** @brief Clamp every command value to its channel (NaN: its default).
 *  @return how many values it changed. Context: the tick; pure, RT-safe. */
uint32_t roz_commands_clamp(const roz_manifest_t *m, const double *in, double *out);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_HAL_JOINTS_H */
