/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port.h
 * @brief The port interface every hardware port implements.
 *
 * A port is a const ops table plus the port's own instance data. The core
 * calls a port only through these wrappers. Channel binding happens once in
 * open(): the port looks the manifest's channels up by name and keeps
 * indices; read() and write() move plain arrays in manifest order.
 *
 * Every hardware port keeps three layers of safe start-up: it sends nothing
 * before its first state frame; on the first state frame it sets every
 * command to the current position with zero stiffness and damping; and it
 * does the same on the first write.
 */
#ifndef ROZ_PORT_H
#define ROZ_PORT_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/error.h"
#include "roz/manifest.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Port parameters: string key/values (robot.toml [hardware.params], CLI). */
typedef struct roz_params {
    const roz_param_t *items;
    size_t             n;
} roz_params_t;

/** What the robot reported when read() returned ROZ_EROBOT. */
typedef struct roz_port_fault {
    const char *what; /**< the part at fault, in storage that lives as long as
                           the port is open: "left_knee_joint" */
    const char *kind; /**< what it reported, static: "motor fault code" */
    uint32_t    code; /**< the robot's own code; after ROZ_EWATCHDOG: how long
                           the tick wrote no command, microseconds */
    uint32_t    limit; /**< after ROZ_EWATCHDOG: the port's command timeout,
                            microseconds; 0 otherwise */
} roz_port_fault_t;

/** @name Capabilities (roz_port_ops_t::caps): what a port's wire and its
 *  implementation offer, so that a consumer (rozrun, the conformance suite
 *  test/ports/common/test_port_conformance.c) need not know the port.
 *  @{ */
/** Every state and command frame carries a CRC that the receiver checks. */
#define ROZ_PORT_CAP_CRC         (1u << 0)
/** State frames carry a sequence number that starts over when the peer
 *  restarts: a restarted peer is told apart from a silent one. */
#define ROZ_PORT_CAP_SEQUENCE    (1u << 1)
/** A command watchdog (roz/hal/cmd_watchdog.h, parameter
 *  command_timeout_us): a silent tick trips it, read() reports
 *  ROZ_EWATCHDOG once. */
#define ROZ_PORT_CAP_WATCHDOG    (1u << 2)
/** The start-up hold: the first write to a new or restarted peer goes out
 *  as every position command holding its paired position state, every
 *  other command 0. */
#define ROZ_PORT_CAP_START_HOLD  (1u << 3)
/** deactivate() then activate() runs the port again without a close. */
#define ROZ_PORT_CAP_RESTART     (1u << 4)
/** A simulator: no robot on the other end; read() advances its time. */
#define ROZ_PORT_CAP_SIMULATOR   (1u << 5)
/** Paced by a robot that keeps its own time: the tick runs at the
 *  manifest's rate, always. */
#define ROZ_PORT_CAP_ROBOT       (1u << 6)
/** Talks over the host's network stack: a test against a real transport
 *  runs in a network namespace of its own (root, or user namespaces). */
#define ROZ_PORT_CAP_NEEDS_NETNS (1u << 7)
/** @} */

/** How a port's parser reads a parameter (roz_port_param_info_t::kind). */
typedef enum roz_port_param_kind {
    /** its own way: the row's range and default are text for people */
    ROZ_PORT_PARAM_TEXT = 0,
    /** an integer in [min, max], dflt when absent (roz_params_get_row_u32()) */
    ROZ_PORT_PARAM_U32,
    /** a finite number in [min, max], dflt when absent (roz_params_get_row_double()) */
    ROZ_PORT_PARAM_DOUBLE
} roz_port_param_kind_t;

/** One parameter a port takes (roz_port_info_t::params). A numeric row
 *  (ROZ_PORT_PARAM_U32_ROW(), ROZ_PORT_PARAM_DOUBLE_ROW()) is also what the
 *  port's parser reads its bounds and default from: the text shown and the
 *  numbers checked are written once. */
