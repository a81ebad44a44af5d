/* SPDX-License-Identifier: Apache-2.0 */
/* The run-time robot.toml loader (roz/manifest_toml.h): manifests built in
 * caller storage, the built-ins equal to rozgen's tables, problems in
 * rozgen's order and words, limits of this build as "storage" problems, file
 * errors as rozgen's "io-error". */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/manifest_toml.h"
#if defined(ROZ_TEST_BUILTINS)
#include "roz/builtin.h"
#endif
#include "support.h"

/* ---- helpers ---------------------------------------------------------------- */

static roz_toml_node_t nodes[16384];
static char arena[65536];
static roz_toml_doc_t doc;
static roz_manifest_storage_t storage;
static roz_manifest_toml_problem_t problems[16];
static char file_buf[1 << 20];
static char text[1 << 18];

static int load(const char *t, size_t max, size_t *found)
{
    roz_toml_init(&doc, nodes, sizeof nodes / sizeof nodes[0], arena, sizeof arena);
    return roz_manifest_toml_load(&storage, &doc, t, strlen(t), problems, max, found);
}

static int load_file(const char *relative, size_t *found)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", ROZ_SOURCE_DIR, relative);
    roz_toml_init(&doc, nodes, sizeof nodes / sizeof nodes[0], arena, sizeof arena);
    return roz_manifest_toml_load_file(path, file_buf, sizeof file_buf, &storage, &doc, problems,
                                       16, found);
}

static const char channel[] = "name = \"%s\"\ninterface_type = \"velocity\"\nunit = \"rad/s\"\n"
                              "limits = [-1.0, 1.0]\ndefault = 0.0\n";

/* ---- tests ---------------------------------------------------------------------- */

static void test_manifest_toml_my_arm(void **state)
{
    const roz_manifest_t *m = &storage.manifest;
    size_t found = 99;
    (void)state;
    assert_int_equal(load_file("examples/my_arm/robot.toml", &found), ROZ_OK);
    assert_int_equal(found, 0);
    assert_string_equal(m->robot_id, "my_arm");
    assert_string_equal(m->robot_class, "manipulator");
    assert_int_equal(m->control_rate_hz, 100);
    assert_int_equal(m->n_commands, 2);
    assert_int_equal(m->n_states, 2);
    assert_string_equal(m->commands[1].name, "joint2/velocity");
    assert_int_equal(m->commands[1].type, ROZ_IF_VELOCITY);
    assert_string_equal(m->commands[1].unit, "rad/s");
    assert_true(m->commands[1].min == -2.0 && m->commands[1].max == 2.0);
    assert_true(m->commands[1].max_rate == 0.2);
    assert_int_equal(m->commands[1].position_state, 1);
    assert_int_equal(m->states[0].position_state, ROZ_CHANNEL_UNPAIRED);
    assert_true(m->states[0].limit_margin == 0.0 && m->states[1].limit_margin == 0.1);
    assert_null(m->hardware);
    assert_int_equal(roz_manifest_validate(m, NULL), ROZ_OK);
    /* the strings live in the storage, not in the file buffer */
    assert_true(m->commands[0].name >= storage.arena &&
                m->commands[0].name < storage.arena + sizeof storage.arena);
}

/* Every built-in manifest read at run time equals rozgen's generated table. */
static void test_manifest_toml_builtins(void **state)
{
#if defined(ROZ_TEST_BUILTINS)
    (void)state;
    assert_true(roz_builtin_count() >= 6);
    for (size_t b = 0; b < roz_builtin_count(); b++) {
        const roz_manifest_t *want = roz_builtin_at(b), *m = &storage.manifest;
        char rel[128];
        size_t found = 0;
        snprintf(rel, sizeof rel, "manifests/%s.toml", want->robot_id);
        assert_int_equal(load_file(rel, &found), ROZ_OK);
        assert_string_equal(m->robot_id, want->robot_id);
        assert_string_equal(m->robot_class, want->robot_class);
        assert_int_equal(m->control_rate_hz, want->control_rate_hz);
        assert_int_equal(m->n_commands, want->n_commands);
        assert_int_equal(m->n_states, want->n_states);
        for (int list = 0; list < 2; list++) {
            const roz_channel_t *a = list ? m->states : m->commands;
            const roz_channel_t *w = list ? want->states : want->commands;
            for (uint16_t i = 0; i < (list ? m->n_states : m->n_commands); i++) {
                assert_string_equal(a[i].name, w[i].name);
                assert_string_equal(a[i].unit, w[i].unit);
                assert_int_equal(a[i].type, w[i].type);
                assert_true(a[i].min == w[i].min && a[i].max == w[i].max);
                assert_true(a[i].default_value == w[i].default_value);
                assert_true(a[i].max_rate == w[i].max_rate);
                assert_int_equal(a[i].position_state, w[i].position_state);
                assert_true(a[i].limit_margin == w[i].limit_margin);
            }
        }
        assert_int_equal(m->hardware == NULL, want->hardware == NULL);
        if (want->hardware != NULL) {
            assert_string_equal(m->hardware->port, want->hardware->port);
            assert_int_equal(m->hardware->n_joints, want->hardware->n_joints);
            for (uint16_t i = 0; i < want->hardware->n_joints; i++)
                assert_string_equal(m->hardware->joints[i], want->hardware->joints[i]);
            assert_int_equal(m->hardware->n_params, want->hardware->n_params);
            for (uint16_t i = 0; i < want->hardware->n_params; i++) {
                assert_string_equal(m->hardware->params[i].key, want->hardware->params[i].key);
                assert_string_equal(m->hardware->params[i].value,
                                    want->hardware->params[i].value);
            }
        }
    }
#else
    skip();
    (void)state;
#endif
}

