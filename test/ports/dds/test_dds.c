/* SPDX-License-Identifier: Apache-2.0 */
/* roz::dds (roz/port/dds.h), on loopback only, inside a private network namespace
 * where permitted (run_netns.sh):
 *  - parameters: defaults, and every bad value refused naming key and value;
 *  - the configuration: lo alone, multicast off, peer 127.0.0.1, participant
 *    index raised; another interface alone; a name that is not one refused;
 *  - the participant: an interface that does not exist is named; a user's
 *    CYCLONEDDS_URI wins and the log says so;
 *  - the periodic writer publishes what the port fills, the receive path
 *    takes every sample into zeroed preallocated storage (its padding zero
 *    whatever was there), the monitor sees the writer's jitter and passes
 *    and the state handler; a stopped writer publishes no more;
 *  - the event-driven writer publishes when woken, and only then; one that
 *    spins for the tick's command publishes nothing on a heads-up alone,
 *    each frame once after it, and stops while spinning;
 *  - a kept reader (a type with a string and a sequence, sized at open)
 *    takes into the same buffers sample after sample, and lets Cyclone grow
 *    them for a longer one; a writer without a thread of its own publishes
 *    from another writer's pass;
 *  - the command path (roz_dds_cmd) over a port's hooks: nothing before
 *    the first state frame, the start-up hold for each robot, frames
 *    clamped, a frame for a robot that restarted not sent, the port's
 *    refusal, the watchdog's damping and its report (on a clock the test
 *    moves: a frame is exactly as old as it says), the damping on stop
 *    only to a robot that got a command;
 *  - two processes find each other with roz's configuration for lo (no
 *    multicast: through the peer) and echo frames both ways.
 * Timeouts here guard against a hang; no test asserts a time. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <sched.h>
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

#include "proc_threads.h"

#include "roz/port/dds.h"
#include "roz/hal/clock.h"
#include "roz_dds_test.h"

#ifndef ROZ_TEST_DDS_DOMAIN
#define ROZ_TEST_DDS_DOMAIN 10
#define ROZ_TEST_DDS_DOMAINS 2
#endif
/* the two-process case meets on the second of its ids (test/CMakeLists.txt) */
_Static_assert(ROZ_TEST_DDS_DOMAINS >= 2, "test_dds takes two DDS domain ids");

#include "support.h"
#include "support_spawn.h"

static char self_path[4096];
static char arg_echo[] = "--echo";

static void sleep_ms(unsigned ms)
{
    struct timespec ts = { (time_t)(ms / 1000u), (long)(ms % 1000u) * 1000000L };
    nanosleep(&ts, NULL);
}

/* Polls @p cond every millisecond for at most @p ms: a hang guard. */
#define WAIT_FOR(cond, ms) ROZ_TEST_WAIT(cond, sleep_ms(1), ms)

/* ---- parameters and configuration -------------------------------------- */

