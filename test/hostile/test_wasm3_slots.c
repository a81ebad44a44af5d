/* SPDX-License-Identifier: Apache-2.0 */
/* wasm3's slot bookkeeping against valid, hostile modules (docs/known-issues.md). Every
 * module here is generated in memory by a small wasm binary builder, passes
 * roz's validator (WebAssembly 1.0) and runs through roz_controller_load and
 * roz_controller_process. The sweeps prove that
 *  - a block, if or loop whose result is i32, i64, f32 or f64, left by br,
 *    br_if, br_table, return or its own end with 0..3 extra operands (of
 *    every type, constant or computed into wasm3's registers) below the value
 *    or below the construct, at several recursion depths, delivers the right
 *    value and leaves the extra operands intact: wasm3 0.5.0 copied the
 *    operand under an f32/f64 branch value into the fp0 register alias "slot"
 *    60002, far past the value stack (upstream #465;
 *    cmake/wasm3/10-block-results.patch);
 *  - a call (direct or call_indirect) with 1..255 i32, i64 or f64 arguments,
 *    made at every recursion depth up to and past the end of the 64 KiB
 *    value stack, from frames of several sizes, either runs with the right
 *    result or traps cleanly with a stack overflow: wasm3 0.5.0 copied the
 *    arguments past the end of the stack before the callee's check
 *    (upstream #477; cmake/wasm3/11-call-args.patch);
 *  - multi-value blocks (the only way to reach upstream #471's
 *    CopyStackSlotsR overrun) are refused at load.
 * Without the patches the ASan build reports the out-of-bounds writes (and
 * the #465 sweep also fails on wrong values in any build). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/abi.h"
#include "roz/controller.h"
#include "support.h"
#include "ur5_manifest.h"
#include "wasm_bytes.h"
#include "support_thin.h"

/* ---- a small wasm binary builder ------------------------------------------ */

enum { I32 = 0x7f, I64 = 0x7e, F32 = 0x7d, F64 = 0x7c };

enum {
    OP_UNREACHABLE = 0x00, OP_BLOCK = 0x02, OP_LOOP = 0x03, OP_IF = 0x04, OP_ELSE = 0x05,
    OP_END = 0x0b, OP_BR = 0x0c, OP_BR_IF = 0x0d, OP_BR_TABLE = 0x0e, OP_RETURN = 0x0f,
    OP_CALL = 0x10, OP_CALL_INDIRECT = 0x11, OP_DROP = 0x1a, OP_LOCAL_GET = 0x20,
    OP_LOCAL_SET = 0x21, OP_LOCAL_TEE = 0x22, OP_I32_CONST = 0x41, OP_I64_CONST = 0x42,
    OP_F32_CONST = 0x43, OP_F64_CONST = 0x44, OP_I32_EQZ = 0x45, OP_I32_GE_U = 0x4f,
    OP_I32_ADD = 0x6a, OP_I32_SUB = 0x6b, OP_I64_ADD = 0x7c, OP_F32_ADD = 0x92,
    OP_F64_ADD = 0xa0, OP_I32_WRAP_I64 = 0xa7, OP_I64_EXTEND_I32_U = 0xad,
    OP_F32_CONVERT_I32_S = 0xb2, OP_F64_CONVERT_I32_S = 0xb7, OP_F64_CONVERT_I64_S = 0xb9,
    OP_F64_PROMOTE_F32 = 0xbb
};

typedef struct {
    uint8_t b[64 * 1024];
    size_t  n;
} buf_t;

/* The test's wrappers of test/wasm_bytes.h around one buffer. */
static void put(buf_t *o, uint8_t v) { roz_wb_byte(o->b, sizeof o->b, &o->n, v); }
static void put_u32(buf_t *o, uint32_t v) { roz_wb_u32(o->b, sizeof o->b, &o->n, v); }
static void put_s64(buf_t *o, int64_t v) { roz_wb_s64(o->b, sizeof o->b, &o->n, (uint64_t)v); }
static void put_bytes(buf_t *o, const void *p, size_t n)
{
    roz_wb_bytes(o->b, sizeof o->b, &o->n, p, n);
}
static void put_name(buf_t *o, const char *s)
{
    roz_wb_name(o->b, sizeof o->b, &o->n, s, strlen(s));
}

