/* SPDX-License-Identifier: Apache-2.0 */
/* Single-writer sequence counters (private to the core): the writer makes
 * the counter odd, stores the data as relaxed atomic 32-bit words, and makes
 * it even again; a reader copies the words and keeps the copy only if the
 * counter was even and unchanged around it. The writer never waits; a
 * reader retries. 32-bit words only: 64-bit atomics are not lock-free on
 * 32-bit microcontrollers. */
#ifndef ROZ_SEQLOCK_H
#define ROZ_SEQLOCK_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

static inline void roz__seq_begin(_Atomic uint32_t *seq)
{
    uint32_t q = atomic_load_explicit(seq, memory_order_relaxed);
    atomic_store_explicit(seq, q + 1u, memory_order_relaxed);
    atomic_thread_fence(memory_order_release);
}

static inline void roz__seq_end(_Atomic uint32_t *seq)
{
    uint32_t q = atomic_load_explicit(seq, memory_order_relaxed);
    atomic_store_explicit(seq, q + 1u, memory_order_release);
}

/* Writer: store @p n words of @p src (between begin and end). */
static inline void roz__seq_store(_Atomic uint32_t *dst, const void *src, size_t n)
{
    const unsigned char *p = (const unsigned char *)src;
    for (size_t i = 0; i < n; i++) {
        uint32_t w;
        memcpy(&w, p + 4u * i, sizeof w);
        atomic_store_explicit(&dst[i], w, memory_order_relaxed);
    }
}

/* Reader: the counter before a copy; odd means "retry". */
static inline uint32_t roz__seq_read_begin(const _Atomic uint32_t *seq)
{
    return atomic_load_explicit(seq, memory_order_acquire);
}

/* Reader: copy @p n words into @p dst. */
static inline void roz__seq_load(void *dst, const _Atomic uint32_t *src, size_t n)
{
    unsigned char *p = (unsigned char *)dst;
    for (size_t i = 0; i < n; i++) {
        uint32_t w = atomic_load_explicit(&src[i], memory_order_relaxed);
        memcpy(p + 4u * i, &w, sizeof w);
    }
}

/* Reader: 1 if the copy since roz__seq_read_begin() returned @p q is good. */
static inline int roz__seq_read_ok(const _Atomic uint32_t *seq, uint32_t q)
{
    atomic_thread_fence(memory_order_acquire);
    return (q & 1u) == 0u && atomic_load_explicit(seq, memory_order_relaxed) == q;
}

#endif /* ROZ_SEQLOCK_H */
