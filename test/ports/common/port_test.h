/* SPDX-License-Identifier: Apache-2.0 */
/* What the hardware ports' own tests (test_unitree_g1.c,
 * test_engineai_pm01.c, test_agibot_x2.c) share beyond their fixtures:
 * opening a fixture's port, finding channels, a command with a distinct
 * value per channel, comparing a state frame with what the peer sent, the
 * cases more than one port runs (decimation, the IMU's order, a robot fault
 * in the runtime, refusals), and a clock for the command watchdog that the
 * test moves. Each fails the running cmocka test on error. */
#ifndef ROZ_TEST_PORT_TEST_H
#define ROZ_TEST_PORT_TEST_H

#include <stddef.h>
#include <stdint.h>

#include "fake_process.h"
#include "port_fixture.h"
#include "roz/manifest.h"
#include "roz/port.h"
#include "roz/port/dds.h"
#include "roz/runtime.h"
#include "support.h"

/* Until @p cond, or fail naming it after a hang guard: 60 s, far beyond
 * what a loaded machine takes (a full parallel ctest, sanitizers), so only
 * a hang fails; nothing here asserts a time. */
#define ROZ_PORT_TEST_WAIT_UNTIL(cond) ROZ_TEST_WAIT(cond, roz_fake_sleep_ms(1), 60000)

/* Opens @p fx's port on @p m with the parameters @p items (n of them). */
void roz_port_test_open(const roz_port_fixture_t *fx, const roz_manifest_t *m,
                        const roz_param_t *items, size_t n, roz_port_t *port);

/* State channel @p name's index; it must exist. */
int roz_port_test_state(const roz_manifest_t *m, const char *name);

/* Command channel "<joint>/<suffix>"'s index, or -1 when @p must_exist is 0
 * and there is none. */
int roz_port_test_command(const roz_manifest_t *m, const char *joint, const char *suffix,
                          int must_exist);

/* A command frame for @p m with a distinct value in every channel (varied
 * by @p k), each inside its limits. */
void roz_port_test_distinct_command(const roz_manifest_t *m, int k, double *cmd);

/* Every state value read is bit for bit what the peer sent. */
void roz_port_test_assert_state(const roz_manifest_t *m, const double *state,
                                const double *sent);

/* ---- the port a test drives ------------------------------------------------
 * One port at a time, bound when it opens: the test's own manifest pointer
 * value, port, state frame and command frame. */

/* roz_port_test_open(), then binds @p port, @p state and @p cmd for the
 * functions below. */
void roz_port_test_drive(const roz_port_fixture_t *fx, const roz_manifest_t *m,
                         const roz_param_t *items, size_t n, roz_port_t *port, double *state,
                         double *cmd);

/* roz_port_read() of the bound port into the bound state frame. */
int roz_port_test_read(void);

/* roz_port_write() of the bound command frame, which must succeed. */
void roz_port_test_write(void);

/* The bound port's fault (its ops' fault()), once read() reported it:
 * @p what, a kind that names @p kind (NULL: any kind) and @p code. */
void roz_port_test_assert_fault(const char *what, const char *kind, uint32_t code);

/* The command "<suffix>" of @p m's hardware joint @p joint; it must exist. */
int roz_port_test_joint_command(const roz_manifest_t *m, uint16_t joint, const char *suffix);

/* The first frame and the first write (the start-up hold) behind us: the
 * peer sends (@p send), the port reads it, writes a distinct command, and
 * the peer has it (@p settle). */
void roz_port_test_start(void (*send)(void), void (*settle)(void));

/* The system clock (CLOCK_REALTIME), ns. */
uint64_t roz_port_test_realtime_ns(void);

/* @p m without its fall rule, for a runtime over a fixture: the fixture's
 * IMU is a tilted test pattern, not a robot, and the rule would latch on
 * it (the same channels otherwise; test_mujoco_fall judges the rule).
 * Static storage: one at a time. */
const roz_manifest_t *roz_port_test_without_fall(const roz_manifest_t *m);

