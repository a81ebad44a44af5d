/* SPDX-License-Identifier: Apache-2.0 */
/*
 * roz_manifest_json: check a robot.toml with the robot.toml rules (their one
 * implementation, roz/manifest_toml.h, and the rules of its port's own
 * [hardware] keys that the port registered, roz/port_rules.h) and print
 * the canonical JSON of `rozgen --json` on stdout, or the problems on stderr,
 * one per line, as rozgen prints them. rozgen runs it for every robot.toml
 * (--rozgen); the DDS ports check their keys at open (and rozgen with them,
 * test_port_vectors).
 *
 *   roz_manifest_json [--check | --identity | --rozgen] [--error-ids]
 *                     [--max-commands N] [--max-states N] [--max-name-len N]
 *                     [--origin ROBOT_TOML] FILE
 *   roz_manifest_json --list-rules
 *
 *   --check      validate only, print nothing when the file is valid
 *   --identity   print "<robot_id> <interface hash>" as `rozgen --identity`
 *                does, the hash computed from the loaded manifest
 *                (roz_manifest_interface_hash())
 *   --rozgen     for rozgen (codegen/rozgen/checker.py): every problem on
 *                stdout as "<rule>\t<text after the file name>", or the JSON
 *                with each limit_margin as written; FILE "-" is stdin
 *   --error-ids  prefix every problem with its rule id: [limits-order] ...
 *   --max-*      the maxima of the build the tables are for (rozgen's
 *                options); default this build's ROZ_CFG_MAX_*
 *   --list-rules the ports' rule ids this build holds and what each
 *                refuses, "<id>\t<what>" a line (rozgen --list-rules)
 *   --origin     the path of the robot.toml read from stdin (FILE "-"):
 *                the files its keys name (a model) are taken relative to
 *                its folder and named so in the messages; default FILE
 *
 * Exit status: 0 valid, 2 on any problem or a usage error (as rozgen).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "roz/identity.h"
#include "roz/manifest_toml.h"
#include "roz/port_rules.h"

#define MAX_FILE (8u << 20)
#define MAX_PROBLEMS 4096u

static char text[MAX_FILE];
static roz_manifest_storage_t storage;
static roz_manifest_toml_problem_t problems[MAX_PROBLEMS];
ROZ_TOML_DOC_DEFINE(doc, 1u << 19, 4u << 20);

typedef struct {
    const char *file;
    int         ids;
    int         rozgen;
} printer_t;

static void print_problem(void *ctx, const char *rule, const char *what)
{
    const printer_t *p = ctx;
    if (p->rozgen)
        printf("%s\t%s\n", rule, what);
    else
        fprintf(stderr, "%s%s%s%s%s\n", p->ids ? "[" : "", p->ids ? rule : "",
                p->ids ? "] " : "", p->file, what);
}

/* The port's rules of its own [hardware] keys, after the robot.toml ones,
 * when this build holds them (roz/port_rules.h), then its rules on the
 * files they name (taken relative to @p origin's folder). */
static int port_checks(const roz_manifest_t *m, const char *origin, printer_t *p)
{
    const roz_port_rules_t *r = m->hardware != NULL ? roz_port_rules_find(m->hardware->port)
                                                    : NULL;
    if (r == NULL)
        return 0;
    if (r->check_hardware(m, print_problem, p) != ROZ_OK)
        return 2;
    if (r->check_files != NULL && r->check_files(m, origin, print_problem, p) != ROZ_OK)
        return 2;
    return 0;
}

/* Every registered port's rule ids, once each, in registration order. */
static int list_rules(void)
{
    const roz_port_rules_t *r;
    for (size_t i = 0; (r = roz_port_rules_at(i)) != NULL; i++) {
        for (const char *const *row = r->rule_ids; *row != NULL; row++) {
            const char *tab = strchr(*row, '\t');
            size_t n = tab != NULL ? (size_t)(tab - *row) + 1 : strlen(*row);
            int seen = 0;
            for (size_t k = 0; k < i && !seen; k++) {
                for (const char *const *o = roz_port_rules_at(k)->rule_ids; *o && !seen; o++)
                    seen = strncmp(*o, *row, n) == 0;
            }
            if (!seen)
                printf("%s\n", *row);
        }
    }
    return 0;
}

static int usage(void)
{
    fprintf(stderr, "usage: roz_manifest_json [--check | --identity | --rozgen] [--error-ids]\n"
                    "                         [--max-commands N] [--max-states N] "
                    "[--max-name-len N]\n"
                    "                         [--origin ROBOT_TOML] FILE\n"
                    "       roz_manifest_json --list-rules\n");
    return 2;
}

