/* SPDX-License-Identifier: Apache-2.0 */
/* The port agibot/X2: the robot's description for roz::ros2 (four joint
 * groups, the torso IMU, topics, types, QoS; what its rules read of it,
 * x2_rules.c) and its conversions between aimdk_msgs messages and joint
 * values. roz/port/agibot_x2.h says what it does. */
#include "roz/port/agibot_x2.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aimdk_msgs.h"
#include "ros2_msgs.h"
#include "x2_rules.h"

typedef aimdk_msgs_msg_dds__JointStateArray_ x2_state_t;
typedef aimdk_msgs_msg_dds__JointState_ x2_joint_t;
typedef roz_x2_docs_msg_dds__JointStateArray_ x2_docs_state_t;
typedef roz_x2_docs_msg_dds__JointState_ x2_docs_joint_t;
typedef aimdk_msgs_msg_dds__JointCommandArray_ x2_cmd_t;
typedef aimdk_msgs_msg_dds__JointCommand_ x2_joint_cmd_t;
typedef sensor_msgs_msg_dds__Imu_ x2_imu_t;

#define NAME_ROOM 47 /* characters a received joint name gets without Cyclone reallocating */

_Static_assert(offsetof(x2_imu_t, header) == 0, "the bridge reads the IMU's header first");
_Static_assert(sizeof(x2_state_t) <= 8u * ROZ_ROS2_SAMPLE_WORDS, "JointStateArray_ storage");
_Static_assert(sizeof(x2_docs_state_t) <= 8u * ROZ_ROS2_SAMPLE_WORDS, "docs storage");
_Static_assert(sizeof(x2_cmd_t) <= 8u * ROZ_ROS2_SAMPLE_WORDS, "JointCommandArray_ storage");
_Static_assert(sizeof(x2_imu_t) <= 8u * ROZ_ROS2_SAMPLE_WORDS, "Imu_ storage");
_Static_assert(sizeof(x2_joint_cmd_t) == 8u * ROZ_AGIBOT_X2_CMD_WORDS, "JointCommand_ storage");
_Static_assert(offsetof(x2_state_t, header) == offsetof(x2_docs_state_t, header) &&
                   offsetof(x2_state_t, state) == offsetof(x2_docs_state_t, state),
               "both layouts share the header and the error state");

/* What rx.fault_kind names (1 + index). */
enum { K_DAMPING = 0, K_POWER_OFF, K_DISABLED, K_COMM_LOST, K_UNKNOWN, K_JOINT };
static const char *const fault_kinds[] = {
    "DomainErrorState 1, damping",
    "DomainErrorState 2, power-off",
    "DomainErrorState 3, disabled",
    "DomainErrorState 4, communication lost",
    "DomainErrorState (a value the documentation does not list)",
    "joint error_code",
};

/* ---- state -------------------------------------------------------------------------- */

/* The docs layout under the SDK's type name, without type information
 * (made in heap storage at open: its members are const). */
static const void *docs_type(roz_agibot_x2_t *x2)
{
    const dds_topic_descriptor_t *d = &roz_x2_docs_msg_dds__JointStateArray__desc;
    const struct dds_type_meta_ser none = { NULL, 0 };
    const dds_topic_descriptor_t renamed = {
        .m_size = d->m_size,
        .m_align = d->m_align,
        .m_flagset = d->m_flagset & ~DDS_TOPIC_XTYPES_METADATA,
        .m_nkeys = d->m_nkeys,
        .m_typename = aimdk_msgs_msg_dds__JointStateArray__desc.m_typename,
        .m_keys = d->m_keys,
        .m_nops = d->m_nops,
        .m_ops = d->m_ops,
        .m_meta = d->m_meta,
        .type_information = none,
        .type_mapping = none,
        .restrict_data_representation = d->restrict_data_representation,
    };
    if (x2->docs_type == NULL)
        x2->docs_type = malloc(sizeof renamed);
    if (x2->docs_type != NULL)
        memcpy(x2->docs_type, &renamed, sizeof renamed);
    return x2->docs_type;
}

static const void *x2_state_type(void *v, size_t *size)
{
    roz_agibot_x2_t *x2 = v;
    if (x2->docs_layout) {
        *size = sizeof(x2_docs_state_t);
        return docs_type(x2);
    }
    *size = sizeof(x2_state_t);
    return &aimdk_msgs_msg_dds__JointStateArray__desc;
}

