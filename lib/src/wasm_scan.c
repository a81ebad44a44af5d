/* SPDX-License-Identifier: Apache-2.0 */
#include "wasm_scan.h"

#include <stdio.h>
#include <string.h>

#include "roz/abi.h"
#include "roz/error.h"

/* ---- private: a cursor over the module bytes ----------------------------- */

typedef struct {
    const uint8_t *p, *end;
    int            bad; /* set on any read past the end or malformed LEB */
} cursor_t;

static uint8_t rd_byte(cursor_t *c)
{
    if (c->p >= c->end) {
        c->bad = 1;
        return 0;
    }
    return *c->p++;
}

static uint32_t rd_u32(cursor_t *c)
{
    uint32_t v = 0;
    for (int shift = 0; shift < 35; shift += 7) {
        uint8_t b = rd_byte(c);
        if (c->bad)
            return 0;
        v |= (uint32_t)(b & 0x7f) << shift;
        if ((b & 0x80) == 0)
            return v;
    }
    c->bad = 1;
    return 0;
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

/* Reads a name into out (truncated, always NUL-terminated). */
static void rd_name(cursor_t *c, char *out, size_t outlen)
{
    uint32_t n = rd_u32(c);
    const uint8_t *s = c->p;
    skip(c, n);
    if (c->bad) {
        out[0] = '\0';
        return;
    }
    size_t k = n < outlen - 1 ? n : outlen - 1;
    for (size_t i = 0; i < k; i++)
        out[i] = (s[i] >= 0x20 && s[i] < 0x7f) ? (char)s[i] : '?';
    out[k] = '\0';
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
    cursor_t c = { m->types, m->types_end, 0 };
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
            snprintf(out, outlen, "%c(%s%s)", ret, args, np > sizeof args - 2 ? "..." : "");
            return ROZ_OK;
        }
    }
    return ROZ_EINVAL;
}

/* The type index of function `fidx` (imports first, then the function section). */
static int func_type(const module_t *m, uint32_t fidx, uint32_t *type_idx)
{
    cursor_t c = { m->funcs, m->funcs_end, 0 };
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
        snprintf(err, errlen, __VA_ARGS__);      \
        return ROZ_EINVAL;                       \
    } while (0)

/* ---- public -------------------------------------------------------------- */

int roz__wasm_scan(const uint8_t *wasm, size_t len, char *err, size_t errlen)
{
    static const uint8_t magic[8] = { 0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00 };
    module_t m = { 0 };
    const uint8_t *imports = NULL, *imports_end = NULL, *exports = NULL, *exports_end = NULL;
    int has_start = 0;

    if (wasm == NULL || len < sizeof magic || memcmp(wasm, magic, sizeof magic) != 0)
        FAIL("not a WebAssembly 1.0 binary (bad magic or version)");

    /* Pass 1: find the sections. */
    cursor_t c = { wasm + sizeof magic, wasm + len, 0 };
    while (c.p < c.end) {
        uint8_t id = rd_byte(&c);
        uint32_t size = rd_u32(&c);
        const uint8_t *body = c.p;
        skip(&c, size);
        if (c.bad)
            FAIL("malformed module: section %u runs past the end", (unsigned)id);
        switch (id) {
        case 1: m.types = body; m.types_end = body + size; break;
        case 2: imports = body; imports_end = body + size; break;
        case 3: m.funcs = body; m.funcs_end = body + size; break;
        case 7: exports = body; exports_end = body + size; break;
        case 8: has_start = 1; break;
        default: break;
        }
    }
    if (m.types != NULL) {
        cursor_t t = { m.types, m.types_end, 0 };
        m.n_types = rd_u32(&t);
    }
    if (has_start)
        FAIL("the module has a start function; a controller must do its set-up in process()");

    /* Pass 2: imports. */
    if (imports != NULL) {
        cursor_t ic = { imports, imports_end, 0 };
        uint32_t n = rd_u32(&ic);
        for (uint32_t i = 0; i < n; i++) {
            char mod[48], name[48], sig[40];
            rd_name(&ic, mod, sizeof mod);
            rd_name(&ic, name, sizeof name);
            uint8_t kind = rd_byte(&ic);
            if (ic.bad)
                FAIL("malformed import section");
            if (kind != 0)
                FAIL("import %s.%s is %s; a controller may import only the roz ABI's "
                     "functions and must define its own memory", mod, name, kind_name(kind));
            uint32_t type_idx = rd_u32(&ic);
            const roz_abi_import_t *imp = roz_abi_find_import(mod, name);
            if (imp == NULL)
                FAIL("unknown import %s.%s: not part of the roz controller ABI", mod, name);
            if (type_signature(&m, type_idx, sig, sizeof sig) != ROZ_OK)
                FAIL("import %s.%s: malformed type index %u", mod, name, (unsigned)type_idx);
            if (strcmp(sig, imp->signature) != 0)
                FAIL("import %s.%s has signature %s, expected %s", mod, name, sig,
                     imp->signature);
            m.n_func_imports++;
        }
    }

    /* Pass 3: export process(i64) -> (). */
    if (exports != NULL) {
        cursor_t ec = { exports, exports_end, 0 };
        uint32_t n = rd_u32(&ec);
        for (uint32_t i = 0; i < n && !ec.bad; i++) {
            char name[48], sig[40];
            uint32_t type_idx = 0;
            rd_name(&ec, name, sizeof name);
            uint8_t kind = rd_byte(&ec);
            uint32_t idx = rd_u32(&ec);
            if (ec.bad || strcmp(name, "process") != 0)
                continue;
            if (kind != 0)
                FAIL("export \"process\" is not a function");
            if (func_type(&m, idx, &type_idx) != ROZ_OK ||
                type_signature(&m, type_idx, sig, sizeof sig) != ROZ_OK)
                FAIL("export \"process\": malformed function index %u", (unsigned)idx);
            if (strcmp(sig, "v(I)") != 0)
                FAIL("export \"process\" has signature %s, expected v(I): process(i64 tick)", sig);
            return ROZ_OK;
        }
    }
    FAIL("no export \"process\": a controller must export process(i64 tick)");
}
