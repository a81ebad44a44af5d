/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port/agibot_x2.h
 * @brief The port `agibot/X2`: an AgiBot X2 (30 joints in four groups)
 *        driven through its AimDK HAL topics spoken directly over Cyclone
 *        DDS (roz/port/ros2.h), as a ROS 2 node on rmw_cyclonedds would.
 *
 * docs/ports/ros2.md describes the port: its topics and QoS, the groups and
 * their slots, the checks, the faults it reports (DomainErrorState, joint
 * error codes), the two JointState layouts (`joint_state_layout`), and what
 * is not known about the robot.
 */
#ifndef ROZ_PORT_AGIBOT_X2_H
#define ROZ_PORT_AGIBOT_X2_H

#include "roz/config.h"

#include <stdint.h>

#include "roz/hal/link.h"
#include "roz/log.h"
#include "roz/port.h"
#include "roz/private.h"
#include "roz/port/ros2.h"

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
 *  comes first: the port's self is the bridge, and roz/port/ros2.h's functions
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
 * @brief The port's rules of @p m's [hardware] keys, as its open applies
 *        them to robot.toml's parameters (roz_ros2_check()): what
 *        roz_manifest_json, and so rozgen, runs (roz_add_port_rules()).
 *        Parameters given at open and CYCLONEDDS_URI are the open's alone.
 * @retval ROZ_OK, or ROZ_EINVAL after reporting every problem
 * Context: host tools and start-up, one call at a time; no heap.
 */
int roz_agibot_x2_check(const roz_manifest_t *m, roz_params_problem_fn report, void *ctx);

/* The library half of the constructor below: the caller's layout and
 * instance size, refused when they are not the library's. */
roz_port_t roz__agibot_x2_port(roz_agibot_x2_t *x2, const roz_port_layout_t *caller,
                               size_t bytes, roz_log_fn log, void *log_ctx);

/**
 * @brief A roz_port_t over @p x2, not yet open (roz_port_open()).
 * @param log  where the port says which DDS configuration it uses, what it
 *             drops and what the monitors see (from its threads); NULL: stderr
 * Context: start-up.
 */
static inline roz_port_t roz_agibot_x2_port(roz_agibot_x2_t *x2, roz_log_fn log, void *log_ctx)
{
    /* the instance as this translation unit lays it out (roz/port.h) */
    const roz_port_layout_t caller = ROZ_PORT_LAYOUT_INIT;
    return roz__agibot_x2_port(x2, &caller, sizeof *x2, log, log_ctx);
}

/** @brief The checks on the state topics, summed (roz_ros2_link()).
 *  Context: any thread. */
void roz_agibot_x2_link(const roz_agibot_x2_t *x2, roz_link_t *out);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_AGIBOT_X2_H */