static int x2_reserve(void *v, void *sample, uint16_t n_slots)
{
    roz_agibot_x2_t *x2 = v;
    x2_state_t *s = sample; /* the header and the sequence's place are the same in both */
    size_t elem = x2->docs_layout ? sizeof(x2_docs_joint_t) : sizeof(x2_joint_t);
    int rc = roz_dds_string_reserve(&s->header.frame_id, 63);
    if (rc == ROZ_OK)
        rc = roz_dds_seq_reserve(&s->joints, n_slots, elem);
    for (uint16_t i = 0; i < n_slots && rc == ROZ_OK; i++) {
        char **name = (char **)(void *)((unsigned char *)s->joints._buffer + i * elem);
        rc = roz_dds_string_reserve(name, NAME_ROOM); /* name is each element's first member */
    }
    return rc;
}

_Static_assert(offsetof(x2_joint_t, name) == 0 && offsetof(x2_docs_joint_t, name) == 0,
               "a joint's name comes first");
_Static_assert(offsetof(x2_state_t, joints) == offsetof(x2_docs_state_t, joints),
               "both layouts keep their joints in the same place");

static void x2_header(void *v, const void *sample, roz_ros2_header_t *h)
{
    const x2_state_t *s = sample;
    (void)v;
    h->sec = s->header.stamp.sec;
    h->nanosec = s->header.stamp.nanosec;
    h->sequence = s->header.sequence;
}

/* Joint @p i of a sample into rx (its velocity and effort when @p full);
 * 0, rx.bad_a = i, for a joint named otherwise than its slot. Both layouts'. */
static int take(roz_ros2_rx_t *rx, uint16_t i, int full, const char *name, const char *slot,
                double q, double dq, double tau)
{
    if (name != NULL && name[0] != '\0' && strcmp(name, slot) != 0) {
        rx->bad_a = i;
        return 0;
    }
    rx->q[i] = q;
    if (full) {
        rx->dq[i] = dq;
        rx->tau[i] = tau;
    }
    return 1;
}

static roz_ros2_bad_t x2_decode(void *v, uint16_t group, const void *sample, int full,
                                roz_ros2_rx_t *rx)
{
    roz_agibot_x2_t *x2 = v;
    const roz_ros2_group_t *g = &roz_agibot_x2_groups[group];
    const x2_state_t *s = sample;
    uint16_t n = g->n_slots;

    if (s->joints._length != n) {
        rx->bad_a = (int32_t)s->joints._length;
        rx->bad_b = n;
        return ROZ_ROS2_BAD_LENGTH;
    }
    if (x2->docs_layout) {
        const x2_docs_state_t *d = sample;
        for (uint16_t i = 0; i < n; i++) {
            const x2_docs_joint_t *j = &d->joints._buffer[i];
            if (!take(rx, i, full, j->name, g->slots[i], j->position, j->velocity, j->effort))
                return ROZ_ROS2_BAD_NAME;
        }
    } else {
        for (uint16_t i = 0; i < n; i++) {
            const x2_joint_t *j = &s->joints._buffer[i];
            if (!take(rx, i, full, j->name, g->slots[i], j->position, j->velocity, j->effort))
                return ROZ_ROS2_BAD_NAME;
            if (j->error_code != 0u && rx->fault_kind == 0) {
                rx->fault_kind = 1u + K_JOINT;
                rx->fault_slot = i;
                rx->fault_code = j->error_code;
            }
        }
    }
    /* the group's own state first: it says more than a joint's code */
    uint8_t e = s->state.value;
    if (e != 0u) {
        rx->fault_kind = 1u + (e >= 1u && e <= 4u ? (uint32_t)(e - 1u) : (uint32_t)K_UNKNOWN);
        rx->fault_slot = -1;
        rx->fault_code = e;
    }
    return ROZ_ROS2_GOOD;
}

static void x2_decode_imu(const void *sample, double *out)
{
    const x2_imu_t *s = sample;
    const double v[ROZ_IMU_VALUES] = {
        s->orientation.x,         s->orientation.y,         s->orientation.z,
        s->orientation.w,         s->angular_velocity.x,    s->angular_velocity.y,
        s->angular_velocity.z,    s->linear_acceleration.x, s->linear_acceleration.y,
        s->linear_acceleration.z,
    };
    memcpy(out, v, sizeof v);
}

