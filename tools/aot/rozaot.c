/* SPDX-License-Identifier: Apache-2.0 */
/* rozaot: the build step in front of wasm2c for an ahead-of-time controller
 * (docs/controllers.md, "Two engines").
 *
 *   rozaot [--limits LIMITS] NAME IN.wasm OUT.wasm OUT_glue.c
 *
 * 1. Loads IN.wasm exactly as the runtime does (roz_controller_load: roz's
 *    validator, then wasm3's compiler): a module roz refuses is never
 *    compiled, and the message names the file and the reason. LIMITS: the
 *    limits of the build the controller is compiled into (its roz/config.h
 *    through that build's preprocessor, cmake/RozAot.cmake), which a
 *    firmware sets far below a host's: the module is checked against them
 *    too (the validator's, the memory's pages, the module's size, the
 *    imports the build leaves out), so that rozaot refuses what that
 *    build's wasm3 loader would.
 * 2. Writes OUT.wasm: the same module with roz's fuel metering inserted, at
 *    the charge points and with the units of wasm3's metering
 *    (cmake/wasm3/02-metering.patch), so that a controller uses the same
 *    fuel on both engines, tick for tick. The units a call pays on entry
 *    come from the wasm3 compilation of step 1 itself, never re-derived.
 *    Added: a mutable i64 global (the slice's fuel, exported "rozfuel"),
 *    the imports roz.refuel, roz.fill and roz.copy (appended after the
 *    module's own, every function index shifted past them), the export
 *    "rozmemory" of memory 0; custom sections dropped.
 * 3. Writes OUT_glue.c: the roz_aot_module_t (roz/aot.h) over wasm2c's
 *    output for OUT.wasm (compiled with -n NAME), with static storage for
 *    ROZ_CFG_AOT_INSTANCES instances, the module's roz.* custom sections (its
 *    identity and declared fuel) and the hash of IN.wasm.
 *
 * A host tool, in C rather than in rozgen: it runs roz's own validator and
 * wasm3's own compiler on the module, so the pass cannot drift from what
 * the interpreter charges. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "roz/controller.h"
#include "roz/recorder.h"

#include "wasm3.h"
#include "m3_env.h"

#include "wasm_scan.h"

/* ---- output buffer -------------------------------------------------------- */

typedef struct {
    uint8_t *p;
    size_t   n, cap;
} buf_t;

static void put(buf_t *b, const void *src, size_t n)
{
    if (b->n + n > b->cap) {
        size_t cap = b->cap ? b->cap : 256;
        while (cap < b->n + n)
            cap *= 2;
        b->p = realloc(b->p, cap);
        if (b->p == NULL) {
            fprintf(stderr, "rozaot: out of memory\n");
            exit(1);
        }
        b->cap = cap;
    }
    memcpy(b->p + b->n, src, n);
    b->n += n;
}

static void put8(buf_t *b, uint8_t v)
{
    put(b, &v, 1);
}

static void put_u32(buf_t *b, uint32_t v)
{
    do {
        uint8_t byte = v & 0x7f;
        v >>= 7;
        put8(b, byte | (v ? 0x80 : 0));
    } while (v);
}

static void put_s64(buf_t *b, int64_t v)
{
    for (;;) {
        uint8_t byte = v & 0x7f;
        v >>= 7; /* arithmetic on every compiler roz builds with */
        if ((v == 0 && !(byte & 0x40)) || (v == -1 && (byte & 0x40))) {
            put8(b, byte);
            return;
        }
        put8(b, byte | 0x80);
    }
}

static void put_name(buf_t *b, const char *s)
{
    put_u32(b, (uint32_t)strlen(s));
    put(b, s, strlen(s));
}

static void put_section(buf_t *out, uint8_t id, const buf_t *body)
{
    put8(out, id);
    put_u32(out, (uint32_t)body->n);
    put(out, body->p, body->n);
}

/* ---- input cursor (the module was validated: a bad read is a bug) --------- */

typedef struct {
    const uint8_t *p, *end;
} cur_t;

