/* SPDX-License-Identifier: Apache-2.0 */
#include "dds_open_file.h"

#include <stdio.h>
#include <string.h>

#include "roz/port/agibot_x2.h"
#include "roz/port/engineai_pm01.h"
#include "roz/manifest_toml.h"
#include "roz/port/unitree_g1.h"
#ifdef ROZ_TEST_HAVE_MUJOCO
#include "roz/port/mujoco.h"
#endif

#define MAX_PROBLEMS 64

static char text[1u << 20];
static roz_manifest_storage_t storage;
static roz_manifest_toml_problem_t problems[MAX_PROBLEMS];
ROZ_TOML_DOC_DEFINE(doc, 1u << 16, 1u << 20);

static roz_unitree_g1_t g1;
static roz_agibot_x2_t x2;
static roz_engineai_pm01_t pm01;
#ifdef ROZ_TEST_HAVE_MUJOCO
static roz_mujoco_t mujoco;
#endif

static void quiet(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    (void)level;
    (void)msg;
}

int roz_test_dds_open_file(const char *file, const char **port_name, char *err, size_t errlen)
{
    size_t found = 0;
    roz_port_t port;

    if (port_name != NULL)
        *port_name = "";
    err[0] = '\0';
    roz_toml_init(&doc, doc_nodes, sizeof doc_nodes / sizeof doc_nodes[0], doc_arena,
                  sizeof doc_arena);
    if (roz_manifest_toml_load_file(file, text, sizeof text, &storage, &doc, problems,
                                    MAX_PROBLEMS, &found) != ROZ_OK) {
        snprintf(err, errlen, "%s", found > 0 ? problems[0].text : "");
        return ROZ_TEST_NOT_LOADED;
    }
    const roz_manifest_t *m = &storage.manifest;
    const char *name = m->hardware != NULL ? m->hardware->port : "";
    if (port_name != NULL)
        *port_name = name;
    if (strcmp(name, "unitree/G1") == 0)
        port = roz_unitree_g1_port(&g1, quiet, NULL);
    else if (strcmp(name, "agibot/X2") == 0)
        port = roz_agibot_x2_port(&x2, quiet, NULL);
    else if (strcmp(name, "engineai/PM01") == 0)
        port = roz_engineai_pm01_port(&pm01, quiet, NULL);
#ifdef ROZ_TEST_HAVE_MUJOCO
    else if (strcmp(name, "mujoco") == 0) /* the physics port's keys, checked alike */
        port = roz_mujoco_port(&mujoco, quiet, NULL);
#endif
    else
        return ROZ_TEST_NO_DDS_PORT;
    roz_port_set_origin(&port, file); /* a model path is relative to the robot.toml */
    int rc = roz_port_open(&port, m, NULL, err, errlen);
    if (rc == ROZ_OK)
        roz_port_close(&port);
    return rc;
}