/* A constant of type t with the value v (integers take v's integer part). */
static void put_const(buf_t *o, uint8_t t, double v)
{
    switch (t) {
    case I32: put(o, OP_I32_CONST); put_s64(o, (int32_t)v); break;
    case I64: put(o, OP_I64_CONST); put_s64(o, (int64_t)v); break;
    case F32: {
        float f = (float)v;
        uint32_t u;
        memcpy(&u, &f, 4);
        put(o, OP_F32_CONST);
        roz_wb_le(o->b, sizeof o->b, &o->n, u, 4);
        break;
    }
    default: {
        uint64_t u;
        memcpy(&u, &v, 8);
        put(o, OP_F64_CONST);
        roz_wb_le(o->b, sizeof o->b, &o->n, u, 8);
        break;
    }
    }
}

/* A value of type t equal to v, computed from local 0 (which holds 0 where
 * this runs) so that wasm3 leaves it in its r0/fp0 register. */
static void put_computed(buf_t *o, uint8_t t, double v)
{
    put(o, OP_LOCAL_GET); put(o, 0);
    switch (t) {
    case I32: put_const(o, I32, v); put(o, OP_I32_ADD); break;
    case I64: put(o, OP_I64_EXTEND_I32_U); put_const(o, I64, v); put(o, OP_I64_ADD); break;
    case F32: put(o, OP_F32_CONVERT_I32_S); put_const(o, F32, v); put(o, OP_F32_ADD); break;
    default:  put(o, OP_F64_CONVERT_I32_S); put_const(o, F64, v); put(o, OP_F64_ADD); break;
    }
}

static void put_value(buf_t *o, uint8_t t, double v, int computed)
{
    if (computed)
        put_computed(o, t, v);
    else
        put_const(o, t, v);
}

/* Converts the value of type t on top of the stack to f64. */
static void put_to_f64(buf_t *o, uint8_t t)
{
    switch (t) {
    case I32: put(o, OP_F64_CONVERT_I32_S); break;
    case I64: put(o, OP_F64_CONVERT_I64_S); break;
    case F32: put(o, OP_F64_PROMOTE_F32); break;
    default: break;
    }
}

/* A module: telemetry.emit_metric is function 0 (type 0, (f64)->()),
 * process(i64) is function 1 (type 1); the caller adds types from 2 on and
 * function bodies from 1 on (a body is its locals declaration, code and
 * final end). An optional table of one entry holds function `elem`. */
#define MAX_TYPES 8
#define MAX_FUNCS 4
typedef struct {
    uint32_t n_types;
    uint32_t n_params[MAX_TYPES];
    uint8_t  params[MAX_TYPES][256];
    uint8_t  result[MAX_TYPES]; /* 0: none */
    uint8_t  result2[MAX_TYPES]; /* a second result (multi-value), 0: none */
    uint32_t n_funcs;           /* defined */
    uint32_t func_type[MAX_FUNCS];
    buf_t    body[MAX_FUNCS];
    int      table;
    uint32_t elem;
} module_t;

static module_t mod;
static buf_t wasm;

static void module_begin(void)
{
    memset(&mod, 0, sizeof mod);
    mod.n_types = 2;
    mod.n_params[0] = 1; mod.params[0][0] = F64;
    mod.n_params[1] = 1; mod.params[1][0] = I64;
    mod.n_funcs = 1;
    mod.func_type[0] = 1;
}

static uint32_t add_type(uint32_t np, const uint8_t *params, uint8_t result)
{
    uint32_t t = mod.n_types++;
    assert_true(t < MAX_TYPES);
    mod.n_params[t] = np;
    memcpy(mod.params[t], params, np);
    mod.result[t] = result;
    return t;
}

/* A new defined function of type t; returns its body and its index. */
static buf_t *add_func(uint32_t t, uint32_t *index)
{
    uint32_t f = mod.n_funcs++;
    assert_true(f < MAX_FUNCS);
    mod.func_type[f] = t;
    mod.body[f].n = 0;
    *index = f + 1; /* after the import */
    return &mod.body[f];
}

static size_t sized_begin(buf_t *o) { return roz_wb_sized_begin(o->b, sizeof o->b, &o->n); }
static void sized_end(buf_t *o, size_t at) { roz_wb_sized_end(o->b, o->n, at); }

static size_t section(buf_t *o, uint8_t id)
{
    put(o, id);
    return sized_begin(o);
}

