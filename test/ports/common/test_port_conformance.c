/* SPDX-License-Identifier: Apache-2.0 */
/* The port conformance suite: the same checks against every port's fixture
 * (port_fixture.h), on a small and a large manifest (UR5, G1):
 *  - parameters: an unknown key is an error naming the key and the port;
 *  - sizes: read() and write() refuse an array of the wrong length;
 *  - start-up: nothing reaches the peer before its first state frame, and
 *    read() says ROZ_ENOENT until then;
 *  - fresh and stale: a new frame reads 1 with exactly the values the peer
 *    sent, no new frame reads 0 with the previous values;
 *  - the link checks (roz/hal/link.h): a frame failing its CRC and a
 *    replayed frame read 0 and are counted; a restarted peer, and one back
 *    after a silence past the peer timeout, read ROZ_ELINK once, then their
 *    frames read 1; a restarted peer gets no command until the next write;
 *    a frame of several topics counts once per topic;
 *  - commands: the peer applies exactly what was written (as the wire
 *    carries it); a command frame corrupted in transit is dropped by the
 *    peer, which keeps the last one;
 *  - a port whose wire has no CRC (ROS 2 messages) skips the two CRC cases
 *    and says so in the output, with what it checks instead; one whose wire
 *    has no sequence number (MIT-mode CAN) skips the restart case, seen
 *    there only as a silence, and says so; one with no link at all (a
 *    simulator in the same process, its info's no_link) skips the link case;
 *  - start-up hold, for a port that keeps it: the first write to a new or
 *    restarted peer reaches it as the hold of the positions it sent, with
 *    zero gains; the next write as written;
 *  - the command watchdog, for a port that has one: the tick writes, then
 *    stops; the peer, still sending, soon applies the port's safe command
 *    (no stiffness, velocity or effort), which the port sends by itself;
 *    the next read() reports the trip once (ROZ_EWATCHDOG, which the
 *    runtime latches as ROZ_FAULT_COMMAND_TIMEOUT: test_latch.c), naming
 *    command_timeout_us, its value and a silence at least that long; the
 *    next write goes out as the start-up hold (no drive either), the one
 *    after as written;
 *  - a blocking log, for a port with threads of its own: with a log
 *    callback that blocks forever on any thread but the suite's, and every
 *    threshold of the port's monitors at 1 ns (each sample its threads
 *    record warns), the command watchdog case passes as above and twenty
 *    more commands reach the peer in order; no port thread called the log
 *    (roz/port.h drain); the warnings come out of roz_port_drain() on the
 *    suite's thread.
 * Each fixture runs on the manifests it serves (the loopback on UR5 and G1,
 * each robot's port on its robot, the socketcan port on the example CAN
 * leg). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "port_fixture.h"
#include "roz/hal/cmd_watchdog.h"
#include "roz/ports.h"
#include "support.h"
#include "support_blocking_log.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"

typedef struct {
    const roz_port_fixture_t *fx;
    const roz_port_ops_t     *ops; /* the port's, from the registry: caps, info */
    const roz_manifest_t     *m;
    roz_port_t                port;
    double                    state[ROZ_CFG_MAX_STATES];
    double                    sent[ROZ_CFG_MAX_STATES];
    double                    cmd[ROZ_CFG_MAX_COMMANDS];
} conformance_t;

/* Every registered port (roz/ports.h) with its fixture, found by name in
 * the fixture table (port_fixture.h); filled by main(). */
typedef struct {
    const roz_port_ops_t     *ops;
    const roz_port_fixture_t *fx;
} port_under_test_t;

static port_under_test_t fixtures[ROZ_PORTS_COUNT > 0 ? ROZ_PORTS_COUNT : 1];
static size_t n_fixtures;

/* What the port's caps say (roz/port.h), as the checks ask it. */
static int has(const roz_port_ops_t *ops, uint32_t cap)
{
    return (ops->caps & cap) != 0;
}

/* Without a CRC (a sequence): what the port checks (sees) instead, from its
 * info; NULL when the wire has one. */
