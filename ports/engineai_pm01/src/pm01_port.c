/* SPDX-License-Identifier: Apache-2.0 */
/* The port engineai/PM01: the robot's description for roz::ros2 (its one
 * joint group, topics, types, QoS; what its rules read of it,
 * pm01_rules.c) and its conversions between
 * interface_protocol messages and joint values. roz/port/engineai_pm01.h says
 * what it does. */
#include "roz/port/engineai_pm01.h"

#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "interface_protocol.h"
#include "pm01_rules.h"

typedef interface_protocol_msg_dds__JointState_ pm01_state_t;
typedef interface_protocol_msg_dds__JointCommand_ pm01_cmd_t;
typedef interface_protocol_msg_dds__ImuInfo_ pm01_imu_t;

#define N ROZ_ENGINEAI_PM01_JOINTS

_Static_assert(offsetof(pm01_imu_t, header) == 0, "the bridge reads the IMU's header first");
_Static_assert(sizeof(pm01_state_t) <= 8u * ROZ_ROS2_SAMPLE_WORDS, "JointState_ storage");
_Static_assert(sizeof(pm01_cmd_t) <= 8u * ROZ_ROS2_SAMPLE_WORDS, "JointCommand_ storage");
_Static_assert(sizeof(pm01_imu_t) <= 8u * ROZ_ROS2_SAMPLE_WORDS, "ImuInfo_ storage");

/* The vendor's client, both ways: KEEP_LAST 3, BEST_EFFORT, VOLATILE. */
static const roz_dds_qos_t pm01_qos = { 0, 0, 3, 0 };

/* ---- state -------------------------------------------------------------------------- */

static const void *pm01_state_type(void *v, size_t *size)
{
    (void)v;
    *size = sizeof(pm01_state_t);
    return &interface_protocol_msg_dds__JointState__desc;
}

static int pm01_reserve(void *v, void *sample, uint16_t n_slots)
{
    pm01_state_t *s = sample;
    (void)v;
    int rc = roz_dds_string_reserve(&s->header.frame_id, 63);
    if (rc == ROZ_OK)
        rc = roz_dds_seq_reserve(&s->position, n_slots, sizeof(double));
    if (rc == ROZ_OK)
        rc = roz_dds_seq_reserve(&s->velocity, n_slots, sizeof(double));
    if (rc == ROZ_OK)
        rc = roz_dds_seq_reserve(&s->torque, n_slots, sizeof(double));
    return rc;
}

static void pm01_header(void *v, const void *sample, roz_ros2_header_t *h)
{
    const pm01_state_t *s = sample;
    (void)v;
    h->sec = s->header.stamp.sec;
    h->nanosec = s->header.stamp.nanosec;
    h->sequence = 0;
}

static roz_ros2_bad_t pm01_decode(void *v, uint16_t group, const void *sample, int full,
                                  roz_ros2_rx_t *rx)
{
    const pm01_state_t *s = sample;
    const dds_sequence_double *arrays[3] = { &s->position, &s->velocity, &s->torque };
    double *out[3] = { rx->q, rx->dq, rx->tau };
    (void)v;
    (void)group;

    for (int k = 0; k < 3; k++) {
        if (arrays[k]->_length != N) {
            rx->bad_a = (int32_t)arrays[k]->_length;
            rx->bad_b = N;
            return ROZ_ROS2_BAD_LENGTH;
        }
    }
    for (int k = 0; k < (full ? 3 : 1); k++)
        memcpy(out[k], arrays[k]->_buffer, N * sizeof(double));
    return ROZ_ROS2_GOOD;
}

static void pm01_decode_imu(const void *sample, double *out)
{
    const pm01_imu_t *s = sample;
    const double v[ROZ_IMU_VALUES] = {
        s->quaternion.x,          s->quaternion.y,          s->quaternion.z,
        s->quaternion.w,          s->angular_velocity.x,    s->angular_velocity.y,
        s->angular_velocity.z,    s->linear_acceleration.x, s->linear_acceleration.y,
        s->linear_acceleration.z,
    };
    memcpy(out, v, sizeof v);
}

