/* SPDX-License-Identifier: Apache-2.0 */
#include "mujoco_robot_file.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "roz/error.h"
#include "roz/manifest_toml.h"

const roz_manifest_t *roz_test_mujoco_robot_file(roz_mujoco_t *mj, const char *file)
{
    static roz_manifest_storage_t st;
    static roz_toml_doc_t doc;
    static roz_toml_node_t nodes[4096];
    static char arena[65536], text[65536];
    static roz_manifest_toml_problem_t problems[4];
    static char path[4096]; /* a clone may sit at any depth */
    size_t found = 0;

    snprintf(path, sizeof path, "%s/%s", ROZ_TEST_MUJOCO_DIR, file);
    roz_toml_init(&doc, nodes, sizeof nodes / sizeof nodes[0], arena, sizeof arena);
    int rc = roz_manifest_toml_load_file(path, text, sizeof text, &st, &doc, problems, 4, &found);
    if (rc != ROZ_OK)
        fail_msg("%s%s", path, found ? problems[0].text : ": cannot load");
    roz_mujoco_set_robot_file(mj, path);
    return &st.manifest;
}
