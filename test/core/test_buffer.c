/* SPDX-License-Identifier: Apache-2.0 */
/* The latest-value buffer: single-thread semantics, and a two-thread stress
 * test (run under ThreadSanitizer by the test command) that checks the reader
 * never sees a torn frame and sequence numbers never go back. */
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/buffer.h"
#include "support.h"

#define N 97
ROZ_BUFFER_DEFINE(buf, N);

static void test_buffer_basic(void **st)
{
    roz_buffer_frame_t f;
    double v[N];
    (void)st;
    roz_buffer_init(&buf, buf_slots, N);
    assert_int_equal(roz_buffer_read(&buf, &f), ROZ_ENOENT);
    assert_int_equal(f.seq, 0);
    assert_false(f.fresh);

    for (int i = 0; i < N; i++)
        v[i] = i;
    assert_int_equal(roz_buffer_write(&buf, v, 111), 1);
    assert_int_equal(roz_buffer_read(&buf, &f), 1);
    assert_true(f.fresh);
    assert_int_equal(f.seq, 1);
    assert_int_equal(f.stamp_ns, 111);
    assert_true(f.values[5] == 5.0 && f.values[N - 1] == N - 1);
    /* nothing new: same frame, not fresh */
    assert_int_equal(roz_buffer_read(&buf, &f), 0);
    assert_int_equal(f.seq, 1);
    assert_false(f.fresh);
    /* three writes between reads: the reader gets the newest */
    for (int k = 2; k <= 4; k++) {
        v[0] = k;
        roz_buffer_write(&buf, v, (uint64_t)k);
    }
    assert_int_equal(roz_buffer_read(&buf, &f), 1);
    assert_int_equal(f.seq, 4);
    assert_true(f.values[0] == 4.0);
    /* write_begin/commit in place */
    double *slot = roz_buffer_write_begin(&buf);
    for (int i = 0; i < N; i++)
        slot[i] = -1.0;
    assert_int_equal(roz_buffer_write_commit(&buf, 9), 5);
    assert_int_equal(roz_buffer_read(&buf, &f), 1);
    assert_true(f.values[0] == -1.0 && f.values[N - 1] == -1.0);
}

/* Every frame k has all values equal to k: a torn frame mixes two. */
#define FRAMES 200000
static atomic_int done;

static void *producer(void *arg)
{
    (void)arg;
    for (int k = 1; k <= FRAMES; k++) {
        double *slot = roz_buffer_write_begin(&buf);
        for (int i = 0; i < N; i++)
            slot[i] = (double)k;
        roz_buffer_write_commit(&buf, (uint64_t)k);
    }
    atomic_store(&done, 1);
    return NULL;
}

static void test_buffer_two_threads(void **st)
{
    pthread_t th;
    roz_buffer_frame_t f;
    uint64_t last = 0, fresh = 0, reads = 0;
    (void)st;
    roz_buffer_init(&buf, buf_slots, N);
    atomic_store(&done, 0);
    assert_int_equal(pthread_create(&th, NULL, producer, NULL), 0);
    for (;;) {
        int finished = atomic_load(&done);
        int rc = roz_buffer_read(&buf, &f);
        reads++;
        if (rc >= 0) {
            double k = f.values[0];
            for (int i = 1; i < N; i++) {
                if (f.values[i] != k)
                    fail_msg("torn frame: value %d is %g, value 0 is %g", i, f.values[i], k);
            }
            assert_true((uint64_t)k == f.seq);
            assert_true(f.stamp_ns == f.seq);
            assert_true(f.seq >= last);
            assert_int_equal(rc == 1, f.seq > last);
            fresh += rc == 1;
            last = f.seq;
        }
        if (finished && last == FRAMES)
            break;
    }
    pthread_join(th, NULL);
    assert_true(fresh > 0 && fresh <= FRAMES);
    print_message("reads %llu, fresh frames seen %llu of %d\n", (unsigned long long)reads,
                  (unsigned long long)fresh, FRAMES);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_buffer_basic),
              cmocka_unit_test(test_buffer_two_threads))
