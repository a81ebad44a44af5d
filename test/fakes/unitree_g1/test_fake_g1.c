/* SPDX-License-Identifier: Apache-2.0 */
/* The fake G1's own test. It runs fake_g1 (argv[1]) as the port's tests
 * do, drives it through its protocol, and watches the wire with a raw
 * Cyclone DDS reader on rt/lowstate and writer on rt/lowcmd of its own.
 * What the fake publishes is checked with this file's CRC (CRC-32/MPEG-2
 * over byte-reversed words, a different algorithm from the fake's
 * bit-by-bit one) over this file's member-by-member copy. Everything stays
 * on the loopback (g1_dds.h); ctest runs it in a network namespace of its
 * own where permitted (test/run_netns.sh).
 *
 * ROZ_TEST_DDS_DOMAIN picks the DDS domain (default 71); FAKE_G1_SEED and
 * FAKE_G1_GARBAGE_LINES the garbage test's seed and length (3000 lines). */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <poll.h>
#include <setjmp.h>
#include <signal.h>
#include <spawn.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "support_spawn.h"
#include <dds/dds.h>
#include <dds/ddsi/ddsi_serdata.h>

#include "g1_crc.h"
#include "g1_dds.h"
#include "g1_frame.h"

extern char **environ;

#define REPLY_MS 20000 /* a reply later than this is a hung fake */
#define WIRE_MS 10000  /* a frame later than this is a lost frame */

static const char *fake_path;
static uint32_t domain_id = 71;

/* ---- an independent CRC: MPEG-2 over bytes, words byte-reversed ---------- */

static uint32_t mpeg2(uint32_t crc, const uint8_t *b, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        crc ^= (uint32_t)b[i] << 24;
        for (int k = 0; k < 8; k++)
            crc = (crc & 0x80000000u) ? (crc << 1) ^ 0x04C11DB7u : crc << 1;
    }
    return crc;
}

/* Unitree's CRC of a native image of @p nwords little-endian words. */
static uint32_t crc_image(const void *image, size_t nwords)
{
    const uint8_t *p = image;
    uint32_t crc = 0xFFFFFFFFu;
    for (size_t i = 0; i < nwords; i++) {
        const uint8_t rev[4] = { p[4 * i + 3], p[4 * i + 2], p[4 * i + 1], p[4 * i] };
        crc = mpeg2(crc, rev, 4);
    }
    return crc;
}

/* A received state rebuilt over zeroes, member by member (the wire has no
 * padding), as a robot's receiver does before it checks the CRC. */
static void state_rebuild(g1_lowstate_t *d, const g1_lowstate_t *s)
{
    memset(d, 0, sizeof *d);
    d->version[0] = s->version[0];
    d->version[1] = s->version[1];
    d->mode_pr = s->mode_pr;
    d->mode_machine = s->mode_machine;
    d->tick = s->tick;
    for (int i = 0; i < 4; i++)
        d->imu_state.quaternion[i] = s->imu_state.quaternion[i];
    for (int i = 0; i < 3; i++) {
        d->imu_state.gyroscope[i] = s->imu_state.gyroscope[i];
        d->imu_state.accelerometer[i] = s->imu_state.accelerometer[i];
        d->imu_state.rpy[i] = s->imu_state.rpy[i];
    }
    d->imu_state.temperature = s->imu_state.temperature;
    for (int i = 0; i < 35; i++) {
        const g1_motorstate_t *a = &s->motor_state[i];
        g1_motorstate_t *b = &d->motor_state[i];
        b->mode = a->mode;
        b->q = a->q;
        b->dq = a->dq;
        b->ddq = a->ddq;
        b->tau_est = a->tau_est;
        b->temperature[0] = a->temperature[0];
        b->temperature[1] = a->temperature[1];
        b->vol = a->vol;
        b->sensor[0] = a->sensor[0];
        b->sensor[1] = a->sensor[1];
        b->motorstate = a->motorstate;
        for (int k = 0; k < 4; k++)
            b->reserve[k] = a->reserve[k];
    }
    for (int i = 0; i < 40; i++)
        d->wireless_remote[i] = s->wireless_remote[i];
    for (int i = 0; i < 4; i++)
        d->reserve[i] = s->reserve[i];
    d->crc = s->crc;
}

static int state_crc_ok(const g1_lowstate_t *s)
{
    g1_lowstate_t z;
    state_rebuild(&z, s);
    return crc_image(&z, 522) == s->crc;
}

/* ---- the fake as a child process ----------------------------------------- */

typedef struct fk {
    pid_t pid;
    int in, out, err; /* its stdin, stdout, stderr (err -1: inherited) */
    char buf[65536];
    size_t len;
    char line[65536];
} fk_t;

static fk_t fake; /* one at a time; the teardown stops a leftover */

static void cloexec_pipe(int fds[2])
{
    assert_int_equal(pipe(fds), 0);
    fcntl(fds[0], F_SETFD, FD_CLOEXEC);
    fcntl(fds[1], F_SETFD, FD_CLOEXEC);
}

/* Start fake_g1 with @p args (NULL-terminated, after the program name). */
static void fk_spawn(fk_t *k, const char *const *args, int capture_err)
{
    int in[2], out[2], err[2] = { -1, -1 };
    static char store[16][256]; /* posix_spawn wants mutable strings */
    char *argv[16];
    size_t n = 0;
    snprintf(store[n], sizeof store[n], "%s", fake_path);
    argv[n] = store[n];
    for (n++; *args != NULL && n < 15; args++, n++) {
        snprintf(store[n], sizeof store[n], "%s", *args);
        argv[n] = store[n];
    }
    argv[n] = NULL;
    cloexec_pipe(in);
    cloexec_pipe(out);
    if (capture_err)
        cloexec_pipe(err);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, in[0], 0);
    posix_spawn_file_actions_adddup2(&fa, out[1], 1);
    if (capture_err)
        posix_spawn_file_actions_adddup2(&fa, err[1], 2);
    int rc = roz_test_spawn(&k->pid, &fa, (const char *const *)argv);
    posix_spawn_file_actions_destroy(&fa);
    assert_int_equal(rc, 0);
    close(in[0]);
    close(out[1]);
    if (capture_err)
        close(err[1]);
    k->in = in[1];
    k->out = out[0];
    k->err = err[0];
    k->len = 0;
}

