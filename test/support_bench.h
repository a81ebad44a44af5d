/* SPDX-License-Identifier: Apache-2.0 */
/* The controller bench: one controller loaded alone, without a runtime, on
 * the UR5's ABI over a zeroed state at tick 0, as the controller and
 * hostile tests load the modules they test. The bench is one per test
 * program (roz_bench); its cmocka fixtures set it up fresh for each test. */
#ifndef ROZ_TEST_SUPPORT_BENCH_H
#define ROZ_TEST_SUPPORT_BENCH_H

#include <stddef.h>
#include <stdint.h>

#include "roz/abi.h"
#include "roz/controller.h"

typedef struct {
    roz_controller_t  ctl;
    roz_abi_t         abi;
    roz_metric_ring_t ring; /* the metrics, with roz_bench_setup_metrics() */
    double            target[ROZ_CFG_MAX_COMMANDS];
    double            state[ROZ_CFG_MAX_STATES];
} roz_bench_t;

extern roz_bench_t roz_bench;

/* cmocka setup: nothing loaded, the UR5's ABI over a zeroed state at tick
 * 0, no metric ring (a controller's metrics go nowhere). */
int roz_bench_setup(void **st);

/* roz_bench_setup(), the metrics going to the bench's ring, emptied. */
int roz_bench_setup_metrics(void **st);

/* cmocka teardown: unloads the controller (twice: unloading is idempotent). */
int roz_bench_teardown(void **st);

/* A test of the bench, set up by roz_bench_setup() or
 * roz_bench_setup_metrics() (needs <cmocka.h>). */
#define roz_bench_test(f) cmocka_unit_test_setup_teardown(f, roz_bench_setup, roz_bench_teardown)
#define roz_bench_test_metrics(f)                                                         \
    cmocka_unit_test_setup_teardown(f, roz_bench_setup_metrics, roz_bench_teardown)

/* Loads the @p len bytes at @p w, or fails the test with the refusal. */
void roz_bench_load(const uint8_t *w, size_t len);

/* Loads the @p len bytes at @p w and expects them refused: ROZ_EINVAL,
 * nothing loaded, @p msg in the error (which is printed). */
void roz_bench_refused(const uint8_t *w, size_t len, const char *msg);

#endif /* ROZ_TEST_SUPPORT_BENCH_H */
