/* SPDX-License-Identifier: Apache-2.0 */
/* The ROS 2 ports' conformance fixtures (engineai/PM01, agibot/X2): the
 * port in this process, its peer the fake robot fake_ros2 (test/fakes/
 * ros2_robot: a separate process with its own IDL and its own description
 * of the robot), driven over its stdin/stdout, over loopback DDS.
 *
 * Where a manifest joint is on the robot comes from the fake ("groups",
 * "joints G"), by name, as the port finds it among the robot's. The port's
 * threads make each call synchronous (port_fixture.h): peer() returns once
 * every state topic the port reads judged its sample (its link counters
 * moved); settle() once the port's writer took every frame written and the
 * fake counted every sample published on every group. The writer is event
 * driven (command_writer_period_us = 0): one sample per write and group.
 * The wire carries float64: what the port delivers is exactly what the
 * fixture asked for, and the reverse. ROS 2 messages carry no CRC: the
 * suite's CRC cases do not apply (no_crc). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "fake_ros2_client.h"
#include "dds_fixture_params.h"
#include "port_fixture.h"
#include "ros2_fixture.h"
#include "roz/port/engineai_pm01.h"
#include "engineai_pm01_manifest.h"
#ifdef ROZ_TEST_HAVE_AGIBOT_X2
#include "agibot_x2_manifest.h"
#include "roz/port/agibot_x2.h"
#endif

#ifndef ROZ_TEST_DDS_DOMAIN
#error "ROZ_TEST_DDS_DOMAIN: a domain id of this test's own"
#endif

#define WAIT_MS 10000u

static const char *const imu_names[ROZ_IMU_VALUES] = {
    "base_imu/orientation.x",         "base_imu/orientation.y",
    "base_imu/orientation.z",         "base_imu/orientation.w",
    "base_imu/angular_velocity.x",    "base_imu/angular_velocity.y",
    "base_imu/angular_velocity.z",    "base_imu/linear_acceleration.x",
    "base_imu/linear_acceleration.y", "base_imu/linear_acceleration.z",
};

/* ---- the robots ------------------------------------------------------------------- */

typedef struct {
    const char *fake_robot; /* fake_ros2 --robot */
    roz_port_t (*make)(roz_log_fn log);
    roz_ros2_bridge_t *bridge;
} robot_t;

static void quiet_log(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    if (level == ROZ_LOG_ERROR)
        fprintf(stderr, "port: %s\n", msg);
}

static roz_log_fn fx_log;

static void fx_set_log(roz_log_fn log)
{
    fx_log = log;
}

static roz_engineai_pm01_t pm01;

static roz_port_t make_pm01(roz_log_fn log)
{
    return roz_engineai_pm01_port(&pm01, log, NULL);
}

static const robot_t robot_pm01 = { "pm01", make_pm01, &pm01.b };

#ifdef ROZ_TEST_HAVE_AGIBOT_X2
static roz_agibot_x2_t x2;

static roz_port_t make_x2(roz_log_fn log)
{
    return roz_agibot_x2_port(&x2, log, NULL);
}

static const robot_t robot_x2 = { "x2", make_x2, &x2.b };
#endif

/* ---- the fixture's state -------------------------------------------------------------- */

static const robot_t *robot;
static roz_port_t the_port;
static int port_open;
static roz_fake_ros2_t fake;
static const roz_manifest_t *man;
static double sent[ROZ_CFG_MAX_STATES];
static double applied[ROZ_CFG_MAX_COMMANDS];
static int place_group[ROZ_CFG_MAX_JOINTS], place_slot[ROZ_CFG_MAX_JOINTS];
static int drives[FAKE_ROS2_MAX_GROUPS]; /* groups with a joint of the manifest */
static uint32_t frame_no;
static int restarted;                           /* peer_command() discounts ... */
static uint64_t got_at_restart[FAKE_ROS2_MAX_GROUPS]; /* ... the commands counted then */
static uint32_t peer_timeout_ms;
static const char *const *fake_args;

roz_ros2_bridge_t *roz_ros2fx_bridge(void)
{
    return robot->bridge;
}

roz_fake_ros2_t *roz_ros2fx_fake(void)
{
    return &fake;
}

void roz_ros2fx_set_fake_args(const char *const *extra)
{
    fake_args = extra;
}

void roz_ros2fx_ask(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    roz_fake_process_vmust(&fake.proc, "fake_ros2", fmt, ap);
    va_end(ap);
}

