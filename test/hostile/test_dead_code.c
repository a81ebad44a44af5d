/* SPDX-License-Identifier: Apache-2.0 */
/* Dead code (docs/known-issues.md: valid modules wrongly refused). The instructions
 * after a br, br_table, return or unreachable, up to the end or else of
 * their block, never run and may pop values their block never pushed (the
 * operand stack is polymorphic there). wasm3 0.5.0 compiled them, and
 * refused some valid modules with "no operation found for opcode" (a
 * differential run's find: test/diff/findings/). roz's patch
 * (cmake/wasm3/13-dead-code.patch) skips them. Each module here is valid
 * (wat2wasm checks), must load, must give the right values through
 * telemetry.emit_metric, and must not be charged for code that never runs. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/abi.h"
#include "roz/controller.h"
#include "roz/module.h"
#include "support.h"
#include "support_wat.h"
#include "ur5_manifest.h"

static uint8_t wasm[64 * 1024];
static char text[16 * 1024];
static roz_controller_t ctl;
static roz_abi_t abi;
static roz_metric_ring_t ring;
static double state[ROZ_CFG_MAX_STATES];
static double targets[ROZ_CFG_MAX_COMMANDS];

/* Loads process() = `body` (with `funcs` before it), runs it once and
 * checks the metrics it emitted. Returns the fuel it used. */
static uint64_t run(const char *funcs, const char *body, const double *want, size_t n_want)
{
    snprintf(text, sizeof text,
             "(module\n"
             " (import \"telemetry\" \"emit_metric\" (func $m (param f64)))\n"
             " (memory 1)\n"
             " %s\n"
             " (func (export \"process\") (param $tick i64) (local $i i32) (local $f f32)\n"
             "%s))\n",
             funcs, body);
    size_t len = roz_test_wat(text, wasm, sizeof wasm);
    roz_controller_init(&ctl);
    roz_abi_init(&abi, &roz_manifest_ur5, targets, &ring);
    roz_abi_begin_tick(&abi, 0, state);
    if (roz_controller_load(&ctl, wasm, len, &abi) != ROZ_OK)
        fail_msg("refused: %s\n%s", roz_controller_error(&ctl), text);
    if (roz_controller_process(&ctl, 0) != ROZ_OK)
        fail_msg("trapped: %s\n%s", roz_controller_error(&ctl), text);
    double got[16];
    roz_metric_t item;
    size_t n = 0;
    while (n < 16 && roz_metric_ring_pop(&ring, &item))
        got[n++] = item.value;
    assert_int_equal(n, n_want);
    for (size_t i = 0; i < n; i++) {
        if (got[i] != want[i])
            fail_msg("metric %zu = %g, expected %g\n%s", i, got[i], want[i], text);
    }
    uint64_t fuel = roz_controller_fuel_used(&ctl);
    roz_controller_unload(&ctl);
    return fuel;
}

static void test_dead_code_after_every_terminator(void **st)
{
    (void)st;
    /* the finding's shape: an f32.sub after a br_table, its operands from
     * below the block, f64 and f32 values live outside it */
    static const double w1[] = { 3.0, 1.5 };
    run("", "(local.set $f (f32.const 1.5))\n"
            "(call $m (block $b (result f64)\n"
            "  (f64.const 2)\n"
            "  (block $c\n"
            "    (br_table $c $c (i32.const 1))\n"
            "    (f32.sub) (drop))\n"
            "  (drop)\n"
            "  (f64.const 3)))\n"
            "(call $m (f64.promote_f32 (local.get $f)))",
        w1, 2);
    /* after br, with blocks, loops and an if/else nested in the dead code */
    static const double w2[] = { 7.0 };
    run("", "(call $m (f64.convert_i32_s (block (result i32)\n"
            "  (i32.const 7) (br 0)\n"
            "  (block (loop (if (i32.const 1) (then (nop)) (else (nop)))))\n"
            "  (f32.const 1) (f32.const 2) (f32.sub) (drop) (f32.add) (drop)\n"
            "  (memory.fill) (memory.copy) (i32.load offset=4) (drop) (call $m)\n"
            "  (br_table 0 0) (i32.const 9))))",
        w2, 1);
    /* after return in a then-arm; the else-arm compiles and runs */
    static const double w3[] = { 5.0 };
    run("(func $pick (param i32) (result i32)\n"
        "  (if (result i32) (local.get 0)\n"
        "    (then (return (i32.const 4)) (f32.mul) (drop) (i32.const 99))\n"
        "    (else (i32.const 5))))",
        "(call $m (f64.convert_i32_s (call $pick (i32.const 0))))", w3, 1);
    /* after unreachable, in an arm that is never taken */
    static const double w4[] = { 1.0 };
    run("", "(if (i32.eqz (i32.const 1)) (then (unreachable) (f64.div) (call $m)))\n"
            "(call $m (f64.const 1))",
        w4, 1);
    /* after a br to a loop (a continue): the loop runs 3 times */
    static const double w5[] = { 3.0 };
    run("", "(loop $l\n"
            "  (local.set $i (i32.add (local.get $i) (i32.const 1)))\n"
            "  (if (i32.lt_u (local.get $i) (i32.const 3)) (then (br $l) (f64.sqrt) (drop))))\n"
            "(call $m (f64.convert_i32_s (local.get $i)))",
        w5, 1);
}

static void test_dead_code_costs_nothing(void **st)
{
    static const double w[] = { 1.0 };
    (void)st;
    uint64_t lean = run("", "(block (call $m (f64.const 1)) (br 0))", w, 1);
    uint64_t dead = run("", "(block (call $m (f64.const 1)) (br 0)\n"
                            "  (i32.const 1) (drop) (i32.const 1) (drop) (i32.const 1) (drop)\n"
                            "  (loop (br 0)))",
                        w, 1);
    assert_int_equal(dead, lean);
}

/* The differential run's find itself: a module of wasm-tools smith that
 * wasm3 0.5.0 refused ("no operation found for opcode") loads and runs. */
static void test_dead_code_the_find(void **st)
{
    static uint8_t big[256 * 1024];
    char err[256];
    size_t len = 0;
    (void)st;
    if (roz_module_read_file(ROZ_DIFF_FINDINGS "/wasm3-no-operation-for-opcode.wat", big,
                             sizeof big, &len, err, sizeof err) != ROZ_OK)
        fail_msg("%s", err);
    roz_controller_init(&ctl);
    roz_abi_init(&abi, &roz_manifest_ur5, targets, &ring);
    roz_abi_begin_tick(&abi, 0, state);
    if (roz_controller_load(&ctl, big, len, &abi) != ROZ_OK)
        fail_msg("refused: %s", roz_controller_error(&ctl));
    assert_int_equal(roz_controller_process(&ctl, 0), ROZ_OK);
    roz_controller_unload(&ctl);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_dead_code_after_every_terminator),
              cmocka_unit_test(test_dead_code_costs_nothing),
              cmocka_unit_test(test_dead_code_the_find))
