/* SPDX-License-Identifier: Apache-2.0 */
/* The G1 PD's channels and reference pose, which g1_pd.c (a call per
 * channel) and g1_pd_bulk.c (the bulk extension) compute alike. */
#ifndef ROZ_EXAMPLE_G1_PD_H
#define ROZ_EXAMPLE_G1_PD_H

#include "roz_controller.h"
#include "unitree_g1_channels.h"

#define JOINTS 29
#define Q ROZ_UNITREE_G1_STATE_LEFT_HIP_PITCH_JOINT_POSITION
#define QD ROZ_UNITREE_G1_STATE_LEFT_HIP_PITCH_JOINT_VELOCITY
#define POS ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_POSITION
#define VEL ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_VELOCITY
#define KP ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS
#define KD ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_DAMPING
#define TAU ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_EFFORT

static const double q_ref[JOINTS] = {
    -0.1, 0.0, 0.0, 0.3, -0.2, 0.0, -0.1, 0.0, 0.0, 0.3, -0.2, 0.0, 0.0, 0.0, 0.0,
    0.2,  0.2, 0.0, 0.9, 0.0,  0.0, 0.0,  0.2, -0.2, 0.0, 0.9, 0.0, 0.0, 0.0,
};

#endif /* ROZ_EXAMPLE_G1_PD_H */
