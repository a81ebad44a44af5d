/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/toml.h
 * @brief A small TOML 1.0 reader for host builds, into caller-provided
 *        storage (no heap, no recursion).
 *
 * Part of roz::toml (CMake option ROZ_TOML). docs/robot-toml.md ("The
 * reader") says what it reads and refuses, how the document lives in the
 * caller's node pool and arena (strings may point into the text, which must
 * outlive the document), its O(n log n) time, and its error positions.
 */
#ifndef ROZ_TOML_H
#define ROZ_TOML_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Node index meaning "none" (no parent, no sibling, no child). */
#define ROZ_TOML_NONE UINT32_MAX

/** Deepest nesting of arrays and inline tables read (`a = [[1]]` is 2
 *  deep); deeper is refused with ROZ_ENOTSUP at the bracket that goes too
 *  deep. rozgen has the same limit (Python's tomllib recurses per level). */
#define ROZ_TOML_MAX_DEPTH 100

/** Type of a node; the names (roz_toml_type_name()) are toml-test's. */
typedef enum roz_toml_type {
    ROZ_TOML_TABLE = 0,       /**< "table": the root, [t], [[t]] elements, {inline}, dotted keys */
    ROZ_TOML_ARRAY,           /**< "array": [values] and [[arrays of tables]] */
    ROZ_TOML_STRING,          /**< "string" */
    ROZ_TOML_INTEGER,         /**< "integer": 64-bit signed */
    ROZ_TOML_FLOAT,           /**< "float": IEEE 754 double */
    ROZ_TOML_BOOL,            /**< "bool" */
    ROZ_TOML_DATETIME,        /**< "datetime": date, time and UTC offset */
    ROZ_TOML_DATETIME_LOCAL,  /**< "datetime-local": date and time, no offset */
    ROZ_TOML_DATE_LOCAL,      /**< "date-local" */
    ROZ_TOML_TIME_LOCAL,      /**< "time-local" */
    ROZ_TOML_TYPE_COUNT_      /**< number of types; not a type */
} roz_toml_type_t;

/** A counted string: UTF-8, may contain NUL, not NUL-terminated. */
typedef struct roz_toml_string {
    const char *ptr; /**< into the text or the arena; NULL only for no key */
    uint32_t    len; /**< bytes */
} roz_toml_string_t;

/** Date and/or time; which fields mean something depends on the type. */
typedef struct roz_toml_datetime {
    uint16_t year;        /**< 0..9999 (dates) */
    uint8_t  month;       /**< 1..12 (dates) */
    uint8_t  day;         /**< 1..31, valid for the month (dates) */
    uint8_t  hour;        /**< 0..23 (times) */
    uint8_t  minute;      /**< 0..59 (times) */
    uint8_t  second;      /**< 0..59 (times) */
    uint8_t  frac_digits; /**< digits of the fraction as written, 0..9 (times) */
    uint32_t nanosecond;  /**< fraction of the second, truncated to ns (times) */
    int16_t  offset_min;  /**< UTC offset in minutes, -1439..1439 (ROZ_TOML_DATETIME) */
    uint8_t  zulu;        /**< 1 when written "Z" (ROZ_TOML_DATETIME) */
} roz_toml_datetime_t;

/** One node of a document: a table, an array or a value. */
typedef struct roz_toml_node {
    roz_toml_string_t key; /**< key in its parent table; {NULL, 0} in arrays and for the root */
    uint32_t parent;       /**< index of the parent node; ROZ_TOML_NONE for the root */
    uint32_t next;         /**< next sibling in document order, or ROZ_TOML_NONE */
    uint8_t  type;         /**< a roz_toml_type_t */
    uint8_t  flags;        /**< the reader's bookkeeping; not API */
    uint8_t  level;        /**< key index of the parent table (AA-tree level); not API */
    uint32_t left, right;  /**< key index of the parent table (children); not API */
    union {
        roz_toml_string_t   str;      /**< ROZ_TOML_STRING */
        int64_t             integer;  /**< ROZ_TOML_INTEGER */
        double              real;     /**< ROZ_TOML_FLOAT */
        int                 boolean;  /**< ROZ_TOML_BOOL: 0 or 1 */
        roz_toml_datetime_t datetime; /**< the four date/time types */
        struct {
            uint32_t first; /**< first child, or ROZ_TOML_NONE */
            uint32_t last;  /**< last child, or ROZ_TOML_NONE */
            uint32_t count; /**< number of children */
            uint32_t index; /**< tables: root of the key index; not API */
        } list;             /**< ROZ_TOML_TABLE, ROZ_TOML_ARRAY */
    } as;
} roz_toml_node_t;

