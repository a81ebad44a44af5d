/* SPDX-License-Identifier: Apache-2.0 */
/* Private to roz::ros2: the manifest bound to a robot's joint slots and the
 * conversions between channel values and joint commands; pure functions
 * (no DDS, no threads). */
#ifndef ROZ_ROS2_MAP_H
#define ROZ_ROS2_MAP_H

#include <stddef.h>
#include <stdint.h>

#include "roz/port/ros2.h"

/* Binds the manifest's joints and IMU to the robot's slots and channels;
 * every channel must find its place. ROZ_ENOENT (a joint: not the robot's,
 * listed twice, too many or none, or without a channel) or ROZ_EINVAL (a
 * channel), err naming it. */
int roz__ros2_bind(roz_ros2_bridge_t *b, const roz_manifest_t *m, char *err, size_t errlen);

/* Reads the parameters @p p into @p b (bound first: the damping gains'
 * range is the bound channels'), the robot's own through its params hook
 * last (ros2_rules.c). Without @p report (the open): ROZ_EINVAL at the
 * first problem, err saying it. With it (roz_ros2_check()): each problem
 * written to err and reported (rule "unknown-key" or "ros2-param"), going
 * on with the next step; ROZ_EINVAL after at least one report. */
int roz__ros2_parse_params(roz_ros2_bridge_t *b, const roz_params_t *p, char *err,
                           size_t errlen, roz_params_problem_fn report, void *ctx);

/* The start-up hold as a command frame (n_commands, manifest order): every
 * joint's position command holds q[robot slot], kd is @p kd where the joint
 * has a damping command, everything else 0; each value clamped
 * (roz_joints_hold() on the joints' positions). With @p last (the
 * controller's last command) the stop's hold from it (roz_joints_hold_keep()). */
void roz__ros2_hold(const roz_ros2_bridge_t *b, const double *q, const double *last, double kd,
                    double *cmd);

/* Every robot slot's joint command from a command frame: a bound joint's
 * channels (a joint without a position command: @p q, its measured
 * position), an unbound slot q[slot] with everything else 0. */
void roz__ros2_joints(const roz_ros2_bridge_t *b, const double *cmd, const double *q,
                      roz_ros2_joint_cmd_t *out);

/* The damping command per robot slot: q the given positions (clamped), kp 0
 * (@p hold: the joint's stiffness default, the hold gain), kd @p kd (NaN:
 * each joint's damping default; clamped) where the joint has a damping
 * command, 0 elsewhere. */
void roz__ros2_damping(const roz_ros2_bridge_t *b, const double *q, double kd, int hold,
                       roz_ros2_joint_cmd_t *out);

#endif /* ROZ_ROS2_MAP_H */
