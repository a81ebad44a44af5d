/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/module.h
 * @brief Reading a controller module from a file, for hosts: `.wasm` as is,
 *        `.wat` (WebAssembly text) assembled with wabt's wat2wasm, which must
 *        be on PATH.
 */
#ifndef ROZ_MODULE_H
#define ROZ_MODULE_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief Read a controller module into caller storage.
 * @param[in]  path  a .wasm file, or a .wat file to assemble
 * @param[out] buf   storage for the module bytes
 * @param[in]  cap   its size; a larger module is refused
 * @param[out] len   bytes read
 * @param[out] err   a message naming the file and the problem
 * @retval ROZ_OK     read
 * @retval ROZ_EIO    the file cannot be read, or wat2wasm is missing or refused it
 * @retval ROZ_ENOSPC the module is larger than @p cap
 * Context: start-up or a loader thread; blocking I/O, may start a process.
 */
int roz_module_read_file(const char *path, uint8_t *buf, size_t cap, size_t *len, char *err,
                         size_t errlen);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_MODULE_H */
