/* SPDX-License-Identifier: Apache-2.0 */
/*
 * roz_manifest_info: prints the built-in manifests roz knows.
 *
 *   roz_manifest_info            one line per built-in manifest
 *   roz_manifest_info ID...      every channel of the named manifests
 *   roz_manifest_info --all      every channel of every built-in
 */
#include <stdio.h>
#include <string.h>

#include "roz/builtin.h"
#include "roz/manifest.h"

static void print_summary(void)
{
    printf("%-16s %-12s %8s %8s %6s  %s\n", "id", "class", "rate_hz", "commands", "states",
           "port");
    for (size_t i = 0; i < roz_builtin_count(); i++) {
        const roz_manifest_t *m = roz_builtin_at(i);
        printf("%-16s %-12s %8u %8u %6u  %s\n", m->robot_id, m->robot_class,
               (unsigned)m->control_rate_hz, (unsigned)m->n_commands, (unsigned)m->n_states,
               m->hardware != NULL ? m->hardware->port : "-");
    }
}

/* margin: the limit margin of position states (the filter's, default worked out) */
static void print_channels(const char *title, const roz_channel_t *c, uint16_t n, int states)
{
    printf("  %s (%u)\n", title, (unsigned)n);
    printf("  %4s  %-40s %-12s %-10s %12s %12s %10s %10s %6s %10s\n", "idx", "name", "type",
           "unit", "min", "max", "default", "max_rate", "pair", "margin");
    for (uint16_t i = 0; i < n; i++) {
        char pair[16] = "-", margin[24] = "-";
        if (c[i].position_state != ROZ_CHANNEL_UNPAIRED)
            snprintf(pair, sizeof pair, "%d", (int)c[i].position_state);
        if (states && c[i].type == ROZ_IF_POSITION)
            snprintf(margin, sizeof margin, "%.6g", roz_manifest_limit_margin(&c[i]));
        printf("  %4u  %-40s %-12s %-10s %12.6g %12.6g %10.6g %10.6g %6s %10s\n", (unsigned)i,
               c[i].name, roz_interface_name(c[i].type), c[i].unit, c[i].min, c[i].max,
               c[i].default_value, c[i].max_rate, pair, margin);
    }
}

static void print_manifest(const roz_manifest_t *m)
{
    printf("\n%s: class %s, %u Hz\n", m->robot_id, m->robot_class, (unsigned)m->control_rate_hz);
    if (m->hardware != NULL) {
        printf("  hardware: port %s, %u joints", m->hardware->port,
               (unsigned)m->hardware->n_joints);
        for (uint16_t i = 0; i < m->hardware->n_params; i++)
            printf(", %s=%s", m->hardware->params[i].key, m->hardware->params[i].value);
        printf("\n");
    }
    print_channels("commands", m->commands, m->n_commands, 0);
    print_channels("states", m->states, m->n_states, 1);
}

int main(int argc, char **argv)
{
    int rc = 0;

    if (argc == 1) {
        print_summary();
        return 0;
    }
    for (int a = 1; a < argc; a++) {
        if (strcmp(argv[a], "--help") == 0 || strcmp(argv[a], "-h") == 0) {
            printf("usage: %s [--all | ID...]\n", argv[0]);
            return 0;
        }
        if (strcmp(argv[a], "--all") == 0) {
            print_summary();
            for (size_t i = 0; i < roz_builtin_count(); i++)
                print_manifest(roz_builtin_at(i));
            continue;
        }
        const roz_manifest_t *m = roz_builtin_find(argv[a]);
        if (m == NULL) {
            fprintf(stderr, "%s: no built-in manifest \"%s\"; known:", argv[0], argv[a]);
            for (size_t i = 0; i < roz_builtin_count(); i++)
                fprintf(stderr, " %s", roz_builtin_at(i)->robot_id);
            fprintf(stderr, "\n");
            rc = 2;
            continue;
        }
        print_manifest(m);
    }
    return rc;
}
