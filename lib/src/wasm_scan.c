/* SPDX-License-Identifier: Apache-2.0 */
#include "wasm_scan.h"

#include <stddef.h>
#include <string.h>

#include "roz/abi.h"
#include "roz/config.h"
#include "roz/error.h"
#include "roz/format.h"
#include "roz/identity.h"

/* ---- private: a cursor over the module bytes ----------------------------- */

typedef struct {
    const uint8_t *p, *end;
    int            bad; /* set on any read past the end or malformed LEB */
    int            leb; /* ... and this too when it was a malformed LEB */
} cursor_t;

/* A LEB128 longer than its type allows, or with bits past its width. */
static void bad_leb(cursor_t *c)
{
    c->bad = 1;
    c->leb = 1;
}

static uint8_t rd_byte(cursor_t *c)
{
    if (c->p >= c->end) {
        c->bad = 1;
        return 0;
    }
    return *c->p++;
}

/* A LEB128 of at most 32 bits: unsigned, or @p sign (sign-extended; bits
 * past 32 must then be the sign's). A malformed one reads 0, c->bad set. */
static uint32_t rd_leb32(cursor_t *c, int sign)
{
    uint32_t v = 0;
    for (int shift = 0; shift < 35; shift += 7) {
        uint8_t b = rd_byte(c);
        if (c->bad)
            return 0;
        v |= (uint32_t)(b & 0x7f) << shift;
        /* bits past 32 (but the sign's): malformed, and an engine may read
         * them differently */
        if (shift == 28 && (sign ? (b & 0x78) != 0 && (b & 0x78) != 0x78 : (b & 0x70) != 0))
            break;
        if ((b & 0x80) == 0) {
            if (sign && shift < 25 && (b & 0x40) != 0)
                v |= ~0u << (shift + 7);
            return v;
        }
    }
    bad_leb(c);
    return 0;
}

static uint32_t rd_u32(cursor_t *c)
{
    return rd_leb32(c, 0);
}

static void skip(cursor_t *c, uint32_t n)
{
    if ((size_t)(c->end - c->p) < n) {
        c->bad = 1;
        c->p = c->end;
        return;
    }
    c->p += n;
}

/* ---- private: names ----------------------------------------------------- */

/* Names (imports, exports, custom sections) are kept as the module's own
 * bytes: every comparison roz makes is on exactly the bytes wasm3 copies.
 * wasm3 keeps names as C strings (a copy ended by a NUL) and compares them
 * with strcmp, so a name with a NUL byte would compare equal to its prefix
 * there: such names are refused, as are names that are not UTF-8 (the
 * specification's rule) and names longer than wasm3's own limit. */
#define SCAN_MAX_NAME 10000 /* bytes; wasm3 refuses longer names (d_m3MaxSaneUtf8Length) */

typedef struct {
    const uint8_t *s;
    uint32_t       n;
} name_t;

static name_t rd_name(cursor_t *c)
{
    name_t nm = { NULL, 0 };
    uint32_t n = rd_u32(c);
    const uint8_t *s = c->p;
    skip(c, n);
    if (!c->bad) {
        nm.s = s;
        nm.n = n;
    }
    return nm;
}

static int name_is(name_t nm, const char *want)
{
    size_t n = strlen(want);
    return nm.n == n && memcmp(nm.s, want, n) == 0;
}

/* Well-formed UTF-8 as Unicode defines it: shortest form, no surrogates,
 * at most U+10FFFF. */
static int utf8_valid(const uint8_t *s, uint32_t n)
{
    uint32_t i = 0;
    while (i < n) {
        uint8_t b = s[i];
        uint32_t k, cp;
        if (b < 0x80) {
            i++;
            continue;
        }
        if (b >= 0xc2 && b <= 0xdf) {
            k = 1;
            cp = b & 0x1fu;
        } else if (b >= 0xe0 && b <= 0xef) {
            k = 2;
            cp = b & 0x0fu;
        } else if (b >= 0xf0 && b <= 0xf4) {
            k = 3;
            cp = b & 0x07u;
        } else {
            return 0;
        }
        if (n - i - 1 < k)
            return 0;
        for (uint32_t j = 1; j <= k; j++) {
            if ((s[i + j] & 0xc0) != 0x80)
                return 0;
            cp = (cp << 6) | (s[i + j] & 0x3fu);
        }
        if ((k == 2 && cp < 0x800) || (k == 3 && cp < 0x10000) || cp > 0x10ffff ||
            (cp >= 0xd800 && cp <= 0xdfff))
            return 0;
        i += k + 1;
    }
    return 1;
}

/* Why a name cannot be accepted, or NULL. */
static const char *name_problem(name_t nm)
{
    if (nm.n > SCAN_MAX_NAME)
        return "is longer than 10000 bytes (wasm3's limit; a roz limitation)";
    if (memchr(nm.s, 0, nm.n) != NULL)
        return "contains a NUL byte (wasm3 would read it as a shorter name)";
    if (!utf8_valid(nm.s, nm.n))
        return "is not valid UTF-8";
    return NULL;
}

/* A name for a message: printable ASCII kept, every other byte as \xNN,
 * cut with "..." to fit. */
static const char *show(name_t nm, char *out, size_t outlen)
{
    size_t k = 0;
    for (uint32_t i = 0; i < nm.n; i++) {
        uint8_t b = nm.s[i];
        size_t need = (b >= 0x20 && b < 0x7f && b != '\\' && b != '"') ? 1 : 4;
        if (k + need + 4 > outlen) {
            memcpy(out + k, "...", 4);
            return out;
        }
        if (need == 1)
            out[k++] = (char)b;
        else
            k += (size_t)roz_format(out + k, outlen - k, "\\x%02x", b);
    }
    out[k] = '\0';
    return out;
}

static char type_letter(uint8_t t)
{
    switch (t) {
    case 0x7f: return 'i';
    case 0x7e: return 'I';
    case 0x7d: return 'f';
    case 0x7c: return 'F';
    default:   return '?';
    }
}

typedef struct {
    const uint8_t *types;     /* type section body, NULL if none */
    const uint8_t *types_end;
    uint32_t       n_types;
    const uint8_t *funcs;     /* function section body */
    const uint8_t *funcs_end;
    uint32_t       n_func_imports;
} module_t;

/* Writes the signature of type `idx` as "ret(args)" (roz/abi.h notation). */
static int type_signature(const module_t *m, uint32_t idx, char *out, size_t outlen)
{
    cursor_t c = { m->types, m->types_end, 0, 0 };
    if (m->types == NULL || idx >= m->n_types)
        return ROZ_EINVAL;
    (void)rd_u32(&c); /* count */
    for (uint32_t t = 0; t <= idx && !c.bad; t++) {
        char args[24];
        size_t na = 0;
        char ret = 'v';
        if (rd_byte(&c) != 0x60)
            return ROZ_EINVAL;
        uint32_t np = rd_u32(&c);
        for (uint32_t i = 0; i < np && !c.bad; i++) {
            char l = type_letter(rd_byte(&c));
            if (na < sizeof args - 2)
                args[na++] = l;
        }
        args[na] = '\0';
        uint32_t nr = rd_u32(&c);
        for (uint32_t i = 0; i < nr && !c.bad; i++)
            ret = type_letter(rd_byte(&c));
        if (nr > 1)
            ret = '*';
        if (t == idx && !c.bad) {
            roz_format(out, outlen, "%c(%s%s)", ret, args, np > sizeof args - 2 ? "..." : "");
            return ROZ_OK;
        }
    }
    return ROZ_EINVAL;
}

/* A signature in roz/abi.h's notation ("i(iF)") as WebAssembly writes it,
 * "(i32, f64) -> i32", for messages. */
