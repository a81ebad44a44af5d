/* SPDX-License-Identifier: Apache-2.0 */
/* The command watchdog every hardware port runs (roz/hal/cmd_watchdog.h),
 * on times the test gives it (no clock):
 *  - a frame is sent while it is no older than the timeout; older, the
 *    sender trips once, sends the safe command from then on, and the tick's
 *    next read reports it once with how long the tick was silent;
 *  - the silence reported is the tick's, also when it wrote before it read;
 *  - the tick's first write after a trip must be a hold; a frame written
 *    before the trip was seen (an older epoch) is never sent, even fresh;
 *  - a tick that comes back and dies again trips again;
 *  - the sender's next look: the expiry of the frame sent, 0 while tripped;
 *  - the parameter: default, least value from the tick's and the
 *    sender's periods, refusals naming key and value;
 *  - two threads: a tick that writes, stops and comes back, a sender that
 *    judges every frame: no frame of an older epoch is sent, every trip is
 *    reported once (run under TSan by make test-tsan). */
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/hal/cmd_watchdog.h"
#include "support.h"

#define MS 1000000ull

static void test_cmd_watchdog_trips_once_and_reports(void **st)
{
    roz_cmd_watchdog_t wd;
    uint32_t epoch = 99, silent = 0;
    (void)st;

    roz_cmd_watchdog_init(&wd, 50000); /* 50 ms */
    assert_true(roz_cmd_watchdog_next_ns(&wd) == UINT64_MAX);
    assert_int_equal(roz_cmd_watchdog_write(&wd, 1000 * MS, &epoch), 0);
    assert_int_equal(epoch, 0);
    /* fresh up to the timeout itself */
    assert_int_equal(roz_cmd_watchdog_judge(&wd, epoch, 0, 1000 * MS, 1000 * MS), ROZ_CMD_SEND);
    assert_int_equal(roz_cmd_watchdog_judge(&wd, epoch, 0, 1000 * MS, 1050 * MS), ROZ_CMD_SEND);
    assert_true(roz_cmd_watchdog_next_ns(&wd) == 1050 * MS + 1);
    assert_int_equal(roz_cmd_watchdog_report(&wd, 1050 * MS, &silent), 0);
    /* one nanosecond older: the trip */
    assert_int_equal(roz_cmd_watchdog_judge(&wd, epoch, 0, 1000 * MS, 1050 * MS + 1), ROZ_CMD_SAFE);
    assert_int_equal(roz_cmd_watchdog_trips(&wd), 1);
    assert_int_equal(roz_cmd_watchdog_stood_us(&wd), 50000);
    assert_true(roz_cmd_watchdog_next_ns(&wd) == 0);
    /* the same stale frame: the safe command again, no second trip */
    for (int k = 1; k <= 10; k++)
        assert_int_equal(roz_cmd_watchdog_judge(&wd, epoch, 0, 1000 * MS, (1050 + 2 * k) * MS),
                         ROZ_CMD_SAFE);
    assert_int_equal(roz_cmd_watchdog_trips(&wd), 1);
    /* the tick is back 300 ms after its last write: read reports once */
    assert_int_equal(roz_cmd_watchdog_report(&wd, 1300 * MS, &silent), 1);
    assert_int_equal(silent, 300000);
    assert_int_equal(roz_cmd_watchdog_report(&wd, 1302 * MS, &silent), 0);
    /* its writes are holds, of the new epoch, until one was sent (a
     * latest-value hand-over may skip one); then as written */
    assert_int_equal(roz_cmd_watchdog_write(&wd, 1300 * MS, &epoch), 1);
    assert_int_equal(epoch, 1);
    assert_int_equal(roz_cmd_watchdog_write(&wd, 1301 * MS, &epoch), 1);
    assert_int_equal(roz_cmd_watchdog_judge(&wd, epoch, 1, 1301 * MS, 1301 * MS), ROZ_CMD_SEND);
    assert_int_equal(roz_cmd_watchdog_write(&wd, 1302 * MS, &epoch), 0);
    assert_int_equal(epoch, 1);
    assert_int_equal(roz_cmd_watchdog_judge(&wd, epoch, 0, 1302 * MS, 1302 * MS), ROZ_CMD_SEND);
    /* silent again: a second trip */
    assert_int_equal(roz_cmd_watchdog_judge(&wd, epoch, 0, 1302 * MS, 1400 * MS), ROZ_CMD_SAFE);
    assert_int_equal(roz_cmd_watchdog_trips(&wd), 2);
    assert_int_equal(roz_cmd_watchdog_stood_us(&wd), 98000);
    /* the tick writes before it reads (a loop that writes first): the
     * silence reported is the one that write ended, not the time since it */
    assert_int_equal(roz_cmd_watchdog_write(&wd, 1500 * MS, &epoch), 1);
    assert_int_equal(roz_cmd_watchdog_write(&wd, 1501 * MS, &epoch), 1);
    assert_int_equal(roz_cmd_watchdog_report(&wd, 1502 * MS, &silent), 1);
    assert_int_equal(silent, 198000);
}

