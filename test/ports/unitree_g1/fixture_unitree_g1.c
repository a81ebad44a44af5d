/* SPDX-License-Identifier: Apache-2.0 */
/* The G1 port's conformance fixture: the port in this process, its peer
 * the fake robot fake_g1 (test/fakes/unitree_g1: a separate process with
 * its own IDL and CRC), driven over its stdin/stdout, over loopback DDS.
 *
 * The port's threads make each call synchronous here (port_fixture.h):
 * peer() returns once the port's receive thread has judged the frame (its
 * link counters moved); settle() once the port's writer took every frame
 * written and the fake counted every sample published. The port runs its
 * writer event-driven (command_writer_period_us = 0), one sample per write,
 * so "the next command frame" is the next write's (a periodic writer sends
 * each command many times); the G1 tests run it periodic too. The fake
 * sends float32: the values it is told are float32 already, so what the
 * port delivers is exactly what the fixture asked for. */
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

#include "fake_g1_client.h"
#include "dds_fixture_params.h"
#include "port_fixture.h"
#include "roz/port/unitree_g1.h"
#include "unitree_g1_fixture.h"
#include "unitree_g1_23dof_manifest.h"
#include "unitree_g1_manifest.h"

#ifndef ROZ_TEST_DDS_DOMAIN
#error "ROZ_TEST_DDS_DOMAIN: a domain id of this test's own"
#endif

/* A hang guard for every wait on the port or the fake: far beyond what a
 * loaded machine takes (a full parallel ctest under a sanitizer once took
 * longer than the 10 s this was), so only a hang fails; nothing asserts a
 * time. */
#define WAIT_MS 60000u

static roz_unitree_g1_t g1;
static roz_port_t the_port;
static int port_open;
static roz_fake_g1_t fake;
static const roz_manifest_t *man;
static double sent[ROZ_CFG_MAX_STATES];
static double applied[ROZ_CFG_MAX_COMMANDS];
static uint32_t frame_no;
static uint32_t peer_timeout_ms;
static const char *const *fake_args; /* the next open's, then none */
static void (*before_activate)(const roz_port_t *port); /* the next open's, then none */

/* ---- helpers for the G1 tests too (unitree_g1_fixture.h) -------------------- */

roz_unitree_g1_t *roz_g1fx_port(void)
{
    return &g1;
}

roz_fake_g1_t *roz_g1fx_fake(void)
{
    return &fake;
}

void roz_g1fx_set_fake_args(const char *const *extra)
{
    fake_args = extra;
}

void roz_g1fx_set_before_activate(void (*fn)(const roz_port_t *port))
{
    before_activate = fn;
}

static void quiet_log(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    if (level == ROZ_LOG_ERROR)
        fprintf(stderr, "unitree/G1: %s\n", msg);
}

static roz_log_fn fx_log;

static void fx_set_log(roz_log_fn log)
{
    fx_log = log;
}

static void fx_strict_monitors(void)
{
    roz_fixture_strict(roz_unitree_g1_writer_monitor(&g1));
    roz_fixture_strict(roz_unitree_g1_state_monitor(&g1));
}

void roz_g1fx_ask(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    roz_fake_process_vmust(&fake, "fake_g1", fmt, ap);
    va_end(ap);
}

/* The G1's motor slots by joint name, written here from the SDK's joint
 * order (not taken from the port): the robot's side of the binding. */
int roz_g1fx_slot(const char *joint)
{
    static const char *const body[29] = {
        "left_hip_pitch_joint", "left_hip_roll_joint", "left_hip_yaw_joint", "left_knee_joint",
        "left_ankle_pitch_joint", "left_ankle_roll_joint", "right_hip_pitch_joint",
        "right_hip_roll_joint", "right_hip_yaw_joint", "right_knee_joint",
        "right_ankle_pitch_joint", "right_ankle_roll_joint", "waist_yaw_joint",
        "waist_roll_joint", "waist_pitch_joint", "left_shoulder_pitch_joint",
        "left_shoulder_roll_joint", "left_shoulder_yaw_joint", "left_elbow_joint",
        "left_wrist_roll_joint", "left_wrist_pitch_joint", "left_wrist_yaw_joint",
        "right_shoulder_pitch_joint", "right_shoulder_roll_joint", "right_shoulder_yaw_joint",
        "right_elbow_joint", "right_wrist_roll_joint", "right_wrist_pitch_joint",
        "right_wrist_yaw_joint",
    };
    for (int s = 0; s < 29; s++) {
        if (strcmp(body[s], joint) == 0)
            return s;
    }
    fail_msg("\"%s\" is not a G1 joint", joint);
    return -1;
}