/* A --max-* value: decimal, 1..@hi. */
static int maximum(const char *option, const char *value, uint32_t hi, uint32_t *out)
{
    char *end;
    unsigned long v = value != NULL ? strtoul(value, &end, 10) : 0;
    if (value == NULL || value[0] < '0' || value[0] > '9' || *end != '\0' || v < 1 || v > hi) {
        fprintf(stderr, "roz_manifest_json: %s %s: expected 1..%lu (what this build holds)\n",
                option, value != NULL ? value : "(missing)", (unsigned long)hi);
        return 0;
    }
    *out = (uint32_t)v;
    return 1;
}

/* FILE "-": the bytes on stdin. */
static int read_stdin(size_t *len)
{
    *len = fread(text, 1, sizeof text, stdin);
    if (ferror(stdin) || (*len == sizeof text && fgetc(stdin) != EOF)) {
        fprintf(stderr, "roz_manifest_json: cannot read stdin (at most %lu bytes)\n",
                (unsigned long)sizeof text);
        return 0;
    }
    return 1;
}

int main(int argc, char **argv)
{
    const char *file = NULL, *origin = NULL;
    int check = 0, identity = 0, ids = 0, rozgen = 0, rc;
    roz_manifest_toml_maxima_t max = { ROZ_CFG_MAX_COMMANDS, ROZ_CFG_MAX_STATES,
                                       ROZ_CFG_MAX_NAME_LEN };
    size_t found = 0, len = 0;
    printer_t printer;

    for (int i = 1; i < argc; i++) {
        const char *next = i + 1 < argc ? argv[i + 1] : NULL;
        rc = 1; /* 0: a bad --max-* value, already said */
        if (strcmp(argv[i], "--check") == 0)
            check = 1;
        else if (strcmp(argv[i], "--identity") == 0)
            identity = 1;
        else if (strcmp(argv[i], "--rozgen") == 0)
            rozgen = 1;
        else if (strcmp(argv[i], "--error-ids") == 0)
            ids = 1;
        else if (strcmp(argv[i], "--max-commands") == 0)
            rc = maximum(argv[i++], next, ROZ_CFG_MAX_COMMANDS, &max.commands);
        else if (strcmp(argv[i], "--max-states") == 0)
            rc = maximum(argv[i++], next, ROZ_CFG_MAX_STATES, &max.states);
        else if (strcmp(argv[i], "--max-name-len") == 0)
            rc = maximum(argv[i++], next, ROZ_MANIFEST_TOML_MAX_NAME_LEN, &max.name_len);
        else if (strcmp(argv[i], "--list-rules") == 0 && argc == 2)
            return list_rules();
        else if (strcmp(argv[i], "--origin") == 0 && next != NULL)
            origin = argv[++i];
        else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return usage() - 2;
        else if (argv[i][0] == '-' && argv[i][1] != '\0')
            return usage();
        else if (file == NULL)
            file = argv[i];
        else
            return usage();
        if (rc == 0)
            return 2;
    }
    if (file == NULL || check + identity + rozgen > 1)
        return usage();
    printer.file = file;
    printer.ids = ids;
    printer.rozgen = rozgen;

    roz_toml_init(&doc, doc_nodes, sizeof doc_nodes / sizeof doc_nodes[0], doc_arena,
                  sizeof doc_arena);
    if (strcmp(file, "-") == 0) {
        if (!read_stdin(&len))
            return 2;
        rc = ROZ_OK;
    } else {
        rc = roz_manifest_toml_read_file(file, text, sizeof text, &len, &problems[0]);
        found = rc == ROZ_OK ? 0u : 1u;
    }
    if (rc == ROZ_OK)
        rc = roz_manifest_toml_load_for(&storage, &doc, text, len, &max, problems, MAX_PROBLEMS,
                                        &found);
    if (rc != ROZ_OK) {
        size_t shown = found < MAX_PROBLEMS ? found : MAX_PROBLEMS;
        for (size_t i = 0; i < shown; i++)
            print_problem(&printer, problems[i].rule, problems[i].text);
        if (found > shown)
            fprintf(stderr, "roz_manifest_json: %lu more problems not shown\n",
                    (unsigned long)(found - shown));
        if (found == 0)
            fprintf(stderr, "%s: %s\n", file, roz_strerror(rc));
        return 2;
    }
    if (origin == NULL && strcmp(file, "-") != 0)
        origin = file;
    if (port_checks(&storage.manifest, origin, &printer) != 0)
        return 2;
    if (identity)
        printf("%s %016llx\n", storage.manifest.robot_id,
               (unsigned long long)roz_manifest_interface_hash(&storage.manifest));
    else if (!check)
        manifest_json_print(&storage.manifest, rozgen);
    return 0;
}
