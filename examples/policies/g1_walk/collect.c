/* SPDX-License-Identifier: Apache-2.0 */
/* The data harness of roz's own walking policy (train.py beside loads it
 * with ctypes): one episode of the 12-joint G1 (unitree_g1_12dof) in MuJoCo,
 * in process, with
 *  - the deploy sequence's start as rozrun runs it: hung on the gantry, the
 *    joints moved from where they are to the stand (the deploy
 *    configuration's default pose and gains) over move_s, then let go as the
 *    controller takes over at its tick 0;
 *  - the scripted operator's velocity command through the manifest's inputs
 *    (roz/inputs.h: each input's rate cap, as rozrun --operator feeds them);
 *  - the expert, examples/controllers/g1_walker.c built natively, run every
 *    tick on the robot's state whoever drives (DAgger's shadow: its
 *    internal state follows the real robot); its command folded into the
 *    policy's action space, the label:
 *        target = position + effort / stiffness   (the walker's PD law
 *        kp (position - q) - kd dq + effort is the policy's fixed-gain PD
 *        toward that target: the same gains, g1_walker.c's)
 *        action = (target - default) / action_scale;
 *  - the policy's runner, roz_policy.h over the tables rozgen-nn deploy
 *    generated for deploy.yaml (the generated C is compiled into this file),
 *    its network replaced by the caller: at every inference the caller gets
 *    the observation exactly as the deployed controller computes it, the
 *    expert's label and the base's truth, and returns the action the robot
 *    executes (the learner's, the expert's, or a mix: train.py decides);
 *  - the safety filter between the runner and the port, as in the runtime.
 * One episode per process: the walker keeps its state in statics (train.py
 * runs each episode in a fresh worker). */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "roz/builtin.h"
#include "roz/error.h"
#include "roz/filter.h"
#include "roz/inputs.h"
#include "roz/port/mujoco.h"

/* the generated controller: its tables and network; its process() renamed */
#define roz_native_process g1_walk_policy_process
#include G1_WALK_POLICY_C
#undef roz_native_process

void g1_walker_process(long long tick); /* g1_walker.c, built with that name */

/* ---- the imports the two native controllers call ---- */

static double cur_state[ROZ_CFG_MAX_STATES + ROZ_CFG_MAX_INPUTS];
static int n_all_states;
static double walker_cmd[ROZ_CFG_MAX_COMMANDS];
static double policy_cmd[ROZ_CFG_MAX_COMMANDS];
static int n_commands_all;

double roz_state_get(int index)
{
    return index >= 0 && index < n_all_states ? cur_state[index] : NAN;
}

int roz_state_count(void)
{
    return n_all_states;
}

int roz_command_set(int index, double value)
{
    if (index < 0 || index >= n_commands_all)
        return ROZ_SET_REFUSED;
    walker_cmd[index] = value;
    return ROZ_SET_TAKEN;
}

int roz_command_count(void)
{
    return n_commands_all;
}

int roz_state_get_all(double *values, int count)
{
    if (count > n_all_states)
        return -1;
    memcpy(values, cur_state, sizeof values[0] * (size_t)count);
    return count;
}

int roz_command_set_all(const double *values, int count)
{
    if (count > n_commands_all)
        return -1;
    memcpy(policy_cmd, values, sizeof values[0] * (size_t)count);
    return 0;
}

double roz_sin(double x)
{
    return sin(x);
}

double roz_cos(double x)
{
    return cos(x);
}

static int estop_requested;
void roz_request_estop(void)
{
    estop_requested = 1;
}

/* ---- the episode ---- */

/** What the caller describes. Times in seconds of the controller (its tick
 *  0 is the hand-over; the operator's rows may start before it, as a
 *  script's do when the run starts after the stand). */
typedef struct g1_walk_episode {
    double pre_s;       /* hung and moved to the stand before the hand-over */
    double move_s;      /* the move's length (<= pre_s) */
    double duration_s;  /* the controller's time */
    int    n_rows;      /* the operator's rows: time, then vx, vy, yaw rate */
    const double *rows; /* n_rows x 4 */
    int    decimation;  /* 0: the configuration's */
    double min_height;  /* m: the episode ends with the pelvis below (fallen) */
} g1_walk_episode_t;

