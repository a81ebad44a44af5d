/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz_policy.h
 * @brief A generic runner of learned locomotion policies: observations from
 *        the robot's state channels, inference every Nth tick through a
 *        roz_nn.h network, actions to position targets with per-joint gains.
 *
 * Driven entirely by a configuration of tables (channel indices, scales,
 * default pose, gains), which `rozgen-nn deploy` writes from a policy's
 * deploy configuration and the robot's manifest (docs/policies.md): no
 * observation code is written per robot. One call a tick:
 *   ROZ_PROCESS(tick) { if (roz_policy_tick(&cfg, &ws, tick) != 0) roz_request_estop(); }
 *
 * Tick 0 (every fresh instance, after a swap too) resets the network's
 * state, the last action and the history, and sets every target to its
 * default. Stiffness ramps from 0 to its value over ramp_s seconds; damping
 * is its value from tick 0 (a runtime taking it over from a stand or another
 * controller keeps the gains on the wire through the ramp: roz/stages.h). Built natively the same header runs with
 * roz_nn.h's plain-C imports: the same bits as under wasm3.
 */
#ifndef ROZ_POLICY_H
#define ROZ_POLICY_H

#include "roz_controller.h"
#include "roz_math.h"
#include "roz_nn.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Observation terms, each of its own width; scales are per element. */
#define ROZ_POLICY_OBS_ANG_VEL     0 /**< 3: IMU angular velocity, body frame */
#define ROZ_POLICY_OBS_GRAVITY     1 /**< 3: (0, 0, -1) in the body frame (IMU quaternion) */
#define ROZ_POLICY_OBS_COMMAND     2 /**< 3: vx, vy, yaw rate */
#define ROZ_POLICY_OBS_JOINT_POS   3 /**< joints: q - default */
#define ROZ_POLICY_OBS_JOINT_VEL   4 /**< joints: dq */
#define ROZ_POLICY_OBS_LAST_ACTION 5 /**< joints: the previous inference's action */
#define ROZ_POLICY_OBS_PHASE       6 /**< 2: sin, cos of the gait phase */

/** One observation term: its kind and a scale per element. */
typedef struct roz_policy_term {
    int kind;
    const double *scale;
} roz_policy_term_t;

/** The configuration: tables the generator writes; const, never changed. */
typedef struct roz_policy_config {
    int n_states, n_commands; /**< the robot's channel counts */
    int control_rate_hz;
    int decimation;           /**< inference every decimation-th tick, from tick 0 */
    /* the policy's joints (one action each) */
    int n_joints;
    const int *q, *dq;                 /**< state channels: position, velocity */
    const int *pos, *kp_ch, *kd_ch;    /**< command channels: position, stiffness, damping */
    const double *default_pos, *kp, *kd, *action_scale;
    /* the joints the policy does not drive: held at a target with gains */
    int n_held;
    const int *held_pos, *held_kp_ch, *held_kd_ch;
    const double *held_target, *held_kp, *held_kd;
    /* every command channel's value before the above (the manifest's defaults) */
    const double *command_init;
    /* the IMU: state channels of orientation x, y, z, w and angular velocity x, y, z */
    int quat[4], gyro[3];
    /* the velocity command: a state channel each (an operator input), or -1
     * for the constant; each clamped to +-command_max (0: not clamped) */
    int command_ch[3];
    double command_const[3], command_max[3];
    /* observations: terms in order, one frame; history frames, oldest first */
    const roz_policy_term_t *terms;
    int n_terms, frame, history;
    double gait_period_s; /**< the phase's period; its time at inference k is (k+1) x decimation ticks */
    double obs_clip, action_clip; /**< symmetric; 0: none */
    double ramp_s;                /**< stiffness ramp-in, seconds; 0: none */
    /* the network (rozgen.nn's header) */
    int n_in, n_out;
    void (*reset)(void);
    int (*forward)(const float *in, float *out);
} roz_policy_config_t;

/** The runner's memory, arrays the caller gives (sizes in the comments). */
typedef struct roz_policy_ws {
    double *s;     /**< n_states: this tick's state */
    double *cmd;   /**< n_commands: the targets sent */
    float *frame;  /**< frame */
    float *obs;    /**< frame x history: the network's input */
    float *action; /**< n_joints */
} roz_policy_ws_t;

static inline float roz__policy_clip(double v, double clip)
{
    if (clip > 0.0)
        v = v > clip ? clip : v < -clip ? -clip : v;
    return (float)v;
}

