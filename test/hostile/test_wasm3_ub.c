/* SPDX-License-Identifier: Apache-2.0 */
/* wasm3's execution edge cases, checked against the WebAssembly spec
 * (docs/known-issues.md, the wasm3 table). What this proves:
 *  - every integer op gives the spec's result at INT_MIN / INT_MAX and the
 *    other edges (add/sub/mul wrap round, div_s and rem_s by -1, shifts and
 *    rotates by >= the width and by negative counts, clz/ctz/popcnt of 0,
 *    the extends and wraps, trunc and trunc_sat at both ends of each range)
 *    and traps where the spec traps, each with wasm3's message. Every case
 *    runs with its operands as constants and as computed values, so each of
 *    wasm3's operand-placement variants of the op (_rs, _sr, _ss, _r, _s)
 *    runs. In the ASan+UBSan build wasm3 itself runs under UBSan with every
 *    report fatal, so a signed overflow or bad shift in the engine fails here
 *    (cmake/wasm3/20-constant-alignment.patch, 21-integer-ops.patch,
 *    cmake/RozWarnings.cmake);
 *  - f32/f64 min and max return NaN when either operand is NaN and order
 *    -0 below +0 (wasm3 0.5.0 already does; no patch);
 *  - a module whose memory section has 0 entries loads
 *    (cmake/wasm3/22-memory-section.patch, upstream #510);
 *  - 100,000 straight-line loads and stores run on a thread with a 256 KiB C
 *    stack: every load/store op chains to the next by a tail call, as
 *    wasm3 0.5.0 already does at roz's flags (cmake/Wasm3.cmake; with
 *    -fno-optimize-sibling-calls this test overflows the stack);
 *  - a trap inside a call below process(), right after host calls, leaves
 *    the instance callable and its runtime frees cleanly; no roz import can
 *    trap (the Runtime_Release bad free, upstream #436;
 *    cmake/wasm3/23-runtime-stack-free.patch);
 *  - process() and the other exports never run a start function: a module
 *    with one is refused, and looking up "process" runs nothing.
 * Modules are generated here byte by byte; results leave through
 * telemetry.emit_metric as exact f64 values (32 bits per metric). */
/* white-box: this test reads the private fields of the module it tests */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "roz/controller.h"
#include "support.h"
#include "support_bench.h"
#include "ur5_manifest.h"
#include "wasm_bytes.h"

/* the bench's controller and ABI (support_bench.h) */
static roz_controller_t *const ctl = &roz_bench.ctl;
static roz_abi_t *const abi = &roz_bench.abi;

/* ---- module writer -------------------------------------------------------- */

static uint8_t gen_buf[ROZ_CFG_WASM_MAX_MODULE_BYTES];
static size_t gen_len;

/* The test's wrappers of test/wasm_bytes.h around gen_buf. */
static void put(uint8_t b) { roz_wb_byte(gen_buf, sizeof gen_buf, &gen_len, b); }
static void put_bytes(const uint8_t *p, size_t n)
{
    roz_wb_bytes(gen_buf, sizeof gen_buf, &gen_len, p, n);
}
static void put_u32(uint32_t v) { roz_wb_u32(gen_buf, sizeof gen_buf, &gen_len, v); }
static void put_s64(uint64_t v) { roz_wb_s64(gen_buf, sizeof gen_buf, &gen_len, v); }
static size_t sized_begin(void) { return roz_wb_sized_begin(gen_buf, sizeof gen_buf, &gen_len); }
static void sized_end(size_t at) { roz_wb_sized_end(gen_buf, gen_len, at); }
static void put_name(const char *s) { roz_wb_name(gen_buf, sizeof gen_buf, &gen_len, s, strlen(s)); }

/* The sections every module here has, up to and including the memory
 * section: types 0 = (f64)->() and 1 = (i64)->(), the import
 * telemetry.emit_metric (function 0), one defined function of type 1
 * (function 1), and `mem_entries` memories of one page (0 or 1). */
static void module_head(unsigned mem_entries)
{
    static const uint8_t magic[] = { 0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00 };
    size_t s;

    gen_len = 0;
    put_bytes(magic, sizeof magic);
    put(1); /* types */
    s = sized_begin();
    put(2);
    put(0x60); put(1); put(0x7c); put(0); /* (f64) -> () */
    put(0x60); put(1); put(0x7e); put(0); /* (i64) -> () */
    sized_end(s);
    put(2); /* imports */
    s = sized_begin();
    put(1);
    put_name("telemetry");
    put_name("emit_metric");
    put(0x00); put(0);
    sized_end(s);
    put(3); /* functions */
    s = sized_begin();
    put(1); put(1);
    sized_end(s);
    put(5); /* memory */
    s = sized_begin();
    put_u32(mem_entries);
    for (unsigned i = 0; i < mem_entries; i++) {
        put(0x00); put(1); /* min 1 page, no max */
    }
    sized_end(s);
    put(7); /* exports */
    s = sized_begin();
    put(1);
    put_name("process");
    put(0x00); put(1);
    sized_end(s);
}

/* Opens the code section and the one body; locals: 1 = i64, 2 = i32.
 * Returns the two size placeholders for code_end(). */
static void code_begin(size_t *sec, size_t *body)
{
    put(10);
    *sec = sized_begin();
    put(1);
    *body = sized_begin();
    put(2);
    put(1); put(0x7e);
    put(1); put(0x7f);
}

static void code_end(size_t sec, size_t body)
{
    put(0x0b);
    sized_end(body);
    sized_end(sec);
}

/* ---- the controller under test ------------------------------------------- */

static void load_generated(void)
{
    if (getenv("ROZ_DUMP_WASM") != NULL) {
        FILE *f = fopen(getenv("ROZ_DUMP_WASM"), "wb");
        if (f != NULL) {
            fwrite(gen_buf, 1, gen_len, f);
            fclose(f);
        }
    }
    if (roz_controller_load(ctl, gen_buf, gen_len, abi) != ROZ_OK)
        fail_msg("load: %s", roz_controller_error(ctl));
}

/* Takes the next metric as the 32-bit value it carries. */
static uint32_t pop_u32(void)
{
    roz_metric_t mt;
    if (!roz_metric_ring_pop(&roz_bench.ring, &mt))
        fail_msg("a metric is missing");
    if (!(mt.value >= 0.0 && mt.value <= 4294967295.0 && mt.value == floor(mt.value)))
        fail_msg("metric %.17g is not a 32-bit value", mt.value);
    return (uint32_t)mt.value;
}