/* The next line the fake prints, or NULL at its EOF; fails on a hang. */
static const char *fk_line(fk_t *k)
{
    for (;;) {
        char *nl = memchr(k->buf, '\n', k->len);
        if (nl != NULL) {
            size_t n = (size_t)(nl - k->buf);
            memcpy(k->line, k->buf, n);
            k->line[n] = '\0';
            memmove(k->buf, nl + 1, k->len - n - 1);
            k->len -= n + 1;
            return k->line;
        }
        if (k->len == sizeof k->buf)
            fail_msg("fake_g1 printed a line longer than %zu bytes", sizeof k->buf);
        struct pollfd p = { k->out, POLLIN, 0 };
        int r = poll(&p, 1, REPLY_MS);
        if (r == 0)
            fail_msg("fake_g1 did not reply within %d ms", REPLY_MS);
        if (r < 0 && errno == EINTR)
            continue;
        ssize_t got = read(k->out, k->buf + k->len, sizeof k->buf - k->len);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0)
            return NULL;
        k->len += (size_t)got;
    }
}

static void fk_write(fk_t *k, const char *data, size_t n)
{
    while (n > 0) {
        ssize_t w = write(k->in, data, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            fail_msg("writing to fake_g1: %s", strerror(errno));
        data += w;
        n -= (size_t)w;
    }
}

/* Send one request line (printf-style, newline added); its reply. */
__attribute__((format(printf, 2, 3)))
static const char *fk_req(fk_t *k, const char *fmt, ...)
{
    char req[4096];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(req, sizeof req - 1, fmt, ap);
    va_end(ap);
    assert_true(n >= 0 && (size_t)n < sizeof req - 1);
    req[n++] = '\n';
    fk_write(k, req, (size_t)n);
    const char *r = fk_line(k);
    if (r == NULL)
        fail_msg("fake_g1 exited on '%.*s'", n - 1, req);
    return r;
}

__attribute__((format(printf, 2, 3)))
static void fk_ok(fk_t *k, const char *fmt, ...)
{
    char req[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(req, sizeof req, fmt, ap);
    va_end(ap);
    const char *r = fk_req(k, "%s", req);
    if (strcmp(r, "ok") != 0)
        fail_msg("'%s' -> '%s', want 'ok'", req, r);
}

/* "ok N" -> N */
static uint64_t fk_ok_n(fk_t *k, const char *req)
{
    const char *r = fk_req(k, "%s", req);
    char *end;
    if (strncmp(r, "ok ", 3) != 0)
        fail_msg("'%s' -> '%s', want 'ok N'", req, r);
    uint64_t v = strtoull(r + 3, &end, 10);
    if (*end != '\0')
        fail_msg("'%s' -> '%s', want 'ok N'", req, r);
    return v;
}

/* Wait for the child's exit; its status. */
static int fk_wait(fk_t *k)
{
    int status = 0;
    for (int i = 0; i < REPLY_MS / 10; i++) {
        pid_t p = waitpid(k->pid, &status, WNOHANG);
        if (p == k->pid) {
            k->pid = 0;
            return status;
        }
        const struct timespec ms10 = { 0, 10000000L };
        nanosleep(&ms10, NULL);
    }
    fail_msg("fake_g1 did not exit within %d ms", REPLY_MS);
    return -1;
}

static void fk_close(fk_t *k)
{
    if (k->in >= 0)
        close(k->in);
    if (k->out >= 0)
        close(k->out);
    if (k->err >= 0)
        close(k->err);
    k->in = k->out = k->err = -1;
}

/* "quit" -> "ok", then exit status 0. */
static void fk_quit(fk_t *k)
{
    const char *r = fk_req(k, "quit");
    assert_string_equal(r, "ok");
    int st = fk_wait(k);
    assert_true(WIFEXITED(st));
    assert_int_equal(WEXITSTATUS(st), 0);
    fk_close(k);
}

static void fk_start(fk_t *k, const char *const *args)
{
    fk_spawn(k, args, 0);
    const char *r = fk_line(k);
    assert_non_null(r);
    assert_string_equal(r, "ready");
}

/* ---- this side of the wire ----------------------------------------------- */

static dds_entity_t participant, state_reader, cmd_writer, state_ws;
static dds_entity_t state_wire, cmd_wire; /* the same samples, serialized */

static int group_setup(void **st)
{
    char err[200];
    (void)st;
    participant = g1_dds_participant(domain_id, "lo", err, sizeof err);
    if (participant < 0) {
        fprintf(stderr, "test_fake_g1: %s\n", err);
        return -1;
    }
    dds_entity_t ts = dds_create_topic(participant, &unitree_hg_msg_dds__LowState__desc,
                                       "rt/lowstate", NULL, NULL);
    dds_entity_t tc = dds_create_topic(participant, &unitree_hg_msg_dds__LowCmd__desc,
                                       "rt/lowcmd", NULL, NULL);
    dds_qos_t *q = dds_create_qos();
    dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 256);
    state_reader = dds_create_reader(participant, ts, q, NULL);
    cmd_writer = dds_create_writer(participant, tc, q, NULL);
    state_wire = dds_create_reader(participant, ts, q, NULL);
    cmd_wire = dds_create_reader(participant, tc, q, NULL); /* this writer's, locally */
    dds_delete_qos(q);
    state_ws = dds_create_waitset(participant);
    dds_entity_t rc = dds_create_readcondition(state_reader, DDS_ANY_STATE);
    if (ts < 0 || tc < 0 || state_reader < 0 || cmd_writer < 0 || state_wire < 0 ||
        cmd_wire < 0 || state_ws < 0 || rc < 0 ||
        dds_waitset_attach(state_ws, rc, 0) < 0) {
        fprintf(stderr, "test_fake_g1: DDS set-up failed\n");
        return -1;
    }
    return 0;
}

static int group_teardown(void **st)
{
    (void)st;
    dds_delete(DDS_CYCLONEDDS_HANDLE);
    return 0;
}

static int case_setup(void **st)
{
    (void)st;
    fake.pid = 0;
    fake.in = fake.out = fake.err = -1;
    return 0;
}

static int case_teardown(void **st)
{
    (void)st;
    if (fake.pid > 0) { /* a failed case left it running */
        kill(fake.pid, SIGKILL);
        waitpid(fake.pid, NULL, 0);
        fake.pid = 0;
    }
    fk_close(&fake);
    return 0;
}

/* The next state sample within @p ms: 1, or 0 if none came. */
static int take_state(g1_lowstate_t *out, int ms)
{
    void *ptr = out;
    dds_sample_info_t info;
    dds_time_t until = dds_time() + DDS_MSECS(ms);
    for (;;) {
        if (dds_take(state_reader, &ptr, &info, 1, 1) == 1 && info.valid_data)
            return 1;
        dds_time_t now = dds_time();
        if (now >= until)
            return 0;
        (void)dds_waitset_wait(state_ws, NULL, 0, until - now);
    }
}

/* The next sample on @p reader as it travelled: its encapsulation header,
 * then the CDR payload. Its size. */
static size_t take_wire(dds_entity_t reader, uint8_t *buf, size_t cap)
{
    struct ddsi_serdata *sd = NULL;
    dds_sample_info_t info;
    for (int i = 0; i < WIRE_MS; i++) {
        if (dds_takecdr(reader, &sd, 1, &info, DDS_ANY_STATE) == 1) {
            size_t n = ddsi_serdata_size(sd);
            if (n > cap)
                fail_msg("a serialized sample of %zu bytes", n);
            ddsi_serdata_to_ser(sd, 0, n, buf);
            ddsi_serdata_unref(sd);
            return n;
        }
        dds_sleepfor(DDS_MSECS(1));
    }
    fail_msg("no serialized sample");
    return 0;
}

static void drain_wire(dds_entity_t reader)
{
    struct ddsi_serdata *sd = NULL;
    dds_sample_info_t info;
    while (dds_takecdr(reader, &sd, 1, &info, DDS_ANY_STATE) == 1)
        ddsi_serdata_unref(sd);
}

static void drain_states(void)
{
    g1_lowstate_t s;
    while (take_state(&s, 0))
        ;
    drain_wire(state_wire);
}

static uint32_t le32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static void expect_le_float(const uint8_t *p, float want, const char *what)
{
    uint32_t bits;
    memcpy(&bits, &want, sizeof bits);
    if (le32(p) != bits)
        fail_msg("%s on the wire: 0x%08x, want 0x%08x", what, le32(p), bits);
}

/* XCDR1, little-endian: the encapsulation Cyclone uses for @final types
 * and ROS 2 expects. */
static void expect_xcdr1_le(const uint8_t *w)
{
    assert_int_equal(w[0], 0x00);
    assert_int_equal(w[1], 0x01);
}

static uint32_t state_matches(void)
{
    dds_subscription_matched_status_t st;
    assert_true(dds_get_subscription_matched_status(state_reader, &st) >= 0);
    return st.total_count;
}

/* Wait until this reader has met @p total writers in all, one of them now. */
static void await_state_writer(uint32_t total)
{
    dds_subscription_matched_status_t st;
    for (int i = 0; i < WIRE_MS; i++) {
        assert_true(dds_get_subscription_matched_status(state_reader, &st) >= 0);
        if (st.total_count >= total && st.current_count >= 1)
            return;
        dds_sleepfor(DDS_MSECS(1));
    }
    fail_msg("the fake's state writer was not discovered");
}

/* Until both ends know each other, a frame may go nowhere: send until one
 * arrives, then once more and read up to it, so that the next sample this
 * reader takes is the next frame the fake sends. Returns that last tick. */
static uint32_t sync_states(fk_t *k)
{
    g1_lowstate_t s;
    await_state_writer(1);
    int got = 0;
    for (int i = 0; i < 100 && !got; i++) {
        (void)fk_ok_n(k, "send");
        got = take_state(&s, 100);
    }
    assert_true(got);
    uint32_t t = (uint32_t)fk_ok_n(k, "send");
    do
        assert_true(take_state(&s, WIRE_MS));
    while (s.tick != t);
    return t;
}

/* The next frame must carry @p tick. */
static void expect_frame(g1_lowstate_t *s, uint32_t tick)
{
    if (!take_state(s, WIRE_MS))
        fail_msg("no frame with tick %u", tick);
    assert_int_equal(s->tick, tick);
}

static void await_cmd_reader(void)
{
    dds_publication_matched_status_t st;
    for (int i = 0; i < WIRE_MS; i++) {
        assert_true(dds_get_publication_matched_status(cmd_writer, &st) >= 0);
        if (st.current_count >= 1)
            return;
        dds_sleepfor(DDS_MSECS(1));
    }
    fail_msg("the fake's command reader was not discovered");
}

/* A command with a distinct value in every field, @p seed apart. */
static void make_command(g1_lowcmd_t *c, int seed)
{
    memset(c, 0, sizeof *c);
    c->mode_pr = 1;
    c->mode_machine = (uint8_t)(13 + seed);
    for (int i = 0; i < 35; i++) {
        g1_motorcmd_t *m = &c->motor_cmd[i];
        m->mode = i < 29 ? 1 : 0;
        m->q = (float)(0.05 * i - 0.7 + 0.001 * seed);
        m->dq = (float)(0.1 * i + 0.3 * seed);
        m->tau = (float)(-0.2 * i - seed);
        m->kp = (float)(100.0 + i + seed);
        m->kd = (float)(2.0 + 0.01 * i);
    }
    c->reserve[0] = 0xDEADBEEFu; /* under the CRC, and on the wire */
    c->crc = crc_image(c, 250);
}

static void publish_command(const g1_lowcmd_t *c)
{
    assert_true(dds_write(cmd_writer, c) >= 0);
}

/* Poll "commands" until it reads @p good @p bad (or fail). */
static void await_counts(fk_t *k, uint64_t good, uint64_t bad)
{
    char want[64];
    snprintf(want, sizeof want, "ok %llu %llu", (unsigned long long)good,
             (unsigned long long)bad);
    const char *r = "";
    for (int i = 0; i < WIRE_MS / 5; i++) {
        r = fk_req(k, "commands");
        if (strcmp(r, want) == 0)
            return;
        dds_sleepfor(DDS_MSECS(5));
    }
    fail_msg("commands: '%s', want '%s'", r, want);
}

/* The reply to @p req ("command", "command_at K") must give @p c's values
 * exactly. */
static void expect_command_reply(fk_t *k, const char *req, const g1_lowcmd_t *c)
{
    const char *r = fk_req(k, "%s", req);
    char *end;
    if (strncmp(r, "ok ", 3) != 0)
        fail_msg("command -> '%.80s'", r);
    const char *p = r + 3;
    double v[2 + 35 * 6];
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        v[i] = strtod(p, &end);
        if (end == p)
            fail_msg("command: value %zu missing in '%.80s'", i, r);
        p = end;
    }
    assert_string_equal(p, "");
    assert_true(v[0] == c->mode_pr && v[1] == c->mode_machine);
    for (int i = 0; i < 35; i++) {
        const double *g = &v[2 + 6 * i];
        const g1_motorcmd_t *m = &c->motor_cmd[i];
        if (g[0] != m->mode || g[1] != (double)m->q || g[2] != (double)m->dq ||
            g[3] != (double)m->tau || g[4] != (double)m->kp || g[5] != (double)m->kd)
            fail_msg("command: motor %d is %g %g %g %g %g %g", i, g[0], g[1], g[2], g[3], g[4],
                     g[5]);
    }
}

