/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port/ros2.h
 * @brief roz::ros2, what the ports that speak a robot's ROS 2 topics share
 *        (`engineai/PM01`, `agibot/X2`): ROS 2's conventions on plain
 *        Cyclone DDS, and the bridge between a robot's joint-group topics
 *        and roz's port contract. No ROS 2 installation is involved.
 *
 * A robot is a constant description (roz_ros2_robot_t: joint groups, the
 * IMU topic, the types, the QoS) and four conversions; the bridge binds the
 * manifest by joint name, checks every state topic, gathers the topics into
 * one frame, runs the start-up layers and the command watchdog, and
 * publishes every group's command in one pass. docs/ports/ros2.md
 * describes it all, with the parameters common to ROS 2 ports.
 */
#ifndef ROZ_PORT_ROS2_H
#define ROZ_PORT_ROS2_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/atomic.h"
#include "roz/buffer.h"
#include "roz/port/dds.h"
#include "roz/hal/cmd_watchdog.h"
#include "roz/hal/joints.h"
#include "roz/hal/link.h"
#include "roz/hal/params.h"
#include "roz/joy.h"
#include "roz/log.h"
#include "roz/manifest.h"
#include "roz/monitor.h"
#include "roz/operator.h"
#include "roz/port.h"
#include "roz/private.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Joint groups of a robot (a state and a command topic each). */
#define ROZ_ROS2_MAX_GROUPS 4
/** State topics: the groups and the IMU. */
#define ROZ_ROS2_MAX_TOPICS (ROZ_ROS2_MAX_GROUPS + 1)
/** Joints in one group. */
#define ROZ_ROS2_MAX_SLOTS 32
/** Joints over all groups. */
#define ROZ_ROS2_MAX_ROBOT_SLOTS 48
/** 8-byte words of storage for one sample's struct (its sequences and
 *  strings are allocated at open). */
#define ROZ_ROS2_SAMPLE_WORDS 48
/** Largest number of merged parameters (robot.toml's and the caller's). */
#define ROZ_ROS2_MAX_PARAMS 48
/** Values after a state topic's values in its frame: session, fault kind,
 *  fault slot, fault code, fault serial. */
#define ROZ_ROS2_STATE_META 5
/** Values after the commands in a command frame: session, hold, sequence,
 *  watchdog epoch, then each robot slot's measured position. */
#define ROZ_ROS2_CMD_META (4 + ROZ_ROS2_MAX_ROBOT_SLOTS)

/* ---- ROS 2 conventions ---------------------------------------------------- */

/** @brief The system clock (ROS time) as a builtin_interfaces/Time.
 *  Context: any; RT-safe (vDSO). */
void roz_ros2_stamp_now(int32_t *sec, uint32_t *nanosec);

/**
 * @brief A header stamp as a link sequence number: microseconds modulo 2^32.
 * @retval 1 valid; 0 not a time (nanosec above 999999999, or before 1970)
 * Context: any; pure.
 */
int roz_ros2_stamp_seq(int32_t sec, uint32_t nanosec, uint32_t *seq);

/** The link window for stamps: a stamp this many microseconds behind the
 *  last (one second) is a replay; further, a restart. */
#define ROZ_ROS2_STAMP_WINDOW_US 1000000u

/* ---- operator devices: /cmd_vel and /joy ------------------------------------ */

/** Most axes, and most buttons, of a sensor_msgs/Joy the bridge takes (the
 *  IDL's bound: Cyclone refuses a longer sample before it is stored): the
 *  core's Joy rule's (roz/joy.h). */
#define ROZ_ROS2_JOY_MAX ROZ_JOY_MAX
/** Room for a DDS topic name ("rt" and a ROS name), with its NUL. */
#define ROZ_ROS2_TOPIC_NAME_MAX 96

/** The parameter joy_map, read by the core's rule (roz/joy.h). */
typedef roz_joy_source_t roz_ros2_joy_source_t;
typedef roz_joy_map_t    roz_ros2_joy_map_t;

/** joy_map's default: ROS 2 joy's game_controller_node (SDL's game
 *  controller order, an Xbox or PlayStation pad): axes 0..5 left x, left y,
 *  right x, right y, left trigger, right trigger, left and up positive,
 *  a trigger 0 released to -1 pressed; buttons A/cross 0, B/circle 1,
 *  X/square 2, Y/triangle 3, back/select 4, guide 5, start 6, the sticks
 *  7 and 8, the shoulders 9 and 10, the D-pad up 11, down 12, left 13,
 *  right 14. The remote's sticks are right and up positive, its triggers
 *  0..1; its buttons l2 and r2 are the triggers pressed past half way;
 *  f1 and f2 have no counterpart. */
