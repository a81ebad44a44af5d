/* SPDX-License-Identifier: Apache-2.0 */
/* What the humanoid stand examples (g1_stand, g1_23dof_stand, pm01_stand,
 * x2_stand) share: each tick, every joint gets its pose's position target,
 * zero velocity and feed-forward torque, and its gains, the stiffness
 * ramped in over the first second (the manifests' rate caps would ramp it
 * anyway; ramping here keeps the command equal to what was asked). The
 * robot's own PD runs it. Each command kind's channels are consecutive,
 * one per joint, from the first joint's (pos, vel, kp, kd, tau).
 *
 * STAND_CONTROLLER writes each example's robot (its channels:
 * STAND_CHANNELS) and process (STAND_PROCESS) from its generated header's
 * names.
 *
 * The G1 stands add balance (stand_lean, stand_balance): the lean seen by
 * the pelvis IMU and the legs' joints, and its rate, move the ankles' and
 * hips' targets (an ankle and hip strategy), so the feet push the body back
 * over them and the hips keep the pelvis upright. */
#ifndef ROZ_EXAMPLE_STAND_H
#define ROZ_EXAMPLE_STAND_H

#include "roz_controller.h"
#include "roz_math.h"

/* 0 builds a stand without its balance, the pose alone (the tests'
 * baselines, the *_stand_pd builds). */
#ifndef STAND_BALANCE
#define STAND_BALANCE 1
#endif

static inline void stand_step(long long tick, double rate_hz, int joints, const double *pose,
                              const double *kp, const double *kd, int pos, int vel, int kp0,
                              int kd0, int tau)
{
    double ramp = (double)tick / rate_hz; /* seconds */
    if (ramp > 1.0)
        ramp = 1.0;
    for (int j = 0; j < joints; j++) {
        roz_command_set(pos + j, pose[j]);
        roz_command_set(vel + j, 0.0);
        roz_command_set(kp0 + j, ramp * kp[j]);
        roz_command_set(kd0 + j, kd[j]);
        roz_command_set(tau + j, 0.0);
    }
}

/* The body's lean, from the pelvis IMU (states from @p quat: orientation x,
 * y, z, w, then angular velocity x, y, z, body frame) and the legs' joint
 * positions (from @p legs: per leg hip pitch, roll, yaw, knee, ankle pitch,
 * roll; the left leg first, as on the G1):
 * - pitch, roll: the pelvis's tilt (gravity seen in its x-z and y-z planes;
 *   pitch > 0 leans forward), and their rates from the gyro;
 * - sway: the pelvis over the ankles, the angle of the line from the ankles
 *   to the hips (a sagittal two-link leg, thigh and shank STAND_LEG_M
 *   long; > 0: in front), the legs' mean; what the ankles balance.
 * rad, rad/s. A bad reading (NaN, or the pelvis upside down) leaves
 * `valid` 0, and stand_balance() then moves nothing. */
#define STAND_LEG_M 0.3
typedef struct {
    double roll, pitch, roll_rate, pitch_rate, sway;
    int valid;
} stand_lean_t;

static inline double stand__sway(double pitch, double hip, double knee)
{
    double x = STAND_LEG_M * (roz_math_sin(pitch + hip) + roz_math_sin(pitch + hip + knee));
    double z = STAND_LEG_M * (roz_math_cos(pitch + hip) + roz_math_cos(pitch + hip + knee));
    return roz_math_atan2(x, z);
}

static inline int stand__finite(double v)
{
    return v == v && v - v == 0.0;
}

static inline stand_lean_t stand_lean(int quat, int gyro, int legs)
{
    double x = roz_state_get(quat), y = roz_state_get(quat + 1);
    double z = roz_state_get(quat + 2), w = roz_state_get(quat + 3);
    stand_lean_t l = { 0.0, 0.0, 0.0, 0.0, 0.0, 0 };
    /* world up in the body frame: the third row of the body's rotation */
    double ux = 2.0 * (x * z - w * y), uy = 2.0 * (y * z + w * x);
    double uz = 1.0 - 2.0 * (x * x + y * y);
    double gx = roz_state_get(gyro), gy = roz_state_get(gyro + 1);
    if (!stand__finite(ux) || !stand__finite(uy) || !(uz > 0.0) || !stand__finite(gx) ||
        !stand__finite(gy))
        return l;
    l.roll = roz_math_atan2(uy, uz);
    l.pitch = roz_math_atan2(-ux, uz);
    l.roll_rate = gx;
    l.pitch_rate = gy;
    double sway = 0.0;
    for (int leg = 0; leg < 12; leg += 6) {
        double hip = roz_state_get(legs + leg), knee = roz_state_get(legs + leg + 3);
        if (!stand__finite(hip) || !stand__finite(knee))
            return l;
        sway += 0.5 * stand__sway(l.pitch, hip, knee);
    }
    l.sway = sway;
    l.valid = 1;
    return l;
}