int roz_ros2fx_place(uint16_t j, int *group, int *slot)
{
    *group = place_group[j];
    *slot = place_slot[j];
    return *group >= 0 ? 0 : -1;
}

static void place_joints(void)
{
    const roz_hardware_t *hw = man->hardware;
    memset(drives, 0, sizeof drives);
    for (uint16_t j = 0; j < hw->n_joints; j++) {
        place_group[j] = place_slot[j] = -1;
        for (unsigned g = 0; g < fake.n_groups && place_group[j] < 0; g++) {
            for (unsigned s = 0; s < fake.n_joints[g]; s++) {
                if (strcmp(fake.joint[g][s], hw->joints[j]) == 0) {
                    place_group[j] = (int)g;
                    place_slot[j] = (int)s;
                    break;
                }
            }
        }
        if (place_group[j] >= 0)
            drives[place_group[j]] = 1;
    }
}

static int state_index(uint16_t j, const char *suffix)
{
    char name[160];
    snprintf(name, sizeof name, "%s/%s", man->hardware->joints[j], suffix);
    return roz_manifest_find_state(man, name);
}

void roz_ros2fx_set_state(uint32_t k)
{
    const roz_hardware_t *hw = man->hardware;
    for (uint16_t j = 0; j < hw->n_joints; j++) {
        if (place_group[j] < 0)
            continue;
        int qi = state_index(j, "position"), dqi = state_index(j, "velocity"),
            ti = state_index(j, "effort");
        double lo = qi >= 0 ? man->states[qi].min : -1.0, hi = qi >= 0 ? man->states[qi].max : 1.0;
        double q = lo + (hi - lo) * (double)((k * 7u + j * 3u) % 17u + 1u) / 19.0;
        double dq = ((int)((k + j) % 11u) - 5) * 0.5 + j * 0.001;
        double tau = ((int)((k * 3u + j) % 13u) - 6) * 0.25 + j * 0.01;
        roz_ros2fx_ask("joint %s %d %.17g %.17g %.17g", fake.group[place_group[j]],
                       place_slot[j], q, dq, tau);
        if (qi >= 0)
            sent[qi] = q;
        if (dqi >= 0)
            sent[dqi] = dq;
        if (ti >= 0)
            sent[ti] = tau;
    }
    const double v[ROZ_IMU_VALUES] = {
        -0.25 + 0.002 * (k % 50u), 0.125, -0.0625 - 0.001 * (k % 30u), 0.5 + 0.001 * (k % 100u),
        0.01 * (k % 7u),           -0.02, 0.03,
        0.1,                       -0.2 * (k % 3u), 9.81,
    };
    roz_ros2fx_ask("imu %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g", v[0], v[1],
                   v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9]);
    for (int i = 0; i < ROZ_IMU_VALUES; i++) {
        int s = roz_manifest_find_state(man, imu_names[i]);
        if (s >= 0)
            sent[s] = v[i];
    }
}

void roz_ros2fx_sent(double *state)
{
    memcpy(state, sent, man->n_states * sizeof state[0]);
}

void roz_ros2fx_links(roz_link_t *out)
{
    for (uint16_t t = 0; t < ROZ_ROS2_MAX_TOPICS; t++)
        (void)roz_ros2_topic_link(robot->bridge, t, &out[t]);
}

static int link_moved(const roz_link_t *before, const roz_link_t *now)
{
    return now->accepted != before->accepted || now->crc_errors != before->crc_errors ||
           now->replays != before->replays;
}

void roz_ros2fx_wait_judged(const roz_link_t *before, uint32_t mask, int resend)
{
    roz_link_t now[ROZ_ROS2_MAX_TOPICS];
    for (unsigned ms = 0; ms < WAIT_MS; ms++) {
        int all = 1;
        for (uint16_t t = 0; t < ROZ_ROS2_MAX_TOPICS; t++) {
            if (roz_ros2_topic_link(robot->bridge, t, &now[t]) != ROZ_OK)
                continue; /* a topic the port does not read */
            if (mask != 0 && !(mask & (1u << t)))
                continue;
            all &= link_moved(&before[t], &now[t]);
        }
        if (all)
            return;
        /* The fake's writers may not have found the port's readers yet
         * (discovery is asynchronous: before the port's first frame, and
         * again for a restarted robot's new writers), and the robots'
         * state topics are BEST_EFFORT: the frame again every 500 ms until
         * every topic has one. */
        if (resend && ms % 500u == 499u) {
            roz_ros2fx_set_state(frame_no);
            roz_ros2fx_ask("send");
        }
        roz_fake_sleep_ms(1);
    }
    char which[128] = "";
    size_t used = 0;
    for (uint16_t t = 0; t < ROZ_ROS2_MAX_TOPICS && used < sizeof which; t++) {
        if (roz_ros2_topic_link(robot->bridge, t, &now[t]) == ROZ_OK &&
            (mask == 0 || (mask & (1u << t))) && !link_moved(&before[t], &now[t]))
            used += (size_t)snprintf(which + used, sizeof which - used, " %u", (unsigned)t);
    }
    fail_msg("%s: the port did not judge the fake's samples within %u ms (topics%s)",
             man->robot_id, WAIT_MS, which);
}

