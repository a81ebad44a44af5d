/* SPDX-License-Identifier: Apache-2.0 */
/* The socketcan port on a real CAN_RAW socket: vcan0, a virtual CAN
 * interface in a network namespace of the test's own (run_vcan.sh makes
 * it, or skips the test where the kernel offers no vcan). The port opens
 * the interface itself (network_interface = vcan0); the fake actuators sit
 * on a second CAN_RAW socket on it. Start-up, a reply's way back as state,
 * commands in the actuators' frames, shutdown. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "can_leg_manifest.h"
#include "can_test_support.h"
#include "support.h"

static roz_socketcan_t sc;
static fake_can_t bus;

static fake_actuator_t actuator(unsigned j)
{
    fake_actuator_t a;
    fake_can_view(&bus, j, &a);
    return a;
}

static uint64_t replies(void)
{
    roz_socketcan_counters_t c;
    roz_socketcan_counters(&sc, &c);
    return c.replies;
}

static void test_socketcan_vcan(void **st)
{
    const roz_manifest_t *m = &roz_manifest_can_leg;
    roz_param_t items[] = { { "network_interface", "vcan0" }, { "command_writer_period_us", "1000" } };
    roz_params_t params = { items, 2 };
    double state[ROZ_CAN_LEG_N_STATES], cmd[ROZ_CAN_LEG_N_COMMANDS];
    roz_socketcan_info_t info;
    char err[300] = "";
    (void)st;

    int fd = fake_can_open_raw("vcan0");
    assert_true(fd >= 0);
    assert_int_equal(fake_can_start(&bus, fd, roz_test_leg_actuators, 3, 0.001, 0), 0);
    roz_port_t port = roz_socketcan_port(&sc, NULL, NULL);
    if (roz_port_open(&port, m, &params, err, sizeof err) != ROZ_OK)
        fail_msg("open: %s", err);
    roz_socketcan_info(&sc, &info);
    assert_string_equal(info.network_interface, "vcan0");
    assert_int_equal(roz_port_activate(&port), ROZ_OK);

    ROZ_WAIT_FOR(roz_port_read(&port, state, m->n_states) == 1);
    for (unsigned j = 0; j < 3; j++) {
        assert_int_equal(actuator(j).before_first_reply, 0);
        assert_int_equal(actuator(j).gains_before_all, 0);
    }
    for (uint16_t i = 0; i < m->n_commands; i++)
        cmd[i] = 0.5 * (m->commands[i].min + m->commands[i].max);
    for (int k = 0; k < 50; k++) {
        assert_int_equal(roz_port_write(&port, cmd, m->n_commands), ROZ_OK);
        roz_test_can_nap();
    }
    ROZ_WAIT_FOR(actuator(2).commands > 10);
    /* the knee: turned round, offset by -1.2 rad */
    assert_true(fabs(actuator(2).cmd[FAKE_P] - -(cmd[10] + 1.2)) < 2e-4);
    uint64_t r = replies();
    ROZ_WAIT_FOR(replies() > r + 30);

    /* the exit is the leg's stop: its hold (damping), in motor mode */
    uint64_t holds[3];
    for (unsigned j = 0; j < 3; j++)
        holds[j] = actuator(j).holds;
    assert_int_equal(roz_port_deactivate(&port), ROZ_OK);
    ROZ_WAIT_FOR(actuator(0).holds > holds[0] && actuator(1).holds > holds[1] &&
                 actuator(2).holds > holds[2]);
    for (unsigned j = 0; j < 3; j++) {
        assert_int_equal(actuator(j).motor_mode, 1);
        assert_int_equal(actuator(j).exits, 0);
    }
    roz_port_close(&port);
    fake_can_stop(&bus);
    close(fd);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_socketcan_vcan))
