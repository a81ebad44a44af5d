/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/toml.h"

#include <locale.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/*
 * A TOML 1.0 reader without heap and without recursion.
 *
 * The text is checked as UTF-8 first, then read one statement at a time.
 * A value that nests (arrays, inline tables) is read by a small state
 * machine that keeps its place in the node tree itself: every open
 * container is a node whose parent is the container around it, so closing
 * one means going to its parent. A value is parsed before its key is
 * placed in the tree, the way Python's tomllib does it, so that errors
 * such as a duplicate key point at the same place as rozgen's (just after
 * the value); the key is read a second time from the text to place it.
 */

/* ---- types ---------------------------------------------------------------- */

/* How a table or array came to be; TOML lets a table be defined only once. */
#define F_IMPLICIT 0x01u /* table made as the parent in a [header]: may still be defined */
#define F_EXPLICIT 0x02u /* table defined by [header], or an element of [[header]] */
#define F_DOTTED   0x04u /* table made by a dotted key */
#define F_INLINE   0x08u /* inline table: closed once written */
#define F_AOT      0x10u /* array of tables made by [[header]]; other arrays are closed */
#define F_PENDING  0x20u /* container parsed before its key is placed */

typedef struct parser {
    roz_toml_doc_t   *doc;
    const char       *src;
    size_t            len;
    size_t            pos;
    uint32_t          table; /* where the key/values of the current section go */
    roz_toml_error_t *err;
} parser_t;

/* ---- private: characters ---------------------------------------------------- */

static int peek_at(const parser_t *p, size_t at)
{
    return at < p->len ? (unsigned char)p->src[at] : -1;
}

static int peek(const parser_t *p)
{
    return peek_at(p, p->pos);
}

static int is_ws(int c)
{
    return c == ' ' || c == '\t';
}

static int is_digit(int c)
{
    return c >= '0' && c <= '9';
}

static int is_bare(int c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || is_digit(c) || c == '_' ||
           c == '-';
}

/* Control characters strings and comments may not hold (tab aside). */
static int is_ctrl(int c)
{
    return (c >= 0 && c < 0x20) || c == 0x7F;
}

static int digit_value(int c, int base)
{
    int v = -1;
    if (c >= '0' && c <= '9')
        v = c - '0';
    else if (c >= 'a' && c <= 'f')
        v = c - 'a' + 10;
    else if (c >= 'A' && c <= 'F')
        v = c - 'A' + 10;
    return v >= 0 && v < base ? v : -1;
}

/* Length of the line end at @at: 1 for LF, 2 for CRLF, 0 otherwise. */
static size_t newline_at(const parser_t *p, size_t at)
{
    int c = peek_at(p, at);
    if (c == '\n')
        return 1;
    if (c == '\r' && peek_at(p, at + 1) == '\n')
        return 2;
    return 0;
}

/* Bytes of the UTF-8 sequence led by @c (the text is valid UTF-8). */
static size_t utf8_len(int c)
{
    return c < 0x80 ? 1u : c < 0xE0 ? 2u : c < 0xF0 ? 3u : 4u;
}

/* Offset of the first byte that starts an invalid UTF-8 sequence (as
 * Python's strict decoder sees it), or n when all is valid. */
static size_t utf8_check(const unsigned char *s, size_t n)
{
    size_t i = 0;
    while (i < n) {
        unsigned c = s[i];
        size_t need;
        unsigned lo = 0x80, hi = 0xBF;
        if (c < 0x80) {
            i++;
            continue;
        }
        if (c >= 0xC2 && c <= 0xDF) {
            need = 1;
        } else if (c >= 0xE0 && c <= 0xEF) {
            need = 2;
            if (c == 0xE0)
                lo = 0xA0;
            else if (c == 0xED)
                hi = 0x9F; /* no surrogates */
        } else if (c >= 0xF0 && c <= 0xF4) {
            need = 3;
            if (c == 0xF0)
                lo = 0x90;
            else if (c == 0xF4)
                hi = 0x8F; /* nothing above U+10FFFF */
        } else {
            return i;
        }
        for (size_t k = 1; k <= need; k++) {
            unsigned b;
            if (i + k >= n)
                return i; /* the text ends inside the sequence */
            b = s[i + k];
            if (b < (k == 1 ? lo : 0x80u) || b > (k == 1 ? hi : 0xBFu))
                return i;
        }
        i += need + 1;
    }
    return n;
}

/* ---- private: errors -------------------------------------------------------- */

static int code_of(roz_toml_error_kind_t kind)
{
    switch (kind) {
    case ROZ_TOML_ERR_NONE:        return ROZ_OK;
    case ROZ_TOML_ERR_UNSUPPORTED: return ROZ_ENOTSUP;
    case ROZ_TOML_ERR_NODES:
    case ROZ_TOML_ERR_ARENA:       return ROZ_ENOSPC;
    default:                       return ROZ_EINVAL;
    }
}

#if defined(__GNUC__) || defined(__clang__)
__attribute__((format(printf, 4, 5)))
#endif
static int fail(parser_t *p, size_t at, roz_toml_error_kind_t kind, const char *fmt, ...)
{
    roz_toml_error_t *e = p->err;
    if (at > p->len)
        at = p->len;
    if (e != NULL) {
        va_list ap;
        uint32_t line = 1;
        size_t line_start = 0;
        for (size_t i = 0; i < at; i++) {
            if (p->src[i] == '\n') {
                line++;
                line_start = i + 1;
            }
        }
        e->kind = kind;
        e->line = line;
        e->column = (uint32_t)(at - line_start + 1);
        e->offset = at;
        va_start(ap, fmt);
        vsnprintf(e->message, sizeof e->message, fmt, ap);
        va_end(ap);
    }
    return code_of(kind);
}

/* A key for messages: bare keys as they are, others quoted, with anything
 * that is not printable ASCII as '?'. */
static const char *key_text(roz_toml_string_t k, char *buf, size_t cap)
{
    int bare = k.len > 0;
    size_t n = 0;
    uint32_t i;
    for (i = 0; i < k.len && bare; i++)
        bare = is_bare((unsigned char)k.ptr[i]);
    if (!bare)
        buf[n++] = '"';
    for (i = 0; i < k.len && n + 6 < cap; i++) { /* room for ..." and NUL */
        int c = (unsigned char)k.ptr[i];
        buf[n++] = (char)(c >= 0x20 && c < 0x7F ? c : '?');
    }
    if (i < k.len) {
        memcpy(buf + n, "...", 3);
        n += 3;
    }
    if (!bare)
        buf[n++] = '"';
    buf[n] = '\0';
    return buf;
}

/* ---- private: storage ------------------------------------------------------- */

static int new_node(parser_t *p, uint8_t type, uint32_t *out)
{
    roz_toml_doc_t *d = p->doc;
    roz_toml_node_t *n;
    if (d->n_nodes >= d->cap_nodes)
        return fail(p, p->pos, ROZ_TOML_ERR_NODES,
                    "the document needs more than the %lu nodes of its storage",
                    (unsigned long)d->cap_nodes);
    n = &d->nodes[d->n_nodes];
    memset(n, 0, sizeof *n);
    n->parent = ROZ_TOML_NONE;
    n->next = ROZ_TOML_NONE;
    n->left = ROZ_TOML_NONE;
    n->right = ROZ_TOML_NONE;
    n->type = type;
    if (type == ROZ_TOML_TABLE || type == ROZ_TOML_ARRAY) {
        n->as.list.first = ROZ_TOML_NONE;
        n->as.list.last = ROZ_TOML_NONE;
        n->as.list.index = ROZ_TOML_NONE;
    }
    *out = d->n_nodes++;
    return ROZ_OK;
}