static void module_end(void)
{
    static const uint8_t head[] = { 0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00 };
    buf_t *o = &wasm;
    size_t s;

    o->n = 0;
    put_bytes(o, head, sizeof head);
    s = section(o, 1);
    put_u32(o, mod.n_types);
    for (uint32_t t = 0; t < mod.n_types; t++) {
        put(o, 0x60);
        put_u32(o, mod.n_params[t]);
        put_bytes(o, mod.params[t], mod.n_params[t]);
        put_u32(o, (mod.result[t] != 0 ? 1u : 0u) + (mod.result2[t] != 0 ? 1u : 0u));
        if (mod.result[t] != 0)
            put(o, mod.result[t]);
        if (mod.result2[t] != 0)
            put(o, mod.result2[t]);
    }
    sized_end(o, s);
    s = section(o, 2);
    put_u32(o, 1);
    put_name(o, "telemetry");
    put_name(o, "emit_metric");
    put(o, 0); put(o, 0);
    sized_end(o, s);
    s = section(o, 3);
    put_u32(o, mod.n_funcs);
    for (uint32_t f = 0; f < mod.n_funcs; f++)
        put_u32(o, mod.func_type[f]);
    sized_end(o, s);
    if (mod.table) {
        s = section(o, 4);
        put(o, 1); put(o, 0x70); put(o, 0); put(o, 1);
        sized_end(o, s);
    }
    s = section(o, 7);
    put_u32(o, 1);
    put_name(o, "process");
    put(o, 0); put(o, 1);
    sized_end(o, s);
    if (mod.table) {
        s = section(o, 9);
        put(o, 1); put(o, 0);
        put(o, OP_I32_CONST); put(o, 0); put(o, OP_END);
        put(o, 1); put_u32(o, mod.elem);
        sized_end(o, s);
    }
    s = section(o, 10);
    put_u32(o, mod.n_funcs);
    for (uint32_t f = 0; f < mod.n_funcs; f++) {
        size_t b = sized_begin(o);
        put_bytes(o, mod.body[f].b, mod.body[f].n);
        sized_end(o, b);
    }
    sized_end(o, s);
}

/* ---- the controller -------------------------------------------------------- */

static roz_controller_t ctl;
static roz_abi_t abi;
static roz_metric_ring_t ring;
static double target[ROZ_CFG_MAX_COMMANDS];
static double state[ROZ_CFG_MAX_STATES];

static void load(const char *what)
{
    roz_controller_unload(&ctl);
    roz_controller_init(&ctl);
    memset(&ring, 0, sizeof ring);
    roz_abi_init(&abi, &roz_manifest_ur5, target, &ring);
    roz_abi_begin_tick(&abi, 0, state);
    if (roz_controller_load(&ctl, wasm.b, wasm.n, &abi) != ROZ_OK)
        fail_msg("%s: refused: %s", what, roz_controller_error(&ctl));
}

static int teardown(void **st)
{
    (void)st;
    roz_controller_unload(&ctl);
    return 0;
}

/* The module built, loaded afresh (no tick begun): roz_controller_load()'s
 * result. */
static int load_fresh(void)
{
    roz_controller_unload(&ctl);
    roz_controller_init(&ctl);
    memset(&ring, 0, sizeof ring);
    roz_abi_init(&abi, &roz_manifest_ur5, target, &ring);
    return roz_controller_load(&ctl, wasm.b, wasm.n, &abi);
}

/* The next metric, which must be there. */
static double metric(const char *what)
{
    roz_metric_t m;
    if (roz_metric_ring_pop(&ring, &m) != 1)
        fail_msg("%s: a metric is missing", what);
    return m.value;
}

/* ---- item 0: results of blocks left by a branch ---------------------------- */

enum { K_BR, K_BR_IF, K_BR_TABLE, K_RETURN, K_END, N_KINDS };
enum { C_BLOCK, C_IF, C_LOOP, N_CONSTRUCTS };
static const char *const kind_name[] = { "br", "br_if", "br_table", "return", "end" };
static const char *const construct_name[] = { "block", "if", "loop" };
static const uint8_t types[] = { I32, I64, F32, F64 };

/* The value the construct delivers and the one it must not. */
#define VALUE 2.5
#define OTHER 7.5
/* Extra operand k holds 100 + k + 0.25 (integers: 100 + k). */
static double extra_value(uint8_t t, int k)
{
    return (t == I32 || t == I64) ? 100.0 + k : 100.25 + k;
}
static double expect_of(uint8_t t, double v)
{
    return (t == I32 || t == I64) ? floor(v) : v;
}

typedef struct {
    int     kind, construct, n_extra, inside, value_computed, extra_computed;
    uint8_t type, extra_type;
} branch_case_t;

/* Drops what a not-taken br_if left in the construct (the value and the
 * extras inside) and pushes the construct's value again. */
static void refill(buf_t *o, const branch_case_t *c)
{
    put(o, OP_DROP);
    for (int k = 0; k < (c->inside ? c->n_extra : 0); k++)
        put(o, OP_DROP);
    put_const(o, c->type, VALUE);
}

