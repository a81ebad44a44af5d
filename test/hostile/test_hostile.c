/* SPDX-License-Identifier: Apache-2.0 */
/* The hostile controller suite: one controller per attack (test/hostile/wat,
 * test/hostile/c, and a few modules built here byte by byte), each run on
 * the loopback simulator through roz_runtime. For every one the test checks
 * that
 *  - the loop keeps ticking: every tick returns, and every tick after the
 *    first state frame hands exactly one frame to the port;
 *  - the attack ends as documented: refused at load or at verification with
 *    a message naming the reason, or a fault latched at the tick of the
 *    attack with its message, defaults going out from that tick, and the
 *    controller running again only after roz_runtime_clear_faults();
 *  - the port received only values inside the manifest: the loopback's own
 *    violation count stays 0, and the test checks every written frame itself
 *    (finite, within [min, max], within max_rate of the frame before except
 *    on an e-stop).
 * The manifest is the UR5's. The test clock advances 1 us per reading and
 * is read every ROZ_CFG_DEADLINE_CHECK_UNITS units, so the 5 ms deadline is
 * millions of fuel units away and the fuel (100,000 units a tick) always
 * stops a runaway first: everything here is deterministic. */
/* white-box in part: reads the runtime's controller slots (a trapped
 * instance must never run again), which no public function exposes */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support_stats.h"
#include "support.h"
#include "support_runtime.h"
#include "ur5_manifest.h"

/* ---- the runtime under test ---------------------------------------------- */

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_test_clock_t clk;
static const roz_manifest_t *const m = &roz_manifest_ur5;

/* What the port got, frame by frame: an e-stop skips the rate cap
 * (roz/filter.h); nothing else may. */
static roz_test_frames_t frames;

enum { BUDGET_DEFAULT = 0, BUDGET_NONE };

static void start(int budget)
{
    roz_runtime_config_t cfg;

    clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_loopback_config(&cfg, &lb, m, NULL, &clk);
    if (budget == BUDGET_NONE) {
        cfg.fuel_per_tick = UINT64_MAX;
        cfg.budget_ns = UINT64_MAX;
    }
    roz_test_runtime_start(&rt, &cfg, NULL);
    roz_test_frames_reset(&frames, &rt, m, 0);
}

/* The frame the port got on this tick, checked against the manifest. */
static void check_written(int64_t tick)
{
    const double *cmd = roz_loopback_last_command(&lb);

    assert_non_null(cmd);
    roz_test_frames_check(&frames, cmd, (unsigned long long)tick);
    assert_int_equal(roz_loopback_counters(&lb).violations, 0);
}

/* One tick; returns its result after checking what reached the port. */
static int tick_checked(int64_t tick)
{
    uint64_t writes = roz_loopback_counters(&lb).writes;
    int rc = roz_runtime_tick(&rt);
    assert_true(rc == ROZ_OK || rc == ROZ_EFAULT);
    /* the loopback delivers from tick 0 */
    assert_int_equal(roz_loopback_counters(&lb).writes, writes + 1);
    check_written(tick);
    return rc;
}

static roz_runtime_slot_t *active_slot(void)
{
    int a = atomic_load(&rt.active);
    assert_true(a >= 0);
    return &rt.slot[a];
}

/* ---- modules -------------------------------------------------------------- */

/* ROZ_HOSTILE_DIR/hostile_<name>.wasm */
static const uint8_t *read_module(const char *name, size_t *len)
{
    char file[128];
    snprintf(file, sizeof file, "hostile_%s", name);
    return roz_test_wasm(ROZ_HOSTILE_DIR, file, len);
}

/* Modules built here, byte by byte, for attacks WAT cannot spell compactly. */
static uint8_t gen_buf[ROZ_CFG_WASM_MAX_MODULE_BYTES + 1024];
static size_t gen_len;

static void put(uint8_t b)
{
    assert_true(gen_len < sizeof gen_buf);
    gen_buf[gen_len++] = b;
}