static const char *wasm_notation(const char *sig, char *out, size_t outlen)
{
    static const char letters[] = "iIfF";
    static const char *const names[] = { "i32", "i64", "f32", "f64" };
    size_t n = 0;
    const char *p = sig + 2; /* past "r(" */

#define PUT(...)                                                             \
    do {                                                                     \
        int k = roz_format(out + n, n < outlen ? outlen - n : 0, __VA_ARGS__); \
        n += k > 0 ? (size_t)k : 0;                                          \
    } while (0)
    PUT("(");
    for (int first = 1; *p != '\0' && *p != ')' && *p != '.'; p++, first = 0) {
        const char *hit = strchr(letters, *p);
        PUT("%s%s", first ? "" : ", ", hit != NULL ? names[hit - letters] : "?");
    }
    PUT("%s)", *p == '.' ? ", ..." : "");
    if (sig[0] == '*') {
        PUT(" -> (more than one value)");
    } else if (sig[0] == 'v') {
        PUT(" -> ()");
    } else {
        const char *hit = strchr(letters, sig[0]);
        PUT(" -> %s", hit != NULL ? names[hit - letters] : "?");
    }
#undef PUT
    if (outlen > 0 && n >= outlen)
        out[outlen - 1] = '\0';
    return out;
}

/* The type index of function `fidx` (imports first, then the function section). */
static int func_type(const module_t *m, uint32_t fidx, uint32_t *type_idx)
{
    cursor_t c = { m->funcs, m->funcs_end, 0, 0 };
    if (m->funcs == NULL || fidx < m->n_func_imports)
        return ROZ_EINVAL;
    uint32_t n = rd_u32(&c), want = fidx - m->n_func_imports;
    if (want >= n)
        return ROZ_EINVAL;
    for (uint32_t i = 0; i < want && !c.bad; i++)
        (void)rd_u32(&c);
    *type_idx = rd_u32(&c);
    return c.bad ? ROZ_EINVAL : ROZ_OK;
}

static const char *kind_name(uint8_t k)
{
    switch (k) {
    case 1:  return "a table";
    case 2:  return "a memory";
    case 3:  return "a global";
    default: return "an unknown kind of import";
    }
}

#define FAIL(...)                                \
    do {                                         \
        roz_format(err, errlen, __VA_ARGS__);    \
        return ROZ_EINVAL;                       \
    } while (0)

/* A signed LEB128 of at most 32 bits (an i32.const immediate). */
static int32_t rd_s32(cursor_t *c)
{
    return (int32_t)rd_leb32(c, 1);
}

/* A signed LEB128 of at most 64 bits, skipped (an i64.const immediate). */
static void skip_s64(cursor_t *c);

/* A constant expression (WebAssembly 1.0, 3.3.10): exactly one constant
 * instruction of value type `type`, then end. `global.get` of an imported
 * immutable global is one too, but a controller imports no globals. NULL
 * when it is one, else what is wrong. */
static const char *const_expr_problem(cursor_t *c, uint8_t type)
{
    static const uint8_t types[4] = { 0x7f, 0x7e, 0x7d, 0x7c }; /* i32 i64 f32 f64 */
    uint8_t op = rd_byte(c);
    switch (op) {
    case 0x41: (void)rd_s32(c); break;
    case 0x42: skip_s64(c); break;
    case 0x43: skip(c, 4); break;
    case 0x44: skip(c, 8); break;
    case 0x23:
        return "is a global.get, which needs an imported global (a controller imports none)";
    default:
        return c->bad ? "is cut short" : "is not a constant instruction";
    }
    if (c->bad)
        return "is cut short";
    if (rd_byte(c) != 0x0b)
        return c->bad ? "is cut short" : "is more than one instruction (a constant, then end)";
    if (types[op - 0x41] != type)
        return "has a constant of another type";
    return NULL;
}

/* Tables: wasm3 skips the table section and sizes its table from the
 * element segments instead (up to 100,000 entries), so a segment written
 * past the declared table is not refused there. Bound the declared size by
 * ROZ_CFG_WASM_MAX_TABLE_ENTRIES and require every segment (MVP form:
 * table 0, constant offset) to fit the declared table. */
static int check_tables(const uint8_t *tables, const uint8_t *tables_end, const uint8_t *elems,
                        const uint8_t *elems_end, uint32_t n_funcs, uint32_t max_entries,
                        char *err, size_t errlen)
{
    uint32_t size = 0;
    int have_table = 0;

    if (tables != NULL) {
        cursor_t tc = { tables, tables_end, 0, 0 };
        uint32_t n = rd_u32(&tc);
        if (n > 1 && !tc.bad)
            FAIL("%u tables; a controller may have one", (unsigned)n);
        have_table = n == 1;
        if (n == 1) {
            (void)rd_byte(&tc); /* element type */
            uint8_t flags = rd_byte(&tc);
            size = rd_u32(&tc);
            uint32_t max = flags == 1 ? rd_u32(&tc) : size;
            if (tc.bad || flags > 1 || max < size || tc.p != tc.end)
                FAIL("malformed table section");
            if (size > max_entries)
                FAIL("table of %u entries, more than ROZ_CFG_WASM_MAX_TABLE_ENTRIES (%u)",
                     (unsigned)size, (unsigned)max_entries);
        }
    }
    if (elems == NULL)
        return ROZ_OK;
    /* WebAssembly 1.0, 5.5.12: a vector of segments (table 0, an offset that
     * is one i32 constant then end, a vector of function indices), and
     * nothing after the last: the rest of the section is never skipped */
    cursor_t ec = { elems, elems_end, 0, 0 };
    uint32_t n = rd_u32(&ec);
    for (uint32_t i = 0; i < n && !ec.bad; i++) {
        uint32_t form = rd_u32(&ec);
        if (ec.bad)
            break;
        if (form != 0)
            FAIL("element segment %u: only the MVP form (table 0, constant offset) is accepted",
                 (unsigned)i);
        if (!have_table)
            FAIL("element segment %u without a table", (unsigned)i);
        cursor_t at = ec;
        const char *why = const_expr_problem(&ec, 0x7f);
        if (why != NULL)
            FAIL("element segment %u: its offset %s", (unsigned)i, why);
        at.p++; /* the i32.const */
        int32_t offset = rd_s32(&at);
        uint32_t count = rd_u32(&ec);
        if (ec.bad)
            break;
        if (offset < 0 || (uint64_t)(uint32_t)offset + count > size)
            FAIL("element segment %u at offset %lld needs a table of %llu entries; the table "
                 "has %u", (unsigned)i, (long long)offset,
                 (unsigned long long)((int64_t)offset + count), (unsigned)size);
        for (uint32_t k = 0; k < count && !ec.bad; k++) {
            uint32_t f = rd_u32(&ec);
            if (!ec.bad && f >= n_funcs)
                FAIL("element segment %u, entry %u: function %u, of %u functions", (unsigned)i,
                     (unsigned)k, (unsigned)f, (unsigned)n_funcs);
        }
    }
    if (ec.bad)
        FAIL("malformed element section");
    if (ec.p != ec.end)
        FAIL("element section: %u bytes after its %u segments", (unsigned)(ec.end - ec.p),
             (unsigned)n);
    return ROZ_OK;
}

/* ---- private: globals, data and function bodies --------------------------- */

/* wasm3 does not validate function bodies before it compiles them: it
 * compiles some malformed ones out of bounds (found by fuzz/fuzz_controller:
 * an `else` outside an `if`, blocks with parameters, docs/known-issues.md)
 * and accepts operands of the wrong type. So roz validates every body as
 * the WebAssembly 1.0 specification does (its validation algorithm: an
 * operand type stack and a stack of control frames) before the engine sees
 * it, within fixed limits, with no heap: block nesting, `else` only inside
 * `if`, branch labels, operand types of every instruction, function, type,
 * local and global indices, memory instructions only with a memory, global
 * writes only to mutable globals. Accepted beyond 1.0: sign extension,
 * saturating truncation, memory.copy and memory.fill (wasm3 implements
 * them; clang may emit them). Refused: blocks with parameters and functions
 * with more than one result (multi-value), and every other opcode; each
 * refusal names the function, the offset in its body and the reason. */