static void test_cmd_watchdog_older_epoch_never_sent(void **st)
{
    roz_cmd_watchdog_t wd;
    uint32_t epoch = 0, silent = 0;
    (void)st;

    roz_cmd_watchdog_init(&wd, 20000);
    assert_int_equal(roz_cmd_watchdog_write(&wd, 0, &epoch), 0);
    assert_int_equal(roz_cmd_watchdog_judge(&wd, epoch, 0, 0, 1 * MS), ROZ_CMD_SEND);
    /* the sender judges an old frame and trips while the tick, back, writes
     * a fresh frame under the epoch it saw before the trip */
    uint32_t before = 0;
    assert_int_equal(roz_cmd_watchdog_write(&wd, 30 * MS, &before), 0);
    assert_int_equal(roz_cmd_watchdog_judge(&wd, epoch, 0, 0, 30 * MS), ROZ_CMD_SAFE);
    /* that frame is fresh, but of the old epoch: never sent */
    for (int k = 0; k < 5; k++)
        assert_int_equal(roz_cmd_watchdog_judge(&wd, before, 0, 30 * MS, (31 + k) * MS),
                         ROZ_CMD_SAFE);
    assert_int_equal(roz_cmd_watchdog_trips(&wd), 1);
    /* the tick's next read reports it and its next write is the hold */
    assert_int_equal(roz_cmd_watchdog_report(&wd, 32 * MS, &silent), 1);
    assert_int_equal(silent, 2000);
    assert_int_equal(roz_cmd_watchdog_write(&wd, 32 * MS, &epoch), 1);
    assert_int_equal(roz_cmd_watchdog_judge(&wd, epoch, 1, 32 * MS, 33 * MS), ROZ_CMD_SEND);
    assert_int_equal(roz_cmd_watchdog_write(&wd, 34 * MS, &epoch), 0);
}

static void test_cmd_watchdog_param(void **st)
{
    uint32_t us = 0;
    char err[300];
    (void)st;

    /* defaults: 50 ms, or 5 periods of the slower of the tick and the sender */
    assert_int_equal(roz_cmd_watchdog_param(NULL, 500, 2000, &us, err, sizeof err), ROZ_OK);
    assert_int_equal(us, 50000);
    assert_int_equal(roz_cmd_watchdog_param(NULL, 500, 0, &us, err, sizeof err), ROZ_OK);
    assert_int_equal(us, 50000);
    assert_int_equal(roz_cmd_watchdog_param(NULL, 50, 2000, &us, err, sizeof err), ROZ_OK);
    assert_int_equal(us, 100000);
    assert_int_equal(roz_cmd_watchdog_param(NULL, 500, 100000, &us, err, sizeof err), ROZ_OK);
    assert_int_equal(us, 500000);
    /* least: two periods */
    roz_param_t item = { "command_timeout_us", "4000" };
    roz_params_t p = { &item, 1 };
    assert_int_equal(roz_cmd_watchdog_param(&p, 500, 2000, &us, err, sizeof err), ROZ_OK);
    assert_int_equal(us, 4000);
    static const char *const bad[] = { "3999", "0", "60000001", "-5", "5e4", "", "50 ms" };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        item.value = bad[i];
        err[0] = '\0';
        assert_int_equal(roz_cmd_watchdog_param(&p, 500, 2000, &us, err, sizeof err),
                         ROZ_EINVAL);
        char want[64];
        snprintf(want, sizeof want, "command_timeout_us = \"%s\"", bad[i]);
        if (strstr(err, want) == NULL || strstr(err, "4000..60000000") == NULL)
            fail_msg("\"%s\": the error \"%s\" names neither key, value nor range", bad[i], err);
    }
    /* a writer too slow for any timeout */
    assert_int_equal(roz_cmd_watchdog_param(NULL, 500, 31000000, &us, err, sizeof err),
                     ROZ_EINVAL);
    assert_non_null(strstr(err, "command_timeout_us"));
}

