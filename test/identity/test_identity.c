/* SPDX-License-Identifier: Apache-2.0 */
/* A controller and its robot (roz/identity.h):
 *  - the interface hash the C side computes from a roz_manifest_t is the one
 *    rozgen wrote into every generated header, for every built-in manifest
 *    and the pan-tilt fixture, and it covers exactly the channel table
 *    (names, types, units, limits, order), not the filter's properties;
 *  - the "roz.manifest" section is read as specified: none, one record,
 *    copies of one record; malformed, different or duplicated ones are
 *    refused by roz_identity_read() and roz_controller_load() with a message
 *    naming the section and what is wrong;
 *  - roz_runtime_load() runs a controller built for this robot, refuses one
 *    built for another robot (naming both) or for another channel table of
 *    this one (saying the table changed), before it runs at all, unless
 *    allow_foreign_controller is set; one without identity loads;
 *  - the same with controllers clang built from the SDK and generated
 *    headers (pan_tilt_sweep.c, examples/controllers/pd_hold.c).
 * Modules without a compiler are built here byte by byte. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "agibot_x2_manifest.h"
#include "diff_drive_manifest.h"
#include "engineai_pm01_manifest.h"
#include "pan_tilt_manifest.h"
#include "quadcopter_manifest.h"
#include "roz/builtin.h"
#include "roz/controller.h"
#include "roz/identity.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_runtime.h"
#include "support_stats.h"
#include "unitree_g1_12dof_manifest.h"
#include "unitree_g1_23dof_manifest.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"
#include "wasm_bytes.h"

/* ---- the interface hash ---------------------------------------------------- */

static void test_identity_hash_is_rozgens(void **st)
{
    static const struct {
        const roz_manifest_t *m;
        const char           *id;
        uint64_t              hash;
    } generated[] = {
        { &roz_manifest_agibot_x2, ROZ_AGIBOT_X2_ROBOT_ID, ROZ_AGIBOT_X2_INTERFACE_HASH },
        { &roz_manifest_diff_drive, ROZ_DIFF_DRIVE_ROBOT_ID, ROZ_DIFF_DRIVE_INTERFACE_HASH },
        { &roz_manifest_engineai_pm01, ROZ_ENGINEAI_PM01_ROBOT_ID,
          ROZ_ENGINEAI_PM01_INTERFACE_HASH },
        { &roz_manifest_quadcopter, ROZ_QUADCOPTER_ROBOT_ID, ROZ_QUADCOPTER_INTERFACE_HASH },
        { &roz_manifest_unitree_g1, ROZ_UNITREE_G1_ROBOT_ID, ROZ_UNITREE_G1_INTERFACE_HASH },
        { &roz_manifest_unitree_g1_12dof, ROZ_UNITREE_G1_12DOF_ROBOT_ID,
          ROZ_UNITREE_G1_12DOF_INTERFACE_HASH },
        { &roz_manifest_unitree_g1_23dof, ROZ_UNITREE_G1_23DOF_ROBOT_ID,
          ROZ_UNITREE_G1_23DOF_INTERFACE_HASH },
        { &roz_manifest_ur5, ROZ_UR5_ROBOT_ID, ROZ_UR5_INTERFACE_HASH },
        { &roz_manifest_pan_tilt, ROZ_PAN_TILT_ROBOT_ID, ROZ_PAN_TILT_INTERFACE_HASH },
    };
    size_t n = sizeof generated / sizeof generated[0];
    (void)st;
    /* every built-in is in the table (a new one must be added here) */
    assert_int_equal(roz_builtin_count(), n - 1);
    for (size_t i = 0; i < n; i++) {
        const roz_manifest_t *m = generated[i].m;
        if (i + 1 < n)
            assert_ptr_equal(roz_builtin_find(generated[i].id), m);
        assert_string_equal(m->robot_id, generated[i].id);
        if (roz_manifest_interface_hash(m) != generated[i].hash)
            fail_msg("%s: C hash %016llx, rozgen's %016llx", m->robot_id,
                     (unsigned long long)roz_manifest_interface_hash(m),
                     (unsigned long long)generated[i].hash);
        for (size_t j = 0; j < i; j++)
            assert_true(generated[j].hash != generated[i].hash);
    }
}

