/* SPDX-License-Identifier: Apache-2.0 */
/* Names never choose what runs (SAFETY.md §3), and valid modules that
 * wasm3 0.5.0 refused load (docs/known-issues.md). This file proves that:
 *  - roz calls exactly the function exported as "process" that its scan
 *    checked: a name section naming another function "process", a second
 *    export "process", an export "process\0x", all aimed at an impostor of a
 *    lower index that takes eight i64 parameters (m3_CallV would read host
 *    stack memory for them), never make the impostor run;
 *  - export names must be unique, valid UTF-8 and free of NUL bytes, import
 *    names too (an import "command"."set\0junk" would link to command.set in
 *    wasm3, which compares names with strcmp), custom section names must be
 *    valid UTF-8; each refusal names the export/import and what is wrong;
 *  - an export "process" of a global is refused as not a function;
 *  - a custom section "name" that is malformed changes nothing: the module
 *    loads and runs (the specification: errors inside a custom section do
 *    not invalidate a module);
 *  - a body with `nop` and a module whose element segments are all empty
 *    load and run.
 * Every module is built here byte by byte (wat2wasm cannot spell most). */
/* white-box: this test reads the private fields of the module it tests */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/controller.h"
#include "support.h"
#include "support_bench.h"
#include "ur5_manifest.h"
#include "wasm_bytes.h"

/* the bench's controller (support_bench.h) */
static roz_controller_t *const ctl = &roz_bench.ctl;

/* ---- a byte-by-byte module builder ---------------------------------------- */

typedef roz_wb_buf_t buf_t;

/* Short names for test/wasm_bytes.h's roz_wb_put*(), the cases being
 * written byte by byte. */
static void put(buf_t *w, uint8_t v) { roz_wb_put(w, v); }
static void put_u32(buf_t *w, uint32_t v) { roz_wb_put_u32(w, v); }
static void put_bytes(buf_t *w, const void *p, size_t n) { roz_wb_put_bytes(w, p, n); }
/* A name of n bytes (may hold NUL bytes). */
static void put_name(buf_t *w, const char *s, size_t n)
{
    roz_wb_name(w->b, sizeof w->b, &w->n, s, n);
}

static void put_section(buf_t *w, uint8_t id, const buf_t *body)
{
    roz_wb_put_section(w, id, body->b, body->n);
}

#define NAME(lit) lit, sizeof lit - 1

typedef struct {
    const char *name;
    size_t      len;
    uint8_t     kind; /* 0 function, 3 global */
    uint32_t    idx;
} export_t;

enum { IMPOSTOR = 1, PROCESS = 2 }; /* function indices (0 is the import) */

typedef struct {
    export_t    exports[3];
    int         n_exports;
    const buf_t *custom;       /* a whole custom section body, or NULL */
    int         custom_first;  /* before every other section, else last */
    const char *imp_mod;       /* the import, default telemetry.emit_metric */
    size_t      imp_mod_len;
    const char *imp_name;
    size_t      imp_name_len;
    int         nop;           /* process's body has nops */
    int         empty_elems;   /* a table and two empty element segments */
} spec_t;

static buf_t mod;

/* (module
 *   (type $p (func (param i64)))            ;; 0: process
 *   (type $m (func (param f64)))            ;; 1: telemetry.emit_metric
 *   (type $x (func (param i64 x 8)))        ;; 2: the impostor
 *   (type $s (func (param i32 f64) (result i32)))  ;; 3: command.set
 *   (import "telemetry" "emit_metric" (func $emit (type $m)))
 *   (func $impostor (type $x) emit 666, then each parameter)
 *   (func $process (type $p) emit 1)
 *   (global i32 (i32.const 7))
 *   exports and the custom section as the spec says) */
