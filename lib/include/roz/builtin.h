/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/builtin.h
 * @brief Registry of the built-in manifests (the robot.toml files in
 *        manifests/), by id.
 *
 * Provided by the roz::manifests target, whose tables rozgen generates at
 * build time. Firmware that needs one robot links its own generated table
 * (roz_generate() in CMake) and can leave this target out.
 */
#ifndef ROZ_BUILTIN_H
#define ROZ_BUILTIN_H

#include "roz/config.h"

#include <stddef.h>

#include "roz/manifest.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief The built-in manifest with id @p robot_id ("ur5", "unitree_g1", ...).
 * @return the manifest, or NULL when there is none of that id (or NULL id).
 * Context: any; linear in the number of built-ins.
 */
const roz_manifest_t *roz_builtin_find(const char *robot_id);

/** @brief Number of built-in manifests. Context: any. */
size_t roz_builtin_count(void);

/**
 * @brief Built-in manifest number @p i, in id order.
 * @return the manifest, or NULL when i >= roz_builtin_count().
 * Context: any.
 */
const roz_manifest_t *roz_builtin_at(size_t i);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_BUILTIN_H */