static void die(const char *what)
{
    fprintf(stderr, "rozaot: %s\n", what);
    exit(1);
}

static uint8_t rd8(cur_t *c)
{
    if (c->p >= c->end)
        die("unexpected end of module");
    return *c->p++;
}

static uint32_t rd_u32(cur_t *c)
{
    uint32_t v = 0;
    for (int s = 0;; s += 7) {
        uint8_t b = rd8(c);
        v |= (uint32_t)(b & 0x7f) << s;
        if (!(b & 0x80))
            return v;
    }
}

static void skip_leb(cur_t *c)
{
    while (rd8(c) & 0x80) {
    }
}

static void skip_n(cur_t *c, size_t n)
{
    if ((size_t)(c->end - c->p) < n)
        die("unexpected end of module");
    c->p += n;
}

/* ---- the metering pass ----------------------------------------------------- */

enum { ADDED_IMPORTS = 3 }; /* roz.refuel, roz.fill, roz.copy: function indices n..n+2 */

typedef struct {
    uint32_t n_imports;  /* the module's own function imports */
    uint32_t fuel_global;
    uint32_t refuel, fill, copy; /* function indices of the added imports */
} meter_t;

static uint32_t fix_func(const meter_t *m, uint32_t f)
{
    return f < m->n_imports ? f : f + ADDED_IMPORTS;
}

static void emit_charge(buf_t *b, const meter_t *m, uint64_t units)
{
    put8(b, 0x23); put_u32(b, m->fuel_global); /* global.get */
    put8(b, 0x42); put_s64(b, (int64_t)units); /* i64.const */
    put8(b, 0x7d);                             /* i64.sub */
    put8(b, 0x24); put_u32(b, m->fuel_global); /* global.set */
    put8(b, 0x23); put_u32(b, m->fuel_global);
    put8(b, 0x42); put_s64(b, 0);
    put8(b, 0x53);                             /* i64.lt_s */
    put8(b, 0x04); put8(b, 0x40);              /* if */
    put8(b, 0x10); put_u32(b, m->refuel);      /* call roz.refuel */
    put8(b, 0x0b);                             /* end */
}

/* One instruction: its opcode (0xfc prefixed: 0xfc00 | sub) and where its
 * immediates end. */
static uint32_t read_instr(cur_t *c, uint32_t *imm)
{
    uint32_t op = rd8(c);
    *imm = 0;
    switch (op) {
    case 0x02: case 0x03: case 0x04: (void)rd8(c); break; /* block type: one byte */
    case 0x0c: case 0x0d: case 0x10: case 0x20: case 0x21: case 0x22: case 0x23: case 0x24:
        *imm = rd_u32(c);
        break;
    case 0x0e: {
        uint32_t n = rd_u32(c);
        for (uint32_t k = 0; k <= n; k++)
            (void)rd_u32(c);
        break;
    }
    case 0x11: *imm = rd_u32(c); (void)rd8(c); break;
    case 0x3f: case 0x40: (void)rd8(c); break;
    case 0x41: case 0x42: skip_leb(c); break;
    case 0x43: skip_n(c, 4); break;
    case 0x44: skip_n(c, 8); break;
    case 0xfc: {
        uint32_t sub = rd8(c);
        op = 0xfc00 | sub;
        if (sub == 10) { (void)rd8(c); (void)rd8(c); }
        else if (sub == 11) (void)rd8(c);
        break;
    }
    default:
        if (op >= 0x28 && op <= 0x3e) {
            (void)rd_u32(c);
            (void)rd_u32(c);
        }
        break;
    }
    return op;
}

#define MAX_DEPTH 1024

/* Pass 1 over a body's instructions: the units of the run that opens at
 * each instruction (0: none opens there), as roz_MeterOpcode in
 * cmake/wasm3/02-metering.patch counts them, with wasm3's skipping of dead
 * code (13-dead-code.patch): after br, br_table, return and unreachable,
 * nothing up to the end or else closing the block is compiled or charged. */
