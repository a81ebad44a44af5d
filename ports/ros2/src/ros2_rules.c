/* SPDX-License-Identifier: Apache-2.0 */
/* A ROS 2 robot's rules of its parameters (the bridge's, the DDS ports',
 * the robot's own; ros2_map.c binds the joints and channels). One
 * implementation, run by roz_ros2_open() and by roz_ros2_check(), the
 * ports' registered check that roz_manifest_json, and so rozgen, runs: no
 * DDS here. */
#include "ros2_map.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "roz/hal/params.h"

/* ---- parameters ---------------------------------------------------------------- */

static int parse_link_check(roz_ros2_bridge_t *b, const roz_params_t *p, char *err,
                            size_t errlen)
{
    /* sequence only where the headers have one */
    static const roz_params_word_t words[] = { { "stamp", 1 }, { "sequence", 0 } };
    int seq = b->robot->has_sequence;
    return roz_params_get_choice(
        p, "link_check", seq ? "sequence" : "stamp", words, seq ? 2u : 1u,
        seq ? "sequence (the header's sequence number) or stamp (its stamp, strictly "
              "increasing) (what the state messages' headers offer the link checks)"
            : "stamp (these messages' std_msgs/Header has no sequence) (what the state "
              "messages' headers offer the link checks)",
        &b->link_by_stamp, err, errlen);
}

/* A ROS topic name: "/" then tokens of A-Z a-z 0-9 _, none starting with a
 * digit, one "/" between two (rcl's rules for a fully qualified name). */
static int ros_topic_name(const char *v)
{
    size_t len = strlen(v);
    if (len < 2 || len + 3 > ROZ_ROS2_TOPIC_NAME_MAX || v[0] != '/' || v[len - 1] == '/')
        return 0;
    for (size_t i = 1; i < len; i++) {
        char c = v[i];
        int start = v[i - 1] == '/';
        if (c == '/' ? start
                     : !((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' ||
                         (!start && c >= '0' && c <= '9')))
            return 0;
    }
    return 1;
}

int roz_ros2_joy_map_parse(const char *text, roz_ros2_joy_map_t *map, char *err, size_t errlen)
{
    return roz_joy_map_parse("parameter joy_map", text, map, err, errlen);
}

/* The operator topics: each read only when an input's source is a field of
 * its device, /joy also when the manifest has a remote_estop (the chord is
 * read whether or not an input names a button of it); their names and
 * joy_map are checked whether read or not. */
static int parse_operator(roz_ros2_bridge_t *b, const roz_params_t *p, char *err, size_t errlen)
{
    static const char *const key[2] = { "cmd_vel_topic", "joy_topic" };
    static const char *const def[2] = { "/cmd_vel", "/joy" };
    static const roz_operator_device_t dev[2] = { ROZ_OPERATOR_DEVICE_TWIST,
                                                  ROZ_OPERATOR_DEVICE_REMOTE };
    const roz_manifest_t *m = b->m;
    for (int k = 0; k < 2; k++) {
        const char *v = roz_params_get_str(p, key[k], def[k]);
        int needed = 0;
        if (!ros_topic_name(v)) {
            snprintf(err, errlen,
                     "parameter %s = \"%s\": expected a ROS topic name (\"/\" then names of "
                     "A-Z a-z 0-9 _ separated by one \"/\", none starting with a digit, at most "
                     "%d characters), such as %s",
                     key[k], v, ROZ_ROS2_TOPIC_NAME_MAX - 3, def[k]);
            return ROZ_EINVAL;
        }
        needed = dev[k] == ROZ_OPERATOR_DEVICE_REMOTE && m->remote_estop != 0u;
        for (uint16_t i = 0; m->input_rules != NULL && i < m->n_inputs; i++)
            needed |= roz_operator_field_device(m->input_rules[i].source) == dev[k];
        b->op[k].bridge = b;
        b->op[k].name[0] = '\0';
        if (needed)
            snprintf(b->op[k].name, sizeof b->op[k].name, "rt%s", v);
    }
    return roz_ros2_joy_map_parse(roz_params_get_str(p, "joy_map", ROZ_ROS2_JOY_MAP_DEFAULT),
                                  &b->joy_map, err, errlen);
}

/* The rows the ports' info shows (ROZ_ROS2_BRIDGE_PARAM_INFO): the bounds
 * and defaults read here. */
static const roz_port_param_info_t bridge_rows[] = { ROZ_ROS2_BRIDGE_PARAM_INFO };

int roz__ros2_parse_params(roz_ros2_bridge_t *b, const roz_params_t *p, char *err,
                           size_t errlen, roz_params_problem_fn report, void *ctx)
{
    const roz_ros2_robot_t *r = b->robot;
    int bad = 0;

/* a problem: the open's error (no report), or one report and on */
#define STEP(call) ROZ_PARAMS_STEP("ros2-param", call)
    ROZ_PARAMS_STEP("unknown-key", roz_params_check_known_rows(p, r->info->params,
                                                               r->info->n_params, r->port, err,
                                                               errlen));
    STEP(roz_dds_params_parse(&b->dds, p, r->default_domain, b->m->control_rate_hz, err,
                              errlen));
    STEP(roz_params_get_row_u32(p, bridge_rows, sizeof bridge_rows / sizeof bridge_rows[0],
                                "peer_timeout_ms", &b->peer_timeout_ms, err, errlen));
    STEP(parse_link_check(b, p, err, errlen));
    STEP(parse_operator(b, p, err, errlen));
    if (roz_dds_params_damping(p, b->m, b->joint, b->n_joints, &b->startup_kd, &b->shutdown_kd,
                               "ros2-param", report, ctx, err, errlen) != ROZ_OK) {
        if (report == NULL)
            return ROZ_EINVAL;
        bad = 1;
    }
    if (r->params != NULL)
        STEP(r->params(b->vendor, p, err, errlen));
#undef STEP
    return bad ? ROZ_EINVAL : ROZ_OK;
}

/* ---- the registered checks --------------------------------------------------- */

int roz_ros2_check(const roz_ros2_robot_t *robot, roz_ros2_bridge_t *b, void *vendor,
                   const roz_manifest_t *m, roz_params_problem_fn report, void *ctx)
{
    roz_params_reporter_t to = { report, ctx };
    char err[ROZ_CFG_PROBLEM_LEN];
    roz_params_t p = roz_params_hardware(m);

    memset(b, 0, sizeof *b);
    b->robot = robot;
    b->vendor = vendor;
    b->m = m;
    int rc = roz__ros2_bind(b, m, err, sizeof err);
    if (rc != ROZ_OK) {
        roz_params_report(&to, rc == ROZ_ENOENT ? "ros2-joint" : "ros2-channel", err);
        return ROZ_EINVAL;
    }
    return roz__ros2_parse_params(b, &p, err, sizeof err, roz_params_report, &to);
}

/* The rule ids of the ROS 2 ports' rules, "<id>\t<what it refuses>", NULL-ended:
 * its registration's RULE_IDS (roz_manifest_json --list-rules). */
const char *const roz_ros2_rule_ids[] = {
    "ros2-joint\tROS 2 ports (agibot/X2, engineai/PM01): [hardware] joints lists "
    "none, more than the robot has, a name that is not one of its joints, or a joint "
    "without a channel",
    "ros2-channel\tROS 2 ports: a channel that is not a listed joint's or the IMU's, "
    "or one of another type than the port serves under its name",
    "ros2-param\tROS 2 ports: a [hardware.params] value their parser refuses (a "
    "number out of range, an unknown link_check or layout, a damping gain a damping "
    "channel does not allow)",
    NULL,
};