typedef struct roz_port_param_info {
    const char *key;   /**< "command_timeout_us" */
    const char *range; /**< the values it takes: "1..1000000", "FROM:TO" */
    const char *def;   /**< its default as text; "" when it has none */
    const char *help;  /**< one short line */
    roz_port_param_kind_t kind; /**< TEXT: the port parses it; the numbers below are 0 */
    double      min, max, dflt; /**< U32, DOUBLE: the bounds and the default */
} roz_port_param_info_t;

/** @cond */
#define ROZ_PORT_PARAM_STR_(x) #x
#define ROZ_PORT_PARAM_STR(x)  ROZ_PORT_PARAM_STR_(x)
/** @endcond */
/** A row of a parameter the port parses its own way (ROZ_PORT_PARAM_TEXT). */
#define ROZ_PORT_PARAM_TEXT_ROW(key, range, def, help) \
    { key, range, def, help, ROZ_PORT_PARAM_TEXT, 0.0, 0.0, 0.0 }
/** A row of an integer parameter: @p min, @p max and @p def are plain
 *  numbers or macros of plain numbers (no suffix): the range and default
 *  shown are their text. */
#define ROZ_PORT_PARAM_U32_ROW(key, min, max, def, help)                                   \
    { key, ROZ_PORT_PARAM_STR(min) ".." ROZ_PORT_PARAM_STR(max), ROZ_PORT_PARAM_STR(def), \
      help, ROZ_PORT_PARAM_U32, (min), (max), (def) }
/** A row of a real parameter; @p unit ("", " m") follows the range shown. */
#define ROZ_PORT_PARAM_DOUBLE_ROW(key, min, max, def, unit, help)                               \
    { key, ROZ_PORT_PARAM_STR(min) ".." ROZ_PORT_PARAM_STR(max) unit, ROZ_PORT_PARAM_STR(def), \
      help, ROZ_PORT_PARAM_DOUBLE, (min), (max), (def) }

/** What a port says about itself (roz_port_ops_t::info): static, const. */
typedef struct roz_port_info {
    const char *summary; /**< one line: "Unitree G1 over Cyclone DDS" */
    const char *header;  /**< the header that documents it: "roz/port/unitree_g1.h" */
    const roz_port_param_info_t *params; /**< the parameters it takes */
    size_t      n_params;
    /** Without ROZ_PORT_CAP_CRC: what the port checks instead, else NULL. */
    const char *no_crc;
    /** Without ROZ_PORT_CAP_SEQUENCE: what the port sees of a restarted
     *  peer instead, else NULL. */
    const char *no_sequence;
    /** A port with no link to check at all (a simulator in the same
     *  process): why, else NULL. */
    const char *no_link;
} roz_port_info_t;

/** A port's parameter table in its roz_port_info_t: @p rows (an array)
 *  and their number. */
#define ROZ_PORT_INFO_PARAMS(rows) .params = (rows), .n_params = sizeof(rows) / sizeof((rows)[0])

/** The checks on the state frames a port received (roz/hal/link.h keeps
 *  them per port), as one struct for every port. */
typedef struct roz_port_link_counters {
    uint64_t accepted;   /**< frames (samples) taken */
    uint64_t crc_errors; /**< dropped: bad CRC */
    uint64_t replays;    /**< dropped: a frame seen before, or overtaken */
    uint64_t missing;    /**< frames lost on the way (sequence gaps) */
    uint64_t restarts;   /**< the peer restarted (its sequence went back) */
    uint64_t returns;    /**< the peer came back after a silence */
    uint64_t malformed;  /**< dropped: not a frame of the expected shape
                              (a port without a CRC: what it checks instead) */
} roz_port_link_counters_t;

/** Most bodies one truth sample names (roz_port_truth_t::bodies). */
#define ROZ_PORT_TRUTH_MAX_BODIES 8

/** A simulator's truth at a tick (roz_port_sim_t::truth): what no sensor
 *  gives, so that a recording tells standing from fallen
 *  (docs/recording.md, /roz/truth). Plain numbers: filled in the tick. */
