/* SPDX-License-Identifier: Apache-2.0 */
/* What the hardware ports' own tests (test_unitree_g1.c,
 * test_engineai_pm01.c, test_agibot_x2.c) share beyond their fixtures:
 * opening a fixture's port, finding channels, a command with a distinct
 * value per channel, and comparing a state frame with what the peer sent.
 * Each fails the running cmocka test on error. */
#ifndef ROZ_TEST_PORT_TEST_H
#define ROZ_TEST_PORT_TEST_H

#include <stddef.h>
#include <stdint.h>

#include "port_fixture.h"
#include "roz/manifest.h"
#include "roz/port.h"

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

/* The command "<suffix>" of @p m's hardware joint @p joint; it must exist. */
int roz_port_test_joint_command(const roz_manifest_t *m, uint16_t joint, const char *suffix);

/* The first frame and the first write (the start-up hold) behind us: the
 * peer sends (@p send), the port reads it, writes a distinct command, and
 * the peer has it (@p settle). */
void roz_port_test_start(void (*send)(void), void (*settle)(void));

/* The system clock (CLOCK_REALTIME), ns. */
uint64_t roz_port_test_realtime_ns(void);

#endif /* ROZ_TEST_PORT_TEST_H */
