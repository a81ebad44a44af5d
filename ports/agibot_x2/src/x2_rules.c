/* SPDX-License-Identifier: Apache-2.0 */
/* The X2's rules of its [hardware] keys: its joints by group and its own
 * parameter; roz::ros2_rules binds and reads the rest. One implementation,
 * run by the port's open and by roz_agibot_x2_check() (what rozgen runs):
 * no DDS here. */
#include "x2_rules.h"

#include "roz/hal/params.h"

/* ---- joints ---------------------------------------------------------------------- */

static const char *const leg[] = {
    "left_hip_pitch_joint",  "left_hip_roll_joint",     "left_hip_yaw_joint",
    "left_knee_joint",       "left_ankle_pitch_joint",  "left_ankle_roll_joint",
    "right_hip_pitch_joint", "right_hip_roll_joint",    "right_hip_yaw_joint",
    "right_knee_joint",      "right_ankle_pitch_joint", "right_ankle_roll_joint",
};
static const char *const waist[] = { "waist_yaw_joint", "waist_pitch_joint",
                                     "waist_roll_joint" };
static const char *const arm[] = {
    "left_shoulder_pitch_joint",  "left_shoulder_roll_joint",  "left_shoulder_yaw_joint",
    "left_elbow_joint",           "left_wrist_yaw_joint",      "left_wrist_pitch_joint",
    "left_wrist_roll_joint",      "right_shoulder_pitch_joint", "right_shoulder_roll_joint",
    "right_shoulder_yaw_joint",   "right_elbow_joint",         "right_wrist_yaw_joint",
    "right_wrist_pitch_joint",    "right_wrist_roll_joint",
};
static const char *const head[] = { "head_yaw_joint", "head_pitch_joint" };

const roz_ros2_group_t roz_agibot_x2_groups[ROZ_AGIBOT_X2_GROUPS] = {
    { "leg", "rt/aima/hal/joint/leg/state", "rt/aima/hal/joint/leg/command", leg, 12 },
    { "waist", "rt/aima/hal/joint/waist/state", "rt/aima/hal/joint/waist/command", waist, 3 },
    { "arm", "rt/aima/hal/joint/arm/state", "rt/aima/hal/joint/arm/command", arm, 14 },
    { "head", "rt/aima/hal/joint/head/state", "rt/aima/hal/joint/head/command", head, 2 },
};

/* ---- parameters ------------------------------------------------------------------- */

int roz__x2_params(void *v, const roz_params_t *p, char *err, size_t errlen)
{
    static const roz_params_word_t words[] = { { "sdk", 0 }, { "docs", 1 } };
    roz_agibot_x2_t *x2 = v;
    return roz_params_get_choice(p, "joint_state_layout", "sdk", words, 2,
                                 "sdk (the SDK's JointState: name, position, velocity, effort, "
                                 "error_code; the default) or docs (the online documentation's: "
                                 "..., coil_temp, motor_temp, motor_vol)",
                                 &x2->docs_layout, err, errlen);
}

/* ---- what the port says of itself: its parameters' rows, its known keys ---- */

static const roz_port_param_info_t x2_param_info[] = {
    ROZ_ROS2_PARAM_INFO,
    ROZ_PORT_PARAM_TEXT_ROW("joint_state_layout", "sdk|docs", "sdk",
                            "the joint_state messages' layout"),
};

const roz_port_info_t roz__x2_info = {
    .summary = "the AgiBot X2 over its AimDK ROS 2 topics on Cyclone DDS",
    .header = "roz/port/agibot_x2.h",
    ROZ_PORT_INFO_PARAMS(x2_param_info),
    .no_crc = "ROS 2 messages carry no CRC (the headers' sequence numbers are checked instead)",
};

/* ---- the registered check ---------------------------------------------------------- */

static const roz_ros2_robot_t x2_rules = { ROZ__X2_ROBOT_RULES };

int roz_agibot_x2_check(const roz_manifest_t *m, roz_params_problem_fn report, void *ctx)
{
    static roz_agibot_x2_t x2; /* host tools, one call at a time */
    return roz_ros2_check(&x2_rules, &x2.b, &x2, m, report, ctx);
}
