/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/text.h
 * @brief The bounded text builder every roz message is put together with.
 *
 * Text is appended to a caller's buffer; what does not fit is cut (and
 * remembered: roz_text_finish() then ends the text in "..."), and the buffer
 * is always terminated. Pieces are copied, numbers written digit by digit:
 * no printf, no allocation, no locale. roz_text_format() appends through
 * roz_format() (roz/format.h) for the messages that need its conversions.
 */
#ifndef ROZ_TEXT_H
#define ROZ_TEXT_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/format.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A text under construction in a caller's buffer. */
typedef struct roz_text {
    char  *buf; /**< the caller's buffer, always terminated */
    size_t cap; /**< its size in bytes, >= 1 */
    size_t len; /**< characters written, < cap */
    int    cut; /**< something did not fit */
} roz_text_t;

/** @brief Start an empty text in @p buf (@p cap >= 1 bytes).
 *  Context: any; bounded, no formatting (the tick may use it). */
void roz_text_init(roz_text_t *t, char *buf, size_t cap);

/** @brief Append @p n bytes of @p s. Context: as roz_text_init(). */
void roz_text_putn(roz_text_t *t, const char *s, size_t n);

/** @brief Append NUL-terminated @p s (NULL appends nothing).
 *  Context: as roz_text_init(). */
void roz_text_put(roz_text_t *t, const char *s);

/** @brief Append @p v in decimal. Context: as roz_text_init(). */
void roz_text_put_u64(roz_text_t *t, uint64_t v);

/** @brief Append @p v in decimal. Context: as roz_text_init(). */
void roz_text_put_i64(roz_text_t *t, int64_t v);

/**
 * @brief Append @p n bytes of @p s as a TOML basic string, quotes included:
 *        `"` and `\` escaped, \\n \\t \\r \\b \\f by name, other control
 *        characters as \\uXXXX (the quoting of rozgen's messages).
 * Context: as roz_text_init().
 */
void roz_text_put_quoted(roz_text_t *t, const char *s, size_t n);

/** @brief Append @p x as roz_format_double() writes it, with ".0" after a
 *  number that would read as an integer (a C double literal: rozgen's
 *  fmt.c_double). Context: not the tick. With ROZ_CFG_FORMAT_DOUBLE 0:
 *  the bits, as `%g` then prints them. */
void roz_text_put_double(roz_text_t *t, double x);

/** @brief Append through roz_format(). Context: not the tick (roz formats
 *  nothing there). */
void roz_text_format(roz_text_t *t, const char *fmt, ...) ROZ_FORMAT_CHECK(2, 3);

/** @brief Cut the text back to its first @p len characters (no-op when
 *  longer than it is); a cut after that point is forgotten. Context: as roz_text_init(). */
void roz_text_truncate(roz_text_t *t, size_t len);

/** @brief When something was cut (and @p cap >= 4), end the text in "...",
 *  so that nobody takes it for the whole message. Context: as roz_text_init(). */
void roz_text_finish(roz_text_t *t);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_TEXT_H */