/* ---- the op cases -------------------------------------------------------- */

/* Value kinds: i = i32, I = i64, f = f32, F = f64 (bits in the low 32 or 64
 * bits of the u64 fields). Expected result kind 'n' = f32 NaN, 'N' = f64 NaN
 * (any payload); trap != NULL: the case must trap with that message. */
typedef struct {
    const char *name;
    uint16_t    op;    /* one byte, or 0xfc00 | sub */
    char        in;    /* operand kind */
    uint8_t     arity; /* 1 or 2 */
    uint64_t    a, b;
    char        out;
    uint64_t    want;
    const char *trap;
} opcase_t;

#define U32(x) ((uint64_t)(uint32_t)(x))
#define U64(x) ((uint64_t)(x))
#define BIN32(n, op, a, b, r) { n, op, 'i', 2, U32(a), U32(b), 'i', U32(r), NULL }
#define BIN64(n, op, a, b, r) { n, op, 'I', 2, U64(a), U64(b), 'I', U64(r), NULL }
#define TRAP32(n, op, a, b, t) { n, op, 'i', 2, U32(a), U32(b), 'i', 0, t }
#define TRAP64(n, op, a, b, t) { n, op, 'I', 2, U64(a), U64(b), 'I', 0, t }
#define UN(n, op, in, a, out, r) { n, op, in, 1, U64(a), 0, out, U64(r), NULL }
#define UNTRAP(n, op, in, a, t) { n, op, in, 1, U64(a), 0, (op) >= 0xae ? 'I' : 'i', 0, t }
#define BINF(n, op, in, a, b, out, r) { n, op, in, 2, U64(a), U64(b), out, U64(r), NULL }

#define I32MIN INT32_MIN
#define I32MAX INT32_MAX
#define I64MIN INT64_MIN
#define I64MAX INT64_MAX

static const char OVF[] = "[trap] integer overflow";
static const char DIV0[] = "[trap] integer divide by zero";
static const char CONV[] = "[trap] invalid conversion to integer";

/* f32 bits */
#define F32_NAN   0x7fc00000u
#define F32_NNAN  0xffc00000u
#define F32_INF   0x7f800000u
#define F32_NINF  0xff800000u
#define F32_P0    0x00000000u
#define F32_N0    0x80000000u
#define F32_ONE   0x3f800000u
#define F32_NONE  0xbf800000u
#define F32_NHALF 0xbf000000u
#define F32_N09   0xbf666666u
#define F32_2P31  0x4f000000u /* 2^31 */
#define F32_N2P31 0xcf000000u
#define F32_B2P31 0x4effffffu /* 2147483520, the largest below 2^31 */
#define F32_2P32  0x4f800000u
#define F32_B2P32 0x4f7fffffu /* 4294967040 */
#define F32_2P63  0x5f000000u
#define F32_N2P63 0xdf000000u
#define F32_B2P63 0x5effffffu /* 9223371487098961920 */
#define F32_2P64  0x5f800000u
#define F32_B2P64 0x5f7fffffu /* 18446742974197923840 */
/* f64 bits */
#define F64_NAN   0x7ff8000000000000u
#define F64_NNAN  0xfff8000000000000u
#define F64_INF   0x7ff0000000000000u
#define F64_NINF  0xfff0000000000000u
#define F64_P0    0x0000000000000000u
#define F64_N0    0x8000000000000000u
#define F64_ONE   0x3ff0000000000000u
#define F64_NONE  0xbff0000000000000u
#define F64_N09   0xbfeccccccccccccdu
#define F64_2P31  0x41e0000000000000u
#define F64_N2P31 0xc1e0000000000000u
#define F64_I32MX 0x41dfffffffc00000u /* 2147483647.0 */
#define F64_I32MX9 0x41dffffffff9999au /* 2147483647.9 */
#define F64_N2P31_9 0xc1e00000001ccccdu /* -2147483648.9 */
#define F64_N2P31_1 0xc1e0000000200000u /* -2147483649.0 */
#define F64_2P32  0x41f0000000000000u
#define F64_U32MX9 0x41effffffffccccdu /* 4294967295.9 */
#define F64_2P63  0x43e0000000000000u
#define F64_N2P63 0xc3e0000000000000u
#define F64_B2P63 0x43dfffffffffffffu /* 9223372036854774784 */
#define F64_2P64  0x43f0000000000000u
#define F64_B2P64 0x43efffffffffffffu /* 18446744073709549568 */

