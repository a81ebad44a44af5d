/* SPDX-License-Identifier: Apache-2.0 */
#include "g1_crc.h"

#include <string.h>

uint32_t g1_crc_feed(uint32_t crc, uint32_t data, unsigned nbits)
{
    for (unsigned i = nbits; i-- > 0;) {
        uint32_t out = crc & 0x80000000u;
        crc <<= 1;
        if (out != 0u)
            crc ^= G1_CRC_POLY;
        if (((data >> i) & 1u) != 0u)
            crc ^= G1_CRC_POLY;
    }
    return crc;
}

uint32_t g1_crc_words(const void *image, size_t nwords)
{
    const unsigned char *p = image;
    uint32_t crc = G1_CRC_INIT;
    for (size_t i = 0; i < nwords; i++) {
        uint32_t w;
        memcpy(&w, p + 4 * i, sizeof w); /* host order, as the robot reads it */
        crc = g1_crc_feed(crc, w, 32);
    }
    return crc;
}