static const uint8_t *build(const spec_t *s, size_t *len)
{
    buf_t body;

    mod.n = 0;
    put_bytes(&mod, "\0asm\1\0\0\0", 8);
    if (s->custom != NULL && s->custom_first)
        put_section(&mod, 0, s->custom);

    body.n = 0; /* types */
    put(&body, 4);
    put(&body, 0x60); put(&body, 1); put(&body, 0x7e); put(&body, 0);
    put(&body, 0x60); put(&body, 1); put(&body, 0x7c); put(&body, 0);
    put(&body, 0x60); put(&body, 8);
    for (int i = 0; i < 8; i++)
        put(&body, 0x7e);
    put(&body, 0);
    put(&body, 0x60); put(&body, 2); put(&body, 0x7f); put(&body, 0x7c); put(&body, 1);
    put(&body, 0x7f);
    put_section(&mod, 1, &body);

    body.n = 0; /* imports */
    put(&body, 1);
    if (s->imp_mod != NULL) {
        put_name(&body, s->imp_mod, s->imp_mod_len);
        put_name(&body, s->imp_name, s->imp_name_len);
        put(&body, 0);
        put(&body, 3);
    } else {
        put_name(&body, NAME("telemetry"));
        put_name(&body, NAME("emit_metric"));
        put(&body, 0);
        put(&body, 1);
    }
    put_section(&mod, 2, &body);

    body.n = 0; /* functions */
    put(&body, 2); put(&body, 2); put(&body, 0);
    put_section(&mod, 3, &body);

    if (s->empty_elems) {
        body.n = 0; /* (table 1 funcref) */
        put(&body, 1); put(&body, 0x70); put(&body, 0); put(&body, 1);
        put_section(&mod, 4, &body);
    }

    body.n = 0; /* (global i32 (i32.const 7)) */
    put(&body, 1); put(&body, 0x7f); put(&body, 0); put(&body, 0x41); put(&body, 7);
    put(&body, 0x0b);
    put_section(&mod, 6, &body);

    body.n = 0; /* exports */
    put_u32(&body, (uint32_t)s->n_exports);
    for (int i = 0; i < s->n_exports; i++) {
        put_name(&body, s->exports[i].name, s->exports[i].len);
        put(&body, s->exports[i].kind);
        put_u32(&body, s->exports[i].idx);
    }
    put_section(&mod, 7, &body);

    if (s->empty_elems) {
        body.n = 0; /* (elem (i32.const 0)) (elem (i32.const 1)): no functions */
        put(&body, 2);
        put(&body, 0); put(&body, 0x41); put(&body, 0); put(&body, 0x0b); put(&body, 0);
        put(&body, 0); put(&body, 0x41); put(&body, 1); put(&body, 0x0b); put(&body, 0);
        put_section(&mod, 9, &body);
    }

    body.n = 0; /* code */
    put(&body, 2);
    {
        buf_t f = { .n = 0 };
        static const uint8_t c666[8] = { 0, 0, 0, 0, 0, 0xd0, 0x84, 0x40 }; /* 666.0 */
        put(&f, 0);
        put(&f, 0x44); put_bytes(&f, c666, 8); put(&f, 0x10); put(&f, 0); /* emit 666 */
        for (uint8_t i = 0; i < 8; i++) {
            put(&f, 0x20); put(&f, i); put(&f, 0xb9); put(&f, 0x10); put(&f, 0);
        }
        put(&f, 0x0b);
        put_u32(&body, (uint32_t)f.n);
        put_bytes(&body, f.b, f.n);
    }
    {
        buf_t f = { .n = 0 };
        static const uint8_t one[8] = { 0, 0, 0, 0, 0, 0, 0xf0, 0x3f };
        put(&f, 0);
        if (s->nop)
            put(&f, 0x01);
        put(&f, 0x44); put_bytes(&f, one, 8);
        if (s->nop)
            put(&f, 0x01);
        put(&f, 0x10); put(&f, 0); /* emit 1 */
        if (s->nop) {
            put(&f, 0x02); put(&f, 0x40); put(&f, 0x01); put(&f, 0x0b); /* block nop end */
            put(&f, 0x01);
        }
        put(&f, 0x0b);
        put_u32(&body, (uint32_t)f.n);
        put_bytes(&body, f.b, f.n);
    }
    put_section(&mod, 10, &body);

    if (s->custom != NULL && !s->custom_first)
        put_section(&mod, 0, s->custom);
    *len = mod.n;
    return mod.b;
}

/* ---- running them ----------------------------------------------------------- */

/* Loads, runs three ticks, and checks that exactly process ran: one metric
 * of 1.0 a tick, never the impostor's 666 or its parameters. */
static void runs_process(const spec_t *s)
{
    size_t len;
    const uint8_t *w = build(s, &len);
    roz_metric_t m;

    roz_bench_load(w, len);
    for (int64_t t = 0; t < 3; t++) {
        assert_int_equal(roz_controller_process(ctl, t), ROZ_OK);
        assert_int_equal(roz_metric_ring_pop(&roz_bench.ring, &m), 1);
        if (m.value != 1.0)
            fail_msg("tick %lld: metric %g: not process's 1.0 (the impostor ran)", (long long)t,
                     m.value);
        assert_int_equal(roz_metric_ring_pop(&roz_bench.ring, &m), 0);
    }
    roz_controller_unload(ctl);
}