/* The worked example of codegen/README.md ("Manifest identity"), also
 * checked on rozgen's side (codegen/tests/test_identity.py). */
static void test_identity_hash_worked_example(void **st)
{
    static const roz_channel_t c[] = { { .name = "j1/velocity", .type = ROZ_IF_VELOCITY,
                                         .unit = "rad/s", .min = -2.0, .max = 2.0,
                                         .position_state = ROZ_CHANNEL_UNPAIRED } };
    static const roz_channel_t s[] = { { .name = "j1/position", .type = ROZ_IF_POSITION,
                                         .unit = "rad", .min = -4.0, .max = 4.0,
                                         .position_state = ROZ_CHANNEL_UNPAIRED } };
    const roz_manifest_t arm = { "arm", "generic", 100, c, 1, s, 1, NULL, NULL, 0, 0, NULL, NULL };
    (void)st;
    assert_true(roz_manifest_interface_hash(&arm) == 0x22b82593f3d5e024ull);
}

/* A copy of the UR5's manifest to change one thing at a time. */
static roz_channel_t cmds[ROZ_UR5_N_COMMANDS], sts[ROZ_UR5_N_STATES];
static roz_manifest_t copy;

static void reset_copy(void)
{
    memcpy(cmds, roz_manifest_ur5.commands, sizeof cmds);
    memcpy(sts, roz_manifest_ur5.states, sizeof sts);
    copy = roz_manifest_ur5;
    copy.commands = cmds;
    copy.states = sts;
}

static void test_identity_hash_covers_the_table(void **st)
{
    static const roz_hardware_t hw = { "unitree/G1", NULL, 0, NULL, 0 };
    const uint64_t ur5 = ROZ_UR5_INTERFACE_HASH;
    (void)st;

    /* not hashed: what the filter does with a channel, and the rest */
    static const char *const same[] = { "default", "max_rate", "pairing", "limit margin",
                                        "robot_id", "class", "rate", "hardware", "-0.0" };
    for (size_t k = 0; k < sizeof same / sizeof same[0]; k++) {
        reset_copy();
        switch (k) {
        case 0: cmds[2].default_value = 1.0; break;
        case 1: cmds[2].max_rate = 0.0; break;
        case 2: cmds[2].position_state = ROZ_CHANNEL_UNPAIRED; break;
        case 3: sts[2].limit_margin = 0.2; break;
        case 4: copy.robot_id = "ur5e"; break;
        case 5: copy.robot_class = "cobot"; break;
        case 6: copy.control_rate_hz = 500; break;
        case 7: copy.hardware = &hw; break;
        default: break;
        }
        if (k == 8) { /* limits of 0: -0.0 is the same limit */
            cmds[0].min = 0.0;
            uint64_t plus = roz_manifest_interface_hash(&copy);
            cmds[0].min = -0.0;
            assert_true(roz_manifest_interface_hash(&copy) == plus);
            continue;
        }
        if (roz_manifest_interface_hash(&copy) != ur5)
            fail_msg("changing the %s changed the hash", same[k]);
    }
    /* hashed: what an index means */
    static const char *const differ[] = { "name", "type", "unit", "min", "max", "order",
                                          "a command less", "a state less", "last bit of max",
                                          "unit to name" };
    for (size_t k = 0; k < sizeof differ / sizeof differ[0]; k++) {
        reset_copy();
        switch (k) {
        case 0: cmds[3].name = "wrist_1_joint/speed"; break;
        case 1: sts[7].type = ROZ_IF_EFFORT; break;
        case 2: sts[0].unit = "deg"; break;
        case 3: sts[11].min = -3.0; break;
        case 4: cmds[5].max = 3.0; break;
        case 5: {
            roz_channel_t t = cmds[0];
            cmds[0] = cmds[1];
            cmds[1] = t;
            break;
        }
        case 6: copy.n_commands--; break;
        case 7: copy.n_states--; break;
        case 8: cmds[0].max = nextafter(cmds[0].max, 10.0); break;
        default: /* the same bytes split differently between name and unit */
            cmds[0].name = "shoulder_pan_joint/velocityrad/s";
            cmds[0].unit = "";
            break;
        }
        if (roz_manifest_interface_hash(&copy) == ur5)
            fail_msg("changing the %s left the hash as it was", differ[k]);
    }
    /* no manifest: the hash of an empty table, never a crash */
    assert_true(roz_manifest_interface_hash(NULL) != 0);
}