/* Sets the fake's state for frame k, distinct per joint and per frame, in
 * float32, inside each channel's limits; records what the port should
 * deliver. */
void roz_g1fx_set_state(uint32_t k)
{
    const roz_hardware_t *hw = man->hardware;
    for (uint16_t j = 0; j < hw->n_joints; j++) {
        char name[160];
        snprintf(name, sizeof name, "%s/position", hw->joints[j]);
        int qi = roz_manifest_find_state(man, name);
        snprintf(name, sizeof name, "%s/velocity", hw->joints[j]);
        int dqi = roz_manifest_find_state(man, name);
        snprintf(name, sizeof name, "%s/effort", hw->joints[j]);
        int ti = roz_manifest_find_state(man, name);
        double lo = qi >= 0 ? man->states[qi].min : -1.0, hi = qi >= 0 ? man->states[qi].max : 1.0;
        float q = (float)(lo + (hi - lo) * (double)((k * 7u + j * 3u) % 17u + 1u) / 19.0);
        float dq = (float)(((int)((k + j) % 11u) - 5) * 0.5);
        float tau = (float)(((int)((k * 3u + j) % 13u) - 6) * 0.25);
        roz_g1fx_ask("motor %d %.9g %.9g %.9g", roz_g1fx_slot(hw->joints[j]), (double)q,
                     (double)dq, (double)tau);
        if (qi >= 0)
            sent[qi] = q;
        if (dqi >= 0)
            sent[dqi] = dq;
        if (ti >= 0)
            sent[ti] = tau;
    }
    /* the IMU: Unitree's w, x, y, z in; the manifest's x, y, z, w out */
    float w = 0.5f + 0.001f * (float)(k % 100u), x = -0.25f + 0.002f * (float)(k % 50u);
    float y = 0.125f, z = -0.0625f - 0.001f * (float)(k % 30u);
    float g[3] = { 0.01f * (float)(k % 7u), -0.02f, 0.03f };
    float a[3] = { 0.1f, -0.2f * (float)(k % 3u), 9.81f };
    roz_g1fx_ask("imu %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g", (double)w, (double)x,
                 (double)y, (double)z, (double)g[0], (double)g[1], (double)g[2], (double)a[0],
                 (double)a[1], (double)a[2]);
    static const char *const imu_names[10] = {
        "base_imu/orientation.x",         "base_imu/orientation.y",
        "base_imu/orientation.z",         "base_imu/orientation.w",
        "base_imu/angular_velocity.x",    "base_imu/angular_velocity.y",
        "base_imu/angular_velocity.z",    "base_imu/linear_acceleration.x",
        "base_imu/linear_acceleration.y", "base_imu/linear_acceleration.z",
    };
    const float v[10] = { x, y, z, w, g[0], g[1], g[2], a[0], a[1], a[2] };
    for (int i = 0; i < 10; i++) {
        int s = roz_manifest_find_state(man, imu_names[i]);
        if (s >= 0)
            sent[s] = v[i];
    }
}

void roz_g1fx_sent(double *state)
{
    memcpy(state, sent, man->n_states * sizeof state[0]);
}

/* After a restart: the fake's good-command count once the writer was idle. */
static int restarted;
static uint64_t good_at_restart;

/* The kind of frame being waited for, for the failure message. */
static const char *judging = "first";

/* Waits until @p pred holds of the port's link checks. */
static int link_moved(const roz_link_t *before, const roz_link_t *now)
{
    return now->accepted != before->accepted || now->crc_errors != before->crc_errors ||
           now->replays != before->replays;
}

void roz_g1fx_wait_judged(const roz_link_t *before, int resend_until_first)
{
    roz_link_t now;
    for (unsigned ms = 0; ms < WAIT_MS; ms++) {
        roz_unitree_g1_link(&g1, &now);
        if (link_moved(before, &now))
            return;
        /* Before the port's first frame, or after the fake restarted (a new
         * writer), the fake's writer may not have found the port's reader
         * yet (discovery is asynchronous, slow on a loaded machine): a new
         * frame every 500 ms until one arrives. resend_until_first: 1 while
         * the port has no live peer, 2 always. */
        if ((resend_until_first == 2 || (resend_until_first && !now.alive)) &&
            ms % 500u == 499u) {
            roz_g1fx_set_state(frame_no);
            roz_g1fx_ask("send");
        }
        roz_fake_g1_sleep_ms(1);
    }
    fail_msg("unitree/G1: the port did not judge the fake's %s frame within %u ms "
             "(link: %llu accepted, %llu bad CRC, %llu replays, %llu restarts, alive %d)",
             judging, WAIT_MS, (unsigned long long)now.accepted,
             (unsigned long long)now.crc_errors, (unsigned long long)now.replays,
             (unsigned long long)now.restarts, (int)now.alive);
}