static void put_extras(buf_t *o, const branch_case_t *c)
{
    for (int k = 0; k < c->n_extra; k++)
        put_value(o, c->extra_type, extra_value(c->extra_type, k), c->extra_computed);
}

/* The construct, leaving one value of c->type. Locals: 0 depth (0 here),
 * 1 a counter (i32), 2 the result (c->type). */
static void put_construct(buf_t *o, const branch_case_t *c)
{
    const uint8_t T = c->type;
    const int in = c->inside;

    if (c->construct == C_LOOP) {
        /* block (result T) loop (result T) ... end end: value branches
         * leave through the block (label 1); br_if and br_table also
         * continue the loop (label 0, no value) once, with the extras on
         * the stack. */
        put(o, OP_BLOCK); put(o, T);
        put(o, OP_LOOP); put(o, T);
        if (in)
            put_extras(o, c);
        if (c->kind == K_BR_TABLE) {
            /* block: ++counter >= 2 ? out of it (label 0) : continue the
             * loop (label 1), over the extras; labels of one arity */
            put(o, OP_BLOCK); put(o, 0x40);
            put(o, OP_LOCAL_GET); put(o, 1); put(o, OP_I32_CONST); put(o, 1); put(o, OP_I32_ADD);
            put(o, OP_LOCAL_TEE); put(o, 1); put(o, OP_I32_CONST); put(o, 2); put(o, OP_I32_GE_U);
            put(o, OP_BR_TABLE); put(o, 1); put(o, 1); put(o, 0);
            put(o, OP_END);
        }
        put_value(o, T, VALUE, c->value_computed);
        switch (c->kind) {
        case K_BR: put(o, OP_BR); put(o, 1); break;
        case K_BR_IF:
            /* continue while ++counter < 2, then fall out with the value */
            put(o, OP_LOCAL_GET); put(o, 1); put(o, OP_I32_CONST); put(o, 1); put(o, OP_I32_ADD);
            put(o, OP_LOCAL_TEE); put(o, 1); put(o, OP_I32_CONST); put(o, 2); put(o, OP_I32_GE_U);
            put(o, OP_I32_EQZ);
            put(o, OP_BR_IF); put(o, 0);
            refill(o, c);
            break;
        case K_BR_TABLE: /* out with the value: label 1 for index 0 and default */
            put(o, OP_LOCAL_GET); put(o, 0);
            put(o, OP_BR_TABLE); put(o, 1); put(o, 1); put(o, 1);
            break;
        case K_RETURN: put(o, OP_RETURN); break;
        default: break;
        }
        put(o, OP_END);
        put(o, OP_END);
        return;
    }
    if (c->construct == C_IF) {
        put(o, OP_LOCAL_GET); put(o, 0); put(o, OP_I32_EQZ); /* 1 */
        put(o, OP_IF); put(o, T);
    } else {
        put(o, OP_BLOCK); put(o, T);
    }
    if (in)
        put_extras(o, c);
    put_value(o, T, VALUE, c->value_computed);
    switch (c->kind) {
    case K_BR: put(o, OP_BR); put(o, 0); break;
    case K_BR_IF:
        put(o, OP_LOCAL_GET); put(o, 0); put(o, OP_I32_EQZ); /* 1: taken */
        put(o, OP_BR_IF); put(o, 0);
        put(o, OP_DROP);
        for (int k = 0; k < (in ? c->n_extra : 0); k++)
            put(o, OP_DROP);
        put_const(o, T, OTHER);
        break;
    case K_BR_TABLE:
        put(o, OP_LOCAL_GET); put(o, 0); /* 0 */
        put(o, OP_BR_TABLE); put(o, 1); put(o, 0); put(o, 0);
        break;
    case K_RETURN: put(o, OP_RETURN); break;
    default: break;
    }
    if (c->construct == C_IF) {
        put(o, OP_ELSE);
        put_const(o, T, OTHER);
    }
    put(o, OP_END);
}

/* process(tick) emits f(tick) as f64; f(d) recurses d times, then runs the
 * construct with the extras, emits each extra operand that sat below the
 * construct (top first), and returns the construct's value. */