static const opcase_t cases[] = {
    /* i32 add/sub/mul wrap round */
    BIN32("i32.add max+1", 0x6a, I32MAX, 1, I32MIN),
    BIN32("i32.add min+min", 0x6a, I32MIN, I32MIN, 0),
    BIN32("i32.add max+max", 0x6a, I32MAX, I32MAX, -2),
    BIN32("i32.add min+-1", 0x6a, I32MIN, -1, I32MAX),
    BIN32("i32.sub min-1", 0x6b, I32MIN, 1, I32MAX),
    BIN32("i32.sub max--1", 0x6b, I32MAX, -1, I32MIN),
    BIN32("i32.sub 0-min", 0x6b, 0, I32MIN, I32MIN),
    BIN32("i32.sub min-max", 0x6b, I32MIN, I32MAX, 1),
    BIN32("i32.mul min*-1", 0x6c, I32MIN, -1, I32MIN),
    BIN32("i32.mul max*max", 0x6c, I32MAX, I32MAX, 1),
    BIN32("i32.mul min*min", 0x6c, I32MIN, I32MIN, 0),
    BIN32("i32.mul 0x10000^2", 0x6c, 0x10000, 0x10000, 0),
    BIN32("i32.mul max*2", 0x6c, I32MAX, 2, -2),
    /* i32 div/rem */
    TRAP32("i32.div_s min/-1", 0x6d, I32MIN, -1, OVF),
    TRAP32("i32.div_s 1/0", 0x6d, 1, 0, DIV0),
    TRAP32("i32.div_u 1/0", 0x6e, 1, 0, DIV0),
    TRAP32("i32.rem_s 1%0", 0x6f, 1, 0, DIV0),
    TRAP32("i32.rem_u 1%0", 0x70, 1, 0, DIV0),
    BIN32("i32.div_s min/1", 0x6d, I32MIN, 1, I32MIN),
    BIN32("i32.div_s max/-1", 0x6d, I32MAX, -1, -I32MAX),
    BIN32("i32.div_s -7/2", 0x6d, -7, 2, -3),
    BIN32("i32.div_u min/-1", 0x6e, I32MIN, -1, 0),
    BIN32("i32.div_u -1/2", 0x6e, -1, 2, I32MAX),
    BIN32("i32.rem_s min%-1", 0x6f, I32MIN, -1, 0),
    BIN32("i32.rem_s -7%2", 0x6f, -7, 2, -1),
    BIN32("i32.rem_s min%max", 0x6f, I32MIN, I32MAX, -1),
    BIN32("i32.rem_u min%-1", 0x70, I32MIN, -1, I32MIN),
    /* i32 shifts and rotates: the count is taken mod 32 */
    BIN32("i32.shl 1<<31", 0x74, 1, 31, I32MIN),
    BIN32("i32.shl 1<<32", 0x74, 1, 32, 1),
    BIN32("i32.shl 1<<33", 0x74, 1, 33, 2),
    BIN32("i32.shl -1<<-1", 0x74, -1, -1, I32MIN),
    BIN32("i32.shl max<<1", 0x74, I32MAX, 1, -2),
    BIN32("i32.shl min<<min", 0x74, I32MIN, I32MIN, I32MIN),
    BIN32("i32.shr_s min>>31", 0x75, I32MIN, 31, -1),
    BIN32("i32.shr_s min>>32", 0x75, I32MIN, 32, I32MIN),
    BIN32("i32.shr_s min>>-1", 0x75, I32MIN, -1, -1),
    BIN32("i32.shr_s -1>>100", 0x75, -1, 100, -1),
    BIN32("i32.shr_u min>>31", 0x76, I32MIN, 31, 1),
    BIN32("i32.shr_u -1>>32", 0x76, -1, 32, -1),
    BIN32("i32.shr_u -1>>-1", 0x76, -1, -1, 1),
    BIN32("i32.rotl min,1", 0x77, I32MIN, 1, 1),
    BIN32("i32.rotl 1,32", 0x77, 1, 32, 1),
    BIN32("i32.rotl 1,-1", 0x77, 1, -1, I32MIN),
    BIN32("i32.rotl x,36", 0x77, 0x12345678, 36, 0x23456781),
    BIN32("i32.rotr 1,1", 0x78, 1, 1, I32MIN),
    BIN32("i32.rotr 1,32", 0x78, 1, 32, 1),
    BIN32("i32.rotr min,-1", 0x78, I32MIN, -1, 1),
    BIN32("i32.rotr x,36", 0x78, 0x12345678, 36, (int32_t)0x81234567),
    /* i32 compares at the edges */
    BIN32("i32.lt_s min<max", 0x48, I32MIN, I32MAX, 1),
    BIN32("i32.lt_u min<max", 0x49, I32MIN, I32MAX, 0),
    BIN32("i32.gt_s -1>0", 0x4a, -1, 0, 0),
    BIN32("i32.gt_u -1>0", 0x4b, -1, 0, 1),
    /* i32 unary */
    UN("i32.clz 0", 0x67, 'i', 0, 'i', 32),
    UN("i32.clz min", 0x67, 'i', U32(I32MIN), 'i', 0),
    UN("i32.clz 1", 0x67, 'i', 1, 'i', 31),
    UN("i32.ctz 0", 0x68, 'i', 0, 'i', 32),
    UN("i32.ctz min", 0x68, 'i', U32(I32MIN), 'i', 31),
    UN("i32.popcnt 0", 0x69, 'i', 0, 'i', 0),
    UN("i32.popcnt -1", 0x69, 'i', U32(-1), 'i', 32),
    UN("i32.eqz 0", 0x45, 'i', 0, 'i', 1),
    UN("i32.eqz min", 0x45, 'i', U32(I32MIN), 'i', 0),
    UN("i32.extend8_s 0x80", 0xc0, 'i', 0x80, 'i', U32(-128)),
    UN("i32.extend8_s 0x7f", 0xc0, 'i', 0x7f, 'i', 0x7f),
    UN("i32.extend8_s max", 0xc0, 'i', U32(I32MAX), 'i', U32(-1)),
    UN("i32.extend16_s 0x8000", 0xc1, 'i', 0x8000, 'i', U32(-32768)),
    UN("i32.extend16_s min", 0xc1, 'i', U32(I32MIN), 'i', 0),

    /* i64 add/sub/mul wrap round */
    BIN64("i64.add max+1", 0x7c, I64MAX, 1, I64MIN),
    BIN64("i64.add min+min", 0x7c, I64MIN, I64MIN, 0),
    BIN64("i64.add min+-1", 0x7c, I64MIN, -1, I64MAX),
    BIN64("i64.sub min-1", 0x7d, I64MIN, 1, I64MAX),
    BIN64("i64.sub 0-min", 0x7d, 0, I64MIN, I64MIN),
    BIN64("i64.sub max--1", 0x7d, I64MAX, -1, I64MIN),
    BIN64("i64.mul min*-1", 0x7e, I64MIN, -1, I64MIN),
    BIN64("i64.mul max*max", 0x7e, I64MAX, I64MAX, 1),
    BIN64("i64.mul 2^32*2^32", 0x7e, INT64_C(0x100000000), INT64_C(0x100000000), 0),
    BIN64("i64.mul max*3", 0x7e, I64MAX, 3, I64MAX - 2),
    /* i64 div/rem */
    TRAP64("i64.div_s min/-1", 0x7f, I64MIN, -1, OVF),
    TRAP64("i64.div_s 1/0", 0x7f, 1, 0, DIV0),
    TRAP64("i64.div_u 1/0", 0x80, 1, 0, DIV0),
    TRAP64("i64.rem_s 1%0", 0x81, 1, 0, DIV0),
    TRAP64("i64.rem_u 1%0", 0x82, 1, 0, DIV0),
    BIN64("i64.div_s min/1", 0x7f, I64MIN, 1, I64MIN),
    BIN64("i64.div_s max/-1", 0x7f, I64MAX, -1, -I64MAX),
    BIN64("i64.div_s -7/2", 0x7f, -7, 2, -3),
    BIN64("i64.div_u min/-1", 0x80, I64MIN, -1, 0),
    BIN64("i64.rem_s min%-1", 0x81, I64MIN, -1, 0),
    BIN64("i64.rem_s -7%2", 0x81, -7, 2, -1),
    BIN64("i64.rem_u min%-1", 0x82, I64MIN, -1, I64MIN),
    /* i64 shifts and rotates: the count is taken mod 64 */
    BIN64("i64.shl 1<<63", 0x86, 1, 63, I64MIN),
    BIN64("i64.shl 1<<64", 0x86, 1, 64, 1),
    BIN64("i64.shl 1<<65", 0x86, 1, 65, 2),
    BIN64("i64.shl -1<<-1", 0x86, -1, -1, I64MIN),
    BIN64("i64.shl max<<1", 0x86, I64MAX, 1, -2),
    BIN64("i64.shl 1<<32", 0x86, 1, 32, INT64_C(0x100000000)),
    BIN64("i64.shr_s min>>63", 0x87, I64MIN, 63, -1),
    BIN64("i64.shr_s min>>64", 0x87, I64MIN, 64, I64MIN),
    BIN64("i64.shr_s min>>-1", 0x87, I64MIN, -1, -1),
    BIN64("i64.shr_u min>>63", 0x88, I64MIN, 63, 1),
    BIN64("i64.shr_u -1>>64", 0x88, -1, 64, -1),
    BIN64("i64.shr_u -1>>-1", 0x88, -1, -1, 1),
    BIN64("i64.rotl min,1", 0x89, I64MIN, 1, 1),
    BIN64("i64.rotl 1,64", 0x89, 1, 64, 1),
    BIN64("i64.rotl 1,-1", 0x89, 1, -1, I64MIN),
    BIN64("i64.rotr 1,1", 0x8a, 1, 1, I64MIN),
    BIN64("i64.rotr 1,64", 0x8a, 1, 64, 1),
    BIN64("i64.rotr min,-1", 0x8a, I64MIN, -1, 1),
    BIN64("i64.rotl x,68", 0x89, INT64_C(0x0123456789abcdef), 68,
          INT64_C(0x123456789abcdef0)),
    /* i64 compares */
    { "i64.lt_s min<max", 0x53, 'I', 2, U64(I64MIN), U64(I64MAX), 'i', 1, NULL },
    { "i64.lt_u min<max", 0x54, 'I', 2, U64(I64MIN), U64(I64MAX), 'i', 0, NULL },
    /* i64 unary */
    UN("i64.clz 0", 0x79, 'I', 0, 'I', 64),
    UN("i64.clz min", 0x79, 'I', U64(I64MIN), 'I', 0),
    UN("i64.clz 1", 0x79, 'I', 1, 'I', 63),
    UN("i64.ctz 0", 0x7a, 'I', 0, 'I', 64),
    UN("i64.ctz min", 0x7a, 'I', U64(I64MIN), 'I', 63),
    UN("i64.popcnt 0", 0x7b, 'I', 0, 'I', 0),
    UN("i64.popcnt -1", 0x7b, 'I', U64(-1), 'I', 64),
    UN("i64.eqz 0", 0x50, 'I', 0, 'i', 1),
    UN("i64.eqz 2^32", 0x50, 'I', U64(0x100000000), 'i', 0),
    UN("i64.extend8_s 0x80", 0xc2, 'I', 0x80, 'I', U64(-128)),
    UN("i64.extend16_s 0x8000", 0xc3, 'I', 0x8000, 'I', U64(-32768)),
    UN("i64.extend32_s 0x80000000", 0xc4, 'I', 0x80000000u, 'I', U64(I32MIN)),
    UN("i64.extend32_s max", 0xc4, 'I', U64(I64MAX), 'I', U64(-1)),
    UN("i64.extend_i32_s min", 0xac, 'i', U32(I32MIN), 'I', U64(I32MIN)),
    UN("i64.extend_i32_s -1", 0xac, 'i', U32(-1), 'I', U64(-1)),
    UN("i64.extend_i32_u min", 0xad, 'i', U32(I32MIN), 'I', 0x80000000u),
    UN("i64.extend_i32_u -1", 0xad, 'i', U32(-1), 'I', 0xffffffffu),
    UN("i32.wrap_i64 min", 0xa7, 'I', U64(I64MIN), 'i', 0),
    UN("i32.wrap_i64 max", 0xa7, 'I', U64(I64MAX), 'i', U32(-1)),
    UN("i32.wrap_i64 2^32+min32", 0xa7, 'I', UINT64_C(0x180000000), 'i', U32(I32MIN)),

    /* trunc: the last values inside each range, the first outside, NaN */
    UN("i32.trunc_f32_s -2^31", 0xa8, 'f', F32_N2P31, 'i', U32(I32MIN)),
    UN("i32.trunc_f32_s below 2^31", 0xa8, 'f', F32_B2P31, 'i', 2147483520u),
    UN("i32.trunc_f32_s -0.9", 0xa8, 'f', F32_N09, 'i', 0),
    UNTRAP("i32.trunc_f32_s 2^31", 0xa8, 'f', F32_2P31, OVF),
    UNTRAP("i32.trunc_f32_s -inf", 0xa8, 'f', F32_NINF, OVF),
    UNTRAP("i32.trunc_f32_s nan", 0xa8, 'f', F32_NAN, CONV),
    UN("i32.trunc_f32_u below 2^32", 0xa9, 'f', F32_B2P32, 'i', 4294967040u),
    UN("i32.trunc_f32_u -0.9", 0xa9, 'f', F32_N09, 'i', 0),
    UNTRAP("i32.trunc_f32_u 2^32", 0xa9, 'f', F32_2P32, OVF),
    UNTRAP("i32.trunc_f32_u -1", 0xa9, 'f', F32_NONE, OVF),
    UNTRAP("i32.trunc_f32_u nan", 0xa9, 'f', F32_NAN, CONV),
    UN("i32.trunc_f64_s 2147483647.9", 0xaa, 'F', F64_I32MX9, 'i', U32(I32MAX)),
    UN("i32.trunc_f64_s -2147483648.9", 0xaa, 'F', F64_N2P31_9, 'i', U32(I32MIN)),
    UNTRAP("i32.trunc_f64_s 2^31", 0xaa, 'F', F64_2P31, OVF),
    UNTRAP("i32.trunc_f64_s -2^31-1", 0xaa, 'F', F64_N2P31_1, OVF),
    UNTRAP("i32.trunc_f64_s nan", 0xaa, 'F', F64_NAN, CONV),
    UN("i32.trunc_f64_u 4294967295.9", 0xab, 'F', F64_U32MX9, 'i', 0xffffffffu),
    UN("i32.trunc_f64_u -0.9", 0xab, 'F', F64_N09, 'i', 0),
    UNTRAP("i32.trunc_f64_u 2^32", 0xab, 'F', F64_2P32, OVF),
    UNTRAP("i32.trunc_f64_u -1", 0xab, 'F', F64_NONE, OVF),
    UN("i64.trunc_f32_s -2^63", 0xae, 'f', F32_N2P63, 'I', U64(I64MIN)),
    UN("i64.trunc_f32_s below 2^63", 0xae, 'f', F32_B2P63, 'I', UINT64_C(9223371487098961920)),
    UNTRAP("i64.trunc_f32_s 2^63", 0xae, 'f', F32_2P63, OVF),
    UNTRAP("i64.trunc_f32_s nan", 0xae, 'f', F32_NAN, CONV),
    UN("i64.trunc_f32_u below 2^64", 0xaf, 'f', F32_B2P64, 'I', UINT64_C(18446742974197923840)),
    UN("i64.trunc_f32_u -0.9", 0xaf, 'f', F32_N09, 'I', 0),
    UNTRAP("i64.trunc_f32_u 2^64", 0xaf, 'f', F32_2P64, OVF),
    UNTRAP("i64.trunc_f32_u -1", 0xaf, 'f', F32_NONE, OVF),
    UN("i64.trunc_f64_s -2^63", 0xb0, 'F', F64_N2P63, 'I', U64(I64MIN)),
    UN("i64.trunc_f64_s below 2^63", 0xb0, 'F', F64_B2P63, 'I', UINT64_C(9223372036854774784)),
    UNTRAP("i64.trunc_f64_s 2^63", 0xb0, 'F', F64_2P63, OVF),
    UNTRAP("i64.trunc_f64_s -inf", 0xb0, 'F', F64_NINF, OVF),
    UNTRAP("i64.trunc_f64_s nan", 0xb0, 'F', F64_NAN, CONV),
    UN("i64.trunc_f64_u below 2^64", 0xb1, 'F', F64_B2P64, 'I', UINT64_C(18446744073709549568)),
    UN("i64.trunc_f64_u -0.9", 0xb1, 'F', F64_N09, 'I', 0),
    UNTRAP("i64.trunc_f64_u 2^64", 0xb1, 'F', F64_2P64, OVF),
    UNTRAP("i64.trunc_f64_u inf", 0xb1, 'F', F64_INF, OVF),
    /* trunc_sat: clamps, NaN gives 0 */
    UN("i32.trunc_sat_f32_s 2^31", 0xfc00, 'f', F32_2P31, 'i', U32(I32MAX)),
    UN("i32.trunc_sat_f32_s -inf", 0xfc00, 'f', F32_NINF, 'i', U32(I32MIN)),
    UN("i32.trunc_sat_f32_s nan", 0xfc00, 'f', F32_NAN, 'i', 0),
    UN("i32.trunc_sat_f32_s below 2^31", 0xfc00, 'f', F32_B2P31, 'i', 2147483520u),
    UN("i32.trunc_sat_f32_u 2^32", 0xfc01, 'f', F32_2P32, 'i', 0xffffffffu),
    UN("i32.trunc_sat_f32_u -1", 0xfc01, 'f', F32_NONE, 'i', 0),
    UN("i32.trunc_sat_f32_u -nan", 0xfc01, 'f', F32_NNAN, 'i', 0),
    UN("i32.trunc_sat_f64_s -2^31-1", 0xfc02, 'F', F64_N2P31_1, 'i', U32(I32MIN)),
    UN("i32.trunc_sat_f64_s 2147483647.9", 0xfc02, 'F', F64_I32MX9, 'i', U32(I32MAX)),
    UN("i32.trunc_sat_f64_s inf", 0xfc02, 'F', F64_INF, 'i', U32(I32MAX)),
    UN("i32.trunc_sat_f64_u 2^32", 0xfc03, 'F', F64_2P32, 'i', 0xffffffffu),
    UN("i32.trunc_sat_f64_u -0.9", 0xfc03, 'F', F64_N09, 'i', 0),
    UN("i32.trunc_sat_f64_u nan", 0xfc03, 'F', F64_NAN, 'i', 0),
    UN("i64.trunc_sat_f32_s 2^63", 0xfc04, 'f', F32_2P63, 'I', U64(I64MAX)),
    UN("i64.trunc_sat_f32_s -2^63", 0xfc04, 'f', F32_N2P63, 'I', U64(I64MIN)),
    UN("i64.trunc_sat_f32_s -inf", 0xfc04, 'f', F32_NINF, 'I', U64(I64MIN)),
    UN("i64.trunc_sat_f32_s nan", 0xfc04, 'f', F32_NAN, 'I', 0),
    UN("i64.trunc_sat_f32_u 2^64", 0xfc05, 'f', F32_2P64, 'I', UINT64_MAX),
    UN("i64.trunc_sat_f32_u -1", 0xfc05, 'f', F32_NONE, 'I', 0),
    UN("i64.trunc_sat_f64_s 2^63", 0xfc06, 'F', F64_2P63, 'I', U64(I64MAX)),
    UN("i64.trunc_sat_f64_s -2^63", 0xfc06, 'F', F64_N2P63, 'I', U64(I64MIN)),
    UN("i64.trunc_sat_f64_s below 2^63", 0xfc06, 'F', F64_B2P63, 'I', UINT64_C(9223372036854774784)),
    UN("i64.trunc_sat_f64_s nan", 0xfc06, 'F', F64_NAN, 'I', 0),
    UN("i64.trunc_sat_f64_u 2^64", 0xfc07, 'F', F64_2P64, 'I', UINT64_MAX),
    UN("i64.trunc_sat_f64_u below 2^64", 0xfc07, 'F', F64_B2P64, 'I', UINT64_C(18446744073709549568)),
    UN("i64.trunc_sat_f64_u -inf", 0xfc07, 'F', F64_NINF, 'I', 0),
    UN("i64.trunc_sat_f64_u nan", 0xfc07, 'F', F64_NNAN, 'I', 0),

    /* min/max: NaN wins, -0 < +0 */
    BINF("f32.min nan,1", 0x96, 'f', F32_NAN, F32_ONE, 'n', 0),
    BINF("f32.min 1,nan", 0x96, 'f', F32_ONE, F32_NAN, 'n', 0),
    BINF("f32.min -inf,nan", 0x96, 'f', F32_NINF, F32_NAN, 'n', 0),
    BINF("f32.max nan,1", 0x97, 'f', F32_NAN, F32_ONE, 'n', 0),
    BINF("f32.max 1,nan", 0x97, 'f', F32_ONE, F32_NAN, 'n', 0),
    BINF("f32.max inf,-nan", 0x97, 'f', F32_INF, F32_NNAN, 'n', 0),
    BINF("f32.min -0,+0", 0x96, 'f', F32_N0, F32_P0, 'f', F32_N0),
    BINF("f32.min +0,-0", 0x96, 'f', F32_P0, F32_N0, 'f', F32_N0),
    BINF("f32.max -0,+0", 0x97, 'f', F32_N0, F32_P0, 'f', F32_P0),
    BINF("f32.max +0,-0", 0x97, 'f', F32_P0, F32_N0, 'f', F32_P0),
    BINF("f32.min -1,1", 0x96, 'f', F32_NONE, F32_ONE, 'f', F32_NONE),
    BINF("f32.max -1,1", 0x97, 'f', F32_NONE, F32_ONE, 'f', F32_ONE),
    BINF("f32.min -inf,inf", 0x96, 'f', F32_NINF, F32_INF, 'f', F32_NINF),
    BINF("f64.min nan,1", 0xa4, 'F', F64_NAN, F64_ONE, 'N', 0),
    BINF("f64.min 1,nan", 0xa4, 'F', F64_ONE, F64_NAN, 'N', 0),
    BINF("f64.max nan,1", 0xa5, 'F', F64_NAN, F64_ONE, 'N', 0),
    BINF("f64.max 1,nan", 0xa5, 'F', F64_ONE, F64_NAN, 'N', 0),
    BINF("f64.max -inf,-nan", 0xa5, 'F', F64_NINF, F64_NNAN, 'N', 0),
    BINF("f64.min -0,+0", 0xa4, 'F', F64_N0, F64_P0, 'F', F64_N0),
    BINF("f64.min +0,-0", 0xa4, 'F', F64_P0, F64_N0, 'F', F64_N0),
    BINF("f64.max -0,+0", 0xa5, 'F', F64_N0, F64_P0, 'F', F64_P0),
    BINF("f64.max +0,-0", 0xa5, 'F', F64_P0, F64_N0, 'F', F64_P0),
    BINF("f64.min -1,1", 0xa4, 'F', F64_NONE, F64_ONE, 'F', F64_NONE),
    BINF("f64.max -1,1", 0xa5, 'F', F64_NONE, F64_ONE, 'F', F64_ONE),
};
#define N_CASES (sizeof cases / sizeof cases[0])

