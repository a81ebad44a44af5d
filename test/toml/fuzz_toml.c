/* SPDX-License-Identifier: Apache-2.0 */
/*
 * libFuzzer target for roz's TOML reader and robot.toml loader (built by
 * test/toml/CMakeLists.txt in the clang ASan build; test/toml/fuzz.sh runs
 * it for longer). Besides the sanitizers' own checks it asserts:
 *
 *  - a parsed document is a well-formed tree: every child's parent link
 *    points back, counts match, strings lie in the text or the arena, and
 *    no node is reached twice;
 *  - an error has a kind that matches its return code, a position inside
 *    the text and a message;
 *  - storage exhaustion is a clean ROZ_ENOSPC (a second parse into tiny
 *    storage);
 *  - a manifest that the loader accepts passes roz_manifest_validate(), so
 *    the loader never builds what the core would refuse; a refused one has
 *    at least one problem with a rule id and a message.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "roz/manifest_toml.h"
#include "roz/toml.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define NODES 4096u
#define ARENA 16384u

static roz_toml_node_t nodes[NODES];
static char arena[ARENA];
static roz_toml_node_t tiny_nodes[12];
static char tiny_arena[24];
static roz_manifest_storage_t storage;
static roz_manifest_toml_problem_t problems[4];

static void check(int ok)
{
    if (!ok)
        abort();
}

static int inside(const char *p, size_t n, const char *base, size_t len)
{
    return p >= base && p + n <= base + len;
}

static void check_string(const roz_toml_doc_t *d, roz_toml_string_t s)
{
    check(s.len == 0 || inside(s.ptr, s.len, d->text, d->text_len) ||
          inside(s.ptr, s.len, d->arena, d->arena_used));
}

/* Walks the tree without recursion and checks its links. */
static void check_tree(const roz_toml_doc_t *d)
{
    static uint8_t seen[NODES];
    const roz_toml_node_t *root = roz_toml_root(d), *n = root;
    uint32_t visited = 0;
    check(root != NULL && root->type == ROZ_TOML_TABLE && roz_toml_parent(d, root) == NULL);
    memset(seen, 0, d->n_nodes);
    for (;;) {
        uint32_t i = (uint32_t)(n - d->nodes);
        check(i < d->n_nodes && !seen[i]);
        seen[i] = 1;
        visited++;
        check(n->type < ROZ_TOML_TYPE_COUNT_);
        if (n->type == ROZ_TOML_STRING)
            check_string(d, n->as.str);
        if (n->type == ROZ_TOML_TABLE || n->type == ROZ_TOML_ARRAY) {
            size_t count = 0;
            for (const roz_toml_node_t *c = roz_toml_first(d, n); c != NULL;
                 c = roz_toml_next(d, c)) {
                check(roz_toml_parent(d, c) == n);
                check((n->type == ROZ_TOML_TABLE) == (c->key.ptr != NULL));
                if (n->type == ROZ_TOML_TABLE) {
                    check_string(d, c->key);
                    check(roz_toml_get_n(d, n, c->key.ptr, c->key.len) == c); /* keys unique */
                }
                count++;
            }
            check(count == roz_toml_count(n));
            if (roz_toml_first(d, n) != NULL) {
                n = roz_toml_first(d, n);
                continue;
            }
        }
        while (n != root && roz_toml_next(d, n) == NULL)
            n = roz_toml_parent(d, n);
        if (n == root)
            break;
        n = roz_toml_next(d, n);
    }
    check(visited == d->n_nodes); /* no node left unlinked */
}

static void check_error(int rc, const roz_toml_error_t *e, size_t size)
{
    switch (e->kind) {
    case ROZ_TOML_ERR_SYNTAX:
    case ROZ_TOML_ERR_UTF8:        check(rc == ROZ_EINVAL); break;
    case ROZ_TOML_ERR_UNSUPPORTED: check(rc == ROZ_ENOTSUP); break;
    case ROZ_TOML_ERR_NODES:
    case ROZ_TOML_ERR_ARENA:       check(rc == ROZ_ENOSPC); break;
    default:                       check(0);
    }
    check(e->offset <= size && e->line >= 1 && e->column >= 1 && e->message[0] != '\0');
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *text = (const char *)data;
    roz_toml_doc_t doc, tiny;
    roz_toml_error_t err;
    size_t found = 0;
    int rc;

    roz_toml_init(&doc, nodes, NODES, arena, ARENA);
    rc = roz_toml_parse(&doc, text, size, &err);
    if (rc == ROZ_OK)
        check_tree(&doc);
    else
        check_error(rc, &err, size);

    roz_toml_init(&tiny, tiny_nodes, 12, tiny_arena, sizeof tiny_arena);
    rc = roz_toml_parse(&tiny, text, size, &err);
    if (rc == ROZ_OK)
        check_tree(&tiny);
    else
        check_error(rc, &err, size);

    rc = roz_manifest_toml_load(&storage, &doc, text, size, problems, 4, &found);
    if (rc == ROZ_OK) {
        roz_manifest_problem_t why;
        check(found == 0);
        check(roz_manifest_validate(&storage.manifest, &why) == ROZ_OK);
    } else {
        check(found >= 1 && problems[0].rule != NULL && problems[0].text[0] == ':');
    }
    return 0;
}
