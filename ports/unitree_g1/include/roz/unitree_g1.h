/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/unitree_g1.h
 * @brief The port `unitree/G1`: a Unitree G1 (29 joints) driven through
 *        `rt/lowcmd` and `rt/lowstate` (unitree_hg LowCmd_ / LowState_) over
 *        Cyclone DDS, as Unitree's own SDKs do on the wire.
 *
 * Binding (at open, by name, never in the tick): each of the manifest's
 * `[hardware] joints` is bound to its motor slot by its SDK joint name, in
 * any order and any subset (the 29-DoF order: left_hip_pitch_joint,
 * left_hip_roll_joint, left_hip_yaw_joint, left_knee_joint,
 * left_ankle_pitch_joint, left_ankle_roll_joint = 0-5; the right leg's six
 * = 6-11; waist_yaw_joint, waist_roll_joint, waist_pitch_joint = 12-14;
 * left_shoulder_pitch_joint, left_shoulder_roll_joint,
 * left_shoulder_yaw_joint, left_elbow_joint, left_wrist_roll_joint,
 * left_wrist_pitch_joint, left_wrist_yaw_joint = 15-21; the right arm's
 * seven = 22-28; roz_unitree_g1_joint_slot()). A name that is not one of
 * these, or one listed twice, is an error at open naming it; a slot with no
 * joint listed is never driven (nor are 29-34). For each joint the
 * states `{joint}/position`, `/velocity`, `/effort` come from the motor's q,
 * dq, tau_est, and the commands `{joint}/position`, `/velocity`, `/effort`,
 * `/stiffness`, `/damping` go to its q, dq, tau, kp, kd. The IMU states
 * `base_imu/orientation.{x,y,z,w}` come from Unitree's quaternion, which is
 * w, x, y, z; `base_imu/angular_velocity.*` from the gyroscope,
 * `base_imu/linear_acceleration.*` from the accelerometer. A manifest
 * channel the G1 has no place for is an error at open naming it.
 *
 * State (Cyclone's receive thread, roz/dds.h): every LowState_ is checked
 * before anything of it is used: its CRC (crc32_core over the native struct,
 * roz/hal/crc32.h), then its `tick` through roz/hal/link.h (bad CRC and
 * replays dropped and counted; a robot that restarts, or comes back after
 * `peer_timeout_ms` of silence, makes read() return ROZ_ELINK once and the
 * start-up layers begin again). Every frame's safety fields are converted:
 * the motors' fault codes, mode_machine and the joint positions; the rest
 * (velocities, efforts, IMU) every `state_decimation`-th frame (the first
 * frame of a robot always). A joint whose motor reports a fault code
 * (`motorstate` != 0) makes read() return ROZ_EROBOT for every frame that
 * reports it; fault() names the joint and the code (the runtime latches
 * ROZ_FAULT_ROBOT).
 *
 * Commands: write() hands the frame to the command writer thread through a
 * latest-value buffer (never blocks); the writer publishes at
 * `command_writer_period_us` (2000), or at once when that is 0. Every
 * publish fills a freshly zeroed LowCmd_ (stale padding under the CRC makes
 * the robot drop a command without a word): mode 1 for the manifest's
 * joints, 0 and all zero for the other slots; q, dq, tau, kp, kd from the
 * command channels (a joint without one sends 0 there); `mode_pr` from the
 * parameter; `mode_machine` echoed from the latest LowState_; the CRC over
 * the native struct. A robot whose `mode_machine` names a variant without a
 * motor for a listed joint (4, 10: 23-DoF, no slots 13, 14, 20, 21, 27, 28;
 * 6, 12, 14, 16: waist locked, no 13, 14) gets nothing, and read() returns
 * ROZ_EROBOT with fault() naming the joint and the mode_machine (0,
 * simulation, and every other value take the whole body). The
 * mode_machine of the first command sent is kept:
 * while the robot reports another, nothing is sent and read() returns
 * ROZ_EROBOT (fault(): "mode_machine changed under a running controller").
 *
 * Safe start-up, three layers: nothing is sent before the first LowState_
 * (writes before it are counted and dropped); the first frame of a robot
 * (at open, or after a restart) sets the command to hold each joint's
 * measured position with zero gains (kd = `startup_damping`, 0 unless set:
 * a damping hold as the vendor's deploy code uses); and the first write
 * after it is published as that hold, not as what was written. A robot that
 * restarted gets nothing until the tick writes again. On deactivate, the
 * writer stops, then the damping command (kp 0, kd `shutdown_damping`,
 * default the manifest's damping default) goes out, when anything was sent,
 * repeated for ROZ_DDS_SHUTDOWN_REPEAT_MS (roz_dds_writer_publish_final()).
 *
 * Command watchdog (roz/hal/cmd_watchdog.h): when the latest command the
 * tick wrote is older than `command_timeout_us` (the tick stopped: a killed
 * or stuck control loop), the writer publishes that same damping command
 * instead, every period (event-driven: every tick period), on its own; the
 * tick's next read() returns ROZ_EWATCHDOG (the runtime latches
 * ROZ_FAULT_COMMAND_TIMEOUT naming how long the tick was silent), and its
 * next write is published as the start-up hold; a command written before
 * the trip is never published.
 *
 * Parameters (robot.toml [hardware.params], overridden by the caller's;
 * errors name the key and the value): `network_interface` (lo),
 * `dds_domain` (0), `enable_monitor` (true), `command_writer_period_us`
 * (2000; 0 = as soon as the tick writes), `command_writer_spin_us` (0;
 * with 0 above: the writer, woken when a LowState_ arrives, spins up to
 * that long for the tick's command: roz/dds.h), `state_decimation` (1), `mode_pr`
 * (PR or AB, or 0 or 1; default PR), `peer_timeout_ms` (500),
 * `startup_damping` (0), `shutdown_damping` (the damping channels' default),
 * `command_timeout_us` (50000, or 5 tick or writer periods when longer).
 *
 * Threads: open, activate, deactivate and close from the application's
 * thread; read, write and fault from the tick; the rest runs on Cyclone's
 * receive thread and the writer thread, which meet the tick through
 * roz/buffer.h and atomics only.
 */
#ifndef ROZ_UNITREE_G1_H
#define ROZ_UNITREE_G1_H

#include "roz/config.h"

#include <stdint.h>

#include "roz/atomic.h"
#include "roz/buffer.h"
#include "roz/dds.h"
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
 *  watchdog epoch. */
#define ROZ_UNITREE_G1_CMD_META 4
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
} roz_unitree_g1_counters_t;

/** The port's instance; caller-owned (large: give it static storage).
 *  Fields are private (roz/private.h); the tests and tools read them
 *  through the functions below. */
typedef struct roz_unitree_g1 {
    /* ---- set at open, then read-only ---- */
    const roz_manifest_t  *ROZ_PRIVATE(m);
    roz_dds_params_t       ROZ_PRIVATE(dds);
    uint8_t                ROZ_PRIVATE(mode_pr);
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

    /* ---- tick <-> writer thread: roz/dds.h's command path ---- */
    roz_dds_cmd_t          ROZ_PRIVATE(cmd);
    double                 ROZ_PRIVATE(cmd_slots)[3 * (ROZ_CFG_MAX_COMMANDS +
                                                       ROZ_UNITREE_G1_CMD_META)];

    /* ---- writer thread ---- */
    /* 0x100 | value once a command went out */
    ROZ_ATOMIC(uint32_t)   ROZ_PRIVATE(locked_mode_machine);
    uint32_t               ROZ_PRIVATE(tx_mode_machine); /* this pass's, for its fill */
    /* positions last commanded, by manifest joint */
    double                 ROZ_PRIVATE(tx_last_q)[ROZ_UNITREE_G1_SLOTS];

    /* ---- counters (atomics: written by one thread, read by any) ---- */
    ROZ_ATOMIC(uint64_t)   ROZ_PRIVATE(c_frames), ROZ_PRIVATE(c_full), ROZ_PRIVATE(c_motor_fault),
                           ROZ_PRIVATE(c_sessions);
} roz_unitree_g1_t;

/** The ops table (name "unitree/G1"). */
extern const roz_port_ops_t roz_unitree_g1_ops;

/**
 * @brief A roz_port_t over @p g1, not yet open (roz_port_open()).
 * @param log  where the port says which DDS configuration it uses and the
 *             monitors warn (from the port's threads); NULL: stderr
 */
roz_port_t roz_unitree_g1_port(roz_unitree_g1_t *g1, roz_log_fn log, void *log_ctx);

/** @brief The motor slot (0-28) of the body joint @p name (the SDK's
 *  joint name, "left_hip_pitch_joint"), or -1 when the G1 has none.
 *  Context: any; pure. */
int roz_unitree_g1_joint_slot(const char *name);

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

#endif /* ROZ_UNITREE_G1_H */
