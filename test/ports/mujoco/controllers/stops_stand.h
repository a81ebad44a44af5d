/* SPDX-License-Identifier: Apache-2.0 */
/* The standing G1 the stop cases start from (test_mujoco_stops.c): the
 * example stand's pose, with legs and waist stiff enough to hold the G1 up
 * as an inverted pendulum (ankles kp 150: the example's 40 tips it over
 * after 1.6 s). Gains ramp in over the first second, as the example's do.
 * Each controller file says what it does at STOP_TICK. */
#ifndef STOPS_STAND_H
#define STOPS_STAND_H

#include "roz_controller.h"
#include "unitree_g1_channels.h"

#define JOINTS 29
#define POS ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_POSITION
#define VEL ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_VELOCITY
#define KP ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS
#define KD ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_DAMPING
#define TAU ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_EFFORT

/* 2 s at 500 Hz: the stand has settled */
#define STOP_TICK 1000

static const double pose[JOINTS] = {
    -0.1, 0.0, 0.0, 0.3, -0.2, 0.0,     /* left leg */
    -0.1, 0.0, 0.0, 0.3, -0.2, 0.0,     /* right leg */
    0.0, 0.0, 0.0,                      /* waist */
    0.2, 0.2, 0.0, 0.9, 0.0, 0.0, 0.0,  /* left arm */
    0.2, -0.2, 0.0, 0.9, 0.0, 0.0, 0.0, /* right arm */
};
static const double kp[JOINTS] = {
    200, 200, 150, 200, 200, 150, 200, 200, 150, 200, 200, 150, 200, 200, 200,
    40, 40, 40, 40, 20, 20, 20, 40, 40, 40, 40, 20, 20, 20,
};
static const double kd[JOINTS] = {
    5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5,
    1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
};

/* Ankle strategy: the ankles' pitch targets lean against the pelvis' pitch
 * (small-angle, from the IMU quaternion) and its rate, so the stand keeps
 * its centre of mass over the feet; the joint-space pose alone drifts
 * forward onto the toes. */
#define BAL_P 1.0
#define BAL_D 0.1
#define L_ANKLE 4
#define R_ANKLE 10

static inline double stops_pitch_lean(void)
{
    double qx = roz_state_get(ROZ_UNITREE_G1_STATE_BASE_IMU_ORIENTATION_X);
    double qy = roz_state_get(ROZ_UNITREE_G1_STATE_BASE_IMU_ORIENTATION_Y);
    double qz = roz_state_get(ROZ_UNITREE_G1_STATE_BASE_IMU_ORIENTATION_Z);
    double qw = roz_state_get(ROZ_UNITREE_G1_STATE_BASE_IMU_ORIENTATION_W);
    double rate = roz_state_get(ROZ_UNITREE_G1_STATE_BASE_IMU_ANGULAR_VELOCITY_Y);
    double lean = BAL_P * 2.0 * (qw * qy - qz * qx) + BAL_D * rate;
    return lean == lean && lean > -0.3 && lean < 0.3 ? lean : 0.0; /* NaN or wild: none */
}

/* One tick of the stand; `ramp_s`: seconds over which the gains ramp in
 * (0: at once, the manifest's rate caps still ramp them). */
static inline void stops_stand(long long tick, double ramp_s)
{
    double ramp = ramp_s > 0.0 ? (double)tick / (ramp_s * ROZ_UNITREE_G1_CONTROL_RATE_HZ) : 1.0;
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