static const char *no_crc(const roz_port_ops_t *ops)
{
    const char *why = roz_port_ops_info(ops)->no_crc;
    return has(ops, ROZ_PORT_CAP_CRC) ? NULL : why != NULL ? why : "the port has no CRC";
}

static const char *no_sequence(const roz_port_ops_t *ops)
{
    const char *why = roz_port_ops_info(ops)->no_sequence;
    return has(ops, ROZ_PORT_CAP_SEQUENCE) ? NULL
           : why != NULL                   ? why
                                           : "the port has no sequence";
}

static const roz_manifest_t *const default_manifests[] = { &roz_manifest_ur5,
                                                           &roz_manifest_unitree_g1, NULL };

static const roz_manifest_t *const *manifests_of(const roz_port_fixture_t *fx)
{
    return fx->manifests != NULL ? fx->manifests : default_manifests;
}

static void open_port_with(conformance_t *c, const port_under_test_t *pt,
                           const roz_manifest_t *m, const roz_params_t *params)
{
    const roz_port_fixture_t *fx = pt->fx;
    char err[300] = "";
    memset(c, 0, sizeof *c);
    c->fx = fx;
    c->ops = pt->ops;
    c->m = m;
    if (fx->open(m, params, &c->port, err, sizeof err) != ROZ_OK)
        fail_msg("%s on %s: open: %s", fx->name, m->robot_id, err);
}

static void open_port(conformance_t *c, const port_under_test_t *pt, const roz_manifest_t *m)
{
    open_port_with(c, pt, m, NULL);
}

/* A command inside the manifest, different for each k. */
static void command(conformance_t *c, int k)
{
    for (uint16_t i = 0; i < c->m->n_commands; i++) {
        const roz_channel_t *ch = &c->m->commands[i];
        c->cmd[i] = ch->min + (ch->max - ch->min) * (double)((k + i) % 7 + 1) / 8.0;
    }
}

static int read_port(conformance_t *c)
{
    return roz_port_read(&c->port, c->state, c->m->n_states);
}

/* The peer sends a good frame; the port reads it, fresh and exact. */
static void fresh_frame(conformance_t *c)
{
    c->fx->peer(ROZ_PEER_SEND);
    assert_int_equal(read_port(c), 1);
    c->fx->peer_sent(c->sent);
    assert_memory_equal(c->state, c->sent, c->m->n_states * sizeof c->state[0]);
}

static void write_checked(conformance_t *c, int k)
{
    command(c, k);
    assert_int_equal(roz_port_write(&c->port, c->cmd, c->m->n_commands), ROZ_OK);
}

/* @p written, as the peer should apply it: through the wire's narrowing */
static void assert_peer_applies(conformance_t *c, const double *written)
{
    double want[ROZ_CFG_MAX_COMMANDS];
    if (c->fx->wire_command != NULL)
        c->fx->wire_command(written, want);
    else
        memcpy(want, written, c->m->n_commands * sizeof want[0]);
    c->fx->settle();
    const double *got = c->fx->peer_command();
    assert_non_null(got);
    for (uint16_t i = 0; i < c->m->n_commands; i++) {
        if (memcmp(&got[i], &want[i], sizeof want[i]) != 0)
            fail_msg("%s on %s: command %u \"%s\": the peer applies %.17g, expected %.17g",
                     c->fx->name, c->m->robot_id, (unsigned)i, c->m->commands[i].name, got[i],
                     want[i]);
    }
}

static double clamp_to(const roz_channel_t *ch, double v)
{
    return v < ch->min ? ch->min : v > ch->max ? ch->max : v;
}

/* The first write to a peer that has sent its first frame (new, or
 * restarted). A port that keeps the start-up hold sends the hold of the
 * positions the peer sent (c->state, the last read), zero elsewhere; then
 * the next write goes out as written. */
