/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/engineai_pm01.h
 * @brief The port `engineai/PM01`: an EngineAI PM01 (24 joints) in "joint
 *        bridge" mode, driven through its ROS 2 topics spoken directly over
 *        Cyclone DDS (roz/ros2.h), as a ROS 2 node on rmw_cyclonedds would.
 *
 * Topics (package interface_protocol; ROS name, DDS name, type):
 * - `/hardware/joint_state` = `rt/hardware/joint_state`,
 *   `interface_protocol::msg::dds_::JointState_`: header, position,
 *   velocity, torque, each 24 values in the robot's joint order;
 * - `/hardware/imu_info` = `rt/hardware/imu_info`, `ImuInfo_`: header,
 *   quaternion (x, y, z, w), rpy, linear_acceleration, angular_velocity;
 * - `/hardware/joint_command` = `rt/hardware/joint_command`,
 *   `JointCommand_`: header, position, velocity, feed_forward_torque,
 *   torque, stiffness, damping (24 each), parallel_parser_type.
 * QoS as the vendor's own client: KEEP_LAST 3, BEST_EFFORT, VOLATILE, both
 * ways. Domain: `dds_domain`, by default the robot's ROS_DOMAIN_ID 69.
 *
 * Binding: each of the manifest's `[hardware] joints` is found by name
 * among the robot's (roz_engineai_pm01_joints: J00_HIP_PITCH_L ..
 * J23_HEAD_YAW, the arrays' index order), in any order and any subset; a
 * name that is not the robot's is refused at open. The names are not on
 * the wire, so only this check keeps a joint from driving another's index.
 * States: position, velocity, effort from joint_state's position, velocity,
 * torque; the IMU from imu_info (rpy is not used). Commands: position,
 * velocity, stiffness, damping to the arrays of those names, effort to
 * feed_forward_torque; `torque` is always 0 (the vendor's example sends 0 in
 * both; which of the two the robot adds to its PD is not documented). An
 * index without a manifest joint gets its measured position and 0 gains.
 *
 * `parallel_parser_type` (parameter: `rl` or 1, default; `classic` or 0):
 * the vendor's ParallelParserType (CLASSIC_PARSER 0, RL_PARSER 1), which
 * of the robot's two conversions between the interface's serial ankle
 * joints (pitch, roll) and the parallel ankle actuators handles the command.
 * The vendor's RL deploy example sends RL_PARSER; what the two do
 * differently is not documented.
 *
 * Checks: every joint_state sample must carry exactly 24 values in each
 * array (else dropped, counted, logged once); its header stamp and the
 * IMU's must increase strictly (link_check = stamp: std_msgs/Header has no
 * sequence and the messages no CRC). The PM01 reports no fault of its own
 * on these topics: read() never returns ROZ_EROBOT.
 *
 * Everything else (the fresh frame of both topics, start-up layers,
 * decimation, the writer, the parameters common to ROS 2 ports) is
 * roz/ros2.h's. Own parameter: `parallel_parser_type`.
 */
#ifndef ROZ_ENGINEAI_PM01_H
#define ROZ_ENGINEAI_PM01_H

#include "roz/config.h"

#include "roz/hal/link.h"
#include "roz/log.h"
#include "roz/port.h"
#include "roz/private.h"
#include "roz/ros2.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Joints of the PM01: the length of every array of its messages. */
#define ROZ_ENGINEAI_PM01_JOINTS 24
/** The robot's ROS_DOMAIN_ID. */
#define ROZ_ENGINEAI_PM01_DOMAIN 69u

/** The port's instance; caller-owned (large: give it static storage). The
 *  bridge comes first: the port's self is the bridge, and roz/ros2.h's
 *  functions take it; the other fields are private (roz/private.h). */
typedef struct roz_engineai_pm01 {
    roz_ros2_bridge_t b;
    uint8_t           ROZ_PRIVATE(parallel_parser_type);
    /* the writer thread's: the command's six arrays */
    double            ROZ_PRIVATE(tx)[6][ROZ_ENGINEAI_PM01_JOINTS];
    char              ROZ_PRIVATE(tx_frame_id)[1];
} roz_engineai_pm01_t;

/** The ops table (name "engineai/PM01"). */
extern const roz_port_ops_t roz_engineai_pm01_ops;

/** The robot's joint names, index order (for logs and tools). */
extern const char *const roz_engineai_pm01_joints[ROZ_ENGINEAI_PM01_JOINTS];

/**
 * @brief A roz_port_t over @p pm, not yet open (roz_port_open()).
 * @param log  where the port says which DDS configuration it uses, what it
 *             drops and what the monitors see (from its threads); NULL: stderr
 * Context: start-up.
 */
roz_port_t roz_engineai_pm01_port(roz_engineai_pm01_t *pm, roz_log_fn log, void *log_ctx);

/** @brief The checks on joint_state and imu_info, summed (roz_ros2_link()).
 *  Context: any thread. */
void roz_engineai_pm01_link(const roz_engineai_pm01_t *pm, roz_link_t *out);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_ENGINEAI_PM01_H */