/* info at each inference: t, truth (vx, vy in the heading frame, yaw rate,
 * height, tilt), the command the controller reads (vx, vy, yaw rate) */
#define G1_WALK_INFO 9

/** The caller's policy: fills action[n_out] from obs[n_in]; label[n_out] is
 *  the expert's; returns 0, or non-zero to end the episode. */
typedef int (*g1_walk_act_fn)(void *user, const float *obs, const float *label, float *action,
                              const double *info);

static g1_walk_act_fn act_fn;
static void *act_user;
static float label[POLICY_JOINTS];
static double info[G1_WALK_INFO];
static int act_stop;

static void no_reset(void)
{
}

static int harness_forward(const float *in, float *out)
{
    if (act_fn(act_user, in, label, out, info) != 0) {
        act_stop = 1;
        return -1;
    }
    return 0;
}

int g1_walk_n_in(void)
{
    return POLICY_FRAME * POLICY_HISTORY;
}

int g1_walk_n_out(void)
{
    return POLICY_JOINTS;
}

int g1_walk_decimation(void)
{
    return config.decimation;
}

int g1_walk_rate_hz(void)
{
    return config.control_rate_hz;
}

/** The configuration's default pose and action scale (for the caller's
 *  records). */
void g1_walk_joints(double *default_pos, double *action_scale, double *kp, double *kd)
{
    for (int j = 0; j < POLICY_JOINTS; j++) {
        default_pos[j] = config.default_pos[j];
        action_scale[j] = config.action_scale[j];
        kp[j] = config.kp[j];
        kd[j] = config.kd[j];
    }
}

static int ran;
static roz_mujoco_t mj;

/** Runs one episode; returns the controller's ticks run (the episode ended
 *  early when fewer than asked), or a negative ROZ_E* (a message on
 *  stderr). @p summary (6): the whole run's truth, pelvis lowest, largest
 *  tilt, filter clamps, rate caps, port violations, falls (0/1). */