static void plan_runs(const uint8_t *code, const uint8_t *end, uint64_t *units_at)
{
    cur_t c = { code, end };
    uint8_t kind[MAX_DEPTH]; /* opcode of each open block; [0] the function's */
    int depth = 0, dead = 0, dead_depth = 0;
    long run = -1; /* offset of the open run's first instruction */
    uint64_t count = 0;

    kind[0] = 0x02;
    while (c.p < c.end) {
        long at = (long)(c.p - code);
        uint32_t imm;
        uint32_t op = read_instr(&c, &imm);

        if (dead) { /* wasm3 reads over it, nested blocks whole */
            if (op == 0x02 || op == 0x03 || op == 0x04) {
                dead_depth++;
                continue;
            }
            if ((op == 0x05 || op == 0x0b) && dead_depth > 0) {
                if (op == 0x0b)
                    dead_depth--;
                continue;
            }
            if (op != 0x05 && op != 0x0b)
                continue;
            dead = 0; /* the block's own end or else: compiled as usual */
        }
        if (run < 0) {
            run = at;
            count = 0;
        }
        count += 1;
        switch (op) {
        case 0x91: case 0x95: case 0x9f: case 0xa3: count += 2; break;
        case 0x03: count += d_m3RozLoopUnits; break;
        case 0x0e: count += 2; break;
        case 0x10: case 0x11: count += d_m3RozCallUnits; break;
        case 0x0c: case 0x0d:
            if ((int)imm <= depth && kind[depth - (int)imm] == 0x03)
                count += 1; /* a back-edge */
            break;
        default:
            if (op >= 0xfc00)
                count += 2;
            break;
        }
        units_at[run] = count;
        /* the block structure */
        if (op == 0x02 || op == 0x03 || op == 0x04) {
            if (++depth >= MAX_DEPTH)
                die("blocks nested too deep");
            kind[depth] = (uint8_t)op;
        } else if (op == 0x05) {
            kind[depth] = 0x05;
        } else if (op == 0x0b) {
            depth--;
        }
        switch (op) {
        case 0x03: case 0x04: case 0x05: case 0x0b: run = -1; break;
        case 0x0c: case 0x0e: case 0x0f: case 0x00:
            run = -1;
            dead = 1;
            dead_depth = 0;
            break;
        default:
            if (count >= d_m3RozMaxRun)
                run = -1;
            break;
        }
        if (op == 0x0d)
            dead = 0; /* br_if falls through */
    }
}

/* Rewrites one function body (its locals and code) into out; n_params: of
 * its type, to place the scratch locals memory.fill and memory.copy need. */
static void meter_body(const meter_t *m, const uint8_t *body, size_t len, uint32_t n_params,
                       uint32_t entry_units, buf_t *out)
{
    cur_t c = { body, body + len };
    uint32_t groups = rd_u32(&c);
    uint32_t n_locals = 0;
    const uint8_t *groups_at = c.p;
    for (uint32_t i = 0; i < groups; i++) {
        n_locals += rd_u32(&c);
        (void)rd8(&c);
    }
    const uint8_t *code = c.p;
    size_t code_len = (size_t)(body + len - code);
    uint64_t *units_at = calloc(code_len + 1, sizeof *units_at);
    if (units_at == NULL)
        die("out of memory");
    plan_runs(code, body + len, units_at);

    int bulk = 0;
    for (cur_t s = { code, body + len }; s.p < s.end;) {
        uint32_t imm, op = read_instr(&s, &imm);
        if (op == 0xfc0a || op == 0xfc0b)
            bulk = 1;
    }
    uint32_t s0 = n_params + n_locals; /* three i32 scratch locals */

    buf_t b = { 0 };
    put_u32(&b, groups + (bulk ? 1u : 0u));
    put(&b, groups_at, (size_t)(code - groups_at));
    if (bulk) {
        put_u32(&b, 3);
        put8(&b, 0x7f);
    }
    /* op_Entry's charge, then the first run's: two charges, as wasm3 */
    if (entry_units != 0)
        emit_charge(&b, m, entry_units);
    while (c.p < c.end) {
        const uint8_t *at = c.p;
        uint32_t imm, op = read_instr(&c, &imm);
        if (units_at[at - code] != 0)
            emit_charge(&b, m, units_at[at - code]);
        if (op == 0x10) {
            put8(&b, 0x10);
            put_u32(&b, fix_func(m, imm));
        } else if (op == 0xfc0a || op == 0xfc0b) {
            /* [d, s|value, n]: the bytes are charged by roz.copy(d, s, n) or
             * roz.fill(d, n) once their bounds hold (as wasm3 charges them
             * after its own check), then the op runs on the same operands */
            for (uint32_t k = 3; k-- > 0;) {
                put8(&b, 0x21);
                put_u32(&b, s0 + k);
            }
            put8(&b, 0x20); put_u32(&b, s0);
            if (op == 0xfc0a) {
                put8(&b, 0x20); put_u32(&b, s0 + 1);
            }
            put8(&b, 0x20); put_u32(&b, s0 + 2);
            put8(&b, 0x10); put_u32(&b, op == 0xfc0a ? m->copy : m->fill);
            for (uint32_t k = 0; k < 3; k++) {
                put8(&b, 0x20);
                put_u32(&b, s0 + k);
            }
            put(&b, at, (size_t)(c.p - at));
        } else {
            put(&b, at, (size_t)(c.p - at));
        }
    }
    free(units_at);
    put_u32(out, (uint32_t)b.n);
    put(out, b.p, b.n);
    free(b.p);
}

