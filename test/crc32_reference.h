/* SPDX-License-Identifier: Apache-2.0 */
/* The frame CRC as Unitree's SDK defines it (crc32_core), one bit at a
 * time: shift left, XOR the polynomial if the bit shifted out was 1, XOR it
 * again if the data bit is 1. The reference roz_crc32_words() is checked
 * against (test/hal/test_link.c) and timed against (bench/tick). */
#ifndef ROZ_TEST_CRC32_REFERENCE_H
#define ROZ_TEST_CRC32_REFERENCE_H

#include <stddef.h>
#include <stdint.h>

static inline uint32_t roz_crc32_reference(const uint32_t *w, size_t n)
{
    uint32_t crc = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        for (uint32_t bit = 1u << 31; bit != 0u; bit >>= 1) {
            uint32_t out = crc & 0x80000000u;
            crc <<= 1;
            if (out)
                crc ^= 0x04C11DB7u;
            if (w[i] & bit)
                crc ^= 0x04C11DB7u;
        }
    }
    return crc;
}

#endif /* ROZ_TEST_CRC32_REFERENCE_H */
