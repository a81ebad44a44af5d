/* SPDX-License-Identifier: Apache-2.0 */
/* A port instance of an application built with other ROZ_CFG_* options
 * than the library (roz/port.h, roz_port_layout_t). This file is compiled
 * with ROZ_CFG_MAX_COMMANDS=16 against libraries built with the default
 * 256: its roz_loopback_t (and every registered port's instance) is
 * smaller than the library's. roz_port_open() and the port constructors
 * pass the caller's layout; the library refuses it with ROZ_ECONFIG naming
 * the option, without writing the instance (ASan: before, lb_open wrote
 * 57,504 bytes past it). The registry (roz/ports.h) is compiled into this
 * test with these options, so each port's constructor is expanded here, as
 * in an application built so, and every registered port is held to it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/port.h"
#include "roz/port/loopback.h"
#include "roz/ports.h"
#include "support.h"

#if ROZ_CFG_MAX_COMMANDS != 16
#error "test_port_layout is compiled with ROZ_CFG_MAX_COMMANDS=16"
#endif

static const roz_channel_t commands[] = {
    { .name = "j/velocity", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = -1.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_manifest_t one = { "one", "generic", 100, commands, 1, NULL, 0, NULL, NULL, 0, 0, NULL, NULL };

static void assert_untouched(const void *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        assert_int_equal(((const unsigned char *)p)[i], 0x5a);
}

static void test_port_layout_loopback_refused(void **st)
{
    static roz_loopback_t lb; /* sized for 16 commands */
    char err[ROZ_CFG_ERROR_LEN] = "";
    (void)st;
    memset(&lb, 0x5a, sizeof lb);
    roz_port_t p = roz_loopback_port(&lb, NULL, NULL);
    assert_int_equal(roz_port_open(&p, &one, NULL, err, sizeof err), ROZ_ECONFIG);
    print_message("%s\n", err);
    assert_non_null(strstr(err, "ROZ_CFG_MAX_COMMANDS is 16 in the application, 256 in "
                                "libroz_core"));
    assert_int_equal(p.opened, 0);
    assert_untouched(&lb, sizeof lb);
}

/* Every registered port's constructor (some write their instance) refuses
 * it too: the port it gives back opens to ROZ_ECONFIG, and nothing was
 * written. */
static void test_port_layout_constructor_refused(void **st)
{
    static _Alignas(max_align_t) unsigned char storage[1u << 20];
    (void)st;
    for (size_t i = 0; i < ROZ_PORTS_COUNT; i++) {
        const roz_port_entry_t *e = &roz_ports[i];
        char err[ROZ_CFG_ERROR_LEN] = "";
        if (e->ops == NULL)
            continue;
        print_message("%s: %zu bytes\n", e->id, e->size);
        assert_true(e->size <= sizeof storage && e->align <= _Alignof(max_align_t));
        memset(storage, 0x5a, e->size);
        roz_port_t p = e->construct(storage, NULL, NULL);
        assert_untouched(storage, e->size);
        assert_int_equal(roz_port_open(&p, &one, NULL, err, sizeof err), ROZ_ECONFIG);
        assert_non_null(strstr(err, "ROZ_CFG_MAX_COMMANDS"));
        assert_untouched(storage, e->size);
    }
}

static void test_port_layout_check_names_the_difference(void **st)
{
    roz_port_layout_t mine = ROZ_PORT_LAYOUT_INIT;
    char err[ROZ_CFG_ERROR_LEN];
    (void)st;
    assert_int_equal(roz_port_layout_check(&mine, err, sizeof err), ROZ_ECONFIG);
    assert_non_null(strstr(err, "ROZ_CFG_MAX_COMMANDS"));
    mine.max_commands = 256;
    assert_int_equal(roz_port_layout_check(&mine, err, sizeof err), ROZ_OK);
    mine.max_joints++;
    assert_int_equal(roz_port_layout_check(&mine, err, sizeof err), ROZ_ECONFIG);
    assert_non_null(strstr(err, "ROZ_CFG_MAX_JOINTS"));
    assert_int_equal(roz_port_layout_check(NULL, err, sizeof err), ROZ_EINVAL);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_port_layout_loopback_refused),
              cmocka_unit_test(test_port_layout_constructor_refused),
              cmocka_unit_test(test_port_layout_check_names_the_difference))
