/* SPDX-License-Identifier: Apache-2.0 */
/* roz_wasm_run: the wasm3 side of the differential test (test/diff/,
 * fuzz/diff/). It reads one module, runs roz's validator on it (the scan
 * roz_controller_load() runs first), loads it into roz's patched wasm3 the
 * way lib/src/controller.c does (same value stack size, every roz ABI import
 * linked), but with every import stubbed to return zero, as
 * `wasm-interp --dummy-import-func` does. Then it calls every exported
 * function that takes no parameters, in the order of the export section
 * (as `wasm-interp --run-all-exports` does) on one instance, and prints one
 * line per call in wasm-interp's format:
 *
 *   name() => i32:4294967289      (unsigned decimal, as wasm-interp prints)
 *   name() => i64:18446744073709551609
 *   name() => f32:0x7fc00000      (bits; the driver compares floats by bits)
 *   name() => f64:0x3ff8000000000000
 *   name() =>                     (no result)
 *   name() => error: [trap] integer divide by zero
 *
 * Like roz, roz's metering hooks (cmake/wasm3/02-metering.patch; defined
 * here, as lib/src/controller.c is not linked) bound the work of each call
 * (fuel) and the C stack depth, so a module that loops or recurses too deep
 * stops with a trap instead of hanging or crashing this process.
 *
 * Exit status: 0 ran, 2 refused by roz's validator (message on stdout as
 * "roz-refused: ..."), 3 refused by wasm3 (parse, load, link or compile),
 * 1 usage or I/O error. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "roz/abi.h"
#include "roz/config.h"
#include "roz/error.h"
#include "m3_env.h"
#include "wasm3.h"
#include "wasm_scan.h"

#define FUEL_PER_CALL 200000000u /* fuel units (about instructions) per export */
#define SLICE 65536              /* units between two calls of the refuel hook */

static uint64_t units;
static uintptr_t stack_base;

static const char fuel_trap[] = "[trap] fuel exhausted";
static const char stack_trap[] = "[trap] native stack limit";

/* roz's metering hooks, as lib/src/controller.c defines them (without a
 * deadline): fuel in slices, the C stack at every function and loop entry. */
M3Result roz__wasm3_refuel(IM3Runtime rt);
M3Result roz__wasm3_stack(IM3Runtime rt, void *here);

M3Result roz__wasm3_refuel(IM3Runtime rt)
{
    units += SLICE + (uint64_t)(-rt->rozFuel);
    rt->rozFuel = units > FUEL_PER_CALL ? 0 : SLICE;
    return units > FUEL_PER_CALL ? fuel_trap : m3Err_none;
}

M3Result roz__wasm3_stack(IM3Runtime rt, void *here)
{
    rt->rozStackLow = here;
    return stack_base - (uintptr_t)here > ROZ_CFG_NATIVE_STACK_BYTES ? stack_trap : m3Err_none;
}

/* Every import returns the zero of its result type (or nothing). */
static m3ApiRawFunction(stub)
{
    const char *sig = roz_abi_imports[(uintptr_t)_ctx->userdata].signature;
    (void)runtime;
    (void)_mem;
    if (sig[0] != 'v')
        _sp[0] = 0;
    m3ApiSuccess();
}

static uint8_t *read_file(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    uint8_t *buf = NULL;
    size_t cap = 0, n = 0;
    if (f == NULL)
        return NULL;
    for (;;) {
        if (n == cap) {
            uint8_t *nb = realloc(buf, cap ? cap * 2 : 65536);
            if (nb == NULL) {
                free(buf);
                fclose(f);
                return NULL;
            }
            buf = nb;
            cap = cap ? cap * 2 : 65536;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0)
            break;
    }
    fclose(f);
    *len = n;
    return buf;
}

/* A LEB128 u32 reader for the export section (the module passed roz's
 * validator, so it is well formed). */
static uint32_t leb(const uint8_t **p)
{
    uint32_t v = 0;
    for (int shift = 0; shift < 35; shift += 7) {
        uint8_t b = *(*p)++;
        v |= (uint32_t)(b & 0x7f) << shift;
        if ((b & 0x80) == 0)
            break;
    }
    return v;
}