static int arena_put(parser_t *p, const char *s, size_t n)
{
    roz_toml_doc_t *d = p->doc;
    if (n > d->arena_cap - d->arena_used)
        return fail(p, p->pos, ROZ_TOML_ERR_ARENA,
                    "the document's strings need more than the %lu bytes of its arena",
                    (unsigned long)d->arena_cap);
    if (n > 0)
        memcpy(d->arena + d->arena_used, s, n);
    d->arena_used += n;
    return ROZ_OK;
}

/* ---- private: the key index of a table ---------------------------------------
 *
 * The members of a table are kept twice: in document order (first, next) and
 * in an AA tree (a balanced binary search tree; Andersson, 1993) whose links
 * live in the member nodes (left, right, level) and whose root is the
 * table's list.index. Keys are ordered by length, then bytes: any total
 * order will do, and this one compares most keys in one step. An AA tree of
 * n nodes is at most 2 log2(n + 1) deep, so a path of 64 steps holds any
 * tree of fewer than 2^32 nodes; insertion walks back up that path instead
 * of recursing. */

#define INDEX_MAX_PATH 64

static int key_cmp(const char *a, size_t alen, roz_toml_string_t b)
{
    if (alen != b.len)
        return alen < b.len ? -1 : 1;
    return alen == 0 ? 0 : memcmp(a, b.ptr, alen);
}

static uint32_t find_child(const roz_toml_doc_t *d, uint32_t table, const char *key,
                           size_t len)
{
    uint32_t i = d->nodes[table].as.list.index;
    while (i != ROZ_TOML_NONE) {
        int c = key_cmp(key, len, d->nodes[i].key);
        if (c == 0)
            return i;
        i = c < 0 ? d->nodes[i].left : d->nodes[i].right;
    }
    return ROZ_TOML_NONE;
}

/* The AA tree's two rotations, on the subtree rooted at @t; each returns
 * the subtree's new root. */
static uint32_t index_skew(roz_toml_doc_t *d, uint32_t t)
{
    uint32_t l = d->nodes[t].left;
    if (l == ROZ_TOML_NONE || d->nodes[l].level != d->nodes[t].level)
        return t;
    d->nodes[t].left = d->nodes[l].right;
    d->nodes[l].right = t;
    return l;
}

static uint32_t index_split(roz_toml_doc_t *d, uint32_t t)
{
    uint32_t r = d->nodes[t].right;
    if (r == ROZ_TOML_NONE || d->nodes[r].right == ROZ_TOML_NONE ||
        d->nodes[d->nodes[r].right].level != d->nodes[t].level)
        return t;
    d->nodes[t].right = d->nodes[r].left;
    d->nodes[r].left = t;
    d->nodes[r].level++;
    return r;
}

/* Adds @child, whose key is not yet in @table, to the table's key index. */
static void index_insert(roz_toml_doc_t *d, uint32_t table, uint32_t child)
{
    uint32_t path[INDEX_MAX_PATH];
    int went_left[INDEX_MAX_PATH];
    size_t depth = 0;
    uint32_t i = d->nodes[table].as.list.index;
    roz_toml_node_t *cn = &d->nodes[child];

    cn->left = ROZ_TOML_NONE;
    cn->right = ROZ_TOML_NONE;
    cn->level = 1;
    while (i != ROZ_TOML_NONE && depth < INDEX_MAX_PATH) {
        path[depth] = i;
        went_left[depth] = key_cmp(cn->key.ptr, cn->key.len, d->nodes[i].key) < 0;
        i = went_left[depth] ? d->nodes[i].left : d->nodes[i].right;
        depth++;
    }
    i = child;
    while (depth-- > 0) {
        uint32_t t = path[depth];
        if (went_left[depth])
            d->nodes[t].left = i;
        else
            d->nodes[t].right = i;
        i = index_split(d, index_skew(d, t));
    }
    d->nodes[table].as.list.index = i;
}

/* Appends @child to table or array @parent; a table's member must have a
 * key not yet in the table (the callers look it up first). */
static void append_child(roz_toml_doc_t *d, uint32_t parent, uint32_t child)
{
    roz_toml_node_t *pn = &d->nodes[parent];
    roz_toml_node_t *cn = &d->nodes[child];
    cn->parent = parent;
    cn->next = ROZ_TOML_NONE;
    if (pn->as.list.last == ROZ_TOML_NONE)
        pn->as.list.first = child;
    else
        d->nodes[pn->as.list.last].next = child;
    pn->as.list.last = child;
    pn->as.list.count++;
    if (pn->type == ROZ_TOML_TABLE)
        index_insert(d, parent, child);
}

/* A new table or array under @parent, named @key (NULL: an array's
 * element), with the reader's @flags. */
static int new_child(parser_t *p, uint32_t parent, uint8_t type, uint8_t flags,
                     const roz_toml_string_t *key, uint32_t *out)
{
    int rc = new_node(p, type, out);
    if (rc != ROZ_OK)
        return rc;
    p->doc->nodes[*out].flags = flags;
    if (key != NULL)
        p->doc->nodes[*out].key = *key;
    append_child(p->doc, parent, *out);
    return ROZ_OK;
}

/* ---- private: whitespace and comments --------------------------------------- */

static void skip_ws(parser_t *p)
{
    while (is_ws(peek(p)))
        p->pos++;
}

static int skip_comment(parser_t *p)
{
    if (peek(p) != '#')
        return ROZ_OK;
    p->pos++;
    for (;;) {
        int c = peek(p);
        if (c < 0 || newline_at(p, p->pos) > 0)
            return ROZ_OK;
        if (is_ctrl(c) && c != '\t')
            return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX,
                        "control character U+%04X in a comment", (unsigned)c);
        p->pos++;
    }
}

/* Whitespace and newlines (no comments). */
static void skip_ws_newlines(parser_t *p)
{
    for (;;) {
        size_t nl = newline_at(p, p->pos);
        if (is_ws(peek(p)))
            p->pos++;
        else if (nl > 0)
            p->pos += nl;
        else
            return;
    }
}

/* Whitespace, newlines and comments, as allowed between array elements. */
static int skip_array_ws(parser_t *p)
{
    for (;;) {
        size_t before = p->pos;
        skip_ws_newlines(p);
        int rc = skip_comment(p);
        if (rc != ROZ_OK)
            return rc;
        if (p->pos == before)
            return ROZ_OK;
    }
}

/* ---- private: strings --------------------------------------------------------- */

static int put_utf8(parser_t *p, uint32_t cp)
{
    char b[4];
    size_t n;
    if (cp < 0x80) {
        b[0] = (char)cp;
        n = 1;
    } else if (cp < 0x800) {
        b[0] = (char)(0xC0 | (cp >> 6));
        b[1] = (char)(0x80 | (cp & 0x3F));
        n = 2;
    } else if (cp < 0x10000) {
        b[0] = (char)(0xE0 | (cp >> 12));
        b[1] = (char)(0x80 | ((cp >> 6) & 0x3F));
        b[2] = (char)(0x80 | (cp & 0x3F));
        n = 3;
    } else {
        b[0] = (char)(0xF0 | (cp >> 18));
        b[1] = (char)(0x80 | ((cp >> 12) & 0x3F));
        b[2] = (char)(0x80 | ((cp >> 6) & 0x3F));
        b[3] = (char)(0x80 | (cp & 0x3F));
        n = 4;
    }
    return arena_put(p, b, n);
}

