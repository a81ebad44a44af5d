/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port/engineai_pm01.h
 * @brief The port `engineai/PM01`: an EngineAI PM01 (24 joints) in "joint
 *        bridge" mode, driven through its ROS 2 topics spoken directly over
 *        Cyclone DDS (roz/port/ros2.h), as a ROS 2 node on rmw_cyclonedds would.
 *
 * docs/ports/ros2.md describes the port: its topics and QoS, the joints
 * (roz_engineai_pm01_joints), the checks, `parallel_parser_type`, and what
 * is not known about the robot.
 */
#ifndef ROZ_PORT_ENGINEAI_PM01_H
#define ROZ_PORT_ENGINEAI_PM01_H

#include "roz/config.h"

#include "roz/hal/link.h"
#include "roz/log.h"
#include "roz/port.h"
#include "roz/private.h"
#include "roz/port/ros2.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Joints of the PM01: the length of every array of its messages. */
#define ROZ_ENGINEAI_PM01_JOINTS 24
/** The robot's ROS_DOMAIN_ID. */
#define ROZ_ENGINEAI_PM01_DOMAIN 69u

/** The port's instance; caller-owned (large: give it static storage). The
 *  bridge comes first: the port's self is the bridge, and roz/port/ros2.h's
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
 * @brief The port's rules of @p m's [hardware] keys, as its open applies
 *        them to robot.toml's parameters (roz_ros2_check()): what
 *        roz_manifest_json, and so rozgen, runs (roz_add_port_rules()).
 *        Parameters given at open and CYCLONEDDS_URI are the open's alone.
 * @retval ROZ_OK, or ROZ_EINVAL after reporting every problem
 * Context: host tools and start-up, one call at a time; no heap.
 */
int roz_engineai_pm01_check(const roz_manifest_t *m, roz_params_problem_fn report, void *ctx);

/* The library half of the constructor below: the caller's layout and
 * instance size, refused when they are not the library's. */
roz_port_t roz__engineai_pm01_port(roz_engineai_pm01_t *pm, const roz_port_layout_t *caller,
                                   size_t bytes, roz_log_fn log, void *log_ctx);

/**
 * @brief A roz_port_t over @p pm, not yet open (roz_port_open()).
 * @param log  where the port says which DDS configuration it uses, what it
 *             drops and what the monitors see (from its threads); NULL: stderr
 * Context: start-up.
 */
static inline roz_port_t roz_engineai_pm01_port(roz_engineai_pm01_t *pm, roz_log_fn log,
                                                void *log_ctx)
{
    /* the instance as this translation unit lays it out (roz/port.h) */
    const roz_port_layout_t caller = ROZ_PORT_LAYOUT_INIT;
    return roz__engineai_pm01_port(pm, &caller, sizeof *pm, log, log_ctx);
}

/** @brief The checks on joint_state and imu_info, summed (roz_ros2_link()).
 *  Context: any thread. */
void roz_engineai_pm01_link(const roz_engineai_pm01_t *pm, roz_link_t *out);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_ENGINEAI_PM01_H */
