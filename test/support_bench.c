/* SPDX-License-Identifier: Apache-2.0 */
#include "support_bench.h"

#include <setjmp.h>
#include <stdarg.h>
#include <string.h>

#include <cmocka.h>

#include "ur5_manifest.h"

roz_bench_t roz_bench;

static void bench_setup(roz_metric_ring_t *ring)
{
    roz_controller_init(&roz_bench.ctl);
    roz_abi_init(&roz_bench.abi, &roz_manifest_ur5, roz_bench.target, ring);
    memset(roz_bench.state, 0, sizeof roz_bench.state);
    roz_abi_begin_tick(&roz_bench.abi, 0, roz_bench.state);
}

int roz_bench_setup(void **st)
{
    (void)st;
    bench_setup(NULL);
    return 0;
}

int roz_bench_setup_metrics(void **st)
{
    (void)st;
    memset(&roz_bench.ring, 0, sizeof roz_bench.ring);
    bench_setup(&roz_bench.ring);
    return 0;
}

int roz_bench_teardown(void **st)
{
    (void)st;
    roz_controller_unload(&roz_bench.ctl);
    roz_controller_unload(&roz_bench.ctl); /* idempotent */
    return 0;
}

void roz_bench_load(const uint8_t *w, size_t len)
{
    if (roz_controller_load(&roz_bench.ctl, w, len, &roz_bench.abi) != ROZ_OK)
        fail_msg("refused: %s", roz_controller_error(&roz_bench.ctl));
}

void roz_bench_refused(const uint8_t *w, size_t len, const char *msg)
{
    roz_controller_t *c = &roz_bench.ctl;

    assert_int_equal(roz_controller_load(c, w, len, &roz_bench.abi), ROZ_EINVAL);
    assert_false(roz_controller_loaded(c));
    print_message("refused: %s\n", roz_controller_error(c));
    if (strstr(roz_controller_error(c), msg) == NULL)
        fail_msg("error \"%s\" lacks \"%s\"", roz_controller_error(c), msg);
}