/* ---- modules byte by byte ------------------------------------------------------ */

typedef struct {
    uint8_t b[1024];
    size_t  n;
} buf_t;

static void put(buf_t *w, uint8_t v) { roz_wb_byte(w->b, sizeof w->b, &w->n, v); }
static void put_bytes(buf_t *w, const void *p, size_t n)
{
    roz_wb_bytes(w->b, sizeof w->b, &w->n, p, n);
}

/* A version-1 record: version, length of robot_id, robot_id, hash LE. */
static void put_record(buf_t *w, const char *id, uint64_t hash)
{
    put(w, 1);
    put(w, (uint8_t)strlen(id));
    put_bytes(w, id, strlen(id));
    roz_wb_le(w->b, sizeof w->b, &w->n, hash, 8);
}

typedef struct {
    const char *name;    /* custom section name */
    const buf_t *body;   /* its content after the name */
} custom_t;

static buf_t mod;

/* (module (func (export "process") (param i64))) with custom sections: the
 * first before the type section, the others after the code. */
static const uint8_t *module(const custom_t *customs, size_t n_customs, size_t *len)
{
    static const uint8_t types[] = { 1, 5, 1, 0x60, 1, 0x7e, 0 };
    static const uint8_t funcs[] = { 3, 2, 1, 0 };
    static const uint8_t exports[] = { 7, 11, 1, 7, 'p', 'r', 'o', 'c', 'e', 's', 's', 0, 0 };
    static const uint8_t code[] = { 10, 4, 1, 2, 0, 0x0b };

    mod.n = 0;
    put_bytes(&mod, "\0asm\1\0\0\0", 8);
    for (size_t i = 0; i < n_customs; i++) {
        if (i == 1) {
            put_bytes(&mod, types, sizeof types);
            put_bytes(&mod, funcs, sizeof funcs);
            put_bytes(&mod, exports, sizeof exports);
            put_bytes(&mod, code, sizeof code);
        }
        put(&mod, 0);
        size_t at = roz_wb_sized_begin(mod.b, sizeof mod.b, &mod.n);
        roz_wb_name(mod.b, sizeof mod.b, &mod.n, customs[i].name, strlen(customs[i].name));
        put_bytes(&mod, customs[i].body->b, customs[i].body->n);
        roz_wb_sized_end(mod.b, mod.n, at);
    }
    if (n_customs < 2) {
        put_bytes(&mod, types, sizeof types);
        put_bytes(&mod, funcs, sizeof funcs);
        put_bytes(&mod, exports, sizeof exports);
        put_bytes(&mod, code, sizeof code);
    }
    *len = mod.n;
    return mod.b;
}

/* A module with one roz.manifest section of the given content. */
static const uint8_t *with_identity(const buf_t *body, size_t *len)
{
    const custom_t c = { ROZ_IDENTITY_SECTION, body };
    return module(&c, 1, len);
}

static const uint8_t *built_for(const char *id, uint64_t hash, size_t *len)
{
    static buf_t body;
    body.n = 0;
    put_record(&body, id, hash);
    return with_identity(&body, len);
}

/* ---- reading the section ---------------------------------------------------------- */

static void expect_read(const uint8_t *w, size_t len, int rc, const char *msg)
{
    roz_identity_t id;
    char err[ROZ_CFG_ERROR_LEN] = "unset";
    int got = roz_identity_read(w, len, &id, err, sizeof err);
    if (got != rc || (msg != NULL && strstr(err, msg) == NULL) || (msg == NULL && err[0] != '\0'))
        fail_msg("roz_identity_read: %d \"%s\", expected %d with \"%s\"", got, err, rc,
                 msg != NULL ? msg : "");
    if (rc != ROZ_OK)
        assert_false(id.present);
}