static void first_write(conformance_t *c, int k)
{
    write_checked(c, k);
    if (has(c->ops, ROZ_PORT_CAP_START_HOLD)) {
        double hold[ROZ_CFG_MAX_COMMANDS];
        for (uint16_t i = 0; i < c->m->n_commands; i++) {
            const roz_channel_t *ch = &c->m->commands[i];
            hold[i] = clamp_to(ch, ch->type == ROZ_IF_POSITION &&
                                           ch->position_state != ROZ_CHANNEL_UNPAIRED
                                       ? c->state[ch->position_state]
                                       : 0.0);
        }
        assert_peer_applies(c, hold);
        write_checked(c, k);
    }
    assert_peer_applies(c, c->cmd);
}

/* ---- the checks, each on one fixture and manifest ------------------------- */

static void check_params(const roz_port_fixture_t *fx, const roz_manifest_t *m)
{
    roz_param_t item = { "no_such_key", "1" };
    roz_params_t params = { &item, 1 };
    roz_port_t port;
    char err[300] = "";
    assert_true(fx->open(m, &params, &port, err, sizeof err) < 0);
    if (strstr(err, "no_such_key") == NULL || strstr(err, fx->name) == NULL)
        fail_msg("%s: \"%s\" names neither the key nor the port", fx->name, err);
    fx->close();
}

static void check_sizes_and_start(conformance_t *c)
{
    uint16_t ns = c->m->n_states, nc = c->m->n_commands;
    assert_int_equal(roz_port_read(&c->port, c->state, (size_t)ns + 1), ROZ_EINVAL);
    assert_int_equal(roz_port_write(&c->port, c->cmd, (size_t)nc - 1), ROZ_EINVAL);
    /* before the peer's first frame: nothing to read, nothing sent */
    c->fx->peer(ROZ_PEER_SILENT);
    assert_int_equal(read_port(c), ROZ_ENOENT);
    write_checked(c, 0);
    c->fx->settle();
    assert_null(c->fx->peer_command());
    fresh_frame(c);
    first_write(c, 1);
}

static void check_fresh_and_stale(conformance_t *c)
{
    double before[ROZ_CFG_MAX_STATES];
    fresh_frame(c);
    memcpy(before, c->state, c->m->n_states * sizeof before[0]);
    c->fx->peer(ROZ_PEER_SILENT);
    assert_int_equal(read_port(c), 0);
    assert_memory_equal(c->state, before, c->m->n_states * sizeof before[0]);
    fresh_frame(c);
}

/* Samples one frame is made of: a replay, restart or return counts once
 * per topic. */
static uint64_t topics(const conformance_t *c)
{
    return c->fx->state_topics > 1 ? (uint64_t)c->fx->state_topics : 1u;
}

static roz_link_t link_now(const conformance_t *c)
{
    roz_link_t l;
    c->fx->link(&l);
    return l;
}

static void check_link(conformance_t *c)
{
    double before[ROZ_CFG_MAX_STATES];

    const char *no_link = roz_port_ops_info(c->ops)->no_link;
    if (no_link != NULL) {
        print_message("%s on %s: skipped: the link: %s\n", c->fx->name, c->m->robot_id,
                      no_link);
        return;
    }

    for (int i = 0; i < 100; i++) /* past the replay window */
        fresh_frame(c);
    write_checked(c, 2);
    memcpy(before, c->state, c->m->n_states * sizeof before[0]);

    if (no_crc(c->ops) == NULL) {
        uint64_t crc = link_now(c).crc_errors;
        c->fx->peer(ROZ_PEER_CORRUPT);
        assert_int_equal(read_port(c), 0);
        assert_int_equal(link_now(c).crc_errors, crc + 1);
        assert_memory_equal(c->state, before, c->m->n_states * sizeof before[0]);
        fresh_frame(c);
    } else {
        print_message("%s on %s: skipped: a state frame failing its CRC: %s\n", c->fx->name,
                      c->m->robot_id, no_crc(c->ops));
    }

    uint64_t replays = link_now(c).replays;
    memcpy(before, c->state, c->m->n_states * sizeof before[0]);
    c->fx->peer(ROZ_PEER_REPLAY);
    assert_int_equal(read_port(c), 0);
    assert_int_equal(link_now(c).replays, replays + topics(c));
    assert_memory_equal(c->state, before, c->m->n_states * sizeof before[0]);
    fresh_frame(c);

    /* restarted: its sequence went back beyond the window */
    if (no_sequence(c->ops) == NULL) {
        uint64_t restarts = link_now(c).restarts;
        c->fx->peer(ROZ_PEER_RESTART);
        assert_int_equal(read_port(c), ROZ_ELINK);
        assert_int_equal(link_now(c).restarts, restarts + topics(c));
        c->fx->settle();
        assert_null(c->fx->peer_command()); /* it forgot */
        fresh_frame(c);
        first_write(c, 3);
    } else {
        print_message("%s on %s: skipped: a restarted peer: %s\n", c->fx->name, c->m->robot_id,
                      no_sequence(c->ops));
    }

    /* gone past the peer timeout, then back */
    uint64_t returns = link_now(c).returns;
    c->fx->peer(ROZ_PEER_VANISH);
    assert_int_equal(read_port(c), ROZ_ELINK);
    assert_int_equal(link_now(c).returns, returns + topics(c));
    fresh_frame(c);
}