/* the limits (roz/config.h) */
#define SCAN_MAX_TYPES   ROZ_CFG_WASM_MAX_TYPES   /* function types per module */
#define SCAN_MAX_FUNCS   ROZ_CFG_WASM_MAX_FUNCS   /* functions, imported and defined */
#define SCAN_MAX_GLOBALS ROZ_CFG_WASM_MAX_GLOBALS /* globals */
#define SCAN_MAX_LOCALS  ROZ_CFG_WASM_MAX_LOCALS  /* parameters and locals per function */
#define SCAN_MAX_STACK   1024                     /* operand stack height per function */
/* control frames: the function body and its nested blocks (wasm3 compiles
 * those recursively: this bounds the loader's C stack, roz/config.h) */
#define SCAN_MAX_DEPTH  (ROZ_CFG_WASM_MAX_BLOCK_DEPTH + 1)
#define SCAN_MAX_PARAMS 255   /* parameters per function type */

enum { T_ANY = 0, T_I32 = 0x7f, T_I64 = 0x7e, T_F32 = 0x7d, T_F64 = 0x7c };

typedef struct {
    uint8_t  kind;       /* 0x02 block, 0x03 loop, 0x04 if, 0x05 else, 0 the body */
    uint8_t  result;     /* a value type, or 0 for none */
    uint8_t  unreachable;
    uint32_t height;     /* operand stack height at entry */
} frame_t;

#define SCAN_MAX_EXPORTS ROZ_CFG_WASM_MAX_EXPORTS /* exports per module */

typedef struct {
    uint32_t at;  /* offset of the name's length in the export section */
    uint32_t idx; /* export index */
} export_ref_t;

typedef struct {
    const uint8_t *types, *types_end;        /* type section body */
    uint32_t n_types;
    uint32_t type_at[SCAN_MAX_TYPES];        /* offset of each type in the section */
    uint32_t n_funcs;
    uint16_t func_type[SCAN_MAX_FUNCS];
    uint32_t n_globals;
    uint8_t  global_type[SCAN_MAX_GLOBALS];
    uint8_t  global_mut[SCAN_MAX_GLOBALS];
    int      has_memory, has_table;
    uint64_t compile_work;                   /* the engine's, so far (roz/config.h) */
    union {
        struct { /* the function being checked */
            uint32_t f, at;
            uint32_t n_locals;
            uint8_t  local_type[SCAN_MAX_LOCALS];
            uint32_t height;
            uint8_t  stack[SCAN_MAX_STACK];
            uint32_t depth;
            frame_t  ctl[SCAN_MAX_DEPTH];
        };
        /* the exports, once every body is checked (check_exports) */
        export_ref_t export_refs[SCAN_MAX_EXPORTS];
    };
    char    *err;
    size_t   errlen;
    const roz__wasm_limits_t *lim; /* at most the storage above */
} vctx_t;

/* The scratch is the caller's (roz_load_scratch_t, roz/controller.h):
 * static storage on firmware, a loader's stack or struct on hosts. */
_Static_assert(sizeof(vctx_t) <= sizeof(roz_load_scratch_t),
               "ROZ_CONTROLLER_SCRATCH_BYTES is smaller than the validator's context");
_Static_assert(_Alignof(vctx_t) <= _Alignof(roz_load_scratch_t),
               "roz_load_scratch_t is less aligned than the validator's context");

static int is_valtype(uint8_t t)
{
    return t == T_I32 || t == T_I64 || t == T_F32 || t == T_F64;
}

/* Skips a signed LEB128 of 64 bits (an i64.const immediate); a tenth byte
 * may carry only the sign. */
static void skip_s64(cursor_t *c)
{
    for (int i = 0; i < 10; i++) {
        uint8_t b = rd_byte(c);
        if (c->bad)
            return;
        if (i == 9 && (b & 0x7f) != 0 && (b & 0x7f) != 0x7f)
            break;
        if ((b & 0x80) == 0)
            return;
    }
    bad_leb(c);
}

static const char *type_name(uint8_t t)
{
    switch (t) {
    case T_I32: return "i32";
    case T_I64: return "i64";
    case T_F32: return "f32";
    case T_F64: return "f64";
    default:    return "nothing";
    }
}

static int bad_body(vctx_t *v, const char *why, const char *a, const char *b)
{
    roz_format(v->err, v->errlen, "function %u, offset %u: %s%s%s%s%s", (unsigned)v->f,
               (unsigned)v->at, why, a != NULL ? " " : "", a != NULL ? a : "",
               b != NULL ? ", got " : "", b != NULL ? b : "");
    return ROZ_EINVAL;
}

static int push(vctx_t *v, uint8_t t)
{
    if (v->height >= SCAN_MAX_STACK)
        return bad_body(v, "operand stack deeper than the limit", NULL, NULL);
    v->stack[v->height++] = t;
    return ROZ_OK;
}

/* Pops one operand of type `want` (T_ANY: any); *got is what it was. */
static int pop(vctx_t *v, uint8_t want, uint8_t *got)
{
    const frame_t *fr = &v->ctl[v->depth - 1];
    uint8_t t = T_ANY;
    if (v->height == fr->height) {
        if (!fr->unreachable)
            return bad_body(v, "operand missing: expected", want ? type_name(want) : "a value",
                            NULL);
    } else {
        t = v->stack[--v->height];
    }
    if (want != T_ANY && t != T_ANY && t != want)
        return bad_body(v, "type mismatch: expected", type_name(want), type_name(t));
    if (got != NULL)
        *got = t;
    return ROZ_OK;
}

static int pops(vctx_t *v, const char *sig)
{
    for (size_t i = strlen(sig); i-- > 0;) {
        static const char letters[] = "iIfF";
        static const uint8_t types[] = { T_I32, T_I64, T_F32, T_F64 };
        uint8_t want = types[strchr(letters, sig[i]) - letters];
        if (pop(v, want, NULL) != ROZ_OK)
            return ROZ_EINVAL;
    }
    return ROZ_OK;
}

/* "ii:i": pop the types left of the colon (last on top), push the right. */
static int apply(vctx_t *v, const char *sig)
{
    char in[4];
    const char *colon = strchr(sig, ':');
    size_t n = (size_t)(colon - sig);
    memcpy(in, sig, n);
    in[n] = '\0';
    if (pops(v, in) != ROZ_OK)
        return ROZ_EINVAL;
    if (colon[1] != '\0') {
        static const char letters[] = "iIfF";
        static const uint8_t types[] = { T_I32, T_I64, T_F32, T_F64 };
        return push(v, types[strchr(letters, colon[1]) - letters]);
    }
    return ROZ_OK;
}

/* Operand types of the numeric instructions 0x45..0xc4. */
static const char *numeric_sig(uint8_t op)
{
    static const struct { uint8_t first, last; const char *sig; } ranges[] = {
        { 0x45, 0x45, "i:i" },  { 0x46, 0x4f, "ii:i" }, { 0x50, 0x50, "I:i" },
        { 0x51, 0x5a, "II:i" }, { 0x5b, 0x60, "ff:i" }, { 0x61, 0x66, "FF:i" },
        { 0x67, 0x69, "i:i" },  { 0x6a, 0x78, "ii:i" }, { 0x79, 0x7b, "I:I" },
        { 0x7c, 0x8a, "II:I" }, { 0x8b, 0x91, "f:f" },  { 0x92, 0x98, "ff:f" },
        { 0x99, 0x9f, "F:F" },  { 0xa0, 0xa6, "FF:F" }, { 0xa7, 0xa7, "I:i" },
        { 0xa8, 0xa9, "f:i" },  { 0xaa, 0xab, "F:i" },  { 0xac, 0xad, "i:I" },
        { 0xae, 0xaf, "f:I" },  { 0xb0, 0xb1, "F:I" },  { 0xb2, 0xb3, "i:f" },
        { 0xb4, 0xb5, "I:f" },  { 0xb6, 0xb6, "F:f" },  { 0xb7, 0xb8, "i:F" },
        { 0xb9, 0xba, "I:F" },  { 0xbb, 0xbb, "f:F" },  { 0xbc, 0xbc, "f:i" },
        { 0xbd, 0xbd, "F:I" },  { 0xbe, 0xbe, "i:f" },  { 0xbf, 0xbf, "I:F" },
        { 0xc0, 0xc1, "i:i" },  { 0xc2, 0xc4, "I:I" },
    };
    for (size_t i = 0; i < sizeof ranges / sizeof ranges[0]; i++) {
        if (op >= ranges[i].first && op <= ranges[i].last)
            return ranges[i].sig;
    }
    return NULL;
}