/* Balance gains: target offsets (rad) per rad of sway (ankle pitch), of
 * roll (ankle roll) and of pelvis pitch (hip pitch), and per rad/s of their
 * rates; and the largest offset. */
typedef struct {
    double ankle_pitch, ankle_pitch_rate, ankle_roll, ankle_roll_rate;
    double hip_pitch, hip_pitch_rate, limit;
    double sway; /* rad: the sway held, from the pose's (< 0: back, the body's mass over the feet) */
} stand_balance_t;

/* Moves the leg targets in @p target (a copy of @p pose) for @p lean, by
 * @p g, faded in by @p ramp (0..1): the ankles push the pelvis back over
 * them (toward the pose's own sway, from the pose upright), the hips hold
 * the pelvis upright. @p sway_rate: the sway's rate (rad/s). Legs as in
 * stand_lean(), from joint 0. */
static inline void stand_balance(double *target, const double *pose, const stand_lean_t *lean,
                                 double sway_rate, const stand_balance_t *g, double ramp)
{
    if (!lean->valid)
        return; /* no reading to balance on: the pose alone */
    double sway0 = 0.5 * (stand__sway(0.0, pose[0], pose[3]) + stand__sway(0.0, pose[6], pose[9]));
    double ap = g->ankle_pitch * (lean->sway - sway0 - g->sway) + g->ankle_pitch_rate * sway_rate;
    double ar = g->ankle_roll * lean->roll + g->ankle_roll_rate * lean->roll_rate;
    double hp = g->hip_pitch * lean->pitch + g->hip_pitch_rate * lean->pitch_rate;
    ap = ramp * roz_math_clamp(ap, -g->limit, g->limit);
    ar = ramp * roz_math_clamp(ar, -g->limit, g->limit);
    hp = ramp * roz_math_clamp(hp, -g->limit, g->limit);
    for (int leg = 0; leg < 12; leg += 6) {
        target[leg + 0] += hp;
        target[leg + 4] += ap;
        target[leg + 5] += ar;
    }
}

/* A stand's robot: its pose and gains per joint, its balance (NULL: the
 * pose alone), the states stand_lean() reads (the IMU's orientation x and
 * angular velocity x, the left hip pitch's position) and the first joint's
 * command of each kind. */
#define STAND_MAX_JOINTS 32
typedef struct {
    int joints; /* at most STAND_MAX_JOINTS */
    double rate_hz;
    const double *pose, *kp, *kd;
    const stand_balance_t *balance;
    int quat, gyro, legs;
    int pos, vel, kp0, kd0, tau;
} stand_robot_t;

/* One tick of the balancing stand on @p r: the pose, moved by the balance
 * (faded in over the first second), sent with the gains (stand_step). The
 * sway's rate is the change of the last valid sway, a tick apart. */
static inline void stand_tick(long long tick, const stand_robot_t *r)
{
    static double sway_prev; /* the last valid sway, for its rate */
    static int have_prev;
    double target[STAND_MAX_JOINTS];
    int joints = r->joints < STAND_MAX_JOINTS ? r->joints : STAND_MAX_JOINTS;
    for (int j = 0; j < joints; j++)
        target[j] = r->pose[j];
    if (r->balance) {
        double ramp = (double)tick / r->rate_hz;
        stand_lean_t lean = stand_lean(r->quat, r->gyro, r->legs);
        double sway_rate = have_prev && lean.valid ? (lean.sway - sway_prev) * r->rate_hz : 0.0;
        have_prev = lean.valid;
        sway_prev = lean.sway;
        stand_balance(target, r->pose, &lean, sway_rate, r->balance, ramp < 1.0 ? ramp : 1.0);
    }
    stand_step(tick, r->rate_hz, joints, target, r->kp, r->kd, r->pos, r->vel, r->kp0, r->kd0,
               r->tau);
}