/* One escape sequence at p->pos (the backslash) of a basic string, decoded
 * into the arena. */
static int escape(parser_t *p, int multi)
{
    size_t at = p->pos;
    int e = peek_at(p, at + 1);
    char c;

    if (multi && (is_ws(e) || newline_at(p, at + 1) > 0)) {
        /* line-ending backslash: drop it and all whitespace and newlines after */
        if (is_ws(e)) {
            p->pos = at + 2;
            skip_ws(p);
            if (peek(p) < 0)
                return ROZ_OK; /* the caller reports the open string */
            if (newline_at(p, p->pos) == 0)
                return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX,
                            "only whitespace may follow a line-ending backslash");
            p->pos += newline_at(p, p->pos);
        } else {
            p->pos = at + 1 + newline_at(p, at + 1);
        }
        skip_ws_newlines(p);
        return ROZ_OK;
    }
    switch (e) {
    case 'b':  c = '\b'; break;
    case 't':  c = '\t'; break;
    case 'n':  c = '\n'; break;
    case 'f':  c = '\f'; break;
    case 'r':  c = '\r'; break;
    case '"':  c = '"'; break;
    case '\\': c = '\\'; break;
    case 'u':
    case 'U': {
        int digits = e == 'u' ? 4 : 8;
        size_t h = at + 2;
        uint32_t cp = 0;
        for (int i = 0; i < digits; i++) {
            int v = digit_value(peek_at(p, h + (size_t)i), 16);
            if (v < 0)
                return fail(p, h, ROZ_TOML_ERR_SYNTAX, "\\%c needs %d hex digits", e, digits);
            cp = cp * 16u + (uint32_t)v;
        }
        if (cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))
            return fail(p, h + (size_t)digits, ROZ_TOML_ERR_SYNTAX,
                        "\\%c%0*lX is not a Unicode scalar value", e, digits, (unsigned long)cp);
        p->pos = h + (size_t)digits;
        return put_utf8(p, cp);
    }
    default: {
        /* tomllib points just past the two characters of the sequence */
        size_t end = at + 1;
        if (e >= 0)
            end += newline_at(p, at + 1) == 2 ? 2u : utf8_len(e);
        return fail(p, end, ROZ_TOML_ERR_SYNTAX,
                    "invalid escape sequence (valid: \\b \\t \\n \\f \\r \\\" \\\\ \\uXXXX "
                    "\\UXXXXXXXX)");
    }
    }
    p->pos = at + 2;
    return arena_put(p, &c, 1);
}

/* A basic string at p->pos ("..." or """..."""). The result points into the
 * text unless it had escapes or CRLF line ends; then it is in the arena. */
static int basic_string(parser_t *p, int multi, roz_toml_string_t *out)
{
    roz_toml_doc_t *d = p->doc;
    size_t base = d->arena_used;
    int copying = 0;
    size_t run;
    int rc;

    p->pos += multi ? 3u : 1u;
    if (multi)
        p->pos += newline_at(p, p->pos);
    run = p->pos;
    for (;;) {
        int c = peek(p);
        if (c < 0)
            return fail(p, p->len, ROZ_TOML_ERR_SYNTAX, "the string is not closed");
        if (c == '"') {
            size_t end = p->pos;
            if (!multi) {
                p->pos++;
            } else if (peek_at(p, end + 1) == '"' && peek_at(p, end + 2) == '"') {
                /* up to two more quotes right before the closing ones are content */
                p->pos += 3;
                for (int extra = 0; extra < 2 && peek(p) == '"'; extra++) {
                    p->pos++;
                    end++;
                }
            } else {
                p->pos++;
                continue;
            }
            if (copying) {
                rc = arena_put(p, p->src + run, end - run);
                if (rc != ROZ_OK)
                    return rc;
                out->ptr = d->arena + base;
                out->len = (uint32_t)(d->arena_used - base);
            } else {
                out->ptr = p->src + run;
                out->len = (uint32_t)(end - run);
            }
            return ROZ_OK;
        }
        if (c == '\\' || (multi && c == '\r' && peek_at(p, p->pos + 1) == '\n')) {
            copying = 1;
            rc = arena_put(p, p->src + run, p->pos - run);
            if (rc == ROZ_OK && c == '\\') {
                rc = escape(p, multi);
            } else if (rc == ROZ_OK) {
                rc = arena_put(p, "\n", 1); /* CRLF is read as LF, as tomllib does */
                p->pos += 2;
            }
            if (rc != ROZ_OK)
                return rc;
            run = p->pos;
            continue;
        }
        if ((c == '\n' || c == '\r') && !multi)
            return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX,
                        "a newline in a one-line string (use \"\"\" for several lines, or \\n)");
        if (is_ctrl(c) && !(c == '\t' || (multi && c == '\n')))
            return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX,
                        "control character U+%04X in a string (write it as \\u%04X)",
                        (unsigned)c, (unsigned)c);
        p->pos++;
    }
}

/* A literal string at p->pos ('...' or '''...'''): no escapes; in the
 * arena only when CRLF line ends had to become LF. */
static int literal_string(parser_t *p, int multi, roz_toml_string_t *out)
{
    roz_toml_doc_t *d = p->doc;
    size_t start = p->pos + (multi ? 3u : 1u);
    size_t end = start;
    int crlf = 0;

    if (multi)
        start += newline_at(p, start);
    /* as tomllib: find the closing quote(s) first, then check what is between */
    for (end = start;; end++) {
        const char *q;
        if (end >= p->len)
            return fail(p, p->len, ROZ_TOML_ERR_SYNTAX, "the literal string is not closed");
        q = memchr(p->src + end, '\'', p->len - end);
        if (q == NULL)
            return fail(p, p->len, ROZ_TOML_ERR_SYNTAX, "the literal string is not closed");
        end = (size_t)(q - p->src);
        if (!multi || (peek_at(p, end + 1) == '\'' && peek_at(p, end + 2) == '\''))
            break;
    }
    for (size_t i = start; i < end; i++) {
        int c = (unsigned char)p->src[i];
        if (multi && c == '\r' && peek_at(p, i + 1) == '\n') {
            crlf = 1;
            continue;
        }
        if ((c == '\n' || c == '\r') && !multi)
            return fail(p, i, ROZ_TOML_ERR_SYNTAX,
                        "a newline in a one-line literal string (use ''' for several lines)");
        if (is_ctrl(c) && !(c == '\t' || (multi && c == '\n')))
            return fail(p, i, ROZ_TOML_ERR_SYNTAX, "control character U+%04X in a literal string",
                        (unsigned)c);
    }
    p->pos = end + (multi ? 3u : 1u);
    if (multi) {
        /* up to two more quotes right before the closing ones are content */
        for (int extra = 0; extra < 2 && peek(p) == '\''; extra++) {
            p->pos++;
            end++;
        }
    }
    if (!crlf) {
        out->ptr = p->src + start;
        out->len = (uint32_t)(end - start);
        return ROZ_OK;
    }
    size_t base = d->arena_used;
    for (size_t i = start; i < end; i++) {
        if (p->src[i] == '\r' && peek_at(p, i + 1) == '\n')
            continue;
        int rc = arena_put(p, p->src + i, 1);
        if (rc != ROZ_OK)
            return rc;
    }
    out->ptr = d->arena + base;
    out->len = (uint32_t)(d->arena_used - base);
    return ROZ_OK;
}

