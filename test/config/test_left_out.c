/* SPDX-License-Identifier: Apache-2.0 */
/* roz built with the parts a firmware may leave out left out
 * (left_out_config.h): a controller importing a left-out function is
 * refused at load with a message naming the import and the option, never
 * linked to nothing; one importing only what is built loads and runs; %g
 * prints a double's bits; a manifest with a fall rule is refused by
 * roz_runtime_init(), never run without it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/abi.h"
#include "roz/controller.h"
#include "roz/fall.h"
#include "roz/format.h"
#include "roz/runtime.h"
#include "roz/text.h"
#include "support.h"
#include "wasm_bytes.h"

_Static_assert(ROZ_CFG_NN_IMPORTS == 0 && ROZ_CFG_MATH_IMPORTS == 0 &&
                   ROZ_CFG_BULK_IMPORTS == 0 && ROZ_CFG_FORMAT_DOUBLE == 0 &&
                   ROZ_CFG_FALL == 0,
               "built with left_out_config.h");

static const roz_channel_t commands[] = {
    { .name = "j/velocity", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = -1.0, .max = 1.0,
      .position_state = ROZ_CHANNEL_UNPAIRED, .safe_default = ROZ_SAFE_FOLLOW },
};
static const roz_channel_t states[] = {
    { .name = "j/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -1.0, .max = 1.0,
      .position_state = ROZ_CHANNEL_UNPAIRED, .safe_default = ROZ_SAFE_FOLLOW },
};
static roz_manifest_t manifest;

/* (module (type (func <params> (result <result>))) (type (func (param i64)))
 *   [(import "<mod>" "<name>" (func (type 0)))]
 *   (func (type 1)) (export "process" (func <0 or 1>))) */
static size_t module(uint8_t *b, size_t cap, const char *mod, const char *name,
                     const char *params, uint8_t result)
{
    size_t n = 0, at;
    int imported = mod != NULL;

    roz_wb_bytes(b, cap, &n, "\0asm\1\0\0\0", 8);
    roz_wb_byte(b, cap, &n, 1); /* types */
    at = roz_wb_sized_begin(b, cap, &n);
    roz_wb_byte(b, cap, &n, 2);
    roz_wb_byte(b, cap, &n, 0x60);
    roz_wb_u32(b, cap, &n, (uint32_t)strlen(params));
    for (const char *p = params; *p != '\0'; p++)
        roz_wb_byte(b, cap, &n, *p == 'i' ? 0x7f : *p == 'I' ? 0x7e : 0x7c);
    roz_wb_byte(b, cap, &n, result != 0 ? 1 : 0);
    if (result != 0)
        roz_wb_byte(b, cap, &n, result);
    roz_wb_bytes(b, cap, &n, "\x60\x01\x7e\x00", 4);
    roz_wb_sized_end(b, n, at);
    if (imported) {
        roz_wb_byte(b, cap, &n, 2); /* imports */
        at = roz_wb_sized_begin(b, cap, &n);
        roz_wb_byte(b, cap, &n, 1);
        roz_wb_name(b, cap, &n, mod, strlen(mod));
        roz_wb_name(b, cap, &n, name, strlen(name));
        roz_wb_byte(b, cap, &n, 0); /* a function */
        roz_wb_byte(b, cap, &n, 0); /* of type 0 */
        roz_wb_sized_end(b, n, at);
    }
    roz_wb_bytes(b, cap, &n, "\x03\x02\x01\x01", 4); /* one function, type 1 */
    roz_wb_bytes(b, cap, &n, "\x05\x03\x01\x00\x01", 5); /* memory 1 */
    roz_wb_byte(b, cap, &n, 7); /* exports */
    at = roz_wb_sized_begin(b, cap, &n);
    roz_wb_byte(b, cap, &n, 1);
    roz_wb_name(b, cap, &n, "process", 7);
    roz_wb_byte(b, cap, &n, 0);
    roz_wb_byte(b, cap, &n, imported ? 1 : 0);
    roz_wb_sized_end(b, n, at);
    roz_wb_bytes(b, cap, &n, "\x0a\x04\x01\x02\x00\x0b", 6); /* code: an empty body */
    return n;
}

static int setup(void **state)
{
    (void)state;
    memset(&manifest, 0, sizeof manifest);
    manifest.robot_id = "left_out";
    manifest.control_rate_hz = 100;
    manifest.commands = commands;
    manifest.n_commands = 1;
    manifest.states = states;
    manifest.n_states = 1;
    return 0;
}

/* Loads the module importing mod.name and returns the load's result; the
 * error text in err. */
static int load(const char *mod, const char *name, const char *params, uint8_t result,
                char *err, size_t errlen)
{
    static uint8_t wasm[512];
    static roz_controller_t c;
    static roz_abi_t abi;
    static double target[1];
    size_t n = module(wasm, sizeof wasm, mod, name, params, result);

    roz_abi_init(&abi, &manifest, target, NULL);
    roz_controller_init(&c);
    int rc = roz_controller_load(&c, wasm, n, &abi);
    roz_format(err, errlen, "%s", roz_controller_error(&c));
    if (rc == ROZ_OK) {
        assert_int_equal(roz_controller_process(&c, 0), ROZ_OK);
        roz_controller_unload(&c);
    }
    return rc;
}

