/* SPDX-License-Identifier: Apache-2.0 */
/* The fake G1's CRC: Unitree's crc32_core, written from its definition and
 * computed one bit at a time (slow and obviously right; the fake is a
 * reference, not a fast path). The register starts at 0xFFFFFFFF; for each
 * data bit, most significant first, the register shifts left, takes the
 * polynomial 0x04C11DB7 if the bit shifted out was 1, and takes it again if
 * the data bit is 1. No reflection, no final XOR. A frame's CRC covers its
 * native struct (zeroed, then filled) as host-endian 32-bit words, every
 * word but the trailing crc.
 *
 * Context: any thread; no state. */
#ifndef FAKE_G1_CRC_H
#define FAKE_G1_CRC_H

#include <stddef.h>
#include <stdint.h>

#define G1_CRC_INIT 0xFFFFFFFFu
#define G1_CRC_POLY 0x04C11DB7u

/* Feed the low @p nbits (1..32) of @p data to @p crc, most significant
 * first. Fed bytes (nbits 8) this is CRC-32/MPEG-2. */
uint32_t g1_crc_feed(uint32_t crc, uint32_t data, unsigned nbits);

/* The CRC of @p nwords 32-bit words read from @p image in host order. */
uint32_t g1_crc_words(const void *image, size_t nwords);

#endif /* FAKE_G1_CRC_H */