static void test_identity_read(void **st)
{
    roz_identity_t id;
    buf_t body = { .n = 0 }, other = { .n = 0 };
    size_t len;
    const uint8_t *w;
    (void)st;

    /* none: a module without the section, or with other custom sections */
    w = module(NULL, 0, &len);
    assert_int_equal(roz_identity_read(w, len, &id, NULL, 0), ROZ_OK);
    assert_false(id.present);
    assert_string_equal(id.robot_id, "");
    put_record(&other, "ur5", 1);
    const custom_t near_names[] = { { "roz.manifes", &other }, { "roz.manifest2", &other },
                                    { "name", &other } };
    w = module(near_names, 3, &len);
    assert_int_equal(roz_identity_read(w, len, &id, NULL, 0), ROZ_OK);
    assert_false(id.present);

    /* one record, before or after the other sections */
    w = built_for("pan_tilt", 0x0123456789abcdefull, &len);
    assert_int_equal(roz_identity_read(w, len, &id, NULL, 0), ROZ_OK);
    assert_true(id.present);
    assert_string_equal(id.robot_id, "pan_tilt");
    assert_true(id.hash == 0x0123456789abcdefull);
    put_record(&body, "a23456789_123456789_123456789_12", ~0ull); /* 32 bytes */
    const custom_t late[] = { { "name", &other }, { ROZ_IDENTITY_SECTION, &body } };
    w = module(late, 2, &len);
    assert_int_equal(roz_identity_read(w, len, &id, NULL, 0), ROZ_OK);
    assert_string_equal(id.robot_id, "a23456789_123456789_123456789_12");
    assert_true(id.hash == ~0ull);

    /* copies of one record (one per object file that included the header) */
    body.n = 0;
    for (int i = 0; i < 3; i++)
        put_record(&body, "ur5", ROZ_UR5_INTERFACE_HASH);
    w = with_identity(&body, &len);
    assert_int_equal(roz_identity_read(w, len, &id, NULL, 0), ROZ_OK);
    assert_string_equal(id.robot_id, "ur5");
    assert_true(id.hash == ROZ_UR5_INTERFACE_HASH);

    /* records of two robots, or of two tables of one */
    body.n = 0;
    put_record(&body, "ur5", ROZ_UR5_INTERFACE_HASH);
    put_record(&body, "pan_tilt", ROZ_PAN_TILT_INTERFACE_HASH);
    w = with_identity(&body, &len);
    expect_read(w, len, ROZ_EINVAL, "two different records: 'ur5' (hash ");
    expect_read(w, len, ROZ_EINVAL, ") and 'pan_tilt' (hash ");
    body.n = 0;
    put_record(&body, "ur5", 1);
    put_record(&body, "ur5", 2);
    w = with_identity(&body, &len);
    expect_read(w, len, ROZ_EINVAL,
                "two different records: 'ur5' (hash 0000000000000001) and 'ur5' (hash "
                "0000000000000002)");

    /* two sections */
    const custom_t twice[] = { { ROZ_IDENTITY_SECTION, &other }, { ROZ_IDENTITY_SECTION, &other } };
    w = module(twice, 2, &len);
    expect_read(w, len, ROZ_EINVAL, "two custom sections \"roz.manifest\" (at offsets 14 and ");

    /* not a module at all, or one cut inside a section */
    expect_read((const uint8_t *)"\0asm\2\0\0\0", 8, ROZ_EINVAL, "not a WebAssembly 1.0 binary");
    expect_read(NULL, 0, ROZ_EINVAL, "not a WebAssembly 1.0 binary");
    w = built_for("ur5", 1, &len);
    expect_read(w, 12, ROZ_EINVAL, "section 0 at offset 8 runs past the end");
    assert_int_equal(roz_identity_read(w, len, NULL, NULL, 0), ROZ_EINVAL);
}

/* Each malformed record, as roz_identity_read() and the controller's loader
 * see it. */