void roz_ros2fx_ask_judged(uint32_t mask, const char *fmt, ...)
{
    char req[1024];
    roz_link_t before[ROZ_ROS2_MAX_TOPICS];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(req, sizeof req, fmt, ap);
    va_end(ap);
    roz_ros2fx_links(before);
    roz_ros2fx_ask("%s", req);
    roz_ros2fx_wait_judged(before, mask, 0);
}

void roz_ros2fx_wait_malformed(int topic, uint64_t before)
{
    for (int w = 0; w < 10000 && roz_ros2fx_counters().topic[topic].malformed == before; w++)
        roz_fake_sleep_ms(1);
    assert_int_equal(roz_ros2fx_counters().topic[topic].malformed, before + 1);
}

uint64_t roz_ros2fx_commands(void)
{
    uint64_t n[FAKE_ROS2_MAX_GROUPS];
    assert_int_equal(roz_fake_ros2_commands(&fake, n), 0);
    return n[0];
}

roz_ros2_counters_t roz_ros2fx_counters(void)
{
    roz_ros2_counters_t c;
    roz_ros2_counters(robot->bridge, &c);
    return c;
}

void roz_ros2fx_send(void)
{
    roz_link_t before[ROZ_ROS2_MAX_TOPICS];
    roz_ros2fx_links(before);
    roz_ros2fx_set_state(++frame_no);
    roz_ros2fx_ask("send");
    roz_ros2fx_wait_judged(before, 0, 1);
}

void roz_ros2fx_settle(void)
{
    roz_ros2_counters_t c;
    uint64_t got[FAKE_ROS2_MAX_GROUPS];
    unsigned ms = 0;

    for (;; ms++) {
        roz_ros2_counters(robot->bridge, &c);
        if (c.handled_seq == c.written_seq && c.writer_passes == c.writer_done)
            break;
        if (ms >= WAIT_MS)
            fail_msg("%s: the writer did not take command %llu within %u ms", man->robot_id,
                     (unsigned long long)c.written_seq, WAIT_MS);
        roz_fake_sleep_ms(1);
    }
    for (;; ms++) {
        if (roz_fake_ros2_commands(&fake, got) != 0)
            fail_msg("fake_ros2: commands: \"%s\"", fake.proc.line);
        int all = 1;
        for (unsigned g = 0; g < fake.n_groups; g++)
            all &= !drives[g] || got[g] >= c.published;
        if (all)
            return;
        if (ms >= WAIT_MS)
            fail_msg("%s: the fake did not count the %llu commands published within %u ms",
                     man->robot_id, (unsigned long long)c.published, WAIT_MS);
        roz_fake_sleep_ms(1);
    }
}

int roz_ros2fx_applied(double *cmd)
{
    static roz_fake_ros2_cmd_t c;
    static const char *const suffix[5] = { "position", "velocity", "effort", "stiffness",
                                           "damping" };
    for (uint16_t i = 0; i < man->n_commands; i++)
        cmd[i] = NAN; /* a command the fake has no value for stays NaN: a failure */
    for (unsigned g = 0; g < fake.n_groups; g++) {
        if (!drives[g])
            continue;
        int rc = roz_fake_ros2_command(&fake, g, &c);
        if (rc < 0)
            fail_msg("fake_ros2: command %s: \"%s\"", fake.group[g], fake.proc.line);
        if (rc == 0)
            return 0;
        for (uint16_t j = 0; j < man->hardware->n_joints; j++) {
            if (place_group[j] != (int)g || place_slot[j] >= (int)c.n)
                continue;
            int s = place_slot[j];
            const double v[5] = { c.q[s], c.dq[s], c.tau[s], c.kp[s], c.kd[s] };
            for (int k = 0; k < 5; k++) {
                char name[160];
                snprintf(name, sizeof name, "%s/%s", man->hardware->joints[j], suffix[k]);
                int i = roz_manifest_find_command(man, name);
                if (i >= 0)
                    cmd[i] = v[k];
            }
        }
    }
    return 1;
}