/* The bound port opened with state_decimation 4: 12 frames from @p send,
 * each read; @p joint's position from every frame, its velocity and the
 * IMU's orientation.w from the last whole conversion (every 4th frame),
 * against what the robot sent (@p sent). */
void roz_port_test_decimation(const char *joint, void (*send)(void), void (*sent)(double *state));

/* One tick of @p rt: ROZ_OK, or ROZ_EFAULT while a fault is latched (which
 * the test checks through roz_runtime_faults()). */
void roz_port_test_tick(roz_runtime_t *rt);

/* A fault the robot reports latches ROZ_FAULT_ROBOT in @p rt (running over
 * the bound port) and is a level: after 20 good frames (@p send, a tick
 * each), @p report(1) has the robot report it: latched at the next tick,
 * the message naming @p what and @p code; a clear does not take while the
 * robot reports it; @p report(0) ends it, and a clear then does. */
void roz_port_test_robot_fault(roz_runtime_t *rt, void (*send)(void), void (*report)(int on),
                               const char *what, const char *code);

/* Every base_imu channel of @p m in @p state is what the fake was asked to
 * send: orientation x, y, z, w 0.25, -0.125, 0.0625, 0.5; angular velocity
 * 1.5, -2.5, 3.5; linear acceleration 0.75, -1.25, 9.75. */
void roz_port_test_assert_imu(const roz_manifest_t *m, const double *state);

/* Opening @p pt on @p man with the one parameter @p key = @p value (@p key
 * NULL: none) fails, and the error names @p want1 and (unless NULL) @p want2;
 * @p pt is closed again. */
void roz_port_test_expect_refused(roz_port_t *pt, const roz_manifest_t *man, const char *key,
                                  const char *value, const char *want1, const char *want2);

/* ---- the watchdog's clock ---------------------------------------------------
 * A clock for the command path's watchdog (roz_dds_cmd_config_t clock) that
 * stands still until the test moves it: a frame is as old as the test says,
 * however slowly a loaded machine runs the writer's passes. */

/* The clock's time now, ns (@p ctx unused). */
uint64_t roz_port_test_clock(void *ctx);

/* Sets the clock to @p ns. */
void roz_port_test_clock_set(uint64_t ns);

/* Moves the clock @p ns on (standing still). */
void roz_port_test_clock_add(uint64_t ns);

/* @p on: from its time now the clock follows the monotonic clock (the
 * writer's periods in real time count); 0: it stands still again at its
 * time then. roz_port_test_clock_set() makes it stand still. */
void roz_port_test_clock_follow(int on);

/* The parameters of a DDS port whose command watchdog counts on that
 * clock: a periodic writer (every 2 ms), a 100 ms timeout, and a robot that may say nothing
 * while the tick is away (no link fault for it). */
#define ROZ_PORT_TEST_WATCHED_N 3
extern const roz_param_t roz_port_test_watched[ROZ_PORT_TEST_WATCHED_N];

/* Command 1 written three times on the bound port after its first frame:
 * the start-up hold and the controller's while the writer of @p path is
 * held back (the command path's test hook: it has sent nothing yet), the
 * third once it is let go. */
void roz_port_test_write_held_back(roz_dds_cmd_t *path);

/* The watchdog of @p path (a DDS port's command path) counts on the clock
 * above from here, set to 5 s, standing still: after the port's open,
 * before its first write; before its activation where the writer is
 * event-driven (the writer's start takes the path's clock: the G1's
 * fixture calls it there, roz_g1fx_set_before_activate()). */
void roz_port_test_watchdog_clock(roz_dds_cmd_t *path);

/* The tick went silent after its last write: on the watchdog's clock,
 * @p timeout_us of silence to the ns is not a trip (the writer's passes
 * send the frame again: two more reach the robot, by @p sent(), its count
 * of commands; an event-driven writer, to which nothing is due yet, is
 * posted one pass), and 1 ns more trips the watchdog (an event-driven
 * writer woken to look at the clock: roz_dds_writer_nudge()). */
void roz_port_test_watchdog_trip(roz_dds_cmd_t *path, uint32_t timeout_us,
                                 uint64_t (*sent)(void));

#endif /* ROZ_TEST_PORT_TEST_H */
