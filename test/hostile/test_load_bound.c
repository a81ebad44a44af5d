/* SPDX-License-Identifier: Apache-2.0 */
/* Loading is bounded by the module (docs/load-bound.md): every count the
 * validator walks is checked before it walks it, and the engine's compile
 * work is bounded before the engine compiles. Generated worst cases:
 *  - more imports than the ABI has functions, and more types than
 *    ROZ_CFG_WASM_MAX_TYPES with 40,000 imports (each import's type was
 *    looked up in the type section: 41 s of CPU for a 1 MiB module before it
 *    was refused for its types);
 *  - 1,000 locals, 1,000 values on the stack and empty blocks (wasm3
 *    compares every local with the stack at each: 990 x 990 x 346,000 took
 *    245 s of CPU), and the same with local.tee: refused at the block or tee
 *    that passes ROZ_CFG_WASM_MAX_COMPILE_WORK, accepted just below it.
 * The tests assert the refusal and the work bound, never a time. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "roz/controller.h"
#include "roz/abi.h"
#include "support.h"
#include "support_bench.h"
#include "ur5_manifest.h"
#include "wasm_bytes.h"

/* the bench's controller and ABI (support_bench.h) */
static roz_controller_t *const ctl = &roz_bench.ctl;
static roz_abi_t *const abi = &roz_bench.abi;

#define CAP (1u << 20)
static uint8_t *mod, *body;
static size_t n, bn;

static void put(uint8_t v) { roz_wb_byte(mod, CAP, &n, v); }
static void put_u32(uint32_t v) { roz_wb_u32(mod, CAP, &n, v); }
static void bput(uint8_t v) { roz_wb_byte(body, CAP, &bn, v); }
static void bput_u32(uint32_t v) { roz_wb_u32(body, CAP, &bn, v); }
static void section(uint8_t id)
{
    put(id);
    put_u32((uint32_t)bn);
    roz_wb_bytes(mod, CAP, &n, body, bn);
    bn = 0;
}

/* (func (export "process") (param i64) (local i32 x locals)
 *   (i32.const 0) x values, then `blocks` x (block end) and `tees` x
 *   (local.tee 1), then drop x values) */
static void build(uint32_t locals, uint32_t values, uint32_t blocks, uint32_t tees)
{
    n = bn = 0;
    roz_wb_bytes(mod, CAP, &n, "\0asm\1\0\0\0", 8);
    bput(1); bput(0x60); bput(1); bput(0x7e); bput(0);
    section(1);
    bput(1); bput(0);
    section(3);
    bput(1); bput(7); roz_wb_bytes(body, CAP, &bn, "process", 7); bput(0); bput(0);
    section(7);
    /* the body, then the code section around it */
    size_t at = 0;
    uint8_t *code = malloc(CAP);
    assert_non_null(code);
    roz_wb_u32(code, CAP, &at, 1);
    roz_wb_u32(code, CAP, &at, locals);
    roz_wb_byte(code, CAP, &at, 0x7f);
    for (uint32_t i = 0; i < values; i++) {
        roz_wb_byte(code, CAP, &at, 0x41);
        roz_wb_byte(code, CAP, &at, 0);
    }
    for (uint32_t i = 0; i < blocks; i++) {
        roz_wb_byte(code, CAP, &at, 0x02);
        roz_wb_byte(code, CAP, &at, 0x40);
        roz_wb_byte(code, CAP, &at, 0x0b);
    }
    for (uint32_t i = 0; i < tees; i++) {
        roz_wb_byte(code, CAP, &at, 0x22);
        roz_wb_byte(code, CAP, &at, 1);
    }
    for (uint32_t i = 0; i < values; i++)
        roz_wb_byte(code, CAP, &at, 0x1a);
    roz_wb_byte(code, CAP, &at, 0x0b);
    bput(1);
    bput_u32((uint32_t)at);
    roz_wb_bytes(body, CAP, &bn, code, at);
    free(code);
    section(10);
}

static int setup(void **st)
{
    mod = malloc(CAP);
    body = malloc(CAP);
    roz_bench_setup(st);
    return mod == NULL || body == NULL;
}

