/* SPDX-License-Identifier: Apache-2.0 */
/* A test helper: the bytes of a WebAssembly binary, written into caller
 * storage (b, cap, *n): a byte, unsigned and signed LEB128, a name, and a
 * size placeholder filled in when its contents are written. The tests that
 * build modules byte by byte (test/hostile/) use them on buffers of their
 * own, or on a roz_wb_buf_t through roz_wb_put*(). Needs <cmocka.h> (a full buffer fails the test). */
#ifndef ROZ_TEST_WASM_BYTES_H
#define ROZ_TEST_WASM_BYTES_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

static inline void roz_wb_byte(uint8_t *b, size_t cap, size_t *n, uint8_t v)
{
    if (*n >= cap)
        fail_msg("wasm builder: %zu bytes are full", cap);
    b[(*n)++] = v;
}

static inline void roz_wb_bytes(uint8_t *b, size_t cap, size_t *n, const void *p, size_t len)
{
    for (size_t i = 0; i < len; i++)
        roz_wb_byte(b, cap, n, ((const uint8_t *)p)[i]);
}

static inline void roz_wb_u32(uint8_t *b, size_t cap, size_t *n, uint32_t v)
{
    do {
        uint8_t low = v & 0x7f;
        v >>= 7;
        roz_wb_byte(b, cap, n, v != 0 ? (uint8_t)(low | 0x80) : low);
    } while (v != 0);
}

/* Signed LEB128 of a 64-bit two's complement value (an i32 arrives sign
 * extended); arithmetic on the unsigned bits only. */
static inline void roz_wb_s64(uint8_t *b, size_t cap, size_t *n, uint64_t v)
{
    for (;;) {
        uint8_t low = v & 0x7f;
        uint64_t sign = (v >> 63) ? ~UINT64_C(0) : 0;
        v = (v >> 7) | (sign << 57);
        if ((v == 0 && (low & 0x40) == 0) || (v == ~UINT64_C(0) && (low & 0x40) != 0)) {
            roz_wb_byte(b, cap, n, low);
            return;
        }
        roz_wb_byte(b, cap, n, (uint8_t)(low | 0x80));
    }
}

/* The low `bytes` bytes of v, little-endian (an f32 or f64 constant's bits). */
static inline void roz_wb_le(uint8_t *b, size_t cap, size_t *n, uint64_t v, unsigned bytes)
{
    for (unsigned i = 0; i < bytes; i++)
        roz_wb_byte(b, cap, n, (uint8_t)(v >> (8 * i)));
}

/* A name of len bytes (it may hold NUL bytes). */
static inline void roz_wb_name(uint8_t *b, size_t cap, size_t *n, const char *s, size_t len)
{
    roz_wb_u32(b, cap, n, (uint32_t)len);
    roz_wb_bytes(b, cap, n, s, len);
}

/* A 5-byte LEB size placeholder; roz_wb_sized_end() writes the size of
 * what followed it. */
static inline size_t roz_wb_sized_begin(uint8_t *b, size_t cap, size_t *n)
{
    size_t at = *n;
    for (int i = 0; i < 4; i++)
        roz_wb_byte(b, cap, n, 0x80);
    roz_wb_byte(b, cap, n, 0x00);
    return at;
}

static inline void roz_wb_sized_end(uint8_t *b, size_t n, size_t at)
{
    size_t size = n - at - 5;
    for (int i = 0; i < 5; i++)
        b[at + (size_t)i] = (uint8_t)(((size >> (7 * i)) & 0x7f) | (i < 4 ? 0x80 : 0));
}

/* A module, or a section's body, being written: a buffer of its own and the
 * bytes used, for the tests that need no other storage. */
typedef struct roz_wb_buf {
    uint8_t b[4096];
    size_t  n;
} roz_wb_buf_t;

static inline void roz_wb_put(roz_wb_buf_t *w, uint8_t v)
{
    roz_wb_byte(w->b, sizeof w->b, &w->n, v);
}

static inline void roz_wb_put_u32(roz_wb_buf_t *w, uint32_t v)
{
    roz_wb_u32(w->b, sizeof w->b, &w->n, v);
}

static inline void roz_wb_put_bytes(roz_wb_buf_t *w, const void *p, size_t n)
{
    roz_wb_bytes(w->b, sizeof w->b, &w->n, p, n);
}

/* A section: its id, its size, its body of n bytes. */
static inline void roz_wb_put_section(roz_wb_buf_t *w, uint8_t id, const void *body, size_t n)
{
    roz_wb_put(w, id);
    roz_wb_put_u32(w, (uint32_t)n);
    roz_wb_put_bytes(w, body, n);
}

#endif /* ROZ_TEST_WASM_BYTES_H */
