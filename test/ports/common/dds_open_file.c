/* SPDX-License-Identifier: Apache-2.0 */
#include "dds_open_file.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "roz/manifest_toml.h"
#include "roz/ports.h"

#define MAX_PROBLEMS 64

static char text[1u << 20];
static roz_manifest_storage_t storage;
static roz_manifest_toml_problem_t problems[MAX_PROBLEMS];
ROZ_TOML_DOC_DEFINE(doc, 1u << 16, 1u << 20);

/* The ports whose open this checks against rozgen's words, found in the
 * registry (roz/ports.h) by the names rozgen knows: the DDS ones, and the
 * mujoco port where the test asks for it (its keys are checked alike). */
static const char *const checked_ports[] = { "unitree/G1", "agibot/X2", "engineai/PM01",
#ifdef ROZ_TEST_HAVE_MUJOCO
                                             "mujoco",
#endif
};

static const roz_port_entry_t *checked(const char *name)
{
    for (size_t i = 0; i < sizeof checked_ports / sizeof checked_ports[0]; i++) {
        const roz_port_entry_t *e = roz_ports_find(checked_ports[i]);
        if (e != NULL && strcmp(e->ops->name, name) == 0)
            return e;
    }
    return NULL;
}

static void quiet(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    (void)level;
    (void)msg;
}

int roz_test_dds_open_file(const char *file, const char **port_name, char *err, size_t errlen)
{
    size_t found = 0;

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
    const roz_port_entry_t *e = checked(name);
    if (e == NULL)
        return ROZ_TEST_NO_DDS_PORT;
    size_t size = (e->size + e->align - 1) / e->align * e->align;
    void *self = aligned_alloc(e->align, size);
    if (self == NULL) {
        snprintf(err, errlen, "no memory for a %s instance", name);
        return ROZ_TEST_NOT_LOADED;
    }
    memset(self, 0, size);
    roz_port_t port = e->construct(self, quiet, NULL);
    roz_port_set_origin(&port, file); /* a model path is relative to the robot.toml */
    int rc = roz_port_open(&port, m, NULL, err, errlen);
    if (rc == ROZ_OK)
        roz_port_close(&port);
    free(self);
    return rc;
}