#define ROZ_ROS2_JOY_MAP_DEFAULT                                                              \
    "lx=-a0 ly=a1 rx=-a2 ry=a3 l2=-a4 r2=-a5 btn.r1=b10 btn.l1=b9 btn.start=b6 "              \
    "btn.select=b4 btn.r2=-a5 btn.l2=-a4 btn.a=b0 btn.b=b1 btn.x=b2 btn.y=b3 btn.up=b11 "      \
    "btn.right=b14 btn.down=b12 btn.left=b13"

/**
 * @brief Read the parameter joy_map: roz_joy_map_parse() (roz/joy.h, its
 *        grammar), its error naming the parameter.
 * @param[out] err "parameter joy_map = \"...\": ..." naming the entry
 * @retval ROZ_OK, ROZ_EINVAL
 * Context: open; no heap.
 */
int roz_ros2_joy_map_parse(const char *text, roz_ros2_joy_map_t *map, char *err, size_t errlen);

/** @brief roz_joy_remote() (roz/joy.h): one Joy message through joy_map.
 *  Context: any (a receive thread); RT-safe, no heap. */
static inline int roz_ros2_joy_remote(const roz_ros2_joy_map_t *map, const float *axes,
                                      uint32_t n_axes, const int32_t *buttons,
                                      uint32_t n_buttons, roz_operator_remote_t *out)
{
    return roz_joy_remote(map, axes, n_axes, buttons, n_buttons, out);
}

/* ---- a robot's description (the port's constant) ----------------------------- */

/** One joint group: its topics (DDS names) and its joints in slot order. */
typedef struct roz_ros2_group {
    const char        *name;          /**< "leg"; "body" */
    const char        *state_topic;   /**< "rt/aima/hal/joint/leg/state" */
    const char        *command_topic; /**< "rt/aima/hal/joint/leg/command" */
    const char *const *slots;         /**< the robot's joint names in slot order */
    uint16_t           n_slots;
} roz_ros2_group_t;

/** A state sample's header, as the port's decode reads it. */
typedef struct roz_ros2_header {
    int32_t  sec;
    uint32_t nanosec;
    uint32_t sequence;  /**< 0 where the message has none */
} roz_ros2_header_t;

/** Why the port's decode refused a sample. */
typedef enum roz_ros2_bad {
    ROZ_ROS2_GOOD = 0,
    ROZ_ROS2_BAD_LENGTH, /**< an array's length is not the group's (a: got, b: expected) */
    ROZ_ROS2_BAD_NAME,   /**< a joint's name is not its slot's (a: slot) */
    ROZ_ROS2_BAD_STAMP,  /**< the header's stamp is not a time */
    ROZ_ROS2_BAD_COUNT_
} roz_ros2_bad_t;

/** What the port's decode makes of one group's state sample. */
typedef struct roz_ros2_rx {
    double  *q, *dq, *tau; /**< n_slots each (the bridge's storage); dq, tau when full */
    uint32_t fault_kind;   /**< 0 none; else 1 + an index into the robot's fault_kinds */
    int32_t  fault_slot;   /**< the joint slot at fault; -1: the group */
    uint32_t fault_code;   /**< the robot's own code */
    int32_t  bad_a, bad_b; /**< what was wrong (roz_ros2_bad_t) */
} roz_ros2_rx_t;

/** One joint's command, as the port's encode puts it on the wire. */
typedef struct roz_ros2_joint_cmd {
    double q, dq, tau, kp, kd;
} roz_ros2_joint_cmd_t;

/** One group's command for the port's encode. */
typedef struct roz_ros2_cmd {
    const roz_ros2_joint_cmd_t *joint;    /**< n_slots, slot order */
    uint16_t                    n_slots;
    int32_t                     sec;      /**< stamp: when the pass began (system clock) */
    uint32_t                    nanosec;
    uint32_t                    sequence; /**< this topic's samples, from 1 */
} roz_ros2_cmd_t;

/** A robot: its groups, topics, types, QoS and the port's conversions.
 *  The hooks get @p v, the port's instance (its roz_ros2_bridge_t first). */
