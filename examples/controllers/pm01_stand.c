/* SPDX-License-Identifier: Apache-2.0 */
/* Stand for the EngineAI PM01: joint-space PD on all 24 joints toward a
 * slightly crouched pose, run by the robot's own PD: position target, zero
 * velocity and feed-forward torque, and the gains, which ramp in over the
 * first second. Leg gains are the vendor's RL example's (kp 70/50/50/70/20/20,
 * kd 7/5/5/7/0.2/0.2), waist, arm and head stiffness too (200, 250, 100);
 * their damping (5, 5, 2) and the pose are ours. */
#include "stand.h"
#include "engineai_pm01_channels.h"

#define JOINTS 24
#define POS ROZ_ENGINEAI_PM01_CMD_J00_HIP_PITCH_L_POSITION
#define VEL ROZ_ENGINEAI_PM01_CMD_J00_HIP_PITCH_L_VELOCITY
#define KP ROZ_ENGINEAI_PM01_CMD_J00_HIP_PITCH_L_STIFFNESS
#define KD ROZ_ENGINEAI_PM01_CMD_J00_HIP_PITCH_L_DAMPING
#define TAU ROZ_ENGINEAI_PM01_CMD_J00_HIP_PITCH_L_EFFORT

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
    70, 50, 50, 70, 20, 20, 70, 50, 50, 70, 20, 20, 200,
    250, 250, 250, 250, 250, 250, 250, 250, 250, 250, 100,
};
static const double kd[JOINTS] = {
    7, 5, 5, 7, 0.2, 0.2, 7, 5, 5, 7, 0.2, 0.2, 5,
    5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 2,
};

ROZ_PROCESS(tick)
{
    stand_step(tick, (double)ROZ_ENGINEAI_PM01_CONTROL_RATE_HZ,
               JOINTS, pose, kp, kd, POS, VEL, KP, KD, TAU);
}