/* How the operands reach the op: as constants (wasm3 reads them from its
 * constant slots), or computed, so the op takes them from its register. */
enum { FORM_CONST, FORM_FIRST_COMPUTED, FORM_SECOND_COMPUTED, N_FORMS };

static void put_operand(char kind, uint64_t v, int computed)
{
    switch (kind) {
    case 'i':
        put(0x41); put_s64((uint64_t)(int64_t)(int32_t)(uint32_t)v);
        if (computed) { put(0x41); put(0); put(0x72); } /* i32.or 0 */
        break;
    case 'I':
        put(0x42); put_s64(v);
        if (computed) { put(0x42); put(0); put(0x84); } /* i64.or 0 */
        break;
    case 'f':
        put(0x43);
        roz_wb_le(gen_buf, sizeof gen_buf, &gen_len, v, 4);
        if (computed) { put(0x8c); put(0x8c); } /* f32.neg twice: the same bits */
        break;
    default:
        put(0x44);
        roz_wb_le(gen_buf, sizeof gen_buf, &gen_len, v, 8);
        if (computed) { put(0x9a); put(0x9a); }
        break;
    }
}

/* The result, as 32-bit metrics: an i32 as one, an i64 as its high then low
 * half; floats as their bits. */
static void put_emit_result(char kind)
{
    if (kind == 'f' || kind == 'n')
        put(0xbc); /* i32.reinterpret_f32 */
    else if (kind == 'F' || kind == 'N')
        put(0xbd); /* i64.reinterpret_f64 */
    if (kind == 'i' || kind == 'f' || kind == 'n') {
        put(0xb8); /* f64.convert_i32_u */
        put(0x10); put(0);
        return;
    }
    put(0x21); put(1); /* local.set 1 */
    put(0x20); put(1); put(0x42); put(32); put(0x88); /* i64.shr_u 32 */
    put(0xba); put(0x10); put(0);                    /* f64.convert_i64_u; emit */
    put(0x20); put(1); put(0x42); put_s64(0xffffffffu); put(0x83); /* i64.and */
    put(0xba); put(0x10); put(0);
}