/* "command" must give @p c's values exactly. */
static void expect_command(fk_t *k, const g1_lowcmd_t *c)
{
    expect_command_reply(k, "command", c);
}

/* "command_at K" must give @p c's values exactly. */
static void expect_command_at(fk_t *k, uint64_t at, const g1_lowcmd_t *c)
{
    char req[64];
    snprintf(req, sizeof req, "command_at %llu", (unsigned long long)at);
    expect_command_reply(k, req, c);
}

static void default_args(const char **args, char *dom)
{
    snprintf(dom, 16, "%u", domain_id);
    args[0] = "--domain";
    args[1] = dom;
    args[2] = NULL;
}

/* ---- the cases ----------------------------------------------------------- */

static void test_fake_g1_crc_reference(void **st)
{
    static const g1_lowcmd_t zero_cmd;
    uint32_t zero[250] = { 0 };
    uint32_t w[522];
    uint32_t x = 2463534242u;
    (void)st;
    /* CRC-32/MPEG-2's check value, fed byte by byte */
    uint32_t crc = G1_CRC_INIT;
    for (const char *s = "123456789"; *s != '\0'; s++)
        crc = g1_crc_feed(crc, (uint8_t)*s, 8);
    assert_int_equal(crc, 0x0376E6E7u);
    assert_int_equal(mpeg2(0xFFFFFFFFu, (const uint8_t *)"123456789", 9), 0x0376E6E7u);
    /* an all-zero LowCmd_: 250 zero words */
    assert_int_equal(g1_crc_words(zero, 250), 0xFE172F9Fu);
    assert_int_equal(g1_lowcmd_crc(&zero_cmd), 0xFE172F9Fu);
    assert_int_equal(crc_image(&zero_cmd, 250), 0xFE172F9Fu);
    /* the fake's bit-by-bit CRC and this file's byte-wise one agree */
    for (size_t i = 0; i < 522; i++) {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        w[i] = x;
    }
    for (size_t n = 0; n <= 522; n += 29)
        assert_int_equal(g1_crc_words(w, n), crc_image(w, n));
    /* and any one bit flipped changes it */
    uint32_t good = g1_crc_words(w, 522);
    for (size_t bit = 0; bit < 522 * 32; bit += 97) {
        w[bit / 32] ^= 1u << (bit % 32);
        assert_int_not_equal(g1_crc_words(w, 522), good);
        w[bit / 32] ^= 1u << (bit % 32);
    }
}

