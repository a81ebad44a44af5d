/* SPDX-License-Identifier: Apache-2.0 */
/* The comparison behind the layout checks (roz_runtime_layout_check(),
 * roz_port_layout_check()): the application's ROZ_CFG_* options and sizes,
 * field by field, against the library's. Internal to libroz_core. */
#ifndef ROZ_SRC_LAYOUT_H
#define ROZ_SRC_LAYOUT_H

#include <stddef.h>

typedef struct {
    const char *name; /* what the field is, as the message names it */
    size_t      at;   /* its offset (a uint32_t) in both layouts */
} roz__layout_field_t;

/* ROZ_OK when every field of @p caller equals @p mine's; else ROZ_ECONFIG
 * with "NAME is A in the application, B in libroz_core: build both with
 * the same ROZ_CONFIG_FILE (@p why)" in @p err, for the first that differs.
 * @p err is left alone on ROZ_OK. */
int roz__layout_compare(const void *caller, const void *mine, const roz__layout_field_t *fields,
                        size_t n, const char *why, char *err, size_t errlen);

#endif /* ROZ_SRC_LAYOUT_H */
