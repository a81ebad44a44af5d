/* SPDX-License-Identifier: Apache-2.0 */
/* The element, data and global sections against WebAssembly 1.0 (5.5.9,
 * 5.5.12, 5.5.14 and 3.3.10, constant expressions): an offset or an
 * initialiser is exactly one constant instruction followed by end (roz
 * imports no globals, so global.get is never one); an element segment
 * needs a table and function indices that exist; a section holds exactly
 * the segments it declares. Before, an offset of two instructions ended the
 * element check without an error, and wasm3 then sized its table from a
 * later segment (100,000 entries for a table of 1, call_indirect reaching
 * entry 99,999). Each refusal names the segment and what is wrong; the
 * valid forms still load and run. Modules are built byte by byte (wat2wasm
 * cannot spell most of them). */
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
#include "wasm_bytes.h"

/* the bench's controller (support_bench.h) */
static roz_controller_t *const ctl = &roz_bench.ctl;

typedef roz_wb_buf_t buf_t;

#define SEC(w, id, ...)                                           \
    do {                                                          \
        static const uint8_t body_[] = { __VA_ARGS__ };           \
        roz_wb_put_section(w, id, body_, sizeof body_);                  \
    } while (0)

/* What a case puts in the optional sections (NULL: none). */
typedef struct {
    const uint8_t *table, *global, *elem, *data, *code;
    size_t         table_n, global_n, elem_n, data_n, code_n;
    int            memory;
} spec_t;

#define PART(name, ...) .name = (const uint8_t[]){ __VA_ARGS__ }, \
                        .name##_n = sizeof((const uint8_t[]){ __VA_ARGS__ })

/* (module
 *   (type (func)) (type (func (param i64)))
 *   (func $nop (type 0))
 *   (func (export "process") (type 1)  call_indirect (type 0) (i32.const 0))
 *   + the case's table, memory, global, elem and data sections) */
static buf_t mod;

static const uint8_t *build(const spec_t *s, size_t *len)
{
    mod.n = 0;
    roz_wb_put_bytes(&mod, "\0asm\1\0\0\0", 8);
    SEC(&mod, 1, 2, 0x60, 0, 0, 0x60, 1, 0x7e, 0);
    SEC(&mod, 3, 2, 0, 1);
    if (s->table != NULL)
        roz_wb_put_section(&mod, 4, s->table, s->table_n);
    if (s->memory)
        SEC(&mod, 5, 1, 0, 1);
    if (s->global != NULL)
        roz_wb_put_section(&mod, 6, s->global, s->global_n);
    SEC(&mod, 7, 1, 7, 'p', 'r', 'o', 'c', 'e', 's', 's', 0, 1);
    if (s->elem != NULL)
        roz_wb_put_section(&mod, 9, s->elem, s->elem_n);
    if (s->code != NULL)
        roz_wb_put_section(&mod, 10, s->code, s->code_n);
    else if (s->table != NULL) /* process calls entry 0 of the table */
        SEC(&mod, 10, 2, 2, 0, 0x0b, 7, 0, 0x41, 0, 0x11, 0, 0, 0x0b);
    else
        SEC(&mod, 10, 2, 2, 0, 0x0b, 2, 0, 0x0b);
    if (s->data != NULL)
        roz_wb_put_section(&mod, 11, s->data, s->data_n);
    *len = mod.n;
    return mod.b;
}

static void refused(const spec_t *s, const char *msg)
{
    size_t len;
    const uint8_t *w = build(s, &len);
    roz_bench_refused(w, len, msg);
}

static void runs(const spec_t *s)
{
    size_t len;
    const uint8_t *w = build(s, &len);
    roz_bench_load(w, len);
    for (int64_t t = 0; t < 3; t++)
        assert_int_equal(roz_controller_process(ctl, t), ROZ_OK);
    roz_controller_unload(ctl);
}

/* (table 1 funcref) */
#define TABLE1 PART(table, 1, 0x70, 0, 1)

/* ---- element segments ------------------------------------------------------ */

static void test_sections_elem_valid(void **st)
{
    (void)st;
    /* (elem (i32.const 0) $nop) and an empty one: load, run call_indirect */
    spec_t s = { TABLE1, PART(elem, 2, 0, 0x41, 0, 0x0b, 1, 0, 0, 0x41, 1, 0x0b, 0) };
    runs(&s);
}

static void test_sections_elem_offset_two_instructions(void **st)
{
    (void)st;
    /* offset "i32.const 0 i32.const 0 end", then a segment at 99999: the
     * first stopped the check, and wasm3 grew a 100,000-entry table */
    spec_t s = { TABLE1, PART(elem, 2, 0, 0x41, 0, 0x41, 0, 0x0b, 1, 0,
                              0, 0x41, 0x9f, 0x8d, 0x06, 0x0b, 1, 0) };
    refused(&s, "element segment 0: its offset is more than one instruction (a constant, "
                "then end)");
}

static void test_sections_elem_offset_not_constant(void **st)
{
    (void)st;
    spec_t s = { TABLE1, PART(elem, 1, 0, 0x23, 0, 0x0b, 1, 0),
                 PART(global, 1, 0x7f, 0, 0x41, 0, 0x0b) };
    refused(&s, "element segment 0: its offset is a global.get, which needs an imported global");
    spec_t t = { TABLE1, PART(elem, 1, 0, 0x42, 0, 0x0b, 1, 0) };
    refused(&t, "element segment 0: its offset has a constant of another type");
    spec_t u = { TABLE1, PART(elem, 1, 0, 0x6a, 0x0b, 1, 0) }; /* i32.add */
    refused(&u, "element segment 0: its offset is not a constant instruction");
}