static void put_u32(uint32_t v)
{
    do {
        uint8_t b = v & 0x7f;
        v >>= 7;
        put(v != 0 ? (uint8_t)(b | 0x80) : b);
    } while (v != 0);
}

/* A 5-byte LEB size placeholder, patched by sized_end() once the content is
 * written: section and function bodies alike. */
static size_t sized_begin(void)
{
    size_t at = gen_len;
    for (int i = 0; i < 5; i++)
        put(0);
    return at;
}

static void sized_end(size_t at)
{
    uint32_t size = (uint32_t)(gen_len - at - 5);
    for (int i = 0; i < 5; i++)
        gen_buf[at + (size_t)i] = (uint8_t)(((size >> (7 * i)) & 0x7f) | (i < 4 ? 0x80 : 0));
}

static size_t section_begin(uint8_t id)
{
    put(id);
    return sized_begin();
}

/* (module (memory PAGES) (func (export "process") (param i64) LOCALS...
 *   CODE) (data (i32.const 0) DATA_LEN bytes)), with the data segment's
 * declared size DATA_DECL (normally DATA_LEN), LOCALS i64 locals and CODE
 * (code_len bytes, before the body's final end) set by the generator. */
static const uint8_t *code;
static size_t code_len;

static const uint8_t *build(uint32_t pages, uint32_t locals, size_t data_len, uint32_t data_decl,
                            size_t *len)
{
    static const uint8_t head[] = { 0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00 };
    size_t s;

    gen_len = 0;
    for (size_t i = 0; i < sizeof head; i++)
        put(head[i]);
    s = section_begin(1); /* type: (func (param i64)) */
    put(1); put(0x60); put(1); put(0x7e); put(0);
    sized_end(s);
    s = section_begin(3); /* function */
    put(1); put(0);
    sized_end(s);
    s = section_begin(5); /* memory */
    put(1); put(0); put_u32(pages);
    sized_end(s);
    s = section_begin(7); /* export "process" */
    put(1); put(7);
    for (const char *p = "process"; *p != '\0'; p++)
        put((uint8_t)*p);
    put(0); put(0);
    sized_end(s);
    s = section_begin(10); /* code */
    put(1);
    size_t body = sized_begin();
    if (locals != 0) {
        put(1); put_u32(locals); put(0x7e);
    } else {
        put(0);
    }
    for (size_t i = 0; i < code_len; i++)
        put(code[i]);
    put(0x0b);
    sized_end(body);
    sized_end(s);
    if (data_len != 0 || data_decl != 0) {
        s = section_begin(11);
        put(1); put(0); put(0x41); put(0); put(0x0b); put_u32(data_decl);
        for (size_t i = 0; i < data_len; i++)
            put((uint8_t)(i * 7u));
        sized_end(s);
    }
    *len = gen_len;
    return gen_buf;
}

/* The bodies wasm3 0.5.0 compiled out of bounds before roz's scan refused
 * them (fuzz/reproducers/); and blocks nested past the scan's limit. */
static const uint8_t *with_code(const uint8_t *c, size_t n, size_t *len)
{
    code = c;
    code_len = n;
    const uint8_t *w = build(1, 0, 0, 0, len);
    code_len = 0;
    return w;
}

static const uint8_t *gen_else_alone(size_t *len)
{
    static const uint8_t c[] = { 0x02, 0x40, 0x05, 0x0b }; /* block, else, end */
    return with_code(c, sizeof c, len);
}

static const uint8_t *gen_block_params(size_t *len)
{
    /* (loop (type 0) ...): a block type naming a function type, i.e. with
     * an i64 parameter taken from an empty stack */
    static const uint8_t c[] = { 0x03, 0x00, 0x0b };
    return with_code(c, sizeof c, len);
}