/* ---- private: keys -------------------------------------------------------------- */

/* One part of a key: bare, "basic" or 'literal' (one line). */
static int key_part(parser_t *p, roz_toml_string_t *out)
{
    int c = peek(p);
    if (is_bare(c)) {
        size_t start = p->pos;
        while (is_bare(peek(p)))
            p->pos++;
        out->ptr = p->src + start;
        out->len = (uint32_t)(p->pos - start);
        return ROZ_OK;
    }
    if (c == '\'')
        return literal_string(p, 0, out);
    if (c == '"')
        return basic_string(p, 0, out);
    return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX, "expected a key (bare, \"quoted\" or 'literal')");
}

/* Checks a whole (dotted) key and moves past it and the whitespace after;
 * decoded parts are dropped again (the key is read once more to place it). */
static int scan_key(parser_t *p)
{
    size_t mark = p->doc->arena_used;
    for (;;) {
        roz_toml_string_t k;
        int rc = key_part(p, &k);
        if (rc != ROZ_OK)
            return rc;
        skip_ws(p);
        if (peek(p) != '.')
            break;
        p->pos++;
        skip_ws(p);
    }
    p->doc->arena_used = mark;
    return ROZ_OK;
}

/* Reads the next part of a key already checked by scan_key(); *last tells
 * whether it was the final part. */
static int next_key_part(parser_t *p, roz_toml_string_t *k, int *last)
{
    int rc = key_part(p, k);
    if (rc != ROZ_OK)
        return rc;
    skip_ws(p);
    *last = peek(p) != '.';
    if (!*last) {
        p->pos++;
        skip_ws(p);
    }
    return ROZ_OK;
}

/* Places value node @n under the dotted key at @key_at, starting in table
 * @base: the table of the current [section] (@top) or an inline table.
 * Errors point at p->pos, just after the value, as tomllib's do. */
static int place(parser_t *p, uint32_t base, int top, const char *key_at, uint32_t n)
{
    roz_toml_doc_t *d = p->doc;
    size_t after = p->pos;
    uint32_t cur = base;
    char kb[48];

    p->pos = (size_t)(key_at - p->src);
    for (;;) {
        roz_toml_string_t k;
        int last;
        size_t mark = d->arena_used;
        int rc = next_key_part(p, &k, &last);
        if (rc != ROZ_OK)
            return rc;
        uint32_t c = find_child(d, cur, k.ptr, k.len);
        if (last) {
            if (c != ROZ_TOML_NONE)
                return fail(p, after, ROZ_TOML_ERR_SYNTAX, "duplicate key %s",
                            key_text(k, kb, sizeof kb));
            d->nodes[n].key = k;
            append_child(d, cur, n);
            break;
        }
        if (c == ROZ_TOML_NONE) {
            rc = new_child(p, cur, ROZ_TOML_TABLE, F_DOTTED, &k, &c);
            if (rc != ROZ_OK)
                return rc;
        } else {
            roz_toml_node_t *t = &d->nodes[c];
            d->arena_used = mark;
            if (t->type != ROZ_TOML_TABLE)
                return fail(p, after, ROZ_TOML_ERR_SYNTAX,
                            "%s is %s, so a dotted key cannot add to it",
                            key_text(k, kb, sizeof kb),
                            t->type == ROZ_TOML_ARRAY ? "an array" : "a value");
            if (t->flags & F_INLINE)
                return fail(p, after, ROZ_TOML_ERR_SYNTAX,
                            "%s is an inline table, which cannot be added to",
                            key_text(k, kb, sizeof kb));
            if ((t->flags & F_EXPLICIT) || !(t->flags & (F_IMPLICIT | F_DOTTED)))
                return fail(p, after, ROZ_TOML_ERR_SYNTAX,
                            "table %s is defined by a [header], so a dotted key cannot add "
                            "to it", key_text(k, kb, sizeof kb));
            if (top && (t->flags & F_IMPLICIT))
                t->flags = F_DOTTED; /* now defined: a [header] may not define it again */
        }
        cur = c;
    }
    p->pos = after;
    return ROZ_OK;
}

/* Opens the table of a [header] or a new element of a [[header]]: the key
 * at @key_at, already checked, ends at @after (errors point there). */
static int open_table(parser_t *p, size_t key_at, size_t after, int aot)
{
    roz_toml_doc_t *d = p->doc;
    uint32_t cur = 0;
    char kb[48];

    p->pos = key_at;
    for (;;) {
        roz_toml_string_t k;
        int last, rc;
        size_t mark = d->arena_used;
        rc = next_key_part(p, &k, &last);
        if (rc != ROZ_OK)
            return rc;
        uint32_t c = find_child(d, cur, k.ptr, k.len);
        roz_toml_node_t *t = c == ROZ_TOML_NONE ? NULL : &d->nodes[c];
        if (t != NULL)
            d->arena_used = mark;
        if (!last) {
            if (t == NULL) {
                rc = new_child(p, cur, ROZ_TOML_TABLE, F_IMPLICIT, &k, &c);
                if (rc != ROZ_OK)
                    return rc;
            } else if (t->type == ROZ_TOML_TABLE && !(t->flags & F_INLINE)) {
                /* a table of any other kind: go in */
            } else if (t->type == ROZ_TOML_ARRAY && (t->flags & F_AOT)) {
                c = t->as.list.last; /* [[a]] then [a.b]: b goes in the last a */
            } else {
                return fail(p, after, ROZ_TOML_ERR_SYNTAX, "%s is %s; it cannot hold a table",
                            key_text(k, kb, sizeof kb),
                            t->type == ROZ_TOML_TABLE ? "an inline table"
                            : t->type == ROZ_TOML_ARRAY ? "an array" : "a value");
            }
            cur = c;
            continue;
        }
        if (!aot) {
            if (t == NULL) {
                rc = new_child(p, cur, ROZ_TOML_TABLE, 0, &k, &c);
                if (rc != ROZ_OK)
                    return rc;
            } else if (!(t->type == ROZ_TOML_TABLE && t->flags == F_IMPLICIT)) {
                return fail(p, after, ROZ_TOML_ERR_SYNTAX, "%s is already defined",
                            key_text(k, kb, sizeof kb));
            }
            d->nodes[c].flags = F_EXPLICIT;
        } else {
            uint32_t elem;
            if (t == NULL) {
                rc = new_child(p, cur, ROZ_TOML_ARRAY, F_AOT, &k, &c);
                if (rc != ROZ_OK)
                    return rc;
            } else if (!(t->type == ROZ_TOML_ARRAY && (t->flags & F_AOT))) {
                return fail(p, after, ROZ_TOML_ERR_SYNTAX,
                            "%s is already defined, and not as an array of tables",
                            key_text(k, kb, sizeof kb));
            }
            rc = new_child(p, c, ROZ_TOML_TABLE, F_EXPLICIT, NULL, &elem);
            if (rc != ROZ_OK)
                return rc;
            c = elem;
        }
        p->table = c;
        break;
    }
    p->pos = after;
    return ROZ_OK;
}

/* ---- private: scalar values ------------------------------------------------------ */