/* The stand_robot_t fields naming a robot's channels, from its generated
 * header's prefix (ROZ_UNITREE_G1) and its first leg joint, the left hip
 * pitch (LEFT_HIP_PITCH_JOINT). */
#define STAND_CHANNELS(PREFIX, FIRST)                                                     \
    .quat = PREFIX##_STATE_BASE_IMU_ORIENTATION_X,                                        \
    .gyro = PREFIX##_STATE_BASE_IMU_ANGULAR_VELOCITY_X,                                   \
    .legs = PREFIX##_STATE_##FIRST##_POSITION, .pos = PREFIX##_CMD_##FIRST##_POSITION,    \
    .vel = PREFIX##_CMD_##FIRST##_VELOCITY, .kp0 = PREFIX##_CMD_##FIRST##_STIFFNESS,      \
    .kd0 = PREFIX##_CMD_##FIRST##_DAMPING, .tau = PREFIX##_CMD_##FIRST##_EFFORT

/* A stand controller: stand_tick() on @p robot every tick. */
#define STAND_PROCESS(robot)                                                              \
    ROZ_PROCESS(tick)                                                                     \
    {                                                                                     \
        stand_tick(tick, &(robot));                                                       \
    }

/* A stand controller for the robot of the generated header's PREFIX, its
 * first leg joint FIRST (STAND_CHANNELS), on the file's JOINTS, RATE_HZ,
 * pose, kp, kd and, when STAND_BALANCE, balance. */
#define STAND_CONTROLLER(PREFIX, FIRST)                                                   \
    static const stand_robot_t robot = {                                                  \
        .joints = JOINTS, .rate_hz = RATE_HZ, .pose = pose, .kp = kp, .kd = kd,           \
        .balance = STAND_BALANCE ? &balance : 0,                                          \
        STAND_CHANNELS(PREFIX, FIRST),                                                    \
    };                                                                                    \
    STAND_PROCESS(robot)

/* The G1's ankle and hip strategy (target offsets per rad of lean and per
 * rad/s), which the PM01 and the 12-joint G1 stand on too. */
#define STAND_G1_BALANCE                                                                  \
    {                                                                                     \
        .ankle_pitch = 3.0, .ankle_pitch_rate = 0.3, .ankle_roll = 0.0,                   \
        .ankle_roll_rate = 0.0, .hip_pitch = 1.0, .hip_pitch_rate = 0.1, .limit = 0.4,    \
        .sway = -0.05,                                                                    \
    }

/* Standing poses (rad) in the manifests' joint order, which the tests'
 * stiff stands (test/ports/mujoco/controllers) stand in too: the 29-DoF
 * G1's, slightly crouched (legs, waist, arms), and the X2's (legs, waist
 * yaw, pitch, roll, arms, head yaw). */
#define STAND_G1_POSE                                                                     \
    {                                                                                     \
        -0.1, 0.0, 0.0, 0.3, -0.2, 0.0,    /* left leg */                                 \
        -0.1, 0.0, 0.0, 0.3, -0.2, 0.0,    /* right leg */                                \
        0.0, 0.0, 0.0,                     /* waist */                                    \
        0.2, 0.2, 0.0, 0.9, 0.0, 0.0, 0.0, /* left arm */                                 \
        0.2, -0.2, 0.0, 0.9, 0.0, 0.0, 0.0 /* right arm */                                \
    }
#define STAND_X2_POSE                                                                     \
    {                                                                                     \
        -0.3, 0.0, 0.0, 0.6, -0.3, 0.0,     /* left leg: hip pitch, roll, yaw, knee, ankle */ \
        -0.3, 0.0, 0.0, 0.6, -0.3, 0.0,     /* right leg */                               \
        0.0, 0.0, 0.0,                      /* waist yaw, pitch, roll */                  \
        0.0, 0.1, 0.0, -0.3, 0.0, 0.0, 0.0, /* left arm: shoulder pitch, roll, yaw, elbow, wrist */ \
        0.0, -0.1, 0.0, -0.3, 0.0, 0.0, 0.0, /* right arm */                              \
        0.0                                 /* head yaw */                                \
    }

#endif /* ROZ_EXAMPLE_STAND_H */
