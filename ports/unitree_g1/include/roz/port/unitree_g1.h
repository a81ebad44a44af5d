/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port/unitree_g1.h
 * @brief The port `unitree/G1`: a Unitree G1 (29 joints) driven through
 *        `rt/lowcmd` and `rt/lowstate` (unitree_hg LowCmd_ / LowState_) over
 *        Cyclone DDS, as Unitree's own SDKs do on the wire.
 *
 * docs/ports/unitree_g1.md describes the port: bringing a robot up, the
 * joints and motor slots, the checks on every LowState_, the commands, the
 * three start-up layers, the exit and watchdog damping, every parameter,
 * and which thread runs what.
 */
#ifndef ROZ_PORT_UNITREE_G1_H
#define ROZ_PORT_UNITREE_G1_H

#include "roz/config.h"

#include <stdint.h>

#include "roz/atomic.h"
#include "roz/buffer.h"
#include "roz/port/dds.h"
#include "roz/hal/cmd_watchdog.h"
#include "roz/hal/joints.h"
#include "roz/hal/link.h"
#include "roz/log.h"
#include "roz/manifest.h"
#include "roz/monitor.h"
#include "roz/port.h"
#include "roz/private.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Motor slots of LowCmd_ / LowState_. */
#define ROZ_UNITREE_G1_SLOTS 35
/** Slots of the body (0-28); the manifest's joints are at most this many. */
#define ROZ_UNITREE_G1_BODY 29
/** 32-bit words of the native LowCmd_ (1004 bytes) and LowState_ (2092). */
#define ROZ_UNITREE_G1_CMD_WORDS 251
#define ROZ_UNITREE_G1_STATE_WORDS 523
/** Values after the states in a state frame: robot session, faulty slot,
 *  its code, mode_machine, tick, then each slot's measured q. */
#define ROZ_UNITREE_G1_STATE_META (5 + ROZ_UNITREE_G1_SLOTS)
/** Values after the commands in a command frame: session, hold, sequence,
 *  watchdog epoch, then each slot's last finite measured q (NaN: none yet). */
#define ROZ_UNITREE_G1_CMD_META (4 + ROZ_UNITREE_G1_SLOTS)
/** Largest number of merged parameters (robot.toml's and the caller's). */
#define ROZ_UNITREE_G1_MAX_PARAMS 48

/** One motor slot's channels (-1: none). */
typedef roz_joint_channels_t roz_unitree_g1_joint_t;

/** The port's counters (roz_unitree_g1_counters()). */
typedef struct roz_unitree_g1_counters {
    uint64_t frames;            /**< LowState_ samples received */
    uint64_t full_conversions;  /**< frames converted whole (decimation) */
    uint64_t motor_fault_frames;/**< accepted frames in which a motor reports a fault */
    uint64_t sessions;          /**< robots seen: the first one, then each restart or return */
    uint64_t writes;            /**< write() calls */
    uint64_t writes_withheld;   /**< writes before the first LowState_ (nothing sent) */
    uint64_t holds;             /**< first writes of a robot published as the start-up hold */
    uint64_t clamped;           /**< written values outside their channel (clamped; 0 behind
                                     the runtime's filter) */
    uint64_t writer_passes;     /**< writer passes begun */
    uint64_t writer_done;       /**< writer passes ended (none open when equal) */
    uint64_t published;         /**< LowCmd_ samples written */
    uint64_t publish_errors;    /**< dds_write failures */
    uint64_t stale_session;     /**< passes that sent nothing: the command was for a robot
                                     that restarted since */
    uint64_t refused_mode_machine; /**< passes that sent nothing: mode_machine changed */
    uint64_t handled_seq;       /**< sequence of the last command frame the writer took */
    uint64_t written_seq;       /**< sequence of the last command frame written */
    uint64_t command_timeouts;  /**< command watchdog trips: the tick went silent */
    uint64_t safe_published;    /**< damping commands the watchdog published */
    uint64_t sim_like_frames;   /**< frames dropped for their CRC that look like
                                     unitree_mujoco's (crc, tick and mode_machine
                                     all 0): the simulator without peer = unitree_mujoco */
    uint64_t remote_frames;     /**< accepted frames whose wireless_remote went to the
                                     operator sink (roz_port_set_operator()) */
    uint64_t remote_nonfinite;  /**< of those, frames with a NaN or infinite stick or
                                     trigger (the inputs refuse and count each value) */
} roz_unitree_g1_counters_t;

/** What is at the other end of rt/lowstate (the parameter `peer`). */
typedef enum roz_unitree_g1_peer {
    ROZ_UNITREE_G1_PEER_ROBOT = 0,      /**< a G1: every check (the default) */
    ROZ_UNITREE_G1_PEER_UNITREE_MUJOCO, /**< Unitree's simulator: no state CRC, no
                                             tick; docs/ports/unitree_g1.md */
} roz_unitree_g1_peer_t;

