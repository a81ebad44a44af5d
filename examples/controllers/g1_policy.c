/* SPDX-License-Identifier: Apache-2.0 */
/* The pattern of a learned locomotion policy on the G1, in unitree_rl_gym's
 * layout (docs/policies.md): every 10th tick of the 500 Hz loop (50 Hz) it
 * builds the 47 observations, runs the network (policy_net.h, written by
 * rozgen.nn: here a random LSTM 47 -> 64 -> 32 ELU -> 12, so it does not
 * walk; an exported trained policy takes its place) and turns the 12
 * actions into leg targets, default + 0.25 action, held with per-joint
 * kp/kd by the robot's PD until the next inference. The other 17 joints
 * hold the standing pose. Gains ramp in over the first second.
 *
 * Observations (scales as unitree_rl_gym's G1 deploy configuration):
 *   0..2    base angular velocity (IMU, body frame) * 0.25
 *   3..5    gravity projected into the body frame, from the IMU quaternion
 *   6..8    command (vx, vy, yaw rate) * (2, 2, 0.25)
 *   9..20   leg joint positions - default pose
 *   21..32  leg joint velocities * 0.05
 *   33..44  the last action
 *   45, 46  sin and cos of the gait phase (period 0.8 s)
 * Tick 0 (every fresh instance, after a swap too) resets the LSTM state
 * and the last action. */
#include "roz_controller.h"
#include "roz_math.h"
#include "roz_nn.h"
#include "unitree_g1_channels.h"

#include "policy_net.h"

/* An inference tick costs about 46,700 units, the others about 1,300;
 * the G1's default budget is 20,000 (roz_controller.h, ROZ_FUEL_PER_TICK). */
ROZ_FUEL_PER_TICK(55000);

#define JOINTS 29
#define LEGS 12
#define DECIMATION 10 /* 500 Hz / 50 Hz */
#define Q ROZ_UNITREE_G1_STATE_LEFT_HIP_PITCH_JOINT_POSITION
#define QD ROZ_UNITREE_G1_STATE_LEFT_HIP_PITCH_JOINT_VELOCITY
#define QUAT ROZ_UNITREE_G1_STATE_BASE_IMU_ORIENTATION_X /* x, y, z, w */
#define GYRO ROZ_UNITREE_G1_STATE_BASE_IMU_ANGULAR_VELOCITY_X
#define POS ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_POSITION
#define KP ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS
#define KD ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_DAMPING

_Static_assert(POLICY_N_IN == 47 && POLICY_N_OUT == LEGS, "the G1 policy's shape");

/* Standing pose (the legs' is the policy's default) and gains, SDK order. */
static const double pose[JOINTS] = {
    -0.1, 0.0, 0.0, 0.3, -0.2, 0.0, -0.1, 0.0, 0.0, 0.3, -0.2, 0.0, 0.0, 0.0, 0.0,
    0.2,  0.2, 0.0, 0.9, 0.0,  0.0, 0.0,  0.2, -0.2, 0.0, 0.9, 0.0, 0.0, 0.0,
};
static const double kp[JOINTS] = {
    100, 100, 100, 150, 40, 40, 100, 100, 100, 150, 40, 40, 100, 40, 40,
    40,  40,  40,  40,  20, 20, 20,  40,  40,  40,  40, 20, 20,  20,
};
static const double kd[JOINTS] = {
    2, 2, 2, 4, 2, 2, 2, 2, 2, 4, 2, 2, 2, 2, 2, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
};
static const double command[3] = { 0.5, 0.0, 0.0 }; /* vx m/s, vy m/s, yaw rate rad/s */
#define ACTION_SCALE 0.25
#define CLIP 100.0f
#define GAIT_PERIOD_S 0.8

static double s[ROZ_UNITREE_G1_N_STATES];
static double cmd[ROZ_UNITREE_G1_N_COMMANDS]; /* velocity and effort commands stay 0 */
static float obs[POLICY_N_IN], action[LEGS];

static float clip(double v)
{
    return v > CLIP ? CLIP : v < -CLIP ? -CLIP : (float)v;
}

static void observe(long long tick)
{
    double x = s[QUAT], y = s[QUAT + 1], z = s[QUAT + 2], w = s[QUAT + 3];
    double cycles = (double)tick / (ROZ_UNITREE_G1_CONTROL_RATE_HZ * GAIT_PERIOD_S);
    double phase = cycles - roz_math_floor(cycles); /* 0..1 */
    for (int k = 0; k < 3; k++)
        obs[k] = clip(s[GYRO + k] * 0.25);
    /* (0, 0, -1) rotated into the body frame */
    obs[3] = clip(2.0 * (w * y - x * z));
    obs[4] = clip(-2.0 * (y * z + w * x));
    obs[5] = clip(-1.0 + 2.0 * (x * x + y * y));
    obs[6] = clip(command[0] * 2.0);
    obs[7] = clip(command[1] * 2.0);
    obs[8] = clip(command[2] * 0.25);
    for (int j = 0; j < LEGS; j++) {
        obs[9 + j] = clip(s[Q + j] - pose[j]);
        obs[21 + j] = clip(s[QD + j] * 0.05);
        obs[33 + j] = action[j];
    }
    obs[45] = clip(roz_math_sin(ROZ_MATH_TWO_PI * phase));
    obs[46] = clip(roz_math_cos(ROZ_MATH_TWO_PI * phase));
}

ROZ_PROCESS(tick)
{
    double ramp = (double)tick / ROZ_UNITREE_G1_CONTROL_RATE_HZ; /* seconds */
    if (ramp > 1.0)
        ramp = 1.0;
    roz_state_get_all(s, ROZ_UNITREE_G1_N_STATES);
    if (tick == 0) {
        policy_reset();
        for (int j = 0; j < LEGS; j++)
            action[j] = 0.0f;
        for (int j = 0; j < JOINTS; j++)
            cmd[POS + j] = pose[j];
    }
    if (tick % DECIMATION == 0) {
        observe(tick);
        if (policy_forward(obs, action) != 0) {
            roz_request_estop(); /* the host refused a call: a broken build */
            return;
        }
        for (int j = 0; j < LEGS; j++) {
            action[j] = clip(action[j]);
            cmd[POS + j] = pose[j] + ACTION_SCALE * (double)action[j];
        }
    }
    /* targets held between inferences; the gains ramp every tick */
    for (int j = 0; j < JOINTS; j++) {
        cmd[KP + j] = ramp * kp[j];
        cmd[KD + j] = kd[j];
    }
    roz_command_set_all(cmd, ROZ_UNITREE_G1_N_COMMANDS);
}
