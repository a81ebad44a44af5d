/* SPDX-License-Identifier: Apache-2.0 */
/* Port parameters: values parsed with errors naming the key and the value;
 * unknown keys refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/hal/params.h"
#include "support.h"

static const roz_param_t items[] = {
    { "command_writer_period_us", "2000" }, { "state_decimation", "0" },
    { "enable_monitor", "off" },            { "network_interface", "lo" },
    { "dds_domain", "-1" },                 { "gain", "1.5e1" },
    { "big", "99999999999999999999" },      { "flag", "maybe" },
    { "dds_domain", "7" }, /* the last one wins */
};
static const roz_params_t p = { items, sizeof items / sizeof items[0] };

static void test_params_values(void **st)
{
    char err[160] = "";
    uint32_t u = 0;
    double d = 0;
    int b = -1;
    (void)st;
    assert_int_equal(roz_params_get_u32(&p, "command_writer_period_us", 1, 100, 1000000, &u, err,
                                        sizeof err), ROZ_OK);
    assert_int_equal(u, 2000);
    assert_int_equal(roz_params_get_u32(&p, "absent", 42, 0, 100, &u, err, sizeof err), ROZ_OK);
    assert_int_equal(u, 42);
    assert_int_equal(roz_params_get_u32(&p, "dds_domain", 0, 0, 232, &u, err, sizeof err), ROZ_OK);
    assert_int_equal(u, 7);
    assert_int_equal(roz_params_get_bool(&p, "enable_monitor", 1, &b, err, sizeof err), ROZ_OK);
    assert_int_equal(b, 0);
    assert_int_equal(roz_params_get_bool(&p, "absent", 1, &b, err, sizeof err), ROZ_OK);
    assert_int_equal(b, 1);
    assert_int_equal(roz_params_get_double(&p, "gain", 0, 0, 100, &d, err, sizeof err), ROZ_OK);
    assert_true(d == 15.0);
    assert_string_equal(roz_params_get_str(&p, "network_interface", "eth0"), "lo");
    assert_string_equal(roz_params_get_str(&p, "absent", "eth0"), "eth0");
}

static void test_params_errors_name_key_and_value(void **st)
{
    static const struct { const char *key; const char *want; } cases[] = {
        { "state_decimation", "parameter state_decimation = \"0\": expected an integer in 1..1000" },
        { "big", "parameter big = \"99999999999999999999\": expected an integer in 1..1000" },
        { "network_interface", "parameter network_interface = \"lo\": expected an integer" },
    };
    char err[160];
    uint32_t u;
    double d;
    int b;
    (void)st;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        err[0] = '\0';
        assert_int_equal(roz_params_get_u32(&p, cases[i].key, 1, 1, 1000, &u, err, sizeof err),
                         ROZ_EINVAL);
        if (strstr(err, cases[i].want) == NULL)
            fail_msg("\"%s\" lacks \"%s\"", err, cases[i].want);
    }
    static const roz_param_t neg[] = { { "dds_domain", "-1" } };
    static const roz_params_t pn = { neg, 1 };
    assert_int_equal(roz_params_get_u32(&pn, "dds_domain", 0, 0, 232, &u, err, sizeof err), ROZ_EINVAL);
    assert_non_null(strstr(err, "dds_domain = \"-1\""));
    assert_int_equal(roz_params_get_bool(&p, "flag", 1, &b, err, sizeof err), ROZ_EINVAL);
    assert_non_null(strstr(err, "parameter flag = \"maybe\": expected true or false"));
    assert_int_equal(roz_params_get_double(&p, "gain", 0, 0, 10, &d, err, sizeof err), ROZ_EINVAL);
    assert_non_null(strstr(err, "parameter gain = \"1.5e1\""));
}