/* ---- the module ------------------------------------------------------------ */

typedef struct {
    const uint8_t *body[13]; /* by section id; NULL: absent */
    size_t         len[13];
} sections_t;

/* The item count of the module's vector section @p id; 0 where it has none. */
static uint32_t count_of(const sections_t *s, uint8_t id)
{
    if (!s->body[id])
        return 0;
    cur_t c = { s->body[id], s->body[id] + s->len[id] };
    return rd_u32(&c);
}

/* Puts the items of the module's vector section @p id (its bytes after the
 * count), where it has one. */
static void put_items(buf_t *b, const sections_t *s, uint8_t id)
{
    if (!s->body[id])
        return;
    cur_t c = { s->body[id], s->body[id] + s->len[id] };
    (void)rd_u32(&c);
    put(b, c.p, (size_t)(c.end - c.p));
}

static int read_file(const char *path, uint8_t **data, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return -1;
    buf_t b = { 0 };
    uint8_t chunk[65536];
    size_t n;
    while ((n = fread(chunk, 1, sizeof chunk, f)) > 0)
        put(&b, chunk, n);
    fclose(f);
    *data = b.p;
    *len = b.n;
    return 0;
}

static int write_file(const char *path, const void *data, size_t len)
{
    FILE *f = fopen(path, "wb");
    if (f == NULL)
        return -1;
    size_t w = fwrite(data, 1, len, f);
    return (fclose(f) == 0 && w == len) ? 0 : -1;
}

/* Parameter count of each type. */
static uint32_t *type_params(const sections_t *s, uint32_t *n_types)
{
    cur_t c = { s->body[1], s->body[1] + s->len[1] };
    *n_types = s->body[1] ? rd_u32(&c) : 0;
    uint32_t *p = calloc(*n_types + 1, sizeof *p);
    for (uint32_t i = 0; i < *n_types; i++) {
        (void)rd8(&c); /* 0x60 */
        p[i] = rd_u32(&c);
        skip_n(&c, p[i]);
        uint32_t r = rd_u32(&c);
        skip_n(&c, r);
    }
    return p;
}

static void usage(void)
{
    fprintf(stderr, "usage: rozaot [--limits LIMITS] NAME IN.wasm OUT.wasm OUT_glue.c\n");
    exit(2);
}

/* ---- the target build's limits ---------------------------------------------- */

/* LIMITS: lines "roz_limit KEY VALUE", VALUE a number as the preprocessor
 * left it (parentheses and an integer suffix allowed); other lines (what
 * roz/config.h leaves after preprocessing: blank) are skipped. Every key
 * must be given. */