typedef struct roz_port_truth {
    uint32_t floating;   /**< 1: the robot has a free-floating base, and the pose
                              below is its; 0: fixed base, pose NaN */
    double   pos[3];     /**< base position, m, world (pos[2]: its height above
                              the world's origin, the ground) */
    double   quat[4];    /**< base orientation w, x, y, z */
    double   roll, pitch, yaw; /**< rad, Z-Y-X from quat */
    uint32_t contacts;   /**< contacts between the robot and the world */
    uint32_t n_bodies;   /**< robot bodies touching the world, at most
                              ROZ_PORT_TRUTH_MAX_BODIES named */
    int32_t  bodies[ROZ_PORT_TRUTH_MAX_BODIES]; /**< the port's body ids
                              (roz_port_sim_t::truth_body names them) */
} roz_port_truth_t;

/** The simulator extension of the port contract: the ops only a simulator
 *  has, reached from its ops (roz_port_ops_t::sim; roz_port_set_origin(),
 *  roz_port_truth() and roz_port_truth_body() call them). Every op may be
 *  NULL; a real robot's port has no extension at all. */
typedef struct roz_port_sim {
    /** The file the manifest was read from (a robot.toml), so that paths
     *  its parameters name (a model file) are taken relative to it; called
     *  before open(). Optional: a port whose parameters name no file has
     *  none. Context: start-up. */
    void (*set_origin)(void *self, const char *robot_toml);
    /** The truth after the last read() (roz_port_truth_t), which the
     *  runtime copies into the flight recorder's record of the tick.
     *  Optional. Context: the tick, after read(); RT-safe: no heap, no
     *  formatting, bounded. */
    int (*truth)(const void *self, roz_port_truth_t *out);
    /** The name of body @p id of a truth sample, in storage that lives as
     *  long as the port is open; NULL for an id it does not know. Optional
     *  (with truth). Context: any thread while the port is open (the
     *  recorder's drain); never formats in the tick. */
    const char *(*truth_body)(const void *self, int32_t id);
} roz_port_sim_t;

/** When roz_port_report() is asked for a port's own lines. */
typedef enum roz_port_report_when {
    ROZ_PORT_REPORT_OPENED = 0, /**< after open: what it opened, one line */
    ROZ_PORT_REPORT_SUMMARY = 1 /**< after the run: lines "label  text" for a summary */
} roz_port_report_when_t;

