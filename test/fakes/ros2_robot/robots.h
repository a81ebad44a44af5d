/* SPDX-License-Identifier: Apache-2.0 */
/* The robots the fake ROS 2 robot can be: their joint groups (a state topic
 * and a command topic each, the joints in slot order) and IMU topic, as the
 * vendors document them. */
#ifndef FAKE_ROS2_ROBOTS_H
#define FAKE_ROS2_ROBOTS_H

#include <stdint.h>

#define FAKE_MAX_GROUPS 4
#define FAKE_MAX_SLOTS 32

typedef enum { FAKE_PM01 = 0, FAKE_X2 = 1 } fake_kind_t;

typedef struct {
    const char        *name;          /* "leg", "body" */
    const char        *state_topic;   /* DDS topic name */
    const char        *command_topic;
    const char *const *joints;
    uint16_t           n_joints;
} fake_group_t;

typedef struct {
    const char         *name;       /* "pm01", "x2" */
    fake_kind_t         kind;
    const fake_group_t *groups;
    uint16_t            n_groups;
    const char         *imu_topic;
} fake_robot_t;

/* The robot called @p name, or NULL. */
const fake_robot_t *fake_robot_find(const char *name);

#endif /* FAKE_ROS2_ROBOTS_H */