/* The XTypes identifiers (minimal and complete) that Cyclone DDS 0.10.2
 * computed for Unitree's own MotorState_ and IMUState_, as recorded in
 * unitree_sdk2's generated include/unitree/idl/hg/HandState_.hpp (which
 * nests both). idlc computes the same hashes from this folder's IDL only
 * if every name, type, length and annotation is the same. */
static void expect_type_id(const dds_topic_descriptor_t *d, const char *name,
                           const uint8_t *minimal, const uint8_t *complete)
{
    const uint8_t *ti = d->type_information.data;
    size_t n = d->type_information.sz;
    int got_min = 0, got_complete = 0;
    for (size_t i = 0; i + 14 <= n; i++) {
        got_min |= memcmp(ti + i, minimal, 14) == 0;
        got_complete |= memcmp(ti + i, complete, 14) == 0;
    }
    if (!got_min || !got_complete)
        fail_msg("%s: type identifiers differ from Unitree's (minimal %s, complete %s)", name,
                 got_min ? "same" : "different", got_complete ? "same" : "different");
}

static void test_fake_g1_types_are_unitrees(void **st)
{
    static const uint8_t motor_min[14] = { 0xf1, 0x7c, 0xc5, 0x84, 0xed, 0x94, 0x0b,
                                           0x8f, 0x30, 0x18, 0xf1, 0x8d, 0xe0, 0xed };
    static const uint8_t motor_complete[14] = { 0xf2, 0xa8, 0x6c, 0xba, 0xb3, 0xae, 0x0a,
                                                0xa9, 0x8a, 0x1e, 0x74, 0x66, 0x43, 0xa0 };
    static const uint8_t imu_min[14] = { 0xf1, 0xfc, 0x68, 0x71, 0x76, 0x65, 0x12,
                                         0x06, 0x55, 0x84, 0x73, 0xdf, 0x44, 0x22 };
    static const uint8_t imu_complete[14] = { 0xf2, 0x7d, 0x41, 0x66, 0x75, 0x41, 0x77,
                                              0xd8, 0x6f, 0xa2, 0x7c, 0xd2, 0x5b, 0x04 };
    (void)st;
    expect_type_id(&unitree_hg_msg_dds__MotorState__desc, "MotorState_", motor_min,
                   motor_complete);
    expect_type_id(&unitree_hg_msg_dds__IMUState__desc, "IMUState_", imu_min, imu_complete);
    assert_string_equal(unitree_hg_msg_dds__LowCmd__desc.m_typename,
                        "unitree_hg::msg::dds_::LowCmd_");
    assert_string_equal(unitree_hg_msg_dds__LowState__desc.m_typename,
                        "unitree_hg::msg::dds_::LowState_");
}