static void check_commands(conformance_t *c)
{
    double first[ROZ_CFG_MAX_COMMANDS];
    fresh_frame(c);
    first_write(c, 4);
    memcpy(first, c->cmd, c->m->n_commands * sizeof first[0]);
    fresh_frame(c);
    if (no_crc(c->ops) == NULL) {
        c->fx->corrupt_next_command();
        write_checked(c, 5);
        assert_peer_applies(c, first); /* dropped: the last good one stays */
        fresh_frame(c);
    } else {
        print_message("%s on %s: skipped: a command frame corrupted in transit: %s\n",
                      c->fx->name, c->m->robot_id, no_crc(c->ops));
    }
    write_checked(c, 6);
    assert_peer_applies(c, c->cmd);
}

/* The watchdog's timeout: long enough that the steps before the tick
 * stops, on a loaded machine, are no silence. */
#define WATCHDOG_US 500000u
#define WATCHDOG_TEXT "500000"
/* Peer frames the suite waits for the safe command at most: only a port
 * that never sends it takes them all (each is a frame period or more). */
#define WATCHDOG_FRAMES 30000

/* Whether @p cmd drives the robot: a stiffness, velocity or effort command
 * other than what the wire makes of 0 (@p zero); with @p hold (what the
 * wire makes of each stiffness channel's default, the manifest's hold
 * gain, else 0), a stiffness at its hold gain is no drive either: the
 * watchdog's hold keeps the positions last sent (SAFETY.md, section 7). */
static int drives(const conformance_t *c, const double *cmd, const double *zero,
                  const double *hold)
{
    for (uint16_t i = 0; i < c->m->n_commands; i++) {
        roz_interface_t t = c->m->commands[i].type;
        if ((t == ROZ_IF_STIFFNESS || t == ROZ_IF_VELOCITY || t == ROZ_IF_EFFORT) &&
            memcmp(&cmd[i], &zero[i], sizeof zero[i]) != 0 &&
            !(t == ROZ_IF_STIFFNESS && hold != NULL &&
              memcmp(&cmd[i], &hold[i], sizeof hold[i]) == 0))
            return 1;
    }
    return 0;
}