/* Loads and stores 0x28..0x3e: operand types and the largest alignment. */
static const char *const memory_sig[] = {
    "i:i", "i:I", "i:f", "i:F", "i:i", "i:i", "i:i", "i:i", "i:I", "i:I", "i:I", "i:I",
    "i:I", "i:I", "ii:", "iI:", "if:", "iF:", "ii:", "ii:", "iI:", "iI:", "iI:",
};
static const uint8_t memory_align[] = { 2, 3, 2, 3, 0, 0, 1, 1, 0, 0, 1, 1,
                                        2, 2, 2, 3, 2, 3, 0, 1, 0, 1, 2 };

/* The parameter types of function type `type` and its result (0: none). */
static void type_sig(const vctx_t *v, uint32_t type, uint8_t *params, uint32_t *np,
                     uint8_t *result)
{
    /* the type section was checked whole before any body */
    cursor_t c = { v->types + v->type_at[type], v->types_end, 0, 0 };
    (void)rd_byte(&c);
    *np = rd_u32(&c);
    for (uint32_t i = 0; i < *np; i++)
        params[i] = rd_byte(&c);
    *result = rd_u32(&c) == 1 ? rd_byte(&c) : 0;
}

static int pop_params(vctx_t *v, uint32_t type, uint8_t *result)
{
    uint8_t params[SCAN_MAX_PARAMS];
    uint32_t np;
    type_sig(v, type, params, &np, result);
    while (np-- > 0) {
        if (pop(v, params[np], NULL) != ROZ_OK)
            return ROZ_EINVAL;
    }
    return ROZ_OK;
}

/* Values a branch to `label` carries: a loop's label takes none. */
static uint8_t label_type(const vctx_t *v, uint32_t label)
{
    const frame_t *fr = &v->ctl[v->depth - 1 - label];
    return fr->kind == 0x03 ? 0 : fr->result;
}

static void unreachable(vctx_t *v)
{
    frame_t *fr = &v->ctl[v->depth - 1];
    v->height = fr->height;
    fr->unreachable = 1;
}

/* The end of a frame's instructions: exactly its result on its stack. */
static int close_frame(vctx_t *v)
{
    const frame_t *fr = &v->ctl[v->depth - 1];
    if (fr->result != 0 && pop(v, fr->result, NULL) != ROZ_OK)
        return ROZ_EINVAL;
    if (v->height != fr->height)
        return bad_body(v, "values left on the stack at the end of a block", NULL, NULL);
    return ROZ_OK;
}

/* The function's locals: its parameters, then the declared groups. Its
 * result type in @p result. */
static int read_locals(vctx_t *v, cursor_t *c, uint8_t *result)
{
    uint8_t params[SCAN_MAX_PARAMS], t;
    uint32_t np;

    type_sig(v, v->func_type[v->f], params, &np, result);
    memcpy(v->local_type, params, np);
    v->n_locals = np;
    uint32_t groups = rd_u32(c);
    for (uint32_t g = 0; g < groups && !c->bad; g++) {
        uint32_t n = rd_u32(c);
        t = rd_byte(c);
        if (c->bad)
            break;
        if (!is_valtype(t))
            return bad_body(v, "a local of an unknown type", NULL, NULL);
        if (n > v->lim->locals - v->n_locals) {
            roz_format(v->err, v->errlen,
                       "function %u, offset %u: more parameters and locals than the limit "
                       "(%u, ROZ_CFG_WASM_MAX_LOCALS)",
                       (unsigned)v->f, (unsigned)v->at, (unsigned)v->lim->locals);
            return ROZ_EINVAL;
        }
        memset(v->local_type + v->n_locals, t, n);
        v->n_locals += n;
    }
    return ROZ_OK;
}

/* Counts instruction @p op into the function's compile work; refuses the
 * function past the limit. */
static int count_compile_work(vctx_t *v, uint8_t op)
{
    /* wasm3's compile work (ROZ_CFG_WASM_MAX_COMPILE_WORK): a step per
     * instruction; at a block, loop or if entered with values on the
     * stack it compares every local with them (PreserveArgsAndLocals),
     * at a local.set or tee every value with the local */
    v->compile_work += 1u;
    if (op >= 0x02 && op <= 0x04)
        v->compile_work += (uint64_t)v->n_locals * v->height;
    else if (op == 0x21 || op == 0x22)
        v->compile_work += v->height;
    if (v->compile_work > v->lim->compile_work) {
        roz_format(v->err, v->errlen,
                   "function %u, offset %u: compile work past "
                   "ROZ_CFG_WASM_MAX_COMPILE_WORK (%llu): %u locals, %u values on the "
                   "stack (docs/load-bound.md)",
                   (unsigned)v->f, (unsigned)v->at,
                   (unsigned long long)v->lim->compile_work,
                   (unsigned)v->n_locals, (unsigned)v->height);
        return ROZ_EINVAL;
    }
    return ROZ_OK;
}

static int bad_opcode(vctx_t *v, uint8_t op)
{
    roz_format(v->err, v->errlen,
               "function %u, offset %u: opcode 0x%02x is not accepted (unknown, or a "
               "feature beyond WebAssembly 1.0 that roz does not enable)",
               (unsigned)v->f, (unsigned)v->at, op);
    return ROZ_EINVAL;
}

/* The function's end: check_control() closed its outermost frame. */
#define SCAN_BODY_END 1

/* A control instruction, @p op 0x00 (unreachable) to 0x0f (return): ROZ_OK,
 * ROZ_EINVAL (said), or SCAN_BODY_END at the end of the function's body. */
