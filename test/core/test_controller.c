/* SPDX-License-Identifier: Apache-2.0 */
/* Loading controllers: every refusal names its import, export or problem;
 * good controllers run through the ABI. */
/* white-box: this test reads the private fields of the module it tests */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/controller.h"
#include "support.h"
#include "support_bench.h"
#include "ur5_manifest.h"

/* the bench's controller and ABI (support_bench.h) */
static roz_controller_t *const ctl = &roz_bench.ctl;
static roz_abi_t *const abi = &roz_bench.abi;

typedef struct {
    const char *controller;
    const char *message; /* substring of the error */
} refusal_t;

static const refusal_t refusals[] = {
    { "bad_unknown_import", "unknown import env.open_valve" },
    { "bad_bad_signature", "import command.set has type (i32, f32) -> i32, expected (i32, f64) -> i32" },
    { "bad_no_process", "no export \"process\"" },
    { "bad_process_signature", "export \"process\" has type (i32) -> (), expected (i64) -> ()" },
    { "bad_imported_memory", "import env.memory is a memory" },
    { "bad_start_function", "start function" },
};

static void test_controller_refusals(void **st)
{
    for (size_t i = 0; i < sizeof refusals / sizeof refusals[0]; i++) {
        size_t len;
        const uint8_t *w = roz_test_controller(refusals[i].controller, &len);
        roz_bench_setup(st);
        assert_int_equal(roz_controller_load(ctl, w, len, abi), ROZ_EINVAL);
        assert_false(roz_controller_loaded(ctl));
        if (strstr(roz_controller_error(ctl), refusals[i].message) == NULL)
            fail_msg("%s: error \"%s\" lacks \"%s\"", refusals[i].controller,
                     roz_controller_error(ctl), refusals[i].message);
        assert_int_equal(roz_controller_process(ctl, 0), ROZ_ESTATE);
    }
}

static void test_controller_garbage(void **st)
{
    static const uint8_t junk[] = { 0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00, 0x01, 0xff };
    static const uint8_t text[] = "(module)";
    (void)st;
    assert_int_equal(roz_controller_load(ctl, text, sizeof text, abi), ROZ_EINVAL);
    assert_non_null(strstr(roz_controller_error(ctl), "not a WebAssembly"));
    assert_int_equal(roz_controller_load(ctl, junk, sizeof junk, abi), ROZ_EINVAL);
    assert_non_null(strstr(roz_controller_error(ctl), "malformed"));
    assert_int_equal(roz_controller_load(ctl, junk, 0, abi), ROZ_EINVAL);
    assert_int_equal(roz_controller_load(ctl, NULL, 0, abi), ROZ_EINVAL);
    size_t len;
    const uint8_t *w = roz_test_controller("hold", &len);
    assert_int_equal(roz_controller_load(ctl, w, ROZ_CFG_WASM_MAX_MODULE_BYTES + 1, abi),
                     ROZ_EINVAL);
    assert_non_null(strstr(roz_controller_error(ctl), "ROZ_CFG_WASM_MAX_MODULE_BYTES"));
}

static void test_controller_runs_sine(void **st)
{
    size_t len;
    const uint8_t *w = roz_test_controller("sine", &len);
    (void)st;
    assert_int_equal(roz_controller_load(ctl, w, len, abi), ROZ_OK);
    assert_int_equal(roz_controller_load(ctl, w, len, abi), ROZ_ESTATE);
    abi->tick = 50; /* 0.5 s at 100 Hz: sin(pi/2 + i*pi/3) */
    assert_int_equal(roz_controller_process(ctl, 50), ROZ_OK);
    for (int i = 0; i < 6; i++)
        assert_near(roz_bench.target[i],
                    1.57 * sin(3.141592653589793 / 2 + i * 3.141592653589793 / 3), 1e-9);
    assert_int_equal(abi->counters.sets, 6);
}

static void test_controller_pd_reads_state(void **st)
{
    size_t len;
    const uint8_t *w = roz_test_controller("pd_hold", &len);
    (void)st;
    assert_int_equal(roz_controller_load(ctl, w, len, abi), ROZ_OK);
    roz_bench.state[1] = -1.0; /* shoulder_lift at -1.0, target -1.2: v = 2 * -0.2 */
    assert_int_equal(roz_controller_process(ctl, 0), ROZ_OK);
    assert_near(roz_bench.target[1], -0.4, 1e-12);
    assert_near(roz_bench.target[0], 0.0, 1e-12);
}

/* The validator's scratch is the caller's: roz_controller_load_in() works
 * in the storage given (filled with a pattern first: nothing may depend on
 * it being zero), a refusal says the same as with the scratch on the stack,
 * and the same scratch serves the next load. */
