/* SPDX-License-Identifier: Apache-2.0 */
/* What the mujoco port reads from a model at open and how it tells a user
 * what to fix: a motor's ctrlrange against the manifest's effort channel
 * (refused past it, taken when the manifest is tighter), mesh files that
 * are not there, a model without the IMU the manifest reads; `lock`
 * holding a bound joint rigid; and the built-in robots' descriptors
 * (ports/mujoco/models/<id>.model.toml). Open, and 0.2 simulated seconds
 * of the G1 for the lock. */
/* white-box in part: reads the bound joints' torque limits (roz/private.h) */
#define ROZ_PRIVATE_ACCESS
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/builtin.h"
#include "roz/manifest_toml.h"
#include "mujoco_robot_file.h"
#include "roz/port/mujoco.h"
#include "support.h"

static roz_mujoco_t mj;

/* Opens test/ports/mujoco/@p file (with `model` = @p model when not NULL);
 * returns open's result, its message in @p err. */
static int open_file(roz_port_t *p, const char *file, const char *model, char *err,
                     size_t errlen)
{
    *p = roz_mujoco_port(&mj, NULL, NULL); /* first: the robot file is named on it */
    const roz_manifest_t *m = roz_test_mujoco_robot_file(&mj, file);
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

/* The same on a model its producer wrote: Menagerie's H1 states its motors'
 * limits as ctrlrange alone (the ankles 40 N.m), and has an IMU site but no
 * sensors. It is in the model wheel beside the built-in G1 (unitree_g1/ and
 * unitree_h1/ in one folder). */
static void test_mujoco_models_menageries_h1(void **state)
{
    (void)state;
    const char *g1 = roz_mujoco_builtin_model("unitree_g1");
    static char h1[4096];
    const char *dir_end = g1 != NULL ? strstr(g1, "/unitree_g1/scene.xml") : NULL;
    if (dir_end == NULL)
        skip(); /* the model wheel is not installed (tools/setup.sh) */
    snprintf(h1, sizeof h1, "%.*s/unitree_h1/h1.xml", (int)(dir_end - g1), g1);
    FILE *f = fopen(h1, "rb");
    if (f == NULL)
        skip(); /* an installed G1 has no H1 beside it */
    fclose(f);
    static const char *const want[] = {
        "h1_ankle.toml", "channel \"left_ankle/effort\": limits [-50, 50] N.m", "h1.xml",
        "actuator \"left_ankle\" (joint \"left_ankle\") can give, [-40, 40]", NULL,
    };
    expect_refused("h1_ankle.toml", h1, want);
    /* inside the ctrlrange the ankle binds; the H1 has an IMU site and no
     * sensors: the help names that site */
    static const char *const imu[] = {
        "h1_imu.toml", "no gyro sensor on a site in", "h1.xml", "the model has site \"imu\"",
        "<gyro name=\"imu-gyro\" site=\"imu\"/>", NULL,
    };
    expect_refused("h1_imu.toml", h1, imu);
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

/* ---- lock: model joints held rigid, bound or not ------------------------------------ */

/* The 29-DoF G1 with its upper body locked as unitree_g1_12dof's is: its
 * left elbow commanded to 1 rad at kp 40 for 0.2 s; the elbow's angle
 * after it (*q), and open's note (@p note). @p lock: the parameter, or
 * NULL (the elbow then moves). */
static char note_text[1024];
static void keep_note(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    if (level == ROZ_LOG_INFO)
        snprintf(note_text, sizeof note_text, "%s", msg);
}

static void run_g1_elbow(const char *lock, double *q)
{
    const roz_manifest_t *m = roz_builtin_find("unitree_g1");
    assert_non_null(m);
    static double cmd[ROZ_CFG_MAX_COMMANDS], st[ROZ_CFG_MAX_STATES];
    roz_param_t items[2] = { { "keyframe", "" }, { "lock", lock } };
    roz_params_t params = { items, lock != NULL ? 2u : 1u };
    char err[1024];
    roz_port_t p = roz_mujoco_port(&mj, keep_note, NULL);
    if (roz_port_open(&p, m, &params, err, sizeof err) != ROZ_OK)
        fail_msg("%s", err);
    int elbow = roz_manifest_find_command(m, "left_elbow_joint/position");
    int kp = roz_manifest_find_command(m, "left_elbow_joint/stiffness");
    int state = roz_manifest_find_state(m, "left_elbow_joint/position");
    assert_true(elbow >= 0 && kp >= 0 && state >= 0);
    for (uint16_t i = 0; i < m->n_commands; i++)
        cmd[i] = 0.0; /* every other joint limp: only the elbow is driven */
    cmd[elbow] = 1.0;
    cmd[kp] = 40.0;
    for (int t = 0; t < 100; t++) {
        assert_int_equal(roz_port_write(&p, cmd, m->n_commands), ROZ_OK);
        assert_int_equal(roz_port_read(&p, st, m->n_states), 1);
    }
    *q = st[state];
    roz_port_close(&p);
}

static void test_mujoco_models_lock_holds_a_bound_joint(void **state)
{
    (void)state;
    if (roz_mujoco_builtin_model("unitree_g1") == NULL)
        skip(); /* the model wheel is not installed (tools/setup.sh) */
    double free_q, locked_q;
    run_g1_elbow(NULL, &free_q);
    assert_true(free_q > 0.5); /* without the lock the drive moves it */
    run_g1_elbow("waist_*, *_shoulder_*, *_elbow_*, *_wrist_*", &locked_q);
    print_message("elbow after 0.2 s at kp 40 toward 1 rad: %.4f free, %.4f locked\n", free_q,
                  locked_q);
    assert_true(fabs(locked_q) < 0.05);
    assert_non_null(strstr(note_text, "29 joints bound, 17 bound joints locked (lock)"));
    static const char *const typo[] = {
        "hardware.params.lock = \"*_elbw_*\": \"*_elbw_*\" names no hinge or slide joint", NULL,
    };
    const roz_manifest_t *m = roz_builtin_find("unitree_g1");
    roz_param_t item = { "lock", "*_elbw_*" };
    roz_params_t params = { &item, 1 };
    char err[1024];
    roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
    assert_int_not_equal(roz_port_open(&p, m, &params, err, sizeof err), ROZ_OK);
    print_message("refused: %s\n", err);
    assert_non_null(strstr(err, typo[0]));
    roz_port_close(&p);
    static char longer[300]; /* a pattern no joint name could match, refused, not cut */
    memset(longer, 'x', 200);
    item.value = longer;
    p = roz_mujoco_port(&mj, NULL, NULL);
    assert_int_not_equal(roz_port_open(&p, m, &params, err, sizeof err), ROZ_OK);
    assert_non_null(strstr(err, "a pattern of 200 bytes"));
    roz_port_close(&p);
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

ROZ_TEST_MAIN(cmocka_unit_test(test_mujoco_models_ctrlrange_refuses_a_wider_manifest),
              cmocka_unit_test(test_mujoco_models_menageries_h1),
              cmocka_unit_test(test_mujoco_models_ctrlrange_takes_a_tighter_manifest),
              cmocka_unit_test(test_mujoco_models_missing_meshes_say_where),
              cmocka_unit_test(test_mujoco_models_no_imu_says_what_to_add),
              cmocka_unit_test(test_mujoco_models_lock_holds_a_bound_joint),
              cmocka_unit_test(test_mujoco_models_g1_12dof_is_the_g1_model))