static void test_manifest_toml_hardware(void **state)
{
    const roz_hardware_t *h;
    (void)state;
    snprintf(text, sizeof text,
             "hardware = {port = \"can/x\", joints = ['j1', \"j2\"], "
             "params = {zeta = \"z\", alpha = \"a\", \"m m\" = \"\\u00e9\"}}\n"
             "[manifest]\nrobot_id = \"hw\"\n[[manifest.commands]]\n");
    snprintf(text + strlen(text), sizeof text - strlen(text), channel, "j1/velocity");
    assert_int_equal(load(text, 16, NULL), ROZ_OK);
    h = storage.manifest.hardware;
    assert_non_null(h);
    assert_string_equal(h->port, "can/x");
    assert_int_equal(h->n_joints, 2);
    assert_string_equal(h->joints[1], "j2");
    assert_int_equal(h->n_params, 3);
    assert_string_equal(h->params[0].key, "alpha"); /* sorted by key */
    assert_string_equal(h->params[1].key, "m m");
    assert_string_equal(h->params[1].value, "\xC3\xA9");
    assert_string_equal(h->params[2].key, "zeta");
    assert_string_equal(storage.manifest.robot_class, "generic");
    assert_int_equal(storage.manifest.control_rate_hz, 100);
    assert_null(storage.manifest.states);
}

/* limit_margin as written on a position state, 0 (the default) when left
 * out; the filter's margin is worked out from it. */
static void test_manifest_toml_limit_margin(void **state)
{
    const roz_manifest_t *m = &storage.manifest;
    (void)state;
    snprintf(text, sizeof text,
             "[manifest]\nrobot_id = \"grip\"\n"
             "[[manifest.commands]]\nname = \"gripper/velocity\"\ninterface_type = \"velocity\"\n"
             "unit = \"m/s\"\nlimits = [-0.05, 0.05]\ndefault = 0.0\nposition_state_index = 0\n"
             "[[manifest.states]]\nname = \"gripper/position\"\ninterface_type = \"position\"\n"
             "unit = \"m\"\nlimits = [0, 0.08]\ndefault = 0.04\nlimit_margin = 0.002\n"
             "[[manifest.states]]\nname = \"wrist/position\"\ninterface_type = \"position\"\n"
             "unit = \"rad\"\nlimits = [-3, 3]\ndefault = 0\n"
             "[[manifest.states]]\nname = \"finger/position\"\ninterface_type = \"position\"\n"
             "unit = \"mm\"\nlimits = [0, 80]\ndefault = 0\nlimit_margin = 1\n");
    assert_int_equal(load(text, 16, NULL), ROZ_OK);
    assert_true(m->states[0].limit_margin == 0.002);
    assert_true(m->states[1].limit_margin == 0.0);
    assert_true(m->states[2].limit_margin == 1.0); /* an integer is a number */
    assert_true(m->commands[0].limit_margin == 0.0);
    assert_true(roz_manifest_limit_margin(&m->states[0]) == 0.002);
    assert_true(roz_manifest_limit_margin(&m->states[1]) == 0.05);
    assert_int_equal(roz_manifest_validate(m, NULL), ROZ_OK);
}