typedef struct roz_ros2_robot {
    const char             *port;           /**< "engineai/PM01" */
    const roz_ros2_group_t *groups;
    uint16_t                n_groups;
    const char             *imu_topic;      /**< "rt/hardware/imu_info"; NULL: none */
    uint32_t                default_domain; /**< dds_domain when no parameter says */
    const roz_dds_qos_t    *state_qos;      /**< the state and IMU readers */
    const roz_dds_qos_t    *command_qos;    /**< the command writers */
    int                     has_sequence;   /**< the state headers carry a sequence */
    /** what the port says of itself: its parameter rows are its known keys,
     *  in the order an unknown key's error lists them (ROZ_ROS2_PARAM_INFO,
     *  then its own) */
    const roz_port_info_t  *info;
    const char *const      *fault_kinds;    /**< what rx.fault_kind names, static */
    /** The port's own parameters. Context: open. */
    int (*params)(void *v, const roz_params_t *p, char *err, size_t errlen);
    /** The group state type (a `const dds_topic_descriptor_t *`) and its
     *  size, which may depend on the port's parameters. Context: open. */
    const void *(*state_type)(void *v, size_t *size);
    const void *imu_type;      /**< descriptor; its struct starts with a std_msgs/Header */
    size_t      imu_size;
    const void *command_type;  /**< descriptor */
    size_t      command_size;
    /** Size a group state sample's sequences and strings for @p n_slots
     *  joints (roz_dds_seq_reserve(), roz_dds_string_reserve()).
     *  Context: open; may allocate. */
    int (*reserve)(void *v, void *sample, uint16_t n_slots);
    /** The header of a group state sample. Context: a receive thread. */
    void (*state_header)(void *v, const void *sample, roz_ros2_header_t *h);
    /** Check and convert a group state sample: positions and faults always,
     *  velocities and efforts when @p full. ROZ_ROS2_GOOD, or why not (rx's
     *  bad_a, bad_b say more). Context: a receive thread; RT-safe. */
    roz_ros2_bad_t (*decode)(void *v, uint16_t group, const void *sample, int full,
                             roz_ros2_rx_t *rx);
    /** The IMU's ten values of an IMU sample. Context: a receive thread. */
    void (*decode_imu)(const void *sample, double *out);
    /** Fill a zeroed command sample for one group; sequences and strings
     *  point into the port's own storage (the writer thread's). Context:
     *  the writer thread (or the caller's after it stopped); RT-safe. */
    void (*encode)(void *v, uint16_t group, const roz_ros2_cmd_t *c, void *sample);
} roz_ros2_robot_t;

/* ---- the bridge ---------------------------------------------------------------- */

/** One manifest joint's place on the robot. */
typedef struct roz_ros2_place {
    uint16_t group, slot;
} roz_ros2_place_t;

/** One state topic: its reader and checks (a receive thread), its frames to
 *  the tick. Fields private (roz/private.h). */