/** The operations of one kind of port. Optional ops may be NULL. */
typedef struct roz_port_ops {
    const char *name; /**< "loopback", "unitree/G1", ... */
    /** Parse parameters, allocate, bind channels by name. Errors name the
     *  parameter or channel in @p err. Context: start-up; may allocate. */
    int (*open)(void *self, const roz_manifest_t *m, const roz_params_t *p, char *err,
                size_t errlen);
    /** Start threads / transport. Optional. */
    int (*activate)(void *self);
    /** Copy the latest state (n = n_states values). Returns 1 for a fresh
     *  frame, 0 when nothing newer than the last read arrived (state then
     *  holds the previous frame), negative ROZ_E* on error (ROZ_ENOENT: no
     *  frame ever; ROZ_ELINK: the link to the robot broke, its peer restarted
     *  or came back after it was lost (roz/hal/link.h), which latches
     *  ROZ_FAULT_LINK; ROZ_EROBOT: a fresh frame, in @p state, in which the
     *  robot reports a fault of its own (fault() says which), which latches
     *  ROZ_FAULT_ROBOT; a port returns it for every fresh frame while the
     *  robot reports the fault: a level, not an event; ROZ_EWATCHDOG: the
     *  port's command watchdog (roz/hal/cmd_watchdog.h) found the tick
     *  silent for longer than its command timeout and sent the robot its
     *  safe command instead of the stale one; reported once per trip, in
     *  place of 0 or 1 (state holds the latest frame, which the runtime
     *  takes as not fresh), with fault() giving how long the tick was
     *  silent (code) and the timeout (limit); latches
     *  ROZ_FAULT_COMMAND_TIMEOUT).
     *  Context: the tick; RT-safe, never blocks. */
    int (*read)(void *self, double *state, size_t n);
    /** Hand n = n_commands filtered commands to the robot. Context: the
     *  tick; RT-safe, never blocks. */
    int (*write)(void *self, const double *cmd, size_t n);
    /** Stop threads. Optional. */
    int (*deactivate)(void *self);
    /** Free everything; idempotent. Optional. */
    void (*close)(void *self);
    /** After read() returned ROZ_EROBOT: what the robot reported; after
     *  ROZ_EWATCHDOG: the silence and the timeout. After read() returned 0
     *  (nothing fresh): why, when the port knows (an actuator that stopped
     *  answering, named), else not ROZ_OK; the runtime adds it to the STALE
     *  fault's message when that latches. Optional (without it the fault
     *  has a code of 0 and no name).
     *  Context: the tick; RT-safe. */
    int (*fault)(void *self, roz_port_fault_t *out);
    /** ROZ_PORT_CAP_* flags. */
    uint32_t caps;
    /** What the port says about itself; NULL: nothing. */
    const roz_port_info_t *info;
    /** What only a simulator does (roz_port_sim_t), else NULL. Beside the
     *  info, not in it: a port's info is also its rules' (a library the
     *  checker links without the simulator). */
    const struct roz_port_sim *sim;
    /** A consistent copy of the checks on the state frames received so far.
     *  Optional. Context: any thread; RT-safe, never blocks. */
    int (*link_counters)(const void *self, roz_port_link_counters_t *out);
    /** The port's own lines of text at @p when, '\n' between lines, into
     *  @p buf of @p len bytes (always terminated when len > 0). Returns the
     *  length the whole text needs (as snprintf does), 0 for none. Optional.
     *  Context: start-up or shut-down, never the tick; may format text. */
    int (*report)(const void *self, roz_port_report_when_t when, char *buf, size_t len);
    /** Format what the port's own threads kept as numbers for the log (its
     *  monitors' threshold warnings, notices about samples it dropped) and
     *  pass each line to the port's log callback; returns the lines passed
     *  on. A port's threads never call the log callback themselves: it may
     *  block (a paused terminal, a full pipe), and a port thread may be the
     *  one that puts commands on the wire (test_port_conformance:
     *  blocking_log). roz_runtime_log_drain() calls it. Optional.
     *  Context: the application's thread that drains the log; formats text. */
    size_t (*drain)(void *self);
    /** Where the port hands the frames of the operator devices it reads
     *  (the G1's wireless remote, a ROS 2 robot's /cmd_vel and /joy:
     *  roz/operator.h); a copy is kept. Called once, after open(); a port
     *  whose reader starts at activate() (the G1's) refuses it after that,
     *  ROZ_ESTATE. Optional: a port that reads no operator device has none.
     *  Context: start-up. */
    int (*set_operator)(void *self, const roz_operator_sink_t *sink);
} roz_port_ops_t;

/** A port instance: its ops and its data. */
typedef struct roz_port {
    const roz_port_ops_t *ops;
    void                 *self;
    /** 1 once roz_port_open() succeeded, 0 again after roz_port_close(); set
     *  only by those two. roz_runtime_init() refuses a port that is not
     *  open: its read() would run on an instance that was never set up. */
    int                   opened;
} roz_port_t;

/**
 * The ROZ_CFG_* options a port's instance is laid out by, as a translation
 * unit sees them. A port instance is the application's storage, written by
 * the library: an application built with other options than the library
 * would have it written past its end. The port constructors and
 * roz_port_open() pass the caller's view, and the library refuses a
 * mismatch before it writes anything (test/core/test_port_layout.c).
 */
typedef struct roz_port_layout {
    uint32_t max_commands, max_states, max_joints, max_params, error_len, max_name_len,
        name_arena_bytes, problem_len;
} roz_port_layout_t;

