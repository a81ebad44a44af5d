/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The decoder that the toml-test suite drives (test/toml/run_toml_test.cmake):
 * reads TOML on stdin with roz's reader and prints toml-test's tagged JSON on
 * stdout,
 *
 *   {"key": {"type": "integer", "value": "1"}, "t": {"a": [ ... ]}}
 *
 * exit 0; or the reader's error on stderr, exit 1. The tree is walked
 * through the nodes' parent links, without recursion.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "roz/toml.h"

#define MAX_TEXT (4u << 20)

static char text[MAX_TEXT];
ROZ_TOML_DOC_DEFINE(doc, 1u << 18, 4u << 20);

static void put_json_string(const char *s, size_t n)
{
    putchar('"');
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == '"' || c == '\\')
            printf("\\%c", c);
        else if (c < 0x20)
            printf("\\u%04x", c);
        else
            putchar(c);
    }
    putchar('"');
}

static void put_scalar(const roz_toml_node_t *n)
{
    char buf[64];
    printf("{\"type\": \"%s\", \"value\": ", roz_toml_type_name((roz_toml_type_t)n->type));
    switch (n->type) {
    case ROZ_TOML_STRING:
        put_json_string(n->as.str.ptr, n->as.str.len);
        break;
    case ROZ_TOML_INTEGER:
        printf("\"%lld\"", (long long)n->as.integer);
        break;
    case ROZ_TOML_FLOAT:
        if (isnan(n->as.real))
            printf("\"nan\"");
        else if (isinf(n->as.real))
            printf("\"%sinf\"", n->as.real < 0 ? "-" : "");
        else
            printf("\"%.17g\"", n->as.real);
        break;
    case ROZ_TOML_BOOL:
        printf("\"%s\"", n->as.boolean ? "true" : "false");
        break;
    default:
        if (roz_toml_datetime_format(n, buf, sizeof buf) < 0)
            buf[0] = '\0';
        printf("\"%s\"", buf);
        break;
    }
    putchar('}');
}

static int is_container(const roz_toml_node_t *n)
{
    return n->type == ROZ_TOML_TABLE || n->type == ROZ_TOML_ARRAY;
}

static void put_document(const roz_toml_doc_t *d)
{
    const roz_toml_node_t *root = roz_toml_root(d), *n = root;
    int down = 1; /* entering n (1) or leaving it (0) */

    for (;;) {
        if (down) {
            const roz_toml_node_t *up = roz_toml_parent(d, n);
            if (up != NULL && up->type == ROZ_TOML_TABLE) {
                put_json_string(n->key.ptr, n->key.len);
                fputs(": ", stdout);
            }
            if (is_container(n)) {
                const roz_toml_node_t *first = roz_toml_first(d, n);
                putchar(n->type == ROZ_TOML_TABLE ? '{' : '[');
                if (first != NULL) {
                    n = first;
                    continue;
                }
                putchar(n->type == ROZ_TOML_TABLE ? '}' : ']');
            } else {
                put_scalar(n);
            }
        }
        if (n == root)
            break;
        const roz_toml_node_t *next = roz_toml_next(d, n);
        if (next != NULL) {
            fputs(", ", stdout);
            n = next;
            down = 1;
            continue;
        }
        n = roz_toml_parent(d, n);
        putchar(n->type == ROZ_TOML_TABLE ? '}' : ']');
        down = 0;
    }
    putchar('\n');
}

int main(void)
{
    roz_toml_error_t err;
    size_t len = fread(text, 1, sizeof text, stdin);
    int rc;

    if (ferror(stdin) || len == sizeof text) {
        fprintf(stderr, "toml_decoder: cannot read stdin (at most %u bytes)\n", MAX_TEXT - 1u);
        return 1;
    }
    roz_toml_init(&doc, doc_nodes, sizeof doc_nodes / sizeof doc_nodes[0], doc_arena,
                  sizeof doc_arena);
    rc = roz_toml_parse(&doc, text, len, &err);
    if (rc != ROZ_OK) {
        fprintf(stderr, "<stdin>:%u:%u: %s (%s)\n", (unsigned)err.line, (unsigned)err.column,
                err.message, roz_strerror(rc));
        return 1;
    }
    put_document(&doc);
    return 0;
}