/* The first problems in rozgen's order, all of them counted. */
static void test_manifest_toml_problem_order(void **state)
{
    static const char bad[] =
        "[hardware]\nport = 1\n"
        "[[manifest.commands]]\nname = \"a\"\ninterface_type = \"speed\"\nunit = \"u\"\n"
        "limits = [1.0, 0.0]\ndefault = 0.0\nfoo = 1\n"
        "[manifest]\nrobot_id = \"OK\"\ncontrol_rate_hz = 0\n";
    size_t found = 0;
    (void)state;
    assert_int_equal(load(bad, 16, &found), ROZ_EINVAL);
    assert_int_equal(found, 6);
    assert_string_equal(problems[0].rule, "robot-id");
    assert_string_equal(problems[0].text, ": manifest: robot_id \"OK\": must match [a-z][a-z0-9_]* "
                                          "(it names C symbols and files)");
    assert_string_equal(problems[1].rule, "control-rate");
    assert_string_equal(problems[1].text, ": manifest: control_rate_hz 0: must be in 1..100000");
    assert_string_equal(problems[2].rule, "unknown-key");
    assert_string_equal(problems[3].rule, "interface-type");
    assert_string_equal(problems[4].rule, "limits-order");
    assert_string_equal(problems[4].text, ": manifest.commands[0] \"a\": limits [1.0, 0.0]: min "
                                          "must be below max");
    assert_string_equal(problems[5].rule, "type");
    assert_string_equal(problems[5].text, ": hardware: port 1: expected a string");
    /* room for two: the first two, the others counted */
    assert_int_equal(load(bad, 2, &found), ROZ_EINVAL);
    assert_int_equal(found, 6);
    assert_string_equal(problems[0].rule, "robot-id");
    assert_string_equal(problems[1].rule, "control-rate");
    /* room for none */
    assert_int_equal(load(bad, 0, &found), ROZ_EINVAL);
    assert_int_equal(found, 6);
}

static void test_manifest_toml_syntax_and_utf8(void **state)
{
    size_t found = 0;
    (void)state;
    assert_int_equal(load("[manifest]\nrobot_id \"x\"\n", 16, &found), ROZ_EINVAL);
    assert_int_equal(found, 1);
    assert_string_equal(problems[0].rule, "toml-syntax");
    assert_memory_equal(problems[0].text, ":2:10: invalid TOML: ", 21);
    assert_int_equal(load("[manifest]\nrobot_id = \"\xE4\"\n", 16, &found), ROZ_EINVAL);
    assert_string_equal(problems[0].rule, "utf8");
    assert_string_equal(problems[0].text,
                        ": cannot read: not valid UTF-8 (byte 0xe4 at offset 23)");
    assert_int_equal(load("a = 00:00:60\n", 16, &found), ROZ_ENOTSUP);
    assert_string_equal(problems[0].rule, "toml-syntax");
}

/* A manifest of one command channel, "a", then @p tail, into @p out of
 * @p size bytes; its length. */
static size_t one_channel_then(char *out, size_t size, const char *tail)
{
    size_t n = (size_t)snprintf(out, size, "[manifest]\nrobot_id = \"r\"\n[[manifest.commands]]\n");
    n += (size_t)snprintf(out + n, size - n, channel, "a");
    n += (size_t)snprintf(out + n, size - n, "%s", tail);
    return n;
}