/* Bad command lines: exit status 2 and a message naming the option. */
static void refused(const char *const *args, const char *want)
{
    char msg[4096];
    size_t n = 0;
    fk_spawn(&fake, args, 1);
    close(fake.in);
    fake.in = -1;
    for (;;) {
        struct pollfd p = { fake.err, POLLIN, 0 };
        assert_true(poll(&p, 1, REPLY_MS) == 1);
        ssize_t got = read(fake.err, msg + n, sizeof msg - 1 - n);
        if (got <= 0)
            break;
        n += (size_t)got;
    }
    msg[n] = '\0';
    int status = fk_wait(&fake);
    fk_close(&fake);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 2);
    if (strstr(msg, want) == NULL)
        fail_msg("refused without naming '%s': %s", want, msg);
}

static void test_fake_g1_bad_options(void **st)
{
    (void)st;
    refused((const char *const[]){ NULL }, "--domain is required");
    refused((const char *const[]){ "--domain", "233", NULL }, "--domain '233'");
    refused((const char *const[]){ "--domain", "-1", NULL }, "--domain");
    refused((const char *const[]){ "--domain", "1", "--interface", "eth0", NULL },
            "--interface eth0 refused");
    refused((const char *const[]){ "--domain", "1", "--interface", "l<o", NULL }, "--interface");
    refused((const char *const[]){ "--domain", "1", "--period-us", "x", NULL }, "--period-us");
    refused((const char *const[]){ "--domain", "1", "--period-us", "99", NULL },
            "--period-us 99");
    refused((const char *const[]){ "--domain", "1", "--mode-machine", "256", NULL },
            "--mode-machine '256'");
    refused((const char *const[]){ "--domain", "1", "--bogus", NULL }, "'--bogus'");
}

/* Start a fake with @p extra options after --domain; wait until this
 * reader has discovered its state writer and the stream is in step. */
static uint32_t start_synced(const char *extra0, const char *extra1)
{
    char dom[16];
    const char *args[6];
    default_args(args, dom);
    args[2] = extra0;
    args[3] = extra1;
    args[4] = NULL;
    drain_states();
    uint32_t seen = state_matches();
    fk_start(&fake, args);
    await_state_writer(seen + 1);
    return sync_states(&fake);
}

static float q_of(int i) { return (float)(0.1 * i - 1.7 + 1e-7 * i); }
static float dq_of(int i) { return (float)(-0.25 * (i + 1)); }
static float tau_of(int i) { return (float)(1.5 * i - 3.0 + 1.0 / 3.0); }

static void test_fake_g1_send(void **st)
{
    g1_lowstate_t s, got, want;
    (void)st;
    uint32_t t = start_synced("--mode-machine", "9");

    /* at rest: upright, still, the --mode-machine given */
    assert_int_equal(fk_ok_n(&fake, "send"), t + 1);
    expect_frame(&s, t + 1);
    assert_true(state_crc_ok(&s));
    assert_int_equal(s.mode_machine, 9);
    assert_int_equal(s.mode_pr, 0);
    assert_true(s.imu_state.quaternion[0] == 1.0f && s.imu_state.quaternion[3] == 0.0f);

    for (int i = 0; i < 35; i++)
        fk_ok(&fake, "motor %d %.17g %.17g %.17g", i, (double)q_of(i), (double)dq_of(i),
              (double)tau_of(i));
    fk_ok(&fake, "motorstate 7 8193");
    fk_ok(&fake, "motorstate 34 4294967295");
    fk_ok(&fake, "imu 0.9 0.1 -0.2 0.3 0.01 -0.02 0.03 0.5 -0.6 9.81");
    fk_ok(&fake, "mode_pr 1");
    fk_ok(&fake, "mode_machine 13");
    assert_int_equal(fk_ok_n(&fake, "send"), t + 2);
    expect_frame(&s, t + 2);

    /* the whole frame, CRC included, as this test builds it */
    memset(&want, 0, sizeof want);
    want.mode_pr = 1;
    want.mode_machine = 13;
    want.tick = t + 2;
    const float imu[10] = { 0.9f, 0.1f, -0.2f, 0.3f, 0.01f, -0.02f, 0.03f, 0.5f, -0.6f, 9.81f };
    for (int i = 0; i < 4; i++)
        want.imu_state.quaternion[i] = imu[i]; /* w, x, y, z */
    for (int i = 0; i < 3; i++) {
        want.imu_state.gyroscope[i] = imu[4 + i];
        want.imu_state.accelerometer[i] = imu[7 + i];
    }
    for (int i = 0; i < 35; i++) {
        want.motor_state[i].q = q_of(i);
        want.motor_state[i].dq = dq_of(i);
        want.motor_state[i].tau_est = tau_of(i);
    }
    want.motor_state[7].motorstate = 8193;
    want.motor_state[34].motorstate = 4294967295u;
    want.crc = crc_image(&want, 522);
    state_rebuild(&got, &s);
    assert_memory_equal(&got, &want, sizeof want);
    assert_true(state_crc_ok(&s));

    /* the same frame as it travelled: CDR aligns each primitive, not each
     * struct, so the payload is 2088 bytes and motor_state[0] starts at 70
     * (natively 72); later slots every 56 bytes from 124 */
    uint8_t w[4096];
    const uint8_t *p = w + 4;
    do
        assert_int_equal(take_wire(state_wire, w, sizeof w), 4 + 2088);
    while (le32(p + 12) != t + 2);
    expect_xcdr1_le(w);
    assert_true(p[8] == 1 && p[9] == 13);
    expect_le_float(p + 16, 0.9f, "quaternion w");
    expect_le_float(p + 28, 0.3f, "quaternion z");
    for (int i = 0; i < 35; i++) {
        const uint8_t *m = i == 0 ? p + 70 : p + 124 + 56 * (i - 1);
        expect_le_float(m + (i == 0 ? 2 : 4), q_of(i), "motor_state[].q");
        expect_le_float(m + (i == 0 ? 6 : 8), dq_of(i), "motor_state[].dq");
        expect_le_float(m + (i == 0 ? 14 : 16), tau_of(i), "motor_state[].tau_est");
    }
    assert_int_equal(le32(p + 124 + 56 * 6 + 36), 8193);            /* [7].motorstate */
    assert_int_equal(le32(p + 124 + 56 * 33 + 36), 4294967295u);    /* [34].motorstate */
    assert_int_equal(le32(p + 2084), want.crc);
    fk_quit(&fake);
}