static void refused(const spec_t *s, const char *msg)
{
    size_t len;
    const uint8_t *w = build(s, &len);

    roz_bench_refused(w, len, msg);
    assert_int_equal(roz_metric_ring_pop(&roz_bench.ring, &(roz_metric_t){ 0 }), 0);
}

#define EXPORT_PROCESS { NAME("process"), 0, PROCESS }

/* The baseline: process alone, and the same function under a second name. */
static void test_names_baseline(void **st)
{
    (void)st;
    runs_process(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1 });
    runs_process(&(spec_t){ .exports = { { NAME("impostor"), 0, IMPOSTOR }, EXPORT_PROCESS,
                                         { NAME("process2"), 0, PROCESS } },
                            .n_exports = 3 });
}

/* (custom "name" (funcnames (1 "process") (2 "real"))): wasm3 0.5.0 named the
 * impostor "process" and m3_FindFunction returned it. */
static void test_names_name_section(void **st)
{
    buf_t names = { .n = 0 }, sub = { .n = 0 };
    (void)st;
    put_name(&names, NAME("name"));
    put(&sub, 2);
    put(&sub, IMPOSTOR); put_name(&sub, NAME("process"));
    put(&sub, PROCESS); put_name(&sub, NAME("real"));
    put(&names, 1);
    put_u32(&names, (uint32_t)sub.n);
    put_bytes(&names, sub.b, sub.n);
    for (int first = 0; first < 2; first++)
        runs_process(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1, .custom = &names,
                                .custom_first = first });
}

/* Malformed name sections: the module is still valid and still runs. */
static void test_names_malformed_name_section(void **st)
{
    static const uint8_t bodies[][12] = {
        /* function names: 0xffffffff of them ("too many names" in wasm3) */
        { 1, 6, 0xff, 0xff, 0xff, 0xff, 0x0f, 0 },
        /* a name that runs past the section */
        { 1, 9, 1, 1, 0x7f, 'p', 'r', 'o' },
        /* a subsection id that is not a LEB at all */
        { 0xff, 0xff, 0xff, 0xff, 0xff, 0xff },
    };
    static const size_t lens[] = { 7, 8, 6 };
    (void)st;
    for (size_t i = 0; i < sizeof lens / sizeof lens[0]; i++) {
        buf_t names = { .n = 0 };
        put_name(&names, NAME("name"));
        put_bytes(&names, bodies[i], lens[i]);
        runs_process(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1,
                                .custom = &names });
    }
}

/* A second export "process" (of the impostor): the first was checked, the
 * lowest-index function of the name was called. Refused as a duplicate,
 * either way round. */
static void test_names_duplicate_export(void **st)
{
    (void)st;
    refused(&(spec_t){ .exports = { EXPORT_PROCESS, { NAME("process"), 0, IMPOSTOR } },
                       .n_exports = 2 },
            "export 1: duplicate export name \"process\" (also export 0); export names must be "
            "unique");
    refused(&(spec_t){ .exports = { { NAME("process"), 0, IMPOSTOR }, EXPORT_PROCESS },
                       .n_exports = 2 },
            "export 1: duplicate export name \"process\" (also export 0)");
    /* duplicates other than process too */
    refused(&(spec_t){ .exports = { { NAME("a"), 0, IMPOSTOR }, EXPORT_PROCESS,
                                    { NAME("a"), 3, 0 } },
                       .n_exports = 3 },
            "export 2: duplicate export name \"a\" (also export 0)");
}

/* "process\0x": a C string "process" to wasm3. */
static void test_names_nul_in_export(void **st)
{
    (void)st;
    refused(&(spec_t){ .exports = { { NAME("process\0x"), 0, IMPOSTOR }, EXPORT_PROCESS },
                       .n_exports = 2 },
            "export 0: its name \"process\\x00x\" contains a NUL byte");
    refused(&(spec_t){ .exports = { EXPORT_PROCESS, { NAME("process\0"), 0, IMPOSTOR } },
                       .n_exports = 2 },
            "export 1: its name \"process\\x00\" contains a NUL byte");
}

