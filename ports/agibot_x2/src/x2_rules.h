/* SPDX-License-Identifier: Apache-2.0 */
/* Private to the X2 port: what its rules need of the robot's description
 * (roz_ros2_robot_t), which its open and its registered check
 * (roz_agibot_x2_check()) use alike. No DDS, no IDL type. */
#ifndef ROZ_X2_RULES_H
#define ROZ_X2_RULES_H

#include <stddef.h>

#include "roz/port/agibot_x2.h"

/* The port's own parameter's reader. */
int roz__x2_params(void *v, const roz_params_t *p, char *err, size_t errlen);

/* What the port says of itself (its ops' info): its parameter rows, the
 * robot's known keys. */
extern const roz_port_info_t roz__x2_info;

/* The robot's fields its rules read: the first initializers of its
 * roz_ros2_robot_t, in the port (x2_port.c) and in its check. */
#define ROZ__X2_ROBOT_RULES                                                                     \
    .port = "agibot/X2", .groups = roz_agibot_x2_groups, .n_groups = ROZ_AGIBOT_X2_GROUPS,      \
    .imu_topic = "rt/aima/hal/imu/torso/state", .default_domain = 0, .has_sequence = 1,         \
    .info = &roz__x2_info, .params = roz__x2_params

#endif /* ROZ_X2_RULES_H */
