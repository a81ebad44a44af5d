/* SPDX-License-Identifier: Apache-2.0 */
/* Private to the X2 port: what its rules need of the robot's description
 * (roz_ros2_robot_t), which its open and its registered check
 * (roz_agibot_x2_check()) use alike. No DDS, no IDL type. */
#ifndef ROZ_X2_RULES_H
#define ROZ_X2_RULES_H

#include <stddef.h>

#include "roz/port/agibot_x2.h"

/* The port's own parameters, NULL-terminated, and their reader. */
extern const char *const roz__x2_own_keys[];
int roz__x2_params(void *v, const roz_params_t *p, char *err, size_t errlen);

/* The robot's fields its rules read: the first initializers of its
 * roz_ros2_robot_t, in the port (x2_port.c) and in its check. */
#define ROZ__X2_ROBOT_RULES                                                                     \
    .port = "agibot/X2", .groups = roz_agibot_x2_groups, .n_groups = ROZ_AGIBOT_X2_GROUPS,      \
    .imu_topic = "rt/aima/hal/imu/torso/state", .default_domain = 0, .has_sequence = 1,         \
    .keys = roz__x2_own_keys, .params = roz__x2_params

#endif /* ROZ_X2_RULES_H */
