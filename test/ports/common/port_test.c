/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L
#include "port_test.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "roz/error.h"

void roz_port_test_open(const roz_port_fixture_t *fx, const roz_manifest_t *m,
                        const roz_param_t *items, size_t n, roz_port_t *port)
{
    roz_params_t p = { items, n };
    char err[300] = "";
    if (fx->open(m, &p, port, err, sizeof err) != ROZ_OK)
        fail_msg("%s: open: %s", fx->name, err);
}

int roz_port_test_state(const roz_manifest_t *m, const char *name)
{
    int i = roz_manifest_find_state(m, name);
    if (i < 0)
        fail_msg("manifest %s: no state \"%s\"", m->robot_id, name);
    return i;
}

int roz_port_test_command(const roz_manifest_t *m, const char *joint, const char *suffix,
                          int must_exist)
{
    char name[160];
    snprintf(name, sizeof name, "%s/%s", joint, suffix);
    int i = roz_manifest_find_command(m, name);
    if (i < 0 && must_exist)
        fail_msg("manifest %s: no command \"%s\"", m->robot_id, name);
    return i;
}

void roz_port_test_distinct_command(const roz_manifest_t *m, int k, double *cmd)
{
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        cmd[i] = c->min +
                 (c->max - c->min) * (double)((i * 13u + (unsigned)k * 7u) % 97u + 1u) / 98.0;
    }
}

void roz_port_test_assert_state(const roz_manifest_t *m, const double *state,
                                const double *sent)
{
    for (uint16_t i = 0; i < m->n_states; i++) {
        if (memcmp(&state[i], &sent[i], sizeof sent[i]) != 0)
            fail_msg("state %u \"%s\": read %.17g, the robot sent %.17g", (unsigned)i,
                     m->states[i].name, state[i], sent[i]);
    }
}

static struct {
    const roz_manifest_t *m;
    roz_port_t           *port;
    double               *state, *cmd;
} driven;

void roz_port_test_drive(const roz_port_fixture_t *fx, const roz_manifest_t *m,
                         const roz_param_t *items, size_t n, roz_port_t *port, double *state,
                         double *cmd)
{
    roz_port_test_open(fx, m, items, n, port);
    driven.m = m;
    driven.port = port;
    driven.state = state;
    driven.cmd = cmd;
}

int roz_port_test_read(void)
{
    return roz_port_read(driven.port, driven.state, driven.m->n_states);
}

void roz_port_test_write(void)
{
    assert_int_equal(roz_port_write(driven.port, driven.cmd, driven.m->n_commands), ROZ_OK);
}

int roz_port_test_joint_command(const roz_manifest_t *m, uint16_t joint, const char *suffix)
{
    return roz_port_test_command(m, m->hardware->joints[joint], suffix, 1);
}

void roz_port_test_start(void (*send)(void), void (*settle)(void))
{
    send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_port_test_distinct_command(driven.m, 0, driven.cmd);
    roz_port_test_write();
    settle();
}

uint64_t roz_port_test_realtime_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}
