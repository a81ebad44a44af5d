/* SPDX-License-Identifier: Apache-2.0 */
/* What the mujoco port reads from a model at open and how it tells a user
 * what to fix: a motor's ctrlrange against the manifest's effort channel
 * (refused past it, taken when the manifest is tighter), mesh files that
 * are not there, a model without the IMU the manifest reads; and the
 * built-in robots' descriptors (ports/mujoco/models/<id>.model.toml).
 * Open only: no step is simulated. */
/* white-box in part: reads the bound joints' torque limits (roz/private.h) */
#define ROZ_PRIVATE_ACCESS
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/manifest_toml.h"
#include "roz/port/mujoco.h"

static roz_mujoco_t mj;

/* test/ports/mujoco/<file>, loaded; the port is told it is the robot file */
static const roz_manifest_t *load(const char *file)
{
    static roz_manifest_storage_t st;
    static roz_toml_doc_t doc;
    static roz_toml_node_t nodes[1024];
    static char arena[16384], text[16384];
    static roz_manifest_toml_problem_t problems[4];
    static char path[4096];
    size_t found = 0;
    snprintf(path, sizeof path, "%s/%s", ROZ_TEST_MUJOCO_DIR, file);
    roz_toml_init(&doc, nodes, sizeof nodes / sizeof nodes[0], arena, sizeof arena);
    int rc = roz_manifest_toml_load_file(path, text, sizeof text, &st, &doc, problems, 4, &found);
    if (rc != ROZ_OK)
        fail_msg("%s%s", path, found ? problems[0].text : ": cannot load");
    roz_mujoco_set_robot_file(&mj, path);
    return &st.manifest;
}

/* Opens test/ports/mujoco/@p file (with `model` = @p model when not NULL);
 * returns open's result, its message in @p err. */
static int open_file(roz_port_t *p, const char *file, const char *model, char *err,
                     size_t errlen)
{
    *p = roz_mujoco_port(&mj, NULL, NULL); /* before load(): it names the robot file */
    const roz_manifest_t *m = load(file);
    roz_param_t item = { "model", model };
    roz_params_t params = { &item, model != NULL ? 1u : 0u };
    err[0] = '\0';
    return roz_port_open(p, m, &params, err, errlen);
}

static void expect_refused(const char *file, const char *model, const char *const *want)
{
    char err[4096];
    roz_port_t p;
    int rc = open_file(&p, file, model, err, sizeof err);
    print_message("refused: %s\n", err);
    assert_int_not_equal(rc, ROZ_OK);
    for (; *want != NULL; want++) {
        if (strstr(err, *want) == NULL)
            fail_msg("\"%s\" not in: %s", *want, err);
    }
    roz_port_close(&p);
}

/* ---- a motor's ctrlrange ---------------------------------------------------------- */

static void test_mujoco_models_ctrlrange_refuses_a_wider_manifest(void **state)
{
    (void)state;
    static const char *const want[] = {
        "calf.toml", "channel \"calf_joint/effort\": limits [-50, 50] N.m", "calf.xml",
        "actuator \"calf\" (joint \"calf_joint\")", "[-45.43, 45.43]: its ctrlrange", NULL,
    };
    expect_refused("calf.toml", NULL, want);
}

static void test_mujoco_models_ctrlrange_takes_a_tighter_manifest(void **state)
{
    (void)state;
    char err[4096];
    roz_port_t p;
    int rc = open_file(&p, "calf_tight.toml", NULL, err, sizeof err);
    if (rc != ROZ_OK)
        fail_msg("%s", err);
    assert_int_equal(mj.n_joints, 1);
    assert_true(mj.joints[0].tau_lo == -40.0 && mj.joints[0].tau_hi == 40.0);
    roz_port_close(&p);
}

/* ---- a user's model: meshes, IMU ------------------------------------------------- */

static void test_mujoco_models_missing_meshes_say_where(void **state)
{
    (void)state;
    static const char *const want[] = {
        "calf_tight.toml", "calf_meshes.xml: <mesh name=\"trunk_mesh\" file=\"trunk.STL\">",
        "no file ", "meshes/trunk.STL", "(1 of the model's 1 mesh files are missing)",
        "<compiler meshdir=\"meshes\">", "set meshdir", NULL,
    };
    expect_refused("calf_tight.toml", "calf_meshes.xml", want);
}

static void test_mujoco_models_no_imu_says_what_to_add(void **state)
{
    (void)state;
    static const char *const gyro[] = {
        "calf_imu.toml", "hardware.params.imu_gyro: no gyro sensor on a site in", "calf.xml",
        "add to <body name=\"trunk\"> <site name=\"imu\"/>",
        "<gyro name=\"imu-gyro\" site=\"imu\"/>",
        "<accelerometer name=\"imu-accelerometer\" site=\"imu\"/>", NULL,
    };
    expect_refused("calf_imu.toml", NULL, gyro);
    static const char *const acc[] = {
        "calf_imu.toml", "hardware.params.imu_accelerometer: no accelerometer sensor in",
        "calf_gyro.xml", "<accelerometer name=\"imu-accelerometer\" site=\"trunk_imu\"/>", NULL,
    };
    expect_refused("calf_imu.toml", "calf_gyro.xml", acc);
}

/* ---- the built-in robots' descriptors --------------------------------------------- */

static void test_mujoco_models_g1_12dof_is_the_g1_model(void **state)
{
    (void)state;
    const char *g1 = roz_mujoco_builtin_model("unitree_g1");
    const char *g12 = roz_mujoco_builtin_model("unitree_g1_12dof");
    if (g1 == NULL)
        skip(); /* the model wheel is not installed (tools/setup.sh) */
    assert_non_null(g12);
    assert_string_equal(g1, g12);
    assert_null(roz_mujoco_builtin_model("unitree_g1_7dof"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mujoco_models_ctrlrange_refuses_a_wider_manifest),
        cmocka_unit_test(test_mujoco_models_ctrlrange_takes_a_tighter_manifest),
        cmocka_unit_test(test_mujoco_models_missing_meshes_say_where),
        cmocka_unit_test(test_mujoco_models_no_imu_says_what_to_add),
        cmocka_unit_test(test_mujoco_models_g1_12dof_is_the_g1_model),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