static int check_control(vctx_t *v, cursor_t *c, uint8_t op)
{
    uint8_t t;
    uint32_t idx;
    int rc = ROZ_OK;

    switch (op) {
    case 0x00: /* unreachable */
        unreachable(v);
        break;
    case 0x01: /* nop */
        break;
    case 0x02: case 0x03: case 0x04: { /* block, loop, if */
        uint8_t bt = rd_byte(c);
        if (c->bad)
            break;
        if (bt != 0x40 && !is_valtype(bt))
            return bad_body(v, "a block type other than none or one value "
                               "(multi-value blocks are not accepted)", NULL, NULL);
        if (op == 0x04 && pop(v, T_I32, NULL) != ROZ_OK)
            return ROZ_EINVAL;
        if (v->depth >= v->lim->block_depth + 1u) {
            roz_format(v->err, v->errlen,
                       "function %u, offset %u: blocks nested deeper than "
                       "ROZ_CFG_WASM_MAX_BLOCK_DEPTH (%u; wasm3 compiles them "
                       "recursively on the loader's C stack)",
                       (unsigned)v->f, (unsigned)v->at,
                       (unsigned)v->lim->block_depth);
            return ROZ_EINVAL;
        }
        v->ctl[v->depth++] = (frame_t){ op, bt == 0x40 ? 0 : bt, 0, v->height };
        break;
    }
    case 0x05: { /* else */
        frame_t *fr = &v->ctl[v->depth - 1];
        if (fr->kind != 0x04)
            return bad_body(v, "else without its if", NULL, NULL);
        if (close_frame(v) != ROZ_OK)
            return ROZ_EINVAL;
        fr->kind = 0x05;
        fr->unreachable = 0;
        break;
    }
    case 0x0b: { /* end */
        const frame_t *fr = &v->ctl[v->depth - 1];
        if (close_frame(v) != ROZ_OK)
            return ROZ_EINVAL;
        if (fr->kind == 0x04 && fr->result != 0)
            return bad_body(v, "an if with a result but no else", NULL, NULL);
        uint8_t result = fr->result;
        if (--v->depth == 0) {
            if (c->p != c->end)
                return bad_body(v, "code after the body's end", NULL, NULL);
            return SCAN_BODY_END;
        }
        if (result != 0)
            rc = push(v, result);
        break;
    }
    case 0x0c: case 0x0d: /* br, br_if */
        idx = rd_u32(c);
        if (c->bad)
            break;
        if (idx >= v->depth)
            return bad_body(v, "a branch to a label outside the function", NULL, NULL);
        if (op == 0x0d && pop(v, T_I32, NULL) != ROZ_OK)
            return ROZ_EINVAL;
        t = label_type(v, idx);
        if (t != 0 && pop(v, t, NULL) != ROZ_OK)
            return ROZ_EINVAL;
        if (op == 0x0c)
            unreachable(v);
        else if (t != 0)
            rc = push(v, t);
        break;
    case 0x0e: { /* br_table */
        uint32_t n = rd_u32(c);
        if ((size_t)(c->end - c->p) < n)
            c->bad = 1;
        if (c->bad)
            break;
        if (pop(v, T_I32, NULL) != ROZ_OK)
            return ROZ_EINVAL;
        int arity = -1;
        for (uint32_t i = 0; i <= n && !c->bad; i++) {
            idx = rd_u32(c);
            if (c->bad)
                break;
            if (idx >= v->depth)
                return bad_body(v, "a br_table label outside the function", NULL, NULL);
            t = label_type(v, idx);
            if (arity == -1)
                arity = t;
            else if (arity != t)
                return bad_body(v, "br_table labels of different types", NULL, NULL);
        }
        if (arity > 0 && pop(v, (uint8_t)arity, NULL) != ROZ_OK)
            return ROZ_EINVAL;
        unreachable(v);
        break;
    }
    case 0x0f: /* return */
        if (v->ctl[0].result != 0 && pop(v, v->ctl[0].result, NULL) != ROZ_OK)
            return ROZ_EINVAL;
        unreachable(v);
        break;
    default:
        return bad_opcode(v, op);
    }
    return rc;
}

static int check_body(vctx_t *v, cursor_t *c)
{
    const uint8_t *start = c->p;
    uint8_t result, t, t2;
    uint32_t idx;

    if (read_locals(v, c, &result) != ROZ_OK)
        return ROZ_EINVAL;
    v->height = 0;
    v->depth = 1;
    v->ctl[0] = (frame_t){ 0, result, 0, 0 };

    while (!c->bad && c->p < c->end) {
        v->at = (uint32_t)(c->p - start);
        uint8_t op = rd_byte(c);
        const char *sig = numeric_sig(op);
        int rc = ROZ_OK;
        if (count_compile_work(v, op) != ROZ_OK)
            return ROZ_EINVAL;
        if (sig != NULL) {
            rc = apply(v, sig);
        } else if (op >= 0x28 && op <= 0x3e) {
            uint32_t align = rd_u32(c);
            (void)rd_u32(c); /* offset */
            if (!v->has_memory)
                return bad_body(v, "a memory access without a memory", NULL, NULL);
            if (!c->bad && align > memory_align[op - 0x28])
                return bad_body(v, "alignment larger than the access", NULL, NULL);
            rc = apply(v, memory_sig[op - 0x28]);
        } else if (op <= 0x0f) {
            rc = check_control(v, c, op);
            if (rc == SCAN_BODY_END)
                return ROZ_OK;
        } else {
            switch (op) {
            case 0x10: /* call */
                idx = rd_u32(c);
                if (c->bad)
                    break;
                if (idx >= v->n_funcs)
                    return bad_body(v, "a call to a function that does not exist", NULL, NULL);
                if (pop_params(v, v->func_type[idx], &t) != ROZ_OK)
                    return ROZ_EINVAL;
                if (t != 0)
                    rc = push(v, t);
                break;
            case 0x11: /* call_indirect */
                idx = rd_u32(c);
                t = rd_byte(c);
                if (c->bad)
                    break;
                if (t != 0) /* 1.0: the byte 0x00, not a LEB128 (0x80 0x00 is not it) */
                    return bad_body(v, "call_indirect's reserved byte is not 0x00", NULL, NULL);
                if (!v->has_table)
                    return bad_body(v, "call_indirect without a table", NULL, NULL);
                if (idx >= v->n_types)
                    return bad_body(v, "call_indirect of a type that does not exist", NULL, NULL);
                if (pop(v, T_I32, NULL) != ROZ_OK || pop_params(v, idx, &t) != ROZ_OK)
                    return ROZ_EINVAL;
                if (t != 0)
                    rc = push(v, t);
                break;
            case 0x1a: /* drop */
                rc = pop(v, T_ANY, NULL);
                break;
            case 0x1b: /* select */
                if (pop(v, T_I32, NULL) != ROZ_OK || pop(v, T_ANY, &t) != ROZ_OK ||
                    pop(v, t, &t2) != ROZ_OK)
                    return ROZ_EINVAL;
                rc = push(v, t != T_ANY ? t : t2);
                break;
            case 0x20: case 0x21: case 0x22: /* local.get, set, tee */
                idx = rd_u32(c);
                if (c->bad)
                    break;
                if (idx >= v->n_locals)
                    return bad_body(v, "a local that does not exist", NULL, NULL);
                t = v->local_type[idx];
                if (op != 0x20 && pop(v, t, NULL) != ROZ_OK)
                    return ROZ_EINVAL;
                if (op != 0x21)
                    rc = push(v, t);
                break;
            case 0x23: case 0x24: /* global.get, set */
                idx = rd_u32(c);
                if (c->bad)
                    break;
                if (idx >= v->n_globals)
                    return bad_body(v, "a global that does not exist", NULL, NULL);
                if (op == 0x24 && !v->global_mut[idx])
                    return bad_body(v, "global.set of an immutable global", NULL, NULL);
                rc = op == 0x23 ? push(v, v->global_type[idx]) : pop(v, v->global_type[idx], NULL);
                break;
            case 0x3f: case 0x40: /* memory.size, memory.grow */
                t = rd_byte(c);
                if (c->bad)
                    break;
                if (t != 0)
                    return bad_body(v, op == 0x3f ? "memory.size's reserved byte is not 0x00"
                                                  : "memory.grow's reserved byte is not 0x00",
                                    NULL, NULL);
                if (!v->has_memory)
                    return bad_body(v, "memory.size or memory.grow without a memory", NULL, NULL);
                rc = apply(v, op == 0x3f ? ":i" : "i:i");
                break;
            case 0x41: (void)rd_s32(c); rc = push(v, T_I32); break;
            case 0x42: skip_s64(c); rc = push(v, T_I64); break;
            case 0x43: skip(c, 4); rc = push(v, T_F32); break;
            case 0x44: skip(c, 8); rc = push(v, T_F64); break;
            case 0xfc: {
                static const char *const sat[8] = { "f:i", "f:i", "F:i", "F:i",
                                                    "f:I", "f:I", "F:I", "F:I" };
                /* one byte: wasm3 reads the sub-opcode as a byte, not a LEB */
                uint8_t sub = rd_byte(c);
                if (c->bad)
                    break;
                if (sub <= 7) {
                    rc = apply(v, sat[sub]);
                } else if ((sub == 10 || sub == 11) && v->has_memory) {
                    if (rd_byte(c) != 0 || (sub == 10 && rd_byte(c) != 0))
                        return bad_body(v, "a malformed memory.copy or memory.fill", NULL, NULL);
                    rc = apply(v, "iii:");
                } else {
                    return bad_body(v, "an opcode (0xfc prefix) that is not accepted", NULL,
                                    NULL);
                }
                break;
            }
            default:
                return bad_opcode(v, op);
            }
        }
        if (rc != ROZ_OK)
            return ROZ_EINVAL;
    }
    if (c->leb)
        return bad_body(v, "a malformed LEB128 immediate (longer than its type allows, or bits "
                           "past its width)", NULL, NULL);
    return bad_body(v, "the body runs past its end", NULL, NULL);
}