/* process(tick) runs case tick / N_FORMS in form tick % N_FORMS. */
static void build_ops_module(void)
{
    size_t sec, body;

    module_head(1);
    code_begin(&sec, &body);
    for (size_t k = 0; k < N_CASES * N_FORMS; k++) {
        const opcase_t *c = &cases[k / N_FORMS];
        int form = (int)(k % N_FORMS);
        put(0x20); put(0); put(0x42); put_s64(k); put(0x51); /* tick == k */
        put(0x04); put(0x40);                                /* if */
        put_operand(c->in, c->a, form == FORM_FIRST_COMPUTED);
        if (c->arity == 2)
            put_operand(c->in, c->b, form == FORM_SECOND_COMPUTED);
        if (c->op >= 0xfc00) {
            put(0xfc);
            put_u32(c->op & 0xff);
        } else {
            put((uint8_t)c->op);
        }
        put_emit_result(c->out);
        put(0x0b);
    }
    code_end(sec, body);
}

static void check_case(size_t k)
{
    const opcase_t *c = &cases[k / N_FORMS];
    int form = (int)(k % N_FORMS);
    int rc;

    if (c->arity == 1 && form == FORM_SECOND_COMPUTED)
        return;
    rc = roz_controller_process(ctl, (int64_t)k);
    if (c->trap != NULL) {
        if (rc != ROZ_ETRAP || strstr(roz_controller_error(ctl), c->trap) == NULL)
            fail_msg("%s (form %d): expected the trap \"%s\", got %d \"%s\"", c->name, form,
                     c->trap, rc, roz_controller_error(ctl));
        return;
    }
    if (rc != ROZ_OK)
        fail_msg("%s (form %d): %d %s", c->name, form, rc, roz_controller_error(ctl));
    switch (c->out) {
    case 'i':
    case 'f': {
        uint32_t got = pop_u32();
        if (got != (uint32_t)c->want)
            fail_msg("%s (form %d): got 0x%08x, expected 0x%08x", c->name, form, got,
                     (uint32_t)c->want);
        break;
    }
    case 'n': {
        uint32_t got = pop_u32();
        if ((got & 0x7f800000u) != 0x7f800000u || (got & 0x007fffffu) == 0)
            fail_msg("%s (form %d): got 0x%08x, expected a NaN", c->name, form, got);
        break;
    }
    default: {
        uint64_t hi = pop_u32();
        uint64_t got = (hi << 32) | pop_u32();
        if (c->out == 'N') {
            if ((got & F64_INF) != F64_INF || (got & 0x000fffffffffffffu) == 0)
                fail_msg("%s (form %d): got 0x%016llx, expected a NaN", c->name, form,
                         (unsigned long long)got);
        } else if (got != c->want) {
            fail_msg("%s (form %d): got 0x%016llx, expected 0x%016llx", c->name, form,
                     (unsigned long long)got, (unsigned long long)c->want);
        }
        break;
    }
    }
    {
        roz_metric_t extra;
        assert_false(roz_metric_ring_pop(&roz_bench.ring, &extra));
    }
}

