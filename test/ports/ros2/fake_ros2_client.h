/* SPDX-License-Identifier: Apache-2.0 */
/* The ROS 2 ports' tests drive the fake robot (test/fakes/ros2_robot, a
 * separate process with its own IDL) over its stdin/stdout: one request
 * line in, one reply line out (its README.md). */
#ifndef ROZ_TEST_FAKE_ROS2_CLIENT_H
#define ROZ_TEST_FAKE_ROS2_CLIENT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/types.h>

#include "fake_process.h"

#define FAKE_ROS2_MAX_GROUPS 4
#define FAKE_ROS2_MAX_JOINTS 32
#define FAKE_ROS2_NAME_LEN 64

typedef struct roz_fake_ros2 {
    roz_fake_process_t proc; /* its pid, pipes and last reply (proc.line) */
    /* the robot, as the fake describes it ("groups", "joints G") */
    unsigned n_groups;
    char     group[FAKE_ROS2_MAX_GROUPS][16];
    unsigned n_joints[FAKE_ROS2_MAX_GROUPS];
    char     joint[FAKE_ROS2_MAX_GROUPS][FAKE_ROS2_MAX_JOINTS][FAKE_ROS2_NAME_LEN];
} roz_fake_ros2_t;

/* Starts fake_ros2 (path ROZ_FAKE_ROS2, set by the build) as @p robot
 * ("pm01", "x2") on @p domain with @p extra options (NULL-terminated, may be
 * NULL), waits for its "ready" and asks for its groups and joints. 0, or -1
 * with err said. */
int roz_fake_ros2_start(roz_fake_ros2_t *f, const char *robot, uint32_t domain,
                        const char *const *extra, char *err, size_t errlen);

/* One request; 0 when the reply is "ok ...", 1 when "err ...", -1 when the
 * fake is gone. The reply is in f->proc.line. */
int roz_fake_ros2_ask(roz_fake_ros2_t *f, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* "quit", then its exit status (-1: it did not exit cleanly). */
int roz_fake_ros2_stop(roz_fake_ros2_t *f);

/* The commands received per group (the fake's group order). 0 or -1. */
int roz_fake_ros2_commands(roz_fake_ros2_t *f, uint64_t *counts);

/* The last command on group @p g's topic. */
typedef struct roz_fake_ros2_cmd {
    uint32_t sec, nanosec;
    uint32_t seq;          /* header sequence (X2); 0 (PM01) */
    char     frame_id[FAKE_ROS2_NAME_LEN]; /* "-" when empty */
    unsigned ppt;          /* parallel_parser_type (PM01) */
    unsigned n;            /* joints: the longest array (PM01), the joints (X2) */
    unsigned min_len;      /* the shortest array (PM01); n (X2) */
    char     name[FAKE_ROS2_MAX_JOINTS][FAKE_ROS2_NAME_LEN]; /* "-" when empty */
    double   q[FAKE_ROS2_MAX_JOINTS], dq[FAKE_ROS2_MAX_JOINTS], tau[FAKE_ROS2_MAX_JOINTS];
    double   kp[FAKE_ROS2_MAX_JOINTS], kd[FAKE_ROS2_MAX_JOINTS];
    double   extra[FAKE_ROS2_MAX_JOINTS]; /* PM01: the torque array; X2: 0 */
} roz_fake_ros2_cmd_t;

/* 1 when there is one, 0 before one ("err none"), -1 on error. */
int roz_fake_ros2_command(roz_fake_ros2_t *f, unsigned g, roz_fake_ros2_cmd_t *out);

/* The fake's group called @p name, or -1. */
int roz_fake_ros2_group(const roz_fake_ros2_t *f, const char *name);

#endif /* ROZ_TEST_FAKE_ROS2_CLIENT_H */