/* Types, globals, memory, data and code: everything the engine would
 * otherwise take on trust. `sec`/`sec_end` are the sections by id; imports
 * were checked before (all functions of the ABI). */
static int check_code(vctx_t *v, const module_t *m, const uint8_t *imports,
                      const uint8_t *imports_end, const uint8_t *const *sec,
                      const uint8_t *const *sec_end, char *err, size_t errlen)
{
    uint32_t n;

    memset(v, 0, offsetof(vctx_t, f));
    v->err = err;
    v->errlen = errlen;
    /* types: functions of at most SCAN_MAX_PARAMS value parameters and one result */
    if (m->n_types > v->lim->types)
        FAIL("%u function types, more than %u (ROZ_CFG_WASM_MAX_TYPES)", (unsigned)m->n_types,
             (unsigned)v->lim->types);
    v->types = sec[1];
    v->types_end = sec_end[1];
    v->n_types = m->n_types;
    if (sec[1] != NULL) {
        cursor_t c = { sec[1], sec_end[1], 0, 0 };
        (void)rd_u32(&c);
        for (uint32_t t = 0; t < v->n_types && !c.bad; t++) {
            v->type_at[t] = (uint32_t)(c.p - sec[1]);
            if (rd_byte(&c) != 0x60)
                FAIL("type %u is not a function type", (unsigned)t);
            uint32_t np = rd_u32(&c);
            if (!c.bad && np > SCAN_MAX_PARAMS)
                FAIL("type %u has %u parameters, more than %u", (unsigned)t, (unsigned)np,
                     (unsigned)SCAN_MAX_PARAMS);
            for (uint32_t i = 0; i < np && !c.bad; i++) {
                if (!is_valtype(rd_byte(&c)) && !c.bad)
                    FAIL("type %u: a parameter of an unknown type", (unsigned)t);
            }
            uint32_t nr = rd_u32(&c);
            if (!c.bad && nr > 1)
                FAIL("type %u returns %u values; WebAssembly 1.0 functions return at most one",
                     (unsigned)t, (unsigned)nr);
            if (nr == 1 && !is_valtype(rd_byte(&c)) && !c.bad)
                FAIL("type %u: a result of an unknown type", (unsigned)t);
        }
        if (c.bad || c.p != c.end)
            FAIL("malformed type section");
    }
    /* functions: the imported ones, then the function section */
    if (imports != NULL) {
        cursor_t c = { imports, imports_end, 0, 0 };
        n = rd_u32(&c);
        for (uint32_t i = 0; i < n && !c.bad; i++) {
            skip(&c, rd_u32(&c));
            skip(&c, rd_u32(&c));
            (void)rd_byte(&c); /* a function: checked before */
            uint32_t type = rd_u32(&c);
            if (c.bad)
                break;
            if (v->n_funcs >= v->lim->funcs)
                FAIL("more than %u functions (ROZ_CFG_WASM_MAX_FUNCS)", (unsigned)v->lim->funcs);
            v->func_type[v->n_funcs++] = (uint16_t)type; /* < n_types: checked before */
        }
        if (c.bad || c.p != c.end)
            FAIL("malformed import section");
    }
    cursor_t fc = { m->funcs, m->funcs_end, 0, 0 };
    uint32_t n_defined = m->funcs != NULL ? rd_u32(&fc) : 0;
    for (uint32_t i = 0; i < n_defined && !fc.bad; i++) {
        uint32_t type = rd_u32(&fc);
        if (fc.bad)
            break;
        if (type >= v->n_types)
            FAIL("function %u has type %u of %u", (unsigned)v->n_funcs, (unsigned)type,
                 (unsigned)v->n_types);
        if (v->n_funcs >= v->lim->funcs)
            FAIL("more than %u functions (ROZ_CFG_WASM_MAX_FUNCS)", (unsigned)v->lim->funcs);
        v->func_type[v->n_funcs++] = (uint16_t)type;
    }
    if (fc.bad || fc.p != fc.end)
        FAIL("malformed function section");
    /* globals: a value type, mutability and one constant of that type */
    if (sec[6] != NULL) {
        cursor_t c = { sec[6], sec_end[6], 0, 0 };
        v->n_globals = rd_u32(&c);
        if (!c.bad && v->n_globals > v->lim->globals)
            FAIL("%u globals, more than %u (ROZ_CFG_WASM_MAX_GLOBALS)", (unsigned)v->n_globals,
                 (unsigned)v->lim->globals);
        for (uint32_t g = 0; g < v->n_globals && !c.bad; g++) {
            v->global_type[g] = rd_byte(&c);
            v->global_mut[g] = rd_byte(&c);
            if (c.bad || !is_valtype(v->global_type[g]) || v->global_mut[g] > 1)
                FAIL("global %u: malformed (a value type, then 0 or 1)", (unsigned)g);
            const char *why = const_expr_problem(&c, v->global_type[g]);
            if (why != NULL)
                FAIL("global %u: its initialiser %s", (unsigned)g, why);
        }
        if (c.bad || c.p != c.end)
            FAIL("malformed global section");
    }
    if (sec[4] != NULL) {
        cursor_t c = { sec[4], sec_end[4], 0, 0 };
        v->has_table = rd_u32(&c) == 1;
    }
    if (sec[5] != NULL) {
        cursor_t c = { sec[5], sec_end[5], 0, 0 };
        n = rd_u32(&c);
        if (n > 1)
            FAIL("%u memories; a controller may have one", (unsigned)n);
        v->has_memory = n == 1;
        if (n == 1) {
            uint8_t flags = rd_byte(&c);
            uint32_t min = rd_u32(&c);
            uint32_t max = flags == 1 ? rd_u32(&c) : min;
            if (!c.bad && flags > 1)
                FAIL("memory limits flag %u: shared or 64-bit memories are not accepted",
                     (unsigned)flags);
            if (min > 65536 || max > 65536 || max < min)
                c.bad = 1;
        }
        if (c.bad || c.p != c.end)
            FAIL("malformed memory section");
    }
    /* data: memory 0, an i32.const offset, bytes within the section */
    if (sec[11] != NULL) {
        cursor_t c = { sec[11], sec_end[11], 0, 0 };
        n = rd_u32(&c);
        if (n > 0 && !v->has_memory)
            FAIL("data segments without a memory");
        for (uint32_t d = 0; d < n && !c.bad; d++) {
            if (rd_u32(&c) != 0)
                FAIL("data segment %u: only memory 0 is accepted", (unsigned)d);
            const char *why = const_expr_problem(&c, T_I32);
            if (why != NULL)
                FAIL("data segment %u: its offset %s", (unsigned)d, why);
            skip(&c, rd_u32(&c));
        }
        if (c.bad)
            FAIL("malformed data section");
        if (c.p != c.end)
            FAIL("data section: %u bytes after its %u segments", (unsigned)(c.end - c.p),
                 (unsigned)n);
    }
    /* code: one valid body per defined function */
    cursor_t cc = { sec[10], sec_end[10], 0, 0 };
    n = sec[10] != NULL ? rd_u32(&cc) : 0;
    if (cc.bad || n != n_defined)
        FAIL("%u function bodies for %u functions", (unsigned)n, (unsigned)n_defined);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t size = rd_u32(&cc);
        if (cc.bad || (size_t)(cc.end - cc.p) < size)
            FAIL("malformed code section");
        cursor_t body = { cc.p, cc.p + size, 0, 0 };
        v->f = m->n_func_imports + i;
        v->at = 0;
        if (check_body(v, &body) != ROZ_OK)
            return ROZ_EINVAL;
        cc.p += size;
    }
    if (cc.p != cc.end)
        FAIL("malformed code section");
    /* exports: of things that exist (process itself is checked below) */
    if (sec[7] != NULL) {
        cursor_t c = { sec[7], sec_end[7], 0, 0 };
        n = rd_u32(&c);
        for (uint32_t e = 0; e < n && !c.bad; e++) {
            skip(&c, rd_u32(&c));
            uint8_t kind = rd_byte(&c);
            uint32_t idx = rd_u32(&c);
            if (c.bad)
                break;
            if ((kind == 0 && idx >= v->n_funcs) || (kind == 1 && (!v->has_table || idx != 0)) ||
                (kind == 2 && (!v->has_memory || idx != 0)) ||
                (kind == 3 && idx >= v->n_globals) || kind > 3)
                FAIL("export %u: of something that does not exist", (unsigned)e);
        }
        if (c.bad || c.p != c.end)
            FAIL("malformed export section");
    }
    return ROZ_OK;
}

