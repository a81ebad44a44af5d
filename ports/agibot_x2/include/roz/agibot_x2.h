/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/agibot_x2.h
 * @brief The port `agibot/X2`: an AgiBot X2 (30 joints in four groups)
 *        driven through its AimDK HAL topics spoken directly over Cyclone
 *        DDS (roz/ros2.h), as a ROS 2 node on rmw_cyclonedds would.
 *
 * Topics (package aimdk_msgs; ROS name, DDS name, type), for each group G
 * of leg, waist, arm, head:
 * - `/aima/hal/joint/G/state` = `rt/aima/hal/joint/G/state`,
 *   `aimdk_msgs::msg::dds_::JointStateArray_`: header (stamp, frame_id,
 *   sequence, meas_stamp), state (DomainErrorState), joints (name, position,
 *   velocity, effort, error_code);
 * - `/aima/hal/joint/G/command` = `rt/aima/hal/joint/G/command`,
 *   `JointCommandArray_`: header, joints (name, position, velocity, effort,
 *   stiffness, damping);
 * and the torso IMU, `/aima/hal/imu/torso/state` =
 * `rt/aima/hal/imu/torso/state`, `sensor_msgs::msg::dds_::Imu_`.
 * QoS as the vendor's example: ROS 2's sensor data profile (KEEP_LAST 5,
 * BEST_EFFORT, VOLATILE), both ways; it matches the state topics'
 * documented TRANSIENT_LOCAL writers. Domain: `dds_domain` (0 unless set;
 * the X2's ROS_DOMAIN_ID is not documented).
 *
 * Groups and their slots (the robot's joint names, in message order): leg
 * 12 (left_ then right_: hip_pitch, hip_roll, hip_yaw, knee, ankle_pitch,
 * ankle_roll, each `_joint`), waist 3 (waist_yaw, waist_pitch, waist_roll),
 * arm 14 (left_ then right_: shoulder_pitch, shoulder_roll, shoulder_yaw,
 * elbow, wrist_yaw, wrist_pitch, wrist_roll), head 2 (head_yaw, then
 * head_pitch, a placeholder on the X2). The manifest's `[hardware] joints`
 * are found among them by name, in any order; a slot without one (the head
 * pitch) is commanded with its measured position and zero gains. A group
 * without a joint of the manifest is neither read nor commanded.
 *
 * The frame: fresh when every group read and the IMU (when the manifest
 * has an IMU channel) delivered a sample since the last fresh frame, so
 * one group that falls silent makes the state stale on its own (the
 * runtime's STALE fault stops the robot) however fast the others are.
 *
 * Checks on every state sample, before anything of it is used: `joints`
 * has the group's length, and every joint that carries a name carries its
 * slot's (a robot whose joint order is not this port's is not driven: its
 * samples are dropped, counted, logged once); its header `sequence` goes
 * through roz/hal/link.h (`link_check = stamp` takes the header's stamp
 * instead, for a robot that does not fill the sequence); the IMU's stamp
 * must increase. ROS 2 messages carry no CRC.
 *
 * Faults the robot reports, latched by the runtime as ROZ_FAULT_ROBOT for
 * as long as they last (read() returns ROZ_EROBOT): a group's
 * DomainErrorState other than 0 (1 damping, 2 power-off, 3 disabled, 4
 * communication lost), fault() naming the group and the state; a joint's
 * error_code other than 0 (its meaning is not documented: roz stops on
 * any), fault() naming the joint and the code.
 *
 * JointState layouts: the SDK's (`joint_state_layout = sdk`, the default:
 * name, position, velocity, effort, error_code) or the online
 * documentation's (`docs`: name, position, velocity, effort, coil_temp,
 * motor_temp, motor_vol; no error codes). DDS cannot tell them apart (the
 * robot's ROS 2 sends no type information): the wrong one garbles every
 * value after the first joint's effort. Check the robot's with `ros2
 * interface show aimdk_msgs/msg/JointState`. The docs layout is registered
 * without type information.
 *
 * Commands: every slot of each group, named, stamped with the system clock,
 * the header's sequence counting that topic's samples from 1.
 *
 * Everything else (start-up layers, decimation, the writer, the parameters
 * common to ROS 2 ports) is roz/ros2.h's. Own parameter:
 * `joint_state_layout`.
 */
#ifndef ROZ_AGIBOT_X2_H
#define ROZ_AGIBOT_X2_H

#include "roz/config.h"

#include <stdint.h>

#include "roz/hal/link.h"
#include "roz/log.h"
#include "roz/port.h"
#include "roz/private.h"
#include "roz/ros2.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Joint groups: leg, waist, arm, head. */
#define ROZ_AGIBOT_X2_GROUPS 4
/** Joints in the largest group (arm). */
#define ROZ_AGIBOT_X2_MAX_GROUP 14
/** 8-byte words of one JointCommand_ (name pointer, five doubles). */
#define ROZ_AGIBOT_X2_CMD_WORDS 6

/** The port's instance; caller-owned (give it static storage). The bridge
 *  comes first: the port's self is the bridge, and roz/ros2.h's functions
 *  take it; the other fields are private (roz/private.h). */
typedef struct roz_agibot_x2 {
    roz_ros2_bridge_t b;
    int               ROZ_PRIVATE(docs_layout); /* joint_state_layout = docs */
    void             *ROZ_PRIVATE(docs_type); /* the docs layout's descriptor, made at open */
    /* the writer thread's: each group's JointCommand_ elements */
    uint64_t          ROZ_PRIVATE(tx)[ROZ_AGIBOT_X2_GROUPS]
                                 [ROZ_AGIBOT_X2_MAX_GROUP * ROZ_AGIBOT_X2_CMD_WORDS];
    char              ROZ_PRIVATE(tx_frame_id)[1];
} roz_agibot_x2_t;

/** The ops table (name "agibot/X2"). */
extern const roz_port_ops_t roz_agibot_x2_ops;

/** The groups (name, topics, joint names), in the port's order. */
extern const roz_ros2_group_t roz_agibot_x2_groups[ROZ_AGIBOT_X2_GROUPS];

/**
 * @brief A roz_port_t over @p x2, not yet open (roz_port_open()).
 * @param log  where the port says which DDS configuration it uses, what it
 *             drops and what the monitors see (from its threads); NULL: stderr
 * Context: start-up.
 */
roz_port_t roz_agibot_x2_port(roz_agibot_x2_t *x2, roz_log_fn log, void *log_ctx);

/** @brief The checks on the state topics, summed (roz_ros2_link()).
 *  Context: any thread. */
void roz_agibot_x2_link(const roz_agibot_x2_t *x2, roz_link_t *out);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_AGIBOT_X2_H */
