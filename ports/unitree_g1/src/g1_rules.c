/* SPDX-License-Identifier: Apache-2.0 */
/* The G1's rules of its [hardware] keys: its joints by SDK name, their
 * channels, its parameters. One implementation, run by the port's open and
 * by roz_unitree_g1_check() (what rozgen runs): no DDS here. */
#include "g1_rules.h"

#include <math.h>
#include <string.h>

#include "roz/format.h"
#include "roz/hal/joints.h"
#include "roz/hal/params.h"

#define PORT "unitree/G1"

/* The port's parameters: the rows its info shows, its known keys (in the
 * order an unknown key's error lists them), the bounds and defaults read. */
static const roz_port_param_info_t rows[] = { ROZ__G1_PARAM_ROWS };
#define ROWS rows, sizeof rows / sizeof rows[0]

/* ---- joints ---------------------------------------------------------------- */

/* The body's motors by their SDK joint names: index = motor_cmd/motor_state
 * slot (the 29-DoF order; a 23-DoF G1 has no motor at 13, 14, 20, 21, 27,
 * 28, a locked waist none at 13, 14). */
static const char *const slot_names[ROZ_UNITREE_G1_BODY] = {
    "left_hip_pitch_joint",      "left_hip_roll_joint",      "left_hip_yaw_joint",
    "left_knee_joint",           "left_ankle_pitch_joint",   "left_ankle_roll_joint",
    "right_hip_pitch_joint",     "right_hip_roll_joint",     "right_hip_yaw_joint",
    "right_knee_joint",          "right_ankle_pitch_joint",  "right_ankle_roll_joint",
    "waist_yaw_joint",           "waist_roll_joint",         "waist_pitch_joint",
    "left_shoulder_pitch_joint", "left_shoulder_roll_joint", "left_shoulder_yaw_joint",
    "left_elbow_joint",          "left_wrist_roll_joint",    "left_wrist_pitch_joint",
    "left_wrist_yaw_joint",      "right_shoulder_pitch_joint", "right_shoulder_roll_joint",
    "right_shoulder_yaw_joint",  "right_elbow_joint",        "right_wrist_roll_joint",
    "right_wrist_pitch_joint",   "right_wrist_yaw_joint",
};

int roz_unitree_g1_joint_slot(const char *name)
{
    for (int s = 0; name != NULL && s < ROZ_UNITREE_G1_BODY; s++) {
        if (strcmp(slot_names[s], name) == 0)
            return s;
    }
    return -1;
}

/* Each manifest joint's motor slot, by name; every error names the joint. */
static int place(roz_unitree_g1_t *g1, const roz_manifest_t *m, char *err, size_t errlen)
{
    const roz_hardware_t *hw = m->hardware;
    int taken[ROZ_UNITREE_G1_BODY];

    for (int s = 0; s < ROZ_UNITREE_G1_BODY; s++)
        taken[s] = -1;
    for (uint16_t k = 0; k < hw->n_joints; k++) {
        int s = roz_unitree_g1_joint_slot(hw->joints[k]);
        if (s < 0)
            return roz_joints_not_the_robots(PORT, k, hw->joints[k], "", err, errlen);
        if (taken[s] >= 0) {
            roz_format(err, errlen,
                       PORT ": [hardware] joints[%u] \"%s\" is a duplicate of joints[%d]",
                       (unsigned)k, hw->joints[k], taken[s]);
            return ROZ_ENOENT;
        }
        taken[s] = (int)k;
        g1->slot[k] = (uint8_t)s;
        g1->listed |= (uint32_t)1u << s;
    }
    return ROZ_OK;
}

int roz__g1_bind(roz_unitree_g1_t *g1, const roz_manifest_t *m, char *err, size_t errlen)
{
    const roz_hardware_t *hw = m->hardware;

    if (hw == NULL || hw->n_joints == 0 || hw->n_joints > ROZ_UNITREE_G1_BODY) {
        roz_format(err, errlen,
                   PORT ": manifest %s: [hardware] joints must list 1..%d of the robot's "
                        "joints by their SDK names, it lists %u",
                   m->robot_id, ROZ_UNITREE_G1_BODY, hw != NULL ? (unsigned)hw->n_joints : 0u);
        return ROZ_ENOENT;
    }
    for (size_t s = 0; s < ROZ_UNITREE_G1_SLOTS; s++) {
        roz_unitree_g1_joint_t *j = &g1->joint[s];
        j->q_state = j->dq_state = j->tau_state = -1;
        j->q_cmd = j->dq_cmd = j->tau_cmd = j->kp_cmd = j->kd_cmd = -1;
    }
    g1->listed = 0;
    int rc = place(g1, m, err, errlen);
    if (rc != ROZ_OK)
        return rc;
    g1->n_joints = hw->n_joints;
    return roz_joints_bind(m, PORT, "the G1", hw->joints, hw->n_joints, g1->joint, g1->imu, err,
                           errlen);
}

/* ---- parameters ------------------------------------------------------------ */

