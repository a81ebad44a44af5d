/* SPDX-License-Identifier: Apache-2.0 */
/* An application built with other ROZ_CFG_* options than libroz_core
 * (SAFETY.md §4; docs/install.md). This file is compiled with ROZ_CFG_MAX_COMMANDS=16
 * against a library built with the default 256: its roz_runtime_t is
 * smaller than the library's. roz_runtime_init() passes the caller's view
 * of the layout (ROZ_RUNTIME_LAYOUT_INIT, expanded here) and the library
 * refuses it with ROZ_ECONFIG and a message naming the option, without
 * writing to the storage (ASan: before, roz_runtime_init wrote past it). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/runtime.h"
#include "support.h"

#if ROZ_CFG_MAX_COMMANDS != 16
#error "test_layout is compiled with ROZ_CFG_MAX_COMMANDS=16"
#endif

static roz_runtime_t rt; /* sized for 16 commands */
static char logged[ROZ_CFG_ERROR_LEN];
static int calls;

static void log_cb(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    assert_int_equal(level, ROZ_LOG_ERROR);
    strncpy(logged, msg, sizeof logged - 1);
    calls++;
}

static void test_layout_mismatch_is_refused(void **st)
{
    roz_runtime_config_t cfg;
    (void)st;
    memset(&rt, 0x5a, sizeof rt);
    roz_runtime_config_default(&cfg);
    cfg.log = log_cb;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_ECONFIG);
    assert_int_equal(calls, 1);
    print_message("%s\n", logged);
    assert_non_null(strstr(logged, "ROZ_CFG_MAX_COMMANDS is 16 in the application, 256 in "
                                   "libroz_core"));
    /* nothing written to the caller's storage */
    for (size_t i = 0; i < sizeof rt; i++)
        assert_int_equal(((const unsigned char *)&rt)[i], 0x5a);
    assert_string_equal(roz_strerror(ROZ_ECONFIG),
                        "the application and roz were built with different configurations");
}

static void test_layout_check_names_the_difference(void **st)
{
    roz_runtime_layout_t mine = ROZ_RUNTIME_LAYOUT_INIT;
    char err[ROZ_CFG_ERROR_LEN];
    (void)st;
    assert_int_equal(roz_runtime_layout_check(&mine, err, sizeof err), ROZ_ECONFIG);
    assert_non_null(strstr(err, "ROZ_CFG_MAX_COMMANDS"));
    /* the library's own view (as if built alike) passes: only commands differ here */
    mine.max_commands = 256;
    mine.runtime_bytes = 0;
    assert_int_equal(roz_runtime_layout_check(&mine, err, sizeof err), ROZ_ECONFIG);
    assert_non_null(strstr(err, "sizeof(roz_runtime_t)"));
    assert_int_equal(roz_runtime_layout_check(NULL, err, sizeof err), ROZ_EINVAL);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_layout_mismatch_is_refused),
              cmocka_unit_test(test_layout_check_names_the_difference))
