/* SPDX-License-Identifier: Apache-2.0 */
/* A small, MCU-sized roz configuration for the config-matrix consumer build:
 * passed through the roz_config INTERFACE target as ROZ_CONFIG_FILE. */
#ifndef SMALL_CONFIG_H
#define SMALL_CONFIG_H

#define ROZ_CFG_MAX_COMMANDS 16
#define ROZ_CFG_MAX_STATES 16
#define ROZ_CFG_NAME_ARENA_BYTES 1024
#define ROZ_CFG_MAX_NAME_LEN 31
#define ROZ_CFG_WASM_STACK_BYTES 8192
#define ROZ_CFG_NATIVE_STACK_BYTES 8192 /* an RTOS task's share; main.c recurses into it */
#define ROZ_CFG_WASM_MAX_PAGES 2
#define ROZ_CFG_WASM_MAX_MODULE_BYTES 16384
#define ROZ_CFG_TELEMETRY_RING 8
#define ROZ_CFG_ERROR_LEN 96

#endif
