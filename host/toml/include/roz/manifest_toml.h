/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/manifest_toml.h
 * @brief Read a robot.toml into a roz_manifest_storage_t, checked by the
 *        robot.toml rules (their one implementation; rozgen runs them
 *        through roz_manifest_json) (host builds).
 *
 * Part of roz::toml (CMake option ROZ_TOML); firmware keeps using the
 * tables rozgen generates. docs/robot-toml.md ("The loader") says how
 * problems are reported, which limits of the build are problems with the
 * rule id "storage", and what both rozgen and this loader refuse.
 */
#ifndef ROZ_MANIFEST_TOML_H
#define ROZ_MANIFEST_TOML_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/error.h"
#include "roz/manifest.h"
#include "roz/toml.h"

#ifdef __cplusplus
extern "C" {
#endif

/** One problem in a robot.toml. */
typedef struct roz_manifest_toml_problem {
    const char *rule; /**< rule id: "limits-order", "toml-syntax", ..., or "storage" */
    char text[ROZ_CFG_PROBLEM_LEN]; /**< the line after the file name, e.g.
                                         ": manifest: control_rate_hz 0: must be in 1..100000" */
    uint32_t order[4]; /**< sort key of rozgen's order; not API */
} roz_manifest_toml_problem_t;

/**
 * @brief Parse and check a robot.toml and build its manifest in @p storage.
 * @param[out] storage      on ROZ_OK, &storage->manifest is the manifest; its
 *                          strings are interned in storage->arena, its
 *                          [hardware] in storage->hardware/joints/params
 * @param[in,out] doc       TOML storage (roz_toml_init()); the text is parsed
 *                          into it and it can be dropped after the call
 * @param[in]  text         the file's bytes, @p len of them
 * @param[out] problems     optional: room for @p max_problems problems; gets
 *                          the first ones in rozgen's order
 * @param[out] n_found      optional: how many problems were found (may be
 *                          more than @p max_problems)
 * @retval ROZ_OK      valid; the manifest is built
 * @retval ROZ_EINVAL  invalid TOML, UTF-8 or manifest (see the problems), or
 *                     NULL storage/doc
 * @retval ROZ_ENOTSUP valid TOML this reader refuses (see roz/toml.h)
 * @retval ROZ_ENOSPC  a limit of this build or of @p doc (rule "storage")
 * Context: start-up or host tools; no heap, no I/O, no recursion.
 */
ROZ_NODISCARD int roz_manifest_toml_load(roz_manifest_storage_t *storage, roz_toml_doc_t *doc,
                                         const char *text, size_t len,
                                         roz_manifest_toml_problem_t *problems,
                                         size_t max_problems, size_t *n_found);

/** The longest channel name a maximum may allow (rozgen's --max-name-len). */
#define ROZ_MANIFEST_TOML_MAX_NAME_LEN 255

/** The maxima the rules hold a manifest to: those of the build its tables
 *  are for (rozgen's --max-commands, --max-states, --max-name-len). */
typedef struct roz_manifest_toml_maxima {
    uint32_t commands; /**< 1..ROZ_CFG_MAX_COMMANDS of this build */
    uint32_t states;   /**< 1..ROZ_CFG_MAX_STATES of this build */
    uint32_t name_len; /**< bytes, 1..ROZ_MANIFEST_TOML_MAX_NAME_LEN */
} roz_manifest_toml_maxima_t;

/**
 * @brief roz_manifest_toml_load() with the maxima of another build (NULL:
 *        this build's ROZ_CFG_MAX_COMMANDS, _STATES and _NAME_LEN).
 * @retval as roz_manifest_toml_load(); ROZ_EINVAL also for maxima out of
 *         their ranges (more channels than this build's storage holds)
 * Context: start-up or host tools; no heap, no I/O, no recursion.
 */
ROZ_NODISCARD int roz_manifest_toml_load_for(roz_manifest_storage_t *storage,
                                             roz_toml_doc_t *doc, const char *text, size_t len,
                                             const roz_manifest_toml_maxima_t *maxima,
                                             roz_manifest_toml_problem_t *problems,
                                             size_t max_problems, size_t *n_found);

/**
 * @brief Read a whole file into a caller buffer (host builds).
 * @param[in]  path     the file
 * @param[out] buf      @p cap bytes; not NUL-terminated
 * @param[out] len      bytes read
 * @param[out] problem  optional: on failure, rozgen's "io-error" problem
 *                      (": cannot read: No such file or directory") or a
 *                      "storage" one for a file larger than @p cap
 * @retval ROZ_OK     read
 * @retval ROZ_EIO    cannot open or read it
 * @retval ROZ_ENOSPC larger than @p cap bytes
 * @retval ROZ_EINVAL NULL arguments
 * Context: host tools; blocking file I/O.
 */
ROZ_NODISCARD int roz_manifest_toml_read_file(const char *path, char *buf, size_t cap,
                                              size_t *len, roz_manifest_toml_problem_t *problem);

/**
 * @brief roz_manifest_toml_read_file() then roz_manifest_toml_load(): the
 *        usual way to load a robot.toml. A read failure is one problem.
 * @retval as the two functions above
 * Context: host tools; blocking file I/O; no heap.
 */
ROZ_NODISCARD int roz_manifest_toml_load_file(const char *path, char *buf, size_t cap,
                                              roz_manifest_storage_t *storage,
                                              roz_toml_doc_t *doc,
                                              roz_manifest_toml_problem_t *problems,
                                              size_t max_problems, size_t *n_found);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_MANIFEST_TOML_H */