/* ---- the fixture ------------------------------------------------------------------------ */

static void fx_close(void);

/* Whether the fake matched the port on every topic the port uses: each
 * driven group's command reader and state writer, the IMU's writer when the
 * port reads it. */
static int fake_matched(void)
{
    unsigned v[2 * FAKE_ROS2_MAX_GROUPS + 1];
    char *p, *end;
    roz_link_t l;
    if (roz_fake_ros2_ask(&fake, "matched") != 0)
        fail_msg("fake_ros2: matched: \"%s\"", fake.proc.line);
    p = fake.proc.line + 2;
    for (unsigned i = 0; i < 2 * fake.n_groups + 1; i++) {
        v[i] = (unsigned)strtoul(p, &end, 10);
        if (end == p)
            fail_msg("fake_ros2: matched: \"%s\"", fake.proc.line);
        p = end;
    }
    for (unsigned g = 0; g < fake.n_groups; g++) {
        if (drives[g] && (v[2 * g] < 1 || v[2 * g + 1] < 1))
            return 0;
    }
    int imu = roz_ros2_topic_link(robot->bridge, roz_ros2_robot(robot->bridge)->n_groups, &l) == ROZ_OK;
    return !imu || v[2 * fake.n_groups] >= 1;
}

static int fx_open_robot(const robot_t *r, const roz_manifest_t *m, const roz_params_t *params,
                         roz_port_t *port, char *err, size_t errlen)
{
    static roz_param_t items[ROZ_ROS2_MAX_PARAMS];

    /* a check that failed half-way left its port and fake behind */
    if (port_open || fake.proc.pid != 0)
        fx_close();
    robot = r;
    man = m;
    frame_no = 0;
    restarted = 0;
    memset(sent, 0, sizeof sent);
    const char *const *extra = fake_args;
    fake_args = NULL;
    if (roz_fake_ros2_start(&fake, r->fake_robot, ROZ_TEST_DDS_DOMAIN, extra, err, errlen) != 0)
        return ROZ_EIO;
    place_joints();
    /* the fixture's parameters first: the caller's win */
    roz_params_t all =
        roz_dds_fixture_params(items, ROZ_ROS2_MAX_PARAMS, params, &peer_timeout_ms);
    the_port = r->make(fx_log != NULL ? fx_log : quiet_log);
    int rc = roz_port_open(&the_port, m, &all, err, errlen);
    if (rc == ROZ_OK)
        port_open = 1;
    if (rc == ROZ_OK)
        rc = roz_port_activate(&the_port);
    if (rc != ROZ_OK)
        return rc;
    *port = the_port;
    /* both directions matched, seen from both sides, before anyone speaks
     * (discovery is asynchronous: a side that has not matched the other's
     * writer yet drops what it sends, and both robots' topics are
     * BEST_EFFORT somewhere) */
    for (unsigned ms = 0;; ms++) {
        uint32_t readers, writers;
        roz_ros2_matched(r->bridge, &readers, &writers);
        if (readers >= 1 && writers >= 1 && fake_matched())
            break;
        if (ms >= WAIT_MS) {
            snprintf(err, errlen, "%s and fake_ros2 did not discover each other in %u ms",
                     m->robot_id, WAIT_MS);
            return ROZ_ETIMEDOUT;
        }
        roz_fake_sleep_ms(1);
    }
    return ROZ_OK;
}

static int fx_open_pm01(const roz_manifest_t *m, const roz_params_t *params, roz_port_t *port,
                        char *err, size_t errlen)
{
    return fx_open_robot(&robot_pm01, m, params, port, err, errlen);
}