typedef struct roz_ros2_topic {
    struct roz_ros2_bridge *ROZ_PRIVATE(bridge);
    uint16_t             ROZ_PRIVATE(index); /* < n_groups: a group; n_groups: the IMU */
    uint16_t             ROZ_PRIVATE(n_values);
    const char          *ROZ_PRIVATE(name); /* DDS topic */
    const void          *ROZ_PRIVATE(type);
    size_t               ROZ_PRIVATE(size);
    roz_dds_reader_t     ROZ_PRIVATE(reader);
    uint64_t             ROZ_PRIVATE(sample)[ROZ_ROS2_SAMPLE_WORDS];
    roz_monitor_t        ROZ_PRIVATE(mon); /* this listener's handler times */
    /* the receive thread's */
    roz_link_t           ROZ_PRIVATE(link);
    uint32_t             ROZ_PRIVATE(session), ROZ_PRIVATE(since_full);
    /* accepted: q, dq, tau (or IMU) */
    double               ROZ_PRIVATE(values)[3 * ROZ_ROS2_MAX_SLOTS];
    double               ROZ_PRIVATE(scratch)[3 * ROZ_ROS2_MAX_SLOTS]; /* a sample being checked */
    roz_link_shared_t    ROZ_PRIVATE(link_shared);
    /* a fault not yet taken */
    uint32_t             ROZ_PRIVATE(held_kind), ROZ_PRIVATE(held_code), ROZ_PRIVATE(held_serial);
    int32_t              ROZ_PRIVATE(held_slot);
    ROZ_ATOMIC(uint32_t) ROZ_PRIVATE(fault_ack); /* tick -> receive thread: the serial it took */
    ROZ_ATOMIC(uint32_t) ROZ_PRIVATE(rx_session); /* for the writer */
    ROZ_ATOMIC(uint32_t) ROZ_PRIVATE(said); /* bad kinds kept to say once (a bit each) */
    ROZ_ATOMIC(int32_t)  ROZ_PRIVATE(said_a)[ROZ_ROS2_BAD_COUNT_]; /* their bad_a, bad_b */
    ROZ_ATOMIC(int32_t)  ROZ_PRIVATE(said_b)[ROZ_ROS2_BAD_COUNT_];
    uint32_t             ROZ_PRIVATE(told);  /* roz_ros2_drain(): the kinds it said */
    ROZ_ATOMIC(uint64_t) ROZ_PRIVATE(c_samples), ROZ_PRIVATE(c_malformed), ROZ_PRIVATE(c_full),
                         ROZ_PRIVATE(c_fault), ROZ_PRIVATE(c_sessions);
    /* receive thread -> tick */
    roz_buffer_t         ROZ_PRIVATE(buf);
    double               ROZ_PRIVATE(slots)[3 * (3 * ROZ_ROS2_MAX_SLOTS + ROZ_ROS2_STATE_META)];
    /* the tick's */
    double               ROZ_PRIVATE(staged)[3 * ROZ_ROS2_MAX_SLOTS + ROZ_ROS2_STATE_META];
    uint32_t             ROZ_PRIVATE(tick_session);
    /* the first since the last frame */
    uint32_t             ROZ_PRIVATE(tick_fault_kind), ROZ_PRIVATE(tick_fault_code);
    int32_t              ROZ_PRIVATE(tick_fault_slot);
} roz_ros2_topic_t;

/** An operator topic (/cmd_vel, /joy): its reader, its sample, what it
 *  refused. Fields private (roz/private.h). */
typedef struct roz_ros2_op_topic {
    struct roz_ros2_bridge *ROZ_PRIVATE(bridge);
    char                 ROZ_PRIVATE(name)[ROZ_ROS2_TOPIC_NAME_MAX]; /* DDS; "": not read */
    roz_dds_reader_t     ROZ_PRIVATE(reader);
    uint64_t             ROZ_PRIVATE(sample)[16];
    ROZ_ATOMIC(uint64_t) ROZ_PRIVATE(c_samples), ROZ_PRIVATE(c_refused), ROZ_PRIVATE(c_handed);
    ROZ_ATOMIC(uint64_t) ROZ_PRIVATE(c_oversized); /* of c_refused: past ROZ_ROS2_JOY_MAX */
} roz_ros2_op_topic_t;

/** One command topic: its writer (only the first group's has a thread; it
 *  publishes the others in its pass). Fields private (roz/private.h). */
typedef struct roz_ros2_out {
    struct roz_ros2_bridge *ROZ_PRIVATE(bridge);
    uint16_t             ROZ_PRIVATE(group);
    roz_dds_writer_t     ROZ_PRIVATE(writer);
    uint64_t             ROZ_PRIVATE(sample)[ROZ_ROS2_SAMPLE_WORDS];
    uint32_t             ROZ_PRIVATE(sequence); /* the writer thread's */
} roz_ros2_out_t;

/** The bridge's counters (roz_ros2_counters()). */
typedef struct roz_ros2_topic_counters {
    uint64_t samples;      /**< samples received */
    uint64_t malformed;    /**< dropped by the port's decode (lengths, names, stamp) */
    uint64_t full;         /**< converted whole (decimation) */
    uint64_t fault_frames; /**< accepted samples reporting a fault */
    uint64_t sessions;     /**< peers seen: the first, then each restart or return */
} roz_ros2_topic_counters_t;

