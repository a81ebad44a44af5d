/* SPDX-License-Identifier: Apache-2.0 */
/* The frame checks every port runs (roz/hal/crc32.h, roz/hal/link.h): the
 * CRC against the reference values of Unitree's crc32_core and a
 * bit-by-bit model of its definition, and the link verdicts, counters and
 * sequence wrap-around. */
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/hal/crc32.h"
#include "roz/hal/link.h"
#include "crc32_reference.h"
#include "support.h"

/* CRC-32/MPEG-2 over bytes, MSB first. */
static uint32_t crc_mpeg2(const uint8_t *b, size_t n)
{
    uint32_t crc = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        crc ^= (uint32_t)b[i] << 24;
        for (int k = 0; k < 8; k++)
            crc = (crc & 0x80000000u) ? (crc << 1) ^ 0x04C11DB7u : crc << 1;
    }
    return crc;
}

static void test_crc32_reference_values(void **st)
{
    static uint32_t zero[250];
    (void)st;
    /* an all-zero G1 LowCmd_ image: 250 words */
    assert_int_equal(roz_crc32_words(zero, 250), 0xFE172F9Fu);
    assert_int_equal(roz_crc32_words(NULL, 0), 0xFFFFFFFFu);
    /* the MPEG-2 check value anchors the byte model below */
    assert_int_equal(crc_mpeg2((const uint8_t *)"123456789", 9), 0x0376E6E7u);
}

static void test_crc32_matches_its_definition(void **st)
{
    uint32_t w[522];
    uint8_t bytes[sizeof w];
    uint32_t x = 12345u;
    (void)st;
    for (size_t i = 0; i < 522; i++) {
        x = x * 1664525u + 1013904223u;
        w[i] = x;
    }
    for (size_t n = 0; n <= 522; n += 29) {
        assert_int_equal(roz_crc32_words(w, n), roz_crc32_reference(w, n));
        /* MPEG-2 over each word's bytes, most significant first */
        for (size_t i = 0; i < n; i++) {
            bytes[4 * i] = (uint8_t)(w[i] >> 24);
            bytes[4 * i + 1] = (uint8_t)(w[i] >> 16);
            bytes[4 * i + 2] = (uint8_t)(w[i] >> 8);
            bytes[4 * i + 3] = (uint8_t)w[i];
        }
        assert_int_equal(roz_crc32_words(w, n), crc_mpeg2(bytes, 4 * n));
    }
    /* every single-bit error in a LowState_-sized image changes the CRC */
    uint32_t good = roz_crc32_words(w, 522);
    for (size_t bit = 0; bit < 522 * 32; bit++) {
        w[bit / 32] ^= 1u << (bit % 32);
        assert_true(roz_crc32_words(w, 522) != good);
        w[bit / 32] ^= 1u << (bit % 32);
    }
}

#define MS 1000000ull

static void test_link_verdicts(void **st)
{
    roz_link_t l;
    (void)st;
    roz_link_init(&l, 100 * MS, 0);
    assert_int_equal(l.window, ROZ_LINK_DEFAULT_WINDOW);
    assert_int_equal(roz_link_check(&l, 0, 7, 0), ROZ_LINK_BAD_CRC); /* before the first */
    assert_false(l.alive);
    assert_int_equal(roz_link_check(&l, 1, 1000, 0), ROZ_LINK_FIRST);
    assert_int_equal(roz_link_check(&l, 1, 1001, 2 * MS), ROZ_LINK_FRESH);
    assert_int_equal(roz_link_check(&l, 1, 1001, 4 * MS), ROZ_LINK_REPLAY); /* duplicate */
    assert_int_equal(roz_link_check(&l, 1, 1004, 6 * MS), ROZ_LINK_FRESH);  /* 2 missing */
    assert_int_equal(roz_link_check(&l, 1, 1003, 6 * MS), ROZ_LINK_REPLAY); /* overtaken */
    assert_int_equal(roz_link_check(&l, 0, 1005, 8 * MS), ROZ_LINK_BAD_CRC);
    assert_int_equal(roz_link_check(&l, 1, 1004 - 64, 8 * MS), ROZ_LINK_REPLAY); /* window edge */
    assert_int_equal(roz_link_check(&l, 1, 1004 - 65, 8 * MS), ROZ_LINK_RESTART); /* beyond */
    assert_int_equal(l.last_seq, 1004 - 65);
    assert_int_equal(roz_link_check(&l, 1, 1004 - 64, 10 * MS), ROZ_LINK_FRESH);
    assert_int_equal(l.accepted, 5);
    assert_int_equal(l.crc_errors, 2);
    assert_int_equal(l.replays, 3);
    assert_int_equal(l.missing, 2);
    assert_int_equal(l.restarts, 1);
    assert_int_equal(l.returns, 0);
    assert_string_equal(roz_link_verdict_name(ROZ_LINK_RESTART), "restart");
    assert_string_equal(roz_link_verdict_name(ROZ_LINK_BAD_CRC), "bad crc");
}