/* ---- commands ------------------------------------------------------------------------ */

static void x2_encode(void *v, uint16_t group, const roz_ros2_cmd_t *c, void *sample)
{
    roz_agibot_x2_t *x2 = v;
    const roz_ros2_group_t *g = &roz_agibot_x2_groups[group];
    x2_cmd_t *out = sample;
    x2_joint_cmd_t *j = (x2_joint_cmd_t *)(void *)x2->tx[group];

    for (uint16_t i = 0; i < c->n_slots; i++) {
        /* Cyclone only reads it: the robot's name of the slot */
        j[i].name = (char *)(uintptr_t)g->slots[i];
        j[i].position = c->joint[i].q;
        j[i].velocity = c->joint[i].dq;
        j[i].effort = c->joint[i].tau;
        j[i].stiffness = c->joint[i].kp;
        j[i].damping = c->joint[i].kd;
    }
    x2->tx_frame_id[0] = '\0';
    out->header.stamp.sec = c->sec;
    out->header.stamp.nanosec = c->nanosec;
    out->header.frame_id = x2->tx_frame_id;
    out->header.sequence = c->sequence;
    out->header.meas_stamp = out->header.stamp;
    out->joints._buffer = j;
    out->joints._length = c->n_slots;
    out->joints._maximum = c->n_slots;
    out->joints._release = false;
}

/* ---- the robot ------------------------------------------------------------------------ */

static const roz_ros2_robot_t x2_robot = {
    ROZ__X2_ROBOT_RULES,
    .state_qos = &roz_dds_qos_sensor_data,
    .command_qos = &roz_dds_qos_sensor_data,
    .fault_kinds = fault_kinds,
    .state_type = x2_state_type,
    .imu_type = &sensor_msgs_msg_dds__Imu__desc,
    .imu_size = sizeof(x2_imu_t),
    .command_type = &aimdk_msgs_msg_dds__JointCommandArray__desc,
    .command_size = sizeof(x2_cmd_t),
    .reserve = x2_reserve,
    .state_header = x2_header,
    .decode = x2_decode,
    .decode_imu = x2_decode_imu,
    .encode = x2_encode,
};

static void x2_close(void *self)
{
    roz_agibot_x2_t *x2 = self;
    roz_ros2_close(&x2->b);
    free(x2->docs_type); /* after the topics that used it are gone */
    x2->docs_type = NULL;
}

static int x2_open(void *self, const roz_manifest_t *m, const roz_params_t *p, char *err,
                   size_t errlen)
{
    roz_agibot_x2_t *x2 = self;
    x2_close(x2);
    x2->docs_layout = 0;
    int rc = roz_ros2_open(&x2->b, &x2_robot, x2, m, p, err, errlen);
    if (rc != ROZ_OK) {
        free(x2->docs_type);
        x2->docs_type = NULL;
    }
    return rc;
}

const roz_port_ops_t roz_agibot_x2_ops = {
    .name = "agibot/X2",
    .open = x2_open,
    .activate = roz_ros2_activate,
    .read = roz_ros2_read,
    .write = roz_ros2_write,
    .deactivate = roz_ros2_deactivate,
    .close = x2_close,
    .fault = roz_ros2_fault,
    .drain = roz_ros2_drain,
    .set_operator = roz_ros2_set_operator,
    .caps = ROZ_PORT_CAP_SEQUENCE | ROZ_PORT_CAP_WATCHDOG | ROZ_PORT_CAP_START_HOLD |
            ROZ_PORT_CAP_ROBOT | ROZ_PORT_CAP_NEEDS_NETNS,
    .info = &roz__x2_info,
    .link_counters = roz_ros2_link_counters,
};

roz_port_t roz__agibot_x2_port(roz_agibot_x2_t *x2, const roz_port_layout_t *caller,
                               size_t bytes, roz_log_fn log, void *log_ctx)
{
    roz_port_t p = roz_ros2_port(&roz_agibot_x2_ops, &x2->b, caller, bytes, sizeof *x2, log,
                                 log_ctx);
    if (p.self != NULL)
        x2->docs_type = NULL;
    return p;
}

void roz_agibot_x2_link(const roz_agibot_x2_t *x2, roz_link_t *out)
{
    roz_ros2_link(&x2->b, out);
}