static void test_sections_elem_without_table(void **st)
{
    (void)st;
    spec_t s = { PART(elem, 1, 0, 0x41, 0, 0x0b, 1, 0) };
    refused(&s, "element segment 0 without a table");
}

static void test_sections_elem_more_than_declared(void **st)
{
    (void)st;
    /* declares 1 segment, holds 2 (the second at 99999) */
    spec_t s = { TABLE1, PART(elem, 1, 0, 0x41, 0, 0x0b, 1, 0,
                              0, 0x41, 0x9f, 0x8d, 0x06, 0x0b, 1, 0) };
    refused(&s, "element section: 8 bytes after its 1 segments");
}

static void test_sections_elem_function_out_of_range(void **st)
{
    (void)st;
    spec_t s = { TABLE1, PART(elem, 1, 0, 0x41, 0, 0x0b, 1, 5) };
    refused(&s, "element segment 0, entry 0: function 5, of 2 functions");
}

/* ---- data segments and global initialisers ---------------------------------- */

static void test_sections_data(void **st)
{
    (void)st;
    spec_t ok = { .memory = 1, PART(data, 1, 0, 0x41, 8, 0x0b, 2, 'h', 'i') };
    runs(&ok);
    spec_t two = { .memory = 1, PART(data, 1, 0, 0x41, 0, 0x41, 8, 0x0b, 2, 'h', 'i') };
    refused(&two, "data segment 0: its offset is more than one instruction");
    spec_t get = { .memory = 1, PART(data, 1, 0, 0x23, 0, 0x0b, 0),
                   PART(global, 1, 0x7f, 0, 0x41, 0, 0x0b) };
    refused(&get, "data segment 0: its offset is a global.get");
    spec_t type = { .memory = 1, PART(data, 1, 0, 0x44, 0, 0, 0, 0, 0, 0, 0, 0, 0x0b, 0) };
    refused(&type, "data segment 0: its offset has a constant of another type");
    spec_t more = { .memory = 1, PART(data, 1, 0, 0x41, 0, 0x0b, 0, 0, 0x41, 0, 0x0b, 0) };
    refused(&more, "data section: 5 bytes after its 1 segments");
}

static void test_sections_globals(void **st)
{
    (void)st;
    spec_t ok = { PART(global, 2, 0x7f, 0, 0x41, 7, 0x0b, 0x7c, 1, 0x44, 0, 0, 0, 0, 0, 0,
                       0xf0, 0x3f, 0x0b) };
    runs(&ok);
    spec_t two = { PART(global, 1, 0x7f, 0, 0x41, 1, 0x41, 2, 0x0b) };
    refused(&two, "global 0: its initialiser is more than one instruction");
    spec_t get = { PART(global, 2, 0x7f, 0, 0x41, 1, 0x0b, 0x7f, 0, 0x23, 0, 0x0b) };
    refused(&get, "global 1: its initialiser is a global.get");
    spec_t type = { PART(global, 1, 0x7e, 0, 0x41, 1, 0x0b) };
    refused(&type, "global 0: its initialiser has a constant of another type");
    spec_t cut = { PART(global, 1, 0x7f, 0, 0x41) };
    refused(&cut, "global 0: its initialiser is cut short");
}

/* ---- what a refusal says ----------------------------------------------------- */

/* The code section: $nop, then process's body (its size first). */
#define CODE(size, ...) PART(code, 2, 2, 0, 0x0b, size, 0, __VA_ARGS__)

static void test_sections_messages(void **st)
{
    (void)st;
    /* call_indirect's reserved byte as the LEB128 "0x80 0x00": the module
     * has a table, the byte is what is wrong */
    spec_t ind = { TABLE1, CODE(8, 0x41, 0, 0x11, 0, 0x80, 0, 0x0b) };
    refused(&ind, "function 1, offset 3: call_indirect's reserved byte is not 0x00");
    spec_t notab = { CODE(7, 0x41, 0, 0x11, 0, 0, 0x0b) };
    refused(&notab, "call_indirect without a table");
    /* memory.size with reserved byte 1, with a memory */
    spec_t msz = { .memory = 1, CODE(5, 0x3f, 1, 0x1a, 0x0b) };
    refused(&msz, "function 1, offset 1: memory.size's reserved byte is not 0x00");
    spec_t nomem = { CODE(5, 0x3f, 0, 0x1a, 0x0b) };
    refused(&nomem, "memory.size or memory.grow without a memory");
    /* a junk bit in the last byte of a LEB128: i32.const's (signed) and
     * local.get's (unsigned); a body that really ends early says so */
    spec_t sleb = { CODE(9, 0x41, 0x80, 0x80, 0x80, 0x80, 0x70, 0x1a, 0x0b) };
    refused(&sleb, "function 1, offset 1: a malformed LEB128 immediate");
    spec_t uleb = { CODE(9, 0x20, 0x80, 0x80, 0x80, 0x80, 0x10, 0x1a, 0x0b) };
    refused(&uleb, "function 1, offset 1: a malformed LEB128 immediate");
    spec_t cut = { CODE(2, 0x41) };
    refused(&cut, "the body runs past its end");
}

ROZ_TEST_MAIN(roz_bench_test(test_sections_elem_valid),
              roz_bench_test(test_sections_elem_offset_two_instructions),
              roz_bench_test(test_sections_elem_offset_not_constant),
              roz_bench_test(test_sections_elem_without_table),
              roz_bench_test(test_sections_elem_more_than_declared),
              roz_bench_test(test_sections_elem_function_out_of_range),
              roz_bench_test(test_sections_data),
              roz_bench_test(test_sections_globals),
              roz_bench_test(test_sections_messages))
