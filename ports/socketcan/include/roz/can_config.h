/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/can_config.h
 * @brief The `[hardware]` table of a robot driven by the socketcan port:
 *        its keys, their rules, and the per-joint settings and bus figures
 *        they give. Portable (no OS, no heap): firmware can use it too.
 *
 * ```toml
 * [hardware]
 * port = "socketcan"
 * joints = ["hip", "thigh", "knee"]          # the actuators, one per joint
 *
 * [hardware.params]
 * network_interface = "can0"
 * bitrate = "1000000"
 * reply = "temperature_error"
 * position_range = "-12.5:12.5"              # the actuators' firmware ranges
 * velocity_range = "-45:45"
 * stiffness_range = "0:500"
 * damping_range = "0:5"
 * effort_range = "-18:18, knee=-24:24"       # every joint, and one exception
 * can_id = "hip=1, thigh=2, knee=3"
 * direction = "knee=-1"
 * zero_offset = "thigh=0.35, knee=-1.2"
 * ```
 *
 * Per-joint keys hold comma-separated entries: `VALUE` for every joint,
 * `JOINT=VALUE` for one (which wins over the former). A joint may appear
 * once per key, and so may the entry for every joint.
 *
 * | key | value | default |
 * |-----|-------|---------|
 * | can_id | the actuator's 11-bit CAN id, 1..2047 (decimal or 0x hex), per joint; the low byte must be unique (a reply names its actuator by it) and none may be master_id | required |
 * | reply | the reply layout (roz/mit_codec.h): `basic` or `temperature_error` | required |
 * | position_range, velocity_range, stiffness_range, damping_range, effort_range | `MIN:MAX`, the actuator firmware's ranges for position (rad), velocity (rad/s), kp (N.m/rad), kd (N.m.s/rad), torque (N.m); all but position hold 0 (a hold sends 0); they must hold the manifest's limits of the joint's channels, seen from the actuator | required |
 * | direction | 1, or -1 when the actuator turns against the joint | 1 |
 * | zero_offset | the joint's position (rad) when the actuator reads 0 | 0 |
 * | network_interface | the CAN interface, at most 15 bytes | can0 |
 * | bitrate | the bus's bit rate as set on the interface (`ip link set can0 type can bitrate ...`; roz does not set it), 10000..1000000 | 1000000 |
 * | command_writer_period_us | the command writer's period; 0 sends a round when the tick writes; else 100..1000000 | 2000 |
 * | max_bus_load_percent | the share of the bus a period's frames may take, worst case, 10..100 | 80 |
 * | reply_timeout_us | a command unanswered this long makes its joint stale; at least two command intervals of a joint, 1000..10000000 | 20000 or three intervals, whichever is longer |
 * | command_timeout_us | the command watchdog (roz/hal/cmd_watchdog.h): the tick silent this long, the writer holds every actuator without gains; at least two command intervals of a joint and two ticks, 1000..60000000 | 50000 or five intervals or ticks, whichever is longer |
 * | master_id | the CAN id replies may come from besides the actuator's own, 0..2047 | 0 |
 * | consistency_margin | rad: a position that moves this much more (or less) than its velocity says is a fault; 0 = off | 0.2 |
 * | enable_monitor | true/false (1/0, yes/no, on/off): jitter warnings | true |
 * | state_decimation | 1 (every reply is converted) | 1 |
 *
 * Joints: the joint of a channel is the name before its last '/', the part
 * after it must be the channel's interface type. Per joint the port reads
 * the states `position`, `velocity`, `effort` and takes the commands
 * `position`, `velocity`, `stiffness`, `damping`, `effort`; any other
 * channel, a channel of a joint not in `hardware.joints`, and a joint
 * without a channel are errors. Seen from the actuator, position is
 * direction * (joint position - zero_offset), velocity and effort are
 * direction * the joint's, gains are the same.
 *
 * The bus: a joint's command is an 8-byte frame and its reply 6 or 8 bytes;
 * worst case (every stuff bit) a standard frame of n bytes takes 47 + 8n +
 * floor((33 + 8n) / 4) bits: 135 for 8 bytes, 115 for 6. When the joints'
 * frames take more than max_bus_load_percent of a period, the joints are
 * commanded round-robin in `groups` (joint i in group i mod groups, one
 * group a period) and each joint every `groups` periods.
 *
 * The rules are rozgen's as well (codegen/rozgen/socketcan.py): the same
 * problems, rule ids and words, for every fixture in manifests/invalid/.
 */