static void test_link_silence(void **st)
{
    roz_link_t l;
    (void)st;
    roz_link_init(&l, 100 * MS, 0);
    assert_int_equal(roz_link_check(&l, 1, 5, 0), ROZ_LINK_FIRST);
    assert_false(roz_link_lost(&l, 99 * MS));
    assert_true(roz_link_lost(&l, 100 * MS));
    /* after the silence: the last frame replayed stays a replay ... */
    assert_int_equal(roz_link_check(&l, 1, 5, 200 * MS), ROZ_LINK_REPLAY);
    assert_int_equal(roz_link_check(&l, 1, 3, 200 * MS), ROZ_LINK_REPLAY);
    /* ... a newer frame is the peer coming back */
    assert_int_equal(roz_link_check(&l, 1, 9, 200 * MS), ROZ_LINK_RESTART);
    assert_int_equal(l.returns, 1);
    assert_int_equal(roz_link_check(&l, 1, 10, 202 * MS), ROZ_LINK_FRESH);
    assert_int_equal(l.missing, 0); /* no gap counted across the silence */
    /* lost_after 0: never lost by time */
    roz_link_init(&l, 0, 4);
    assert_int_equal(roz_link_check(&l, 1, 5, 0), ROZ_LINK_FIRST);
    assert_false(roz_link_lost(&l, UINT64_MAX));
    assert_int_equal(roz_link_check(&l, 1, 6, UINT64_MAX), ROZ_LINK_FRESH);
    assert_int_equal(roz_link_check(&l, 1, 1, UINT64_MAX), ROZ_LINK_RESTART); /* window 4 */
}

/* Older frames in order within the window stay replays: a peer that
 * restarted and counts again from 0 cannot be told from old frames replayed
 * in order or frames overtaken in transit, and none of them may pass. */
static void test_link_in_order_old_frames(void **st)
{
    roz_link_t l;
    (void)st;
    roz_link_init(&l, 0, 0);
    assert_int_equal(roz_link_check(&l, 1, 30, 0), ROZ_LINK_FIRST);
    for (uint32_t s = 0; s < 30; s++) /* counting again from 0 */
        assert_int_equal(roz_link_check(&l, 1, s, s), ROZ_LINK_REPLAY);
    assert_int_equal(roz_link_check(&l, 1, 30, 30), ROZ_LINK_REPLAY);
    assert_int_equal(roz_link_check(&l, 1, 31, 31), ROZ_LINK_FRESH); /* past the old one */
    /* frames overtaken in transit, two and more in a row */
    for (uint32_t s = 200; s < 204; s++)
        assert_int_equal(roz_link_check(&l, 1, s, s), ROZ_LINK_FRESH);
    assert_int_equal(roz_link_check(&l, 1, 210, 210), ROZ_LINK_FRESH);
    for (uint32_t s = 204; s < 210; s++)
        assert_int_equal(roz_link_check(&l, 1, s, 211), ROZ_LINK_REPLAY);
    assert_int_equal(roz_link_check(&l, 1, 211, 212), ROZ_LINK_FRESH);
    assert_int_equal(l.restarts, 0);
    /* windows beyond half the sequence space are clamped */
    roz_link_init(&l, 0, 0xFFFFFFFFu);
    assert_int_equal(l.window, ROZ_LINK_MAX_WINDOW);
}

static void test_link_wraps(void **st)
{
    roz_link_t l;
    (void)st;
    roz_link_init(&l, 0, 0);
    assert_int_equal(roz_link_check(&l, 1, 0xFFFFFFFEu, 0), ROZ_LINK_FIRST);
    assert_int_equal(roz_link_check(&l, 1, 0xFFFFFFFFu, 1), ROZ_LINK_FRESH);
    assert_int_equal(roz_link_check(&l, 1, 0u, 2), ROZ_LINK_FRESH);  /* wraps */
    assert_int_equal(roz_link_check(&l, 1, 2u, 3), ROZ_LINK_FRESH);  /* 1 missing */
    assert_int_equal(roz_link_check(&l, 1, 0xFFFFFFFFu, 4), ROZ_LINK_REPLAY);
    assert_int_equal(l.missing, 1);
    /* half the sequence space ahead is behind: a restart, not a jump */
    assert_int_equal(roz_link_check(&l, 1, 2u + 0x80000000u, 5), ROZ_LINK_RESTART);
}

/* 10^6 random frames (CRC good or bad, sequence near the last, far off or
 * wrapped, receive times with silences): every verdict agrees with its
 * definition, and the counters add up. Seeded; the seed is printed. */