static const uint8_t *gen_deep_nesting(size_t *len)
{
    static uint8_t c[2 * 300 + 300];
    size_t n = 0;
    for (int i = 0; i < 300; i++) {
        c[n++] = 0x02;
        c[n++] = 0x40;
    }
    for (int i = 0; i < 300; i++)
        c[n++] = 0x0b;
    return with_code(c, n, len);
}

/* Operands of the wrong type, or none: wasm3 0.5.0 compiled both. */
static const uint8_t *gen_type_confusion(size_t *len)
{
    static const uint8_t c[] = { 0x41, 0x01, 0x99, 0x1a }; /* i32.const 1, f64.abs, drop */
    return with_code(c, sizeof c, len);
}

static const uint8_t *gen_stack_underflow(size_t *len)
{
    static const uint8_t c[] = { 0x6a, 0x1a }; /* i32.add on an empty stack, drop */
    return with_code(c, sizeof c, len);
}

static const uint8_t *gen_simd(size_t *len)
{
    static const uint8_t c[] = { 0xfd, 0x0c }; /* v128.const: not enabled */
    return with_code(c, sizeof c, len);
}

static const uint8_t *gen_data_900k(size_t *len)
{
    return build(16, 0, 900 * 1024, 900 * 1024, len);
}

static const uint8_t *gen_too_large(size_t *len)
{
    /* pad the data segment until the module is one byte over the limit */
    (void)build(16, 0, 0, 0, len);
    size_t overhead = *len + 16;
    size_t data = ROZ_CFG_WASM_MAX_MODULE_BYTES - overhead;
    (void)build(16, 0, data, (uint32_t)data, len);
    size_t want = (size_t)ROZ_CFG_WASM_MAX_MODULE_BYTES + 1;
    data += want - *len;
    return build(16, 0, data, (uint32_t)data, len);
}

static const uint8_t *gen_data_lies(size_t *len)
{
    return build(1, 0, 16, 0x7fffffff, len);
}

static const uint8_t *gen_locals_100k(size_t *len)
{
    return build(1, 100000, 0, 0, len);
}

static const uint8_t *gen_locals_4g(size_t *len)
{
    return build(1, 0xffffffffu, 0, 0, len);
}

/* ---- per-case checks at the end of a run ---------------------------------- */

static void check_grow(void)
{
    const double *tgt = roz_runtime_last_targets(&rt);
    assert_true(tgt[0] == 0.0);  /* not one page granted */
    assert_near(tgt[1], 0.1, 1e-12); /* memory.grow(0): still one page */
}

static void check_nonfinite(void)
{
    const roz_abi_counters_t *k = &active_slot()->abi.counters;
    const double *out = roz_runtime_last_commands(&rt);
    assert_int_equal(k->set_nonfinite, 3 * 150); /* ticks 150-299, three channels */
    assert_int_equal(k->set_clamped, 2 * 150);
    /* refused values send their channels to the safe default (0) */
    assert_true(out[0] == 0.0 && out[1] == 0.0 && out[2] == 0.0);
    assert_near(out[3], 3.14, 1e-12);
    assert_near(out[4], -3.14, 1e-12);
    assert_true(out[5] == 0x1p-1074);
}

static void check_indices(void)
{
    const roz_abi_counters_t *k = &active_slot()->abi.counters;
    print_message("indices: %llu sets, %llu bad set indices, %llu bad get indices, %llu clamped\n",
                  (unsigned long long)k->sets, (unsigned long long)k->set_bad_index,
                  (unsigned long long)k->get_bad_index, (unsigned long long)k->set_clamped);
    assert_int_equal(k->sets, 64 * 300);
    assert_true(k->set_bad_index > 1000);
    assert_true(k->get_bad_index > 3000);
    assert_true(k->set_clamped > 100);
    assert_true(k->set_nonfinite == 0);
}

static void check_estop_spam(void)
{
    assert_int_equal(active_slot()->abi.counters.estop_requests, 5000);
    assert_int_equal(RT_COUNT(&rt, faults[4]), 1); /* latched (and counted) once */
}