static void test_names_bad_utf8(void **st)
{
    (void)st;
    refused(&(spec_t){ .exports = { EXPORT_PROCESS, { NAME("\xff"), 0, IMPOSTOR } },
                       .n_exports = 2 },
            "export 1: its name \"\\xff\" is not valid UTF-8");
    /* overlong "/", a surrogate, past U+10FFFF, a cut sequence */
    refused(&(spec_t){ .exports = { EXPORT_PROCESS, { NAME("\xc0\xaf"), 0, IMPOSTOR } },
                       .n_exports = 2 },
            "not valid UTF-8");
    refused(&(spec_t){ .exports = { EXPORT_PROCESS, { NAME("\xed\xa0\x80"), 0, IMPOSTOR } },
                       .n_exports = 2 },
            "not valid UTF-8");
    refused(&(spec_t){ .exports = { EXPORT_PROCESS, { NAME("\xf4\x90\x80\x80"), 0, IMPOSTOR } },
                       .n_exports = 2 },
            "not valid UTF-8");
    refused(&(spec_t){ .exports = { EXPORT_PROCESS, { NAME("ab\xe2\x82"), 0, IMPOSTOR } },
                       .n_exports = 2 },
            "not valid UTF-8");
    /* valid UTF-8 beyond ASCII is a name like any other */
    runs_process(&(spec_t){ .exports = { EXPORT_PROCESS,
                                         { NAME("r\xc3\xa9gler \xe2\x82\xac \xf0\x9f\xa4\x96"), 0,
                                           IMPOSTOR } },
                            .n_exports = 2 });
    /* a custom section's name must be UTF-8 too (a malformed module) */
    buf_t bad = { .n = 0 };
    put_name(&bad, NAME("na\xffme"));
    refused(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1, .custom = &bad,
                       .custom_first = 1 },
            "custom section at offset 10: its name \"na\\xffme\" is not valid UTF-8");
    buf_t cut = { .n = 0 };
    put(&cut, 20);
    put_bytes(&cut, "name", 4);
    refused(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1, .custom = &cut,
                       .custom_first = 1 },
            "custom section at offset 10: malformed name");
}

/* An export "process" of a global, with the function under another name. */
static void test_names_process_is_a_global(void **st)
{
    (void)st;
    refused(&(spec_t){ .exports = { { NAME("process"), 3, 0 }, { NAME("run"), 0, PROCESS } },
                       .n_exports = 2 },
            "export \"process\" is not a function");
    refused(&(spec_t){ .exports = { { NAME("process"), 3, 0 }, EXPORT_PROCESS }, .n_exports = 2 },
            "export 1: duplicate export name \"process\" (also export 0)");
}

/* Imports, compared byte for byte: wasm3's strcmp would link
 * "command"."set\0junk" to command.set. */
static void test_names_imports(void **st)
{
    (void)st;
    refused(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1,
                       .imp_mod = "command", .imp_mod_len = 7,
                       .imp_name = NAME("set\0junk") },
            "import 0: its name \"set\\x00junk\" contains a NUL byte");
    refused(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1,
                       .imp_mod = NAME("command\0x"), .imp_name = NAME("set") },
            "import 0: its module name \"command\\x00x\" contains a NUL byte");
    refused(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1,
                       .imp_mod = NAME("comm\xe4nd"), .imp_name = NAME("set") },
            "import 0: its module name \"comm\\xe4nd\" is not valid UTF-8");
    /* the same name with bytes roz used to show as '?' is not the ABI's */
    refused(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1,
                       .imp_mod = NAME("command"), .imp_name = NAME("s\xc3\xa9t") },
            "unknown import command.s\\xc3\\xa9t: not part of the roz controller ABI");
    /* a prefix or an extension of an ABI name is another name */
    refused(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1,
                       .imp_mod = NAME("command"), .imp_name = NAME("se") },
            "unknown import command.se:");
    refused(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1,
                       .imp_mod = NAME("command"), .imp_name = NAME("setx") },
            "unknown import command.setx:");
}

/* Valid modules wasm3 0.5.0 refused: nop, element segments all empty. */
static void test_names_nop(void **st)
{
    (void)st;
    runs_process(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1, .nop = 1 });
}

static void test_names_empty_elements(void **st)
{
    (void)st;
    runs_process(&(spec_t){ .exports = { EXPORT_PROCESS }, .n_exports = 1, .empty_elems = 1 });
}

ROZ_TEST_MAIN(roz_bench_test_metrics(test_names_baseline),
              roz_bench_test_metrics(test_names_name_section),
              roz_bench_test_metrics(test_names_malformed_name_section),
              roz_bench_test_metrics(test_names_duplicate_export),
              roz_bench_test_metrics(test_names_nul_in_export),
              roz_bench_test_metrics(test_names_bad_utf8),
              roz_bench_test_metrics(test_names_process_is_a_global),
              roz_bench_test_metrics(test_names_imports),
              roz_bench_test_metrics(test_names_nop),
              roz_bench_test_metrics(test_names_empty_elements))
