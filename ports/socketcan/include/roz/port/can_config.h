/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port/can_config.h
 * @brief The `[hardware]` table of a robot driven by the socketcan port:
 *        its keys, their rules, and the per-joint settings and bus figures
 *        they give. Portable (no OS, no heap): firmware can use it too.
 *
 * docs/ports/socketcan.md lists every key with its values and default, the
 * channels a joint takes, and the bus load and round-robin rule. rozgen
 * runs these rules too (through roz_manifest_json), so a robot.toml is
 * refused at build time with the words the port says at open.
 */
#ifndef ROZ_PORT_CAN_CONFIG_H
#define ROZ_PORT_CAN_CONFIG_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/manifest.h"
#include "roz/port/mit_codec.h"
#include "roz/port.h"
#include "roz/hal/thread.h"

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
    roz_thread_config_t receive_thread; /**< receive_thread_sched, ... (roz/hal/thread.h) */
    roz_thread_config_t writer_thread;  /**< command_writer_sched, ... */
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

/**
 * @brief roz_can_config_load() without extra parameters, into storage of its
 *        own: the port's check_hardware (roz_add_port_rules(), roz/port_rules.h),
 *        which roz_manifest_json and so rozgen run.
 * @retval ROZ_OK     valid
 * @retval ROZ_EINVAL a problem (each reported)
 * Context: host tools; not reentrant (one static configuration); no heap.
 */
int roz_can_config_check(const roz_manifest_t *m, roz_can_problem_fn report, void *ctx);

/** The rule ids of roz_can_config_check(), "<id>\t<what it refuses>", NULL-ended
 *  (its registration's RULE_IDS: roz_manifest_json --list-rules). */
extern const char *const roz_can_rule_ids[];

/** @brief The rule ids roz_can_config_load() reports, NULL-terminated.
 *  Context: any. */
const char *const *roz_can_config_rules(void);

/** @brief The keys it knows, NULL-terminated, in the order it checks them.
 *  Context: any. */
const char *const *roz_can_config_keys(void);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_CAN_CONFIG_H */