/* Until the fake's reader knows this writer a command may go nowhere:
 * publish @p c until one is counted. The GOOD count after. */
static uint64_t prime_commands(const g1_lowcmd_t *c)
{
    await_cmd_reader();
    for (int i = 0; i < 100; i++) {
        publish_command(c);
        if (strncmp(fk_req(&fake, "wait_commands 1 100"), "ok ", 3) == 0)
            return fk_ok_n(&fake, "wait_commands 1 0");
    }
    fail_msg("no command reached the fake");
    return 0;
}

static void test_fake_g1_frames(void **st)
{
    g1_lowstate_t s, good, again;
    g1_lowcmd_t c;
    (void)st;
    uint32_t t = start_synced("--period-us", "0");
    fk_ok(&fake, "motor 0 0.5 0 0");

    /* corrupt: the next tick, one bit off after the CRC */
    assert_int_equal(fk_ok_n(&fake, "corrupt"), t + 1);
    expect_frame(&s, t + 1);
    assert_false(state_crc_ok(&s));
    uint32_t bits;
    memcpy(&bits, &s.motor_state[0].q, sizeof bits);
    bits ^= 1u;
    memcpy(&s.motor_state[0].q, &bits, sizeof bits);
    assert_true(state_crc_ok(&s)); /* that one bit, nothing else */
    assert_true(s.motor_state[0].q == 0.5f);

    /* send goes on after it; replay repeats the last good frame exactly */
    assert_int_equal(fk_ok_n(&fake, "send"), t + 2);
    expect_frame(&s, t + 2);
    assert_true(state_crc_ok(&s));
    state_rebuild(&good, &s);
    assert_int_equal(fk_ok_n(&fake, "replay"), t + 2);
    expect_frame(&s, t + 2);
    state_rebuild(&again, &s);
    assert_memory_equal(&again, &good, sizeof good);
    assert_string_equal(fk_req(&fake, "silent"), "ok");
    assert_false(take_state(&s, 50)); /* silent sends nothing */

    /* restart: a new writer, tick 0, the last command forgotten */
    make_command(&c, 0);
    uint64_t g = prime_commands(&c);
    expect_command(&fake, &c);
    uint32_t seen = state_matches();
    fk_ok(&fake, "restart");
    await_state_writer(seen + 1);
    assert_int_equal(fk_ok_n(&fake, "send"), 0);
    expect_frame(&s, 0);
    assert_true(state_crc_ok(&s));
    assert_int_equal(fk_ok_n(&fake, "send"), 1);
    expect_frame(&s, 1);
    assert_string_equal(fk_req(&fake, "command"), "err none");
    char want[64];
    snprintf(want, sizeof want, "ok %llu 0", (unsigned long long)g);
    assert_string_equal(fk_req(&fake, "commands"), want); /* counters stay */
    fk_quit(&fake);
}