static void check_flood(void)
{
    const roz_abi_counters_t *k = &active_slot()->abi.counters;
    assert_true(k->sets >= 1000000);
    assert_near(roz_runtime_last_targets(&rt)[0], 0.3, 1e-12);
}

static void check_metrics(void)
{
    assert_int_equal(active_slot()->abi.counters.metrics, 4000ull * 300);
    assert_true(rt.metrics.dropped > 0);
}

/* memory.grow(0xffffffff) must be refused (-1) and leave memory as it was:
 * wasm3 0.5.0 wrapped the page count in 32 bits and shrank memory with a
 * realloc inside the tick; roz's cmake/wasm3/01-memory-grow.patch refuses the delta. */
static void check_grow_wrap(void)
{
    const double *tgt = roz_runtime_last_targets(&rt);
    print_message("memory.grow(0xffffffff): %g, memory.size %g pages after 300 ticks\n", tgt[0],
                  tgt[1] / 0.1);
    assert_true(tgt[0] == -0.1);
    assert_near(tgt[1], 0.2, 1e-12);
}

/* The deepest C stack of the run stayed within the limit, plus the little a
 * check interval adds. */
static void check_stack(void)
{
    print_message("native stack: %llu bytes at most (limit %u)\n",
                  (unsigned long long)RT_COUNT(&rt, max_stack), (unsigned)ROZ_CFG_NATIVE_STACK_BYTES);
    assert_true(RT_COUNT(&rt, max_stack) > 0);
    assert_true(RT_COUNT(&rt, max_stack) <= ROZ_CFG_NATIVE_STACK_BYTES + 4096);
}

/* ---- the table ------------------------------------------------------------ */

typedef struct {
    const char *name;    /* hostile_<name>.wasm, or the generator's name */
    const uint8_t *(*gen)(size_t *len); /* builds the module instead of a file */
    int         budget;  /* BUDGET_DEFAULT or BUDGET_NONE (no fuel, no deadline) */
    int         load_rc; /* ROZ_OK, ROZ_EINVAL (refused at load), ROZ_EVERIFY (verify) */
    const char *msg;     /* in roz_runtime_error() when refused, else in the fault message */
    unsigned    faults;  /* faults that may latch; 0 = none may */
    int         fault_tick; /* controller tick the fault latches at */
    void (*check)(void); /* extra checks at the end, or NULL */
} hostile_t;

#define FUEL_150 "fuel exhausted at tick 150: 100002 units, budget 100000"