/* Sends one good frame (new values) and waits for the port to take it. */
void roz_g1fx_send(void)
{
    roz_link_t before;
    roz_unitree_g1_link(&g1, &before);
    roz_g1fx_set_state(++frame_no);
    roz_g1fx_ask("send");
    roz_g1fx_wait_judged(&before, 1);
}

void roz_g1fx_settle(void)
{
    roz_unitree_g1_counters_t c;
    uint64_t good = 0, bad = 0;
    unsigned ms = 0;

    /* the port's writer took the last frame written, and no pass is open */
    for (;; ms++) {
        roz_unitree_g1_counters(&g1, &c);
        if (c.handled_seq == c.written_seq && c.writer_passes == c.writer_done)
            break;
        if (ms >= WAIT_MS)
            fail_msg("unitree/G1: the writer did not take command %llu within %u ms",
                     (unsigned long long)c.written_seq, WAIT_MS);
        roz_fake_g1_sleep_ms(1);
    }
    /* the fake counted everything published (good or flipped) */
    for (;; ms++) {
        if (roz_fake_g1_commands(&fake, &good, &bad) != 0)
            fail_msg("fake_g1: commands: \"%s\"", fake.line);
        if (good + bad >= c.published)
            return;
        if (ms >= WAIT_MS)
            fail_msg("fake_g1 counted %llu of the %llu commands published within %u ms",
                     (unsigned long long)(good + bad), (unsigned long long)c.published, WAIT_MS);
        roz_fake_g1_sleep_ms(1);
    }
}

/* ---- the fixture ---------------------------------------------------------------- */

static void fx_close(void);

/* Whether the fake matched the port both ways: its command reader the
 * port's writer, its state writer the port's reader. */
static int fake_matched(void)
{
    unsigned w = 0, r = 0;
    if (roz_fake_g1_ask(&fake, "matched") != 0 || sscanf(fake.line, "ok %u %u", &w, &r) != 2)
        fail_msg("fake_g1: matched: \"%s\"", fake.line);
    return w >= 1 && r >= 1;
}

static int fx_open(const roz_manifest_t *m, const roz_params_t *params, roz_port_t *port,
                   char *err, size_t errlen)
{
    static roz_param_t items[ROZ_UNITREE_G1_MAX_PARAMS];

    restarted = 0;

    /* a check that failed half-way left its port and fake behind */
    if (port_open || fake.pid != 0)
        fx_close();
    man = m;
    frame_no = 0;
    memset(sent, 0, sizeof sent);
    const char *const *extra = fake_args;
    fake_args = NULL;
    if (roz_fake_g1_start(&fake, ROZ_TEST_DDS_DOMAIN, extra, err, errlen) != 0)
        return ROZ_EIO;
    /* the fixture's parameters first: the caller's win */
    roz_params_t all =
        roz_dds_fixture_params(items, ROZ_UNITREE_G1_MAX_PARAMS, params, &peer_timeout_ms);
    the_port = roz_unitree_g1_port(&g1, fx_log != NULL ? fx_log : quiet_log, NULL);
    int rc = roz_port_open(&the_port, m, &all, err, errlen);
    if (rc == ROZ_OK)
        port_open = 1;
    if (rc == ROZ_OK && before_activate != NULL)
        before_activate(&the_port);
    before_activate = NULL;
    if (rc == ROZ_OK)
        rc = roz_port_activate(&the_port);
    if (rc != ROZ_OK)
        return rc;
    *port = the_port;
    /* both directions matched, seen from both sides, before anyone speaks
     * (discovery is asynchronous: a side that has not matched the other's
     * writer yet drops what it is sent, so the first command could be lost
     * and a wait for it never end) */
    for (unsigned ms = 0;; ms++) {
        uint32_t readers, writers;
        roz_unitree_g1_matched(&g1, &readers, &writers);
        if (readers >= 1 && writers >= 1 && fake_matched())
            break;
        if (ms >= WAIT_MS) {
            snprintf(err, errlen, "unitree/G1 and fake_g1 did not discover each other in %u ms",
                     WAIT_MS);
            return ROZ_ETIMEDOUT;
        }
        roz_fake_g1_sleep_ms(1);
    }
    return ROZ_OK;
}

