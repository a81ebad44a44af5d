/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/identity.h
 * @brief Which robot a controller was built for: a manifest's identity, and
 *        the record a controller carries in its "roz.manifest" custom section.
 *
 * A manifest's identity is its robot_id and its interface hash (FNV-1a 64
 * over a canonical byte string of the channel table, defined in
 * codegen/README.md, "Manifest identity"). docs/architecture.md ("A
 * controller and its robot") says what is hashed and what is not, and how
 * roz_runtime_load() compares it; it guards against accidents, it is not
 * authentication.
 */
#ifndef ROZ_IDENTITY_H
#define ROZ_IDENTITY_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/error.h"
#include "roz/manifest.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Name of the custom section that carries a controller's identity. */
#define ROZ_IDENTITY_SECTION "roz.manifest"
/** The version of the record this roz reads (and rozgen writes). */
#define ROZ_IDENTITY_VERSION 1u
/** Longest robot_id in a record, bytes (rozgen's limit). */
#define ROZ_IDENTITY_MAX_ID 32u

/** The identity a module carries. */
typedef struct roz_identity {
    int      present;                          /**< 1: the module has a roz.manifest section */
    char     robot_id[ROZ_IDENTITY_MAX_ID + 1]; /**< NUL-terminated; "" when absent */
    uint64_t hash;                             /**< interface hash; 0 when absent */
} roz_identity_t;

/** A module's identity against a manifest. */
typedef enum roz_identity_match {
    ROZ_IDENTITY_NONE = 0,      /**< the module carries no identity (WAT, other toolchains) */
    ROZ_IDENTITY_SAME,          /**< built for this robot_id and this channel table */
    ROZ_IDENTITY_OTHER_ROBOT,   /**< built for another robot_id */
    ROZ_IDENTITY_TABLE_CHANGED, /**< built for this robot_id, but another channel table */
} roz_identity_match_t;

/**
 * @brief The interface hash of a manifest in memory (generated tables,
 *        roz/manifest_toml.h, or built by hand): equal to rozgen's
 *        ROZ_<ID>_INTERFACE_HASH for the same robot.toml.
 * @return the hash; that of an empty table for a NULL manifest
 * Context: any; no heap; linear in the channels and the lengths of their
 *          names and units: at start-up or load, not per tick.
 */
uint64_t roz_manifest_interface_hash(const roz_manifest_t *m);

/**
 * @brief Read the identity of a WebAssembly module: its custom section
 *        "roz.manifest", if any. Nothing else of the module is checked.
 * @param[in]  wasm, len  the module
 * @param[out] id         the identity; id->present 0 when there is none
 * @param[out] err        on ROZ_EINVAL, why (names the section and its
 *                        offset); may be NULL
 * @retval ROZ_OK     read (present or not)
 * @retval ROZ_EINVAL not a WebAssembly 1.0 module, a section runs past the
 *                    end, two roz.manifest sections, or a malformed record
 *                    (empty, unknown version, cut short, a robot_id that is
 *                    not [a-z][a-z0-9_]* of 1..32 bytes, or two different
 *                    records: the controller was built for two robots)
 * Context: any; no heap; linear in the number of sections and the record.
 */
ROZ_NODISCARD int roz_identity_read(const uint8_t *wasm, size_t len, roz_identity_t *id,
                                    char *err, size_t errlen);

/**
 * @brief Compare an identity with a manifest.
 * @param[out] msg  for OTHER_ROBOT and TABLE_CHANGED, a message naming both
 *                  robots and hashes; "" otherwise; may be NULL
 * @return how they compare
 * Context: any; no heap.
 */
roz_identity_match_t roz_identity_check(const roz_identity_t *id, const roz_manifest_t *m,
                                        char *msg, size_t len);

/** Name of the custom section in which a controller declares the fuel it
 *  needs per tick (roz_controller.h, ROZ_FUEL_PER_TICK). */
#define ROZ_FUEL_SECTION "roz.fuel"
/** The version of its record: u8 version, u64 fuel units little-endian. */
#define ROZ_FUEL_VERSION 1u

/**
 * @brief Read the fuel a module declares it needs per tick: its custom
 *        section "roz.fuel", one or more copies of one record.
 * @param[out] fuel  the units declared; 0 when the module declares none
 * @param[out] err   on ROZ_EINVAL, why (names the section); may be NULL
 * @retval ROZ_OK     read (declared or not)
 * @retval ROZ_EINVAL not a WebAssembly 1.0 module, a section runs past the
 *                    end, two such sections, or a malformed record (empty,
 *                    unknown version, cut short, 0 units, or two different
 *                    declarations)
 * Context: any; no heap; linear in the number of sections.
 */
ROZ_NODISCARD int roz_identity_read_fuel(const uint8_t *wasm, size_t len, uint64_t *fuel,
                                         char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_IDENTITY_H */