static const hostile_t cases[] = {
    /* runaway code: the budget stops it */
    { "loop_run", NULL, BUDGET_DEFAULT, ROZ_OK, FUEL_150, ROZ_FAULT_OVERRUN, 150, NULL },
    { "loop_verify", NULL, BUDGET_DEFAULT, ROZ_EVERIFY, "fuel exhausted at tick 0", 0, 0, NULL },
    { "recursion", NULL, BUDGET_DEFAULT, ROZ_OK, "at tick 150",
      ROZ_FAULT_TRAP | ROZ_FAULT_OVERRUN, 150, NULL },
    { "stack_smash", NULL, BUDGET_DEFAULT, ROZ_OK, "trap at tick 150: [trap] out of bounds",
      ROZ_FAULT_TRAP, 150, NULL },
    /* unmetered, the recursion runs until wasm3's value stack or roz's C
     * stack limit (ROZ_CFG_NATIVE_STACK_BYTES; wasm3 recurses on the C stack
     * per wasm call) stops it, whichever comes first in this build */
    { "recursion", NULL, BUDGET_NONE, ROZ_OK, "trap at tick 150: ", ROZ_FAULT_TRAP, 150,
      check_stack },
    /* memory */
    { "oob_store", NULL, BUDGET_DEFAULT, ROZ_OK, "trap at tick 150: [trap] out of bounds",
      ROZ_FAULT_TRAP, 150, NULL },
    { "oob_offset", NULL, BUDGET_DEFAULT, ROZ_OK, "trap at tick 150: [trap] out of bounds",
      ROZ_FAULT_TRAP, 150, NULL },
    { "grow", NULL, BUDGET_DEFAULT, ROZ_OK, NULL, 0, 0, check_grow },
    { "grow_wrap", NULL, BUDGET_DEFAULT, ROZ_OK, NULL, 0, 0, check_grow_wrap },
    { "memory_huge", NULL, BUDGET_DEFAULT, ROZ_EINVAL,
      "linear memory too large: 65536 pages of 64 KiB, more than ROZ_CFG_WASM_MAX_PAGES", 0, 0,
      NULL },
    { "memory_over", NULL, BUDGET_DEFAULT, ROZ_EINVAL, "17 pages of 64 KiB", 0, 0, NULL },
    { "data_oob", NULL, BUDGET_DEFAULT, ROZ_EINVAL, "data segment out of bounds", 0, 0, NULL },
    { "data_900k", gen_data_900k, BUDGET_DEFAULT, ROZ_OK, NULL, 0, 0, NULL },
    { "too_large", gen_too_large, BUDGET_DEFAULT, ROZ_EINVAL,
      "module too large: 1048577 bytes, more than ROZ_CFG_WASM_MAX_MODULE_BYTES", 0, 0, NULL },
    { "data_lies", gen_data_lies, BUDGET_DEFAULT, ROZ_EINVAL, "malformed data section", 0, 0,
      NULL },
    { "locals_100k", gen_locals_100k, BUDGET_DEFAULT, ROZ_EINVAL,
      "function 0, offset 0: more parameters and locals than the limit (4096, "
      "ROZ_CFG_WASM_MAX_LOCALS)", 0, 0, NULL },
    { "locals_4g", gen_locals_4g, BUDGET_DEFAULT, ROZ_EINVAL,
      "function 0, offset 0: more parameters and locals than the limit (4096, "
      "ROZ_CFG_WASM_MAX_LOCALS)", 0, 0, NULL },
    /* malformed code that wasm3 would compile out of bounds */
    { "else_alone", gen_else_alone, BUDGET_DEFAULT, ROZ_EINVAL,
      "function 0, offset 3: else without its if", 0, 0, NULL },
    { "block_params", gen_block_params, BUDGET_DEFAULT, ROZ_EINVAL,
      "function 0, offset 1: a block type other than none or one value", 0, 0, NULL },
    { "deep_nesting", gen_deep_nesting, BUDGET_DEFAULT, ROZ_EINVAL,
      "function 0, offset 201: blocks nested deeper than ROZ_CFG_WASM_MAX_BLOCK_DEPTH (100;", 0,
      0, NULL },
    { "type_confusion", gen_type_confusion, BUDGET_DEFAULT, ROZ_EINVAL,
      "function 0, offset 3: type mismatch: expected f64, got i32", 0, 0, NULL },
    { "stack_underflow", gen_stack_underflow, BUDGET_DEFAULT, ROZ_EINVAL,
      "function 0, offset 1: operand missing: expected i32", 0, 0, NULL },
    { "simd", gen_simd, BUDGET_DEFAULT, ROZ_EINVAL, "function 0, offset 1: opcode 0xfd", 0, 0,
      NULL },
    /* tables */
    { "table_huge", NULL, BUDGET_DEFAULT, ROZ_EINVAL,
      "table of 1000000 entries, more than ROZ_CFG_WASM_MAX_TABLE_ENTRIES", 0, 0, NULL },
    { "elem_far", NULL, BUDGET_DEFAULT, ROZ_EINVAL,
      "element segment 0 at offset 99999 needs a table of 100000 entries; the table has 4", 0,
      0, NULL },
    /* wasm3 sizes its table from the element segments, so an empty entry
     * past the last one filled reads "undefined element", not "null" */
    { "indirect_null", NULL, BUDGET_DEFAULT, ROZ_OK, "trap at tick 150: [trap] ",
      ROZ_FAULT_TRAP, 150, NULL },
    { "indirect_oob", NULL, BUDGET_DEFAULT, ROZ_OK, "[trap] undefined element", ROZ_FAULT_TRAP,
      150, NULL },
    { "indirect_type", NULL, BUDGET_DEFAULT, ROZ_OK, "[trap] indirect call type mismatch",
      ROZ_FAULT_TRAP, 150, NULL },
    /* values and indices */
    { "nonfinite_run", NULL, BUDGET_DEFAULT, ROZ_OK, NULL, 0, 0, check_nonfinite },
    { "nonfinite_verify", NULL, BUDGET_DEFAULT, ROZ_EVERIFY,
      "command.set with a non-finite value at tick 7", 0, 0, NULL },
    { "indices", NULL, BUDGET_DEFAULT, ROZ_OK, NULL, 0, 0, check_indices },
    /* host-call floods */
    { "estop_spam", NULL, BUDGET_DEFAULT, ROZ_OK, "the controller called safety.request_estop",
      ROZ_FAULT_ESTOP_REQUEST, 150, check_estop_spam },
    { "estop_verify", NULL, BUDGET_DEFAULT, ROZ_EVERIFY, "safety.request_estop at tick 42", 0, 0,
      NULL },
    /* the loop body's runs are charged whole before they run: the budget
     * stops it at the first run it cannot pay */
    { "set_flood", NULL, BUDGET_DEFAULT, ROZ_OK,
      "fuel exhausted at tick 150: 100019 units, budget 100000", ROZ_FAULT_OVERRUN, 150, NULL },
    { "set_flood", NULL, BUDGET_NONE, ROZ_OK, NULL, 0, 0, check_flood },
    { "metric_spam", NULL, BUDGET_DEFAULT, ROZ_OK, NULL, 0, 0, check_metrics },
    /* traps: at verification vs at run time */
    { "trap_verify", NULL, BUDGET_DEFAULT, ROZ_EVERIFY, "verify: trap at tick 5: [trap] unreachable",
      0, 0, NULL },
    { "trap_run", NULL, BUDGET_DEFAULT, ROZ_OK, "trap at tick 150: [trap] unreachable executed",
      ROZ_FAULT_TRAP, 150, NULL },
    { "div_zero", NULL, BUDGET_DEFAULT, ROZ_OK, "[trap] integer divide by zero", ROZ_FAULT_TRAP,
      150, NULL },
    { "bad_convert", NULL, BUDGET_DEFAULT, ROZ_OK, "[trap] invalid conversion to integer",
      ROZ_FAULT_TRAP, 150, NULL },
};