/* @n decimal digits at @at, as a number; -1 if they are not all digits. */
static int digits(const parser_t *p, size_t at, int n)
{
    int v = 0;
    for (int i = 0; i < n; i++) {
        int c = peek_at(p, at + (size_t)i);
        if (!is_digit(c))
            return -1;
        v = v * 10 + (c - '0');
    }
    return v;
}

/* HH:MM:SS[.frac] at @at, as tomllib's pattern has it. Returns the end,
 * 0 when there is no time here, or (size_t)-1 for a leap second. */
static size_t match_time(const parser_t *p, size_t at, roz_toml_datetime_t *t)
{
    int h = digits(p, at, 2), m = digits(p, at + 3, 2), s = digits(p, at + 6, 2);
    size_t end = at + 8;
    if (h < 0 || m < 0 || s < 0 || peek_at(p, at + 2) != ':' || peek_at(p, at + 5) != ':' ||
        h > 23 || m > 59)
        return 0;
    if (s > 59)
        return s == 60 ? (size_t)-1 : 0;
    t->hour = (uint8_t)h;
    t->minute = (uint8_t)m;
    t->second = (uint8_t)s;
    t->frac_digits = 0;
    t->nanosecond = 0;
    if (peek_at(p, end) == '.' && is_digit(peek_at(p, end + 1))) {
        end++;
        while (is_digit(peek_at(p, end))) {
            if (t->frac_digits < 9) {
                t->nanosecond = t->nanosecond * 10u + (uint32_t)(p->src[end] - '0');
                t->frac_digits++;
            }
            end++;
        }
        for (int i = t->frac_digits; i < 9; i++)
            t->nanosecond *= 10u;
    }
    return end;
}

static int days_in_month(int y, int m)
{
    static const unsigned char days[12] = { 31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31 };
    int leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    return m == 2 && leap ? 29 : days[m - 1];
}

/* A date, date-time or time at p->pos. Returns 1 with a node, 0 when there
 * is none here, or an error. */
static int datetime(parser_t *p, uint32_t *out)
{
    size_t at = p->pos, end;
    roz_toml_datetime_t t;
    uint8_t type;
    int y = digits(p, at, 4), mo = digits(p, at + 5, 2), dd = digits(p, at + 8, 2);

    memset(&t, 0, sizeof t);
    if (y >= 0 && mo >= 1 && mo <= 12 && dd >= 1 && dd <= 31 && peek_at(p, at + 4) == '-' &&
        peek_at(p, at + 7) == '-') {
        int sep = peek_at(p, at + 10);
        size_t tend = 0;
        t.year = (uint16_t)y;
        t.month = (uint8_t)mo;
        t.day = (uint8_t)dd;
        end = at + 10;
        type = ROZ_TOML_DATE_LOCAL;
        if (sep == 'T' || sep == 't' || sep == ' ')
            tend = match_time(p, at + 11, &t);
        if (dd > days_in_month(y, mo))
            return fail(p, at, ROZ_TOML_ERR_SYNTAX, "%04d-%02d-%02d: no such date", y, mo, dd);
        if (y == 0)
            return fail(p, at, ROZ_TOML_ERR_UNSUPPORTED,
                        "year 0000 is not supported (rozgen's dates start at year 1)");
        if (tend == (size_t)-1) /* where tomllib, which reads the date alone, stops */
            return fail(p, at + (sep == ' ' ? 11u : 10u), ROZ_TOML_ERR_UNSUPPORTED,
                        "leap seconds (:60) are not supported");
        if (tend > 0) {
            int z = peek_at(p, tend), oh, om;
            end = tend;
            type = ROZ_TOML_DATETIME_LOCAL;
            if (z == 'Z' || z == 'z') {
                type = ROZ_TOML_DATETIME;
                t.zulu = 1;
                end++;
            } else if ((z == '+' || z == '-') && (oh = digits(p, tend + 1, 2)) >= 0 &&
                       oh <= 23 && peek_at(p, tend + 3) == ':' &&
                       (om = digits(p, tend + 4, 2)) >= 0 && om <= 59) {
                type = ROZ_TOML_DATETIME;
                t.offset_min = (int16_t)((z == '-' ? -1 : 1) * (oh * 60 + om));
                end = tend + 6;
            }
        }
    } else {
        end = match_time(p, at, &t);
        if (end == (size_t)-1) /* where tomllib, which reads the hour as an integer, stops */
            return fail(p, at + (peek_at(p, at) == '0' ? 1u : 2u), ROZ_TOML_ERR_UNSUPPORTED,
                        "leap seconds (:60) are not supported");
        if (end == 0)
            return 0;
        type = ROZ_TOML_TIME_LOCAL;
    }
    int rc = new_node(p, type, out);
    if (rc != ROZ_OK)
        return rc;
    p->doc->nodes[*out].as.datetime = t;
    p->pos = end;
    return 1;
}

/* Digits of @base from @at, single underscores between digits allowed
 * ("1_000"); returns the end. */
static size_t digit_run(const parser_t *p, size_t at, int base)
{
    while (digit_value(peek_at(p, at), base) >= 0) {
        at++;
        if (peek_at(p, at) == '_' && digit_value(peek_at(p, at + 1), base) >= 0)
            at++;
    }
    return at;
}

#define INT_RANGE_MESSAGE \
    "integer does not fit in 64 bits (-9223372036854775808..9223372036854775807)"

/* Text [from, to) as a 64-bit integer in @base, skipping '_' and an
 * optional sign; 0 on overflow. */
static int to_int64(const parser_t *p, size_t from, size_t to, int base, int64_t *out)
{
    int neg = 0;
    uint64_t v = 0, limit = (uint64_t)INT64_MAX;
    if (p->src[from] == '+' || p->src[from] == '-') {
        neg = p->src[from] == '-';
        from++;
    }
    if (neg)
        limit += 1u;
    for (size_t i = from; i < to; i++) {
        int d = digit_value((unsigned char)p->src[i], base);
        if (d < 0)
            continue; /* '_' */
        if (v > (limit - (uint64_t)d) / (uint64_t)base)
            return 0;
        v = v * (uint64_t)base + (uint64_t)d;
    }
    *out = neg ? (int64_t)(0u - v) : (int64_t)v;
    return 1;
}

/* The float text [from, to) -- already matched: sign, digits, optional
 * fraction and exponent, single underscores between digits -- as a double,
 * correctly rounded by strtod, whatever its length.
 *
 * strtod needs a NUL-terminated copy, and the literal may be longer than any
 * buffer. The copy is 0.DDD...e<exp> with the leading zeros dropped (moved
 * into the exponent) and at most FLOAT_DIGITS significant digits, plus one
 * sticky '1' when a dropped digit was not zero. That rounds the same: a
 * value halfway between two doubles has at most 767 significant digits, so
 * no halfway value and no double lies strictly between the kept digits and
 * the kept digits plus one unit of the last, where both the literal and the
 * copy are. The exponent is clamped to +-EXP_CLAMP: beyond 10^400 any
 * 0.D... is inf and below 10^-400 it is 0, either way. */
#define FLOAT_DIGITS 800
#define EXP_CLAMP    100000