/** A document over caller storage; see roz_toml_init(). */
typedef struct roz_toml_doc {
    roz_toml_node_t *nodes;      /**< node pool; nodes[0] is the root table */
    uint32_t         cap_nodes;  /**< pool size */
    uint32_t         n_nodes;    /**< nodes in use */
    char            *arena;      /**< bytes for decoded strings */
    size_t           arena_cap;  /**< arena size */
    size_t           arena_used; /**< arena bytes in use */
    const char      *text;       /**< the text parsed last */
    size_t           text_len;   /**< its length */
} roz_toml_doc_t;

/** What went wrong in roz_toml_parse(). */
typedef enum roz_toml_error_kind {
    ROZ_TOML_ERR_NONE = 0,
    ROZ_TOML_ERR_SYNTAX,      /**< not valid TOML (return ROZ_EINVAL) */
    ROZ_TOML_ERR_UTF8,        /**< not valid UTF-8; offset is the bad sequence (ROZ_EINVAL) */
    ROZ_TOML_ERR_UNSUPPORTED, /**< valid TOML this reader refuses (ROZ_ENOTSUP) */
    ROZ_TOML_ERR_NODES,       /**< the node pool is full (ROZ_ENOSPC) */
    ROZ_TOML_ERR_ARENA,       /**< the string arena is full (ROZ_ENOSPC) */
    ROZ_TOML_ERR_ARG          /**< bad argument (ROZ_EINVAL) */
} roz_toml_error_kind_t;

/** Where and why roz_toml_parse() stopped. */
typedef struct roz_toml_error {
    roz_toml_error_kind_t kind;
    uint32_t line;        /**< 1-based line of the error */
    uint32_t column;      /**< 1-based column, in bytes */
    size_t   offset;      /**< byte offset into the text (== length at its end) */
    char     message[ROZ_CFG_ERROR_LEN]; /**< what is wrong, no position, NUL-terminated */
} roz_toml_error_t;

/**
 * @brief File-scope storage for a document of @p n_nodes nodes and
 *        @p arena_bytes of string arena, and the document itself:
 *        `ROZ_TOML_DOC_DEFINE(doc, 4096, 16384);` then
 *        `roz_toml_init(&doc, doc_nodes, 4096, doc_arena, 16384);`
 */
#define ROZ_TOML_DOC_DEFINE(name, n_nodes, arena_bytes)                            \
    _Static_assert((n_nodes) > 0 && (arena_bytes) > 0,                             \
                   "ROZ_TOML_DOC_DEFINE: sizes must be > 0");                      \
    static roz_toml_node_t name##_nodes[(n_nodes)];                                \
    static char name##_arena[(arena_bytes)];                                       \
    static roz_toml_doc_t name

/**
 * @brief Attach a document to caller storage; the document is empty.
 * @param[out] doc          the document
 * @param[in]  nodes        pool of @p n_nodes nodes (at least 1, at most UINT32_MAX - 1)
 * @param[in]  arena        @p arena_bytes bytes for decoded strings (may be 0)
 * Context: any; does no I/O.
 */
void roz_toml_init(roz_toml_doc_t *doc, roz_toml_node_t *nodes, size_t n_nodes, char *arena,
                   size_t arena_bytes);