#define TICKS 300

static void run_refused(const hostile_t *hc, int rc)
{
    if (rc != hc->load_rc)
        fail_msg("%s: load returned %d (%s), expected %d", hc->name, rc, roz_runtime_error(&rt),
                 hc->load_rc);
    if (strstr(roz_runtime_error(&rt), hc->msg) == NULL)
        fail_msg("%s: error \"%s\" lacks \"%s\"", hc->name, roz_runtime_error(&rt), hc->msg);
    assert_int_equal(RT_COUNT(&rt, swaps_refused), 1);
    /* no controller: the safe defaults go out, and nothing is latched */
    for (int64_t t = 0; t < 20; t++)
        assert_int_equal(tick_checked(t), ROZ_OK);
    assert_int_equal(RT_COUNT(&rt, writes), 20);
    assert_null(roz_runtime_last_targets(&rt));
    for (uint16_t i = 0; i < m->n_commands; i++)
        assert_true(roz_runtime_last_commands(&rt)[i] == m->commands[i].default_value);
}

static void run_faulting(const hostile_t *hc)
{
    const char *fmsg = roz_runtime_fault_message(&rt);
    if (strstr(fmsg, hc->msg) == NULL)
        fail_msg("%s: fault message \"%s\" lacks \"%s\"", hc->name, fmsg, hc->msg);
    /* it never ran again after the fault; its commands are the defaults */
    assert_int_equal(RT_COUNT(&rt, controller_ticks), (uint64_t)hc->fault_tick + 1);
    for (uint16_t i = 0; i < m->n_commands; i++)
        assert_true(roz_runtime_last_commands(&rt)[i] == m->commands[i].default_value);

    /* Only the application unlatches it. A trapped or budget-stopped
     * instance is rebuilt and verified again, then restarts at tick 0. */
    int spent = (roz_runtime_faults(&rt) & ROZ_FAULT_TRAP) || active_slot()->ctrl.spent;
    uint64_t ran = RT_COUNT(&rt, controller_ticks);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    assert_int_equal(RT_COUNT(&rt, rebuilds), spent ? 1 : 0);
    for (int64_t t = 0; t < 40; t++)
        assert_int_equal(tick_checked(TICKS + t), ROZ_OK);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(RT_COUNT(&rt, controller_ticks), ran + 40);
}