static int to_double(parser_t *p, size_t from, size_t to, double *out)
{
    char buf[FLOAT_DIGITS + 40];
    const char *point = localeconv()->decimal_point;
    size_t plen = point != NULL && point[0] != '\0' ? strlen(point) : 0u;
    size_t i = from, n = 0, kept = 0;
    int64_t exp10 = 0, exp_text = 0;
    int seen_point = 0, sticky = 0, exp_neg = 0;
    char *end;

    if (plen == 0 || plen > 8) { /* strtod follows the C locale's decimal point */
        point = ".";
        plen = 1;
    }
    if (p->src[i] == '+' || p->src[i] == '-')
        buf[n++] = p->src[i++];
    buf[n++] = '0';
    memcpy(buf + n, point, plen);
    n += plen;
    for (; i < to; i++) {
        char c = p->src[i];
        if (c == '_')
            continue;
        if (c == '.') {
            seen_point = 1;
            continue;
        }
        if (c == 'e' || c == 'E')
            break;
        if (kept == 0 && c == '0') { /* a leading zero: only the exponent moves */
            exp10 -= seen_point;
            continue;
        }
        exp10 += !seen_point;
        if (kept < FLOAT_DIGITS) {
            buf[n++] = c;
            kept++;
        } else if (c != '0') {
            sticky = 1;
        }
    }
    if (i < to) { /* the exponent, saturated: its sign and digits */
        i++;
        if (p->src[i] == '+' || p->src[i] == '-')
            exp_neg = p->src[i++] == '-';
        for (; i < to; i++) {
            if (p->src[i] != '_' && exp_text < 10 * (int64_t)EXP_CLAMP)
                exp_text = exp_text * 10 + (p->src[i] - '0');
        }
    }
    if (kept == 0) {
        buf[n++] = '0'; /* zero, with its sign */
    } else {
        exp10 += exp_neg ? -exp_text : exp_text;
        exp10 = exp10 > EXP_CLAMP ? EXP_CLAMP : exp10 < -EXP_CLAMP ? -EXP_CLAMP : exp10;
        if (sticky)
            buf[n++] = '1';
        n += (size_t)snprintf(buf + n, sizeof buf - n, "e%ld", (long)exp10);
    }
    buf[n] = '\0';
    *out = strtod(buf, &end); /* out of range gives +-inf or 0, as Python's float() */
    if (end != buf + n)
        return fail(p, from, ROZ_TOML_ERR_UNSUPPORTED, "the C library could not read this float");
    return ROZ_OK;
}

/* An integer node of the digits [from, to) in @p base; an error at @p at
 * (the number's start) when it does not fit. */
static int integer_node(parser_t *p, size_t at, size_t from, size_t to, int base,
                        uint32_t *out)
{
    int64_t iv;
    if (!to_int64(p, from, to, base, &iv))
        return fail(p, at, ROZ_TOML_ERR_SYNTAX, INT_RANGE_MESSAGE);
    int rc = new_node(p, ROZ_TOML_INTEGER, out);
    if (rc == ROZ_OK)
        p->doc->nodes[*out].as.integer = iv;
    return rc;
}

/* An integer or float at p->pos, matched as tomllib's pattern does.
 * Returns 1 with a node, 0 when there is no number here, or an error. */
static int number(parser_t *p, uint32_t *out)
{
    size_t at = p->pos, i = at, int_end;
    int base = 0, rc;
    double fv;

    if (peek_at(p, at) == '0') {
        int b = peek_at(p, at + 1);
        base = b == 'x' ? 16 : b == 'o' ? 8 : b == 'b' ? 2 : 0;
        if (base != 0 && digit_value(peek_at(p, at + 2), base) < 0)
            base = 0;
    }
    if (base != 0) {
        i = digit_run(p, at + 2, base);
        rc = integer_node(p, at, at + 2, i, base, out);
        if (rc != ROZ_OK)
            return rc;
        p->pos = i;
        return 1;
    }
    if (peek_at(p, i) == '+' || peek_at(p, i) == '-')
        i++;
    if (peek_at(p, i) == '0')
        i++;
    else if (peek_at(p, i) >= '1' && peek_at(p, i) <= '9')
        i = digit_run(p, i, 10);
    else
        return 0;
    int_end = i;
    if (peek_at(p, i) == '.' && is_digit(peek_at(p, i + 1)))
        i = digit_run(p, i + 1, 10);
    if (peek_at(p, i) == 'e' || peek_at(p, i) == 'E') {
        size_t k = i + 1;
        if (peek_at(p, k) == '+' || peek_at(p, k) == '-')
            k++;
        if (is_digit(peek_at(p, k)))
            i = digit_run(p, k, 10);
    }
    if (i == int_end) {
        rc = integer_node(p, at, at, i, 10, out);
        if (rc != ROZ_OK)
            return rc;
    } else {
        rc = to_double(p, at, i, &fv);
        if (rc != ROZ_OK)
            return rc;
        rc = new_node(p, ROZ_TOML_FLOAT, out);
        if (rc != ROZ_OK)
            return rc;
        p->doc->nodes[*out].as.real = fv;
    }
    p->pos = i;
    return 1;
}

static int starts_with(const parser_t *p, const char *s)
{
    size_t n = strlen(s);
    return p->len - p->pos >= n && memcmp(p->src + p->pos, s, n) == 0;
}

/* Any value but an array or inline table, at p->pos, tried in tomllib's
 * order. */
static int scalar(parser_t *p, uint32_t *out)
{
    int c = peek(p), rc;

    if (c == '"' || c == '\'') {
        roz_toml_string_t s;
        int multi = peek_at(p, p->pos + 1) == c && peek_at(p, p->pos + 2) == c;
        rc = c == '"' ? basic_string(p, multi, &s) : literal_string(p, multi, &s);
        if (rc == ROZ_OK)
            rc = new_node(p, ROZ_TOML_STRING, out);
        if (rc == ROZ_OK)
            p->doc->nodes[*out].as.str = s;
        return rc;
    }
    if (starts_with(p, "true") || starts_with(p, "false")) {
        int v = c == 't';
        rc = new_node(p, ROZ_TOML_BOOL, out);
        if (rc == ROZ_OK) {
            p->doc->nodes[*out].as.boolean = v;
            p->pos += v ? 4u : 5u;
        }
        return rc;
    }
    rc = datetime(p, out);
    if (rc != 0)
        return rc < 0 ? rc : ROZ_OK;
    rc = number(p, out);
    if (rc != 0)
        return rc < 0 ? rc : ROZ_OK;
    static const char *const specials[] = { "inf", "nan", "+inf", "+nan", "-inf", "-nan" };
    for (size_t k = 0; k < sizeof specials / sizeof specials[0]; k++) {
        if (starts_with(p, specials[k])) {
            const char *s = specials[k];
            double v = s[strlen(s) - 3] == 'i' ? HUGE_VAL : (double)NAN;
            rc = new_node(p, ROZ_TOML_FLOAT, out);
            if (rc != ROZ_OK)
                return rc;
            p->doc->nodes[*out].as.real = s[0] == '-' ? -v : v;
            p->pos += strlen(s);
            return ROZ_OK;
        }
    }
    return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX, "expected a value");
}

/* ---- private: values that nest ------------------------------------------------- */

/* Hands a finished value to where it belongs: an array (append), an
 * inline table, or the current [section] (@dest == NONE) under its key. */
static int deliver(parser_t *p, uint32_t dest, const char *key_at, uint32_t n)
{
    if (dest != ROZ_TOML_NONE && p->doc->nodes[dest].type == ROZ_TOML_ARRAY) {
        append_child(p->doc, dest, n);
        return ROZ_OK;
    }
    if (dest == ROZ_TOML_NONE)
        return place(p, p->table, 1, key_at, n);
    return place(p, dest, 0, key_at, n);
}