/* ---- private: exports --------------------------------------------------- */

/* Export names must be unique (the specification); wasm3 would keep them
 * all and m3_FindFunction would return the first function with the name,
 * which need not be the export roz checked. Duplicates are found by sorting
 * the names (heapsort: no recursion, no heap, O(n log n) comparisons) in
 * v->export_refs, over the body checker's scratch. */

static name_t export_name(const uint8_t *sec, const uint8_t *end, const export_ref_t *r)
{
    cursor_t c = { sec + r->at, end, 0, 0 };
    return rd_name(&c);
}

static int name_cmp(name_t a, name_t b)
{
    int d = memcmp(a.s, b.s, a.n < b.n ? a.n : b.n);
    if (d != 0)
        return d;
    return a.n < b.n ? -1 : a.n > b.n;
}

static void sift_down(export_ref_t *r, size_t root, size_t n, const uint8_t *sec,
                      const uint8_t *end)
{
    for (;;) {
        size_t child = 2 * root + 1;
        if (child >= n)
            return;
        if (child + 1 < n && name_cmp(export_name(sec, end, &r[child]),
                                      export_name(sec, end, &r[child + 1])) < 0)
            child++;
        if (name_cmp(export_name(sec, end, &r[root]), export_name(sec, end, &r[child])) >= 0)
            return;
        export_ref_t t = r[root];
        r[root] = r[child];
        r[child] = t;
        root = child;
    }
}

/* Names, uniqueness, and the export "process": a function defined in the
 * module of type (i64) -> (), whose function index goes to *process_index.
 * The kinds and indices of all exports were checked with the code. */
static int check_exports(vctx_t *v, const module_t *m, const uint8_t *sec, const uint8_t *end,
                         uint32_t *process_index, char *err, size_t errlen)
{
    export_ref_t *refs = v->export_refs;
    uint32_t n = 0, found = 0, pidx = 0;
    uint8_t pkind = 0;
    char shown[48], sig[40];

    if (sec != NULL) {
        cursor_t c = { sec, end, 0, 0 };
        n = rd_u32(&c);
        if (n > v->lim->exports)
            FAIL("%u exports, more than %u (ROZ_CFG_WASM_MAX_EXPORTS)", (unsigned)n,
                 (unsigned)v->lim->exports);
        for (uint32_t e = 0; e < n; e++) {
            const char *why;
            refs[e] = (export_ref_t){ (uint32_t)(c.p - sec), e };
            name_t nm = rd_name(&c);
            uint8_t kind = rd_byte(&c);
            uint32_t idx = rd_u32(&c);
            if (c.bad)
                FAIL("malformed export section"); /* checked before: not reached */
            if ((why = name_problem(nm)) != NULL)
                FAIL("export %u: its name \"%s\" %s", (unsigned)e, show(nm, shown, sizeof shown),
                     why);
            if (name_is(nm, "process")) {
                found = 1;
                pkind = kind;
                pidx = idx;
            }
        }
    }
    /* heapsort by name; equal names end up next to each other */
    for (size_t i = n / 2; i-- > 0;)
        sift_down(refs, i, n, sec, end);
    for (size_t i = n; i-- > 1;) {
        export_ref_t t = refs[0];
        refs[0] = refs[i];
        refs[i] = t;
        sift_down(refs, 0, i, sec, end);
    }
    for (uint32_t i = 1; i < n; i++) {
        name_t a = export_name(sec, end, &refs[i - 1]), b = export_name(sec, end, &refs[i]);
        if (name_cmp(a, b) == 0) {
            uint32_t first = refs[i - 1].idx < refs[i].idx ? refs[i - 1].idx : refs[i].idx;
            uint32_t second = refs[i - 1].idx ^ refs[i].idx ^ first;
            FAIL("export %u: duplicate export name \"%s\" (also export %u); export names "
                 "must be unique", (unsigned)second, show(b, shown, sizeof shown),
                 (unsigned)first);
        }
    }
    if (!found)
        FAIL("no export \"process\": a controller must export process(i64 tick)");
    if (pkind != 0)
        FAIL("export \"process\" is not a function");
    if (pidx < m->n_func_imports)
        FAIL("export \"process\" is imported function %u; process must be defined in the "
             "module", (unsigned)pidx);
    uint32_t type_idx = 0;
    if (func_type(m, pidx, &type_idx) != ROZ_OK ||
        type_signature(m, type_idx, sig, sizeof sig) != ROZ_OK)
        FAIL("export \"process\": malformed function index %u", (unsigned)pidx);
    if (strcmp(sig, "v(I)") != 0) {
        char got[64];
        FAIL("export \"process\" has type %s, expected (i64) -> (): process(i64 tick)",
             wasm_notation(sig, got, sizeof got));
    }
    *process_index = pidx;
    return ROZ_OK;
}

/* ---- public -------------------------------------------------------------- */

/* A limit of another build's, within this build's storage for the scan. */
static uint32_t within(uint32_t asked, uint32_t cap)
{
    return asked < cap ? asked : cap;
}

/* The option that leaves an import out of the build the limits are for
 * (the import table's own, roz_abi_imports[], names it for this build). */
static const char *left_out_by(const roz__wasm_limits_t *lim, const roz_abi_import_t *imp)
{
    if (!lim->math_imports && strcmp(imp->module, "math") == 0)
        return "ROZ_CFG_MATH_IMPORTS";
    if (!lim->nn_imports && strcmp(imp->module, "nn") == 0)
        return "ROZ_CFG_NN_IMPORTS";
    if (!lim->bulk_imports && (strcmp(imp->name, "get_all") == 0 ||
                               strcmp(imp->name, "set_all") == 0))
        return "ROZ_CFG_BULK_IMPORTS";
    return NULL;
}

void roz__wasm_limits_of_build(roz__wasm_limits_t *lim)
{
    *lim = (roz__wasm_limits_t){
        .types = ROZ_CFG_WASM_MAX_TYPES,
        .funcs = ROZ_CFG_WASM_MAX_FUNCS,
        .globals = ROZ_CFG_WASM_MAX_GLOBALS,
        .locals = ROZ_CFG_WASM_MAX_LOCALS,
        .exports = ROZ_CFG_WASM_MAX_EXPORTS,
        .table_entries = ROZ_CFG_WASM_MAX_TABLE_ENTRIES,
        .block_depth = ROZ_CFG_WASM_MAX_BLOCK_DEPTH,
        .compile_work = ROZ_CFG_WASM_MAX_COMPILE_WORK,
        .pages = ROZ_CFG_WASM_MAX_PAGES,
        .module_bytes = ROZ_CFG_WASM_MAX_MODULE_BYTES,
        .math_imports = ROZ_CFG_MATH_IMPORTS,
        .bulk_imports = ROZ_CFG_BULK_IMPORTS,
        .nn_imports = ROZ_CFG_NN_IMPORTS,
    };
}