static void test_integer_and_float_edges(void **st)
{
    (void)st;
    build_ops_module();
    load_generated();
    for (size_t k = 0; k < N_CASES * N_FORMS; k++)
        check_case(k);
    assert_int_equal(roz_bench.ring.dropped, 0);
}

/* A memory section with 0 entries is valid WebAssembly (a module without a
 * memory); roz's validator accepts it and wasm3 must load it. */
static void test_memory_section_without_entries(void **st)
{
    size_t sec, body;
    (void)st;
    module_head(0);
    code_begin(&sec, &body);
    put(0x44); /* f64.const 7 */
    {
        static const uint8_t seven[8] = { 0, 0, 0, 0, 0, 0, 0x1c, 0x40 };
        put_bytes(seven, sizeof seven);
    }
    put(0x10); put(0);
    code_end(sec, body);
    load_generated();
    assert_int_equal(roz_controller_process(ctl, 0), ROZ_OK);
    assert_int_equal(pop_u32(), 7);
}

/* ---- straight-line loads and stores on a small C stack ------------------ */

/* 100,000 memory ops in one basic block: 50,000 load/store pairs through
 * i32, i64, f64, f32 and 8-bit accesses, copying a value along a chain of
 * addresses; then the value at the chain's end and its low byte go out as
 * metrics. If any load or store op called the next op instead of jumping
 * to it, every op would nest a C frame: 100,000 frames do not fit in 256
 * KiB, and nothing in a straight line reaches the stack guard (which checks
 * at function and loop entries). */