/** The layout of the translation unit that expands it. */
#define ROZ_PORT_LAYOUT_INIT                                                                 \
    {                                                                                        \
        (uint32_t)ROZ_CFG_MAX_COMMANDS, (uint32_t)ROZ_CFG_MAX_STATES,                        \
            (uint32_t)ROZ_CFG_MAX_JOINTS, (uint32_t)ROZ_CFG_MAX_PARAMS,                      \
            (uint32_t)ROZ_CFG_ERROR_LEN, (uint32_t)ROZ_CFG_MAX_NAME_LEN,                     \
            (uint32_t)ROZ_CFG_NAME_ARENA_BYTES, (uint32_t)ROZ_CFG_PROBLEM_LEN                \
    }

/**
 * @brief Compare a caller's port layout with the library's.
 * @param[out] err  names the first difference ("ROZ_CFG_MAX_COMMANDS is 16
 *                  in the application, 256 in libroz_core: ..."); may be NULL
 * @retval ROZ_OK the same; ROZ_ECONFIG different
 * Context: any; no I/O.
 */
ROZ_NODISCARD int roz_port_layout_check(const roz_port_layout_t *caller, char *err,
                                        size_t errlen);

/**
 * @brief What a port constructor returns for an instance it must not write
 *        (the caller's layout is not the library's, or its instance has
 *        another size): a port whose open() fails with ROZ_ECONFIG saying
 *        so; nothing written.
 * Context: start-up.
 */
roz_port_t roz_port_misbuilt(void);

/**
 * @brief The check a port constructor makes before it writes its instance:
 *        a roz_port_t of @p ops over @p self, not yet open, when the
 *        caller's layout (@p caller) and instance size (@p bytes) are the
 *        library's (@p size); roz_port_misbuilt() otherwise (its self is
 *        NULL: the constructor then writes nothing to @p self).
 * Context: start-up; no I/O.
 */
roz_port_t roz_port_make(const roz_port_ops_t *ops, void *self, const roz_port_layout_t *caller,
                         size_t bytes, size_t size);

/** @brief open(); a port without the op has nothing to open and is open at
 *  once. Marks @p p open on success. Refuses (ROZ_ECONFIG, @p err naming
 *  the option) an application built with other ROZ_CFG_* options than the
 *  library, before the port's open() writes its instance.
 *  Context: start-up; may allocate. */
static inline int roz_port_open(roz_port_t *p, const roz_manifest_t *m,
                                const roz_params_t *params, char *err, size_t errlen)
{
    const roz_port_layout_t caller = ROZ_PORT_LAYOUT_INIT;
    int rc = roz_port_layout_check(&caller, err, errlen);
    if (rc == ROZ_OK)
        rc = p->ops->open != NULL ? p->ops->open(p->self, m, params, err, errlen) : ROZ_OK;
    p->opened = rc == ROZ_OK;
    return rc;
}

/** @brief activate(); ROZ_OK when the port has none (nothing to start).
 *  Context: start-up, not the tick. */
static inline int roz_port_activate(const roz_port_t *p)
{
    return p->ops->activate != NULL ? p->ops->activate(p->self) : ROZ_OK;
}

/** @brief read()
 *  Context: the tick; must not block. */
static inline int roz_port_read(const roz_port_t *p, double *state, size_t n)
{
    return p->ops->read != NULL ? p->ops->read(p->self, state, n) : ROZ_ENOTSUP;
}

/** @brief write()
 *  Context: the tick; must not block. */
static inline int roz_port_write(const roz_port_t *p, const double *cmd, size_t n)
{
    return p->ops->write != NULL ? p->ops->write(p->self, cmd, n) : ROZ_ENOTSUP;
}

/** @brief deactivate(); ROZ_OK when the port has none.
 *  Context: shut-down, after the tick stopped. */
static inline int roz_port_deactivate(const roz_port_t *p)
{
    return p->ops->deactivate != NULL ? p->ops->deactivate(p->self) : ROZ_OK;
}

/** @brief close(), if any; marks @p p not open.
 *  Context: shut-down, after the tick stopped; idempotent. */
static inline void roz_port_close(roz_port_t *p)
{
    if (p->ops->close != NULL)
        p->ops->close(p->self);
    p->opened = 0;
}

