/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port/mujoco.h
 * @brief The mujoco port: a robot in physics (MuJoCo's C API), driven as the
 *        real robot is: its joints' drivers run the robot's own actuator law
 *        at every physics step, its sensors give what the real ones give.
 *
 * Everything is allocated at open (the model parsed and compiled, its data
 * made); read() and write() never allocate (test/ports/mujoco: the heap counted
 * through the tick). Time is simulated: each read() but the first advances
 * the physics by one control period, period / timestep steps, so the same
 * build gives the same trace bit for bit on every run. docs/ports/mujoco.md
 * has the parameters, the actuator law, time, faults and the built-in
 * robots; this header keeps the types.
 */
#ifndef ROZ_PORT_MUJOCO_H
#define ROZ_PORT_MUJOCO_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/hal/inject.h"
#include "roz/hal/joints.h"
#include "roz/hal/params.h"
#include "roz/log.h"
#include "roz/manifest.h"
#include "roz/port.h"
#include "roz/private.h"

#ifdef __cplusplus
extern "C" {
#endif

/* MuJoCo's own types, only pointed to (its headers stay out of roz's). */
struct mjModel_;
struct mjData_;

/** Most joints one robot binds. */
#define ROZ_MUJOCO_MAX_JOINTS (ROZ_CFG_MAX_JOINTS > 0 ? ROZ_CFG_MAX_JOINTS : 1)
/** Most ticks of sensor latency (`latency_ticks`, the `delay` fault). */
#define ROZ_MUJOCO_MAX_DELAY ROZ_INJECT_MAX_DELAY
/** Fault injections and pushes at once. */
#define ROZ_MUJOCO_MAX_FAULTS 8
/** Longest model path, bytes. */
#define ROZ_MUJOCO_PATH_MAX 1024
/** Longest MuJoCo name the port keeps (a body in the report). */
#define ROZ_MUJOCO_NAME_MAX 64
/** Bodies touching the ground the report names. */
#define ROZ_MUJOCO_MAX_CONTACT_BODIES 4

/** One injected fault; `to` = 0: forever. Its kind (roz/hal/inject.h), each
 *  over ticks [from, to), is one of ROZ_INJECT_DROP (state frames are lost:
 *  read() gives nothing fresh), _FREEZE (the robot sends nothing: read() as
 *  for drop), _DELAY (state frames arrive `arg` ticks late), _PUSH (force
 *  `force`, N, world frame, on body `body` at its centre of mass), _GANTRY
 *  (the floating base hung where it is, a weld to the world), _RESTART (the
 *  robot's board is dead, motors limp, no state, and boots at `to`). */
typedef struct roz_mujoco_fault {
    roz_inject_kind_t kind;
    uint64_t from, to;
    uint32_t arg;      /**< DELAY: ticks, 1..ROZ_MUJOCO_MAX_DELAY */
    int32_t  body;     /**< PUSH: MuJoCo body id */
    double   force[3]; /**< PUSH: N, world frame */
} roz_mujoco_fault_t;

/** One bound joint. */
typedef struct roz_mujoco_joint {
    roz_joint_channels_t ch;   /**< its manifest channels (roz/hal/joints.h) */
    int32_t jnt, qadr, dadr;   /**< MuJoCo joint id, qpos and qvel addresses */
    int32_t act;               /**< the actuator driving it */
    double  gear;              /**< the actuator's gear: joint torque = gear * ctrl */
    double  tau_lo, tau_hi;    /**< the joint's effort limit, N.m (the manifest's) */
    uint8_t law;               /**< private: how it is driven (mujoco.c) */
    double  q_ref;             /**< velocity servo: the integrated reference */
} roz_mujoco_joint_t;

/** The simulated base and contacts, the simulator's truth (not a sensor). */
typedef struct roz_mujoco_base {
    int    floating;           /**< 1: the robot has a floating base (a free joint) */
    double pos[3];             /**< m, world */
    double quat[4];            /**< w, x, y, z (MuJoCo's order) */
    double roll, pitch, yaw;   /**< rad, Z-Y-X */
    double lin_vel[3];         /**< m/s, world */
    double ang_vel[3];         /**< rad/s, body frame */
    double min_height;         /**< lowest base height since open, m */
    double max_tilt;           /**< largest |roll| or |pitch| since open, rad */
    uint32_t contacts;         /**< contacts between the robot and the world */
    uint32_t n_bodies;         /**< robot bodies touching the world (at most the names kept) */
    char   bodies[ROZ_MUJOCO_MAX_CONTACT_BODIES][ROZ_MUJOCO_NAME_MAX];
    double sim_time;           /**< s */
    uint64_t steps;            /**< physics steps since open */
} roz_mujoco_base_t;

/** The port's counters (roz_mujoco_counters()). */
typedef struct roz_mujoco_counters {
    uint64_t writes;
    uint64_t writes_withheld; /**< before the first state frame: not applied */
    uint64_t frames;          /**< fresh frames read() gave */
    uint64_t frames_dropped;  /**< DROP, FREEZE, RESTART */
    uint64_t clamped;         /**< written values clamped to the manifest */
    uint64_t saturated;       /**< physics steps x joints whose torque was saturated */
    uint64_t violations;      /**< values written outside [min, max] or not finite (the
                                   filter upstream lets none through): stays 0 */
    uint64_t warnings;        /**< MuJoCo's warnings (a diverged or overfull simulation):
                                   the first one fails every read() after it */
} roz_mujoco_counters_t;

/** The port's data; caller-owned (give it static storage). Its fields are
 *  private (roz/private.h): read it through the functions below. */
typedef struct roz_mujoco {
    roz_log_fn            ROZ_PRIVATE(log);
    void                 *ROZ_PRIVATE(log_ctx);
    const char           *ROZ_PRIVATE(robot_file); /**< robot.toml the model path is relative to; NULL: none */
    const roz_manifest_t *ROZ_PRIVATE(m);
    struct mjModel_      *ROZ_PRIVATE(model);
    struct mjData_       *ROZ_PRIVATE(data);
    char                  ROZ_PRIVATE(model_path)[ROZ_MUJOCO_PATH_MAX];
    double                ROZ_PRIVATE(timestep);
    uint32_t              ROZ_PRIVATE(steps_per_tick);
    uint64_t              ROZ_PRIVATE(tick);       /**< reads so far */
    uint64_t              ROZ_PRIVATE(steps);      /**< physics steps so far */

    roz_mujoco_joint_t    ROZ_PRIVATE(joints)[ROZ_MUJOCO_MAX_JOINTS];
    uint16_t              ROZ_PRIVATE(n_joints);
    int16_t               ROZ_PRIVATE(imu)[ROZ_IMU_VALUES];
    int32_t               ROZ_PRIVATE(gyro_adr), ROZ_PRIVATE(acc_adr), ROZ_PRIVATE(imu_site); /**< sensordata addresses, site id */
    int32_t               ROZ_PRIVATE(base_jnt), ROZ_PRIVATE(base_body), ROZ_PRIVATE(base_qadr), ROZ_PRIVATE(base_dadr); /**< -1: fixed base */
    int32_t               ROZ_PRIVATE(gantry_eq);  /**< the gantry's weld, -1 none */
    double                ROZ_PRIVATE(velocity_kp), ROZ_PRIVATE(velocity_kd);
    /* a mobile base driven by body velocities (diff_drive, quadcopter) */
    uint8_t               ROZ_PRIVATE(mobile);       /**< private: none, wheels or autopilot (mujoco.c) */
    int16_t               ROZ_PRIVATE(mob_cmd)[4];   /**< v, w (wheels); vx, vy, vz, yaw rate (autopilot) */
    int16_t               ROZ_PRIVATE(mob_state)[4]; /**< x, y, yaw (wheels); x, y, z, yaw (autopilot) */
    double                ROZ_PRIVATE(wheel_radius), ROZ_PRIVATE(wheel_separation); /**< m */
    double                ROZ_PRIVATE(odom)[3];      /**< wheels: x, y, yaw from the encoders */
    double                ROZ_PRIVATE(max_thrust);   /**< autopilot: N */
    double                ROZ_PRIVATE(mass);         /**< autopilot: the airframe's, kg */
    uint32_t              ROZ_PRIVATE(unbound);    /**< model joints locked because no channel binds them */

    double                ROZ_PRIVATE(cmd)[ROZ_CFG_MAX_COMMANDS]; /**< the command the drivers apply */
    int                   ROZ_PRIVATE(have_cmd);
    int                   ROZ_PRIVATE(dead);       /**< RESTART: the board is down */
    int                   ROZ_PRIVATE(rebooted);   /**< RESTART: read() reports ROZ_ELINK once */
    char                  ROZ_PRIVATE(engine_error)[ROZ_MUJOCO_PATH_MAX + 640]; /**< what MuJoCo raised or threw in a step, and the model; "": nothing */
    uint64_t              ROZ_PRIVATE(engine_step); /**< the physics step it did so at */

    roz_mujoco_fault_t    ROZ_PRIVATE(faults)[ROZ_MUJOCO_MAX_FAULTS];
    uint32_t              ROZ_PRIVATE(n_faults);
    uint32_t              ROZ_PRIVATE(latency);    /**< ticks */
    double                ROZ_PRIVATE(noise_q), ROZ_PRIVATE(noise_dq), ROZ_PRIVATE(noise_tau), ROZ_PRIVATE(noise_gyro), ROZ_PRIVATE(noise_acc);
    uint64_t              ROZ_PRIVATE(rng);        /**< the noise's state (seeded: deterministic) */
    /* perturbations (docs/ports/mujoco.md, "Perturbations"): applied at open
     * to the model, and at read and write to what the sensors and drivers see */
    double                ROZ_PRIVATE(gains_scale);    /**< kp and kd the drivers apply, x */
    uint32_t              ROZ_PRIVATE(cmd_latency);    /**< ticks a command takes to the drivers */
    uint64_t              ROZ_PRIVATE(cmd_count);      /**< commands written since open (the ring's head) */
    double                ROZ_PRIVATE(cmd_hist)[ROZ_MUJOCO_MAX_DELAY + 1][ROZ_CFG_MAX_COMMANDS];
    double                ROZ_PRIVATE(bias_q)[ROZ_MUJOCO_MAX_JOINTS]; /**< encoder offsets, rad */
    double                ROZ_PRIVATE(bias_imu)[6];    /**< gyro, accelerometer offsets */
    double                ROZ_PRIVATE(bias_quat)[4];   /**< the IMU's mounting error, w x y z */
    double                ROZ_PRIVATE(hist)[ROZ_MUJOCO_MAX_DELAY + 1][ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    double                ROZ_PRIVATE(tau)[ROZ_MUJOCO_MAX_JOINTS]; /**< last torque applied per joint */

    roz_mujoco_base_t     ROZ_PRIVATE(base);

    /* counters */
    uint64_t              ROZ_PRIVATE(writes);
    uint64_t              ROZ_PRIVATE(writes_withheld); /**< before the first state frame: not applied */
    uint64_t              ROZ_PRIVATE(frames);          /**< fresh frames read() gave */
    uint64_t              ROZ_PRIVATE(frames_dropped);  /**< DROP, FREEZE, RESTART */
    uint64_t              ROZ_PRIVATE(clamped);         /**< written values clamped to the manifest */
    uint64_t              ROZ_PRIVATE(saturated);       /**< physics steps x joints whose torque was saturated */
    uint64_t              ROZ_PRIVATE(violations);      /**< values written outside the manifest: stays 0 */
    int                   ROZ_PRIVATE(warned);          /**< MuJoCo's first warning + 1; 0: none */
    uint64_t              ROZ_PRIVATE(warned_step);     /**< the physics step that raised it */
} roz_mujoco_t;

/** The ops table ("mujoco"). */
extern const roz_port_ops_t roz_mujoco_ops;

/**
 * @brief The port's rules of @p m's [hardware] keys that need no model, as
 *        its open applies them to robot.toml's parameters: the keys known
 *        (an unknown one is said alone), then every number and word (rules
 *        "unknown-key", "mujoco-param"). No MuJoCo: this is what
 *        roz_manifest_json, and so rozgen, runs (roz_add_port_rules()).
 * @retval ROZ_OK, or ROZ_EINVAL after reporting every problem
 * Context: host tools and start-up; no heap.
 */
int roz_mujoco_check(const roz_manifest_t *m, roz_params_problem_fn report, void *ctx);

/**
 * @brief The port's rules that need @p m's model, as its open applies them:
 *        the model `model` names (relative to the folder of @p robot_toml,
 *        the file @p m was read from; NULL: the working directory) read
 *        without MuJoCo, every joint bound to a joint of it and an actuator
 *        (by name, or `joint_names`), the effort limits it can give, the
 *        IMU's sensors (rules "mujoco-model", "mujoco-joint",
 *        "mujoco-effort", "mujoco-imu"; the first problem is said). A
 *        built-in robot naming no model is the port's build's to check.
 *        What only MuJoCo's compiler can say (a motor's ctrlrange, the
 *        timestep's fit, a keyframe) stays the open's. This is what
 *        roz_manifest_json, and so rozgen, runs after roz_mujoco_check().
 * @retval ROZ_OK, or ROZ_EINVAL after reporting the problem
 * Context: host tools; allocates while it reads the model.
 */
int roz_mujoco_check_model(const roz_manifest_t *m, const char *robot_toml,
                           roz_params_problem_fn report, void *ctx);

/** The rule ids of roz_mujoco_check() and roz_mujoco_check_model(), "<id>\t<what it
 *  refuses>", NULL-ended (its registration's RULE_IDS: roz_manifest_json --list-rules). */
extern const char *const roz_mujoco_rule_ids[];

/* The library half of the constructor below: the caller's layout and
 * instance size, refused when they are not the library's. */
roz_port_t roz__mujoco_port(roz_mujoco_t *self, const roz_port_layout_t *caller,
                            size_t bytes, roz_log_fn log, void *log_ctx);

/**
 * @brief A roz_port_t over @p self, not yet open (roz_port_open()).
 * @param log  open's notes (a model's servos made motors, locked joints);
 *             NULL: none. Never called from the tick.
 * Zeroes @p self: call it before roz_mujoco_set_robot_file(), and not on a
 * port that is open (close it first).
 * Context: start-up.
 */
static inline roz_port_t roz_mujoco_port(roz_mujoco_t *self, roz_log_fn log, void *log_ctx)
{
    /* the instance as this translation unit lays it out (roz/port.h) */
    const roz_port_layout_t caller = ROZ_PORT_LAYOUT_INIT;
    return roz__mujoco_port(self, &caller, sizeof *self, log, log_ctx);
}

/** @brief The robot.toml a relative `model` path is read from (its folder);
 *  NULL: the working directory. After roz_mujoco_port(), before open.
 *  Context: start-up. */
void roz_mujoco_set_robot_file(roz_mujoco_t *self, const char *robot_toml);

/** @brief The counters. Context: the thread that ticks (the port has no
 *  threads of its own), or after the tick stopped. */
void roz_mujoco_counters(const roz_mujoco_t *self, roz_mujoco_counters_t *out);

/**
 * @brief Add a fault injection (before or while running), from the tick's
 *        thread between ticks.
 * @retval ROZ_ENOSPC ROZ_MUJOCO_MAX_FAULTS active already
 * @retval ROZ_EINVAL a bad kind, delay or body
 * Context: the tick's thread; no heap.
 */
int roz_mujoco_inject(roz_mujoco_t *self, const roz_mujoco_fault_t *f);

/** @brief The simulated base pose and contacts after the last read().
 *  Context: the tick's thread between ticks, or after it stopped. */
void roz_mujoco_base(const roz_mujoco_t *self, roz_mujoco_base_t *out);

/** @brief The command the simulated drivers apply (n_commands), or NULL
 *         before the first (and while a restarted board boots).
 *  Context: the tick's thread between ticks. */
const double *roz_mujoco_last_command(const roz_mujoco_t *self);

/** @brief The built-in model of robot @p robot_id ("unitree_g1", "ur5"):
 *  its MJCF path, under the install prefix of the running program
 *  (<prefix>/bin/../share/roz/models/) when it is there, else where this
 *  build found it; NULL when neither is there. Context: start-up (it reads
 *  the file system; the path is kept in static storage). */
const char *roz_mujoco_builtin_model(const char *robot_id);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_MUJOCO_H */