static int teardown(void **st)
{
    roz_bench_teardown(st);
    free(mod);
    free(body);
    return 0;
}

static void refused(const char *msg)
{
    assert_int_equal(roz_controller_load(ctl, mod, n, abi), ROZ_EINVAL);
    print_message("refused (%zu bytes): %s\n", n, roz_controller_error(ctl));
    if (strstr(roz_controller_error(ctl), msg) == NULL)
        fail_msg("error \"%s\" lacks \"%s\"", roz_controller_error(ctl), msg);
}

static void loads(void)
{
    if (roz_controller_load(ctl, mod, n, abi) != ROZ_OK)
        fail_msg("refused: %s", roz_controller_error(ctl));
    assert_int_equal(roz_controller_process(ctl, 0), ROZ_OK);
    roz_controller_unload(ctl);
}

/* n_locals x values per block: 1,000 x 1,000 */
#define WORK_PER_BLOCK (1000ull * 1000ull)
#define BLOCKS_BELOW   ((uint32_t)(ROZ_CFG_WASM_MAX_COMPILE_WORK / WORK_PER_BLOCK) - 1u)

static void test_load_bound_blocks(void **st)
{
    (void)st;
    build(999, 1000, BLOCKS_BELOW, 0); /* the work bound less a block: loads and runs */
    loads();
    build(999, 1000, BLOCKS_BELOW + 2u, 0);
    refused("compile work past ROZ_CFG_WASM_MAX_COMPILE_WORK");
    refused("(16777216): 1000 locals, 1000 values on the stack (docs/load-bound.md)");
    /* the report's module, smaller: refused at the first block past the bound,
     * whatever follows */
    build(989, 990, 346000, 0);
    refused("compile work past ROZ_CFG_WASM_MAX_COMPILE_WORK");
}

static void test_load_bound_tees(void **st)
{
    (void)st;
    uint32_t below = (uint32_t)(ROZ_CFG_WASM_MAX_COMPILE_WORK / 1000u) - 4000u;
    build(1, 1000, 0, below);
    loads();
    build(1, 1000, 0, below + 8000u);
    refused("compile work past ROZ_CFG_WASM_MAX_COMPILE_WORK");
}

/* The import section: 40,000 imports of telemetry.emit_metric, functions of
 * type @p type. */
static void emit_metric_imports(uint32_t type)
{
    bput_u32(40000);
    for (int i = 0; i < 40000; i++) {
        roz_wb_name(body, CAP, &bn, "telemetry", 9);
        roz_wb_name(body, CAP, &bn, "emit_metric", 11);
        bput(0);
        bput_u32(type);
    }
    section(2);
}

static void test_load_bound_imports(void **st)
{
    (void)st;
    /* (type (func (param f64))) and 40,000 imports of telemetry.emit_metric */
    n = bn = 0;
    roz_wb_bytes(mod, CAP, &n, "\0asm\1\0\0\0", 8);
    bput(1); bput(0x60); bput(1); bput(0x7c); bput(0);
    section(1);
    emit_metric_imports(0);
    char want[96];
    snprintf(want, sizeof want, "40000 imports, more than the %u functions of the roz ABI",
             (unsigned)roz_abi_import_count);
    refused(want);
    /* the type count is checked before the imports are walked */
    n = bn = 0;
    roz_wb_bytes(mod, CAP, &n, "\0asm\1\0\0\0", 8);
    bput_u32(ROZ_CFG_WASM_MAX_TYPES + 1u);
    for (uint32_t i = 0; i < ROZ_CFG_WASM_MAX_TYPES + 1u; i++) {
        bput(0x60); bput(1); bput(0x7c); bput(0);
    }
    section(1);
    emit_metric_imports(ROZ_CFG_WASM_MAX_TYPES);
    refused("function types, more than");
}

ROZ_TEST_MAIN(cmocka_unit_test_setup_teardown(test_load_bound_blocks, setup, teardown),
              cmocka_unit_test_setup_teardown(test_load_bound_tees, setup, teardown),
              cmocka_unit_test_setup_teardown(test_load_bound_imports, setup, teardown))