static void test_controller_load_in_scratch(void **st)
{
    static roz_load_scratch_t scratch;
    static const unsigned char no_process[] = { 0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00 };
    char on_stack[ROZ_CFG_ERROR_LEN];
    size_t len;
    const uint8_t *w = roz_test_controller("pd_hold", &len);
    (void)st;
    assert_true(sizeof scratch >= ROZ_CONTROLLER_SCRATCH_BYTES);
    memset(&scratch, 0xa5, sizeof scratch);
    assert_int_equal(roz_controller_load(ctl, no_process, sizeof no_process, abi), ROZ_EINVAL);
    strcpy(on_stack, roz_controller_error(ctl));
    assert_int_equal(roz_controller_load_in(ctl, no_process, sizeof no_process, abi, &scratch),
                     ROZ_EINVAL);
    assert_string_equal(roz_controller_error(ctl), on_stack);
    assert_int_equal(roz_controller_load_in(ctl, w, len, abi, &scratch), ROZ_OK);
    roz_bench.state[1] = -1.0;
    assert_int_equal(roz_controller_process(ctl, 0), ROZ_OK);
    assert_near(roz_bench.target[1], -0.4, 1e-12);
}

static void test_controller_traps(void **st)
{
    static const struct { const char *name; int64_t tick; const char *msg; } traps[] = {
        { "bad_trap_run", 150, "unreachable" },
        { "bad_oob_memory", 150, "out of bounds" },
        { "bad_recursion", 150, "stack" },
    };
    for (size_t i = 0; i < sizeof traps / sizeof traps[0]; i++) {
        size_t len;
        const uint8_t *w = roz_test_controller(traps[i].name, &len);
        roz_bench_setup(st);
        assert_int_equal(roz_controller_load(ctl, w, len, abi), ROZ_OK);
        assert_int_equal(roz_controller_process(ctl, 0), ROZ_OK);
        assert_int_equal(roz_controller_process(ctl, traps[i].tick), ROZ_ETRAP);
        if (strstr(roz_controller_error(ctl), traps[i].msg) == NULL)
            fail_msg("%s: \"%s\" lacks \"%s\"", traps[i].name, roz_controller_error(ctl),
                     traps[i].msg);
        roz_controller_unload(ctl);
    }
}

static void test_controller_memory_is_fixed(void **st)
{
    roz_metric_ring_t ring;
    roz_metric_t m;
    size_t len;
    const uint8_t *w = roz_test_controller("bad_grow_memory", &len);
    (void)st;
    memset(&ring, 0, sizeof ring);
    abi->metrics = &ring;
    assert_int_equal(roz_controller_load(ctl, w, len, abi), ROZ_OK);
    for (int t = 0; t < 5; t++)
        assert_int_equal(roz_controller_process(ctl, t), ROZ_OK);
    for (int t = 0; t < 5; t++) {
        assert_int_equal(roz_metric_ring_pop(&ring, &m), 1);
        assert_true(m.value == -1.0); /* memory.grow refused */
    }
}

/* The WAT twins of the C examples compute the same targets, bit for bit. */
static void test_controller_c_and_wat_agree(void **st)
{
    static const char *const pairs[][2] = { { "sine", "sine_wat" },
                                            { "constant_velocity", "constant_velocity_wat" } };
    static double out_c[ROZ_CFG_MAX_COMMANDS];
    (void)st;
    for (size_t p = 0; p < 2; p++) {
        roz_controller_t a, b;
        roz_abi_t abi_b;
        static double target_b[ROZ_CFG_MAX_COMMANDS];
        size_t la, lb;
        const uint8_t *wa = roz_test_controller(pairs[p][0], &la);
        const uint8_t *wb = roz_test_controller(pairs[p][1], &lb);
        roz_controller_init(&a);
        roz_controller_init(&b);
        roz_abi_init(&abi_b, &roz_manifest_ur5, target_b, NULL);
        roz_abi_begin_tick(&abi_b, 0, roz_bench.state);
        assert_int_equal(roz_controller_load(&a, wa, la, abi), ROZ_OK);
        assert_int_equal(roz_controller_load(&b, wb, lb, &abi_b), ROZ_OK);
        for (int64_t t = 0; t < 300; t++) {
            abi->tick = abi_b.tick = t;
            assert_int_equal(roz_controller_process(&a, t), ROZ_OK);
            assert_int_equal(roz_controller_process(&b, t), ROZ_OK);
            memcpy(out_c, roz_bench.target, sizeof out_c);
            assert_memory_equal(out_c, target_b, 6 * sizeof(double));
        }
        roz_controller_unload(&a);
        roz_controller_unload(&b);
    }
}

ROZ_TEST_MAIN(roz_bench_test(test_controller_refusals),
              roz_bench_test(test_controller_garbage),
              roz_bench_test(test_controller_runs_sine),
              roz_bench_test(test_controller_pd_reads_state),
              roz_bench_test(test_controller_load_in_scratch),
              roz_bench_test(test_controller_traps),
              roz_bench_test(test_controller_memory_is_fixed),
              roz_bench_test(test_controller_c_and_wat_agree))