typedef struct roz_ros2_counters {
    uint16_t                  n_topics;
    roz_ros2_topic_counters_t topic[ROZ_ROS2_MAX_TOPICS]; /**< groups, then the IMU */
    uint64_t frames;          /**< fresh frames read (every topic delivered) */
    uint64_t writes;          /**< write() calls */
    uint64_t writes_withheld; /**< writes before the first frame (nothing sent) */
    uint64_t holds;           /**< first writes of a robot published as the start-up hold */
    uint64_t clamped;         /**< written values outside their channel (clamped) */
    uint64_t writer_passes;   /**< writer passes begun */
    uint64_t writer_done;     /**< writer passes ended (none open when equal) */
    uint64_t published;       /**< passes that published every group's command */
    uint64_t publish_errors;  /**< dds_write failures, any topic */
    uint64_t stale_session;   /**< passes that sent nothing: the command was for a robot
                                   that restarted since */
    uint64_t handled_seq;     /**< sequence of the last command frame the writer took */
    uint64_t written_seq;     /**< sequence of the last command frame written */
    uint64_t command_timeouts;/**< command watchdog trips: the tick went silent */
    uint64_t safe_published;  /**< passes that published the watchdog's damping command */
    /** The operator topics, cmd_vel then joy: samples received, refused (a
     *  Joy shorter than joy_map needs, with a mapped axis not finite, or
     *  with more than ROZ_ROS2_JOY_MAX axes or buttons), and handed to a
     *  runtime (roz_runtime_operator_twist(), _remote()). */
    uint64_t operator_samples[2], operator_refused[2], operator_handed[2];
    /** Of the Joys refused, those with more than ROZ_ROS2_JOY_MAX axes or
     *  buttons (the reader's storage holds one more of each, which Cyclone
     *  fills and never grows: so many say the sample had more). */
    uint64_t operator_oversized;
} roz_ros2_counters_t;

/** The bridge's instance: the first member of a ROS 2 port's instance.
 *  Caller-owned (large: give it static storage); fields private
 *  (roz/private.h): the tests and tools read them through the functions
 *  below. */