static void build_branch_module(const branch_case_t *c)
{
    uint8_t p_i32 = I32;
    uint32_t t_f, f_f;
    buf_t *o;

    module_begin();
    t_f = add_type(1, &p_i32, c->type);
    o = add_func(t_f, &f_f);
    /* f: locals 1 i32 counter, 2 result */
    put(o, 2); put(o, 1); put(o, I32); put(o, 1); put(o, c->type);
    put(o, OP_BLOCK); put(o, 0x40);
    put(o, OP_LOCAL_GET); put(o, 0); put(o, OP_I32_EQZ); put(o, OP_BR_IF); put(o, 0);
    put(o, OP_LOCAL_GET); put(o, 0); put(o, OP_I32_CONST); put(o, 1); put(o, OP_I32_SUB);
    put(o, OP_CALL); put_u32(o, f_f);
    put(o, OP_RETURN);
    put(o, OP_END);
    if (!c->inside)
        put_extras(o, c);
    put_construct(o, c);
    if (!c->inside) {
        put(o, OP_LOCAL_SET); put(o, 2);
        for (int k = 0; k < c->n_extra; k++) {
            put_to_f64(o, c->extra_type);
            put(o, OP_CALL); put(o, 0);
        }
        put(o, OP_LOCAL_GET); put(o, 2);
    }
    put(o, OP_END);

    o = &mod.body[0];
    o->n = 0;
    put(o, 0);
    put(o, OP_LOCAL_GET); put(o, 0); put(o, OP_I32_WRAP_I64);
    put(o, OP_CALL); put_u32(o, f_f);
    put_to_f64(o, c->type);
    put(o, OP_CALL); put(o, 0);
    put(o, OP_END);
    module_end();
}

static void test_block_results_sweep(void **st)
{
    static const int64_t depths[] = { 0, 1, 2, 7, 40 };
    unsigned modules = 0, runs = 0, combo = 0;
    branch_case_t c;
    (void)st;

    for (c.kind = 0; c.kind < N_KINDS; c.kind++)
    for (c.construct = 0; c.construct < N_CONSTRUCTS; c.construct++)
    for (size_t ti = 0; ti < sizeof types; ti++)
    for (c.n_extra = 0; c.n_extra <= 3; c.n_extra++)
    for (size_t ei = 0; ei < (c.n_extra > 0 ? sizeof types : 1); ei++)
    for (c.inside = 0; c.inside <= 1; c.inside++)
    for (int form = 0; form < 4; form++) {
        char what[160];
        /* under an emulator every third combination (support_thin.h) */
        if (combo++ % ROZ_TEST_THIN(3) != 0)
            continue;
        /* a fallthrough end takes exactly its value: extras only outside */
        if (c.kind == K_END && c.inside && c.n_extra > 0)
            continue;
        if (c.n_extra == 0 && (c.inside || (form & 2) != 0))
            continue;
        c.type = types[ti];
        c.extra_type = types[ei];
        c.value_computed = form & 1;
        c.extra_computed = (form & 2) != 0;
        snprintf(what, sizeof what, "%s %s (result %s), %d %s%s extras %s, value %s",
                 kind_name[c.kind], construct_name[c.construct],
                 c.type == I32 ? "i32" : c.type == I64 ? "i64" : c.type == F32 ? "f32" : "f64",
                 c.n_extra,
                 c.extra_computed ? "computed " : "",
                 c.extra_type == I32 ? "i32" : c.extra_type == I64 ? "i64"
                     : c.extra_type == F32 ? "f32" : "f64",
                 c.inside ? "inside" : "below", c.value_computed ? "computed" : "constant");
        build_branch_module(&c);
        load(what);
        modules++;
        for (size_t d = 0; d < sizeof depths / sizeof depths[0]; d++) {
            int rc = roz_controller_process(&ctl, depths[d]);
            if (rc != ROZ_OK)
                fail_msg("%s, depth %lld: %s", what, (long long)depths[d],
                         roz_controller_error(&ctl));
            runs++;
            if (!c.inside && c.kind != K_RETURN) /* return skips the emits */
                for (int k = c.n_extra - 1; k >= 0; k--) {
                    double e = metric(what);
                    if (e != expect_of(c.extra_type, extra_value(c.extra_type, k)))
                        fail_msg("%s, depth %lld: extra %d is %g", what,
                                 (long long)depths[d], k, e);
                }
            double v = metric(what);
            if (v != expect_of(c.type, VALUE))
                fail_msg("%s, depth %lld: result %g, expected %g", what, (long long)depths[d],
                         v, expect_of(c.type, VALUE));
        }
        roz_metric_t m;
        assert_int_equal(roz_metric_ring_pop(&ring, &m), 0);
    }
    print_message("block results: %u modules, %u runs\n", modules, runs);
    assert_true(modules > 2000 / ROZ_TEST_THIN(3));
}