/** @brief Fills ws->frame from ws->s (this tick's state) and the last action. */
static inline void roz_policy_observe(const roz_policy_config_t *c, roz_policy_ws_t *ws,
                                      long long tick)
{
    const double *s = ws->s;
    double x = s[c->quat[0]], y = s[c->quat[1]], z = s[c->quat[2]], w = s[c->quat[3]];
    double v[3];
    int n = 0;
    for (int t = 0; t < c->n_terms; t++) {
        const roz_policy_term_t *term = &c->terms[t];
        switch (term->kind) {
        case ROZ_POLICY_OBS_ANG_VEL:
            for (int k = 0; k < 3; k++)
                ws->frame[n++] = roz__policy_clip(s[c->gyro[k]] * term->scale[k], c->obs_clip);
            break;
        case ROZ_POLICY_OBS_GRAVITY:
            v[0] = 2.0 * (w * y - x * z);
            v[1] = -2.0 * (y * z + w * x);
            v[2] = -1.0 + 2.0 * (x * x + y * y);
            for (int k = 0; k < 3; k++)
                ws->frame[n++] = roz__policy_clip(v[k] * term->scale[k], c->obs_clip);
            break;
        case ROZ_POLICY_OBS_COMMAND:
            for (int k = 0; k < 3; k++) {
                double u = c->command_ch[k] >= 0 ? s[c->command_ch[k]] : c->command_const[k];
                double m = c->command_max[k];
                if (!(u == u) || u > 1e300 || u < -1e300)
                    u = 0.0; /* a missing or broken input commands standing still */
                if (m > 0.0)
                    u = u > m ? m : u < -m ? -m : u;
                ws->frame[n++] = roz__policy_clip(u * term->scale[k], c->obs_clip);
            }
            break;
        case ROZ_POLICY_OBS_JOINT_POS:
            for (int j = 0; j < c->n_joints; j++)
                ws->frame[n++] = roz__policy_clip((s[c->q[j]] - c->default_pos[j]) * term->scale[j],
                                                  c->obs_clip);
            break;
        case ROZ_POLICY_OBS_JOINT_VEL:
            for (int j = 0; j < c->n_joints; j++)
                ws->frame[n++] = roz__policy_clip(s[c->dq[j]] * term->scale[j], c->obs_clip);
            break;
        case ROZ_POLICY_OBS_LAST_ACTION:
            for (int j = 0; j < c->n_joints; j++)
                ws->frame[n++] = roz__policy_clip((double)ws->action[j] * term->scale[j],
                                                  c->obs_clip);
            break;
        default: { /* ROZ_POLICY_OBS_PHASE */
            double ticks = (double)(tick / c->decimation + 1) * c->decimation;
            double cycles = ticks / (c->control_rate_hz * c->gait_period_s);
            double phase = cycles - roz_math_floor(cycles); /* 0..1 */
            ws->frame[n++] = roz__policy_clip(roz_math_sin(ROZ_MATH_TWO_PI * phase) * term->scale[0],
                                              c->obs_clip);
            ws->frame[n++] = roz__policy_clip(roz_math_cos(ROZ_MATH_TWO_PI * phase) * term->scale[1],
                                              c->obs_clip);
        } break;
        }
    }
}

/**
 * @brief One tick: reads the state (state.get_all), infers on every
 *        decimation-th tick, writes every command (command.set_all).
 * @return 0, or -1 when the host refused a call (state.get_all of the
 *         tables' state count, or an nn call: a broken build or another
 *         robot; the caller asks for an e-stop; nothing is written that tick)
 * Context: the controller's process(); no heap; bounded by the tables.
 */
static inline int roz_policy_tick(const roz_policy_config_t *c, roz_policy_ws_t *ws, long long tick)
{
    double ramp = c->ramp_s > 0.0 ? (double)tick / (c->control_rate_hz * c->ramp_s) : 1.0;
    if (ramp > 1.0)
        ramp = 1.0;
    if (roz_state_get_all(ws->s, c->n_states) != c->n_states)
        return -1; /* a robot of fewer states than the tables: not the one built for */
    if (tick == 0) {
        c->reset();
        for (int i = 0; i < c->n_commands; i++)
            ws->cmd[i] = c->command_init[i];
        for (int j = 0; j < c->n_joints; j++) {
            ws->action[j] = 0.0f;
            ws->cmd[c->pos[j]] = c->default_pos[j];
        }
        for (int j = 0; j < c->n_held; j++)
            ws->cmd[c->held_pos[j]] = c->held_target[j];
    }
    if (tick % c->decimation == 0) {
        int f = c->frame, h = c->history;
        roz_policy_observe(c, ws, tick);
        for (int k = 0; k < (tick == 0 ? h : 1); k++) { /* tick 0 fills the history */
            for (int i = 0; i < (h - 1) * f; i++)
                ws->obs[i] = ws->obs[i + f];
            for (int i = 0; i < f; i++)
                ws->obs[(h - 1) * f + i] = ws->frame[i];
        }
        if (c->forward(ws->obs, ws->action) != 0)
            return -1;
        for (int j = 0; j < c->n_joints; j++) {
            ws->action[j] = roz__policy_clip((double)ws->action[j], c->action_clip);
            ws->cmd[c->pos[j]] = c->default_pos[j] + c->action_scale[j] * (double)ws->action[j];
        }
    }
    for (int j = 0; j < c->n_joints; j++) {
        ws->cmd[c->kp_ch[j]] = ramp * c->kp[j];
        ws->cmd[c->kd_ch[j]] = c->kd[j];
    }
    for (int j = 0; j < c->n_held; j++) {
        ws->cmd[c->held_kp_ch[j]] = ramp * c->held_kp[j];
        ws->cmd[c->held_kd_ch[j]] = c->held_kd[j];
    }
    roz_command_set_all(ws->cmd, c->n_commands);
    return 0;
}

#ifdef __cplusplus
}
#endif

#endif /* ROZ_POLICY_H */