static void check_watchdog(conformance_t *c)
{
    double nothing[ROZ_CFG_MAX_COMMANDS] = { 0 }, zero[ROZ_CFG_MAX_COMMANDS];
    double gains[ROZ_CFG_MAX_COMMANDS] = { 0 }, hold[ROZ_CFG_MAX_COMMANDS];
    roz_port_fault_t f;

    for (uint16_t i = 0; i < c->m->n_commands; i++) {
        if (c->m->commands[i].type == ROZ_IF_STIFFNESS)
            gains[i] = c->m->commands[i].default_value;
    }
    if (c->fx->wire_command != NULL) {
        c->fx->wire_command(nothing, zero);
        c->fx->wire_command(gains, hold);
    } else {
        memcpy(zero, nothing, sizeof zero);
        memcpy(hold, gains, sizeof hold);
    }
    fresh_frame(c);
    first_write(c, 8);
    fresh_frame(c);
    write_checked(c, 9);
    assert_peer_applies(c, c->cmd);
    if (!drives(c, c->cmd, zero, hold))
        fail_msg("%s on %s: the suite's command drives nothing: no watchdog to see",
                 c->fx->name, c->m->robot_id);

    /* the tick stops writing (and reading); the peer goes on */
    int k = 0;
    for (; k < WATCHDOG_FRAMES; k++) {
        c->fx->peer(ROZ_PEER_SEND);
        c->fx->settle();
        const double *got = c->fx->peer_command();
        if (got != NULL && !drives(c, got, zero, hold))
            break;
    }
    if (k == WATCHDOG_FRAMES)
        fail_msg("%s on %s: the peer still applies a driving command after %d of its frames "
                 "with the tick silent (command_timeout_us %u)",
                 c->fx->name, c->m->robot_id, k, WATCHDOG_US);

    /* the tick is back: the trip reported once, named */
    assert_int_equal(read_port(c), ROZ_EWATCHDOG);
    assert_non_null(c->port.ops->fault);
    assert_int_equal(c->port.ops->fault(c->port.self, &f), ROZ_OK);
    assert_string_equal(f.what, ROZ_CMD_WATCHDOG_KEY);
    assert_int_equal(f.limit, WATCHDOG_US);
    assert_true(f.code >= WATCHDOG_US); /* silent at least that long */
    fresh_frame(c);
    /* the first write goes out as the stop's hold, which drives nothing
     * either (its positions are the port's: the robot may stand outside
     * the limits now) and keeps the hold gains: never a frame without
     * stiffness between the watchdog's hold and the tick's, the next as
     * written */
    write_checked(c, 10);
    c->fx->settle();
    const double *got = c->fx->peer_command();
    assert_non_null(got);
    if (drives(c, got, zero, hold))
        fail_msg("%s on %s: the first write after the trip drives the robot: no hold",
                 c->fx->name, c->m->robot_id);
    for (uint16_t i = 0; i < c->m->n_commands; i++) {
        if (c->m->commands[i].type == ROZ_IF_STIFFNESS &&
            memcmp(&got[i], &hold[i], sizeof hold[i]) != 0)
            fail_msg("%s on %s: the first write after the trip sends %s %g, not its hold gain "
                     "%g", c->fx->name, c->m->robot_id, c->m->commands[i].name, got[i], hold[i]);
    }
    write_checked(c, 11);
    assert_peer_applies(c, c->cmd);
}

/* The command watchdog's parameter: WATCHDOG_TEXT microseconds. */
static const roz_param_t watchdog_item = { "command_timeout_us", WATCHDOG_TEXT };
static const roz_params_t watchdog_params = { &watchdog_item, 1 };

/* ---- every fixture, every manifest ---------------------------------------- */

typedef void (*check_fn)(conformance_t *c);

static void each(check_fn check)
{
    static conformance_t c;
    for (size_t f = 0; f < n_fixtures; f++) {
        const roz_manifest_t *const *ms = manifests_of(fixtures[f].fx);
        for (size_t k = 0; ms[k] != NULL; k++) {
            print_message("%s on %s\n", fixtures[f].fx->name, ms[k]->robot_id);
            open_port(&c, &fixtures[f], ms[k]);
            check(&c);
            fixtures[f].fx->close();
        }
    }
}

static void test_port_conformance_params(void **st)
{
    (void)st;
    for (size_t f = 0; f < n_fixtures; f++)
        check_params(fixtures[f].fx, manifests_of(fixtures[f].fx)[0]);
}

/* A test that runs @p check on each fixture's robots. */
#define EACH_TEST(name, check) \
    static void name(void **st) \
    {                           \
        (void)st;               \
        each(check);            \
    }

EACH_TEST(test_port_conformance_start, check_sizes_and_start)
EACH_TEST(test_port_conformance_fresh_and_stale, check_fresh_and_stale)
EACH_TEST(test_port_conformance_link, check_link)
EACH_TEST(test_port_conformance_commands, check_commands)