/* ---- commands ------------------------------------------------------------------------ */

static void point(dds_sequence_double *seq, double *values)
{
    seq->_buffer = values;
    seq->_length = N;
    seq->_maximum = N;
    seq->_release = false;
}

static void pm01_encode(void *v, uint16_t group, const roz_ros2_cmd_t *c, void *sample)
{
    roz_engineai_pm01_t *pm = v;
    pm01_cmd_t *out = sample;
    (void)group;

    for (uint16_t i = 0; i < N; i++) {
        const roz_ros2_joint_cmd_t *j = &c->joint[i];
        pm->tx[0][i] = j->q;
        pm->tx[1][i] = j->dq;
        pm->tx[2][i] = j->tau; /* feed_forward_torque */
        pm->tx[3][i] = 0.0;    /* torque */
        pm->tx[4][i] = j->kp;
        pm->tx[5][i] = j->kd;
    }
    pm->tx_frame_id[0] = '\0';
    out->header.stamp.sec = c->sec;
    out->header.stamp.nanosec = c->nanosec;
    out->header.frame_id = pm->tx_frame_id;
    point(&out->position, pm->tx[0]);
    point(&out->velocity, pm->tx[1]);
    point(&out->feed_forward_torque, pm->tx[2]);
    point(&out->torque, pm->tx[3]);
    point(&out->stiffness, pm->tx[4]);
    point(&out->damping, pm->tx[5]);
    out->parallel_parser_type = pm->parallel_parser_type;
}

/* ---- the robot ------------------------------------------------------------------------ */

static const roz_ros2_robot_t pm01_robot = {
    ROZ__PM01_ROBOT_RULES,
    .state_qos = &pm01_qos,
    .command_qos = &pm01_qos,
    .fault_kinds = NULL,
    .state_type = pm01_state_type,
    .imu_type = &interface_protocol_msg_dds__ImuInfo__desc,
    .imu_size = sizeof(pm01_imu_t),
    .command_type = &interface_protocol_msg_dds__JointCommand__desc,
    .command_size = sizeof(pm01_cmd_t),
    .reserve = pm01_reserve,
    .state_header = pm01_header,
    .decode = pm01_decode,
    .decode_imu = pm01_decode_imu,
    .encode = pm01_encode,
};

static int pm01_open(void *self, const roz_manifest_t *m, const roz_params_t *p, char *err,
                     size_t errlen)
{
    roz_engineai_pm01_t *pm = self;
    pm->parallel_parser_type = 1;
    return roz_ros2_open(&pm->b, &pm01_robot, pm, m, p, err, errlen);
}

const roz_port_ops_t roz_engineai_pm01_ops = {
    .name = "engineai/PM01",
    .open = pm01_open,
    .activate = roz_ros2_activate,
    .read = roz_ros2_read,
    .write = roz_ros2_write,
    .deactivate = roz_ros2_deactivate,
    .close = roz_ros2_close,
    .fault = roz_ros2_fault,
    .drain = roz_ros2_drain,
    .set_operator = roz_ros2_set_operator,
    .caps = ROZ_PORT_CAP_SEQUENCE | ROZ_PORT_CAP_WATCHDOG | ROZ_PORT_CAP_START_HOLD |
            ROZ_PORT_CAP_ROBOT | ROZ_PORT_CAP_NEEDS_NETNS,
    .info = &roz__pm01_info,
    .link_counters = roz_ros2_link_counters,
};

roz_port_t roz__engineai_pm01_port(roz_engineai_pm01_t *pm, const roz_port_layout_t *caller,
                                   size_t bytes, roz_log_fn log, void *log_ctx)
{
    return roz_ros2_port(&roz_engineai_pm01_ops, &pm->b, caller, bytes, sizeof *pm, log,
                         log_ctx);
}

void roz_engineai_pm01_link(const roz_engineai_pm01_t *pm, roz_link_t *out)
{
    roz_ros2_link(&pm->b, out);
}
