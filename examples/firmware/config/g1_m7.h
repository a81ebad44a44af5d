/* SPDX-License-Identifier: Apache-2.0 */
/* roz's configuration for the Unitree G1 image on the Cortex-M7
 * (ROZ_CONFIG_FILE): sized for this robot and controller, from the verify
 * report and the image's measured high-water marks (docs/firmware.md). */
#ifndef ROZ_FW_G1_M7_CONFIG_H
#define ROZ_FW_G1_M7_CONFIG_H

#define ROZ_CFG_MAX_COMMANDS          145   /* the G1's table: 29 joints x 5 */
#define ROZ_CFG_MAX_STATES            97    /* 29 joints x 3, the IMU's 10 */
#define ROZ_CFG_MAX_INPUTS            0     /* no operator inputs in the manifest */
#define ROZ_CFG_NAME_ARENA_BYTES      64    /* no manifest is built at run time */
#define ROZ_CFG_MAX_JOINTS            0
#define ROZ_CFG_MAX_PARAMS            0
#define ROZ_CFG_WASM_STACK_BYTES      8192  /* the PD controller's calls are shallow */
#define ROZ_CFG_NATIVE_STACK_BYTES    6144  /* process()'s C stack, below the main stack */
#define ROZ_CFG_WASM_MAX_PAGES        1
#define ROZ_CFG_WASM_MAX_MODULE_BYTES 16384
#define ROZ_CFG_WASM_MAX_TABLE_ENTRIES 16
#define ROZ_CFG_WASM_MAX_BLOCK_DEPTH  16
/* the validator's limits: its scratch (a static buffer) is 1.5 KiB, not 22 */
#define ROZ_CFG_WASM_MAX_TYPES        16
#define ROZ_CFG_WASM_MAX_FUNCS        32
#define ROZ_CFG_WASM_MAX_GLOBALS      8
#define ROZ_CFG_WASM_MAX_LOCALS       64
#define ROZ_CFG_WASM_MAX_EXPORTS      8
#define ROZ_CFG_TELEMETRY_RING        16
#define ROZ_CFG_AOT_INSTANCES         1     /* the AOT image loads once: verification's
                                               instance is gone before the driving one starts */
#define ROZ_CFG_AOT_MAX_TYPES         24    /* the 16 types the validator takes, and rozaot's 3 */
/* what this image leaves out (roz/config.h; the saving of each: docs/firmware.md) */
#define ROZ_CFG_NN_IMPORTS            0     /* the PD controller imports no nn.* */
#define ROZ_CFG_BULK_IMPORTS          0     /* nor state.get_all, command.set_all */
#define ROZ_CFG_MATH_IMPORTS          0     /* nor math.sin, math.cos */
#define ROZ_CFG_FORMAT_DOUBLE         0     /* no message of this image prints a double */
#define ROZ_CFG_CRC32_SLICES          1     /* the loopback's CRC: a 1 KiB table, not 4 */

#endif /* ROZ_FW_G1_M7_CONFIG_H */