static void call_export(IM3Runtime rt, const char *name)
{
    IM3Function fn = NULL;
    if (m3_FindFunction(&fn, rt, name) != m3Err_none || fn == NULL) {
        printf("%s() => error: roz_wasm_run: not found\n", name);
        return;
    }
    if (m3_GetArgCount(fn) != 0)
        return; /* wasm-interp --run-all-exports skips these too */
    units = 0;
    stack_base = (uintptr_t)__builtin_frame_address(0);
    rt->rozFuel = SLICE;
    rt->rozStackLow = (void *)stack_base;
    M3Result r = m3_Call(fn, 0, NULL);
    if (r != m3Err_none) {
        printf("%s() => error: %s\n", name, r);
        return;
    }
    if (m3_GetRetCount(fn) == 0) {
        printf("%s() =>\n", name);
        return;
    }
    uint64_t raw = 0;
    const void *ptrs[1] = { &raw };
    if (m3_GetResults(fn, 1, ptrs) != m3Err_none) {
        printf("%s() => error: roz_wasm_run: no result\n", name);
        return;
    }
    switch (m3_GetRetType(fn, 0)) {
    case c_m3Type_i32: printf("%s() => i32:%" PRIu32 "\n", name, (uint32_t)raw); break;
    case c_m3Type_i64: printf("%s() => i64:%" PRIu64 "\n", name, raw); break;
    case c_m3Type_f32: printf("%s() => f32:0x%08" PRIx32 "\n", name, (uint32_t)raw); break;
    case c_m3Type_f64: printf("%s() => f64:0x%016" PRIx64 "\n", name, raw); break;
    default: printf("%s() => error: roz_wasm_run: unknown result type\n", name); break;
    }
}

int main(int argc, char **argv)
{
    size_t len = 0;
    char err[256];
    int rc = 0;

    setvbuf(stdout, NULL, _IOLBF, 0); /* every line out before a crash */
    if (argc != 2) {
        fprintf(stderr, "usage: %s module.wasm\n", argv[0]);
        return 1;
    }
    uint8_t *wasm = read_file(argv[1], &len);
    if (wasm == NULL) {
        fprintf(stderr, "%s: cannot read %s\n", argv[0], argv[1]);
        return 1;
    }
    uint32_t process_index;
    static roz_load_scratch_t scratch;
    if (roz__wasm_scan(wasm, len, &scratch, &process_index, err, sizeof err) != ROZ_OK) {
        printf("roz-refused: %s\n", err);
        free(wasm);
        return 2;
    }

    IM3Environment env = m3_NewEnvironment();
    IM3Runtime rt = env ? m3_NewRuntime(env, ROZ_CFG_WASM_STACK_BYTES, NULL) : NULL;
    IM3Module mod = NULL;
    M3Result r = rt ? m3_ParseModule(env, &mod, wasm, (uint32_t)len) : "out of memory";
    if (r == m3Err_none) {
        r = m3_LoadModule(rt, mod);
        if (r != m3Err_none)
            m3_FreeModule(mod);
    }
    for (size_t i = 0; r == m3Err_none && i < roz_abi_import_count; i++) {
        const roz_abi_import_t *imp = &roz_abi_imports[i];
        r = m3_LinkRawFunctionEx(mod, imp->module, imp->name, imp->signature, stub,
                                 (void *)(uintptr_t)i);
        if (r == m3Err_functionLookupFailed)
            r = m3Err_none;
    }
    if (r == m3Err_none)
        r = m3_CompileModule(mod);
    if (r != m3Err_none) {
        printf("wasm3-refused: %s\n", r);
        rc = 3;
    }

    /* the exports, in section order */
    const uint8_t *p = wasm + 8, *end = wasm + len;
    while (rc == 0 && p < end) {
        uint8_t id = *p++;
        uint32_t size = leb(&p);
        const uint8_t *next = p + size;
        if (id == 7) {
            uint32_t n = leb(&p);
            for (uint32_t i = 0; i < n; i++) {
                uint32_t nl = leb(&p);
                char name[256];
                size_t k = nl < sizeof name - 1 ? nl : sizeof name - 1;
                memcpy(name, p, k);
                name[k] = '\0';
                p += nl;
                uint8_t kind = *p++;
                (void)leb(&p);
                if (kind == 0)
                    call_export(rt, name);
            }
        }
        p = next;
    }
    fflush(stdout);
    if (rt != NULL)
        m3_FreeRuntime(rt);
    if (env != NULL)
        m3_FreeEnvironment(env);
    free(wasm);
    return rc;
}
