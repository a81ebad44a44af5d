/* SPDX-License-Identifier: Apache-2.0 */
/* Private: a small, bounded reader of a wasm module's type, import, function,
 * export and start sections, used to refuse a controller with a clear message
 * before any engine parses it. Engine-neutral. */
#ifndef ROZ_WASM_SCAN_H
#define ROZ_WASM_SCAN_H

#include <stddef.h>
#include <stdint.h>

#include "roz/controller.h"

/* Checks that the module imports only functions of the roz ABI with their
 * exact signatures (names compared byte for byte), exports process(i64)
 * once, under export names that are unique, valid UTF-8 and free of NUL
 * bytes, has no start function, and has at most one table of at most
 * ROZ_CFG_WASM_MAX_TABLE_ENTRIES entries that every element segment fits,
 * and at most one well-formed "roz.manifest" section (roz/identity.h).
 * On ROZ_OK, *process_index is the function index of the export "process"
 * (a function defined in the module, never an import): the one to call.
 * The validator works in *scratch (roz_load_scratch_t, the caller's).
 * Returns ROZ_OK, or ROZ_EINVAL with a message in err. */
int roz__wasm_scan(const uint8_t *wasm, size_t len, roz_load_scratch_t *scratch,
                   uint32_t *process_index, char *err, size_t errlen);

/* The limits a module is checked against (roz/config.h's ROZ_CFG_WASM_MAX_*
 * and the optional imports): this build's, or another build's for a tool
 * that checks a module for it (rozaot, for the firmware an ahead-of-time
 * controller is compiled into). pages and module_bytes are the loader's
 * (roz_controller_load_in), not the scan's. */
typedef struct {
    uint32_t types, funcs, globals, locals, exports, table_entries, block_depth;
    uint64_t compile_work;
    uint32_t pages;
    uint64_t module_bytes;
    uint8_t  math_imports, bulk_imports, nn_imports;
} roz__wasm_limits_t;

/* This build's limits. */
void roz__wasm_limits_of_build(roz__wasm_limits_t *lim);

/* As roz__wasm_scan(), against @p lim (NULL: this build's); a limit above
 * this build's is this build's (the scan's storage is sized by it). */
int roz__wasm_scan_for(const uint8_t *wasm, size_t len, roz_load_scratch_t *scratch,
                       const roz__wasm_limits_t *lim, uint32_t *process_index, char *err,
                       size_t errlen);

#endif /* ROZ_WASM_SCAN_H */
