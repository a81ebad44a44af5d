/* SPDX-License-Identifier: Apache-2.0 */
/* QoS profiles, and their translation into Cyclone's QoS objects. */
#include "dds_internal.h"

#include <stdio.h>

const roz_dds_qos_t roz_dds_qos_ros2_default = { 1, 0, 10, 100000 };
const roz_dds_qos_t roz_dds_qos_sensor_data = { 0, 0, 5, 0 };
const roz_dds_qos_t roz_dds_qos_robot_state = { 0, 0, 1, 0 };
/* A write of KEEP_LAST 1 replaces the unacknowledged sample instead of
 * waiting for room; the bound on blocking is a second line. */
const roz_dds_qos_t roz_dds_qos_robot_command = { 1, 0, 1, 1000 };

dds_qos_t *roz__dds_qos(const roz_dds_qos_t *q)
{
    dds_qos_t *qos = dds_create_qos();
    if (qos == NULL)
        return NULL;
    dds_qset_reliability(qos, q->reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT,
                         DDS_USECS((int64_t)q->max_blocking_us));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, q->depth > 0 ? (int32_t)q->depth : 1);
    dds_qset_durability(qos, q->transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL
                                                : DDS_DURABILITY_VOLATILE);
    /* XCDR1: what ROS 2 (rmw_cyclonedds) and the robots' SDKs speak */
    dds_qset_data_representation(qos, 1, (const dds_data_representation_id_t[]){ DDS_DATA_REPRESENTATION_XCDR1 });
    return qos;
}

int roz__dds_error(dds_return_t rc)
{
    switch (rc) {
    case DDS_RETCODE_OK:
        return ROZ_OK;
    case DDS_RETCODE_BAD_PARAMETER:
        return ROZ_EINVAL;
    case DDS_RETCODE_TIMEOUT:
        return ROZ_ETIMEDOUT;
    case DDS_RETCODE_OUT_OF_RESOURCES:
        return ROZ_ENOSPC;
    case DDS_RETCODE_PRECONDITION_NOT_MET:
    case DDS_RETCODE_ILLEGAL_OPERATION:
    case DDS_RETCODE_ALREADY_DELETED:
        return ROZ_ESTATE;
    default:
        return ROZ_EIO;
    }
}

void roz__dds_say(char *err, size_t errlen, const char *topic, const char *what, dds_return_t rc)
{
    snprintf(err, errlen, "topic %s: %s: %s", topic, what, dds_strretcode(rc));
}