/* The value of a key/value statement whose key is at @key_at, p->pos at
 * the value. Nesting is followed through the nodes' parent links. */
static int value(parser_t *p, const char *key_at)
{
    enum { S_VALUE, S_KEY, S_CLOSE, S_AFTER } s = S_VALUE;
    roz_toml_doc_t *d = p->doc;
    uint32_t e = ROZ_TOML_NONE; /* innermost open array or inline table */
    uint32_t n = ROZ_TOML_NONE; /* value just read, or container just closed */
    const char *key = key_at;   /* key of the next value, unless e is an array */
    unsigned depth = 0;         /* containers open: e and those around it */
    int rc = ROZ_OK, c;

    for (;;) {
        switch (s) {
        case S_VALUE:
            c = peek(p);
            if (c == '[' || c == '{') {
                if (depth >= ROZ_TOML_MAX_DEPTH)
                    return fail(p, p->pos, ROZ_TOML_ERR_UNSUPPORTED,
                                "arrays and inline tables nested more than %d deep are not "
                                "supported", ROZ_TOML_MAX_DEPTH);
                rc = new_node(p, c == '[' ? ROZ_TOML_ARRAY : ROZ_TOML_TABLE, &n);
                if (rc != ROZ_OK)
                    return rc;
                if (c == '{')
                    d->nodes[n].flags = F_INLINE;
                if (e != ROZ_TOML_NONE && d->nodes[e].type == ROZ_TOML_ARRAY) {
                    append_child(d, e, n);
                } else {
                    d->nodes[n].parent = e;
                    d->nodes[n].key.ptr = key;
                    d->nodes[n].flags |= F_PENDING;
                }
                p->pos++;
                if (c == '[') {
                    rc = skip_array_ws(p);
                    if (rc != ROZ_OK)
                        return rc;
                    if (peek(p) == ']') {
                        p->pos++;
                        s = S_CLOSE;
                    } else {
                        e = n;
                        depth++;
                    }
                } else {
                    skip_ws(p);
                    if (peek(p) == '}') {
                        p->pos++;
                        s = S_CLOSE;
                    } else {
                        e = n;
                        depth++;
                        s = S_KEY;
                    }
                }
            } else {
                rc = scalar(p, &n);
                if (rc == ROZ_OK)
                    rc = deliver(p, e, key, n);
                if (rc != ROZ_OK)
                    return rc;
                s = S_AFTER;
            }
            break;
        case S_KEY: /* next key/value of inline table e */
            key = p->src + p->pos;
            rc = scan_key(p);
            if (rc != ROZ_OK)
                return rc;
            if (peek(p) != '=')
                return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX, "expected '=' after the key");
            p->pos++;
            skip_ws(p);
            s = S_VALUE;
            break;
        case S_CLOSE: { /* container n is complete */
            roz_toml_node_t *nd = &d->nodes[n];
            uint32_t outer = nd->parent;
            if (nd->flags & F_PENDING) {
                const char *k = nd->key.ptr;
                nd->flags &= (uint8_t)~F_PENDING;
                nd->parent = ROZ_TOML_NONE;
                nd->key.ptr = NULL;
                rc = deliver(p, outer, k, n);
                if (rc != ROZ_OK)
                    return rc;
            }
            e = outer;
            s = S_AFTER;
            break;
        }
        case S_AFTER: /* a value of e is complete */
            if (e == ROZ_TOML_NONE)
                return ROZ_OK;
            if (d->nodes[e].type == ROZ_TOML_ARRAY) {
                rc = skip_array_ws(p);
                if (rc != ROZ_OK)
                    return rc;
                c = peek(p);
                if (c == ',') {
                    p->pos++;
                    rc = skip_array_ws(p);
                    if (rc != ROZ_OK)
                        return rc;
                    c = peek(p);
                    if (c != ']') {
                        s = S_VALUE;
                        break;
                    }
                }
                if (c != ']')
                    return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX, "expected ',' or ']' in the array");
                p->pos++;
            } else {
                skip_ws(p);
                c = peek(p);
                if (c == ',') {
                    p->pos++;
                    skip_ws(p);
                    s = S_KEY;
                    break;
                }
                if (c != '}')
                    return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX,
                                "expected ',' or '}' in the inline table (it must be on one "
                                "line, without a trailing comma)");
                p->pos++;
            }
            n = e;
            depth--;
            s = S_CLOSE;
            break;
        }
    }
}

/* ---- private: statements --------------------------------------------------------- */

static int key_value(parser_t *p)
{
    const char *key_at = p->src + p->pos;
    int rc = scan_key(p);
    if (rc != ROZ_OK)
        return rc;
    if (peek(p) != '=')
        return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX, "expected '=' after the key");
    p->pos++;
    skip_ws(p);
    return value(p, key_at);
}

static int header(parser_t *p)
{
    int aot = peek_at(p, p->pos + 1) == '[';
    size_t key_at;
    int rc;

    p->pos += aot ? 2u : 1u;
    skip_ws(p);
    key_at = p->pos;
    rc = scan_key(p);
    if (rc == ROZ_OK)
        rc = open_table(p, key_at, p->pos, aot);
    if (rc != ROZ_OK)
        return rc;
    if (aot) {
        if (peek(p) != ']' || peek_at(p, p->pos + 1) != ']')
            return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX,
                        "expected ']]' at the end of the [[array of tables]] header");
        p->pos += 2;
    } else {
        if (peek(p) != ']')
            return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX,
                        "expected ']' at the end of the [table] header");
        p->pos++;
    }
    return ROZ_OK;
}

static int document(parser_t *p)
{
    uint32_t root;
    int rc = new_node(p, ROZ_TOML_TABLE, &root);
    if (rc != ROZ_OK)
        return rc;
    p->table = root;
    for (;;) {
        int c;
        size_t nl;
        skip_ws(p);
        c = peek(p);
        if (c < 0)
            return ROZ_OK;
        nl = newline_at(p, p->pos);
        if (nl > 0) {
            p->pos += nl;
            continue;
        }
        if (is_bare(c) || c == '"' || c == '\'') {
            rc = key_value(p);
            skip_ws(p);
        } else if (c == '[') {
            rc = header(p);
            skip_ws(p);
        } else if (c != '#') {
            if (p->pos == 0 && starts_with(p, "\xEF\xBB\xBF"))
                return fail(p, 0, ROZ_TOML_ERR_SYNTAX, "a byte order mark is not allowed");
            return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX,
                        "expected a key, a [table] header or a comment");
        }
        if (rc == ROZ_OK)
            rc = skip_comment(p);
        if (rc != ROZ_OK)
            return rc;
        if (peek(p) < 0)
            return ROZ_OK;
        nl = newline_at(p, p->pos);
        if (nl == 0)
            return fail(p, p->pos, ROZ_TOML_ERR_SYNTAX,
                        "expected the end of the line after this statement");
        p->pos += nl;
    }
}

/* ---- public ------------------------------------------------------------------------ */