static int parse_mode_pr(const roz_params_t *p, uint8_t *out, char *err, size_t errlen)
{
    static const roz_params_word_t words[] = {
        { "PR", 0 }, { "pr", 0 }, { "0", 0 }, { "AB", 1 }, { "ab", 1 }, { "1", 1 },
    };
    int mode;
    int rc = roz_params_get_choice(p, "mode_pr", "PR", words, sizeof words / sizeof words[0],
                                   "PR (0: ankles and waist in serial pitch/roll joint space) "
                                   "or AB (1: the parallel actuators directly)",
                                   &mode, err, errlen);
    if (rc == ROZ_OK)
        *out = (uint8_t)mode;
    return rc;
}

/* What answers on rt/lowstate. unitree_mujoco never sets crc, tick or
 * mode_machine, so the CRC and the tick's link checks would drop all of it;
 * the relaxation stays on the loopback, where no robot can be
 * (docs/ports/unitree_g1.md, "In Unitree's simulator"; test_g1_sim). */
static int parse_peer(roz_unitree_g1_t *g1, const roz_params_t *p, char *err, size_t errlen)
{
    static const roz_params_word_t words[] = {
        { "robot", ROZ_UNITREE_G1_PEER_ROBOT },
        { "unitree_mujoco", ROZ_UNITREE_G1_PEER_UNITREE_MUJOCO },
    };
    int peer;
    int rc = roz_params_get_choice(p, "peer", "robot", words, 2,
                                   "robot (a G1: every check, the default) or unitree_mujoco "
                                   "(Unitree's simulator on lo: no state CRC or tick checks; "
                                   "never a robot)",
                                   &peer, err, errlen);
    if (rc == ROZ_OK)
        g1->peer = peer;
    return rc;
}

/* The simulator's relaxed checks on lo only (CYCLONEDDS_URI, the
 * environment's, is the open's to check). */
static int check_sim_network(const roz_unitree_g1_t *g1, char *err, size_t errlen)
{
    if (g1->peer == ROZ_UNITREE_G1_PEER_UNITREE_MUJOCO &&
        strcmp(g1->dds.network_interface, "lo") != 0) {
        roz_format(err, errlen,
                   "parameter peer = \"unitree_mujoco\" with network_interface = \"%s\": the "
                   "simulator's checks are off, so roz takes them only on lo (unitree_mujoco's "
                   "INTERFACE); a robot's network is refused",
                   g1->dds.network_interface);
        return ROZ_EINVAL;
    }
    return ROZ_OK;
}

int roz__g1_parse_params(roz_unitree_g1_t *g1, const roz_params_t *p, char *err,
                         size_t errlen, roz_unitree_g1_problem_fn report, void *ctx)
{
    int bad = 0, dds_ok;

/* a problem: the open's error (no report), or one report and on */
#define STEP(call) ROZ_PARAMS_STEP("g1-param", call)
    ROZ_PARAMS_STEP("unknown-key", roz_params_check_known_rows(p, ROWS, PORT, err, errlen));
    STEP(parse_peer(g1, p, err, errlen));
    dds_ok = roz_dds_params_parse(&g1->dds, p, 0, g1->m->control_rate_hz, err, errlen);
    STEP(dds_ok);
    if (dds_ok == ROZ_OK) /* the interface it names */
        STEP(check_sim_network(g1, err, errlen));
    STEP(parse_mode_pr(p, &g1->mode_pr, err, errlen));
    STEP(roz_params_get_row_u32(p, ROWS, "peer_timeout_ms", &g1->peer_timeout_ms, err, errlen));
#undef STEP
    if (roz_dds_params_damping(p, g1->m, g1->joint, g1->n_joints, &g1->startup_kd,
                               &g1->shutdown_kd, "g1-param", report, ctx, err, errlen) != ROZ_OK)
        return ROZ_EINVAL;
    return bad ? ROZ_EINVAL : ROZ_OK;
}

/* ---- the registered check ---------------------------------------------------- */

int roz_unitree_g1_check(const roz_manifest_t *m, roz_unitree_g1_problem_fn report, void *ctx)
{
    static roz_unitree_g1_t g1; /* host tools, one call at a time */
    roz_params_reporter_t to = { report, ctx };
    char err[ROZ_CFG_PROBLEM_LEN];
    roz_params_t p = roz_params_hardware(m);
    int rc;

    memset(&g1, 0, sizeof g1);
    g1.m = m;
    rc = roz__g1_bind(&g1, m, err, sizeof err);
    if (rc != ROZ_OK) {
        roz_params_report(&to, rc == ROZ_ENOENT ? "g1-joint" : "g1-channel", err);
        return ROZ_EINVAL;
    }
    return roz__g1_parse_params(&g1, &p, err, sizeof err, roz_params_report, &to);
}

/* The rule ids of the unitree/G1 port's rules, "<id>\t<what it refuses>", NULL-ended:
 * its registration's RULE_IDS (roz_manifest_json --list-rules). */
const char *const roz_unitree_g1_rule_ids[] = {
    "g1-joint\tunitree/G1 port: [hardware] joints lists none, more than the G1 has, a "
    "name that is not one of its SDK joint names, or a joint without a channel",
    "g1-channel\tunitree/G1 port: a channel that is not a listed joint's or the "
    "IMU's, or one of another type than the port serves under its name",
    "g1-param\tunitree/G1 port: a [hardware.params] value its parser refuses (a "
    "number out of range, an unknown mode_pr, a damping gain a damping channel does "
    "not allow)",
    NULL,
};
