/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/aot.h
 * @brief Ahead-of-time controllers: a module compiled into the image at
 *        build time (roz_add_aot_controller(), docs/controllers.md), run
 *        behind the same roz_controller_t as a module wasm3 loads.
 *
 * The build checked the module with roz's validator, inserted the fuel
 * metering wasm3 charges (the same units, tick for tick) and compiled it
 * with wasm2c; the same imports (roz/abi.h), the same budget and the same
 * trap texts apply. Each compiled controller has static storage for
 * ROZ_CFG_AOT_INSTANCES instances; an image may hold several and swap
 * between them (roz_runtime_load_aot()). Library: roz::aot.
 */
#ifndef ROZ_AOT_H
#define ROZ_AOT_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/controller.h"

#ifdef __cplusplus
extern "C" {
#endif

/** One compiled controller: written by the build (rozaot's glue), read by
 *  roz. Declare it with ROZ_AOT_DECLARE(name). */
typedef struct roz_aot_module {
    const char    *name;         /**< the name it was built under */
    uint64_t       hash;         /**< roz_recorder_hash() of the module it was compiled from */
    const uint8_t *sections;     /**< its roz.* custom sections (identity, declared fuel),
                                      as a module of their own (roz/identity.h reads them) */
    size_t         sections_len;
    unsigned       instances;    /**< instances that may exist at once */
    unsigned char *in_use;       /**< [instances]: roz's */
    uint8_t       *memory;       /**< instances * pages * 64 KiB, NULL without a memory */
    uint32_t       pages;
    uint32_t       table;        /**< table entries per instance */
    void          *tables;       /**< instances * table entries */
    void (*init_module)(void);
    void (*instantiate)(unsigned i, void *ctx);
    void (*release)(unsigned i);
    void (*process)(unsigned i, int64_t tick);
    int64_t *(*fuel)(unsigned i);
    void *(*memory_of)(unsigned i); /**< the engine's memory object, NULL without one */
    /** roz_controller_load_aot(): through the module, so that roz::core
     *  (roz_runtime_load_aot()) needs no link to roz::aot */
    int (*load)(roz_controller_t *c, const struct roz_aot_module *m, roz_abi_t *abi);
} roz_aot_module_t;

/** Declares the module roz_add_aot_controller(NAME ...) built. */
#define ROZ_AOT_DECLARE(name) extern const roz_aot_module_t roz_aot_##name

/**
 * @brief Start an instance of a compiled controller; the imports will run
 *        on @p abi. As roz_controller_load() for a module wasm3 loads: the
 *        instance starts fresh (its data segments), with no budget.
 * @retval ROZ_OK     loaded
 * @retval ROZ_ENOMEM every instance of @p m is in use
 * @retval ROZ_EINVAL more function types than ROZ_CFG_AOT_MAX_TYPES, or no
 *                    @p abi; roz_controller_error() says which
 * @retval ROZ_ESTATE already loaded
 * Context: outside the tick; one load or unload of a compiled controller at
 * a time in the whole image (the engine's start-up state is shared).
 */
ROZ_NODISCARD int roz_controller_load_aot(roz_controller_t *c, const roz_aot_module_t *m,
                                          roz_abi_t *abi);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_AOT_H */