static void test_port_conformance_watchdog(void **st)
{
    static conformance_t c;
    (void)st;
    for (size_t f = 0; f < n_fixtures; f++) {
        const roz_port_fixture_t *fx = fixtures[f].fx;
        const roz_manifest_t *const *ms = manifests_of(fx);
        if (!has(fixtures[f].ops, ROZ_PORT_CAP_WATCHDOG)) {
            print_message("%s: skipped: the command watchdog: the port has none\n", fx->name);
            continue;
        }
        for (size_t k = 0; ms[k] != NULL; k++) {
            print_message("%s on %s\n", fx->name, ms[k]->robot_id);
            open_port_with(&c, &fixtures[f], ms[k], &watchdog_params);
            check_watchdog(&c);
            fx->close();
        }
    }
}

static void check_blocking_log(conformance_t *c)
{
    c->fx->strict_monitors();
    check_watchdog(c);
    for (int i = 0; i < 20; i++) {
        fresh_frame(c);
        write_checked(c, 12 + i);
        assert_peer_applies(c, c->cmd);
    }
    assert_int_equal(roz_test_blocking_log_blocked(), 0);
    /* the warnings the port's threads kept, said on this thread */
    assert_true(roz_port_drain(&c->port) >= 1);
    assert_true(roz_test_blocking_log_saw(" took "));
}

static void test_port_conformance_blocking_log(void **st)
{
    static conformance_t c;
    (void)st;
    for (size_t f = 0; f < n_fixtures; f++) {
        const roz_port_fixture_t *fx = fixtures[f].fx;
        const roz_manifest_t *const *ms = manifests_of(fx);
        if (fx->set_log == NULL || fx->strict_monitors == NULL ||
            !has(fixtures[f].ops, ROZ_PORT_CAP_WATCHDOG)) {
            print_message("%s: skipped: a blocking log: the port has no threads of its own\n",
                          fx->name);
            continue;
        }
        for (size_t k = 0; ms[k] != NULL; k++) {
            print_message("%s on %s\n", fx->name, ms[k]->robot_id);
            roz_test_blocking_log_arm();
            fx->set_log(roz_test_blocking_log);
            open_port_with(&c, &fixtures[f], ms[k], &watchdog_params);
            check_blocking_log(&c);
            roz_test_blocking_log_release();
            fx->close();
            fx->set_log(NULL);
        }
    }
}

/* Every registered port (roz/ports.h) must have a fixture (port_fixture.h),
 * found by name: one built, or one that says why it cannot be here. A port
 * registered without one fails. */
static void test_port_conformance_registry(void **st)
{
    (void)st;
    for (size_t i = 0; i < ROZ_PORTS_COUNT; i++) {
        const roz_port_entry_t *pe = &roz_ports[i];
        const roz_port_fixture_entry_t *e = roz_port_fixtures;
        while (e->port != NULL && strcmp(e->port, pe->id) != 0)
            e++;
        if (e->port == NULL)
            fail_msg("port %s (%s) is registered but has no conformance fixture "
                     "(test/ports/common/port_fixture.h)", pe->ops->name, pe->id);
        if (e->fixture == NULL) {
            print_message("%s: skipped: its fixture is not built here: %s\n", pe->ops->name,
                          e->unavailable);
            continue;
        }
        if (strcmp(e->fixture->name, pe->ops->name) != 0)
            fail_msg("port %s: its fixture says it is %s", pe->ops->name, e->fixture->name);
        fixtures[n_fixtures].ops = pe->ops;
        fixtures[n_fixtures].fx = e->fixture;
        n_fixtures++;
    }
    assert_true(n_fixtures > 0);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_port_conformance_registry),
              cmocka_unit_test(test_port_conformance_params),
              cmocka_unit_test(test_port_conformance_start),
              cmocka_unit_test(test_port_conformance_fresh_and_stale),
              cmocka_unit_test(test_port_conformance_link),
              cmocka_unit_test(test_port_conformance_commands),
              cmocka_unit_test(test_port_conformance_watchdog),
              cmocka_unit_test(test_port_conformance_blocking_log))