static void fx_peer(roz_peer_frame_t what)
{
    roz_link_t before[ROZ_ROS2_MAX_TOPICS];
    roz_ros2fx_links(before);
    switch (what) {
    case ROZ_PEER_SEND:
        roz_ros2fx_send();
        break;
    case ROZ_PEER_SILENT:
        roz_fake_sleep_ms(2); /* a frame period */
        break;
    case ROZ_PEER_CORRUPT:
        fail_msg("%s: no CRC to corrupt", man->robot_id);
        break;
    case ROZ_PEER_REPLAY:
        roz_ros2fx_ask("replay");
        roz_ros2fx_wait_judged(before, 0, 0);
        break;
    case ROZ_PEER_RESTART:
        roz_ros2fx_ask("restart");
        roz_ros2fx_set_state(++frame_no);
        roz_ros2fx_ask("send");
        roz_ros2fx_wait_judged(before, 0, 1);
        /* Commands the port's writer published before it judged the
         * restart may reach the fake after it restarted: a limit of any
         * port (SAFETY.md), not what the suite checks. Once the writer is
         * idle, the commands counted so far are those; peer_command()
         * ignores them. */
        roz_ros2fx_settle();
        if (roz_fake_ros2_commands(&fake, got_at_restart) != 0)
            fail_msg("fake_ros2: commands: \"%s\"", fake.proc.line);
        restarted = 1;
        break;
    case ROZ_PEER_VANISH:
        roz_fake_sleep_ms(peer_timeout_ms + 100u);
        roz_ros2fx_send();
        break;
    }
}

static void fx_peer_sent(double *state)
{
    roz_ros2fx_sent(state);
}

static const double *fx_peer_command(void)
{
    if (restarted) {
        uint64_t got[FAKE_ROS2_MAX_GROUPS];
        int newer = 0;
        if (roz_fake_ros2_commands(&fake, got) != 0)
            fail_msg("fake_ros2: commands: \"%s\"", fake.proc.line);
        for (unsigned g = 0; g < fake.n_groups; g++)
            newer |= drives[g] && got[g] != got_at_restart[g];
        if (!newer)
            return NULL; /* nothing written for the restarted robot yet */
        restarted = 0;
    }
    return roz_ros2fx_applied(applied) ? applied : NULL;
}

static void fx_corrupt_next_command(void)
{
    fail_msg("%s: no CRC to corrupt", man->robot_id);
}

static void fx_link(roz_link_t *out)
{
    roz_ros2_link(robot->bridge, out);
}

static void fx_close(void)
{
    if (port_open) {
        (void)roz_port_deactivate(&the_port);
        roz_port_close(&the_port);
        port_open = 0;
    }
    if (fake.proc.pid != 0 && roz_fake_ros2_stop(&fake) != 0)
        fail_msg("fake_ros2 did not exit cleanly");
}

static const roz_manifest_t *const pm01_manifests[] = { &roz_manifest_engineai_pm01, NULL };

static void fx_strict_monitors(void)
{
    roz_ros2_counters_t c;
    roz_ros2_counters(robot->bridge, &c);
    roz_fixture_strict(roz_ros2_writer_monitor(robot->bridge));
    for (uint16_t t = 0; t < c.n_topics; t++)
        roz_fixture_strict(roz_ros2_topic_monitor(robot->bridge, t));
}

/* The members of both robots' fixtures but the open: the same fake, the
 * same bridge (the wire carries float64: no narrowing). */
#define FX_ROS2_OPS                                                                       \
    .wire_command = NULL, .peer = fx_peer, .peer_sent = fx_peer_sent,                     \
    .settle = roz_ros2fx_settle, .peer_command = fx_peer_command,                         \
    .corrupt_next_command = fx_corrupt_next_command, .link = fx_link, .close = fx_close,  \
    .set_log = fx_set_log, .strict_monitors = fx_strict_monitors,

const roz_port_fixture_t roz_fixture_engineai_pm01 = {
    .name = "engineai/PM01",
    .manifests = pm01_manifests,
    .state_topics = 2, /* joint_state, imu_info */
    .open = fx_open_pm01,
    FX_ROS2_OPS
};

#ifdef ROZ_TEST_HAVE_AGIBOT_X2
static int fx_open_x2(const roz_manifest_t *m, const roz_params_t *params, roz_port_t *port,
                      char *err, size_t errlen)
{
    return fx_open_robot(&robot_x2, m, params, port, err, errlen);
}

static const roz_manifest_t *const x2_manifests[] = { &roz_manifest_agibot_x2, NULL };

const roz_port_fixture_t roz_fixture_agibot_x2 = {
    .name = "agibot/X2",
    .manifests = x2_manifests,
    .state_topics = 5, /* leg, waist, arm, head, torso IMU */
    .open = fx_open_x2,
    FX_ROS2_OPS
};
#endif
