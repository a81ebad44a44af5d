/* SPDX-License-Identifier: Apache-2.0 */
/* roz_runtime_init() refuses a port that was never opened (SAFETY.md
 * §4): the firmware snippet in docs/firmware.md, followed literally, never
 * called roz_port_open(), init accepted the port, and the first tick
 * crashed in the loopback's read() on an instance never set up. Now init
 * returns ROZ_ESTATE and says why; after roz_port_open() it succeeds; after
 * roz_port_close() it refuses again. test/readme/ runs the snippet itself.
 * And roz_runtime_start() arms the tick: before it, a tick touches nothing. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_stats.h"
#include "ur5_manifest.h"

static roz_runtime_t rt;
static roz_loopback_t lb;
static char logged[ROZ_CFG_ERROR_LEN];

static void log_cb(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    (void)level;
    strncpy(logged, msg, sizeof logged - 1);
}

static void test_init_refuses_an_unopened_port(void **st)
{
    roz_runtime_config_t cfg;
    char err[128];
    roz_port_t port = roz_loopback_port(&lb, NULL, NULL);
    (void)st;

    roz_runtime_config_default(&cfg);
    cfg.manifest = &roz_manifest_ur5;
    cfg.log = log_cb;
    cfg.port = port; /* never opened */
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_ESTATE);
    assert_non_null(strstr(logged, "the port is not open"));

    assert_int_equal(roz_port_open(&port, &roz_manifest_ur5, NULL, err, sizeof err), ROZ_OK);
    cfg.port = port;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    /* not started: the tick touches nothing */
    assert_int_equal(roz_runtime_tick(&rt), ROZ_ESTATE);
    assert_int_equal(RT_COUNT(&rt, writes), 0);
    assert_null(roz_loopback_last_command(&lb));
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_ESTATE);
    assert_int_equal(roz_runtime_tick(&rt), ROZ_OK); /* nothing loaded: defaults go out */
    roz_runtime_deinit(&rt);

    roz_port_close(&port);
    cfg.port = port;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_ESTATE);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_init_refuses_an_unopened_port))
