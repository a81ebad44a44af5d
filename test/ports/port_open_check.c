/* SPDX-License-Identifier: Apache-2.0 */
/*
 * port_open_check: opens each robot.toml given through its DDS port, as
 * rozrun would with no --param, and says what the open says:
 *
 *   port_open_check FILE...
 *
 * one line per file on stdout: "FILE: ok" when the port opens (and is
 * closed again), "FILE: <the port's error>" when it refuses,
 * "FILE: [loader] ..." when roz's C loader refuses the file, "FILE: [no DDS
 * port]" for a robot of another port. test/ports/port_agreement.py compares
 * these with rozgen's verdict on the same files. Exit status 0, or 2 on a
 * usage error.
 */
#include <stdio.h>
#include <string.h>

#include "roz/agibot_x2.h"
#include "roz/engineai_pm01.h"
#include "roz/manifest_toml.h"
#include "roz/unitree_g1.h"

#define MAX_PROBLEMS 64

static char text[1u << 20];
static roz_manifest_storage_t storage;
static roz_manifest_toml_problem_t problems[MAX_PROBLEMS];
ROZ_TOML_DOC_DEFINE(doc, 1u << 16, 1u << 20);

static roz_unitree_g1_t g1;
static roz_agibot_x2_t x2;
static roz_engineai_pm01_t pm01;

static void quiet(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    (void)level;
    (void)msg;
}

static void check(const char *file)
{
    char err[1024];
    size_t found = 0;
    roz_port_t port;

    roz_toml_init(&doc, doc_nodes, sizeof doc_nodes / sizeof doc_nodes[0], doc_arena,
                  sizeof doc_arena);
    if (roz_manifest_toml_load_file(file, text, sizeof text, &storage, &doc, problems,
                                    MAX_PROBLEMS, &found) != ROZ_OK) {
        printf("%s: [loader] %s\n", file, found > 0 ? problems[0].text : "");
        return;
    }
    const roz_manifest_t *m = &storage.manifest;
    const char *name = m->hardware != NULL ? m->hardware->port : "";
    if (strcmp(name, "unitree/G1") == 0)
        port = roz_unitree_g1_port(&g1, quiet, NULL);
    else if (strcmp(name, "agibot/X2") == 0)
        port = roz_agibot_x2_port(&x2, quiet, NULL);
    else if (strcmp(name, "engineai/PM01") == 0)
        port = roz_engineai_pm01_port(&pm01, quiet, NULL);
    else {
        printf("%s: [no DDS port]\n", file);
        return;
    }
    err[0] = '\0';
    if (roz_port_open(&port, m, NULL, err, sizeof err) == ROZ_OK) {
        roz_port_close(&port);
        printf("%s: ok\n", file);
    } else {
        printf("%s: %s\n", file, err);
    }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: port_open_check FILE...\n");
        return 2;
    }
    for (int i = 1; i < argc; i++)
        check(argv[i]);
    return 0;
}
