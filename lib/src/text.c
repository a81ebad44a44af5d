/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/text.h"

#include <stdarg.h>
#include <string.h>

void roz_text_init(roz_text_t *t, char *buf, size_t cap)
{
    t->buf = buf;
    t->cap = cap;
    t->len = 0;
    t->cut = 0;
    buf[0] = '\0';
}

void roz_text_putn(roz_text_t *t, const char *s, size_t n)
{
    size_t room = t->cap - 1u - t->len;
    if (n > room) {
        n = room;
        t->cut = 1;
    }
    memcpy(t->buf + t->len, s, n);
    t->len += n;
    t->buf[t->len] = '\0';
}

void roz_text_put(roz_text_t *t, const char *s)
{
    if (s != NULL)
        roz_text_putn(t, s, strlen(s));
}

void roz_text_put_u64(roz_text_t *t, uint64_t v)
{
    char d[20];
    size_t n = sizeof d;
    do {
        d[--n] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0u);
    roz_text_putn(t, d + n, sizeof d - n);
}

void roz_text_put_i64(roz_text_t *t, int64_t v)
{
    if (v < 0) {
        roz_text_put(t, "-");
        roz_text_put_u64(t, (uint64_t)0 - (uint64_t)v);
    } else {
        roz_text_put_u64(t, (uint64_t)v);
    }
}

void roz_text_put_quoted(roz_text_t *t, const char *s, size_t n)
{
    static const char hex[] = "0123456789ABCDEF";
    roz_text_put(t, "\"");
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        switch (c) {
        case '"':  roz_text_put(t, "\\\""); break;
        case '\\': roz_text_put(t, "\\\\"); break;
        case '\n': roz_text_put(t, "\\n"); break;
        case '\t': roz_text_put(t, "\\t"); break;
        case '\r': roz_text_put(t, "\\r"); break;
        case '\b': roz_text_put(t, "\\b"); break;
        case '\f': roz_text_put(t, "\\f"); break;
        default:
            if (c < 0x20 || c == 0x7F) {
                char u[6] = { '\\', 'u', '0', '0', hex[c >> 4], hex[c & 0xFu] };
                roz_text_putn(t, u, sizeof u);
            } else {
                roz_text_putn(t, (const char *)&c, 1);
            }
        }
    }
    roz_text_put(t, "\"");
}

void roz_text_format(roz_text_t *t, const char *fmt, ...)
{
    size_t room = t->cap - t->len;
    va_list ap;
    int n;

    va_start(ap, fmt);
    n = roz_vformat(t->buf + t->len, room, fmt, ap);
    va_end(ap);
    if (n < 0)
        return;
    if ((size_t)n >= room) {
        t->len = t->cap - 1u;
        t->cut = 1;
    } else {
        t->len += (size_t)n;
    }
}

void roz_text_truncate(roz_text_t *t, size_t len)
{
    /* a cut leaves len at cap - 1: what is left before it is whole */
    if (len < t->len) {
        t->len = len;
        t->buf[len] = '\0';
        t->cut = 0;
    }
}

void roz_text_finish(roz_text_t *t)
{
    if (t->cut && t->cap >= 4u) {
        size_t at = t->len >= 3u ? t->len - 3u : 0u;
        memcpy(t->buf + at, "...", 3);
        t->len = at + 3u;
        t->buf[t->len] = '\0';
    }
}
