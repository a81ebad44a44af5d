/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/hal/crc32.h"

/* The register after shifting a 4-bit value through it, MSB first. */
static const uint32_t nibble[16] = {
    0x00000000u, 0x04C11DB7u, 0x09823B6Eu, 0x0D4326D9u, 0x130476DCu, 0x17C56B6Bu,
    0x1A864DB2u, 0x1E475005u, 0x2608EDB8u, 0x22C9F00Fu, 0x2F8AD6D6u, 0x2B4BCB61u,
    0x350C9B64u, 0x31CD86D3u, 0x3C8EA00Au, 0x384FBDBDu,
};

uint32_t roz_crc32_words(const uint32_t *words, size_t n)
{
    uint32_t crc = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        uint32_t w = words[i];
        for (int k = 0; k < 8; k++) {
            crc = (crc << 4) ^ nibble[(crc >> 28) ^ (w >> 28)];
            w <<= 4;
        }
    }
    return crc;
}