int roz__wasm_scan(const uint8_t *wasm, size_t len, roz_load_scratch_t *scratch,
                   uint32_t *process_index, char *err, size_t errlen)
{
    return roz__wasm_scan_for(wasm, len, scratch, NULL, process_index, err, errlen);
}

int roz__wasm_scan_for(const uint8_t *wasm, size_t len, roz_load_scratch_t *scratch,
                       const roz__wasm_limits_t *asked, uint32_t *process_index, char *err,
                       size_t errlen)
{
    vctx_t *v = (vctx_t *)(void *)scratch;
    roz__wasm_limits_t lim;
    roz__wasm_limits_of_build(&lim);
    if (asked != NULL) { /* another build's: this one's where that asks more */
        lim.types = within(asked->types, lim.types);
        lim.funcs = within(asked->funcs, lim.funcs);
        lim.globals = within(asked->globals, lim.globals);
        lim.locals = within(asked->locals, lim.locals);
        lim.exports = within(asked->exports, lim.exports);
        lim.table_entries = within(asked->table_entries, lim.table_entries);
        lim.block_depth = within(asked->block_depth, lim.block_depth);
        if (asked->compile_work < lim.compile_work)
            lim.compile_work = asked->compile_work;
        lim.math_imports &= asked->math_imports;
        lim.bulk_imports &= asked->bulk_imports;
        lim.nn_imports &= asked->nn_imports;
    }
    v->lim = &lim;
    static const uint8_t magic[8] = { 0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00 };
    module_t m = { 0 };
    const uint8_t *imports = NULL, *imports_end = NULL, *exports = NULL, *exports_end = NULL;
    const uint8_t *tables = NULL, *tables_end = NULL, *elems = NULL, *elems_end = NULL;
    const uint8_t *sec[13] = { 0 }, *sec_end[13] = { 0 };
    int has_start = 0;

    if (wasm == NULL || len < sizeof magic || memcmp(wasm, magic, sizeof magic) != 0)
        FAIL("not a WebAssembly 1.0 binary (bad magic or version)");

    /* Pass 1: find the sections. */
    cursor_t c = { wasm + sizeof magic, wasm + len, 0, 0 };
    while (c.p < c.end) {
        uint8_t id = rd_byte(&c);
        uint32_t size = rd_u32(&c);
        const uint8_t *body = c.p;
        skip(&c, size);
        if (c.bad)
            FAIL("malformed module: section %u runs past the end", (unsigned)id);
        if (id < 13) {
            sec[id] = body;
            sec_end[id] = body + size;
        }
        switch (id) {
        case 1: m.types = body; m.types_end = body + size; break;
        case 2: imports = body; imports_end = body + size; break;
        case 3: m.funcs = body; m.funcs_end = body + size; break;
        case 4: tables = body; tables_end = body + size; break;
        case 7: exports = body; exports_end = body + size; break;
        case 8: has_start = 1; break;
        case 9: elems = body; elems_end = body + size; break;
        case 0: { /* custom: a well-formed name; the content never reaches wasm3
                   (roz.manifest's is read below) */
            cursor_t cc = { body, body + size, 0, 0 };
            char shown[48];
            const char *why;
            name_t nm = rd_name(&cc);
            if (cc.bad)
                FAIL("custom section at offset %u: malformed name",
                     (unsigned)(body - wasm));
            if ((why = name_problem(nm)) != NULL)
                FAIL("custom section at offset %u: its name \"%s\" %s",
                     (unsigned)(body - wasm), show(nm, shown, sizeof shown), why);
            break;
        }
        default: break;
        }
    }
    /* The custom section "roz.manifest" (roz/identity.h): malformed or twice,
     * refused whatever the robot; comparing it with the robot is the
     * runtime's (roz_runtime_load). */
    roz_identity_t identity;
    if (roz_identity_read(wasm, len, &identity, err, errlen) != ROZ_OK)
        return ROZ_EINVAL;
    if (m.types != NULL) {
        cursor_t t = { m.types, m.types_end, 0, 0 };
        m.n_types = rd_u32(&t);
    }
    if (has_start)
        FAIL("the module has a start function; a controller must do its set-up in process()");
    /* The counts the import pass walks are bounded before it walks them:
     * each import's type is looked up in the type section (docs/load-bound.md) */
    if (m.n_types > lim.types)
        FAIL("%u function types, more than %u (ROZ_CFG_WASM_MAX_TYPES)", (unsigned)m.n_types,
             (unsigned)lim.types);

    /* Pass 2: imports, by the exact bytes of their names (wasm3 links them
     * by the same bytes, see lib/src/controller.c). */
    if (imports != NULL) {
        cursor_t ic = { imports, imports_end, 0, 0 };
        uint32_t n = rd_u32(&ic);
        if (!ic.bad && n > roz_abi_import_count)
            FAIL("%u imports, more than the %u functions of the roz ABI", (unsigned)n,
                 (unsigned)roz_abi_import_count);
        for (uint32_t i = 0; i < n; i++) {
            char mod[48], name[48], sig[40];
            const char *why;
            name_t nm_mod = rd_name(&ic), nm_name = rd_name(&ic);
            uint8_t kind = rd_byte(&ic);
            if (ic.bad)
                FAIL("malformed import section");
            if ((why = name_problem(nm_mod)) != NULL)
                FAIL("import %u: its module name \"%s\" %s", (unsigned)i,
                     show(nm_mod, mod, sizeof mod), why);
            if ((why = name_problem(nm_name)) != NULL)
                FAIL("import %u: its name \"%s\" %s", (unsigned)i, show(nm_name, name, sizeof name),
                     why);
            show(nm_mod, mod, sizeof mod);
            show(nm_name, name, sizeof name);
            if (kind != 0)
                FAIL("import %s.%s is %s; a controller may import only the roz ABI's "
                     "functions and must define its own memory", mod, name, kind_name(kind));
            uint32_t type_idx = rd_u32(&ic);
            const roz_abi_import_t *imp = NULL;
            for (size_t k = 0; k < roz_abi_import_count && imp == NULL; k++) {
                if (name_is(nm_mod, roz_abi_imports[k].module) &&
                    name_is(nm_name, roz_abi_imports[k].name))
                    imp = &roz_abi_imports[k];
            }
            if (imp == NULL)
                FAIL("unknown import %s.%s: not part of the roz controller ABI", mod, name);
            const char *left_out = imp->left_out != NULL ? imp->left_out
                                                         : left_out_by(&lim, imp);
            if (left_out != NULL)
                FAIL("import %s.%s: left out of this build of roz (%s is 0)", mod, name,
                     left_out);
            if (type_signature(&m, type_idx, sig, sizeof sig) != ROZ_OK)
                FAIL("import %s.%s: malformed type index %u", mod, name, (unsigned)type_idx);
            if (strcmp(sig, imp->signature) != 0) {
                char got[64], want[64];
                FAIL("import %s.%s has type %s, expected %s", mod, name,
                     wasm_notation(sig, got, sizeof got),
                     wasm_notation(imp->signature, want, sizeof want));
            }
            m.n_func_imports++;
        }
    }

    /* The table and the element segments, their function indices against
     * the imported and defined functions. */
    uint32_t n_defined = 0;
    if (m.funcs != NULL) {
        cursor_t fc = { m.funcs, m.funcs_end, 0, 0 };
        n_defined = rd_u32(&fc);
        if (n_defined > lim.funcs)
            n_defined = lim.funcs; /* refused by check_code() */
    }
    if (check_tables(tables, tables_end, elems, elems_end, m.n_func_imports + n_defined,
                     lim.table_entries, err, errlen) != ROZ_OK)
        return ROZ_EINVAL;

    /* Pass 3: types, globals, memory, data, function bodies. */
    if (check_code(v, &m, imports, imports_end, sec, sec_end, err, errlen) != ROZ_OK)
        return ROZ_EINVAL;

    /* Pass 4: export names, and process(i64) -> (). */
    return check_exports(v, &m, exports, exports_end, process_index, err, errlen);
}