static void test_fake_g1_commands(void **st)
{
    g1_lowcmd_t c0, c1, c2, c3, c4, c5, c6;
    char want[64];
    (void)st;
    (void)start_synced("--mode-machine", "5");
    assert_string_equal(fk_req(&fake, "command"), "err none");
    make_command(&c0, 0);
    uint64_t g = prime_commands(&c0);
    await_counts(&fake, g, 0);
    expect_command(&fake, &c0);
    /* discovery from the fake's side: its command reader matched our
     * writer, its state writer our reader */
    unsigned mw = 0, mr = 0;
    assert_int_equal(sscanf(fk_req(&fake, "matched"), "ok %u %u", &mw, &mr), 2);
    assert_true(mw >= 1 && mr >= 1);

    /* good: counted and applied */
    make_command(&c1, 1);
    drain_wire(cmd_wire);
    publish_command(&c1);
    await_counts(&fake, g + 1, 0);
    expect_command(&fake, &c1);

    /* c1 as it travelled: 1000 bytes, motor_cmd[i] at 28 i (its mode at 2
     * for i = 0), reserve at 980, crc at 996 */
    uint8_t w[2048];
    const uint8_t *p = w + 4;
    assert_int_equal(take_wire(cmd_wire, w, sizeof w), 4 + 1000);
    expect_xcdr1_le(w);
    assert_true(p[0] == c1.mode_pr && p[1] == c1.mode_machine && p[2] == c1.motor_cmd[0].mode);
    for (int i = 0; i < 35; i++) {
        const uint8_t *m = p + 28 * i;
        if (i > 0)
            assert_int_equal(m[0], c1.motor_cmd[i].mode);
        expect_le_float(m + 4, c1.motor_cmd[i].q, "motor_cmd[].q");
        expect_le_float(m + 20, c1.motor_cmd[i].kd, "motor_cmd[].kd");
    }
    assert_int_equal(le32(p + 980), 0xDEADBEEFu);
    assert_int_equal(le32(p + 996), c1.crc);

    /* a wrong CRC: counted bad, the last good command stays */
    make_command(&c2, 2);
    c2.crc ^= 0x80000000u;
    publish_command(&c2);
    await_counts(&fake, g + 1, 1);
    expect_command(&fake, &c1);

    /* a sender that CRCs its padding garbage: bad on the robot, which
     * rebuilds the struct from the wire over zeroes */
    make_command(&c4, 3);
    memset(&c3, 0xA5, sizeof c3);
    c3.mode_pr = c4.mode_pr;
    c3.mode_machine = c4.mode_machine;
    for (int i = 0; i < 35; i++) {
        c3.motor_cmd[i].mode = c4.motor_cmd[i].mode;
        c3.motor_cmd[i].q = c4.motor_cmd[i].q;
        c3.motor_cmd[i].dq = c4.motor_cmd[i].dq;
        c3.motor_cmd[i].tau = c4.motor_cmd[i].tau;
        c3.motor_cmd[i].kp = c4.motor_cmd[i].kp;
        c3.motor_cmd[i].kd = c4.motor_cmd[i].kd;
        c3.motor_cmd[i].reserve = c4.motor_cmd[i].reserve;
    }
    memcpy(c3.reserve, c4.reserve, sizeof c3.reserve);
    c3.crc = crc_image(&c3, 250);
    assert_int_not_equal(c3.crc, c4.crc); /* the padding is under the CRC */
    publish_command(&c3);
    await_counts(&fake, g + 1, 2);
    expect_command(&fake, &c1);
    publish_command(&c4); /* the same values over zero padding */
    await_counts(&fake, g + 2, 2);
    expect_command(&fake, &c4);

    /* flip_next_command: the next one is lost to a flipped bit */
    fk_ok(&fake, "flip_next_command");
    make_command(&c5, 5);
    publish_command(&c5);
    await_counts(&fake, g + 2, 3);
    expect_command(&fake, &c4);
    make_command(&c6, 6);
    publish_command(&c6);
    await_counts(&fake, g + 3, 3);
    expect_command(&fake, &c6);

    /* wait_commands */
    snprintf(want, sizeof want, "ok %llu", (unsigned long long)(g + 3));
    assert_string_equal(fk_req(&fake, "wait_commands %llu 0", (unsigned long long)(g + 3)), want);
    snprintf(want, sizeof want, "err timeout %llu", (unsigned long long)(g + 3));
    assert_string_equal(fk_req(&fake, "wait_commands %llu 50", (unsigned long long)(g + 4)),
                        want);

    /* command_at: every good one by its number, bad ones not numbered */
    expect_command_at(&fake, g + 1, &c1);
    expect_command_at(&fake, g + 2, &c4);
    expect_command_at(&fake, g + 3, &c6);
    expect_command_at(&fake, g, &c0);
    assert_true(strncmp(fk_req(&fake, "command_at %llu", (unsigned long long)(g + 4)),
                        "err command_at", 14) == 0);
    assert_true(strncmp(fk_req(&fake, "command_at 0"), "err command_at", 14) == 0);
    fk_quit(&fake);
}

static void test_fake_g1_malformed(void **st)
{
    static const struct {
        const char *line, *want;
    } bad[] = {
        { "", "err empty request" },
        { " \t ", "err empty request" },
        { "bogus", "err unknown request 'bogus'" },
        { "SEND", "err unknown request 'SEND'" },
        { "motor", "err motor: takes 4 arguments" },
        { "motor 1 0 0", "err motor: takes 4 arguments" },
        { "motor 1 0 0 0 0", "err motor: takes 4 arguments" },
        { "motor 35 0 0 0", "err motor: argument 1 '35' is not a motor slot" },
        { "motor -1 0 0 0", "err motor: argument 1 '-1'" },
        { "motor 1 x 0 0", "err motor: argument 2 'x'" },
        { "motor 1 0 1e400 0", "err motor: argument 3 '1e400'" },
        { "motor 1 0 0 1e39", "err motor: argument 4 '1e39'" },
        { "motorstate 0 4294967296", "err motorstate: argument 2" },
        { "motorstate 0 0x10", "err motorstate: argument 2" },
        { "imu 1 0 0 0 0 0 0 0 0", "err imu: takes 10 arguments" },
        { "mode_pr 256", "err mode_pr: argument 1 '256'" },
        { "mode_machine +5", "err mode_machine: argument 1 '+5'" },
        { "send now", "err send: takes 0 arguments" },
        { "quit now", "err quit: takes 0 arguments" },
        { "wait_commands 1", "err wait_commands: takes 2 arguments" },
        { "wait_commands 1 600001", "err wait_commands: argument 2 '600001'" },
        { "wait_commands 99999999999 1", "err wait_commands: argument 1" },
        { "flip_next_command 1", "err flip_next_command: takes 0 arguments" },
        { "command", "err none" },
        { "replay", "err replay: nothing sent yet" },
    };
    char dom[16];
    const char *args[4];
    (void)st;
    default_args(args, dom);
    fk_start(&fake, args);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        const char *r = fk_req(&fake, "%s", bad[i].line);
        if (strncmp(r, bad[i].want, strlen(bad[i].want)) != 0)
            fail_msg("'%s' -> '%s', want '%s...'", bad[i].line, r, bad[i].want);
    }
    char longline[3000];
    memset(longline, 'a', sizeof longline - 1);
    longline[sizeof longline - 1] = '\0';
    assert_string_equal(fk_req(&fake, "%s", longline), "err request longer than 1024 bytes");
    fk_write(&fake, "send\0x\n", 7);
    assert_string_equal(fk_line(&fake), "err request contains a NUL byte");
    /* none of that changed anything; NaN and infinities pass */
    fk_ok(&fake, "motor 1 nan inf -inf");
    fk_ok(&fake, "motorstate 0 4294967295");
    fk_ok(&fake, "silent");
    assert_int_equal(fk_ok_n(&fake, "send"), 0);
    assert_string_equal(fk_req(&fake, "commands"), "ok 0 0");
    fk_quit(&fake);
}

static void test_fake_g1_eof_exits_0(void **st)
{
    char dom[16];
    const char *args[4];
    (void)st;
    default_args(args, dom);
    fk_start(&fake, args);
    fk_ok(&fake, "silent");
    fk_write(&fake, "send", 4); /* a last line without its newline counts */
    close(fake.in);
    fake.in = -1;
    assert_string_equal(fk_line(&fake), "ok 0");
    assert_null(fk_line(&fake));
    int status = fk_wait(&fake);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 0);
}

