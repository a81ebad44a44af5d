/* SPDX-License-Identifier: Apache-2.0 */
/* The robots' topics and joints, from the vendors' descriptions:
 * - EngineAI PM01 (interface_protocol): /hardware/joint_state,
 *   /hardware/joint_command, /hardware/imu_info; 24 joints J00..J23;
 * - AgiBot X2 (AimDK): /aima/hal/joint/{leg,waist,arm,head}/{state,command},
 *   /aima/hal/imu/torso/state; leg 12, waist 3 (yaw, pitch, roll), arm 14
 *   (left 7, right 7), head 2 (yaw, then a pitch placeholder).
 * ROS 2 puts "rt" before a topic's name on DDS. */
#include "robots.h"

#include <string.h>

static const char *const pm01_joints[] = {
    "J00_HIP_PITCH_L",      "J01_HIP_ROLL_L",       "J02_HIP_YAW_L",      "J03_KNEE_PITCH_L",
    "J04_ANKLE_PITCH_L",    "J05_ANKLE_ROLL_L",     "J06_HIP_PITCH_R",    "J07_HIP_ROLL_R",
    "J08_HIP_YAW_R",        "J09_KNEE_PITCH_R",     "J10_ANKLE_PITCH_R",  "J11_ANKLE_ROLL_R",
    "J12_WAIST_YAW",        "J13_SHOULDER_PITCH_L", "J14_SHOULDER_ROLL_L", "J15_SHOULDER_YAW_L",
    "J16_ELBOW_PITCH_L",    "J17_ELBOW_YAW_L",      "J18_SHOULDER_PITCH_R", "J19_SHOULDER_ROLL_R",
    "J20_SHOULDER_YAW_R",   "J21_ELBOW_PITCH_R",    "J22_ELBOW_YAW_R",    "J23_HEAD_YAW",
};

static const fake_group_t pm01_groups[] = {
    { "body", "rt/hardware/joint_state", "rt/hardware/joint_command", pm01_joints, 24 },
};

static const char *const x2_leg[] = {
    "left_hip_pitch_joint",  "left_hip_roll_joint",    "left_hip_yaw_joint",
    "left_knee_joint",       "left_ankle_pitch_joint", "left_ankle_roll_joint",
    "right_hip_pitch_joint", "right_hip_roll_joint",   "right_hip_yaw_joint",
    "right_knee_joint",      "right_ankle_pitch_joint", "right_ankle_roll_joint",
};
static const char *const x2_waist[] = { "waist_yaw_joint", "waist_pitch_joint",
                                        "waist_roll_joint" };
static const char *const x2_arm[] = {
    "left_shoulder_pitch_joint",  "left_shoulder_roll_joint",  "left_shoulder_yaw_joint",
    "left_elbow_joint",           "left_wrist_yaw_joint",      "left_wrist_pitch_joint",
    "left_wrist_roll_joint",      "right_shoulder_pitch_joint", "right_shoulder_roll_joint",
    "right_shoulder_yaw_joint",   "right_elbow_joint",         "right_wrist_yaw_joint",
    "right_wrist_pitch_joint",    "right_wrist_roll_joint",
};
static const char *const x2_head[] = { "head_yaw_joint", "head_pitch_joint" };

static const fake_group_t x2_groups[] = {
    { "leg", "rt/aima/hal/joint/leg/state", "rt/aima/hal/joint/leg/command", x2_leg, 12 },
    { "waist", "rt/aima/hal/joint/waist/state", "rt/aima/hal/joint/waist/command", x2_waist, 3 },
    { "arm", "rt/aima/hal/joint/arm/state", "rt/aima/hal/joint/arm/command", x2_arm, 14 },
    { "head", "rt/aima/hal/joint/head/state", "rt/aima/hal/joint/head/command", x2_head, 2 },
};

static const fake_robot_t robots[] = {
    { "pm01", FAKE_PM01, pm01_groups, 1, "rt/hardware/imu_info" },
    { "x2", FAKE_X2, x2_groups, 4, "rt/aima/hal/imu/torso/state" },
};

const fake_robot_t *fake_robot_find(const char *name)
{
    for (size_t i = 0; i < sizeof robots / sizeof robots[0]; i++) {
        if (strcmp(robots[i].name, name) == 0)
            return &robots[i];
    }
    return NULL;
}
