/* SPDX-License-Identifier: Apache-2.0 */
/* Private to the PM01 port: what its rules need of the robot's description
 * (roz_ros2_robot_t), which its open and its registered check
 * (roz_engineai_pm01_check()) use alike. No DDS, no IDL type. */
#ifndef ROZ_PM01_RULES_H
#define ROZ_PM01_RULES_H

#include <stddef.h>

#include "roz/port/engineai_pm01.h"

/* The robot's one joint group and its own parameter's reader. */
extern const roz_ros2_group_t roz__pm01_groups[1];
int roz__pm01_params(void *v, const roz_params_t *p, char *err, size_t errlen);

/* What the port says of itself (its ops' info): its parameter rows, the
 * robot's known keys. */
extern const roz_port_info_t roz__pm01_info;

/* The robot's fields its rules read: the first initializers of its
 * roz_ros2_robot_t, in the port (pm01_port.c) and in its check. */
#define ROZ__PM01_ROBOT_RULES                                                                   \
    .port = "engineai/PM01", .groups = roz__pm01_groups, .n_groups = 1,                         \
    .imu_topic = "rt/hardware/imu_info", .default_domain = ROZ_ENGINEAI_PM01_DOMAIN,            \
    .has_sequence = 0, .info = &roz__pm01_info, .params = roz__pm01_params

#endif /* ROZ_PM01_RULES_H */
