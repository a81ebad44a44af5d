/* SPDX-License-Identifier: Apache-2.0 */
/* The G1 fixture's helpers, for the G1 tests beyond the conformance suite
 * (test_unitree_g1.c): the port and the fake it opened, and the steps the
 * fixture is made of. Call roz_fixture_unitree_g1.open() first. */
#ifndef ROZ_TEST_UNITREE_G1_FIXTURE_H
#define ROZ_TEST_UNITREE_G1_FIXTURE_H

#include <stdint.h>

#include "fake_g1_client.h"
#include "roz/hal/link.h"
#include "roz/port/unitree_g1.h"

roz_unitree_g1_t *roz_g1fx_port(void);
/* The motor slot of G1 joint @p joint (the SDK's name); fails the test for
 * a name the G1 does not have. */
int roz_g1fx_slot(const char *joint);
roz_fake_g1_t *roz_g1fx_fake(void);
/* Options for the fake of the next open only (NULL-terminated), such as
 * --period-us for a robot that publishes by itself. */
void roz_g1fx_set_fake_args(const char *const *extra);
/* Called by the next open only, between the port's open and its activate
 * (a runtime set up and given as the port's operator sink before the
 * port's receive path runs); NULL: nothing. */
void roz_g1fx_set_before_activate(void (*fn)(const roz_port_t *port));
/* One request to the fake; anything but "ok" fails the test. */
void roz_g1fx_ask(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* The fake's motors and IMU for frame k (distinct per joint and frame). */
void roz_g1fx_set_state(uint32_t k);
/* The states the port should deliver for the last roz_g1fx_set_state(). */
void roz_g1fx_sent(double *state);
/* A good frame with new values; returns once the port took it. */
void roz_g1fx_send(void);
/* Waits until the port judged a frame since @p before. */
void roz_g1fx_wait_judged(const roz_link_t *before, int resend_until_first);
/* Returns once the port's writer took every write and the fake counted
 * every sample published. */
void roz_g1fx_settle(void);

#endif /* ROZ_TEST_UNITREE_G1_FIXTURE_H */