static void test_link_random(void **st)
{
    uint64_t x = 0x9E3779B97F4A7C15ull, now = 0;
    roz_link_t l;
    uint64_t calls = 0, first = 0;
    (void)st;
    print_message("seed 0x9E3779B97F4A7C15\n");
    roz_link_init(&l, 50 * MS, 16);
    for (int i = 0; i < 1000000; i++) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        int crc_ok = (x & 15u) != 0u;
        uint32_t r = (uint32_t)(x >> 8) & 1023u, seq;
        if (r < 900)
            seq = l.last_seq + (uint32_t)(int32_t)((int)(r % 40) - 20); /* near */
        else if (r < 1000)
            seq = (uint32_t)(x >> 32);                                  /* anywhere */
        else
            seq = l.last_seq + 0x7FFFFFF0u + (r & 31u);                 /* half-way round */
        now += (x >> 40) % 64 == 0 ? 60 * MS : MS;                      /* some silences */
        int was_alive = l.alive, lost = roz_link_lost(&l, now);
        uint32_t last = l.last_seq, ahead = seq - last;
        int newer = ahead != 0u && ahead < 0x80000000u;
        roz_link_verdict_t v = roz_link_check(&l, crc_ok, seq, now);
        calls++;
        roz_link_verdict_t want;
        if (!crc_ok)
            want = ROZ_LINK_BAD_CRC;
        else if (!was_alive)
            want = ROZ_LINK_FIRST;
        else if (newer)
            want = lost ? ROZ_LINK_RESTART : ROZ_LINK_FRESH;
        else if (last - seq <= 16u)
            want = ROZ_LINK_REPLAY;
        else
            want = ROZ_LINK_RESTART;
        if (v != want)
            fail_msg("frame %d: seq %u after %u: %s, expected %s", i, seq, last,
                     roz_link_verdict_name(v), roz_link_verdict_name(want));
        first += v == ROZ_LINK_FIRST;
        if (v == ROZ_LINK_BAD_CRC || v == ROZ_LINK_REPLAY)
            assert_int_equal(l.last_seq, last);
        else
            assert_int_equal(l.last_seq, seq);
    }
    assert_int_equal(first, 1);
    assert_int_equal(l.accepted + l.crc_errors + l.replays, calls);
    assert_true(l.restarts > 0 && l.returns > 0 && l.replays > 0 && l.missing > 0);
}

/* The copy for other threads: every field round-trips, and a reader on
 * another thread always gets one published state, never a mix of two. */
static void test_link_shared_copy(void **st)
{
    roz_link_shared_t sh;
    roz_link_t l, out;
    (void)st;

    roz_link_shared_init(&sh);
    assert_int_equal(roz_link_shared_read(&sh, &out), ROZ_OK);
    assert_int_equal(out.accepted, 0);
    memset(&l, 0, sizeof l);
    l.lost_after_ns = 123456789012ull;
    l.window = 77;
    l.alive = 1;
    l.last_seq = 0xfffffff0u;
    l.last_ns = 987654321098ull;
    l.accepted = 1;
    l.crc_errors = 2;
    l.replays = 3;
    l.restarts = 4;
    l.returns = 5;
    l.missing = 6;
    roz_link_shared_publish(&sh, &l);
    assert_int_equal(roz_link_shared_read(&sh, &out), ROZ_OK);
    assert_memory_equal(&out, &l, sizeof l);
}

static roz_link_shared_t shared;

static void *shared_writer(void *arg)
{
    roz_link_t l;
    (void)arg;
    roz_link_init(&l, 0, 0);
    for (uint64_t k = 1; k <= 200000; k++) {
        l.accepted = k;
        l.crc_errors = 2 * k;
        l.replays = 3 * k;
        l.missing = k ^ 0x5555u;
        l.last_seq = (uint32_t)k;
        roz_link_shared_publish(&shared, &l);
    }
    return NULL;
}

static void test_link_shared_threads(void **st)
{
    pthread_t th;
    roz_link_t out;
    uint64_t last = 0, reads = 0;
    (void)st;

    roz_link_shared_init(&shared);
    assert_int_equal(pthread_create(&th, NULL, shared_writer, NULL), 0);
    while (last < 200000) {
        if (roz_link_shared_read(&shared, &out) != ROZ_OK)
            continue; /* the writer kept it busy: try again */
        reads++;
        assert_true(out.accepted >= last); /* never goes back */
        assert_int_equal(out.crc_errors, 2 * out.accepted);
        assert_int_equal(out.replays, 3 * out.accepted);
        if (out.accepted != 0) {
            assert_int_equal(out.missing, out.accepted ^ 0x5555u);
            assert_int_equal(out.last_seq, (uint32_t)out.accepted);
        }
        last = out.accepted;
    }
    assert_int_equal(pthread_join(th, NULL), 0);
    assert_true(reads > 0);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_crc32_reference_values),
              cmocka_unit_test(test_crc32_matches_its_definition),
              cmocka_unit_test(test_link_verdicts),
              cmocka_unit_test(test_link_silence),
              cmocka_unit_test(test_link_in_order_old_frames),
              cmocka_unit_test(test_link_wraps),
              cmocka_unit_test(test_link_random),
              cmocka_unit_test(test_link_shared_copy),
              cmocka_unit_test(test_link_shared_threads))