#define CHAIN_PAIRS 50000
#define SMALL_STACK (256 * 1024)

static void put_copy(uint8_t dst, uint8_t src, uint8_t load, uint8_t store, uint8_t align)
{
    put(0x41); put_s64(dst);
    put(0x41); put_s64(src);
    put(load); put(align); put(0);
    put(store); put(align); put(0);
}

static void build_chain_module(void)
{
    static const struct { uint8_t dst, src, load, store, align; } step[5] = {
        { 0, 4, 0x28, 0x36, 2 },   /* i32: mem[0] = mem[4] */
        { 16, 0, 0x29, 0x37, 3 },  /* i64: mem[16..24] = mem[0..8] */
        { 32, 16, 0x2b, 0x39, 3 }, /* f64 */
        { 48, 32, 0x2a, 0x38, 2 }, /* f32 */
        { 64, 48, 0x2d, 0x3a, 0 }, /* i32.load8_u / i32.store8 */
    };
    size_t sec, body;

    module_head(1);
    code_begin(&sec, &body);
    put(0x41); put(4); put(0x41); put_s64(12345); put(0x36); put(2); put(0); /* mem[4] = 12345 */
    for (unsigned k = 0; k < CHAIN_PAIRS; k++) {
        unsigned i = k % 5;
        put_copy(step[i].dst, step[i].src, step[i].load, step[i].store, step[i].align);
    }
    put(0x41); put(48); put(0x28); put(2); put(0); /* i32.load mem[48] */
    put(0xb8); put(0x10); put(0);
    put(0x41); put_s64(64); put(0x28); put(2); put(0); /* i32.load mem[64] */
    put(0xb8); put(0x10); put(0);
    code_end(sec, body);
    assert_true(gen_len <= ROZ_CFG_WASM_MAX_MODULE_BYTES);
}

static int chain_rc;

static void *chain_thread(void *arg)
{
    (void)arg;
    chain_rc = roz_controller_process(ctl, 0);
    return NULL;
}

static void test_straight_line_memory_ops_small_stack(void **st)
{
    pthread_attr_t attr;
    pthread_t th;
    (void)st;

    build_chain_module();
    load_generated();
    assert_int_equal(pthread_attr_init(&attr), 0);
    assert_int_equal(pthread_attr_setstacksize(&attr, SMALL_STACK), 0);
    chain_rc = -1000;
    assert_int_equal(pthread_create(&th, &attr, chain_thread, NULL), 0);
    assert_int_equal(pthread_join(th, NULL), 0);
    pthread_attr_destroy(&attr);
    if (chain_rc != ROZ_OK)
        fail_msg("process: %d %s", chain_rc, roz_controller_error(ctl));
    assert_int_equal(pop_u32(), 12345);
    assert_int_equal(pop_u32(), 12345 & 0xff);
}