/** The port's instance; caller-owned (large: give it static storage).
 *  Fields are private (roz/private.h); the tests and tools read them
 *  through the functions below. */
typedef struct roz_unitree_g1 {
    /* ---- set at open, then read-only ---- */
    const roz_manifest_t  *ROZ_PRIVATE(m);
    roz_dds_params_t       ROZ_PRIVATE(dds);
    uint8_t                ROZ_PRIVATE(mode_pr);
    roz_unitree_g1_peer_t  ROZ_PRIVATE(peer);
    uint32_t               ROZ_PRIVATE(peer_timeout_ms);
    double                 ROZ_PRIVATE(startup_kd), ROZ_PRIVATE(shutdown_kd);
    roz_log_fn             ROZ_PRIVATE(log);
    void                  *ROZ_PRIVATE(log_ctx);
    uint16_t               ROZ_PRIVATE(n_joints);
    roz_unitree_g1_joint_t ROZ_PRIVATE(joint)[ROZ_UNITREE_G1_SLOTS]; /* by manifest joint */
    /* manifest joint -> motor slot */
    uint8_t                ROZ_PRIVATE(slot)[ROZ_UNITREE_G1_BODY];
    uint32_t               ROZ_PRIVATE(listed); /* bit s: slot s has a joint */
    /* quat x,y,z,w; gyro x,y,z; acc x,y,z: state or -1 */
    int16_t                ROZ_PRIVATE(imu)[ROZ_IMU_VALUES];
    roz_param_t            ROZ_PRIVATE(params)[ROZ_UNITREE_G1_MAX_PARAMS];
    int                    ROZ_PRIVATE(open), ROZ_PRIVATE(active);
    /* where LowState_.wireless_remote goes (set before activate) */
    roz_operator_sink_t    ROZ_PRIVATE(operator_sink);

    /* ---- DDS ---- */
    roz_dds_participant_t  ROZ_PRIVATE(part);
    roz_dds_reader_t       ROZ_PRIVATE(reader);
    roz_dds_writer_t       ROZ_PRIVATE(writer);
    /* one per thread that records */
    roz_monitor_t          ROZ_PRIVATE(mon_rx), ROZ_PRIVATE(mon_tx);
    /* LowState_, receive thread */
    uint32_t               ROZ_PRIVATE(rx_sample)[ROZ_UNITREE_G1_STATE_WORDS];
    /* LowCmd_, writer thread */
    uint32_t               ROZ_PRIVATE(tx_sample)[ROZ_UNITREE_G1_CMD_WORDS];

    /* ---- receive thread ---- */
    roz_link_t             ROZ_PRIVATE(link);
    uint32_t               ROZ_PRIVATE(session); /* robots seen */
    uint32_t               ROZ_PRIVATE(since_full); /* frames since the last full conversion */
    uint32_t               ROZ_PRIVATE(arrivals); /* peer unitree_mujoco: the link's sequence */
    double                 ROZ_PRIVATE(rx_values)[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    roz_link_shared_t      ROZ_PRIVATE(link_shared);
    ROZ_ATOMIC(uint32_t)   ROZ_PRIVATE(rx_session); /* for the writer */
    ROZ_ATOMIC(uint32_t)   ROZ_PRIVATE(rx_mode_machine);

    /* ---- receive thread -> tick ---- */
    roz_buffer_t           ROZ_PRIVATE(state_buf);
    double                 ROZ_PRIVATE(state_slots)[3 * ((ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES
                                                                                 : 1) +
                                                         ROZ_UNITREE_G1_STATE_META)];

    /* ---- tick ---- */
    int                    ROZ_PRIVATE(tick_has_state);
    uint32_t               ROZ_PRIVATE(tick_session); /* robot session of the last frame read */
    double                 ROZ_PRIVATE(tick_q)[ROZ_UNITREE_G1_SLOTS];
    roz_port_fault_t       ROZ_PRIVATE(tick_fault);

    /* ---- tick <-> writer thread: roz/port/dds.h's command path ---- */
    roz_dds_cmd_t          ROZ_PRIVATE(cmd);
    double                 ROZ_PRIVATE(cmd_slots)[3 * (ROZ_CFG_MAX_COMMANDS +
                                                       ROZ_UNITREE_G1_CMD_META)];

    /* ---- writer thread ---- */
    /* 0x100 | value once a command went out */
    ROZ_ATOMIC(uint32_t)   ROZ_PRIVATE(locked_mode_machine);
    uint32_t               ROZ_PRIVATE(tx_mode_machine); /* this pass's, for its fill */
    /* positions last commanded, by manifest joint */
    double                 ROZ_PRIVATE(tx_last_q)[ROZ_UNITREE_G1_SLOTS];
    /* and the stiffness and the measured position they went out with */
    double                 ROZ_PRIVATE(tx_last_kp)[ROZ_UNITREE_G1_SLOTS];
    int                    ROZ_PRIVATE(tx_ctrl);  /* tx_last_* hold a controller's frame */
    double                 ROZ_PRIVATE(tx_meas_q)[ROZ_UNITREE_G1_SLOTS];

    /* ---- counters (atomics: written by one thread, read by any) ---- */
    ROZ_ATOMIC(uint64_t)   ROZ_PRIVATE(c_frames), ROZ_PRIVATE(c_full), ROZ_PRIVATE(c_motor_fault),
                           ROZ_PRIVATE(c_sessions), ROZ_PRIVATE(c_sim_like),
                           ROZ_PRIVATE(c_remote), ROZ_PRIVATE(c_remote_nonfinite);
} roz_unitree_g1_t;

/** The ops table (name "unitree/G1"). */
extern const roz_port_ops_t roz_unitree_g1_ops;

/* The library half of the constructor below: the caller's layout and
 * instance size, refused when they are not the library's. */
roz_port_t roz__unitree_g1_port(roz_unitree_g1_t *g1, const roz_port_layout_t *caller,
                                size_t bytes, roz_log_fn log, void *log_ctx);

/**
 * @brief A roz_port_t over @p g1, not yet open (roz_port_open()).
 * @param log  where the port says which DDS configuration it uses and the
 *             monitors warn (from the port's threads); NULL: stderr
 */
static inline roz_port_t roz_unitree_g1_port(roz_unitree_g1_t *g1, roz_log_fn log, void *log_ctx)
{
    /* the instance as this translation unit lays it out (roz/port.h) */
    const roz_port_layout_t caller = ROZ_PORT_LAYOUT_INIT;
    return roz__unitree_g1_port(g1, &caller, sizeof *g1, log, log_ctx);
}

/** @brief The motor slot (0-28) of the body joint @p name (the SDK's
 *  joint name, "left_hip_pitch_joint"), or -1 when the G1 has none.
 *  Context: any; pure. */
int roz_unitree_g1_joint_slot(const char *name);

/** Called once per problem by roz_unitree_g1_check(): a rule id
 *  ("g1-joint", "g1-channel", "g1-param", "unknown-key") and the text after
 *  the file name (": unitree/G1: ..."). */
typedef void (*roz_unitree_g1_problem_fn)(void *ctx, const char *rule, const char *text);

/**
 * @brief The port's rules of @p m's [hardware] keys, as its open applies
 *        them to robot.toml's parameters: the joints and channels bound,
 *        then the parameters (a problem of the joints stops there; the
 *        parameters are each checked). No DDS: this is what
 *        roz_manifest_json, and so rozgen, runs (roz_add_port_rules()).
 *        Parameters given at open and CYCLONEDDS_URI are the open's alone.
 * @retval ROZ_OK, or ROZ_EINVAL after reporting every problem
 * Context: host tools and start-up, one call at a time; no heap.
 */
int roz_unitree_g1_check(const roz_manifest_t *m, roz_unitree_g1_problem_fn report, void *ctx);

/** The rule ids of roz_unitree_g1_check(), "<id>\t<what it refuses>", NULL-ended
 *  (its registration's RULE_IDS: roz_manifest_json --list-rules). */
extern const char *const roz_unitree_g1_rule_ids[];

/** @brief A consistent copy of the checks on LowState_ frames.
 *  Context: any thread. */
void roz_unitree_g1_link(const roz_unitree_g1_t *g1, roz_link_t *out);

/** @brief The counters. Context: any thread (each value is one atomic load). */
void roz_unitree_g1_counters(const roz_unitree_g1_t *g1, roz_unitree_g1_counters_t *out);

/** @brief Readers of rt/lowcmd and writers of rt/lowstate matched now (a
 *  test waits for both before it speaks). Context: any thread. */
void roz_unitree_g1_matched(const roz_unitree_g1_t *g1, uint32_t *cmd_readers,
                            uint32_t *state_writers);

/** @brief The port's DDS participant (its entity, domain and configuration),
 *  valid while the port is open. Context: any thread. */
const roz_dds_participant_t *roz_unitree_g1_participant(const roz_unitree_g1_t *g1);

/** @brief The command writer's monitor (jitter against its period, each
 *  pass's time), for roz_monitor_snapshot(). Context: any thread. */
const roz_monitor_t *roz_unitree_g1_writer_monitor(const roz_unitree_g1_t *g1);

/** @brief The receive path's monitor (the state handler's times), for
 *  roz_monitor_snapshot(). Context: any thread. */
const roz_monitor_t *roz_unitree_g1_state_monitor(const roz_unitree_g1_t *g1);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_UNITREE_G1_H */
