/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/hal/crc32.h
 * @brief The CRC-32 that ports put on their frames: the one the Unitree SDK
 *        calls crc32_core, over 32-bit words (Unitree's SDK).
 *
 * Register starts at 0xFFFFFFFF; polynomial 0x04C11DB7; each word's bits are
 * taken most significant first; no reflection, no final XOR. Over a byte
 * stream this is CRC-32/MPEG-2 with every 4-byte little-endian word read
 * byte-reversed. The words are the frame's native struct image (memset to
 * zero, filled, then checked), never its serialized bytes.
 *
 * Context: any; RT-safe (no heap, up to 4 KiB of tables: ROZ_CFG_CRC32_SLICES; bounded by @p n).
 */
#ifndef ROZ_HAL_CRC32_H
#define ROZ_HAL_CRC32_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief CRC of @p n words.
 * @param[in] words the image; may be NULL when @p n is 0
 * @param[in] n     word count (for a struct with a trailing crc field:
 *                  sizeof(struct) / 4 - 1)
 * @return the CRC; 0xFFFFFFFF for n = 0
 * Context: any; RT-safe; O(n).
 */
uint32_t roz_crc32_words(const uint32_t *words, size_t n);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_HAL_CRC32_H */
