/* SPDX-License-Identifier: Apache-2.0 */
/* Stand for the EngineAI PM01: joint-space PD on all 24 joints toward a
 * slightly crouched pose, run by the robot's own PD (position target, zero
 * velocity and feed-forward torque, and the gains, which ramp in over the
 * first second), with the G1 stand's balance (stand.h): ankle pitch from
 * the pelvis's sway over the ankles, hip pitch from its tilt, read off the
 * IMU. Hip and knee gains are the vendor's RL example's (kp 70/50/50/70,
 * kd 7/5/5/7), waist, arm and head stiffness too (200, 250, 100); the
 * ankles' (kp 100, kd 3: the example's 20 lets the robot fall within 2 s in
 * MuJoCo), the damping of the rest (5, 5, 2) and the pose are ours. */
#include "stand.h"
#include "engineai_pm01_channels.h"

#define JOINTS 24
#define RATE_HZ ((double)ROZ_ENGINEAI_PM01_CONTROL_RATE_HZ)

/* Standing pose in the robot's joint order (rad). */
static const double pose[JOINTS] = {
    -0.24, 0.0, 0.0, 0.48, -0.24, 0.0, /* left leg: hip pitch, roll, yaw, knee, ankle */
    -0.24, 0.0, 0.0, 0.48, -0.24, 0.0, /* right leg */
    0.0,                               /* waist yaw */
    0.0, 0.2, 0.0, -0.3, 0.0,          /* left arm: shoulder pitch, roll, yaw, elbow */
    0.0, -0.2, 0.0, -0.3, 0.0,         /* right arm */
    0.0,                               /* head yaw */
};
static const double kp[JOINTS] = {
    70, 50, 50, 70, 100, 100, 70, 50, 50, 70, 100, 100, 200,
    250, 250, 250, 250, 250, 250, 250, 250, 250, 250, 100,
};
static const double kd[JOINTS] = {
    7, 5, 5, 7, 3, 3, 7, 5, 5, 7, 3, 3, 5,
    5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 2,
};

/* Target offsets per rad of lean and per rad/s (stand.h): the G1's
 * ankle and hip strategy, on the PM01's legs (the same joint order:
 * hip pitch, roll, yaw, knee, ankle pitch, roll). */
static const stand_balance_t balance = STAND_G1_BALANCE;

STAND_CONTROLLER(ROZ_ENGINEAI_PM01, J00_HIP_PITCH_L)
