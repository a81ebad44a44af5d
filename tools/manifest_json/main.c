/* SPDX-License-Identifier: Apache-2.0 */
/*
 * roz_manifest_json: load a robot.toml at run time with roz's C reader
 * (roz/manifest_toml.h) and print what `rozgen --json` prints for it, byte
 * for byte: the canonical JSON (codegen/rozgen/canonical.py) on stdout, or
 * the problems on stderr, one per line, as rozgen prints them. A robot for
 * the socketcan port (hardware.port = "socketcan") also passes that port's
 * checks of its [hardware] keys (roz/port/can_config.h), as in rozgen. The DDS
 * ports check theirs at open (test/ports/common/test_port_vectors.c holds them to
 * rozgen on the same vectors).
 *
 *   roz_manifest_json [--check | --identity] [--error-ids] FILE
 *
 *   --check      validate only, print nothing when the file is valid
 *   --identity   print "<robot_id> <interface hash>" as `rozgen --identity`
 *                does, the hash computed from the loaded manifest
 *                (roz_manifest_interface_hash())
 *   --error-ids  prefix every problem with its rule id: [limits-order] ...
 *
 * Exit status: 0 valid, 2 on any problem or a usage error (as rozgen).
 * test/toml/compare_vectors.py runs both on every shared test vector.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "roz/port/can_config.h"
#include "roz/identity.h"
#include "roz/manifest_toml.h"

#define MAX_FILE (8u << 20)
#define MAX_PROBLEMS 4096u

static char text[MAX_FILE];
static roz_manifest_storage_t storage;
static roz_manifest_toml_problem_t problems[MAX_PROBLEMS];
ROZ_TOML_DOC_DEFINE(doc, 1u << 19, 4u << 20);

typedef struct {
    const char *file;
    int         ids;
} printer_t;

static void print_problem(void *ctx, const char *rule, const char *what)
{
    const printer_t *p = ctx;
    fprintf(stderr, "%s%s%s%s%s\n", p->ids ? "[" : "", p->ids ? rule : "", p->ids ? "] " : "",
            p->file, what);
}

/* A port's checks of its own [hardware] keys, after the generic ones. */
static int port_checks(const roz_manifest_t *m, const char *file, int ids)
{
    static roz_can_config_t can;
    printer_t p = { file, ids };
    if (m->hardware == NULL || strcmp(m->hardware->port, "socketcan") != 0)
        return 0;
    return roz_can_config_load(&can, m, NULL, print_problem, &p) == ROZ_OK ? 0 : 2;
}

static int usage(void)
{
    fprintf(stderr, "usage: roz_manifest_json [--check | --identity] [--error-ids] FILE\n");
    return 2;
}

int main(int argc, char **argv)
{
    const char *file = NULL;
    int check = 0, identity = 0, ids = 0, rc;
    size_t found = 0;

    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--check") == 0)
            check = 1;
        else if (strcmp(argv[i], "--identity") == 0)
            identity = 1;
        else if (strcmp(argv[i], "--error-ids") == 0)
            ids = 1;
        else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return usage() - 2;
        else if (argv[i][0] == '-' && argv[i][1] != '\0')
            return usage();
        else if (file == NULL)
            file = argv[i];
        else
            return usage();
    }
    if (file == NULL || (check && identity))
        return usage();

    roz_toml_init(&doc, doc_nodes, sizeof doc_nodes / sizeof doc_nodes[0], doc_arena,
                  sizeof doc_arena);
    rc = roz_manifest_toml_load_file(file, text, sizeof text, &storage, &doc, problems,
                                     MAX_PROBLEMS, &found);
    if (rc != ROZ_OK) {
        size_t shown = found < MAX_PROBLEMS ? found : MAX_PROBLEMS;
        for (size_t i = 0; i < shown; i++)
            fprintf(stderr, "%s%s%s%s%s\n", ids ? "[" : "", ids ? problems[i].rule : "",
                    ids ? "] " : "", file, problems[i].text);
        if (found > shown)
            fprintf(stderr, "roz_manifest_json: %lu more problems not shown\n",
                    (unsigned long)(found - shown));
        if (found == 0)
            fprintf(stderr, "%s: %s\n", file, roz_strerror(rc));
        return 2;
    }
    if (port_checks(&storage.manifest, file, ids) != 0)
        return 2;
    if (identity)
        printf("%s %016llx\n", storage.manifest.robot_id,
               (unsigned long long)roz_manifest_interface_hash(&storage.manifest));
    else if (!check)
        manifest_json_print(&storage.manifest);
    return 0;
}