/**
 * @brief Parse TOML text into @p doc, replacing what it held.
 * @param[in,out] doc  an initialised document
 * @param[in]     text UTF-8 TOML, @p len bytes (need not be NUL-terminated);
 *                     must outlive the document (strings point into it)
 * @param[out]    err  optional: where and why parsing stopped
 * @retval ROZ_OK      parsed; roz_toml_root() is the document
 * @retval ROZ_EINVAL  invalid TOML or UTF-8, or NULL doc/text (see @p err)
 * @retval ROZ_ENOTSUP valid TOML that this reader refuses (see @p err)
 * @retval ROZ_ENOSPC  the node pool or the arena is full (see @p err)
 * On any error the document is empty again. Context: start-up or host
 * tools; O(n log n) in the text (see above); no heap, no recursion.
 */
ROZ_NODISCARD int roz_toml_parse(roz_toml_doc_t *doc, const char *text, size_t len,
                                 roz_toml_error_t *err);

/** @brief The root table; NULL if @p doc is NULL or holds no document.
 *  Context: any; no I/O. */
const roz_toml_node_t *roz_toml_root(const roz_toml_doc_t *doc);

/**
 * @brief The member of table @p table called @p key (NUL-terminated).
 * @param[in] doc    the document
 * @param[in] table  a table node of @p doc
 * @param[in] key    the key, decoded (as it reads, not as it is written)
 * @return the node, or NULL when there is none, @p table is not a table or
 *         an argument is NULL.
 * Context: any; O(log n) key comparisons in a table of n members.
 */
const roz_toml_node_t *roz_toml_get(const roz_toml_doc_t *doc, const roz_toml_node_t *table,
                                    const char *key);

/** @brief As roz_toml_get(), with a counted key (which may hold NUL).
 *  Context: any; O(log n) key comparisons in a table of n members. */
const roz_toml_node_t *roz_toml_get_n(const roz_toml_doc_t *doc, const roz_toml_node_t *table,
                                      const char *key, size_t key_len);

/** @brief First child of a table or array, in document order; NULL if none
 *  or if @p node is a value. Context: any; constant time. */
const roz_toml_node_t *roz_toml_first(const roz_toml_doc_t *doc, const roz_toml_node_t *node);

/** @brief Next sibling of @p node; NULL after the last. Context: any;
 *  constant time. */
const roz_toml_node_t *roz_toml_next(const roz_toml_doc_t *doc, const roz_toml_node_t *node);

/** @brief Parent of @p node; NULL for the root. Context: any; constant time. */
const roz_toml_node_t *roz_toml_parent(const roz_toml_doc_t *doc, const roz_toml_node_t *node);

/** @brief Element @p i of an array (or member @p i of a table); NULL if
 *  none. Context: any; linear in @p i. */
const roz_toml_node_t *roz_toml_at(const roz_toml_doc_t *doc, const roz_toml_node_t *node,
                                   size_t i);

/** @brief Number of children of a table or array; 0 for values and NULL.
 *  Context: any. */
size_t roz_toml_count(const roz_toml_node_t *node);

/** @brief "table", "array", "string", "integer", "float", "bool", "datetime",
 *         "datetime-local", "date-local", "time-local"; "?" otherwise.
 *  Context: any. */
const char *roz_toml_type_name(roz_toml_type_t type);

/**
 * @brief Write a date/time node as RFC 3339 text ("1979-05-27T07:32:00Z",
 *        "1979-05-27T00:32:00.999-07:00", "1979-05-27", "07:32:00"), with the
 *        fraction digits as written (at most 9).
 * @param[in]  node  a date/time node
 * @param[out] buf   @p cap bytes, NUL-terminated on success
 * @return the length written (without the NUL)
 * @retval ROZ_EINVAL @p node is not a date/time, or NULL arguments
 * @retval ROZ_ENOSPC @p cap is below 40
 * Context: any.
 */
int roz_toml_datetime_format(const roz_toml_node_t *node, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_TOML_H */