static void test_manifest_toml_storage_limits(void **state)
{
    static roz_toml_node_t few[8];
    size_t found = 0, n;
    (void)state;
    /* more joints than ROZ_CFG_MAX_JOINTS */
    n = one_channel_then(text, sizeof text, "[hardware]\nport = \"p\"\njoints = [");
    for (int i = 0; i <= ROZ_CFG_MAX_JOINTS; i++)
        n += (size_t)snprintf(text + n, sizeof text - n, "\"j%d\", ", i);
    snprintf(text + n, sizeof text - n, "]\n");
    assert_int_equal(load(text, 16, &found), ROZ_ENOSPC);
    assert_int_equal(found, 1);
    assert_string_equal(problems[0].rule, "storage");
    assert_non_null(strstr(problems[0].text, "ROZ_CFG_MAX_JOINTS"));
    /* beyond it, a joint is compared with the first ROZ_CFG_MAX_JOINTS only
     * (a long list costs linear time, not quadratic): a duplicate of one of
     * them is found, one of a later joint is left to the storage problem */
    n = one_channel_then(text, sizeof text, "[hardware]\nport = \"p\"\njoints = [");
    for (int i = 0; i < ROZ_CFG_MAX_JOINTS + 8; i++)
        n += (size_t)snprintf(text + n, sizeof text - n, "\"j%d\", ", i);
    n += (size_t)snprintf(text + n, sizeof text - n, "\"j%d\", \"j3\"]\n", ROZ_CFG_MAX_JOINTS + 2);
    assert_int_equal(load(text, 16, &found), ROZ_EINVAL);
    assert_int_equal(found, 1);
    assert_string_equal(problems[0].rule, "duplicate-joint");
    assert_non_null(strstr(problems[0].text, "duplicate of joints[3]"));

    /* more params than ROZ_CFG_MAX_PARAMS */
    n = one_channel_then(text, sizeof text, "[hardware]\nport = \"p\"\n[hardware.params]\n");
    for (int i = 0; i <= ROZ_CFG_MAX_PARAMS; i++)
        n += (size_t)snprintf(text + n, sizeof text - n, "k%d = \"v\"\n", i);
    assert_int_equal(load(text, 16, &found), ROZ_ENOSPC);
    assert_non_null(strstr(problems[0].text, "ROZ_CFG_MAX_PARAMS"));

    /* names and units beyond the name arena: 256 commands of 63-byte names */
    n = (size_t)snprintf(text, sizeof text, "[manifest]\nrobot_id = \"r\"\n");
    for (int i = 0; i < ROZ_CFG_MAX_COMMANDS; i++) {
        char name[ROZ_CFG_MAX_NAME_LEN + 1];
        snprintf(name, sizeof name, "%0*d", ROZ_CFG_MAX_NAME_LEN, i);
        n += (size_t)snprintf(text + n, sizeof text - n, "[[manifest.commands]]\n");
        n += (size_t)snprintf(text + n, sizeof text - n, channel, name);
    }
    assert_true(n < sizeof text - 1);
    assert_int_equal(load(text, 16, &found), ROZ_ENOSPC);
    assert_string_equal(problems[0].rule, "storage");
    assert_non_null(strstr(problems[0].text, "ROZ_CFG_NAME_ARENA_BYTES"));
    assert_int_equal(storage.arena_used, 0);

    /* a TOML document larger than the caller's node pool */
    roz_toml_init(&doc, few, 8, NULL, 0);
    assert_int_equal(roz_manifest_toml_load(&storage, &doc, text, strlen(text), problems, 16,
                                            &found),
                     ROZ_ENOSPC);
    assert_string_equal(problems[0].rule, "storage");
    assert_memory_equal(problems[0].text, ":7:", 3);

    /* and a manifest that fits loads again into the same storage */
    assert_int_equal(load_file("manifests/ur5.toml", &found), ROZ_OK);
    assert_int_equal(storage.manifest.n_commands, 6);
}

static void test_manifest_toml_files(void **state)
{
    static char small[16];
    roz_manifest_toml_problem_t p;
    size_t len = 0, found = 0;
    (void)state;
    assert_int_equal(load_file("no/such/robot.toml", &found), ROZ_EIO);
    assert_int_equal(found, 1);
    assert_string_equal(problems[0].rule, "io-error");
    assert_string_equal(problems[0].text, ": cannot read: No such file or directory");
    assert_int_equal(load_file("manifests", &found), ROZ_EIO);
    assert_string_equal(problems[0].text, ": cannot read: Is a directory");
    assert_int_equal(roz_manifest_toml_read_file(ROZ_SOURCE_DIR "/manifests/ur5.toml", small,
                                                 sizeof small, &len, &p),
                     ROZ_ENOSPC);
    assert_string_equal(p.rule, "storage");
    assert_int_equal(roz_manifest_toml_read_file(NULL, small, sizeof small, &len, &p), ROZ_EINVAL);
    /* a bad manifest file: rozgen's messages */
    assert_int_equal(load_file("manifests/invalid/max-rate.toml", &found), ROZ_EINVAL);
    assert_int_equal(found, 1);
    assert_string_equal(problems[0].rule, "max-rate");
    assert_string_equal(problems[0].text, ": manifest.commands[0] \"joint1/velocity\": "
                                          "max_rate_of_change -0.5: must not be negative");
}

static void test_manifest_toml_arguments(void **state)
{
    size_t found = 7;
    (void)state;
    roz_toml_init(&doc, nodes, 16, arena, 16);
    assert_int_equal(roz_manifest_toml_load(NULL, &doc, "", 0, problems, 16, &found), ROZ_EINVAL);
    assert_int_equal(found, 0);
    assert_int_equal(roz_manifest_toml_load(&storage, NULL, "", 0, problems, 16, NULL),
                     ROZ_EINVAL);
    /* an empty document: the manifest is missing */
    assert_int_equal(roz_manifest_toml_load(&storage, &doc, "", 0, NULL, 0, &found), ROZ_EINVAL);
    assert_int_equal(found, 1);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_manifest_toml_my_arm),
              cmocka_unit_test(test_manifest_toml_builtins),
              cmocka_unit_test(test_manifest_toml_hardware),
              cmocka_unit_test(test_manifest_toml_limit_margin),
              cmocka_unit_test(test_manifest_toml_problem_order),
              cmocka_unit_test(test_manifest_toml_syntax_and_utf8),
              cmocka_unit_test(test_manifest_toml_storage_limits),
              cmocka_unit_test(test_manifest_toml_files),
              cmocka_unit_test(test_manifest_toml_arguments))
