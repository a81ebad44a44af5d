/* SPDX-License-Identifier: Apache-2.0 */
/* The model's include tree within rozgen's limits, before MuJoCo reads it
 * (mjcf_scan.c). Private to the mujoco port. */
#ifndef ROZ_MUJOCO_MJCF_SCAN_H
#define ROZ_MUJOCO_MJCF_SCAN_H

#include <stddef.h>

/* codegen/rozgen/mjcf.py's MAX_DEPTH, MAX_INCLUDES and MAX_BYTES */
#define ROZ_MJCF_MAX_DEPTH    16
#define ROZ_MJCF_MAX_INCLUDES 256
#define ROZ_MJCF_MAX_BYTES    (32 * 1024 * 1024)
#define ROZ_MJCF_PATH_MAX     1024

/* ROZ_OK when the model at @p model and every file it includes are regular
 * files within the limits; else ROZ_EINVAL (ROZ_ENOMEM) and the reason,
 * naming the file or include, in @p err. Allocates while it runs (open
 * only). */
int roz__mjcf_scan(const char *model, char *err, size_t errlen);

#endif /* ROZ_MUJOCO_MJCF_SCAN_H */