static void test_left_out_imports_refused(void **state)
{
    static const struct {
        const char *mod, *name, *params;
        uint8_t     result;
        const char *option;
    } cases[] = {
        { "nn", "matvec", "iiiiiii", 0x7f, "ROZ_CFG_NN_IMPORTS" },
        { "nn", "act", "iii", 0x7f, "ROZ_CFG_NN_IMPORTS" },
        { "math", "sin", "F", 0x7c, "ROZ_CFG_MATH_IMPORTS" },
        { "math", "cos", "F", 0x7c, "ROZ_CFG_MATH_IMPORTS" },
        { "state", "get_all", "ii", 0x7f, "ROZ_CFG_BULK_IMPORTS" },
        { "command", "set_all", "ii", 0x7f, "ROZ_CFG_BULK_IMPORTS" },
    };
    char err[ROZ_CFG_ERROR_LEN], want[ROZ_CFG_ERROR_LEN];

    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        assert_int_equal(load(cases[i].mod, cases[i].name, cases[i].params, cases[i].result, err,
                              sizeof err),
                         ROZ_EINVAL);
        roz_format(want, sizeof want, "import %s.%s: left out of this build of roz (%s is 0)",
                   cases[i].mod, cases[i].name, cases[i].option);
        assert_string_equal(err, want);
        assert_string_equal(roz_abi_find_import(cases[i].mod, cases[i].name)->left_out,
                            cases[i].option);
    }
}

static void test_left_out_built_imports_load(void **state)
{
    char err[ROZ_CFG_ERROR_LEN];

    (void)state;
    assert_int_equal(load(NULL, NULL, "", 0, err, sizeof err), ROZ_OK);
    assert_int_equal(load("command", "count", "", 0x7f, err, sizeof err), ROZ_OK);
    assert_int_equal(load("state", "get", "i", 0x7c, err, sizeof err), ROZ_OK);
    assert_null(roz_abi_find_import("state", "get")->left_out);
}

static void test_left_out_format_double_bits(void **state)
{
    char s[64];
    roz_text_t t;

    (void)state;
    roz_format(s, sizeof s, "%g", 1.0);
    assert_string_equal(s, "f64:3ff0000000000000");
    roz_format(s, sizeof s, "[%.3g|%022g]", -0.0, 0.5);
    assert_string_equal(s, "[f64:8000000000000000|  f64:3fe0000000000000]");
    assert_int_equal(roz_format_double(s, sizeof s, 2.0), 20);
    assert_string_equal(s, "f64:4000000000000000");
    roz_text_init(&t, s, sizeof s);
    roz_text_put_double(&t, 3.0);
    roz_text_finish(&t);
    assert_string_equal(s, "f64:4008000000000000");
}

static int port_read(void *self, double *state, size_t n)
{
    (void)self;
    memset(state, 0, n * sizeof *state);
    return 1;
}

static int port_write(void *self, const double *cmd, size_t n)
{
    (void)self;
    (void)cmd;
    (void)n;
    return ROZ_OK;
}

static char logged[256];

static void log_line(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    (void)level;
    roz_format(logged, sizeof logged, "%s", msg);
}

/* Without fall detection a manifest's fall rule is refused, the message
 * naming the rule and the option, never ignored; without a rule the same
 * runtime starts; the detector never reports a fall. */
static void test_left_out_fall_rule_refused(void **state)
{
    (void)state;
    static const roz_port_ops_t ops = { .name = "left_out", .read = port_read,
                                        .write = port_write };
    static roz_runtime_t rt;
    static const roz_fall_rule_t rule = { "j", { 0, 0, 0, 0 }, 0.8, 20 };
    roz_runtime_config_t cfg;
    roz_runtime_config_default(&cfg);
    cfg.manifest = &manifest;
    cfg.port = (roz_port_t){ &ops, NULL, 1 };
    cfg.log = log_line;

    manifest.fall = &rule;
    logged[0] = '\0';
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_EINVAL);
    assert_non_null(strstr(logged, "fall rule"));
    assert_non_null(strstr(logged, "ROZ_CFG_FALL 0"));

    manifest.fall = NULL;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    roz_runtime_deinit(&rt);

    roz_fall_t f;
    double s[1] = { 0.0 };
    manifest.fall = &rule;
    roz_fall_init(&f, &manifest);
    assert_int_equal(roz_fall_tick(&f, s), 0);
    manifest.fall = NULL;
}

ROZ_TEST_MAIN(cmocka_unit_test_setup(test_left_out_imports_refused, setup),
              cmocka_unit_test_setup(test_left_out_built_imports_load, setup),
              cmocka_unit_test(test_left_out_format_double_bits),
              cmocka_unit_test_setup(test_left_out_fall_rule_refused, setup))