int g1_walk_run(const g1_walk_episode_t *ep, g1_walk_act_fn fn, void *user, double *summary)
{
    if (ran++) {
        fprintf(stderr, "g1_walk_run: one episode a process (the walker's state is static)\n");
        return ROZ_ESTATE;
    }
    const roz_manifest_t *m = roz_builtin_find("unitree_g1_12dof");
    if (m == NULL || m->n_states + m->n_inputs != config.n_states ||
        m->n_commands != (size_t)config.n_commands) {
        fprintf(stderr, "g1_walk_run: the tables are not unitree_g1_12dof's\n");
        return ROZ_EINVAL;
    }
    n_all_states = config.n_states;
    n_commands_all = config.n_commands;
    long long pre = llround(ep->pre_s * config.control_rate_hz);
    long long move = llround(ep->move_s * config.control_rate_hz);
    long long ticks = llround(ep->duration_s * config.control_rate_hz);
    char gantry[64], err[512] = "";
    snprintf(gantry, sizeof gantry, "0:%lld", pre + 1);
    roz_param_t item = { "gantry", gantry };
    roz_params_t params = { &item, pre > 0 ? 1 : 0 };
    roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
    if (roz_port_open(&p, m, &params, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "g1_walk_run: %s\n", err);
        return ROZ_EINVAL;
    }
    static roz_filter_t filter;
    static roz_inputs_t inputs;
    if (roz_filter_init(&filter, m) != ROZ_OK) {
        roz_port_close(&p);
        return ROZ_EINVAL;
    }
    roz_inputs_init(&inputs, m);
    roz_policy_config_t c = config;
    c.forward = harness_forward;
    c.reset = no_reset;
    if (ep->decimation > 0)
        c.decimation = ep->decimation;
    act_fn = fn;
    act_user = user;

    double out[ROZ_CFG_MAX_COMMANDS], stand[ROZ_CFG_MAX_COMMANDS], q0[POLICY_JOINTS];
    double lowest = INFINITY, tilt = 0.0;
    int fell = 0, primed = 0;
    long long t;
    for (t = 0; t < pre + ticks; t++) {
        int rc = roz_port_read(&p, cur_state, m->n_states);
        if (rc < 0) {
            fprintf(stderr, "g1_walk_run: read at tick %lld: %d\n", t, rc);
            break;
        }
        if (!primed) {
            roz_filter_prime(&filter, cur_state);
            primed = 1;
        }
        long long ct = t - pre; /* the controller's tick */
        double now = (double)ct / config.control_rate_hz;
        int row = -1;
        for (int r = 0; r < ep->n_rows; r++)
            if (ep->rows[4 * r] <= now + 1e-9)
                row = r;
        for (uint32_t k = 0; k < 3 && k < m->n_inputs; k++)
            (void)roz_inputs_set(&inputs, k, row >= 0 ? ep->rows[4 * row + 1 + k] : 0.0);
        roz_inputs_tick(&inputs, (uint64_t)t * 2000000u, cur_state + m->n_states);
        roz_mujoco_base_t b;
        roz_mujoco_base(&mj, &b);
        if (ct >= 0) {
            if (b.pos[2] < lowest)
                lowest = b.pos[2];
            double tl = fmax(fabs(b.roll), fabs(b.pitch));
            tilt = tl > tilt ? tl : tilt;
            if (b.pos[2] < ep->min_height || tl > 0.8) {
                fell = 1;
                break;
            }
        }
        const double *target;
        if (ct < 0) { /* the stand: moved from the measured pose, then held */
            if (t == 0)
                for (int j = 0; j < POLICY_JOINTS; j++)
                    q0[j] = cur_state[config.q[j]];
            double s = move > 0 ? fmin(1.0, (double)t / (double)move) : 1.0;
            for (size_t i = 0; i < m->n_commands; i++)
                stand[i] = config.command_init[i];
            for (int j = 0; j < POLICY_JOINTS; j++) {
                stand[config.pos[j]] = q0[j] + s * (config.default_pos[j] - q0[j]);
                stand[config.kp_ch[j]] = config.kp[j];
                stand[config.kd_ch[j]] = config.kd[j];
            }
            target = stand;
        } else {
            g1_walker_process(ct);
            for (int j = 0; j < POLICY_JOINTS; j++) {
                double kp = walker_cmd[config.kp_ch[j]];
                double q = walker_cmd[config.pos[j]];
                if (kp > 1e-6)
                    q += walker_cmd[config.pos[j] + 4 * POLICY_JOINTS] / kp; /* effort / kp */
                label[j] = (float)((q - config.default_pos[j]) / config.action_scale[j]);
            }
            double cy = cos(b.yaw), sy = sin(b.yaw);
            info[0] = now;
            info[1] = cy * b.lin_vel[0] + sy * b.lin_vel[1];
            info[2] = -sy * b.lin_vel[0] + cy * b.lin_vel[1];
            info[3] = 0.0;
            { /* the body's angular velocity about the world's z */
                double w = b.quat[0], x = b.quat[1], y = b.quat[2], z = b.quat[3];
                double r20 = 2 * (x * z - w * y), r21 = 2 * (y * z + w * x),
                       r22 = 1 - 2 * (x * x + y * y);
                info[3] = r20 * b.ang_vel[0] + r21 * b.ang_vel[1] + r22 * b.ang_vel[2];
            }
            info[4] = b.pos[2];
            info[5] = fmax(fabs(b.roll), fabs(b.pitch));
            for (int k = 0; k < 3; k++)
                info[6 + k] = cur_state[m->n_states + k];
            if (roz_policy_tick(&c, &ws, ct) != 0)
                break;
            target = policy_cmd;
        }
        roz_filter_apply(&filter, target, cur_state, ROZ_STOP_NONE, out);
        if (roz_port_write(&p, out, m->n_commands) != ROZ_OK) {
            fprintf(stderr, "g1_walk_run: write at tick %lld\n", t);
            break;
        }
    }
    roz_filter_counters_t fc;
    roz_filter_counters_get(&filter, &fc);
    roz_mujoco_counters_t mc;
    roz_mujoco_counters(&mj, &mc);
    if (summary != NULL) {
        summary[0] = lowest;
        summary[1] = tilt;
        summary[2] = (double)fc.clamps;
        summary[3] = (double)fc.rate_caps;
        summary[4] = (double)mc.violations;
        summary[5] = fell;
    }
    roz_port_close(&p);
    return (int)(t - pre > 0 ? t - pre : 0);
}