static void test_identity_malformed(void **st)
{
    static const struct {
        const char *bytes;
        size_t      len;
        const char *msg;
    } bad[] = {
        { "", 0, "empty (a version-1 record was expected)" },
        { "\2\3ur5\1\2\3\4\5\6\7\10", 13, "record version 2 at byte 0; this roz reads version 1" },
        { "\0\3ur5\1\2\3\4\5\6\7\10", 13, "record version 0 at byte 0" },
        { "\1", 1, "record at byte 0: a robot_id of 0 bytes (1..32)" },
        { "\1\0\1\2\3\4\5\6\7\10", 10, "a robot_id of 0 bytes" },
        { "\1\41a23456789_123456789_123456789_123\1\2\3\4\5\6\7\10", 43,
          "a robot_id of 33 bytes (1..32)" },
        { "\1\3ur5\1\2\3\4\5\6\7", 12, "record at byte 0 cut short: 12 bytes of 13" },
        { "\1\3UR5\1\2\3\4\5\6\7\10", 13, "robot_id 'UR5' is not [a-z][a-z0-9_]*" },
        { "\1\3u\0005\1\2\3\4\5\6\7\10", 13, "robot_id 'u\\x005' is not" },
        { "\1\0035ur\1\2\3\4\5\6\7\10", 13, "robot_id '5ur' is not" },
        { "\1\3ur5\1\2\3\4\5\6\7\10\1", 14, "record at byte 13: a robot_id of 0 bytes" },
        { "\1\3ur5\1\2\3\4\5\6\7\10\7", 14, "record version 7 at byte 13" },
    };
    roz_abi_t abi;
    static double target[ROZ_CFG_MAX_COMMANDS], state[ROZ_CFG_MAX_STATES];
    (void)st;
    roz_abi_init(&abi, &roz_manifest_ur5, target, NULL);
    roz_abi_begin_tick(&abi, 0, state);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        buf_t body = { .n = 0 };
        size_t len;
        static const char where[] = "custom section \"roz.manifest\" at offset 14: ";
        put_bytes(&body, bad[i].bytes, bad[i].len);
        const uint8_t *w = with_identity(&body, &len);
        expect_read(w, len, ROZ_EINVAL, where);
        expect_read(w, len, ROZ_EINVAL, bad[i].msg);
        /* the loader refuses it for any robot, and says the same */
        roz_controller_t c;
        roz_controller_init(&c);
        assert_int_equal(roz_controller_load(&c, w, len, &abi), ROZ_EINVAL);
        if (strncmp(roz_controller_error(&c), where, sizeof where - 1) != 0 ||
            strstr(roz_controller_error(&c), bad[i].msg) == NULL)
            fail_msg("load: \"%s\" lacks \"%s%s\"", roz_controller_error(&c), where,
                     bad[i].msg);
        assert_false(roz_controller_loaded(&c));
    }
    /* a good one loads; two sections do not */
    roz_controller_t c;
    size_t len;
    roz_controller_init(&c);
    const uint8_t *w = built_for("quadcopter", 5, &len); /* any robot: not checked here */
    assert_int_equal(roz_controller_load(&c, w, len, &abi), ROZ_OK);
    roz_controller_unload(&c);
    buf_t one = { .n = 0 };
    put_record(&one, "ur5", ROZ_UR5_INTERFACE_HASH);
    const custom_t twice[] = { { ROZ_IDENTITY_SECTION, &one }, { ROZ_IDENTITY_SECTION, &one } };
    w = module(twice, 2, &len);
    assert_int_equal(roz_controller_load(&c, w, len, &abi), ROZ_EINVAL);
    assert_non_null(strstr(roz_controller_error(&c), "two custom sections \"roz.manifest\""));
}

static void test_identity_check(void **st)
{
    roz_identity_t id = { 1, "ur5", ROZ_UR5_INTERFACE_HASH };
    char msg[ROZ_CFG_ERROR_LEN];
    (void)st;
    assert_int_equal(roz_identity_check(&id, &roz_manifest_ur5, msg, sizeof msg),
                     ROZ_IDENTITY_SAME);
    assert_string_equal(msg, "");
    assert_int_equal(roz_identity_check(&id, &roz_manifest_pan_tilt, msg, sizeof msg),
                     ROZ_IDENTITY_OTHER_ROBOT);
    snprintf(id.robot_id, sizeof id.robot_id, "pan_tilt");
    id.hash = ROZ_PAN_TILT_INTERFACE_HASH;
    assert_int_equal(roz_identity_check(&id, &roz_manifest_ur5, msg, sizeof msg),
                     ROZ_IDENTITY_OTHER_ROBOT);
    char want[ROZ_CFG_ERROR_LEN];
    snprintf(want, sizeof want,
             "controller built for robot 'pan_tilt' (hash %016llx), this robot is 'ur5' "
             "(hash %016llx)", (unsigned long long)ROZ_PAN_TILT_INTERFACE_HASH,
             (unsigned long long)ROZ_UR5_INTERFACE_HASH);
    assert_string_equal(msg, want);
    id.hash = 42;
    assert_int_equal(roz_identity_check(&id, &roz_manifest_pan_tilt, msg, sizeof msg),
                     ROZ_IDENTITY_TABLE_CHANGED);
    snprintf(want, sizeof want,
             "controller built for robot 'pan_tilt' (hash 000000000000002a) before its channel "
             "table changed: this robot's table has hash %016llx",
             (unsigned long long)ROZ_PAN_TILT_INTERFACE_HASH);
    assert_string_equal(msg, want);
    id.present = 0;
    assert_int_equal(roz_identity_check(&id, &roz_manifest_pan_tilt, msg, sizeof msg),
                     ROZ_IDENTITY_NONE);
    assert_int_equal(roz_identity_check(NULL, &roz_manifest_ur5, NULL, 0), ROZ_IDENTITY_NONE);
}

