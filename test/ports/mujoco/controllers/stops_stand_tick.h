/* SPDX-License-Identifier: Apache-2.0 */
/* The stiff stand's tick, for the robot whose stops_stand header includes
 * this after naming its channels' prefix (STOPS_ROBOT), JOINTS and the
 * pose and gains: stops_stand.h (the G1), x2_stops_stand.h (the X2). Each
 * controller file says what it does at STOP_TICK. */
#ifndef STOPS_STAND_TICK_H
#define STOPS_STAND_TICK_H

#define POS STOPS_ROBOT(CMD_LEFT_HIP_PITCH_JOINT_POSITION)
#define VEL STOPS_ROBOT(CMD_LEFT_HIP_PITCH_JOINT_VELOCITY)
#define KP STOPS_ROBOT(CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS)
#define KD STOPS_ROBOT(CMD_LEFT_HIP_PITCH_JOINT_DAMPING)
#define TAU STOPS_ROBOT(CMD_LEFT_HIP_PITCH_JOINT_EFFORT)

/* 2 s at 500 Hz: the stand has settled */
#define STOP_TICK 1000

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
    double qx = roz_state_get(STOPS_ROBOT(STATE_BASE_IMU_ORIENTATION_X));
    double qy = roz_state_get(STOPS_ROBOT(STATE_BASE_IMU_ORIENTATION_Y));
    double qz = roz_state_get(STOPS_ROBOT(STATE_BASE_IMU_ORIENTATION_Z));
    double qw = roz_state_get(STOPS_ROBOT(STATE_BASE_IMU_ORIENTATION_W));
    double rate = roz_state_get(STOPS_ROBOT(STATE_BASE_IMU_ANGULAR_VELOCITY_Y));
    double lean = BAL_P * 2.0 * (qw * qy - qz * qx) + BAL_D * rate;
    return lean == lean && lean > -0.3 && lean < 0.3 ? lean : 0.0; /* NaN or wild: none */
}

/* One tick of the stand; `ramp_s`: seconds over which the gains ramp in
 * (0: at once, the manifest's rate caps still ramp them). */
static inline void stops_stand(long long tick, double ramp_s)
{
    double ramp = ramp_s > 0.0 ? (double)tick / (ramp_s * STOPS_ROBOT(CONTROL_RATE_HZ)) : 1.0;
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

#endif /* STOPS_STAND_TICK_H */