static void run_case(const hostile_t *hc)
{
    size_t len;
    const uint8_t *w = hc->gen != NULL ? hc->gen(&len) : read_module(hc->name, &len);
    roz_verify_report_t rep;

    print_message("case %s%s\n", hc->name, hc->budget == BUDGET_NONE ? " (unmetered)" : "");
    start(hc->budget);
    int rc = roz_runtime_load(&rt, w, len, &rep);
    if (hc->load_rc != ROZ_OK) {
        run_refused(hc, rc);
        return;
    }
    if (rc != ROZ_OK)
        fail_msg("%s: load returned %d (%s)", hc->name, rc, roz_runtime_error(&rt));
    assert_int_equal(rep.ticks_run, ROZ_RUNTIME_VERIFY_TICKS);

    for (int64_t t = 0; t < TICKS; t++) {
        int trc = tick_checked(t);
        unsigned f = roz_runtime_faults(&rt);
        if (hc->faults == 0 || t < hc->fault_tick) {
            if (trc != ROZ_OK || f != 0)
                fail_msg("%s: tick %lld: unexpected fault 0x%x: %s", hc->name, (long long)t, f,
                         roz_runtime_fault_message(&rt));
        } else {
            assert_int_equal(trc, ROZ_EFAULT);
            if (f == 0 || (f & ~hc->faults) != 0)
                fail_msg("%s: tick %lld: faults 0x%x, expected some of 0x%x", hc->name,
                         (long long)t, f, hc->faults);
        }
    }
    assert_int_equal(RT_COUNT(&rt, ticks), TICKS);
    assert_int_equal(RT_COUNT(&rt, writes), TICKS);
    assert_int_equal(RT_COUNT(&rt, write_errors), 0);
    if (hc->faults != 0)
        run_faulting(hc);
    else
        assert_int_equal(RT_COUNT(&rt, controller_ticks), TICKS);
    if (hc->check != NULL)
        hc->check();
    assert_int_equal(roz_loopback_counters(&lb).violations, 0);
}

static int teardown(void **st)
{
    (void)st;
    roz_runtime_deinit(&rt);
    return 0;
}

static void test_hostile_case(void **st)
{
    run_case(*st);
}

/* One cmocka test per row of the table, named after it. */
int main(void)
{
    enum { N = sizeof cases / sizeof cases[0] };
    static struct CMUnitTest tests[N];
    static char names[N][64];

    for (size_t i = 0; i < N; i++) {
        snprintf(names[i], sizeof names[i], "test_hostile_%s%s", cases[i].name,
                 cases[i].budget == BUDGET_NONE ? "_unmetered" : "");
        tests[i] = (struct CMUnitTest){ names[i], test_hostile_case, NULL, teardown,
                                        (void *)(uintptr_t)&cases[i] };
    }
    return _cmocka_run_group_tests("test_hostile", tests, N, NULL, NULL);
}