void roz_toml_init(roz_toml_doc_t *doc, roz_toml_node_t *nodes, size_t n_nodes, char *arena,
                   size_t arena_bytes)
{
    if (doc == NULL)
        return;
    memset(doc, 0, sizeof *doc);
    doc->nodes = nodes;
    doc->cap_nodes = nodes == NULL ? 0u
                     : n_nodes >= (size_t)ROZ_TOML_NONE ? ROZ_TOML_NONE - 1u
                                                         : (uint32_t)n_nodes;
    static char no_arena[1]; /* so that strings never point at NULL + 0 */
    doc->arena = arena != NULL ? arena : no_arena;
    doc->arena_cap = arena != NULL ? arena_bytes : 0u;
}

int roz_toml_parse(roz_toml_doc_t *doc, const char *text, size_t len, roz_toml_error_t *err)
{
    parser_t p;
    size_t bad;
    int rc;

    memset(&p, 0, sizeof p);
    p.doc = doc;
    p.src = text != NULL ? text : "";
    p.len = text != NULL ? len : 0u;
    p.err = err;
    if (err != NULL)
        memset(err, 0, sizeof *err);
    if (doc == NULL || (text == NULL && len > 0))
        return fail(&p, 0, ROZ_TOML_ERR_ARG, "no document or no text");
#if SIZE_MAX > UINT32_MAX
    if (len > UINT32_MAX) { /* string lengths are 32-bit */
        p.len = 0;
        doc->n_nodes = 0;
        return fail(&p, 0, ROZ_TOML_ERR_UNSUPPORTED, "documents of 4 GiB or more are not supported");
    }
#endif
    doc->n_nodes = 0;
    doc->arena_used = 0;
    doc->text = p.src;
    doc->text_len = p.len;
    bad = utf8_check((const unsigned char *)p.src, p.len);
    if (bad < p.len) {
        rc = fail(&p, bad, ROZ_TOML_ERR_UTF8, "not valid UTF-8 (byte 0x%02x at offset %lu)",
                  (unsigned)(unsigned char)p.src[bad], (unsigned long)bad);
    } else {
        rc = document(&p);
    }
    if (rc != ROZ_OK) {
        doc->n_nodes = 0;
        doc->arena_used = 0;
    }
    return rc;
}

const roz_toml_node_t *roz_toml_root(const roz_toml_doc_t *doc)
{
    return doc == NULL || doc->n_nodes == 0 ? NULL : &doc->nodes[0];
}

static uint32_t index_of(const roz_toml_doc_t *doc, const roz_toml_node_t *node)
{
    if (doc == NULL || node == NULL || node < doc->nodes || node >= doc->nodes + doc->n_nodes)
        return ROZ_TOML_NONE;
    return (uint32_t)(node - doc->nodes);
}

static const roz_toml_node_t *node_at(const roz_toml_doc_t *doc, uint32_t i)
{
    return i == ROZ_TOML_NONE ? NULL : &doc->nodes[i];
}

const roz_toml_node_t *roz_toml_get_n(const roz_toml_doc_t *doc, const roz_toml_node_t *table,
                                      const char *key, size_t key_len)
{
    uint32_t t = index_of(doc, table);
    if (t == ROZ_TOML_NONE || table->type != ROZ_TOML_TABLE || (key == NULL && key_len > 0))
        return NULL;
    return node_at(doc, find_child(doc, t, key, key_len));
}

const roz_toml_node_t *roz_toml_get(const roz_toml_doc_t *doc, const roz_toml_node_t *table,
                                    const char *key)
{
    if (key == NULL)
        return NULL;
    return roz_toml_get_n(doc, table, key, strlen(key));
}

const roz_toml_node_t *roz_toml_first(const roz_toml_doc_t *doc, const roz_toml_node_t *node)
{
    if (index_of(doc, node) == ROZ_TOML_NONE ||
        (node->type != ROZ_TOML_TABLE && node->type != ROZ_TOML_ARRAY))
        return NULL;
    return node_at(doc, node->as.list.first);
}

const roz_toml_node_t *roz_toml_next(const roz_toml_doc_t *doc, const roz_toml_node_t *node)
{
    if (index_of(doc, node) == ROZ_TOML_NONE)
        return NULL;
    return node_at(doc, node->next);
}

const roz_toml_node_t *roz_toml_parent(const roz_toml_doc_t *doc, const roz_toml_node_t *node)
{
    if (index_of(doc, node) == ROZ_TOML_NONE)
        return NULL;
    return node_at(doc, node->parent);
}

const roz_toml_node_t *roz_toml_at(const roz_toml_doc_t *doc, const roz_toml_node_t *node,
                                   size_t i)
{
    const roz_toml_node_t *c = roz_toml_first(doc, node);
    while (c != NULL && i-- > 0)
        c = roz_toml_next(doc, c);
    return c;
}

size_t roz_toml_count(const roz_toml_node_t *node)
{
    if (node == NULL || (node->type != ROZ_TOML_TABLE && node->type != ROZ_TOML_ARRAY))
        return 0;
    return node->as.list.count;
}

const char *roz_toml_type_name(roz_toml_type_t type)
{
    static const char *const names[ROZ_TOML_TYPE_COUNT_] = {
        [ROZ_TOML_TABLE] = "table",
        [ROZ_TOML_ARRAY] = "array",
        [ROZ_TOML_STRING] = "string",
        [ROZ_TOML_INTEGER] = "integer",
        [ROZ_TOML_FLOAT] = "float",
        [ROZ_TOML_BOOL] = "bool",
        [ROZ_TOML_DATETIME] = "datetime",
        [ROZ_TOML_DATETIME_LOCAL] = "datetime-local",
        [ROZ_TOML_DATE_LOCAL] = "date-local",
        [ROZ_TOML_TIME_LOCAL] = "time-local",
    };
    if ((unsigned)type >= (unsigned)ROZ_TOML_TYPE_COUNT_)
        return "?";
    return names[type];
}

int roz_toml_datetime_format(const roz_toml_node_t *node, char *buf, size_t cap)
{
    const roz_toml_datetime_t *t;
    int n = 0;
    if (node == NULL || buf == NULL || node->type < ROZ_TOML_DATETIME ||
        node->type > ROZ_TOML_TIME_LOCAL)
        return ROZ_EINVAL;
    if (cap < 40)
        return ROZ_ENOSPC;
    t = &node->as.datetime;
    if (node->type != ROZ_TOML_TIME_LOCAL)
        n += snprintf(buf + n, cap - (size_t)n, "%04u-%02u-%02u", (unsigned)t->year,
                      (unsigned)t->month, (unsigned)t->day);
    if (node->type == ROZ_TOML_DATE_LOCAL)
        return n;
    if (node->type != ROZ_TOML_TIME_LOCAL)
        buf[n++] = 'T';
    n += snprintf(buf + n, cap - (size_t)n, "%02u:%02u:%02u", (unsigned)t->hour,
                  (unsigned)t->minute, (unsigned)t->second);
    if (t->frac_digits > 0) {
        char frac[16];
        snprintf(frac, sizeof frac, "%09lu", (unsigned long)t->nanosecond);
        n += snprintf(buf + n, cap - (size_t)n, ".%.*s", (int)t->frac_digits, frac);
    }
    if (node->type == ROZ_TOML_DATETIME) {
        if (t->zulu) {
            n += snprintf(buf + n, cap - (size_t)n, "Z");
        } else {
            int off = t->offset_min < 0 ? -t->offset_min : t->offset_min;
            n += snprintf(buf + n, cap - (size_t)n, "%c%02d:%02d", t->offset_min < 0 ? '-' : '+',
                          off / 60, off % 60);
        }
    }
    return n;
}