static void test_dds_params(void **st)
{
    roz_dds_params_t d;
    char err[256];
    (void)st;

    assert_int_equal(roz_dds_params_parse(&d, NULL, 7, 500, err, sizeof err), ROZ_OK);
    assert_string_equal(d.network_interface, "lo");
    assert_int_equal(d.domain, 7);
    assert_int_equal(d.enable_monitor, 1);
    assert_int_equal(d.command_writer_period_us, 2000);
    assert_int_equal(d.state_decimation, 1);
    assert_int_equal(d.command_timeout_us, ROZ_CMD_WATCHDOG_DEFAULT_US); /* 50 ms at 500 Hz */
    assert_int_equal(d.command_writer_spin_us, 0);

    static const struct { const char *key, *value; } bad[] = {
        { "network_interface", "eth0\"/><x" }, { "network_interface", "" },
        { "network_interface", "a_very_long_interface_name" }, { "dds_domain", "233" },
        { "dds_domain", "-1" }, { "dds_domain", "0x1" }, { "enable_monitor", "maybe" },
        { "command_writer_period_us", "50" }, { "command_writer_period_us", "1000001" },
        { "command_writer_period_us", "2 ms" }, { "state_decimation", "0" },
        { "state_decimation", "1001" },
        /* the watchdog: under two periods of the tick (500 Hz: 2 ms), over 60 s, not a number */
        { "command_timeout_us", "3999" }, { "command_timeout_us", "60000001" },
        { "command_timeout_us", "50ms" }, { "command_timeout_us", "0" },
        { "command_writer_spin_us", "10001" }, { "command_writer_spin_us", "-5" },
        /* a spin only for an event-driven writer (the default period is 2 ms) */
        { "command_writer_spin_us", "200" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        roz_param_t item = { bad[i].key, bad[i].value };
        roz_params_t p = { &item, 1 };
        err[0] = '\0';
        assert_int_equal(roz_dds_params_parse(&d, &p, 0, 500, err, sizeof err), ROZ_EINVAL);
        if (strstr(err, bad[i].key) == NULL || strstr(err, bad[i].value) == NULL)
            fail_msg("%s = \"%s\": \"%s\" names neither", bad[i].key, bad[i].value, err);
    }
    roz_param_t good[] = { { "network_interface", "eth0.10" }, { "dds_domain", "232" },
                           { "command_writer_period_us", "0" }, { "state_decimation", "4" },
                           { "enable_monitor", "false" }, { "command_timeout_us", "4000" },
                           { "command_writer_spin_us", "200" } };
    roz_params_t p = { good, 7 };
    assert_int_equal(roz_dds_params_parse(&d, &p, 0, 500, err, sizeof err), ROZ_OK);
    assert_string_equal(d.network_interface, "eth0.10");
    assert_int_equal(d.domain, 232);
    assert_int_equal(d.command_writer_period_us, 0);
    assert_int_equal(d.state_decimation, 4);
    assert_int_equal(d.enable_monitor, 0);
    assert_int_equal(d.command_timeout_us, 4000);
    assert_int_equal(d.command_writer_spin_us, 200);

    /* the least timeout and the default follow the slower of the tick and
     * the writer: a 20 ms writer period allows 40 ms, defaults to 100 ms;
     * a 10 Hz tick allows 200 ms, defaults to 500 ms */
    roz_param_t slow[] = { { "command_writer_period_us", "20000" },
                           { "command_timeout_us", "39999" } };
    roz_params_t ps = { slow, 2 };
    assert_int_equal(roz_dds_params_parse(&d, &ps, 0, 500, err, sizeof err), ROZ_EINVAL);
    assert_non_null(strstr(err, "40000..60000000"));
    ps.n = 1;
    assert_int_equal(roz_dds_params_parse(&d, &ps, 0, 500, err, sizeof err), ROZ_OK);
    assert_int_equal(d.command_timeout_us, 100000);
    assert_int_equal(roz_dds_params_parse(&d, NULL, 0, 10, err, sizeof err), ROZ_OK);
    assert_int_equal(d.command_timeout_us, 500000);
}

static void test_dds_config_xml(void **st)
{
    char xml[ROZ_DDS_CONFIG_MAX], small[64];
    (void)st;

    assert_true(roz_dds_config_xml("lo", NULL, xml, sizeof xml) > 0);
    assert_non_null(strstr(xml, "<NetworkInterface name=\"lo\"/>"));
    assert_non_null(strstr(xml, "<AllowMulticast>false</AllowMulticast>"));
    assert_non_null(strstr(xml, "<Peer address=\"127.0.0.1\"/>"));
    assert_non_null(strstr(xml, "<ParticipantIndex>auto</ParticipantIndex>"));
    assert_non_null(strstr(xml, "<MaxAutoParticipantIndex>63</MaxAutoParticipantIndex>"));

    assert_true(roz_dds_config_xml("eth0", NULL, xml, sizeof xml) > 0);
    assert_non_null(strstr(xml, "<NetworkInterface name=\"eth0\"/>"));
    assert_null(strstr(xml, "lo\""));
    assert_null(strstr(xml, "Peer"));

    assert_int_equal(roz_dds_config_xml("eth0\"><", NULL, xml, sizeof xml), ROZ_EINVAL);
    assert_int_equal(roz_dds_config_xml("lo", NULL, small, sizeof small), ROZ_ENOSPC);
}

/* Cyclone's threads from roz's configuration: the XML names each of them,
 * and where the process may have SCHED_FIFO the running "recv" thread has
 * it at the priority asked for (read back through /proc). */
static void *nothing(void *arg)
{
    return arg;
}

/* Of this process's threads whose name starts with a prefix, how many run
 * with another policy or priority than asked, and how many there are. */
typedef struct {
    const char *prefix;
    int         policy, prio;
    int         seen, off;
} threads_want_t;

static void want_thread(void *ctx, const char *name, int policy, int prio)
{
    threads_want_t *w = ctx;
    if (strncmp(name, w->prefix, strlen(w->prefix)) != 0)
        return;
    w->seen++;
    if (policy != w->policy || prio != w->prio) {
        print_message("thread %s: policy %d priority %d\n", name, policy, prio);
        w->off++;
    }
}

static void test_dds_cyclone_threads(void **st)
{
    char xml[ROZ_DDS_CONFIG_MAX], err[256];
    roz_thread_config_t t = { ROZ_THREAD_FIFO, 4, 0, 512 };
    roz_dds_participant_t p;
    unsigned long th;
    (void)st;

    assert_true(roz_dds_config_xml("lo", &t, xml, sizeof xml) > 0);
    for (size_t i = 0; roz_dds_cyclone_threads[i] != NULL; i++) {
        char want[200];
        snprintf(want, sizeof want,
                 "<Thread Name=\"%s\"><Scheduling><Class>realtime</Class><Priority>4</Priority>"
                 "</Scheduling><StackSize>512kB</StackSize></Thread>",
                 roz_dds_cyclone_threads[i]);
        assert_non_null(strstr(xml, want));
    }
    assert_non_null(strstr(xml, "<Internal><MultipleReceiveThreads>false</MultipleReceiveThreads>"
                                "</Internal>"));
    t.sched = ROZ_THREAD_RR;
    assert_int_equal(roz_dds_config_xml("lo", &t, xml, sizeof xml), ROZ_EINVAL);
    t = (roz_thread_config_t){ ROZ_THREAD_OTHER, 0, 0, 0 };
    assert_true(roz_dds_config_xml("lo", &t, xml, sizeof xml) > 0);
    assert_null(strstr(xml, "<Threads>"));
    assert_null(strstr(xml, "MultipleReceiveThreads")); /* Cyclone's defaults */

    /* the running threads: the stack always (Cyclone takes the
     * configuration), SCHED_FIFO where permitted */
    t = (roz_thread_config_t){ ROZ_THREAD_FIFO, 4, 0, 512 };
    int may_fifo = roz_thread_start(&th, &t, "probe", nothing, NULL, err, sizeof err) == ROZ_OK;
    if (may_fifo)
        roz_thread_join(th);
    else
        t = (roz_thread_config_t){ ROZ_THREAD_OTHER, 0, 0, 512 };
    int rc = roz_dds_participant_open(&p, "lo", ROZ_TEST_DDS_DOMAIN, &t, NULL, NULL, err,
                                      sizeof err);
    if (rc != ROZ_OK)
        fail_msg("%s", err);
    /* every thread that receives (one: several receive threads would put
     * the data on "recvUC", which Cyclone 0.10 lets no configuration
     * reach), and the delivery and event threads */
    int off = 0, all = 0;
    static const char *const data_path[] = { "recv", "dq.user", "tev", NULL };
    for (size_t i = 0; data_path[i] != NULL; i++) {
        threads_want_t w = { data_path[i], may_fifo ? SCHED_FIFO : SCHED_OTHER, may_fifo ? 4 : 0,
                             0, 0 };
        /* a thread names itself once it runs: on a loaded machine that can
         * come after the open returned, so look again for up to 10 s (a
         * hang guard, not a time the test judges) */
        for (int tries = 0; tries < 1000; tries++) {
            w.seen = w.off = 0;
            roz_test_proc_threads(0, want_thread, &w);
            if (w.seen > 0)
                break;
            sleep_ms(10);
        }
        if (w.seen == 0)
            fail_msg("no thread %s: is this Cyclone's configuration taken?", data_path[i]);
        off += w.off;
        all += w.seen;
    }
    roz_dds_participant_close(&p);
    assert_int_equal(off, 0);
    assert_int_equal(all, 3);
    if (!may_fifo)
        print_message("SCHED_FIFO not permitted here: Cyclone's threads at normal priority\n");
}

static char logged[1024];

static void log_capture(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    (void)level;
    size_t used = strlen(logged);
    snprintf(logged + used, sizeof logged - used, "%s\n", msg);
}

static void test_dds_participant(void **st)
{
    roz_dds_participant_t p;
    char err[256] = "";
    (void)st;

    assert_int_equal(roz_dds_participant_open(&p, "roznosuch0", ROZ_TEST_DDS_DOMAIN, NULL, NULL, NULL,
                                              err, sizeof err),
                     ROZ_ENOENT);
    assert_non_null(strstr(err, "network_interface = \"roznosuch0\""));
    assert_int_equal(roz_dds_participant_open(&p, "lo", 300, NULL, NULL, NULL, err, sizeof err),
                     ROZ_EINVAL);
    assert_non_null(strstr(err, "dds_domain"));

    logged[0] = '\0';
    assert_int_equal(roz_dds_participant_open(&p, "lo", ROZ_TEST_DDS_DOMAIN, NULL, log_capture, NULL,
                                              err, sizeof err),
                     ROZ_OK);
    assert_int_equal(p.user_config, 0);
    assert_non_null(strstr(p.config, "127.0.0.1"));
    assert_non_null(strstr(logged, "multicast off"));
    roz_dds_participant_close(&p);
    roz_dds_participant_close(&p); /* idempotent */

    /* the user's configuration wins, and the log says so */
    logged[0] = '\0';
    setenv("CYCLONEDDS_URI",
           "<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface name=\"lo\"/>"
           "</Interfaces><AllowMulticast>false</AllowMulticast></General></Domain></CycloneDDS>",
           1);
    assert_int_equal(roz_dds_participant_open(&p, "lo", ROZ_TEST_DDS_DOMAIN, NULL, log_capture, NULL,
                                              err, sizeof err),
                     ROZ_OK);
    unsetenv("CYCLONEDDS_URI");
    assert_int_equal(p.user_config, 1);
    assert_string_equal(p.config, "");
    assert_non_null(strstr(logged, "CYCLONEDDS_URI"));
    roz_dds_participant_close(&p);

    /* settings for Cyclone's threads that the user's file would drop
     * without a word are refused, naming the file's variable
     * (test_dds_participant) */
    setenv("CYCLONEDDS_URI", "<CycloneDDS/>", 1);
    roz_thread_config_t fifo = { ROZ_THREAD_FIFO, 10, 0, 0 }, stack = { ROZ_THREAD_OTHER, 0, 0, 256 };
    int rc_fifo = roz_dds_participant_open(&p, "lo", ROZ_TEST_DDS_DOMAIN, &fifo, log_capture, NULL,
                                           err, sizeof err);
    int rc_stack = roz_dds_participant_open(&p, "lo", ROZ_TEST_DDS_DOMAIN, &stack, log_capture,
                                            NULL, err, sizeof err);
    unsetenv("CYCLONEDDS_URI");
    assert_int_equal(rc_fifo, ROZ_EINVAL);
    assert_int_equal(rc_stack, ROZ_EINVAL);
    assert_non_null(strstr(err, "CYCLONEDDS_URI is set"));
    assert_non_null(strstr(err, "dds_threads_sched"));
}

/* ---- one process: writer thread, receive path ------------------------------ */

typedef struct {
    ROZ_ATOMIC(uint32_t) next;        /* what the fill function publishes next */
    ROZ_ATOMIC(uint32_t) fills;
    ROZ_ATOMIC(uint32_t) seen;        /* samples received */
    ROZ_ATOMIC(uint32_t) last_seq;
    ROZ_ATOMIC(uint32_t) bad;         /* samples with wrong content or dirty padding */
    ROZ_ATOMIC(uint32_t) gate;        /* 1: a fill, once it took next, waits until 0 */
    ROZ_ATOMIC(uint32_t) in_fill;     /* fills waiting at the gate */
    int                  increment;   /* periodic: every fill publishes next++ */
} bench_t;

static int fill_frame(void *ctx, void *sample, uint64_t now_ns)
{
    bench_t *b = ctx;
    roz_dds_test_Frame *f = sample;
    const unsigned char *raw = sample;
    (void)now_ns;

    /* roz zeroed the sample, padding included */
    for (size_t i = 0; i < sizeof *f; i++) {
        if (raw[i] != 0)
            atomic_fetch_add(&b->bad, 1u);
    }
    uint32_t seq = b->increment ? atomic_fetch_add(&b->next, 1u) : atomic_load(&b->next);
    if (atomic_load(&b->gate)) { /* the test holds this pass here */
        atomic_fetch_add(&b->in_fill, 1u);
        while (atomic_load(&b->gate))
            sleep_ms(1);
    }
    f->seq = seq;
    f->flag = (uint8_t)(seq & 0xffu);
    f->word = seq ^ 0xa5a5a5a5u;
    for (int i = 0; i < 4; i++)
        f->values[i] = seq + 0.25 * i;
    atomic_fetch_add(&b->fills, 1u);
    return 1;
}

static void on_frame(void *ctx, void *sample, uint64_t now_ns)
{
    bench_t *b = ctx;
    const roz_dds_test_Frame *f = sample;
    const unsigned char *raw = sample;
    int ok = f->flag == (uint8_t)(f->seq & 0xffu) && f->word == (f->seq ^ 0xa5a5a5a5u);
    (void)now_ns;

    for (int i = 0; i < 4; i++)
        ok &= f->values[i] == f->seq + 0.25 * i;
    /* the padding after flag is zero although the storage started dirty */
    for (size_t i = offsetof(roz_dds_test_Frame, flag) + 1; i < offsetof(roz_dds_test_Frame, word);
         i++)
        ok &= raw[i] == 0;
    if (!ok)
        atomic_fetch_add(&b->bad, 1u);
    atomic_store(&b->last_seq, f->seq);
    atomic_fetch_add(&b->seen, 1u);
}

static roz_dds_participant_t part;
static roz_dds_reader_t rd;
static roz_dds_writer_t wr;
static roz_dds_test_Frame rx_storage, tx_storage;
static roz_monitor_t mon_rx, mon_tx; /* one per thread that records */

static void open_pair(bench_t *b)
{
    char err[256] = "";
    memset(b, 0, sizeof *b);
    memset(&rx_storage, 0xAA, sizeof rx_storage); /* dirty: the reader zeroes it */
    memset(&tx_storage, 0x55, sizeof tx_storage);
    roz_monitor_init(&mon_rx, "test_dds rx", 1000000u, NULL, NULL);
    roz_monitor_init(&mon_tx, "test_dds tx", 1000000u, NULL, NULL);
    if (roz_dds_participant_open(&part, "lo", ROZ_TEST_DDS_DOMAIN, NULL, NULL, NULL, err,
                                 sizeof err) != ROZ_OK)
        fail_msg("participant: %s", err);
    if (roz_dds_reader_open(&rd, &part, "roz_test/frame", &roz_dds_test_Frame_desc,
                            &roz_dds_qos_robot_state, &rx_storage, sizeof rx_storage, on_frame, b,
                            &mon_rx, err, sizeof err) != ROZ_OK)
        fail_msg("reader: %s", err);
    if (roz_dds_writer_open(&wr, &part, "roz_test/frame", &roz_dds_test_Frame_desc,
                            &roz_dds_qos_robot_command, &tx_storage, sizeof tx_storage, err,
                            sizeof err) != ROZ_OK)
        fail_msg("writer: %s", err);
    WAIT_FOR(roz_dds_writer_matched(&wr) >= 1 && roz_dds_reader_matched(&rd) >= 1, 5000);
}

static void close_pair(void)
{
    roz_dds_writer_close(&wr);
    roz_dds_writer_close(&wr); /* idempotent */
    roz_dds_reader_close(&rd);
    roz_dds_reader_close(&rd);
    roz_dds_participant_close(&part);
}

static void test_dds_periodic_writer(void **st)
{
    static bench_t b;
    (void)st;

    open_pair(&b);
    b.increment = 1;
    assert_int_equal(roz_dds_writer_start(&wr, 50, fill_frame, &b, &mon_tx), ROZ_EINVAL);
    assert_int_equal(roz_dds_writer_start(&wr, 1000, fill_frame, &b, &mon_tx), ROZ_OK);
    assert_int_equal(roz_dds_writer_start(&wr, 1000, fill_frame, &b, &mon_tx), ROZ_ESTATE);
    WAIT_FOR(atomic_load(&b.seen) >= 50, 10000);
    roz_dds_writer_stop(&wr);

    uint64_t published = atomic_load(&wr.published);
    assert_true(published >= 50);
    assert_int_equal(atomic_load(&b.bad), 0);
    assert_int_equal(atomic_load(&wr.errors), 0);
    /* every published frame arrives (reliable, loopback), in order */
    WAIT_FOR(atomic_load(&b.seen) == published, 5000);
    assert_int_equal(atomic_load(&b.last_seq), published - 1);
    /* stopped: nothing more */
    sleep_ms(20);
    assert_int_equal(atomic_load(&wr.published), published);
    assert_int_equal(atomic_load(&b.seen), published);
    /* the monitors saw the writer's periods and passes, and the handler */
    roz_dds_reader_close(&rd);
    roz_monitor_stat_t s;
    assert_int_equal(roz_monitor_snapshot(&mon_tx, ROZ_MON_JITTER, &s), ROZ_OK);
    assert_true(s.count >= published - 1);
    assert_int_equal(roz_monitor_snapshot(&mon_tx, ROZ_MON_COMMAND_WRITER, &s), ROZ_OK);
    assert_int_equal(s.count, atomic_load(&wr.passes));
    assert_int_equal(roz_monitor_snapshot(&mon_rx, ROZ_MON_STATE_HANDLER, &s), ROZ_OK);
    assert_int_equal(s.count, published);
    close_pair();
}

/* Event-driven: a pass per wake, none without one, a wake that comes while
 * a pass runs never lost, wakes that piled up one pass with the latest
 * frame. Each step waits for what it needs (60 s the hang guard), then
 * counts exactly: nothing here depends on the machine's pace. */
static void test_dds_event_writer(void **st)
{
    static bench_t b;
    (void)st;

    open_pair(&b);
    b.increment = 0;
    assert_int_equal(roz_dds_writer_start(&wr, 0, fill_frame, &b, &mon_tx), ROZ_OK);
    sleep_ms(200);
    assert_int_equal(atomic_load(&wr.passes), 0); /* not woken: nothing */
    for (uint32_t k = 1; k <= 100; k++) {
        atomic_store(&b.next, k);
        roz_dds_writer_wake(&wr);
        WAIT_FOR(atomic_load(&b.last_seq) == k && atomic_load(&wr.published) >= k, 60000);
        /* one pass for the wake, none of its own (a writer that polls, or
         * passes on a timeout, shows here however fast it is) */
        assert_int_equal(atomic_load(&wr.passes), k);
        assert_int_equal(atomic_load(&wr.published), k);
    }
    /* a wake while a pass runs: the pass held in its fill (it took 200),
     * then 10 wakes for 300; let go, the writer passes once more, for 300 */
    atomic_store(&b.gate, 1u);
    atomic_store(&b.next, 200u);
    roz_dds_writer_wake(&wr);
    WAIT_FOR(atomic_load(&b.in_fill) == 1u, 60000);
    atomic_store(&b.next, 300u);
    for (int i = 0; i < 10; i++)
        roz_dds_writer_wake(&wr);
    atomic_store(&b.gate, 0u);
    WAIT_FOR(atomic_load(&b.last_seq) == 300u, 60000); /* a lost wake hangs here */
    assert_int_equal(atomic_load(&wr.passes), 102); /* the held pass and one for the 10 */
    /* a burst of wakes while the writer sleeps: at least one pass, at most
     * one per wake, the latest frame */
    uint64_t before = atomic_load(&wr.passes);
    atomic_store(&b.next, 1000u);
    for (int i = 0; i < 10; i++)
        roz_dds_writer_wake(&wr);
    WAIT_FOR(atomic_load(&b.last_seq) == 1000u, 60000);
    uint64_t burst = atomic_load(&wr.passes) - before;
    assert_true(burst >= 1 && burst <= 10);
    roz_dds_writer_stop(&wr);
    assert_int_equal(atomic_load(&b.bad), 0);
    assert_int_equal(atomic_load(&wr.errors), 0);
    /* every pass published, every sample arrived (reliable, loopback) */
    assert_int_equal(atomic_load(&wr.published), atomic_load(&wr.passes));
    WAIT_FOR(atomic_load(&b.seen) == atomic_load(&wr.published), 60000);
    /* the writer publishes one last sample on the caller's thread */
    atomic_store(&b.next, 2000u);
    assert_int_equal(roz_dds_writer_publish(&wr, fill_frame, &b), 1);
    assert_int_equal(roz_dds_writer_flush(&wr, 2000), ROZ_OK);
    WAIT_FOR(atomic_load(&b.last_seq) == 2000u, 60000);
    close_pair();
}

static void test_dds_spinning_writer(void **st)
{
    static bench_t b;
    (void)st;

    open_pair(&b);
    b.increment = 0;
    assert_int_equal(roz_dds_writer_spin(&wr, ROZ_DDS_MAX_SPIN_US + 1u), ROZ_EINVAL);
    assert_int_equal(roz_dds_writer_spin(&wr, 5000), ROZ_OK);
    roz_dds_writer_expect(&wr); /* before the start: no news once it runs */
    assert_int_equal(roz_dds_writer_start(&wr, 0, fill_frame, &b, &mon_tx), ROZ_OK);
    assert_int_equal(roz_dds_writer_spin(&wr, 100), ROZ_ESTATE);
    /* a heads-up alone publishes nothing: the writer spins, then sleeps */
    for (int i = 0; i < 20; i++) {
        roz_dds_writer_expect(&wr);
        sleep_ms(1);
    }
    sleep_ms(20);
    assert_int_equal(atomic_load(&wr.passes), 0);
    /* a heads-up, then the tick's wake: one frame each time, the latest */
    for (uint32_t k = 1; k <= 100; k++) {
        roz_dds_writer_expect(&wr);
        atomic_store(&b.next, k);
        roz_dds_writer_wake(&wr);
        WAIT_FOR(atomic_load(&b.last_seq) == k, 5000);
    }
    /* the wake also works without a heads-up (the writer asleep) */
    sleep_ms(20);
    atomic_store(&b.next, 500u);
    roz_dds_writer_wake(&wr);
    WAIT_FOR(atomic_load(&b.last_seq) == 500u, 5000);
    uint64_t passes = atomic_load(&wr.passes);
    assert_true(passes >= 101 && passes <= 101 + 20);
    /* a stop while the writer spins returns (the hang guard is ctest's) */
    roz_dds_writer_expect(&wr);
    roz_dds_writer_stop(&wr);
    assert_int_equal(atomic_load(&b.bad), 0);
    assert_int_equal(atomic_load(&wr.errors), 0);
    close_pair();

    /* a periodic writer takes no heads-up (nothing to spin for) */
    open_pair(&b);
    b.increment = 1;
    assert_int_equal(roz_dds_writer_spin(&wr, 5000), ROZ_OK);
    assert_int_equal(roz_dds_writer_start(&wr, 1000, fill_frame, &b, &mon_tx), ROZ_OK);
    roz_dds_writer_expect(&wr);
    WAIT_FOR(atomic_load(&b.seen) >= 5, 10000);
    assert_int_equal(atomic_load(&wr.expects), 0);
    roz_dds_writer_stop(&wr);
    close_pair();
}

/* ---- sequences and strings: kept storage ----------------------------------- */

typedef struct {
    ROZ_ATOMIC(uint32_t) n;       /* values in the next sample */
    ROZ_ATOMIC(uint32_t) seen;
    ROZ_ATOMIC(uint32_t) bad;
    ROZ_ATOMIC(uint32_t) moved;   /* samples taken into another buffer than the last */
    ROZ_ATOMIC(uint32_t) lengths; /* sum of the lengths received */
    const void          *last_buf, *last_name;
    double               tx_values[16];
    char                 tx_name[16];
} joints_t;

static roz_dds_test_Joints joints_rx, joints_tx, joints_tx2;
static roz_dds_writer_t wr2;
static joints_t jt;

static int fill_joints_on(roz_dds_test_Joints *j, uint32_t seq)
{
    uint32_t n = atomic_load(&jt.n);
    for (uint32_t i = 0; i < n; i++)
        jt.tx_values[i] = seq * 10.0 + i;
    snprintf(jt.tx_name, sizeof jt.tx_name, "joint_%03u", (unsigned)(seq % 1000u));
    j->seq = seq;
    j->name = jt.tx_name;
    j->values._buffer = jt.tx_values;
    j->values._length = n;
    j->values._maximum = n;
    j->values._release = false;
    return 1;
}

static int fill_second(void *ctx, void *sample, uint64_t now_ns)
{
    (void)now_ns;
    return fill_joints_on(sample, (uint32_t)(uintptr_t)ctx);
}

/* The thread's pass: the second writer first (from this thread), then its
 * own sample. */
static int fill_first(void *ctx, void *sample, uint64_t now_ns)
{
    uint32_t seq = (uint32_t)atomic_load(&wr.passes);
    (void)ctx;
    (void)now_ns;
    if (roz_dds_writer_publish(&wr2, fill_second, (void *)(uintptr_t)(seq + 100000u)) != 1)
        atomic_fetch_add(&jt.bad, 1u);
    return fill_joints_on(sample, seq);
}

static void on_joints(void *ctx, void *sample, uint64_t now_ns)
{
    const roz_dds_test_Joints *j = sample;
    char want[16];
    int ok = 1;
    (void)ctx;
    (void)now_ns;
    for (uint32_t i = 0; i < j->values._length; i++)
        ok &= j->values._buffer[i] == j->seq * 10.0 + i;
    snprintf(want, sizeof want, "joint_%03u", (unsigned)(j->seq % 1000u));
    ok &= j->name != NULL && strcmp(j->name, want) == 0;
    if (!ok)
        atomic_fetch_add(&jt.bad, 1u);
    if ((const void *)j->values._buffer != jt.last_buf || (const void *)j->name != jt.last_name)
        atomic_fetch_add(&jt.moved, 1u);
    jt.last_buf = j->values._buffer;
    jt.last_name = j->name;
    atomic_fetch_add(&jt.lengths, j->values._length);
    atomic_fetch_add(&jt.seen, 1u);
}

static void test_dds_kept_storage(void **st)
{
    char err[256] = "";
    (void)st;

    memset(&jt, 0, sizeof jt);
    memset(&joints_rx, 0, sizeof joints_rx);
    assert_int_equal(roz_dds_seq_reserve(&joints_rx.values, 8, sizeof(double)), ROZ_OK);
    assert_int_equal(roz_dds_seq_reserve(&joints_rx.values, 8, sizeof(double)), ROZ_EINVAL);
    assert_int_equal(roz_dds_string_reserve(&joints_rx.name, 15), ROZ_OK);
    assert_int_equal(roz_dds_string_reserve(&joints_rx.name, 15), ROZ_EINVAL);
    assert_int_equal(joints_rx.values._maximum, 8);
    assert_int_equal(strlen(joints_rx.name), 15);
    jt.last_buf = joints_rx.values._buffer;
    jt.last_name = joints_rx.name;

    if (roz_dds_participant_open(&part, "lo", ROZ_TEST_DDS_DOMAIN, NULL, NULL, NULL, err,
                                 sizeof err) != ROZ_OK ||
        roz_dds_reader_open_kept(&rd, &part, "roz_test/joints", &roz_dds_test_Joints_desc,
                                 &roz_dds_qos_ros2_default, &joints_rx, sizeof joints_rx,
                                 on_joints, NULL, NULL, err, sizeof err) != ROZ_OK ||
        roz_dds_writer_open(&wr, &part, "roz_test/joints", &roz_dds_test_Joints_desc,
                            &roz_dds_qos_ros2_default, &joints_tx, sizeof joints_tx, err,
                            sizeof err) != ROZ_OK ||
        roz_dds_writer_open(&wr2, &part, "roz_test/joints", &roz_dds_test_Joints_desc,
                            &roz_dds_qos_ros2_default, &joints_tx2, sizeof joints_tx2, err,
                            sizeof err) != ROZ_OK)
        fail_msg("%s", err);
    WAIT_FOR(roz_dds_writer_matched(&wr) >= 1 && roz_dds_writer_matched(&wr2) >= 1 &&
                 roz_dds_reader_matched(&rd) >= 2,
             5000);
    /* up to the room given at open: the same buffers every time */
    atomic_store(&jt.n, 8u);
    assert_int_equal(roz_dds_writer_start(&wr, 0, fill_first, NULL, NULL), ROZ_OK);
    for (int k = 1; k <= 50; k++) {
        atomic_store(&jt.n, (uint32_t)(k % 2 ? 8 : 5));
        uint32_t before = atomic_load(&jt.seen);
        roz_dds_writer_wake(&wr);
        WAIT_FOR(atomic_load(&jt.seen) >= before + 2, 5000); /* both writers' samples */
    }
    assert_int_equal(atomic_load(&jt.bad), 0);
    assert_int_equal(atomic_load(&jt.moved), 0);
    assert_int_equal(atomic_load(&wr2.published), atomic_load(&wr.published));
    /* a longer sample: Cyclone grows the sequence, the content is right */
    atomic_store(&jt.n, 16u);
    uint32_t before = atomic_load(&jt.seen);
    roz_dds_writer_wake(&wr);
    WAIT_FOR(atomic_load(&jt.seen) >= before + 2, 5000);
    roz_dds_writer_stop(&wr);
    assert_int_equal(atomic_load(&jt.bad), 0);
    assert_true(joints_rx.values._maximum >= 16);
    assert_int_equal(joints_rx.values._length, 16);
    roz_dds_reader_close(&rd);
    roz_dds_writer_close(&wr2);
    roz_dds_writer_close(&wr);
    roz_dds_participant_close(&part);
    roz_dds_sample_free(&joints_rx, sizeof joints_rx, &roz_dds_test_Joints_desc);
    assert_null(joints_rx.values._buffer);
    assert_null(joints_rx.name);
    roz_dds_sample_free(&joints_rx, sizeof joints_rx, &roz_dds_test_Joints_desc);
}

/* ---- the command path -------------------------------------------------------- */

/* A port of two command channels, its hooks counting what they are asked
 * (hold: the tick's; send, safe: the writer thread's, or the caller's on
 * stop): the command path alone, without a port's wire. */
static const roz_channel_t cp_commands[2] = {
    { .name = "j/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -1.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "j/damping", .type = ROZ_IF_DAMPING, .unit = "N.m.s/rad", .min = 0.0, .max = 10.0,
      .default_value = 1.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_manifest_t cp_manifest = { "cmd_path", "test", 100, cp_commands, 2, NULL, 0,
                                            NULL, NULL, 0, 0, NULL, NULL };

typedef struct {
    ROZ_ATOMIC(uint32_t) rx_session; /* the receive path's, as the hooks see it */
    ROZ_ATOMIC(int)      refuse;
    ROZ_ATOMIC(uint32_t) sends, safes, refuse_asked;
    uint32_t             holds;      /* the tick's */
    double               sent[2], extra; /* the last send's (writer thread) */
} cmd_port_t;

static cmd_port_t cp;
static roz_dds_cmd_t cmdp;
static double cmd_slots[3 * (2 + ROZ_DDS_CMD_META + 1)];

static void cp_hold(void *port, const double *last, double *cmd)
{
    cmd_port_t *p = port;
    (void)last;
    p->holds++;
    cmd[0] = 0.25; /* "the measured position" */
    cmd[1] = 0.0;
}

static uint32_t cp_rx_session(void *port)
{
    cmd_port_t *p = port;
    return atomic_load(&p->rx_session);
}

static int cp_refuse(void *port)
{
    cmd_port_t *p = port;
    atomic_fetch_add(&p->refuse_asked, 1u);
    return atomic_load(&p->refuse);
}

static int cp_send(void *port, void *sample, const double *cmd, const double *extra, int hold)
{
    cmd_port_t *p = port;
    (void)hold;
    roz_dds_test_Frame *f = sample;
    p->sent[0] = cmd[0];
    p->sent[1] = cmd[1];
    p->extra = extra[0];
    f->seq = 1;
    atomic_fetch_add(&p->sends, 1u);
    return 1;
}

static int cp_safe(void *port, void *sample)
{
    cmd_port_t *p = port;
    roz_dds_test_Frame *f = sample;
    f->seq = 2;
    atomic_fetch_add(&p->safes, 1u);
    return 1;
}

static const roz_dds_cmd_ops_t cp_ops = { cp_hold, cp_rx_session, cp_refuse, cp_send, cp_safe,
                                          NULL };

/* The test's clock for the watchdog: it stands still until the test moves it. */
static ROZ_ATOMIC(uint64_t) cp_now_ns;

static uint64_t cp_clock(void *ctx)
{
    (void)ctx;
    return atomic_load(&cp_now_ns);
}

/* A participant, a writer (no reader needed) and the path, whose watchdog
 * counts on the monotonic clock or, @p test_clock, on cp_clock(); its
 * writer event-driven (@p period_us 0) or periodic. Returns what starting
 * the writer returned. */
static int cp_start(uint32_t timeout_us, uint32_t period_us, int test_clock)
{
    char err[256] = "";
    memset(&cp, 0, sizeof cp);
    atomic_store(&cp.rx_session, 1u);
    memset(&tx_storage, 0x55, sizeof tx_storage);
    if (roz_dds_participant_open(&part, "lo", ROZ_TEST_DDS_DOMAIN, NULL, NULL, NULL, err,
                                 sizeof err) != ROZ_OK ||
        roz_dds_writer_open(&wr, &part, "roz_test/command", &roz_dds_test_Frame_desc,
                            &roz_dds_qos_robot_command, &tx_storage, sizeof tx_storage, err,
                            sizeof err) != ROZ_OK)
        fail_msg("%s", err);
    roz_dds_cmd_config_t cfg = { .m = &cp_manifest, .ops = &cp_ops, .port = &cp, .writer = &wr,
                                 .slots = cmd_slots, .n_extra = 1, .timeout_us = timeout_us,
                                 .clock = test_clock ? cp_clock : NULL };
    roz_dds_cmd_init(&cmdp, &cfg);
    assert_int_equal(roz_dds_cmd_attach(&cmdp, 0), ROZ_OK);
    return roz_dds_cmd_start(&cmdp, period_us, NULL);
}

/* An event-driven writer, the watchdog on the monotonic clock. */
static void cp_open(uint32_t timeout_us)
{
    assert_int_equal(cp_start(timeout_us, 0, 0), ROZ_OK);
}

static void cp_close(void)
{
    roz_dds_writer_close(&wr);
    roz_dds_participant_close(&part);
}

static uint64_t cp_count(roz_dds_cmd_counter_t k)
{
    return roz_dds_cmd_count(&cmdp, k);
}

/* A write as the tick makes it after a read that saw @p robot's frames of
 * @p session; the writer's pass over it has ended when this returns. */
static void cp_write(double q, double kd, uint32_t robot, uint32_t session)
{
    const double cmd[2] = { q, kd };
    const double extra = 7.5;
    roz_dds_cmd_tick_t t = { 1, robot, session, &extra };
    uint64_t written = cp_count(ROZ_DDS_CMD_WRITTEN_SEQ);
    assert_int_equal(roz_dds_cmd_write(&cmdp, cmd, 2, &t), ROZ_OK);
    assert_int_equal(cp_count(ROZ_DDS_CMD_WRITTEN_SEQ), written + 1);
    WAIT_FOR(cp_count(ROZ_DDS_CMD_HANDLED_SEQ) == written + 1 &&
                 atomic_load(&wr.passes) == atomic_load(&wr.done),
             5000);
}

static void test_dds_command_path(void **st)
{
    const double cmd[2] = { 0.5, 2.0 };
    roz_port_fault_t fault;
    (void)st;

    cp_open(ROZ_CMD_WATCHDOG_MAX_US); /* no trip while this part runs */
    /* nothing before the first state frame; a frame of the wrong length refused */
    roz_dds_cmd_tick_t none = { 0, 0, 0, NULL };
    assert_int_equal(roz_dds_cmd_write(&cmdp, cmd, 2, &none), ROZ_OK);
    assert_int_equal(roz_dds_cmd_write(&cmdp, cmd, 3, &none), ROZ_EINVAL);
    assert_int_equal(cp_count(ROZ_DDS_CMD_WRITES), 1);
    assert_int_equal(cp_count(ROZ_DDS_CMD_WITHHELD), 1);
    sleep_ms(20);
    assert_int_equal(atomic_load(&wr.passes), 0);
    /* the first write for a robot is the start-up hold, sent with the
     * port's own values */
    cp_write(0.5, 2.0, 1, 1);
    assert_int_equal(cp.holds, 1);
    assert_int_equal(cp_count(ROZ_DDS_CMD_HOLDS), 1);
    assert_int_equal(atomic_load(&cp.sends), 1);
    assert_true(cp.sent[0] == 0.25 && cp.sent[1] == 0.0 && cp.extra == 7.5);
    /* then the tick's frames, clamped to their channels */
    cp_write(0.5, 2.0, 1, 1);
    assert_true(cp.sent[0] == 0.5 && cp.sent[1] == 2.0);
    cp_write(5.0, -3.0, 1, 1);
    assert_true(cp.sent[0] == 1.0 && cp.sent[1] == 0.0);
    assert_int_equal(cp_count(ROZ_DDS_CMD_CLAMPED), 2);
    assert_int_equal(atomic_load(&cp.sends), 3);
    assert_int_equal(atomic_load(&wr.published), 3);
    /* the robot restarted (its receive path says so) before the tick read
     * it: a frame for the old one is not sent; the tick's first write for
     * the new one is its hold */
    atomic_store(&cp.rx_session, 2u);
    cp_write(0.5, 2.0, 1, 1);
    assert_int_equal(cp_count(ROZ_DDS_CMD_STALE), 1);
    assert_int_equal(atomic_load(&cp.sends), 3);
    cp_write(0.5, 2.0, 2, 2);
    assert_int_equal(cp_count(ROZ_DDS_CMD_HOLDS), 2);
    assert_true(cp.sent[0] == 0.25 && cp.sent[1] == 0.0);
    assert_int_equal(atomic_load(&cp.sends), 4);
    /* the port refuses: nothing, counted; asked on every pass with a frame */
    atomic_store(&cp.refuse, 1);
    cp_write(0.5, 2.0, 2, 2);
    assert_int_equal(cp_count(ROZ_DDS_CMD_REFUSED), 1);
    assert_int_equal(atomic_load(&cp.sends), 4);
    assert_int_equal(atomic_load(&cp.refuse_asked), 6);
    atomic_store(&cp.refuse, 0);
    /* no trip: read()'s own result */
    assert_int_equal(roz_dds_cmd_report(&cmdp, 1, &fault), 1);
    assert_int_equal(roz_dds_cmd_report(&cmdp, ROZ_ELINK, &fault), ROZ_ELINK);
    assert_int_equal(roz_dds_cmd_timeouts(&cmdp), 0);
    assert_int_equal(atomic_load(&cp.safes), 0);
    /* deactivate: the damping command from this thread */
    assert_int_equal(roz_dds_cmd_stop(&cmdp), 1);
    assert_true(atomic_load(&cp.safes) >= 1);
    assert_int_equal(atomic_load(&cp.sends), 4);
    cp_close();

    /* the tick goes silent: the watchdog's damping command on the writer's
     * own, read() reports the trip once, and the next write is a hold. The
     * watchdog counts on the test's clock, which stands still until the
     * test moves it: however late the writer's passes come on a loaded
     * machine, a frame is as old as the test says, no older. A periodic
     * writer here; an event-driven one below. */
    atomic_store(&cp_now_ns, 1000000000u);
    assert_int_equal(cp_start(20000u, 2000u, 1), ROZ_OK); /* two ticks at 100 Hz */
    cp_write(0.5, 2.0, 1, 1); /* the start-up hold, sent: the robot got a command */
    assert_true(atomic_load(&cp.sends) >= 1);
    /* 19.999 ms on: the frame is fresh on every pass, sent again */
    atomic_store(&cp_now_ns, 1000000000u + 19999000u);
    uint32_t sends = atomic_load(&cp.sends);
    WAIT_FOR(atomic_load(&cp.sends) >= sends + 2, 10000);
    assert_int_equal(roz_dds_cmd_timeouts(&cmdp), 0);
    assert_int_equal(cp_count(ROZ_DDS_CMD_SAFE), 0);
    /* 30 ms: the next pass trips it; the damping command from then on */
    atomic_store(&cp_now_ns, 1000000000u + 30000000u);
    WAIT_FOR(roz_dds_cmd_timeouts(&cmdp) == 1 && cp_count(ROZ_DDS_CMD_SAFE) >= 2, 10000);
    sends = atomic_load(&cp.sends);
    uint64_t safe = cp_count(ROZ_DDS_CMD_SAFE);
    WAIT_FOR(cp_count(ROZ_DDS_CMD_SAFE) >= safe + 2, 10000);
    assert_int_equal(atomic_load(&cp.sends), sends); /* no frame of the tick's after the trip */
    assert_true(atomic_load(&cp.safes) >= 2);
    assert_int_equal(roz_dds_cmd_timeouts(&cmdp), 1);
    assert_int_equal(roz_dds_cmd_report(&cmdp, 1, &fault), ROZ_EWATCHDOG);
    assert_string_equal(fault.what, ROZ_CMD_WATCHDOG_KEY);
    assert_int_equal(fault.code, 30000u); /* the silence, by the watchdog's clock */
    assert_int_equal(fault.limit, 20000u);
    assert_int_equal(roz_dds_cmd_report(&cmdp, 1, &fault), 1);
    uint32_t holds = cp.holds;
    const double q[2] = { 0.5, 2.0 };
    roz_dds_cmd_tick_t t = { 1, 1, 1, q };
    assert_int_equal(roz_dds_cmd_write(&cmdp, q, 2, &t), ROZ_OK);
    assert_int_equal(cp.holds, holds + 1);
    assert_int_equal(roz_dds_cmd_stop(&cmdp), 1);
    cp_close();

    /* event-driven on the test's clock: the writer judges by it when the
     * watchdog is due (its sleeps stay on real time), and looks again when
     * the test wakes it (roz_dds_writer_nudge(): no frame posted). Exactly
     * the timeout is not due: a posted pass sends the frame again; 1 ns
     * more, the writer's own pass trips it; then the damping once each
     * tick period (10 ms at 100 Hz) the clock moves on, and never more. */
    atomic_store(&cp_now_ns, 1000000000u);
    assert_int_equal(cp_start(20000u, 0, 1), ROZ_OK);
    cp_write(0.5, 2.0, 1, 1);
    sends = atomic_load(&cp.sends);
    atomic_store(&cp_now_ns, 1000000000u + 20000000u);
    roz_dds_writer_wake(&wr);
    WAIT_FOR(atomic_load(&cp.sends) == sends + 1, 10000);
    assert_int_equal(roz_dds_cmd_timeouts(&cmdp), 0);
    atomic_store(&cp_now_ns, 1000000000u + 20000001u);
    roz_dds_writer_nudge(&wr);
    WAIT_FOR(roz_dds_cmd_timeouts(&cmdp) == 1 && cp_count(ROZ_DDS_CMD_SAFE) == 1, 10000);
    atomic_store(&cp_now_ns, 1000000000u + 30000000u); /* 1 ns short of the repeat */
    roz_dds_writer_wake(&wr); /* a pass posted: the damping, a period from it */
    WAIT_FOR(cp_count(ROZ_DDS_CMD_SAFE) == 2, 10000);
    atomic_store(&cp_now_ns, 1000000000u + 40000000u);
    roz_dds_writer_nudge(&wr);
    WAIT_FOR(cp_count(ROZ_DDS_CMD_SAFE) == 3, 10000);
    sleep_ms(30); /* the writer's own look on real time: nothing due by the clock */
    assert_int_equal(cp_count(ROZ_DDS_CMD_SAFE), 3);
    assert_int_equal(atomic_load(&cp.sends), sends + 1);
    assert_int_equal(roz_dds_cmd_report(&cmdp, 1, &fault), ROZ_EWATCHDOG);
    assert_int_equal(fault.code, 40000u); /* the silence, by the watchdog's clock */
    assert_int_equal(roz_dds_cmd_stop(&cmdp), 1);
    cp_close();

    /* a robot that never got a command gets no damping either */
    cp_open(ROZ_CMD_WATCHDOG_MAX_US);
    assert_int_equal(roz_dds_cmd_write(&cmdp, cmd, 2, &none), ROZ_OK);
    assert_int_equal(roz_dds_cmd_stop(&cmdp), 0);
    assert_int_equal(atomic_load(&cp.safes), 0);
    assert_int_equal(atomic_load(&wr.published), 0);
    cp_close();
}

/* ---- two processes -------------------------------------------------------- */

/* The echo peer: a frame on roz_test/ping comes back on roz_test/pong, made
 * again from its sequence number, with the flag spoiled if the ping's
 * content was not what its sequence number says. */
static roz_dds_writer_t echo_wr;
static roz_dds_test_Frame echo_rx, echo_tx;
static ROZ_ATOMIC(uint32_t) echo_seq;  /* the last ping's sequence, its bit 31 = bad */
static ROZ_ATOMIC(uint32_t) echo_have;

static void on_ping(void *ctx, void *sample, uint64_t now_ns)
{
    const roz_dds_test_Frame *f = sample;
    int ok = f->flag == (uint8_t)(f->seq & 0xffu) && f->word == (f->seq ^ 0xa5a5a5a5u);
    (void)ctx;
    (void)now_ns;
    for (int i = 0; i < 4; i++)
        ok &= f->values[i] == f->seq + 0.25 * i;
    atomic_store(&echo_seq, (f->seq & 0x7fffffffu) | (ok ? 0u : 0x80000000u));
    atomic_store(&echo_have, 1u);
    roz_dds_writer_wake(&echo_wr);
}

static int fill_echo(void *ctx, void *sample, uint64_t now_ns)
{
    roz_dds_test_Frame *f = sample;
    uint32_t s = atomic_load(&echo_seq), seq = s & 0x7fffffffu;
    (void)ctx;
    (void)now_ns;
    f->seq = seq;
    f->flag = (uint8_t)((seq & 0xffu) ^ (s >> 31 ? 1u : 0u));
    f->word = seq ^ 0xa5a5a5a5u;
    for (int i = 0; i < 4; i++)
        f->values[i] = seq + 0.25 * i;
    return atomic_load(&echo_have) != 0u;
}

static int echo_main(uint32_t domain)
{
    roz_dds_participant_t p;
    roz_dds_reader_t r;
    char err[256] = "", line[16];

    atomic_init(&echo_have, 0u);
    atomic_init(&echo_seq, 0u);
    if (roz_dds_participant_open(&p, "lo", domain, NULL, NULL, NULL, err, sizeof err) != ROZ_OK ||
        roz_dds_writer_open(&echo_wr, &p, "roz_test/pong", &roz_dds_test_Frame_desc,
                            &roz_dds_qos_robot_command, &echo_tx, sizeof echo_tx, err,
                            sizeof err) != ROZ_OK ||
        roz_dds_writer_start(&echo_wr, 0, fill_echo, NULL, NULL) != ROZ_OK ||
        roz_dds_reader_open(&r, &p, "roz_test/ping", &roz_dds_test_Frame_desc,
                            &roz_dds_qos_robot_state, &echo_rx, sizeof echo_rx, on_ping, NULL,
                            NULL, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "echo: %s\n", err);
        return 1;
    }
    /* until the parent closes our stdin */
    while (fgets(line, sizeof line, stdin) != NULL)
        ;
    roz_dds_reader_close(&r);
    roz_dds_writer_close(&echo_wr);
    roz_dds_participant_close(&p);
    return 0;
}

static void test_dds_two_processes(void **st)
{
    static bench_t b;
    char err[256] = "", domain[16];
    int in[2];
    pid_t pid;
    posix_spawn_file_actions_t fa;
    (void)st;

    snprintf(domain, sizeof domain, "%d", ROZ_TEST_DDS_DOMAIN + 1);
    char *argv[] = { self_path, arg_echo, domain, NULL };
    assert_int_equal(pipe(in), 0);
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, in[0], 0);
    posix_spawn_file_actions_addclose(&fa, in[1]);
    assert_int_equal(roz_test_spawn(&pid, &fa, (const char *const *)argv), 0);
    posix_spawn_file_actions_destroy(&fa);
    close(in[0]);

    memset(&b, 0, sizeof b);
    memset(&rx_storage, 0xAA, sizeof rx_storage);
    if (roz_dds_participant_open(&part, "lo", ROZ_TEST_DDS_DOMAIN + 1, NULL, NULL, NULL, err,
                                 sizeof err) != ROZ_OK ||
        roz_dds_reader_open(&rd, &part, "roz_test/pong", &roz_dds_test_Frame_desc,
                            &roz_dds_qos_robot_state, &rx_storage, sizeof rx_storage, on_frame,
                            &b, NULL, err, sizeof err) != ROZ_OK ||
        roz_dds_writer_open(&wr, &part, "roz_test/ping", &roz_dds_test_Frame_desc,
                            &roz_dds_qos_robot_command, &tx_storage, sizeof tx_storage, err,
                            sizeof err) != ROZ_OK ||
        roz_dds_writer_start(&wr, 0, fill_frame, &b, NULL) != ROZ_OK)
        fail_msg("%s", err);
    /* discovery through the peer address, multicast off: both directions
     * here; the echo's writer may find our reader a little later, so a
     * ping goes again every 50 ms until its echo is back */
    WAIT_FOR(roz_dds_writer_matched(&wr) >= 1 && roz_dds_reader_matched(&rd) >= 1, 20000);
    for (uint32_t k = 1; k <= 20; k++) {
        atomic_store(&b.next, k);
        for (unsigned tries = 0; atomic_load(&b.last_seq) != k && tries < 200; tries++) {
            roz_dds_writer_wake(&wr);
            for (int i = 0; i < 50 && atomic_load(&b.last_seq) != k; i++)
                sleep_ms(1);
        }
        assert_int_equal(atomic_load(&b.last_seq), k);
    }
    assert_int_equal(atomic_load(&b.bad), 0);
    close(in[1]);
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    close_pair();
}

int main(int argc, char **argv)
{
    snprintf(self_path, sizeof self_path, "%s", argv[0]);
    if (argc == 3 && strcmp(argv[1], "--echo") == 0)
        return echo_main((uint32_t)strtoul(argv[2], NULL, 10));
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dds_params),
        cmocka_unit_test(test_dds_config_xml),
        cmocka_unit_test(test_dds_participant),
        cmocka_unit_test(test_dds_cyclone_threads),
        cmocka_unit_test(test_dds_periodic_writer),
        cmocka_unit_test(test_dds_event_writer),
        cmocka_unit_test(test_dds_spinning_writer),
        cmocka_unit_test(test_dds_kept_storage),
        cmocka_unit_test(test_dds_command_path),
        cmocka_unit_test(test_dds_two_processes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