/* ---- two threads ----------------------------------------------------------- */

/* A clock the test advances, and the latest frame as a port hands it over
 * (epoch, hold and time packed in one word: a latest-value slot). */
typedef struct {
    roz_cmd_watchdog_t wd;
    _Atomic uint64_t   clock_ns;
    _Atomic uint64_t   frame; /* epoch << 41 | hold << 40 | written time in us */
    _Atomic int        stop;
    uint32_t           unheld; /* sender: a command sent after a trip before a hold */
    uint32_t           reported; /* tick: reports */
} race_t;

static void *sender(void *arg)
{
    race_t *r = arg;
    uint32_t trips = 0;
    int need_hold = 0;
    while (!atomic_load(&r->stop)) {
        uint64_t f = atomic_load(&r->frame);
        if (f == 0)
            continue;
        uint32_t epoch = (uint32_t)(f >> 41);
        int hold = (int)((f >> 40) & 1u);
        uint64_t written = (f & ((1ull << 40) - 1u)) * 1000u;
        roz_cmd_verdict_t v =
            roz_cmd_watchdog_judge(&r->wd, epoch, hold, written, atomic_load(&r->clock_ns));
        if (roz_cmd_watchdog_trips(&r->wd) != trips) {
            trips = roz_cmd_watchdog_trips(&r->wd);
            need_hold = 1;
        }
        if (v == ROZ_CMD_SEND) {
            if (need_hold && !hold)
                r->unheld++;
            need_hold = 0;
        }
    }
    return NULL;
}

static void test_cmd_watchdog_threads(void **st)
{
    static race_t r;
    pthread_t th;
    uint32_t epoch, silent;
    (void)st;

    memset(&r, 0, sizeof r);
    roz_cmd_watchdog_init(&r.wd, 1000); /* 1 ms */
    assert_int_equal(pthread_create(&th, NULL, sender, &r), 0);
    uint64_t t = 1000000; /* us */
    for (int round = 0; round < 2000; round++) {
        /* a tick at 10 kHz for a while */
        for (int k = 0; k < 5; k++) {
            t += 100;
            atomic_store(&r.clock_ns, t * 1000u);
            if (roz_cmd_watchdog_report(&r.wd, t * 1000u, &silent))
                r.reported++;
            int hold = roz_cmd_watchdog_write(&r.wd, t * 1000u, &epoch);
            atomic_store(&r.frame, (uint64_t)epoch << 41 | (uint64_t)hold << 40 | t);
        }
        /* then silent for 5 ms every other round: the sender trips when it
         * judges the frame meanwhile (or not, when it is slow) */
        if (round % 2 == 0) {
            t += 5000;
            atomic_store(&r.clock_ns, t * 1000u);
            uint32_t before = roz_cmd_watchdog_trips(&r.wd);
            for (int spin = 0; spin < 100000 && roz_cmd_watchdog_trips(&r.wd) == before; spin++)
                ;
        }
    }
    atomic_store(&r.stop, 1);
    pthread_join(th, NULL);
    if (roz_cmd_watchdog_report(&r.wd, t * 1000u, &silent))
        r.reported++;
    assert_int_equal(r.unheld, 0);
    assert_true(roz_cmd_watchdog_trips(&r.wd) >= 1);
    assert_int_equal(r.reported, roz_cmd_watchdog_trips(&r.wd));
}

ROZ_TEST_MAIN(cmocka_unit_test(test_cmd_watchdog_trips_once_and_reports),
              cmocka_unit_test(test_cmd_watchdog_older_epoch_never_sent),
              cmocka_unit_test(test_cmd_watchdog_param),
              cmocka_unit_test(test_cmd_watchdog_threads))
