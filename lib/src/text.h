/* SPDX-License-Identifier: Apache-2.0 */
/* Bounded text building without printf (private to the core): for the
 * messages the tick path writes, where a formatter's stack use and time are
 * unwelcome. Text past the end is cut; the buffer is always terminated. */
#ifndef ROZ_TEXT_H
#define ROZ_TEXT_H

#include <stddef.h>
#include <stdint.h>

typedef struct roz__text {
    char  *buf;
    size_t len; /* capacity, >= 1 */
    size_t pos; /* characters written, < len */
} roz__text_t;

static inline roz__text_t roz__text(char *buf, size_t len)
{
    roz__text_t t = { buf, len, 0 };
    buf[0] = '\0';
    return t;
}

static inline void roz__text_str(roz__text_t *t, const char *s)
{
    while (*s != '\0' && t->pos + 1u < t->len)
        t->buf[t->pos++] = *s++;
    t->buf[t->pos] = '\0';
}

static inline void roz__text_u64(roz__text_t *t, uint64_t v)
{
    char d[21];
    size_t n = 0;
    do {
        d[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0u);
    while (n > 0 && t->pos + 1u < t->len)
        t->buf[t->pos++] = d[--n];
    t->buf[t->pos] = '\0';
}

static inline void roz__text_i64(roz__text_t *t, int64_t v)
{
    if (v < 0) {
        roz__text_str(t, "-");
        roz__text_u64(t, (uint64_t)0 - (uint64_t)v);
    } else {
        roz__text_u64(t, (uint64_t)v);
    }
}

#endif /* ROZ_TEXT_H */
