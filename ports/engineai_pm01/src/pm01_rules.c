/* SPDX-License-Identifier: Apache-2.0 */
/* The PM01's rules of its [hardware] keys: its joints and its own
 * parameter; roz::ros2_rules binds and reads the rest. One implementation,
 * run by the port's open and by roz_engineai_pm01_check() (what rozgen
 * runs): no DDS here. */
#include "pm01_rules.h"

#include "roz/hal/params.h"

#define N ROZ_ENGINEAI_PM01_JOINTS

/* ---- joints ---------------------------------------------------------------------- */

const char *const roz_engineai_pm01_joints[N] = {
    "J00_HIP_PITCH_L",      "J01_HIP_ROLL_L",      "J02_HIP_YAW_L",       "J03_KNEE_PITCH_L",
    "J04_ANKLE_PITCH_L",    "J05_ANKLE_ROLL_L",    "J06_HIP_PITCH_R",     "J07_HIP_ROLL_R",
    "J08_HIP_YAW_R",        "J09_KNEE_PITCH_R",    "J10_ANKLE_PITCH_R",   "J11_ANKLE_ROLL_R",
    "J12_WAIST_YAW",        "J13_SHOULDER_PITCH_L", "J14_SHOULDER_ROLL_L", "J15_SHOULDER_YAW_L",
    "J16_ELBOW_PITCH_L",    "J17_ELBOW_YAW_L",     "J18_SHOULDER_PITCH_R", "J19_SHOULDER_ROLL_R",
    "J20_SHOULDER_YAW_R",   "J21_ELBOW_PITCH_R",   "J22_ELBOW_YAW_R",     "J23_HEAD_YAW",
};

const roz_ros2_group_t roz__pm01_groups[1] = {
    { "body", "rt/hardware/joint_state", "rt/hardware/joint_command", roz_engineai_pm01_joints,
      N },
};

/* ---- parameters ------------------------------------------------------------------- */

int roz__pm01_params(void *v, const roz_params_t *p, char *err, size_t errlen)
{
    static const roz_params_word_t words[] = {
        { "rl", 1 }, { "RL_PARSER", 1 }, { "1", 1 },
        { "classic", 0 }, { "CLASSIC_PARSER", 0 }, { "0", 0 },
    };
    roz_engineai_pm01_t *pm = v;
    int type;
    int rc = roz_params_get_choice(p, "parallel_parser_type", "rl", words,
                                   sizeof words / sizeof words[0],
                                   "rl (1, RL_PARSER, the default, as the vendor's RL example) "
                                   "or classic (0, CLASSIC_PARSER)",
                                   &type, err, errlen);
    if (rc == ROZ_OK)
        pm->parallel_parser_type = (uint8_t)type;
    return rc;
}

/* ---- what the port says of itself: its parameters' rows, its known keys ---- */

static const roz_port_param_info_t pm01_param_info[] = {
    ROZ_ROS2_PARAM_INFO,
    ROZ_PORT_PARAM_TEXT_ROW("parallel_parser_type", "rl|classic|1|0", "rl",
                            "the ankle parser: rl (the vendor's RL example) or classic"),
};

const roz_port_info_t roz__pm01_info = {
    .summary = "the EngineAI PM01 over its ROS 2 topics on Cyclone DDS",
    .header = "roz/port/engineai_pm01.h",
    ROZ_PORT_INFO_PARAMS(pm01_param_info),
    .no_crc = "ROS 2 messages carry no CRC (the stamps are checked instead)",
};

/* ---- the registered check ---------------------------------------------------------- */

static const roz_ros2_robot_t pm01_rules = { ROZ__PM01_ROBOT_RULES };

int roz_engineai_pm01_check(const roz_manifest_t *m, roz_params_problem_fn report, void *ctx)
{
    static roz_engineai_pm01_t pm; /* host tools, one call at a time */
    return roz_ros2_check(&pm01_rules, &pm.b, &pm, m, report, ctx);
}