/* The module of upstream issue #465 itself, as process(). */
static void test_block_results_issue_465(void **st)
{
    static const uint8_t code[] = {
        0, OP_BLOCK, F32, OP_F32_CONST, 0, 0, 0x80, 0x3f, OP_F32_CONST, 0, 0, 0, 0x40,
        OP_BR, 0, OP_END, OP_DROP, OP_END
    };
    (void)st;
    module_begin();
    put_bytes(&mod.body[0], code, sizeof code);
    module_end();
    load("issue 465");
    for (int64_t t = 0; t < 3; t++)
        assert_int_equal(roz_controller_process(&ctl, t), ROZ_OK);
}

/* ---- item 1: call arguments at the end of the value stack ----------------- */

/* process(tick) calls rec(tick); rec(d) (with `locals` i64 locals) recurses
 * d times, then calls wide (directly or through the table) with n_args
 * arguments of type t, 1.5, 2.5, ..., and emits what it returns: its last
 * argument. */
static void build_call_module(uint8_t t, uint32_t n_args, uint32_t locals, int indirect)
{
    static uint8_t params[256];
    uint8_t p_i32 = I32;
    uint32_t t_rec, t_wide, f_rec, f_wide;
    buf_t *o;

    module_begin();
    t_rec = add_type(1, &p_i32, 0);
    memset(params, t, sizeof params);
    t_wide = add_type(n_args, params, t);
    o = &mod.body[0];
    put(o, 0);
    put(o, OP_LOCAL_GET); put(o, 0); put(o, OP_I32_WRAP_I64);
    put(o, OP_CALL); put(o, 2);
    put(o, OP_END);

    o = add_func(t_rec, &f_rec);
    assert_int_equal(f_rec, 2);
    if (locals > 0) {
        put(o, 1); put_u32(o, locals); put(o, I64);
    } else {
        put(o, 0);
    }
    put(o, OP_LOCAL_GET); put(o, 0);
    put(o, OP_IF); put(o, 0x40);
    put(o, OP_LOCAL_GET); put(o, 0); put(o, OP_I32_CONST); put(o, 1); put(o, OP_I32_SUB);
    put(o, OP_CALL); put_u32(o, f_rec);
    put(o, OP_ELSE);
    for (uint32_t i = 0; i < n_args; i++)
        put_const(o, t, 1.5 + i);
    if (indirect) {
        put(o, OP_I32_CONST); put(o, 0);
        put(o, OP_CALL_INDIRECT); put_u32(o, t_wide); put(o, 0);
    } else {
        put(o, OP_CALL); put(o, 3);
    }
    put_to_f64(o, t);
    put(o, OP_CALL); put(o, 0);
    put(o, OP_END);
    put(o, OP_END);

    o = add_func(t_wide, &f_wide);
    assert_int_equal(f_wide, 3);
    put(o, 0);
    put(o, OP_LOCAL_GET); put_u32(o, n_args - 1);
    put(o, OP_END);
    mod.table = indirect;
    mod.elem = f_wide;
    module_end();
}

static unsigned value_stack_traps, native_stack_traps;

/* Runs process(depth): 1 when it ran (and emitted the right value), 0 when it
 * trapped for the stack. */
static int run_depth(const char *what, int64_t depth, double expect)
{
    int rc = roz_controller_process(&ctl, depth);
    if (rc == ROZ_OK) {
        double v = metric(what);
        if (v != expect)
            fail_msg("%s, depth %lld: %g, expected %g", what, (long long)depth, v, expect);
        return 1;
    }
    if (rc != ROZ_ETRAP)
        fail_msg("%s, depth %lld: process returned %d", what, (long long)depth, rc);
    const char *e = roz_controller_error(&ctl);
    if (strstr(e, "[trap] stack overflow") != NULL)
        value_stack_traps++;
    else if (strstr(e, "native stack limit") != NULL)
        native_stack_traps++;
    else
        fail_msg("%s, depth %lld: \"%s\" is no stack trap", what, (long long)depth, e);
    roz_metric_t m;
    if (roz_metric_ring_pop(&ring, &m) != 0)
        fail_msg("%s, depth %lld: a trapped run emitted", what, (long long)depth);
    return 0;
}

/* The deepest depth that runs, found by bisection (traps are monotonic in
 * depth), then every depth around it. */
static void sweep_depths(const char *what, double expect)
{
    int64_t lo = 0, hi = 1;
    if (!run_depth(what, 0, expect))
        fail_msg("%s: depth 0 traps", what);
    while (run_depth(what, hi, expect)) {
        lo = hi;
        hi *= 2;
        if (hi > 100000)
            fail_msg("%s: no stack limit reached", what);
    }
    while (hi - lo > 1) {
        int64_t mid = lo + (hi - lo) / 2;
        if (run_depth(what, mid, expect))
            lo = mid;
        else
            hi = mid;
    }
    for (int64_t d = lo - 2; d <= lo + 3; d++)
        if (d >= 0 && run_depth(what, d, expect) != (d <= lo))
            fail_msg("%s: depth %lld is not monotonic", what, (long long)d);
}