static void read_limits(const char *path, roz__wasm_limits_t *lim)
{
    static const struct {
        const char *key;
        size_t      at, size;
    } keys[] = {
#define K(k, f) { k, offsetof(roz__wasm_limits_t, f), sizeof(((roz__wasm_limits_t *)0)->f) }
        K("wasm_max_types", types), K("wasm_max_funcs", funcs), K("wasm_max_globals", globals),
        K("wasm_max_locals", locals), K("wasm_max_exports", exports),
        K("wasm_max_table_entries", table_entries), K("wasm_max_block_depth", block_depth),
        K("wasm_max_compile_work", compile_work), K("wasm_max_pages", pages),
        K("wasm_max_module_bytes", module_bytes), K("math_imports", math_imports),
        K("bulk_imports", bulk_imports), K("nn_imports", nn_imports),
#undef K
    };
    enum { N_KEYS = sizeof keys / sizeof keys[0] };
    int seen[N_KEYS] = { 0 };
    char line[512];
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        fprintf(stderr, "rozaot: %s: cannot read the limits\n", path);
        exit(1);
    }
    while (fgets(line, sizeof line, f) != NULL) {
        char key[64], value[256];
        if (sscanf(line, " roz_limit %63s %255[^\n]", key, value) != 2)
            continue;
        char *v = value, *end;
        while (*v == '(' || *v == ' ')
            v++;
        unsigned long long n = strtoull(v, &end, 0);
        while (*end == 'u' || *end == 'U' || *end == 'l' || *end == 'L' || *end == ')' ||
               *end == ' ' || *end == '\r')
            end++;
        if (end == v || *end != '\0' || *v == '-') {
            fprintf(stderr, "rozaot: %s: %s: not a number once preprocessed: %s\n", path, key,
                    value);
            exit(1);
        }
        size_t k = 0;
        while (k < N_KEYS && strcmp(keys[k].key, key) != 0)
            k++;
        if (k == N_KEYS) {
            fprintf(stderr, "rozaot: %s: unknown limit %s\n", path, key);
            exit(1);
        }
        uint8_t *field = (uint8_t *)lim + keys[k].at;
        if (keys[k].size == 1) {
            uint8_t b = n != 0;
            memcpy(field, &b, 1);
        } else if (keys[k].size == 4) {
            uint32_t w = n > UINT32_MAX ? UINT32_MAX : (uint32_t)n;
            memcpy(field, &w, 4);
        } else {
            uint64_t w = n;
            memcpy(field, &w, 8);
        }
        seen[k] = 1;
    }
    fclose(f);
    for (size_t k = 0; k < N_KEYS; k++)
        if (!seen[k]) {
            fprintf(stderr, "rozaot: %s: no limit %s\n", path, keys[k].key);
            exit(1);
        }
}