#ifndef ROZ_CAN_CONFIG_H
#define ROZ_CAN_CONFIG_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/manifest.h"
#include "roz/mit_codec.h"
#include "roz/port.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Most joints (actuators) of one robot. */
#define ROZ_CAN_MAX_JOINTS (ROZ_CFG_MAX_JOINTS > 0 ? ROZ_CFG_MAX_JOINTS : 1)
/** Longest interface name, bytes (Linux's IFNAMSIZ less the NUL). */
#define ROZ_CAN_IFNAME_MAX 15
/** Worst-case bits on the bus of a standard data frame of @p n bytes. */
#define ROZ_CAN_FRAME_BITS(n) (47u + 8u * (n) + (33u + 8u * (n)) / 4u)

/** One joint's actuator and its channels (-1: none). */
typedef struct roz_can_joint {
    const char            *name;        /**< hardware.joints[i] (the manifest's storage) */
    uint16_t               can_id;      /**< 1..2047 */
    roz_mit_reply_layout_t reply;
    roz_mit_ranges_t       ranges;      /**< the actuator's, in its own frame */
    int                    direction;   /**< 1 or -1 */
    double                 zero_offset; /**< joint position at actuator position 0 */
    int32_t                pos_state, vel_state, eff_state;
    int32_t                pos_cmd, vel_cmd, kp_cmd, kd_cmd, eff_cmd;
} roz_can_joint_t;

/** A checked configuration. */
typedef struct roz_can_config {
    char            network_interface[ROZ_CAN_IFNAME_MAX + 1];
    uint32_t        bitrate;                  /**< bit/s */
    uint32_t        command_writer_period_us; /**< 0: a round per write */
    uint32_t        max_bus_load_percent;
    uint32_t        reply_timeout_us;
    uint32_t        command_timeout_us;       /**< the command watchdog */
    uint32_t        master_id;
    double          consistency_margin;       /**< rad; 0 = off */
    int             enable_monitor;
    uint16_t        n_joints;
    roz_can_joint_t joints[ROZ_CAN_MAX_JOINTS];
    /* the bus */
    uint32_t        round_us;           /**< a round's time: the period, or the control period */
    uint32_t        groups;             /**< round-robin groups, 1 = every joint every round */
    uint32_t        group_bits;         /**< worst-case bits of the busiest round */
    double          bus_load;           /**< group_bits / the bits a round holds, 0..1 */
    uint32_t        joint_interval_us;  /**< how often each joint is commanded */
} roz_can_config_t;

/** Called once per problem: @p rule is a rozgen rule id ("can-id"),
 *  @p text starts with ": " (rozgen prints the file name before it). */
typedef void (*roz_can_problem_fn)(void *ctx, const char *rule, const char *text);

/**
 * @brief Read and check the CAN keys of @p m (its [hardware] table) with
 *        @p extra parameters over them (a later key wins: the caller's
 *        override robot.toml's), and bind the joints' channels.
 * @param[out] cfg     the configuration; valid only on ROZ_OK
 * @param[in]  m       a manifest that passes roz_manifest_validate()
 * @param[in]  extra   more parameters, or NULL
 * @param[in]  report  called for every problem, in rozgen's order; may be NULL
 * @retval ROZ_OK     valid; @p cfg filled
 * @retval ROZ_EINVAL a problem (each reported); also for a manifest without
 *                    [hardware] or whose port is not "socketcan"
 * Context: start-up (a port's open(), a tool); no heap; not the tick.
 */
int roz_can_config_load(roz_can_config_t *cfg, const roz_manifest_t *m, const roz_params_t *extra,
                        roz_can_problem_fn report, void *ctx);

/** @brief The rule ids roz_can_config_load() reports, NULL-terminated.
 *  Context: any. */
const char *const *roz_can_config_rules(void);

/** @brief The keys it knows, NULL-terminated, in the order it checks them.
 *  Context: any. */
const char *const *roz_can_config_keys(void);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_CAN_CONFIG_H */
