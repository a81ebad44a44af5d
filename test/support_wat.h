/* SPDX-License-Identifier: Apache-2.0 */
/* A test helper: WebAssembly text assembled with wabt's wat2wasm (through
 * roz_module_read_file(), roz::hal), for tests that write their modules
 * inline. */
#ifndef ROZ_TEST_SUPPORT_WAT_H
#define ROZ_TEST_SUPPORT_WAT_H

#include <stddef.h>
#include <stdint.h>

/* Assembles `wat` into buf (cap bytes); fails the test (cmocka) with
 * wat2wasm's message if it does not assemble. Returns the module's length. */
size_t roz_test_wat(const char *wat, uint8_t *buf, size_t cap);

#endif /* ROZ_TEST_SUPPORT_WAT_H */
