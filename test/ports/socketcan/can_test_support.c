/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L
#include "can_test_support.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#define LEG_RANGES(tmax)                                                                        \
    { { -12.5, 12.5 }, { -45.0, 45.0 }, { 0.0, 500.0 }, { 0.0, 5.0 }, { -(tmax), (tmax) } }

const fake_actuator_cfg_t roz_test_leg_actuators[3] = {
    { 1, 1, FAKE_TEMP_ERROR, LEG_RANGES(18.0) },
    { 2, 2, FAKE_TEMP_ERROR, LEG_RANGES(18.0) },
    { 3, 0, FAKE_TEMP_ERROR, LEG_RANGES(24.0) },
};

void roz_test_can_nap(void)
{
    struct timespec ts = { 0, 1000000 };
    nanosleep(&ts, NULL);
}

void roz_test_can_open(roz_test_can_t *t, roz_socketcan_t *sc, fake_can_t *bus,
                       const roz_manifest_t *m, const fake_actuator_cfg_t *acts, unsigned n,
                       double dt, int manual, const char *const *params)
{
    roz_param_t items[16];
    size_t k = 0;
    char err[300] = "";

    memset(t, 0, sizeof *t);
    t->sc = sc;
    t->bus = bus;
    assert_int_equal(socketpair(AF_UNIX, SOCK_SEQPACKET, 0, t->fds), 0);
    assert_int_equal(fake_can_start(bus, t->fds[1], acts, n, dt, manual), 0);
    for (; params != NULL && params[2 * k] != NULL && k < 16; k++)
        items[k] = (roz_param_t){ params[2 * k], params[2 * k + 1] };
    roz_params_t p = { items, k };
    t->port = roz_socketcan_port(sc, NULL, NULL);
    roz_socketcan_set_fd(sc, t->fds[0]);
    if (roz_port_open(&t->port, m, &p, err, sizeof err) != ROZ_OK)
        fail_msg("open: %s", err);
    assert_int_equal(roz_port_activate(&t->port), ROZ_OK);
}

void roz_test_can_close(roz_test_can_t *t)
{
    (void)roz_port_deactivate(&t->port);
    roz_port_close(&t->port);
    fake_can_stop(t->bus);
    close(t->fds[0]);
    close(t->fds[1]);
    t->sc = NULL;
}

void roz_test_can_settle(roz_test_can_t *t)
{
    roz_socketcan_counters_t c;
    for (int i = 0;; i++) {
        roz_socketcan_counters(t->sc, &c);
        if (c.wakes_served == c.wakes && fake_can_received(t->bus) >= c.frames_sent)
            return;
        if (i > 10000)
            fail_msg("settle: %llu of %llu rounds served, %llu of %llu frames arrived",
                     (unsigned long long)c.wakes_served, (unsigned long long)c.wakes,
                     (unsigned long long)fake_can_received(t->bus),
                     (unsigned long long)c.frames_sent);
        roz_test_can_nap();
    }
}

void roz_test_can_round(roz_test_can_t *t)
{
    roz_socketcan_send_round(t->sc);
    roz_test_can_settle(t);
}