typedef struct roz_ros2_bridge {
    /* ---- set at open, then read-only ---- */
    const roz_ros2_robot_t *ROZ_PRIVATE(robot);
    void                 *ROZ_PRIVATE(vendor); /* the port's instance */
    const roz_manifest_t *ROZ_PRIVATE(m);
    roz_dds_params_t      ROZ_PRIVATE(dds);
    uint32_t              ROZ_PRIVATE(peer_timeout_ms);
    int                   ROZ_PRIVATE(link_by_stamp);
    double                ROZ_PRIVATE(startup_kd), ROZ_PRIVATE(shutdown_kd);
    roz_log_fn            ROZ_PRIVATE(log);
    void                 *ROZ_PRIVATE(log_ctx);
    uint16_t              ROZ_PRIVATE(n_joints);
    roz_joint_channels_t  ROZ_PRIVATE(joint)[ROZ_CFG_MAX_JOINTS]; /* channels */
    roz_ros2_place_t      ROZ_PRIVATE(place)[ROZ_CFG_MAX_JOINTS];
    /* robot slot -> joint, -1 */
    int16_t               ROZ_PRIVATE(slot_joint)[ROZ_ROS2_MAX_ROBOT_SLOTS];
    uint16_t              ROZ_PRIVATE(group_base)[ROZ_ROS2_MAX_GROUPS]; /* first robot slot */
    uint16_t              ROZ_PRIVATE(n_slots); /* robot slots */
    int16_t               ROZ_PRIVATE(imu)[ROZ_IMU_VALUES]; /* state index or -1 */
    uint16_t              ROZ_PRIVATE(n_topics); /* state topics read */
    uint32_t              ROZ_PRIVATE(required); /* a bit per topic read */
    roz_param_t           ROZ_PRIVATE(params)[ROZ_ROS2_MAX_PARAMS];
    int                   ROZ_PRIVATE(open), ROZ_PRIVATE(active);

    /* ---- DDS ---- */
    roz_dds_participant_t ROZ_PRIVATE(part);
    roz_ros2_topic_t      ROZ_PRIVATE(topic)[ROZ_ROS2_MAX_TOPICS];
    roz_ros2_out_t        ROZ_PRIVATE(out)[ROZ_ROS2_MAX_GROUPS];
    roz_monitor_t         ROZ_PRIVATE(mon_tx);

    /* ---- tick ---- */
    int                   ROZ_PRIVATE(tick_has_state);
    /* robots seen by the tick: first, each restart */
    uint32_t              ROZ_PRIVATE(tick_robot);
    uint32_t              ROZ_PRIVATE(delivered); /* topics fresh since the last fresh frame */
    double                ROZ_PRIVATE(tick_frame)[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    double                ROZ_PRIVATE(tick_q)[ROZ_ROS2_MAX_ROBOT_SLOTS];
    roz_port_fault_t      ROZ_PRIVATE(tick_fault);

    /* ---- tick <-> writer thread: roz/port/dds.h's command path ---- */
    roz_dds_cmd_t         ROZ_PRIVATE(cmd);
    double                ROZ_PRIVATE(cmd_slots)[3 * (ROZ_CFG_MAX_COMMANDS + ROZ_ROS2_CMD_META)];

    /* ---- writer thread ---- */
    double                ROZ_PRIVATE(tx_last_q)[ROZ_ROS2_MAX_ROBOT_SLOTS];
    /* the stiffness each slot last went out with, and its position measured
     * then: the watchdog's hold keeps that torque (roz_hold_keep_torque()) */
    double                ROZ_PRIVATE(tx_last_kp)[ROZ_ROS2_MAX_ROBOT_SLOTS];
    int                    ROZ_PRIVATE(tx_ctrl);  /* tx_last_* hold a controller's frame */
    double                ROZ_PRIVATE(tx_meas_q)[ROZ_ROS2_MAX_ROBOT_SLOTS];
    roz_ros2_joint_cmd_t  ROZ_PRIVATE(tx_joint)[ROZ_ROS2_MAX_ROBOT_SLOTS];
    int32_t               ROZ_PRIVATE(tx_sec);
    uint32_t              ROZ_PRIVATE(tx_nanosec);

    /* ---- operator devices: read only when an input's source needs them ---- */
    roz_ros2_op_topic_t   ROZ_PRIVATE(op)[2]; /* cmd_vel, joy */
    roz_ros2_joy_map_t    ROZ_PRIVATE(joy_map);
    roz_operator_sink_t   ROZ_PRIVATE(op_sink); /* where they go (roz_ros2_set_operator()) */
    ROZ_ATOMIC(int)       ROZ_PRIVATE(op_set);  /* 1 once op_sink is set: Cyclone's threads read it */

    /* ---- counters (atomics: written by one thread, read by any) ---- */
    ROZ_ATOMIC(uint64_t)  ROZ_PRIVATE(c_frames);
} roz_ros2_bridge_t;

/**
 * @brief Open the bridge for @p robot (a port's open): bind the manifest,
 *        read the parameters, create the participant and the writers.
 * @param[in] vendor the port's instance, handed to the robot's hooks
 * @retval ROZ_OK, or ROZ_EINVAL / ROZ_ENOENT / ROZ_EIO with @p err naming
 *         the port and the key, channel, joint or topic at fault
 * Context: start-up; allocates (Cyclone, the samples' sequences).
 */
int roz_ros2_open(roz_ros2_bridge_t *b, const roz_ros2_robot_t *robot, void *vendor,
                  const roz_manifest_t *m, const roz_params_t *p, char *err, size_t errlen);

/**
 * @brief A ROS 2 port's rules of @p m's [hardware] keys, as roz_ros2_open()
 *        applies them to robot.toml's parameters: the joints and channels
 *        bound, then the parameters (a problem of the joints stops there;
 *        the parameters are each checked), every problem reported (rules
 *        "ros2-joint", "ros2-channel", "ros2-param", "unknown-key"). No DDS:
 *        a port's registered check (roz_add_port_rules()) calls it, with
 *        its robot and storage for its instance.
 * @param[out] b      storage for the bridge (overwritten)
 * @param[in]  vendor the port's instance, handed to the robot's params hook
 * @retval ROZ_OK, or ROZ_EINVAL after reporting every problem
 * Context: host tools and start-up, one call at a time; no heap.
 */
int roz_ros2_check(const roz_ros2_robot_t *robot, roz_ros2_bridge_t *b, void *vendor,
                   const roz_manifest_t *m, roz_params_problem_fn report, void *ctx);

/** The rule ids of roz_ros2_check(), "<id>\t<what it refuses>", NULL-ended
 *  (the ROS 2 ports' registrations' RULE_IDS: roz_manifest_json --list-rules). */
extern const char *const roz_ros2_rule_ids[];

/* The port ops on a bridge (@p self is the bridge, the port instance's first
 * member); their contexts are roz/port.h's. */
int  roz_ros2_activate(void *self);
int  roz_ros2_read(void *self, double *state, size_t n);
int  roz_ros2_write(void *self, const double *cmd, size_t n);
int  roz_ros2_deactivate(void *self);
void roz_ros2_close(void *self);
int  roz_ros2_fault(void *self, roz_port_fault_t *out);
size_t roz_ros2_drain(void *self);
int  roz_ros2_set_operator(void *self, const roz_operator_sink_t *sink);

/** @brief The link checks of every state topic, summed (alive: every topic
 *  has a peer; last_seq, last_ns: the first topic's; missing: only topics
 *  checked by sequence number, a stamp's gaps being microseconds, not
 *  frames). Context: any thread. */
void roz_ros2_link(const roz_ros2_bridge_t *b, roz_link_t *out);

/** @brief The link checks of state topic @p t (the groups, then the IMU),
 *  a consistent copy. ROZ_EINVAL for a topic not read. Context: any thread. */
int roz_ros2_topic_link(const roz_ros2_bridge_t *b, uint16_t t, roz_link_t *out);

/** @brief The counters. Context: any thread (each value one atomic load). */
void roz_ros2_counters(const roz_ros2_bridge_t *b, roz_ros2_counters_t *out);

/** @brief roz_ros2_link() and every topic's malformed samples, as a port's
 *  link counters (roz_port_link_counters_t): the link_counters op on a
 *  bridge. Context: any thread. */
int roz_ros2_link_counters(const void *self, roz_port_link_counters_t *out);

/**
 * @brief A ROS 2 port's constructor (its library half): roz_port_make()'s
 *        check of the caller's layout and instance @p size, then the
 *        bridge @p b (the instance's first member) not yet open, logging to
 *        @p log. Context: start-up.
 */
roz_port_t roz_ros2_port(const roz_port_ops_t *ops, roz_ros2_bridge_t *b,
                         const roz_port_layout_t *caller, size_t bytes, size_t size,
                         roz_log_fn log, void *log_ctx);

/** The rows of the bridge's own parameters (roz_ros2_open() reads its
 *  numeric rows' bounds and defaults). */
#define ROZ_ROS2_BRIDGE_PARAM_INFO                                                              \
    ROZ_DDS_HOLD_PARAM_INFO,                                                                    \
    ROZ_PORT_PARAM_TEXT_ROW("link_check", "sequence|stamp",                                     \
                            "sequence where the messages have one", "what the link checks run on"), \
    ROZ_PORT_PARAM_TEXT_ROW("cmd_vel_topic", "a ROS topic name", "/cmd_vel",                    \
                            "geometry_msgs/Twist, read when an input's source is twist.*"),     \
    ROZ_PORT_PARAM_TEXT_ROW("joy_topic", "a ROS topic name", "/joy",                            \
                            "sensor_msgs/Joy, read when an input's source is remote.*"),        \
    ROZ_PORT_PARAM_TEXT_ROW("joy_map", "FIELD=aN|-aN|bN ...", "ROS 2 joy's pad layout",         \
                            "the remote's fields from a Joy's axes and buttons")

/** The rows of the parameters every ROS 2 port takes in a port's parameter
 *  table (roz_port_info_t::params): the DDS ports' own, then the bridge's. */
#define ROZ_ROS2_PARAM_INFO ROZ_DDS_PARAM_INFO("the robot's"), ROZ_ROS2_BRIDGE_PARAM_INFO

/** @brief The fewest readers matched by any command writer, and the fewest
 *  writers matched by any state reader (a test waits for both to be >= 1).
 *  Context: any thread. */
void roz_ros2_matched(const roz_ros2_bridge_t *b, uint32_t *cmd_readers, uint32_t *state_writers);

/** @brief The robot the bridge was opened for. Context: any thread, open. */
const roz_ros2_robot_t *roz_ros2_robot(const roz_ros2_bridge_t *b);

/** @brief The common DDS parameters as open read them. Context: any thread,
 *  open. */
const roz_dds_params_t *roz_ros2_dds_params(const roz_ros2_bridge_t *b);

/** @brief The bridge's DDS participant (its entity, domain and
 *  configuration). Context: any thread, open. */
const roz_dds_participant_t *roz_ros2_participant(const roz_ros2_bridge_t *b);

/** @brief The command writer's monitor (jitter against its period, each
 *  pass's time), for roz_monitor_snapshot(). Context: any thread. */
const roz_monitor_t *roz_ros2_writer_monitor(const roz_ros2_bridge_t *b);

/** @brief State topic @p t's monitor (its handler's times), for
 *  roz_monitor_snapshot(); NULL for a topic not read. Context: any thread. */
const roz_monitor_t *roz_ros2_topic_monitor(const roz_ros2_bridge_t *b, uint16_t t);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_ROS2_H */