/* ---- the runtime ------------------------------------------------------------------------ */

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_test_clock_t clk;

static void start(const roz_manifest_t *m, int allow)
{
    roz_runtime_config_t cfg;
    clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_loopback_config(&cfg, &lb, m, NULL, &clk);
    cfg.allow_foreign_controller = allow;
    roz_test_runtime_start(&rt, &cfg, NULL);
}

static int teardown(void **st)
{
    (void)st;
    roz_runtime_deinit(&rt);
    return 0;
}

/* Loads w and expects rc, a message holding msg (rc != OK), and match. */
static void expect_load(const uint8_t *w, size_t len, int rc, const char *msg,
                        roz_identity_match_t match)
{
    roz_verify_report_t rep;
    uint64_t refused = RT_COUNT(&rt, swaps_refused);
    int got = roz_runtime_load(&rt, w, len, &rep);
    if (got != rc || (msg != NULL && strstr(roz_runtime_error(&rt), msg) == NULL))
        fail_msg("load: %d \"%s\", expected %d with \"%s\"", got, roz_runtime_error(&rt), rc,
                 msg != NULL ? msg : "");
    assert_int_equal(rep.identity_match, match);
    assert_int_equal(RT_COUNT(&rt, swaps_refused), refused + (rc != ROZ_OK));
    if (rc != ROZ_OK)
        assert_int_equal(rep.ticks_run, 0); /* refused before it ran at all */
}

static void run(int ticks)
{
    for (int i = 0; i < ticks; i++)
        roz_test_tick(&rt);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(roz_loopback_counters(&lb).violations, 0);
}

static void test_identity_runtime_refuses_another_robot(void **st)
{
    size_t len;
    char want[ROZ_CFG_ERROR_LEN];
    (void)st;
    start(&roz_manifest_ur5, 0);
    /* built for this robot: runs, and the report says so */
    const uint8_t *w = built_for("ur5", ROZ_UR5_INTERFACE_HASH, &len);
    expect_load(w, len, ROZ_OK, NULL, ROZ_IDENTITY_SAME);
    run(5);
    uint64_t driven = RT_COUNT(&rt, controller_ticks);
    assert_true(driven > 0);
    /* built for another robot: refused, naming both; the running one keeps running */
    w = built_for("pan_tilt", ROZ_PAN_TILT_INTERFACE_HASH, &len);
    snprintf(want, sizeof want,
             "load: controller built for robot 'pan_tilt' (hash %016llx), this robot is 'ur5' "
             "(hash %016llx)", (unsigned long long)ROZ_PAN_TILT_INTERFACE_HASH,
             (unsigned long long)ROZ_UR5_INTERFACE_HASH);
    expect_load(w, len, ROZ_EINVAL, want, ROZ_IDENTITY_OTHER_ROBOT);
    assert_string_equal(roz_runtime_error(&rt), want);
    /* this robot before its table changed */
    w = built_for("ur5", ROZ_UR5_INTERFACE_HASH ^ 1, &len);
    expect_load(w, len, ROZ_EINVAL, "before its channel table changed",
                ROZ_IDENTITY_TABLE_CHANGED);
    /* malformed: refused */
    buf_t body = { .n = 0 };
    put_bytes(&body, "\2", 1);
    w = with_identity(&body, &len);
    expect_load(w, len, ROZ_EINVAL, "load: custom section \"roz.manifest\" at offset 14: record "
                "version 2", ROZ_IDENTITY_NONE);
    run(5);
    assert_true(RT_COUNT(&rt, controller_ticks) > driven);
    assert_int_equal(RT_COUNT(&rt, swaps), 1);
    /* no identity: loads on any robot */
    w = module(NULL, 0, &len);
    expect_load(w, len, ROZ_OK, NULL, ROZ_IDENTITY_NONE);
    run(5);
    assert_int_equal(RT_COUNT(&rt, swaps), 2);
}