int main(int argc, char **argv)
{
    static roz__wasm_limits_t target;
    int have_target = 0;
    if (argc == 7 && strcmp(argv[1], "--limits") == 0) {
        read_limits(argv[2], &target);
        have_target = 1;
        argc -= 2;
        argv += 2;
    }
    if (argc != 5)
        usage();
    const char *name = argv[1], *in = argv[2], *out_wasm = argv[3], *out_glue = argv[4];
    uint8_t *wasm;
    size_t len;
    if (read_file(in, &wasm, &len) != 0) {
        fprintf(stderr, "rozaot: %s: cannot read\n", in);
        return 1;
    }

    /* 0. the build it is compiled for: what its own loader would refuse */
    if (have_target) {
        static roz_load_scratch_t scratch;
        char why[ROZ_CFG_ERROR_LEN];
        uint32_t process_index;
        if (len > target.module_bytes) {
            fprintf(stderr,
                    "rozaot: %s: refused for the build it is compiled into: module too large: "
                    "%zu bytes, more than ROZ_CFG_WASM_MAX_MODULE_BYTES (%llu)\n",
                    in, len, (unsigned long long)target.module_bytes);
            return 1;
        }
        if (roz__wasm_scan_for(wasm, len, &scratch, &target, &process_index, why, sizeof why) !=
            ROZ_OK) {
            fprintf(stderr, "rozaot: %s: refused for the build it is compiled into: %s\n", in,
                    why);
            return 1;
        }
    }

    /* 1. the runtime's own load: validator, then wasm3 */
    static roz_controller_t ctl;
    static roz_abi_t abi;
    roz_controller_init(&ctl);
    if (roz_controller_load(&ctl, wasm, len, &abi) != ROZ_OK) {
        fprintf(stderr, "rozaot: %s: refused: %s\n", in, roz_controller_error(&ctl));
        return 1;
    }
    IM3Module mod = ctl.module;
    if (have_target && mod->memoryInfo.initPages > target.pages) {
        fprintf(stderr,
                "rozaot: %s: refused for the build it is compiled into: linear memory too "
                "large: %u pages of 64 KiB, more than ROZ_CFG_WASM_MAX_PAGES (%u)\n",
                in, (unsigned)mod->memoryInfo.initPages, (unsigned)target.pages);
        return 1;
    }
    uint32_t n_imports = mod->numFuncImports;
    uint32_t n_funcs = mod->numFunctions;

    /* the sections */
    sections_t s = { 0 };
    buf_t custom = { 0 }; /* the roz.* custom sections, as a module of their own */
    put(&custom, "\0asm\1\0\0\0", 8);
    cur_t c = { wasm + 8, wasm + len };
    while (c.p < c.end) {
        uint8_t id = rd8(&c);
        uint32_t size = rd_u32(&c);
        const uint8_t *body = c.p;
        skip_n(&c, size);
        if (id == 0) {
            cur_t nc = { body, body + size };
            uint32_t nl = rd_u32(&nc);
            if (nl >= 4 && (size_t)(nc.end - nc.p) >= nl && memcmp(nc.p, "roz.", 4) == 0) {
                put8(&custom, 0);
                put_u32(&custom, size);
                put(&custom, body, size);
            }
        } else if (id < 13) {
            s.body[id] = body;
            s.len[id] = size;
        }
    }
    uint32_t n_types;
    uint32_t *params = type_params(&s, &n_types);

    meter_t m = { 0 };
    m.n_imports = n_imports;
    m.refuel = n_imports;
    m.fill = n_imports + 1;
    m.copy = n_imports + 2;
    uint32_t n_globals = count_of(&s, 6);
    m.fuel_global = n_globals; /* roz imports no globals */

    buf_t o = { 0 }, sec = { 0 };
    put(&o, "\0asm\1\0\0\0", 8);
    /* 1 types: the module's, then () -> (), (i32 i32) -> (), (i32 i32 i32) -> () */
    sec.n = 0;
    put_u32(&sec, n_types + 3);
    put_items(&sec, &s, 1);
    static const uint8_t added_types[] = { 0x60, 0, 0, 0x60, 2, 0x7f, 0x7f, 0,
                                            0x60, 3, 0x7f, 0x7f, 0x7f, 0 };
    put(&sec, added_types, sizeof added_types);
    put_section(&o, 1, &sec);
    /* 2 imports: the module's, then roz's */
    sec.n = 0;
    {
        put_u32(&sec, count_of(&s, 2) + 3);
        put_items(&sec, &s, 2);
        const char *hooks[3] = { "refuel", "fill", "copy" };
        for (uint32_t k = 0; k < 3; k++) {
            put_name(&sec, "roz");
            put_name(&sec, hooks[k]);
            put8(&sec, 0x00);
            put_u32(&sec, n_types + k);
        }
    }
    put_section(&o, 2, &sec);
    for (uint8_t id = 3; id <= 5; id++) /* functions, table, memory */
        if (s.body[id]) {
            sec.n = 0;
            put(&sec, s.body[id], s.len[id]);
            put_section(&o, id, &sec);
        }
    /* 6 globals: the module's, then the fuel (mutable i64, 0) */
    sec.n = 0;
    put_u32(&sec, n_globals + 1);
    put_items(&sec, &s, 6);
    put8(&sec, 0x7e); put8(&sec, 1); put8(&sec, 0x42); put8(&sec, 0); put8(&sec, 0x0b);
    put_section(&o, 6, &sec);
    /* 7 exports: the module's (function indices shifted), the fuel, memory 0 */
    sec.n = 0;
    {
        uint32_t n = 0;
        cur_t e = { s.body[7], s.body[7] ? s.body[7] + s.len[7] : NULL };
        if (s.body[7])
            n = rd_u32(&e);
        put_u32(&sec, n + 1 + (s.body[5] ? 1u : 0u));
        for (uint32_t i = 0; i < n; i++) {
            uint32_t nl = rd_u32(&e);
            put_u32(&sec, nl);
            put(&sec, e.p, nl);
            skip_n(&e, nl);
            uint8_t kind = rd8(&e);
            uint32_t idx = rd_u32(&e);
            put8(&sec, kind);
            put_u32(&sec, kind == 0 ? fix_func(&m, idx) : idx);
        }
        put_name(&sec, "rozfuel");
        put8(&sec, 0x03);
        put_u32(&sec, m.fuel_global);
        if (s.body[5]) {
            put_name(&sec, "rozmemory");
            put8(&sec, 0x02);
            put_u32(&sec, 0);
        }
    }
    put_section(&o, 7, &sec);
    /* 9 elements: the MVP form only (roz's validator), indices shifted */
    if (s.body[9]) {
        sec.n = 0;
        cur_t e = { s.body[9], s.body[9] + s.len[9] };
        uint32_t n = rd_u32(&e);
        put_u32(&sec, n);
        for (uint32_t i = 0; i < n; i++) {
            const uint8_t *head = e.p;
            (void)rd_u32(&e); /* flags 0 */
            for (uint8_t op = rd8(&e); op != 0x0b; op = rd8(&e))
                skip_leb(&e); /* i32.const offset */
            put(&sec, head, (size_t)(e.p - head));
            uint32_t k = rd_u32(&e);
            put_u32(&sec, k);
            for (uint32_t j = 0; j < k; j++)
                put_u32(&sec, fix_func(&m, rd_u32(&e)));
        }
        put_section(&o, 9, &sec);
    }
    if (s.body[12]) { /* data count */
        sec.n = 0;
        put(&sec, s.body[12], s.len[12]);
        put_section(&o, 12, &sec);
    }
    /* 10 code */
    if (s.body[10]) {
        sec.n = 0;
        cur_t f = { s.body[3], s.body[3] + s.len[3] };
        cur_t k = { s.body[10], s.body[10] + s.len[10] };
        uint32_t n = rd_u32(&k);
        (void)rd_u32(&f);
        put_u32(&sec, n);
        for (uint32_t i = 0; i < n; i++) {
            uint32_t type = rd_u32(&f);
            uint32_t size = rd_u32(&k);
            const uint8_t *body = k.p;
            skip_n(&k, size);
            if (n_imports + i >= n_funcs || type >= n_types)
                die("the module and wasm3 disagree on its functions");
            uint32_t entry = mod->functions[n_imports + i].rozEntryUnits;
            meter_body(&m, body, size, params[type], entry, &sec);
        }
        put_section(&o, 10, &sec);
    }
    if (s.body[11]) {
        sec.n = 0;
        put(&sec, s.body[11], s.len[11]);
        put_section(&o, 11, &sec);
    }
    if (write_file(out_wasm, o.p, o.n) != 0) {
        fprintf(stderr, "rozaot: %s: cannot write\n", out_wasm);
        return 1;
    }

    /* 3. the glue */
    uint32_t pages = 0, table = 0;
    if (s.body[5]) {
        cur_t mm = { s.body[5], s.body[5] + s.len[5] };
        (void)rd_u32(&mm);
        (void)rd8(&mm);
        pages = rd_u32(&mm);
    }
    if (s.body[4]) {
        cur_t t = { s.body[4], s.body[4] + s.len[4] };
        (void)rd_u32(&t);
        (void)rd8(&t);
        (void)rd8(&t);
        table = rd_u32(&t);
    }
    /* the import modules wasm2c passes an instance for: every distinct one */
    uint32_t n_modules = 1; /* roz */
    {
        const char *seen[32];
        uint32_t n_seen = 0;
        for (uint32_t i = 0; i < n_imports; i++) {
            const char *mn = mod->functions[i].import.moduleUtf8;
            int dup = 0;
            for (uint32_t j = 0; j < n_seen; j++)
                dup |= strcmp(seen[j], mn) == 0;
            if (!dup && n_seen < 32)
                seen[n_seen++] = mn;
        }
        n_modules += n_seen;
    }
    FILE *g = fopen(out_glue, "w");
    if (g == NULL) {
        fprintf(stderr, "rozaot: %s: cannot write\n", out_glue);
        return 1;
    }
    fprintf(g, "/* Generated by rozaot from %s: DO NOT EDIT. */\n", name);
    fprintf(g, "#include \"roz/aot.h\"\n#include \"%s_aot.h\"\n\n", name);
    fprintf(g, "#define PAGES %uu\n#define TABLE %uu\n\n", pages, table);
    fprintf(g, "static Z_%s_instance_t instances[ROZ_CFG_AOT_INSTANCES];\n", name);
    if (pages)
        fprintf(g, "static _Alignas(16) uint8_t memory[ROZ_CFG_AOT_INSTANCES][PAGES * 65536u];\n");
    if (table)
        fprintf(g, "static wasm_rt_funcref_t table[ROZ_CFG_AOT_INSTANCES][TABLE];\n");
    fprintf(g, "static unsigned char in_use[ROZ_CFG_AOT_INSTANCES];\n\n");
    fprintf(g, "static void init_module(void)\n{\n    Z_%s_init_module();\n}\n\n", name);
    fprintf(g, "static void instantiate(unsigned i, void *ctx)\n{\n    Z_%s_instantiate(&instances[i]", name);
    for (uint32_t i = 0; i < n_modules; i++)
        fprintf(g, ", ctx");
    fprintf(g, ");\n}\n\n");
    fprintf(g, "static void release(unsigned i)\n{\n    Z_%s_free(&instances[i]);\n}\n\n", name);
    fprintf(g, "static void process(unsigned i, int64_t tick)\n{\n    Z_%sZ_process(&instances[i], (u64)tick);\n}\n\n", name);
    fprintf(g, "static int64_t *fuel(unsigned i)\n{\n    return (int64_t *)Z_%sZ_rozfuel(&instances[i]);\n}\n\n", name);
    fprintf(g, "static void *mem(unsigned i)\n{\n");
    if (pages)
        fprintf(g, "    return Z_%sZ_rozmemory(&instances[i]);\n}\n\n", name);
    else
        fprintf(g, "    (void)i;\n    return NULL;\n}\n\n");
    fprintf(g, "static const uint8_t sections[] = {");
    for (size_t i = 0; i < custom.n; i++)
        fprintf(g, "%s0x%02x,", i % 12 == 0 ? "\n    " : " ", custom.p[i]);
    fprintf(g, "\n};\n\n");
    fprintf(g, "const roz_aot_module_t roz_aot_%s = {\n", name);
    fprintf(g, "    \"%s\", 0x%016llxull, sections, sizeof sections, ROZ_CFG_AOT_INSTANCES, in_use,\n",
            name, (unsigned long long)roz_recorder_hash(wasm, len));
    fprintf(g, "    %s, %s, TABLE, %s,\n", pages ? "memory[0]" : "NULL", pages ? "PAGES" : "0",
            table ? "table[0]" : "NULL");
    fprintf(g, "    init_module, instantiate, release, process, fuel, mem, roz_controller_load_aot,\n};\n");
    int rc = fclose(g) != 0;
    roz_controller_unload(&ctl);
    free(o.p);
    free(sec.p);
    free(custom.p);
    free(params);
    free(wasm);
    return rc;
}