/** @brief The port's ROZ_PORT_CAP_* flags. Context: any. */
static inline uint32_t roz_port_caps(const roz_port_t *p)
{
    return p->ops->caps;
}

/** @brief What the port says about itself; an empty info when it says
 *  nothing (never NULL). Context: any. */
static inline const roz_port_info_t *roz_port_ops_info(const roz_port_ops_t *ops)
{
    static const roz_port_info_t none = { "", "", NULL, 0, NULL, NULL, NULL };
    return ops->info != NULL ? ops->info : &none;
}

/** @brief roz_port_ops_info() of @p p's ops. Context: any. */
static inline const roz_port_info_t *roz_port_info(const roz_port_t *p)
{
    return roz_port_ops_info(p->ops);
}

/** @brief link_counters(); all 0 and ROZ_ENOTSUP when the port has none.
 *  Context: any thread; RT-safe. */
static inline int roz_port_link_counters(const roz_port_t *p, roz_port_link_counters_t *out)
{
    if (p->ops->link_counters != NULL)
        return p->ops->link_counters(p->self, out);
    out->accepted = out->crc_errors = out->replays = out->missing = 0;
    out->restarts = out->returns = out->malformed = 0;
    return ROZ_ENOTSUP;
}

/** @brief drain(); 0 when the port has none (nothing kept).
 *  Context: the application's thread that drains the log, never the tick. */
static inline size_t roz_port_drain(const roz_port_t *p)
{
    return p->ops->drain != NULL ? p->ops->drain(p->self) : 0;
}

/** @brief The port's simulator extension (roz_port_sim_t); NULL for a
 *  port that is no simulator. Context: any. */
static inline const roz_port_sim_t *roz_port_sim(const roz_port_t *p)
{
    return p->ops->sim;
}

/** @brief set_origin(), if any: @p robot_toml is the file the manifest was
 *  read from (it must outlive the port). Context: start-up, before open. */
static inline void roz_port_set_origin(const roz_port_t *p, const char *robot_toml)
{
    const roz_port_sim_t *sim = roz_port_sim(p);
    if (sim != NULL && sim->set_origin != NULL)
        sim->set_origin(p->self, robot_toml);
}

/** @brief 1 when the port gives truth samples (a simulator). Context: any. */
static inline int roz_port_has_truth(const roz_port_t *p)
{
    const roz_port_sim_t *sim = roz_port_sim(p);
    return sim != NULL && sim->truth != NULL;
}

/** @brief truth(); ROZ_ENOTSUP when the port has none.
 *  Context: the tick, after read(); RT-safe. */
static inline int roz_port_truth(const roz_port_t *p, roz_port_truth_t *out)
{
    return roz_port_has_truth(p) ? roz_port_sim(p)->truth(p->self, out) : ROZ_ENOTSUP;
}

/** @brief truth_body(): a truth sample's body name; NULL when unknown.
 *  Context: any thread while the port is open. */
static inline const char *roz_port_truth_body(const roz_port_t *p, int32_t id)
{
    const roz_port_sim_t *sim = roz_port_sim(p);
    return sim != NULL && sim->truth_body != NULL ? sim->truth_body(p->self, id) : NULL;
}

/** @brief set_operator(); ROZ_ENOTSUP when the port reads no operator
 *  device. Context: start-up, after open (roz_port_ops_t.set_operator). */
static inline int roz_port_set_operator(const roz_port_t *p, const roz_operator_sink_t *sink)
{
    return p->ops->set_operator != NULL ? p->ops->set_operator(p->self, sink) : ROZ_ENOTSUP;
}

/** @brief report(); an empty text (0) when the port has none.
 *  Context: start-up or shut-down, never the tick. */
static inline int roz_port_report(const roz_port_t *p, roz_port_report_when_t when, char *buf,
                                  size_t len)
{
    if (p->ops->report != NULL)
        return p->ops->report(p->self, when, buf, len);
    if (len > 0)
        buf[0] = '\0';
    return 0;
}

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_H */