static void test_identity_runtime_override(void **st)
{
    size_t len;
    (void)st;
    start(&roz_manifest_ur5, 1);
    const uint8_t *w = built_for("pan_tilt", ROZ_PAN_TILT_INTERFACE_HASH, &len);
    expect_load(w, len, ROZ_OK, NULL, ROZ_IDENTITY_OTHER_ROBOT);
    run(5);
    assert_true(RT_COUNT(&rt, controller_ticks) > 0);
    w = built_for("ur5", 7, &len);
    expect_load(w, len, ROZ_OK, NULL, ROZ_IDENTITY_TABLE_CHANGED);
    run(5);
    assert_int_equal(RT_COUNT(&rt, swaps), 2);
    /* the override is for other robots, never for a malformed identity */
    buf_t body = { .n = 0 };
    put_record(&body, "ur5", ROZ_UR5_INTERFACE_HASH);
    put_record(&body, "pan_tilt", ROZ_PAN_TILT_INTERFACE_HASH);
    w = with_identity(&body, &len);
    expect_load(w, len, ROZ_EINVAL, "two different records: 'ur5'", ROZ_IDENTITY_NONE);
}

/* ---- controllers clang built ----------------------------------------------------------- */

static void test_identity_built_controllers(void **st)
{
    size_t len;
    roz_identity_t id;
    (void)st;
    const uint8_t *w = roz_test_wasm_file(ROZ_IDENTITY_DIR "/identity_pan_tilt_sweep.wasm", &len);
    assert_int_equal(roz_identity_read(w, len, &id, NULL, 0), ROZ_OK);
    assert_true(id.present);
    assert_string_equal(id.robot_id, "pan_tilt");
    assert_true(id.hash == ROZ_PAN_TILT_INTERFACE_HASH);

    start(&roz_manifest_pan_tilt, 0);
    expect_load(w, len, ROZ_OK, NULL, ROZ_IDENTITY_SAME);
    run(50);
    assert_true(roz_runtime_last_commands(&rt)[0] != 0.0); /* it pans */
    roz_runtime_deinit(&rt);

    start(&roz_manifest_ur5, 0);
    expect_load(w, len, ROZ_EINVAL, "controller built for robot 'pan_tilt'",
                ROZ_IDENTITY_OTHER_ROBOT);
    w = roz_test_wasm_file(ROZ_CONTROLLER_DIR "/pd_hold.wasm", &len); /* includes ur5_channels.h */
    expect_load(w, len, ROZ_OK, NULL, ROZ_IDENTITY_SAME);
    run(1); /* takes the pending swap */
    w = roz_test_wasm_file(ROZ_CONTROLLER_DIR "/sine.wasm", &len); /* works with any manifest */
    expect_load(w, len, ROZ_OK, NULL, ROZ_IDENTITY_NONE);
    roz_runtime_deinit(&rt);

    start(&roz_manifest_pan_tilt, 0);
    w = roz_test_wasm_file(ROZ_CONTROLLER_DIR "/pd_hold.wasm", &len);
    expect_load(w, len, ROZ_EINVAL, "controller built for robot 'ur5'", ROZ_IDENTITY_OTHER_ROBOT);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_identity_hash_is_rozgens),
              cmocka_unit_test(test_identity_hash_worked_example),
              cmocka_unit_test(test_identity_hash_covers_the_table),
              cmocka_unit_test(test_identity_read),
              cmocka_unit_test(test_identity_malformed),
              cmocka_unit_test(test_identity_check),
              cmocka_unit_test_teardown(test_identity_runtime_refuses_another_robot, teardown),
              cmocka_unit_test_teardown(test_identity_runtime_override, teardown),
              cmocka_unit_test_teardown(test_identity_built_controllers, teardown))
