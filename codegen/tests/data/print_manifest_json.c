/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Test helper for codegen/tests/test_compile.py: prints a manifest of the
 * generated registry in rozgen's canonical JSON (codegen/rozgen/canonical.py),
 * from the C tables and with printf alone, to show that a C tool can print
 * the same bytes as `rozgen --json`.
 *
 *   print_manifest_json <robot_id>   the manifest's JSON
 *   print_manifest_json --registry   check roz/builtin.h, print the ids
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "roz/builtin.h"

static const char *const interface_names[] = {
    "position", "velocity", "effort", "stiffness", "damping", "acceleration", "orientation",
};

/* JSON string, ASCII only: \uXXXX (UTF-16) for everything outside 0x20..0x7E. */
static void put_string(const char *s)
{
    const unsigned char *p = (const unsigned char *)s;

    putchar('"');
    while (*p != 0) {
        unsigned long cp = *p++;
        int extra = 0;

        if (cp >= 0xF0) {
            cp &= 0x07;
            extra = 3;
        } else if (cp >= 0xE0) {
            cp &= 0x0F;
            extra = 2;
        } else if (cp >= 0xC0) {
            cp &= 0x1F;
            extra = 1;
        }
        for (; extra > 0 && *p != 0; extra--) {
            cp = (cp << 6) | (*p++ & 0x3Fu);
        }
        switch (cp) {
        case '"': fputs("\\\"", stdout); break;
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

/* Shortest round-trip %g, integral values below 1e16 without exponent. */
static void put_double(double x)
{
    char buf[64];
    const char *e;
    int p;

    for (p = 1; p <= 17; p++) {
        snprintf(buf, sizeof buf, "%.*g", p, x);
        if (strtod(buf, NULL) == x) {
            break;
        }
    }
    e = strchr(buf, 'e');
    if (e != NULL && atoi(e + 1) >= 0 && atoi(e + 1) < 16) {
        snprintf(buf, sizeof buf, "%.*g", atoi(e + 1) + 1, x);
    }
    fputs(buf, stdout);
}

static void put_channels(const char *key, const roz_channel_t *c, uint16_t n)
{
    uint16_t i;

    printf("  \"%s\": [", key);
    for (i = 0; i < n; i++) {
        fputs(i == 0 ? "\n    {\"name\": " : ",\n    {\"name\": ", stdout);
        put_string(c[i].name);
        fputs(", \"interface_type\": ", stdout);
        put_string(interface_names[c[i].type]);
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
    uint16_t i;

    fputs("{\n  \"robot_id\": ", stdout);
    put_string(m->robot_id);
    fputs(",\n  \"robot_class\": ", stdout);
    put_string(m->robot_class);
    printf(",\n  \"control_rate_hz\": %lu,\n", (unsigned long)m->control_rate_hz);
    put_channels("commands", m->commands, m->n_commands);
    put_channels("states", m->states, m->n_states);
    fputs("  \"hardware\": ", stdout);
    if (m->hardware == NULL) {
        fputs("null", stdout);
    } else {
        fputs("{\"port\": ", stdout);
        put_string(m->hardware->port);
        fputs(", \"joints\": [", stdout);
        for (i = 0; i < m->hardware->n_joints; i++) {
            fputs(i == 0 ? "" : ", ", stdout);
            put_string(m->hardware->joints[i]);
        }
        fputs("], \"params\": {", stdout);
        for (i = 0; i < m->hardware->n_params; i++) {
            fputs(i == 0 ? "" : ", ", stdout);
            put_string(m->hardware->params[i].key);
            fputs(": ", stdout);
            put_string(m->hardware->params[i].value);
        }
        fputs("}}", stdout);
    }
    fputs("\n}\n", stdout);
}

static int check_registry(void)
{
    size_t i, n = roz_builtin_count();

    if (n == 0 || roz_builtin_at(n) != NULL || roz_builtin_find(NULL) != NULL ||
        roz_builtin_find("no such robot") != NULL) {
        return 1;
    }
    for (i = 0; i < n; i++) {
        const roz_manifest_t *m = roz_builtin_at(i);

        if (m == NULL || roz_builtin_find(m->robot_id) != m ||
            (i > 0 && strcmp(roz_builtin_at(i - 1)->robot_id, m->robot_id) >= 0)) {
            return 1;
        }
        printf("%s\n", m->robot_id);
    }
    return 0;
}

int main(int argc, char **argv)
{
    const roz_manifest_t *m;

    if (argc != 2) {
        return 2;
    }
    if (strcmp(argv[1], "--registry") == 0) {
        return check_registry();
    }
    m = roz_builtin_find(argv[1]);
    if (m == NULL) {
        return 1;
    }
    put_manifest(m);
    return 0;
}