/* ---- traps below process(), after host calls ----------------------------- */

static uint8_t file_buf[64 * 1024];

static void load_file(const char *name)
{
    char path[512];
    size_t len;
    FILE *f;

    snprintf(path, sizeof path, "%s/hostile_%s.wasm", ROZ_HOSTILE_DIR, name);
    f = fopen(path, "rb");
    if (f == NULL)
        fail_msg("cannot open %s", path);
    len = fread(file_buf, 1, sizeof file_buf, f);
    fclose(f);
    assert_true(len > 0 && len < sizeof file_buf);
    if (roz_controller_load(ctl, file_buf, len, abi) != ROZ_OK)
        fail_msg("load %s: %s", name, roz_controller_error(ctl));
}

/* What one host_trap tick leaves in the ring: the four import results, then
 * metrics 0..251 of the 300 (the ring holds 256; the rest are dropped and
 * counted, never a trap). */
static void check_host_calls(uint64_t dropped_before)
{
    roz_metric_t mt;

    assert_true(roz_metric_ring_pop(&roz_bench.ring, &mt));
    assert_true(mt.value == -1.0); /* command.set, bad index: refused */
    assert_true(roz_metric_ring_pop(&roz_bench.ring, &mt));
    assert_true(mt.value == -1.0); /* command.set, NaN: refused */
    assert_true(roz_metric_ring_pop(&roz_bench.ring, &mt));
    assert_true(isnan(mt.value)); /* state.get, bad index */
    assert_true(roz_metric_ring_pop(&roz_bench.ring, &mt));
    assert_true(isnan(mt.value)); /* command.limit_min, bad index */
    for (uint32_t i = 0; i < ROZ_CFG_TELEMETRY_RING - 4; i++) {
        assert_true(roz_metric_ring_pop(&roz_bench.ring, &mt));
        assert_true(mt.value == (double)i);
    }
    assert_false(roz_metric_ring_pop(&roz_bench.ring, &mt));
    assert_true(roz_bench.ring.dropped > dropped_before);
    assert_int_equal(abi->estop_requested, 1);
}

/* wasm3 0.5.0 moves runtime->stack to the caller's frame during a host
 * call and puts it back when the host function returns; upstream #436 (a
 * bad free in Runtime_Release) is the case where it is not put back. Every
 * roz import is plain C that returns (none returns a trap, none calls back
 * into the engine), so the stack is always put back; roz's patch 23 frees
 * the allocation itself anyway. Here: host calls with bad arguments 20 wasm
 * calls deep, a trap right after them on odd ticks, the instance runs
 * again with the same results, and the runtime frees cleanly (ASan). */
static void test_trap_after_host_calls(void **st)
{
    uint64_t dropped;
    (void)st;

    load_file("host_trap");
    for (int64_t tick = 0; tick < 6; tick++) {
        int rc;
        dropped = roz_bench.ring.dropped;
        abi->estop_requested = 0;
        rc = roz_controller_process(ctl, tick);
        if (tick % 2 == 0) {
            if (rc != ROZ_OK)
                fail_msg("tick %lld: %s", (long long)tick, roz_controller_error(ctl));
        } else {
            assert_int_equal(rc, ROZ_ETRAP);
            assert_non_null(strstr(roz_controller_error(ctl), "unreachable"));
        }
        check_host_calls(dropped);
    }
    roz_controller_unload(ctl);
    assert_false(roz_controller_loaded(ctl));
}

/* ---- start functions ------------------------------------------------------ */

/* wasm3 runs a module's start function lazily, from m3_FindFunction (roz
 * calls it once, for "process", at load), and 0.5.0 marks it run only
 * after it returns: a start function that traps runs again at the next
 * lookup, one that reaches a lookup re-enters itself (upstream #281, #363).
 * roz refuses any module with a start section before wasm3 sees it, so
 * m3_RunStart never finds one; no import calls back into the engine. */
static void test_start_section_refused(void **st)
{
    size_t sec, body;
    size_t start_at;
    (void)st;

    /* the same module twice: without and with a start section (function
     * 0 is the import; a start function must be a defined () -> () one, but
     * the validator refuses the section whatever it names) */
    module_head(1);
    code_begin(&sec, &body);
    put(0x44);
    {
        static const uint8_t one[8] = { 0, 0, 0, 0, 0, 0, 0xf0, 0x3f };
        put_bytes(one, sizeof one);
    }
    put(0x10); put(0);
    code_end(sec, body);
    load_generated();
    assert_false(roz_metric_ring_pop(&roz_bench.ring, &(roz_metric_t){ 0, 0 })); /* nothing ran */
    assert_int_equal(roz_controller_process(ctl, 0), ROZ_OK);
    assert_int_equal(pop_u32(), 1);
    roz_controller_unload(ctl);

    /* insert a start section (id 8) before the code section */
    for (start_at = 8; start_at < gen_len;) {
        uint8_t id = gen_buf[start_at];
        size_t n = 0;
        int shift = 0;
        size_t p = start_at + 1;
        while (gen_buf[p] & 0x80) {
            n |= (size_t)(gen_buf[p] & 0x7f) << shift;
            shift += 7;
            p++;
        }
        n |= (size_t)gen_buf[p] << shift;
        if (id == 10)
            break;
        start_at = p + 1 + n;
    }
    assert_true(start_at < gen_len);
    memmove(gen_buf + start_at + 3, gen_buf + start_at, gen_len - start_at);
    gen_buf[start_at] = 8;
    gen_buf[start_at + 1] = 1;
    gen_buf[start_at + 2] = 1; /* function 1 */
    gen_len += 3;
    assert_int_equal(roz_controller_load(ctl, gen_buf, gen_len, abi), ROZ_EINVAL);
    assert_non_null(strstr(roz_controller_error(ctl), "start function"));
    assert_false(roz_controller_loaded(ctl));
    assert_int_equal(abi->counters.metrics, 1); /* the one from the first module */
}

ROZ_TEST_MAIN(roz_bench_test_metrics(test_integer_and_float_edges),
              roz_bench_test_metrics(test_memory_section_without_entries),
              roz_bench_test_metrics(test_straight_line_memory_ops_small_stack),
              roz_bench_test_metrics(test_trap_after_host_calls),
              roz_bench_test_metrics(test_start_section_refused))