static void call_sweep(const uint8_t *ts, size_t n_ts, uint32_t step, const uint32_t *locals,
                       size_t n_locals)
{
    unsigned modules = 0;
    value_stack_traps = native_stack_traps = 0;
    for (size_t ti = 0; ti < n_ts; ti++)
    for (int indirect = 0; indirect <= 1; indirect++)
    for (size_t li = 0; li < n_locals; li++)
    for (uint32_t n = 1; n <= 255; n = (n == 255 ? 256 : (n + step > 255 ? 255 : n + step))) {
        char what[120];
        uint8_t t = ts[ti];
        snprintf(what, sizeof what, "%s call of %u %s arguments from a frame of %u locals",
                 indirect ? "indirect" : "direct", (unsigned)n,
                 t == I32 ? "i32" : t == I64 ? "i64" : "f64", (unsigned)locals[li]);
        build_call_module(t, n, locals[li], indirect);
        load(what);
        sweep_depths(what, t == F64 ? 0.5 + n : (double)n);
        modules++;
    }
    print_message("call arguments: %u modules, %u value stack traps, %u native stack traps\n",
                  modules, value_stack_traps, native_stack_traps);
    /* the sweep must reach the end of the value stack, not only the C stack's */
    assert_true(value_stack_traps > modules);
}

/* Every argument count with i64 arguments, direct and indirect, from frames
 * of 8 sizes (their ends land on every 8-byte offset); under an emulator
 * every 7th count (support_thin.h: 7 is prime to 8, so the ends still land
 * on every offset). */
static void test_call_args_i64(void **st)
{
    static const uint8_t ts[] = { I64 };
    static const uint32_t locals[] = { 24, 25, 26, 27, 28, 29, 30, 31 };
    (void)st;
    call_sweep(ts, 1, ROZ_TEST_THIN(7), locals, sizeof locals / sizeof locals[0]);
}

/* i32 and f64 arguments, every 3rd count (every 21st under an emulator). */
static void test_call_args_i32_f64(void **st)
{
    static const uint8_t ts[] = { I32, F64 };
    static const uint32_t locals[] = { 24, 27 };
    (void)st;
    call_sweep(ts, 2, 3 * ROZ_TEST_THIN(7), locals, sizeof locals / sizeof locals[0]);
}

/* ---- upstream #471: multi-value blocks are refused ------------------------- */

/* Upstream #471 (an out-of-bounds copy in CopyStackSlotsR) needs a block of
 * more than one value: roz refuses both the type with two results and a
 * block typed by a type index, before wasm3 sees the module. */
static void test_multi_value_refused(void **st)
{
    static const struct { int two_results; const char *msg; } cases[] = {
        { 1, "WebAssembly 1.0 functions return at most one" },
        { 0, "multi-value blocks are not accepted" },
    };
    uint8_t none = 0;
    (void)st;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        uint32_t t;
        buf_t *o;
        /* (block (type $t) (block (type $t) f64.const f64.const br 1)) drop... */
        module_begin();
        t = add_type(0, &none, F64);
        mod.result2[t] = cases[i].two_results ? F64 : 0;
        o = &mod.body[0];
        put(o, 0);
        put(o, OP_BLOCK); put_u32(o, t);
        put(o, OP_BLOCK); put_u32(o, t);
        put_const(o, F64, 1.0); put_const(o, F64, 2.0);
        if (!cases[i].two_results)
            put(o, OP_DROP);
        put(o, OP_BR); put(o, 1);
        put(o, OP_END); put(o, OP_END);
        put(o, OP_DROP);
        if (cases[i].two_results)
            put(o, OP_DROP);
        put(o, OP_END);
        module_end();
        assert_int_equal(load_fresh(), ROZ_EINVAL);
        if (strstr(roz_controller_error(&ctl), cases[i].msg) == NULL)
            fail_msg("\"%s\" lacks \"%s\"", roz_controller_error(&ctl), cases[i].msg);
    }
}

/* ---- item 4: the compiler's own bookkeeping --------------------------------- */

/* wasm3 0.5.0's compiler keeps params, locals, operands and block result
 * records on one stack of d_m3MaxFunctionStackHeight (2000) entries; roz's
 * validator allows more (4096 locals, 1024 operands). A failed Push still
 * moved the stack index past the array and CompileBlock ignored
 * PushBlockResults' error, so the compiler went on indexing past its
 * arrays (upstream e485482). Every such function must now be refused with
 * wasm3's "compiling function overran its stack height limit" or run
 * correctly. */
