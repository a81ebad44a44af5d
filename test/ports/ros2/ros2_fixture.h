/* SPDX-License-Identifier: Apache-2.0 */
/* The ROS 2 ports' fixture helpers (fixture_ros2.c), for their tests beyond
 * the conformance suite: the port and fake of the fixture opened last (open
 * roz_fixture_engineai_pm01 or roz_fixture_agibot_x2 first), and the steps
 * the fixture is made of. */
#ifndef ROZ_TEST_ROS2_FIXTURE_H
#define ROZ_TEST_ROS2_FIXTURE_H

#include <stdint.h>

#include "fake_ros2_client.h"
#include "roz/hal/link.h"
#include "roz/port/ros2.h"

roz_ros2_bridge_t *roz_ros2fx_bridge(void);
roz_fake_ros2_t *roz_ros2fx_fake(void);
/* Options for the fake of the next open only (NULL-terminated), such as
 * --period-us for a robot that publishes by itself. */
void roz_ros2fx_set_fake_args(const char *const *extra);
/* One request to the fake; anything but "ok" fails the test. */
void roz_ros2fx_ask(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Manifest joint @p j's group (the fake's index) and slot; -1 when the
 * robot has no such joint. */
int roz_ros2fx_place(uint16_t j, int *group, int *slot);
/* The fake's joints and IMU for frame k (distinct per joint and frame,
 * inside each channel's limits). */
void roz_ros2fx_set_state(uint32_t k);
/* The states the port should deliver for the last roz_ros2fx_set_state(). */
void roz_ros2fx_sent(double *state);
/* The port's link checks, per state topic (unread topics zero). */
void roz_ros2fx_links(roz_link_t *out /* [ROZ_ROS2_MAX_TOPICS] */);
/* Waits until every state topic in @p mask (port topic indices; 0: every
 * topic the port reads) judged a sample since @p before; with @p resend,
 * the last frame's values go out again as a new frame every 500 ms until
 * they have (a sample lost before discovery completed). */
void roz_ros2fx_wait_judged(const roz_link_t *before, uint32_t mask, int resend);
/* One request to the fake ("send leg imu", "replay"), then waits until
 * every state topic in @p mask (0: every topic the port reads) judged a
 * sample. */
void roz_ros2fx_ask_judged(uint32_t mask, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* Waits until state topic @p topic counted one malformed sample more than
 * @p before (a hang guard of 10 s), and fails unless it did. */
void roz_ros2fx_wait_malformed(int topic, uint64_t before);
/* The commands the fake counted on its first group. */
uint64_t roz_ros2fx_commands(void);
/* The port's counters. */
roz_ros2_counters_t roz_ros2fx_counters(void);
/* A good frame with new values on every topic; returns once the port took it. */
void roz_ros2fx_send(void);
/* Returns once the port's writer took every write and the fake counted
 * every sample published, on every group the port drives. */
void roz_ros2fx_settle(void);
/* The command the fake applies, mapped back to manifest channels (NaN where
 * it has none); 0 before it has one from every group. */
int roz_ros2fx_applied(double *cmd);

#endif /* ROZ_TEST_ROS2_FIXTURE_H */
