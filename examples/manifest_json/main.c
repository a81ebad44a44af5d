/* SPDX-License-Identifier: Apache-2.0 */
/*
 * roz_manifest_json: load a robot.toml at run time with roz's C reader
 * (roz/manifest_toml.h) and print what `rozgen --json` prints for it, byte
 * for byte: the canonical JSON (codegen/rozgen/canonical.py) on stdout, or
 * the problems on stderr, one per line, as rozgen prints them.
 *
 *   roz_manifest_json [--check] [--error-ids] FILE
 *
 *   --check      validate only, print nothing when the file is valid
 *   --error-ids  prefix every problem with its rule id: [limits-order] ...
 *
 * Exit status: 0 valid, 2 on any problem or a usage error (as rozgen).
 * test/toml/compare_vectors.py runs both on every shared test vector.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "roz/manifest_toml.h"

#define MAX_FILE (8u << 20)
#define MAX_PROBLEMS 4096u

static char text[MAX_FILE];
static roz_manifest_storage_t storage;
static roz_manifest_toml_problem_t problems[MAX_PROBLEMS];
ROZ_TOML_DOC_DEFINE(doc, 1u << 19, 4u << 20);

/* json.dumps(s, ensure_ascii=True): \uXXXX (UTF-16, lower-case hex) for
 * everything outside printable ASCII. */
static void put_string(const char *s)
{
    const unsigned char *p = (const unsigned char *)s;
    putchar('"');
    while (*p != 0) {
        unsigned long cp = *p++;
        int more = cp >= 0xF0 ? 3 : cp >= 0xE0 ? 2 : cp >= 0xC0 ? 1 : 0;
        if (more > 0)
            cp &= 0x3Fu >> more;
        for (; more > 0 && *p != 0; more--)
            cp = (cp << 6) | (*p++ & 0x3Fu);
        switch (cp) {
        case '"':  fputs("\\\"", stdout); break;
        case '\\': fputs("\\\\", stdout); break;
        case '\b': fputs("\\b", stdout); break;
        case '\f': fputs("\\f", stdout); break;
        case '\n': fputs("\\n", stdout); break;
        case '\r': fputs("\\r", stdout); break;
        case '\t': fputs("\\t", stdout); break;
        default:
            if (cp >= 0x20 && cp < 0x7F) {
                putchar((int)cp);
            } else if (cp >= 0x10000) {
                cp -= 0x10000;
                printf("\\u%04lx\\u%04lx", 0xD800 + (cp >> 10), 0xDC00 + (cp & 0x3FF));
            } else {
                printf("\\u%04lx", cp);
            }
        }
    }
    putchar('"');
}

/* rozgen.fmt.shortest_g (this program keeps the "C" locale). */
static void put_double(double x)
{
    char buf[40];
    const char *e;
    for (int p = 1; p <= 17; p++) {
        snprintf(buf, sizeof buf, "%.*g", p, x);
        if (strtod(buf, NULL) == x)
            break;
    }
    e = strchr(buf, 'e');
    if (e != NULL && atoi(e + 1) >= 0 && atoi(e + 1) < 16)
        snprintf(buf, sizeof buf, "%.*g", atoi(e + 1) + 1, x);
    fputs(buf, stdout);
}

static void put_channels(const char *key, const roz_channel_t *c, uint16_t n)
{
    printf("  \"%s\": [", key);
    for (uint16_t i = 0; i < n; i++) {
        fputs(i == 0 ? "\n    {\"name\": " : ",\n    {\"name\": ", stdout);
        put_string(c[i].name);
        fputs(", \"interface_type\": ", stdout);
        put_string(roz_interface_name(c[i].type));
        fputs(", \"unit\": ", stdout);
        put_string(c[i].unit);
        fputs(", \"limits\": [", stdout);
        put_double(c[i].min);
        fputs(", ", stdout);
        put_double(c[i].max);
        fputs("], \"default\": ", stdout);
        put_double(c[i].default_value);
        fputs(", \"max_rate_of_change\": ", stdout);
        put_double(c[i].max_rate);
        printf(", \"position_state_index\": %ld}", (long)c[i].position_state);
    }
    fputs(n == 0 ? "],\n" : "\n  ],\n", stdout);
}

static void put_manifest(const roz_manifest_t *m)
{
    const roz_hardware_t *h = m->hardware;
    fputs("{\n  \"robot_id\": ", stdout);
    put_string(m->robot_id);
    fputs(",\n  \"robot_class\": ", stdout);
    put_string(m->robot_class);
    printf(",\n  \"control_rate_hz\": %lu,\n", (unsigned long)m->control_rate_hz);
    put_channels("commands", m->commands, m->n_commands);
    put_channels("states", m->states, m->n_states);
    fputs("  \"hardware\": ", stdout);
    if (h == NULL) {
        fputs("null", stdout);
    } else {
        fputs("{\"port\": ", stdout);
        put_string(h->port);
        fputs(", \"joints\": [", stdout);
        for (uint16_t i = 0; i < h->n_joints; i++) {
            fputs(i == 0 ? "" : ", ", stdout);
            put_string(h->joints[i]);
        }
        fputs("], \"params\": {", stdout);
        for (uint16_t i = 0; i < h->n_params; i++) {
            fputs(i == 0 ? "" : ", ", stdout);
            put_string(h->params[i].key);
            fputs(": ", stdout);
            put_string(h->params[i].value);
        }
        fputs("}}", stdout);
    }
    fputs("\n}\n", stdout);
}

static int usage(void)
{
    fprintf(stderr, "usage: roz_manifest_json [--check] [--error-ids] FILE\n");
    return 2;
}

int main(int argc, char **argv)
{
    const char *file = NULL;
    int check = 0, ids = 0, rc;
    size_t found = 0;

    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--check") == 0)
            check = 1;
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
    if (file == NULL)
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
    if (!check)
        put_manifest(&storage.manifest);
    return 0;
}
