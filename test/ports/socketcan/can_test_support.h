/* SPDX-License-Identifier: Apache-2.0 */
/* The socketcan port's tests share this: the example leg on a socketpair
 * with fake actuators (test/fakes/can) on the other end, and bounded waits
 * (a wait that runs out fails the test; no test asserts a time). */
#ifndef ROZ_TEST_CAN_SUPPORT_H
#define ROZ_TEST_CAN_SUPPORT_H

#include <stddef.h>
#include <stdint.h>

#include "fake_can.h"
#include "roz/port/socketcan.h"
#include "support.h"

/* The leg's actuators as fake_can sees them: ids 1, 2, 3; the knee answers
 * from the host's id 0 (as the reference firmware does), the others from
 * their own (as other firmware does). */
extern const fake_actuator_cfg_t roz_test_leg_actuators[3];

typedef struct {
    roz_socketcan_t *sc;
    roz_port_t       port;
    fake_can_t      *bus;
    int              fds[2];
} roz_test_can_t;

/* Open the leg on a socketpair with the fake on the other end and
 * activate it; @p params (key, value, ..., NULL) go over robot.toml's. */
void roz_test_can_open(roz_test_can_t *t, roz_socketcan_t *sc, fake_can_t *bus,
                       const roz_manifest_t *m, const fake_actuator_cfg_t *acts, unsigned n,
                       double dt, int manual, const char *const *params);
void roz_test_can_close(roz_test_can_t *t);

/* Sleep a millisecond. */
void roz_test_can_nap(void);

/* Poll @p cond (a C expression) every millisecond for up to 10 s. */
#define ROZ_WAIT_FOR(cond) ROZ_TEST_WAIT(cond, roz_test_can_nap(), 10000)

/* With a period of 0: return once every round asked for has been sent and
 * every frame sent has reached the fake. */
void roz_test_can_settle(roz_test_can_t *t);

/* Send a round (period 0) and settle. */
void roz_test_can_round(roz_test_can_t *t);

#endif /* ROZ_TEST_CAN_SUPPORT_H */