static void fx_peer(roz_peer_frame_t what)
{
    roz_link_t before;
    roz_unitree_g1_link(&g1, &before);
    static const char *const names[] = { "good", "silent", "corrupt", "replayed", "restart",
                                         "after-vanish" };
    judging = (unsigned)what < sizeof names / sizeof names[0] ? names[what] : "?";
    switch (what) {
    case ROZ_PEER_SEND:
        roz_g1fx_send();
        break;
    case ROZ_PEER_SILENT:
        roz_g1fx_ask("silent");
        roz_fake_g1_sleep_ms(2); /* a frame period */
        break;
    case ROZ_PEER_CORRUPT:
        roz_g1fx_ask("corrupt");
        roz_g1fx_wait_judged(&before, 0);
        break;
    case ROZ_PEER_REPLAY:
        roz_g1fx_ask("replay");
        roz_g1fx_wait_judged(&before, 0);
        break;
    case ROZ_PEER_RESTART: {
        roz_g1fx_ask("restart");
        roz_g1fx_set_state(++frame_no);
        roz_g1fx_ask("send");
        roz_g1fx_wait_judged(&before, 2);
        /* Commands the port's writer published before it judged the
         * restart frame may reach the fake after it restarted: a limit of
         * any port (SAFETY.md), not what the suite checks. Once the writer
         * is idle, the commands counted so far are those; peer_command()
         * ignores them. */
        uint64_t bad;
        roz_g1fx_settle();
        if (roz_fake_g1_commands(&fake, &good_at_restart, &bad) != 0)
            fail_msg("fake_g1: commands: \"%s\"", fake.line);
        restarted = 1;
        break;
    }
    case ROZ_PEER_VANISH:
        roz_fake_g1_sleep_ms(peer_timeout_ms + 100u);
        roz_g1fx_send();
        break;
    }
}

static void fx_peer_sent(double *state)
{
    roz_g1fx_sent(state);
}

static const double *fx_peer_command(void)
{
    static roz_fake_g1_cmd_t c;
    if (restarted) {
        uint64_t good, bad;
        if (roz_fake_g1_commands(&fake, &good, &bad) != 0)
            fail_msg("fake_g1: commands: \"%s\"", fake.line);
        if (good == good_at_restart)
            return NULL; /* nothing written for the restarted robot yet */
        restarted = 0;
    }
    int rc = roz_fake_g1_command(&fake, &c);
    if (rc < 0)
        fail_msg("fake_g1: command: \"%s\"", fake.line);
    if (rc == 0)
        return NULL;
    const roz_hardware_t *hw = man->hardware;
    for (uint16_t i = 0; i < man->n_commands; i++)
        applied[i] = NAN; /* a command the fake has no value for stays NaN: a failure */
    for (uint16_t j = 0; j < hw->n_joints; j++) {
        static const char *const suffix[5] = { "position", "velocity", "effort", "stiffness",
                                               "damping" };
        int sl = roz_g1fx_slot(hw->joints[j]);
        const double v[5] = { c.q[sl], c.dq[sl], c.tau[sl], c.kp[sl], c.kd[sl] };
        for (int k = 0; k < 5; k++) {
            char name[160];
            snprintf(name, sizeof name, "%s/%s", hw->joints[j], suffix[k]);
            int i = roz_manifest_find_command(man, name);
            if (i >= 0)
                applied[i] = v[k];
        }
    }
    return applied;
}

static void fx_corrupt_next_command(void)
{
    roz_g1fx_ask("flip_next_command");
}

static void fx_link(roz_link_t *out)
{
    roz_unitree_g1_link(&g1, out);
}

static void fx_close(void)
{
    if (port_open) {
        (void)roz_port_deactivate(&the_port);
        roz_port_close(&the_port);
        port_open = 0;
    }
    if (fake.pid != 0 && roz_fake_g1_stop(&fake) != 0)
        fail_msg("fake_g1 did not exit cleanly");
}

/* The wire carries float32. */
static void fx_wire_command(const double *in, double *out)
{
    for (uint16_t i = 0; i < man->n_commands; i++)
        out[i] = (float)in[i];
}

static const roz_manifest_t *const g1_manifests[] = { &roz_manifest_unitree_g1,
                                                      &roz_manifest_unitree_g1_23dof, NULL };

const roz_port_fixture_t roz_fixture_unitree_g1 = {
    .name = "unitree/G1",
    .manifests = g1_manifests,
    .wire_command = fx_wire_command,
    .open = fx_open,
    .peer = fx_peer,
    .peer_sent = fx_peer_sent,
    .settle = roz_g1fx_settle,
    .peer_command = fx_peer_command,
    .corrupt_next_command = fx_corrupt_next_command,
    .link = fx_link,
    .close = fx_close,
    .set_log = fx_set_log,
    .strict_monitors = fx_strict_monitors,
};
