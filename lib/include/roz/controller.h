/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/controller.h
 * @brief One instance of a WebAssembly controller: load, link, call process().
 *
 * The engine is wasm3 (linked PRIVATE; no wasm3 type appears here). Before
 * the engine sees a module, roz checks it itself: size, magic, that every
 * import is a function of the roz ABI with its exact signature
 * (roz/abi.h), that process(i64) is exported, and that there is no start
 * function. Every function is compiled at load, so calling process() never
 * compiles or allocates; linear memory is fixed at its declared initial size
 * (at most ROZ_CFG_WASM_MAX_PAGES) and memory.grow returns -1.
 *
 * Load and unload allocate (wasm3's heap, or its fixed heap on firmware):
 * do them outside the tick. The module bytes must outlive the instance
 * (wasm3 keeps pointers into them).
 */
#ifndef ROZ_CONTROLLER_H
#define ROZ_CONTROLLER_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/abi.h"
#include "roz/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A controller instance. Fields are private to controller.c. */
typedef struct roz_controller {
    void      *env;       /* engine handles, NULL when not loaded */
    void      *runtime;
    void      *module;
    void      *process;
    roz_abi_t *abi;       /* the context the imports run on */
    uint64_t   calls;     /* process() calls since load */
    char       error[ROZ_CFG_ERROR_LEN]; /* last load or trap message */
} roz_controller_t;

/** @brief Zero an instance (not loaded). Context: any; no I/O. */
void roz_controller_init(roz_controller_t *c);

/**
 * @brief Check, load, link and compile a module; the imports will run on @p abi.
 * @param[in] wasm  the module bytes; must outlive the instance
 * @param[in] len   their length, at most ROZ_CFG_WASM_MAX_MODULE_BYTES
 * @param[in] abi   the context; must outlive the instance
 * @retval ROZ_OK     loaded
 * @retval ROZ_EINVAL refused; roz_controller_error() names the import,
 *                    export or problem
 * @retval ROZ_ENOSPC the engine could not allocate
 * @retval ROZ_ESTATE already loaded
 * Context: outside the tick; allocates.
 */
ROZ_NODISCARD int roz_controller_load(roz_controller_t *c, const uint8_t *wasm, size_t len,
                                      roz_abi_t *abi);

/**
 * @brief Call process(tick) once.
 * @retval ROZ_OK     returned normally
 * @retval ROZ_EFAULT the controller trapped; roz_controller_error() says why
 * @retval ROZ_ESTATE not loaded
 * Context: the tick; RT-safe (no allocation, no compilation).
 */
ROZ_NODISCARD int roz_controller_process(roz_controller_t *c, int64_t tick);

/** @brief Free the instance; idempotent. Context: outside the tick. */
void roz_controller_unload(roz_controller_t *c);

/** @brief 1 if loaded. */
int roz_controller_loaded(const roz_controller_t *c);

/** @brief The last load or trap message ("" if none). */
const char *roz_controller_error(const roz_controller_t *c);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_CONTROLLER_H */