static void test_fake_g1_period(void **st)
{
    g1_lowstate_t s;
    char dom[16];
    const char *args[6];
    (void)st;
    default_args(args, dom);
    args[2] = "--period-us";
    args[3] = "2000";
    args[4] = NULL;
    drain_states();
    uint32_t seen = state_matches();
    fk_start(&fake, args);
    await_state_writer(seen + 1);
    /* nothing asked for, frames come: good, ticks rising */
    uint32_t last = 0;
    for (int i = 0; i < 50; i++) {
        if (!take_state(&s, WIRE_MS))
            fail_msg("frame %d of the periodic stream missing", i);
        assert_true(state_crc_ok(&s));
        if (i > 0)
            assert_true(s.tick > last);
        last = s.tick;
    }
    fk_quit(&fake);
}

/* ---- garbage in, one reply per line, no crash ---------------------------- */

static uint64_t rng_state;

static uint32_t rnd(uint32_t n)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)((rng_state >> 33) % n);
}

static size_t random_line(char *buf, size_t cap)
{
    static const char *const verbs[] = {
        "motor",   "motorstate", "imu",      "mode_machine",  "mode_pr", "send",
        "corrupt", "replay",     "restart",  "silent",        "commands", "wait_commands",
        "command", "flip_next_command",      "Motor", "sendx", "q", "",
    };
    static const char *const toks[] = {
        "0",    "1",     "34",   "35",   "-1",   "255",  "256",  "4294967295", "4294967296",
        "18446744073709551616",  "1e400", "-1e400", "1e39", "nan", "-nan", "inf", "-inf",
        "infinity", "1.5", "-0", "0x10", "+3", "1e-400", "abc", "\t", "\r", "", "1,5", "0.",
    };
    size_t n = 0;
    if (rnd(10) < 4) { /* bytes */
        uint32_t kind = rnd(20);
        size_t len = kind < 14 ? rnd(60) : kind < 19 ? 60 + rnd(940) : 1000 + rnd(2000);
        for (; n < len && n + 1 < cap; n++) {
            char c = (char)(1 + rnd(255));
            buf[n] = c == '\n' ? ' ' : c;
        }
        if (len > 0 && rnd(10) == 0)
            buf[rnd((uint32_t)n)] = '\0';
    } else { /* words */
        n = (size_t)snprintf(buf, cap, "%s", verbs[rnd(sizeof verbs / sizeof verbs[0])]);
        uint32_t k = rnd(13);
        for (uint32_t i = 0; i < k && n + 40 < cap; i++) {
            buf[n++] = rnd(8) == 0 ? '\t' : ' ';
            if (rnd(10) == 0) {
                for (uint32_t j = rnd(8); j > 0; j--) {
                    char c = (char)(1 + rnd(255));
                    buf[n++] = c == '\n' ? 'x' : c;
                }
            } else {
                n += (size_t)snprintf(buf + n, cap - n, "%s",
                                      toks[rnd(sizeof toks / sizeof toks[0])]);
            }
        }
    }
    buf[n] = '\0';
    return n;
}

/* Whether the fake would take @p line (up to a NUL) for "quit". */
static int is_quit(const char *line)
{
    const char *p = line + strspn(line, " \t\r");
    return strncmp(p, "quit", 4) == 0 && (p[4] == '\0' || strchr(" \t\r", p[4]) != NULL);
}

static void test_fake_g1_garbage(void **st)
{
    char line[4096];
    char dom[16];
    const char *args[4];
    (void)st;
    const char *seed = getenv("FAKE_G1_SEED");
    rng_state = seed != NULL ? strtoull(seed, NULL, 0) : 20240613u;
    const char *count = getenv("FAKE_G1_GARBAGE_LINES");
    long lines = count != NULL ? strtol(count, NULL, 10) : 3000;
    print_message("%ld garbage lines, seed %llu (FAKE_G1_GARBAGE_LINES, FAKE_G1_SEED)\n", lines,
                  (unsigned long long)rng_state);
    default_args(args, dom);
    fk_start(&fake, args);
    for (long i = 0; i < lines; i++) {
        size_t n;
        do
            n = random_line(line, sizeof line - 1);
        while (is_quit(line));
        line[n] = '\n';
        fk_write(&fake, line, n + 1);
        const char *r = fk_line(&fake);
        if (r == NULL)
            fail_msg("fake_g1 died on garbage line %ld", i);
        if (strncmp(r, "ok", 2) != 0 && strncmp(r, "err ", 4) != 0)
            fail_msg("garbage line %ld -> '%.80s'", i, r);
        if (strncmp(r, "ok", 2) == 0 && r[2] != '\0' && r[2] != ' ')
            fail_msg("garbage line %ld -> '%.80s'", i, r);
    }
    (void)fk_ok_n(&fake, "send"); /* still a robot */
    fk_quit(&fake);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fake_g1_crc_reference),
        cmocka_unit_test(test_fake_g1_types_are_unitrees),
        cmocka_unit_test_setup_teardown(test_fake_g1_bad_options, case_setup, case_teardown),
        cmocka_unit_test_setup_teardown(test_fake_g1_send, case_setup, case_teardown),
        cmocka_unit_test_setup_teardown(test_fake_g1_frames, case_setup, case_teardown),
        cmocka_unit_test_setup_teardown(test_fake_g1_commands, case_setup, case_teardown),
        cmocka_unit_test_setup_teardown(test_fake_g1_malformed, case_setup, case_teardown),
        cmocka_unit_test_setup_teardown(test_fake_g1_eof_exits_0, case_setup, case_teardown),
        cmocka_unit_test_setup_teardown(test_fake_g1_period, case_setup, case_teardown),
        cmocka_unit_test_setup_teardown(test_fake_g1_garbage, case_setup, case_teardown),
    };
    if (argc < 2) {
        fprintf(stderr, "usage: test_fake_g1 PATH_OF_FAKE_G1\n");
        return 2;
    }
    fake_path = argv[1];
    const char *d = getenv("ROZ_TEST_DDS_DOMAIN");
    if (d != NULL)
        domain_id = (uint32_t)strtoul(d, NULL, 10);
    signal(SIGPIPE, SIG_IGN);
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