static void test_compiler_stack_full(void **st)
{
    unsigned refused = 0, ran = 0;
    (void)st;
    for (uint32_t locals = 1990; locals <= 2002; locals++)
    for (int shape = 0; shape < 4; shape++) {
        char what[96];
        buf_t *o;
        snprintf(what, sizeof what, "%u i32 locals, shape %d", (unsigned)locals, shape);
        module_begin();
        o = &mod.body[0];
        put(o, 1); put_u32(o, locals); put(o, I32);
        switch (shape) {
        case 0: /* block (result f64) with a value, emitted */
            put(o, OP_BLOCK); put(o, F64); put_const(o, F64, VALUE); put(o, OP_END);
            break;
        case 1: /* block (result i32) left by br, converted */
            put(o, OP_BLOCK); put(o, I32); put_const(o, I32, VALUE);
            put(o, OP_BR); put(o, 0); put(o, OP_END);
            put_to_f64(o, I32);
            break;
        case 2: /* an unreachable block (result i64), never run */
            put(o, OP_LOCAL_GET); put(o, 0); put(o, OP_I64_CONST); put(o, 0); put(o, 0x51); /* i64.eq */
            put(o, OP_IF); put(o, 0x40); put(o, OP_ELSE);
            put(o, OP_BLOCK); put(o, I64); put(o, OP_UNREACHABLE); put(o, OP_END);
            put(o, OP_DROP); put(o, OP_END);
            put_const(o, F64, VALUE);
            break;
        default: /* nested blocks (result f32) */
            for (int i = 0; i < 4; i++) {
                put(o, OP_BLOCK); put(o, F32);
            }
            put_const(o, F32, VALUE);
            for (int i = 0; i < 4; i++)
                put(o, OP_END);
            put_to_f64(o, F32);
            break;
        }
        put(o, OP_CALL); put(o, 0);
        put(o, OP_END);
        module_end();
        if (load_fresh() != ROZ_OK) {
            if (strstr(roz_controller_error(&ctl), "overran its stack height limit") == NULL)
                fail_msg("%s: refused: %s", what, roz_controller_error(&ctl));
            refused++;
            continue;
        }
        assert_int_equal(roz_controller_process(&ctl, 0), ROZ_OK);
        if (metric(what) != expect_of(shape == 1 ? I32 : F64, VALUE))
            fail_msg("%s: wrong result", what);
        ran++;
    }
    print_message("compiler stack: %u ran, %u refused\n", ran, refused);
    assert_true(ran > 0 && refused > 0);
}

/* Compile_BranchTable reserves targetCount + 4 code lines in a u32, which
 * wraps for counts near 2^32 (upstream #570): roz's validator refuses a
 * br_table whose label count passes the bytes left in the body. */
static void test_br_table_count_refused(void **st)
{
    static const uint32_t counts[] = { 0xfffffffcu, 0xfffffffdu, 0xffffffffu, 100000u };
    (void)st;
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; i++) {
        buf_t *o;
        module_begin();
        o = &mod.body[0];
        put(o, 0);
        put(o, OP_BLOCK); put(o, 0x40);
        put(o, OP_I32_CONST); put(o, 0);
        put(o, OP_BR_TABLE); put_u32(o, counts[i]);
        for (int k = 0; k < 16; k++)
            put(o, 0);
        put(o, OP_END);
        put(o, OP_END);
        module_end();
        assert_int_equal(load_fresh(), ROZ_EINVAL);
        assert_false(roz_controller_loaded(&ctl));
    }
}

/* An argument runs only the tests whose names contain it. */
int main(int argc, char **argv)
{
    static const struct CMUnitTest all[] = {
        cmocka_unit_test_teardown(test_block_results_issue_465, teardown),
        cmocka_unit_test_teardown(test_block_results_sweep, teardown),
        cmocka_unit_test_teardown(test_call_args_i64, teardown),
        cmocka_unit_test_teardown(test_call_args_i32_f64, teardown),
        cmocka_unit_test_teardown(test_multi_value_refused, teardown),
        cmocka_unit_test_teardown(test_compiler_stack_full, teardown),
        cmocka_unit_test_teardown(test_br_table_count_refused, teardown),
    };
    struct CMUnitTest tests[sizeof all / sizeof all[0]];
    size_t n = 0;
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        if (argc < 2 || strstr(all[i].name, argv[1]) != NULL)
            tests[n++] = all[i];
    return _cmocka_run_group_tests("test_wasm3_slots", tests, n, NULL, NULL);
}