static void test_params_unknown_keys(void **st)
{
    static const char *const known[] = { "command_writer_period_us", "state_decimation",
                                         "enable_monitor", "network_interface", "dds_domain",
                                         "gain", "big", "flag", NULL };
    static const char *const few[] = { "dds_domain", NULL };
    char err[256];
    (void)st;
    assert_int_equal(roz_params_check_known(&p, known, "test/port", err, sizeof err), ROZ_OK);
    assert_int_equal(roz_params_check_known(&p, few, "test/port", err, sizeof err), ROZ_ENOENT);
    assert_string_equal(err, "unknown parameter \"command_writer_period_us\" for port test/port "
                             "(known: dds_domain)");
    assert_int_equal(roz_params_check_known(NULL, few, "x", err, sizeof err), ROZ_OK);
}

/* A port's table is the one source: the row's text is the numbers the
 * parser checks (roz_params_get_row_u32(), roz_params_get_row_double()). */
static const roz_port_param_info_t rows[] = {
    ROZ_PORT_PARAM_U32_ROW("state_decimation", 1, 1000, 1, "every Nth frame"),
    ROZ_PORT_PARAM_U32_ROW("dds_domain", 0, 232, 3, "the domain"),
    ROZ_PORT_PARAM_DOUBLE_ROW("gain", 0, 1e1, 2.5, " N", "a gain"),
    ROZ_PORT_PARAM_DOUBLE_ROW("absent_gain", -1, 1, 0.5, "", "a gain nobody sets"),
    ROZ_PORT_PARAM_TEXT_ROW("network_interface", "a name", "lo", "text only"),
};
#define ROWS rows, sizeof rows / sizeof rows[0]

static void test_params_rows(void **st)
{
    char err[160] = "";
    uint32_t u = 0;
    double d = 0;
    (void)st;
    /* the text the port's info shows */
    assert_string_equal(rows[0].range, "1..1000");
    assert_string_equal(rows[0].def, "1");
    assert_string_equal(rows[2].range, "0..1e1 N");
    assert_string_equal(rows[2].def, "2.5");
    assert_int_equal(rows[4].kind, ROZ_PORT_PARAM_TEXT);
    /* the numbers the parser reads from the same rows */
    assert_int_equal(roz_params_get_row_u32(&p, ROWS, "dds_domain", &u, err, sizeof err), ROZ_OK);
    assert_int_equal(u, 7);
    assert_int_equal(roz_params_get_row_double(&p, ROWS, "absent_gain", &d, err, sizeof err),
                     ROZ_OK);
    assert_true(d == 0.5);
    assert_int_equal(roz_params_get_row_u32(&p, ROWS, "state_decimation", &u, err, sizeof err),
                     ROZ_EINVAL);
    assert_string_equal(err, "parameter state_decimation = \"0\": expected an integer in 1..1000");
    assert_int_equal(roz_params_get_row_double(&p, ROWS, "gain", &d, err, sizeof err),
                     ROZ_EINVAL);
    assert_string_equal(err, "parameter gain = \"1.5e1\": expected a number in 0..10");
    /* a key without a numeric row of that kind is the port's bug, said so */
    assert_int_equal(roz_params_get_row_u32(&p, ROWS, "network_interface", &u, err, sizeof err),
                     ROZ_EINVAL);
    assert_string_equal(err, "parameter network_interface: the port's table has no numeric row "
                             "for it");
    assert_int_equal(roz_params_get_row_double(&p, ROWS, "dds_domain", &d, err, sizeof err),
                     ROZ_EINVAL);
}

static void test_params_split(void **st)
{
    char a[] = "drop=10:20", b[] = "novalue", c[] = "=x", d[] = "k=";
    roz_param_t out;
    (void)st;
    assert_int_equal(roz_params_split(a, &out), ROZ_OK);
    assert_string_equal(out.key, "drop");
    assert_string_equal(out.value, "10:20");
    assert_int_equal(roz_params_split(b, &out), ROZ_EINVAL);
    assert_int_equal(roz_params_split(c, &out), ROZ_EINVAL);
    assert_int_equal(roz_params_split(d, &out), ROZ_OK);
    assert_string_equal(out.value, "");
}

ROZ_TEST_MAIN(cmocka_unit_test(test_params_values),
              cmocka_unit_test(test_params_errors_name_key_and_value),
              cmocka_unit_test(test_params_unknown_keys),
              cmocka_unit_test(test_params_rows),
              cmocka_unit_test(test_params_split))
