/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L
#define ROZ_PRIVATE_ACCESS /* roz_port_test_watchdog_clock(): the command path's clock */
#include "port_test.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "roz/atomic.h"
#include "roz/error.h"
#include "roz/hal/clock.h"

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

void roz_port_test_assert_fault(const char *what, const char *kind, uint32_t code)
{
    roz_port_fault_t f;
    assert_non_null(driven.port->ops->fault);
    assert_int_equal(driven.port->ops->fault(driven.port->self, &f), ROZ_OK);
    if (strcmp(f.what, what) != 0 || (kind != NULL && strstr(f.kind, kind) == NULL) ||
        f.code != code)
        fail_msg("the port's fault: %s (%s) code %lu; expected %s (%s) code %lu", f.what,
                 f.kind, (unsigned long)f.code, what, kind != NULL ? kind : "any",
                 (unsigned long)code);
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

void roz_port_test_decimation(const char *joint, void (*send)(void), void (*sent)(double *state))
{
    static double now[ROZ_CFG_MAX_STATES], full[ROZ_CFG_MAX_STATES];
    const double *state = driven.state;
    char name[160];
    snprintf(name, sizeof name, "%s/position", joint);
    int q0 = roz_port_test_state(driven.m, name);
    snprintf(name, sizeof name, "%s/velocity", joint);
    int dq0 = roz_port_test_state(driven.m, name);
    int ow = roz_port_test_state(driven.m, "base_imu/orientation.w");
    for (int k = 0; k < 12; k++) {
        send();
        assert_int_equal(roz_port_test_read(), 1);
        sent(now);
        if (k % 4 == 0)
            memcpy(full, now, sizeof full); /* converted whole */
        /* positions: every frame; the rest: the last whole conversion */
        assert_true(state[q0] == now[q0]);
        assert_true(state[dq0] == full[dq0]);
        assert_true(state[ow] == full[ow]);
        if (k % 4 != 0)
            assert_true(full[dq0] != now[dq0] || full[ow] != now[ow]);
    }
}

uint64_t roz_port_test_realtime_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

const roz_manifest_t *roz_port_test_without_fall(const roz_manifest_t *m)
{
    static roz_manifest_t no_fall;
    no_fall = *m;
    no_fall.fall = NULL;
    return &no_fall;
}

void roz_port_test_assert_imu(const roz_manifest_t *m, const double *state)
{
    static const struct { const char *name; double value; } imu[] = {
        { "base_imu/orientation.x", 0.25 },          { "base_imu/orientation.y", -0.125 },
        { "base_imu/orientation.z", 0.0625 },        { "base_imu/orientation.w", 0.5 },
        { "base_imu/angular_velocity.x", 1.5 },      { "base_imu/angular_velocity.y", -2.5 },
        { "base_imu/angular_velocity.z", 3.5 },      { "base_imu/linear_acceleration.x", 0.75 },
        { "base_imu/linear_acceleration.y", -1.25 }, { "base_imu/linear_acceleration.z", 9.75 },
    };
    for (size_t i = 0; i < sizeof imu / sizeof imu[0]; i++) {
        double got = state[roz_port_test_state(m, imu[i].name)];
        if (got != imu[i].value)
            fail_msg("%s: read %.17g, the robot sent %.17g", imu[i].name, got, imu[i].value);
    }
}

void roz_port_test_expect_refused(roz_port_t *pt, const roz_manifest_t *man, const char *key,
                                  const char *value, const char *want1, const char *want2)
{
    roz_param_t item = { key, value };
    roz_params_t p = { &item, key != NULL ? 1u : 0u };
    char err[400] = "";
    assert_true(roz_port_open(pt, man, &p, err, sizeof err) < 0);
    if (strstr(err, want1) == NULL || (want2 != NULL && strstr(err, want2) == NULL))
        fail_msg("%s = \"%s\": the error \"%s\" does not name \"%s\" and \"%s\"",
                 key != NULL ? key : "(manifest)", value != NULL ? value : "", err, want1,
                 want2 != NULL ? want2 : "");
    roz_port_close(pt);
}

/* Standing still: its time is clock_ns. Following the monotonic clock:
 * the monotonic clock's time plus follow_ns (modulo 2^64). A reader that
 * saw one mode reads that mode's word, which the switch leaves alone. */
static ROZ_ATOMIC(uint64_t) clock_ns;
static ROZ_ATOMIC(uint64_t) follow_ns;
static ROZ_ATOMIC(int) following;

uint64_t roz_port_test_clock(void *ctx)
{
    (void)ctx;
    if (atomic_load(&following))
        return roz_clock_monotonic_ns(NULL) + atomic_load(&follow_ns);
    return atomic_load(&clock_ns);
}

void roz_port_test_clock_set(uint64_t ns)
{
    atomic_store(&following, 0);
    atomic_store(&clock_ns, ns);
}

void roz_port_test_clock_add(uint64_t ns)
{
    assert_false(atomic_load(&following));
    atomic_fetch_add(&clock_ns, ns);
}

void roz_port_test_clock_follow(int on)
{
    if (on == atomic_load(&following))
        return;
    if (on) {
        atomic_store(&follow_ns, atomic_load(&clock_ns) - roz_clock_monotonic_ns(NULL));
        atomic_store(&following, 1);
    } else {
        atomic_store(&clock_ns, roz_port_test_clock(NULL));
        atomic_store(&following, 0);
    }
}

const roz_param_t roz_port_test_watched[ROZ_PORT_TEST_WATCHED_N] = {
    { "command_writer_period_us", "2000" },
    { "command_timeout_us", "100000" },
    { "peer_timeout_ms", "60000" },
};

void roz_port_test_write_held_back(roz_dds_cmd_t *path)
{
    atomic_store(&path->held_back, 1);
    roz_port_test_distinct_command(driven.m, 1, driven.cmd);
    roz_port_test_write(); /* the hold */
    roz_port_test_write(); /* the controller's, before the writer sent anything */
    atomic_store(&path->held_back, 0);
    roz_port_test_write(); /* wakes the writer */
}

void roz_port_test_watchdog_clock(roz_dds_cmd_t *path)
{
    roz_port_test_clock_set(5000000000u);
    path->clock = roz_port_test_clock;
    path->clock_ctx = NULL;
}

void roz_port_test_watchdog_trip(roz_dds_cmd_t *path, uint32_t timeout_us,
                                 uint64_t (*sent)(void))
{
    int events = path->writer->period_ns == 0;
    uint64_t safe = roz_dds_cmd_count(path, ROZ_DDS_CMD_SAFE);
    assert_int_equal(roz_dds_cmd_timeouts(path), 0);
    roz_port_test_clock_add((uint64_t)timeout_us * 1000u);
    uint64_t n = sent();
    if (events) /* nothing is due yet: a post makes the pass that judges the frame */
        roz_dds_writer_wake(path->writer);
    ROZ_PORT_TEST_WAIT_UNTIL(sent() >= n + (events ? 1u : 2u));
    if (roz_dds_cmd_timeouts(path) != 0 || roz_dds_cmd_count(path, ROZ_DDS_CMD_SAFE) != safe)
        fail_msg("the watchdog tripped after %u us of silence, no longer than its timeout",
                 (unsigned)timeout_us);
    roz_port_test_clock_add(1u);
    if (events) /* due by the clock now: the writer's own pass, no post */
        roz_dds_writer_nudge(path->writer);
    ROZ_PORT_TEST_WAIT_UNTIL(roz_dds_cmd_timeouts(path) == 1);
}

void roz_port_test_tick(roz_runtime_t *rt)
{
    int rc = roz_runtime_tick(rt);
    assert_true(rc == ROZ_OK || rc == ROZ_EFAULT);
}

void roz_port_test_robot_fault(roz_runtime_t *rt, void (*send)(void), void (*report)(int on),
                               const char *what, const char *code)
{
    for (int t = 0; t < 20; t++) {
        send();
        roz_port_test_tick(rt);
    }
    assert_int_equal(roz_runtime_faults(rt), 0);
    report(1);
    send();
    roz_port_test_tick(rt);
    assert_int_equal(roz_runtime_faults(rt), ROZ_FAULT_ROBOT);
    const char *msg = roz_runtime_fault_message(rt);
    if (strstr(msg, what) == NULL || strstr(msg, code) == NULL)
        fail_msg("the fault names not \"%s\" and \"%s\": \"%s\"", what, code, msg);
    /* a level: while the robot reports it, a clear does not take */
    assert_int_equal(roz_runtime_clear_faults(rt), ROZ_OK);
    send();
    roz_port_test_tick(rt);
    assert_int_equal(roz_runtime_faults(rt), ROZ_FAULT_ROBOT);
    report(0);
    send();
    roz_port_test_tick(rt);
    assert_int_equal(roz_runtime_clear_faults(rt), ROZ_OK);
    send();
    roz_port_test_tick(rt);
    assert_int_equal(roz_runtime_faults(rt), 0);
}
