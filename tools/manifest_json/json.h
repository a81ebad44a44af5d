/* SPDX-License-Identifier: Apache-2.0 */
/* rozgen's canonical JSON for a manifest in memory (see json.c). */
#ifndef ROZ_EXAMPLES_MANIFEST_JSON_H
#define ROZ_EXAMPLES_MANIFEST_JSON_H

#include "roz/manifest.h"

/* Writes the manifest to stdout exactly as `rozgen --json` prints it; with
 * @as_written, each channel's limit_margin as written (0: the default)
 * instead of the margin worked out, for rozgen's model (--rozgen). */
void manifest_json_print(const roz_manifest_t *m, int as_written);

#endif
