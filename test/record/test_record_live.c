/* SPDX-License-Identifier: Apache-2.0 */
/* roz/record_live.h (docs/live.md): the live stream never waits for its
 * reader. A tick thread runs the UR5 on the loopback while this thread
 * drains the recorder into a stream whose pipe nobody reads: every tick
 * runs, the stream drops whole ticks and counts them, and the pipe holds
 * the stream's start and exactly the ticks counted as sent, each one chunk.
 * Under TSan (label threads) the drain races the tick; a reader that went
 * away ends the stream without a signal. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "roz/record_live.h"
#include "roz/recorder.h"
#include "roz/runtime.h"
#include "support_runtime.h"
#include "support_stats.h"
#include "ur5_manifest.h"

#define TICKS 20000u

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_recorder_t rec;
static uint64_t storage[(1u << 20) / 8u];
static roz_record_live_t live;
static atomic_uint ticked;

static void start(void)
{
    roz_runtime_config_t cfg;
    static roz_test_clock_t clk;
    size_t len;
    (void)roz_test_controller("sine", &len);
    clk.now = 1;
    clk.step = 100;
    assert_int_equal(roz_recorder_init(&rec, &roz_manifest_ur5, storage, sizeof storage, 1),
                     ROZ_OK);
    roz_test_loopback_config(&cfg, &lb, &roz_manifest_ur5, NULL, &clk);
    cfg.recorder = &rec;
    roz_test_runtime_start(&rt, &cfg, "sine");
}

static int to_live(void *ctx, const roz_record_t *r)
{
    (void)ctx;
    roz_record_live_put(&live, r);
    return 0;
}

static void *ticker(void *arg)
{
    (void)arg;
    for (unsigned t = 0; t < TICKS; t++) {
        roz_test_tick(&rt);
        atomic_store(&ticked, t + 1u);
    }
    return NULL;
}

static void open_live(int fd)
{
    char path[32], err[256];
    snprintf(path, sizeof path, "/dev/fd/%d", fd);
    roz_record_file_options_t opt = { "sine.wasm", 0, ROZ_MCAP_COMPRESS_NONE };
    int rc = roz_record_live_open(&live, path, &rt, &rec, &opt, err, sizeof err);
    if (rc != ROZ_OK)
        fail_msg("roz_record_live_open: %s", err);
}

/* The pipe's bytes: the magic, then records; the whole chunks counted
 * (-1: not a stream). A stream closed while its reader was behind may end
 * in part of a tick's chunk (it was being written): *torn says so. */
static long count_chunks(const unsigned char *p, size_t n, int *torn)
{
    static const unsigned char magic[8] = { 0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n' };
    long chunks = 0;
    size_t at = 8;
    *torn = 0;
    if (n < 8 || memcmp(p, magic, 8) != 0)
        return -1;
    while (at < n) {
        uint64_t len = 0;
        for (int i = 0; i < 8 && at + 1u + (size_t)i < n; i++)
            len |= (uint64_t)p[at + 1u + (size_t)i] << (8 * i);
        if (n - at < 9 || len > n - at - 9u) {
            *torn = p[at] == 0x06;
            return *torn ? chunks : -1;
        }
        chunks += p[at] == 0x06;
        at += 9u + (size_t)len;
    }
    return chunks;
}

static void test_live_reader_never_reads(void **st)
{
    int fds[2];
    pthread_t th;
    (void)st;

    start();
    assert_int_equal(pipe(fds), 0);
    open_live(fds[1]);
    atomic_store(&ticked, 0u);
    assert_int_equal(pthread_create(&th, NULL, ticker, NULL), 0);
    while (atomic_load(&ticked) < TICKS) {
        (void)roz_recorder_drain(&rec, to_live, NULL, 0);
        roz_record_live_flush(&live);
    }
    pthread_join(th, NULL);
    (void)roz_recorder_drain(&rec, to_live, NULL, 0);
    roz_record_live_close(&live, 0);
    close(fds[1]);

    uint64_t put = roz_record_live_ticks(&live), sent = roz_record_live_sent(&live);
    uint64_t dropped = roz_record_live_dropped(&live);
    print_message("live: %u ticks, %llu put, %llu sent, %llu dropped, %u lost in the ring\n",
                  TICKS, (unsigned long long)put, (unsigned long long)sent,
                  (unsigned long long)dropped, (unsigned)roz_recorder_dropped(&rec));
    assert_int_equal(RT_COUNT(&rt, ticks), TICKS);
    assert_int_equal(put + roz_recorder_dropped(&rec), TICKS);
    assert_int_equal(sent + dropped, put);
    assert_true(dropped > 0);
    assert_string_equal(roz_record_live_error(&live), "the viewer was still behind at the end");

    static unsigned char buf[1u << 20];
    size_t n = 0;
    ssize_t k;
    while ((k = read(fds[0], buf + n, sizeof buf - n)) > 0)
        n += (size_t)k;
    close(fds[0]);
    assert_true(n < sizeof buf);
    /* the start's chunk (schemas, channels, /roz/run), then one a tick,
     * each whole but perhaps the last, cut at the close */
    int torn;
    assert_int_equal(count_chunks(buf, n, &torn), (long)(1u + sent));
    roz_runtime_deinit(&rt);
}

static void test_live_reader_gone(void **st)
{
    int fds[2];
    (void)st;

    start();
    assert_int_equal(pipe(fds), 0);
    close(fds[0]);
    open_live(fds[1]);
    for (unsigned t = 0; t < 100u; t++) {
        roz_test_tick(&rt);
        (void)roz_recorder_drain(&rec, to_live, NULL, 0);
        roz_record_live_flush(&live);
    }
    roz_record_live_close(&live, 1000);
    close(fds[1]);
    assert_int_equal(roz_record_live_ticks(&live), 100);
    assert_int_equal(roz_record_live_sent(&live), 0);
    assert_int_equal(roz_record_live_dropped(&live), 100);
    assert_string_equal(roz_record_live_error(&live), "the viewer went away");
    roz_runtime_deinit(&rt);
}

static void test_live_refuses(void **st)
{
    char err[256];
    (void)st;
    start();
    roz_record_file_options_t opt = { NULL, 0, ROZ_MCAP_COMPRESS_NONE };
    assert_int_equal(roz_record_live_open(&live, "-", &rt, &rec, &opt, err, sizeof err),
                     ROZ_EINVAL);
    assert_non_null(strstr(err, "not standard output"));
    assert_int_equal(roz_record_live_open(&live, "/nonexistent/dir/x.live", &rt, &rec, &opt,
                                          err, sizeof err),
                     ROZ_EIO);
    assert_non_null(strstr(err, "/nonexistent/dir/x.live: cannot open"));
    roz_runtime_deinit(&rt);
}

int main(void)
{
    /* a reader that went away: EPIPE, never the signal (roz/record_live.h) */
    signal(SIGPIPE, SIG_IGN);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_live_reader_never_reads),
        cmocka_unit_test(test_live_reader_gone),
        cmocka_unit_test(test_live_refuses),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
