/* SPDX-License-Identifier: Apache-2.0 */
/* The standing X2 the X2's stop cases start from (test_mujoco_stops.c,
 * test_mujoco_stops_x2): x2_stand's pose, with legs and waist at the
 * manifest's hold gains (the stiffness defaults a stop brings them to) and
 * the G1 stiff stand's ankle strategy; gains ramp in over the first
 * second. It takes the place of stops_stand.h (the same guard), so each of
 * the G1's stop controllers, included after it by an x2_stops_*.c file, is
 * the same stop on the X2. */
#ifndef STOPS_STAND_H
#define STOPS_STAND_H

#include "roz_controller.h"
#include "agibot_x2_channels.h"

#define JOINTS 30
#define POS ROZ_AGIBOT_X2_CMD_LEFT_HIP_PITCH_JOINT_POSITION
#define VEL ROZ_AGIBOT_X2_CMD_LEFT_HIP_PITCH_JOINT_VELOCITY
#define KP ROZ_AGIBOT_X2_CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS
#define KD ROZ_AGIBOT_X2_CMD_LEFT_HIP_PITCH_JOINT_DAMPING
#define TAU ROZ_AGIBOT_X2_CMD_LEFT_HIP_PITCH_JOINT_EFFORT

/* 2 s at 500 Hz: the stand has settled */
#define STOP_TICK 1000

static const double pose[JOINTS] = {
    -0.3, 0.0, 0.0, 0.6, -0.3, 0.0,      /* left leg */
    -0.3, 0.0, 0.0, 0.6, -0.3, 0.0,      /* right leg */
    0.0, 0.0, 0.0,                       /* waist */
    0.0, 0.1, 0.0, -0.3, 0.0, 0.0, 0.0,  /* left arm */
    0.0, -0.1, 0.0, -0.3, 0.0, 0.0, 0.0, /* right arm */
    0.0,                                 /* head yaw */
};
static const double kp[JOINTS] = {
    200, 200, 150, 200, 200, 150, 200, 200, 150, 200, 200, 150, 150, 200, 200,
    40, 40, 40, 40, 20, 20, 20, 40, 40, 40, 40, 20, 20, 20, 20,
};
static const double kd[JOINTS] = {
    5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5,
    1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
};

#define BAL_P 1.0
#define BAL_D 0.1
#define L_ANKLE 4
#define R_ANKLE 10

static inline double stops_pitch_lean(void)
{
    double qx = roz_state_get(ROZ_AGIBOT_X2_STATE_BASE_IMU_ORIENTATION_X);
    double qy = roz_state_get(ROZ_AGIBOT_X2_STATE_BASE_IMU_ORIENTATION_Y);
    double qz = roz_state_get(ROZ_AGIBOT_X2_STATE_BASE_IMU_ORIENTATION_Z);
    double qw = roz_state_get(ROZ_AGIBOT_X2_STATE_BASE_IMU_ORIENTATION_W);
    double rate = roz_state_get(ROZ_AGIBOT_X2_STATE_BASE_IMU_ANGULAR_VELOCITY_Y);
    double lean = BAL_P * 2.0 * (qw * qy - qz * qx) + BAL_D * rate;
    return lean == lean && lean > -0.3 && lean < 0.3 ? lean : 0.0; /* NaN or wild: none */
}

static inline void stops_stand(long long tick, double ramp_s)
{
    double ramp = ramp_s > 0.0 ? (double)tick / (ramp_s * ROZ_AGIBOT_X2_CONTROL_RATE_HZ) : 1.0;
    if (ramp > 1.0)
        ramp = 1.0;
    double lean = stops_pitch_lean();
    for (int j = 0; j < JOINTS; j++) {
        roz_command_set(POS + j, pose[j] + (j == L_ANKLE || j == R_ANKLE ? lean : 0.0));
        roz_command_set(VEL + j, 0.0);
        roz_command_set(KP + j, ramp * kp[j]);
        roz_command_set(KD + j, kd[j]);
        roz_command_set(TAU + j, 0.0);
    }
}

#endif /* STOPS_STAND_H */
