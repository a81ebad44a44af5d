/* SPDX-License-Identifier: Apache-2.0 */
/* The [hardware] keys of a CAN robot (roz/port/can_config.h) beyond what the
 * shared fixtures check (their messages agree with rozgen's, compare_vectors):
 * what a valid table gives (the leg example's joints, channels, ranges,
 * directions, offsets), the caller's parameters over robot.toml's, the bus
 * figures worked out by hand (frames, groups, load, intervals, timeouts),
 * manifests that are no CAN robot, numbers under another C locale; and the
 * holds the port sends (roz/port/can_hold.h): the command watchdog's keeps
 * the last command's torque at the hold gains, inside every channel. */
#include <locale.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/port/can_config.h"
#include "roz/port/can_hold.h"
#include "roz/manifest_toml.h"
#include "support.h"

#ifndef ROZ_SOURCE_DIR
#error "ROZ_SOURCE_DIR: the repository"
#endif

static char text[1u << 16];
static roz_manifest_storage_t storage;
static roz_can_config_t cfg;
ROZ_TOML_DOC_DEFINE(doc, 4096, 1u << 16);

static const roz_manifest_t *load_leg(void)
{
    size_t len = 0;
    roz_manifest_toml_problem_t problem;
    roz_toml_init(&doc, doc_nodes, sizeof doc_nodes / sizeof doc_nodes[0], doc_arena,
                  sizeof doc_arena);
    assert_int_equal(roz_manifest_toml_read_file(ROZ_SOURCE_DIR "/examples/can_leg/leg.toml", text,
                                                 sizeof text, &len, &problem),
                     ROZ_OK);
    assert_int_equal(roz_manifest_toml_load(&storage, &doc, text, len, &problem, 1, NULL), ROZ_OK);
    return &storage.manifest;
}

typedef struct {
    unsigned n;
    char     rule[32];
    char     first[ROZ_CFG_PROBLEM_LEN];
} seen_t;

static void collect(void *ctx, const char *rule, const char *what)
{
    seen_t *s = ctx;
    if (s->n++ == 0) {
        snprintf(s->rule, sizeof s->rule, "%s", rule);
        snprintf(s->first, sizeof s->first, "%s", what);
    }
}

static void test_can_config_the_leg(void **state)
{
    const roz_manifest_t *m = load_leg();
    seen_t seen = { 0 };
    (void)state;
    assert_int_equal(roz_can_config_load(&cfg, m, NULL, collect, &seen), ROZ_OK);
    assert_int_equal(seen.n, 0);
    assert_string_equal(cfg.network_interface, "can0");
    assert_int_equal(cfg.bitrate, 1000000);
    assert_int_equal(cfg.command_writer_period_us, 2000);
    assert_int_equal(cfg.n_joints, 3);

    static const char *const names[] = { "hip", "thigh", "knee" };
    for (int j = 0; j < 3; j++) {
        const roz_can_joint_t *jt = &cfg.joints[j];
        char ch[64];
        assert_string_equal(jt->name, names[j]);
        assert_int_equal(jt->can_id, j + 1);
        assert_int_equal(jt->reply, ROZ_MIT_REPLY_TEMP_ERROR);
        /* bound by name: commands j*5 .. j*5+4, states j*3 .. j*3+2 */
        snprintf(ch, sizeof ch, "%s/position", names[j]);
        assert_int_equal(jt->pos_cmd, roz_manifest_find_command(m, ch));
        assert_int_equal(jt->pos_state, roz_manifest_find_state(m, ch));
        snprintf(ch, sizeof ch, "%s/velocity", names[j]);
        assert_int_equal(jt->vel_cmd, roz_manifest_find_command(m, ch));
        assert_int_equal(jt->vel_state, roz_manifest_find_state(m, ch));
        snprintf(ch, sizeof ch, "%s/stiffness", names[j]);
        assert_int_equal(jt->kp_cmd, roz_manifest_find_command(m, ch));
        snprintf(ch, sizeof ch, "%s/damping", names[j]);
        assert_int_equal(jt->kd_cmd, roz_manifest_find_command(m, ch));
        snprintf(ch, sizeof ch, "%s/effort", names[j]);
        assert_int_equal(jt->eff_cmd, roz_manifest_find_command(m, ch));
        assert_int_equal(jt->eff_state, roz_manifest_find_state(m, ch));
        assert_true(jt->pos_cmd >= 0 && jt->eff_state >= 0);
        assert_true(jt->ranges.position.min == -12.5 && jt->ranges.position.max == 12.5);
        assert_true(jt->ranges.velocity.min == -45.0 && jt->ranges.velocity.max == 45.0);
        assert_true(jt->ranges.kp.min == 0.0 && jt->ranges.kp.max == 500.0);
        assert_true(jt->ranges.kd.min == 0.0 && jt->ranges.kd.max == 5.0);
    }
    /* the knee: its own torque range, turned round, offset */
    assert_true(cfg.joints[0].ranges.torque.max == 18.0 && cfg.joints[2].ranges.torque.max == 24.0);
    assert_int_equal(cfg.joints[0].direction, 1);
    assert_int_equal(cfg.joints[2].direction, -1);
    assert_true(cfg.joints[0].zero_offset == 0.0 && cfg.joints[2].zero_offset == -1.2);

    /* by hand: a command is 8 bytes, 47 + 64 + floor(97/4) = 135 bits worst
     * case; a temperature_error reply the same: 3 joints x 270 = 810 bits in
     * a 2000 us round of a 1 Mbit/s bus (2000 bits): 40.5 %, one group */
    assert_int_equal(ROZ_CAN_FRAME_BITS(8), 135);
    assert_int_equal(ROZ_CAN_FRAME_BITS(6), 115);
    assert_int_equal(cfg.round_us, 2000);
    assert_int_equal(cfg.groups, 1);
    assert_int_equal(cfg.group_bits, 810);
    assert_true(fabs(cfg.bus_load - 0.405) < 1e-12);
    assert_int_equal(cfg.joint_interval_us, 2000);
    assert_int_equal(cfg.reply_timeout_us, 20000); /* 20 ms > three intervals */
    assert_int_equal(cfg.command_timeout_us, 50000); /* 50 ms > five intervals or ticks */
}

static void test_can_config_caller_params_win(void **state)
{
    const roz_manifest_t *m = load_leg();
    roz_param_t items[] = { { "network_interface", "vcan0" }, { "can_id", "hip=0x21, thigh=0x22, knee=0x23" },
                            { "command_writer_period_us", "0" }, { "reply_timeout_us", "4000" } };
    roz_params_t extra = { items, sizeof items / sizeof items[0] };
    (void)state;
    assert_int_equal(roz_can_config_load(&cfg, m, &extra, NULL, NULL), ROZ_OK);
    assert_string_equal(cfg.network_interface, "vcan0");
    assert_int_equal(cfg.joints[2].can_id, 0x23);
    /* a round per write: the round is the control period, 1/500 s */
    assert_int_equal(cfg.command_writer_period_us, 0);
    assert_int_equal(cfg.round_us, 2000);
    assert_int_equal(cfg.reply_timeout_us, 4000);

    /* an unknown key from the caller is refused as one from robot.toml */
    roz_param_t bad = { "bitrates", "1" };
    roz_params_t extra_bad = { &bad, 1 };
    seen_t seen = { 0 };
    assert_int_equal(roz_can_config_load(&cfg, m, &extra_bad, collect, &seen), ROZ_EINVAL);
    assert_int_equal(seen.n, 1);
    assert_string_equal(seen.rule, "unknown-key");
    assert_non_null(strstr(seen.first, "bitrates: unknown key of the socketcan port"));
}

/* A robot built by hand: n joints with one effort command each. */
static roz_channel_t hand_commands[ROZ_CAN_MAX_JOINTS];
static char hand_names[ROZ_CAN_MAX_JOINTS][2][24];
static const char *hand_joints[ROZ_CAN_MAX_JOINTS];
static roz_param_t hand_params[16];
static roz_hardware_t hand_hw;
static roz_manifest_t hand;
static char hand_ids[ROZ_CAN_MAX_JOINTS * 12];

static const roz_manifest_t *hand_robot(uint16_t n, const char *reply, const char *period,
                                        const char *bitrate)
{
    size_t used = 0;
    hand_ids[0] = '\0';
    for (uint16_t j = 0; j < n; j++) {
        snprintf(hand_names[j][0], sizeof hand_names[j][0], "j%u", (unsigned)j);
        snprintf(hand_names[j][1], sizeof hand_names[j][1], "j%u/effort", (unsigned)j);
        hand_joints[j] = hand_names[j][0];
        hand_commands[j] = (roz_channel_t){ .name = hand_names[j][1], .type = ROZ_IF_EFFORT,
                                            .unit = "N.m", .min = -1.0, .max = 1.0,
                                            .position_state = ROZ_CHANNEL_UNPAIRED };
        used += (size_t)snprintf(hand_ids + used, sizeof hand_ids - used, "%sj%u=%u",
                                 j > 0 ? ", " : "", (unsigned)j, (unsigned)j + 1u);
    }
    size_t k = 0;
    hand_params[k++] = (roz_param_t){ "can_id", hand_ids };
    hand_params[k++] = (roz_param_t){ "reply", reply };
    hand_params[k++] = (roz_param_t){ "position_range", "-12.5:12.5" };
    hand_params[k++] = (roz_param_t){ "velocity_range", "-45:45" };
    hand_params[k++] = (roz_param_t){ "stiffness_range", "0:500" };
    hand_params[k++] = (roz_param_t){ "damping_range", "0:5" };
    hand_params[k++] = (roz_param_t){ "effort_range", "-18:18" };
    hand_params[k++] = (roz_param_t){ "command_writer_period_us", period };
    hand_params[k++] = (roz_param_t){ "bitrate", bitrate };
    hand_hw = (roz_hardware_t){ "socketcan", hand_joints, n, hand_params, (uint16_t)k };
    hand = (roz_manifest_t){ "hand", "legged", 500, hand_commands, n, NULL, 0, &hand_hw, NULL, 0, 0, NULL, NULL };
    assert_int_equal(roz_manifest_validate(&hand, NULL), ROZ_OK);
    return &hand;
}

static void test_can_config_round_robin(void **state)
{
    seen_t seen = { 0 };
    (void)state;
    /* 12 joints, 270 bits each (8-byte replies), 80 % of 2000 bits = 1600:
     * 6 a round would be 1620, so 3 groups of 4 (1080 bits, 54 %), each
     * joint every 6 ms; the timeout default stays 20 ms (> 18 ms) */
    assert_int_equal(roz_can_config_load(&cfg, hand_robot(12, "temperature_error", "2000",
                                                          "1000000"),
                                         NULL, collect, &seen),
                     ROZ_OK);
    assert_int_equal(cfg.groups, 3);
    assert_int_equal(cfg.group_bits, 1080);
    assert_true(fabs(cfg.bus_load - 0.54) < 1e-12);
    assert_int_equal(cfg.joint_interval_us, 6000);
    assert_int_equal(cfg.reply_timeout_us, 20000);

    /* 6-byte replies: 250 bits a joint, 6 a round = 1500: 2 groups */
    assert_int_equal(roz_can_config_load(&cfg, hand_robot(12, "basic", "2000", "1000000"), NULL,
                                         NULL, NULL),
                     ROZ_OK);
    assert_int_equal(cfg.groups, 2);
    assert_int_equal(cfg.group_bits, 1500);

    /* 12 joints at 250 kbit/s: 400 bits a round, one joint (250) a round:
     * 12 groups, each joint every 24 ms, so the timeout is 72 ms */
    assert_int_equal(roz_can_config_load(&cfg, hand_robot(12, "basic", "2000", "250000"), NULL,
                                         NULL, NULL),
                     ROZ_OK);
    assert_int_equal(cfg.groups, 12);
    assert_int_equal(cfg.joint_interval_us, 24000);
    assert_int_equal(cfg.reply_timeout_us, 72000);
    assert_int_equal(cfg.command_timeout_us, 120000); /* five intervals */

    /* 64 joints, the most there may be: still a configuration */
    assert_int_equal(roz_can_config_load(&cfg, hand_robot(ROZ_CAN_MAX_JOINTS, "basic", "2000",
                                                          "1000000"),
                                         NULL, NULL, NULL),
                     ROZ_OK);
    assert_int_equal(cfg.n_joints, ROZ_CAN_MAX_JOINTS);
}

static void test_can_config_not_a_can_robot(void **state)
{
    const roz_manifest_t *m = hand_robot(2, "basic", "2000", "1000000");
    roz_manifest_t other = *m;
    roz_hardware_t hw = hand_hw;
    seen_t seen = { 0 };
    (void)state;
    other.hardware = NULL;
    assert_int_equal(roz_can_config_load(&cfg, &other, NULL, collect, &seen), ROZ_EINVAL);
    assert_string_equal(seen.rule, "can-joint");
    assert_non_null(strstr(seen.first, "needs the [hardware] table"));

    hw.port = "unitree/G1";
    other.hardware = &hw;
    memset(&seen, 0, sizeof seen);
    assert_int_equal(roz_can_config_load(&cfg, &other, NULL, collect, &seen), ROZ_EINVAL);
    assert_string_equal(seen.first, ": hardware: port \"unitree/G1\": this robot is not one for "
                                    "the socketcan port");
}

/* strtod follows the C locale's decimal point, which a host may have set
 * (as test_toml_floats_any_locale: where such a locale is installed). */
static void test_can_config_any_locale(void **state)
{
    static const char *const locales[] = { "de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8",
                                           "C.UTF-8" };
    (void)state;
    for (size_t i = 0; i < sizeof locales / sizeof locales[0]; i++) {
        if (setlocale(LC_NUMERIC, locales[i]) == NULL)
            continue;
        const roz_manifest_t *m = load_leg();
        int rc = roz_can_config_load(&cfg, m, NULL, NULL, NULL);
        setlocale(LC_NUMERIC, "C");
        assert_int_equal(rc, ROZ_OK);
        assert_true(cfg.joints[2].zero_offset == -1.2);
        assert_true(cfg.joints[2].ranges.torque.min == -24.0);
    }
}

/* The command watchdog's timeout: at least two command intervals of a joint
 * and two ticks, else refused naming key, value and why. */
static void test_can_config_command_timeout(void **state)
{
    const roz_manifest_t *m = load_leg();
    seen_t seen = { 0 };
    (void)state;
    roz_param_t ok = { "command_timeout_us", "4000" };
    roz_params_t extra = { &ok, 1 };
    assert_int_equal(roz_can_config_load(&cfg, m, &extra, NULL, NULL), ROZ_OK);
    assert_int_equal(cfg.command_timeout_us, 4000);
    roz_param_t short_one = { "command_timeout_us", "3999" };
    extra.items = &short_one;
    assert_int_equal(roz_can_config_load(&cfg, m, &extra, collect, &seen), ROZ_EINVAL);
    assert_string_equal(seen.rule, "can-bus");
    assert_non_null(strstr(seen.first, "command_timeout_us \"3999\": shorter than two command "
                                       "intervals of a joint or two ticks (2 x 2000 us)"));
    static const char *const bad[] = { "999", "60000001", "fast", "-1" };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        roz_param_t b = { "command_timeout_us", bad[i] };
        extra.items = &b;
        memset(&seen, 0, sizeof seen);
        assert_int_equal(roz_can_config_load(&cfg, m, &extra, collect, &seen), ROZ_EINVAL);
        assert_string_equal(seen.rule, "can-param");
        char want[80];
        snprintf(want, sizeof want, "command_timeout_us \"%s\"", bad[i]);
        if (strstr(seen.first, want) == NULL || strstr(seen.first, "1000..60000000") == NULL)
            fail_msg("\"%s\": \"%s\" names neither the key, the value nor the range", bad[i],
                     seen.first);
    }
}

static void test_can_config_rules_and_keys(void **state)
{
    const char *const *rules = roz_can_config_rules();
    const char *const *keys = roz_can_config_keys();
    size_t n = 0;
    (void)state;
    while (rules[n] != NULL)
        n++;
    assert_int_equal(n, 7);
    for (n = 0; keys[n] != NULL; n++)
        ;
    assert_int_equal(n, 27); /* 19, and the two threads' four each */
    assert_string_equal(keys[0], "network_interface");
    assert_string_equal(keys[26], "zero_offset");
}

/* ---- the holds (roz/port/can_hold.h) ------------------------------------- */

static roz_channel_t hold_cmds[ROZ_CFG_MAX_COMMANDS];
static roz_manifest_t hold_leg;

/* The leg with stiffness channels whose default (the hold stiffness) is
 * @p kp: the leg's own is 0 (its stop is damping only); its position
 * commands capped at 0.1 rad a tick, so a hold stays within 0.5 rad of the
 * measured position (roz_hold_band()). */
static const roz_can_joint_t *leg_with_hold(double kp, const char *joint)
{
    const roz_manifest_t *m = load_leg();
    assert_int_equal(roz_can_config_load(&cfg, m, NULL, NULL, NULL), ROZ_OK);
    memcpy(hold_cmds, m->commands, m->n_commands * sizeof hold_cmds[0]);
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (hold_cmds[i].type == ROZ_IF_STIFFNESS)
            hold_cmds[i].default_value = kp;
        if (hold_cmds[i].type == ROZ_IF_POSITION)
            hold_cmds[i].max_rate = 0.1;
    }
    hold_leg = *m;
    hold_leg.commands = hold_cmds;
    for (uint16_t j = 0; j < cfg.n_joints; j++) {
        if (strcmp(cfg.joints[j].name, joint) == 0)
            return &cfg.joints[j];
    }
    fail_msg("the leg has no joint %s", joint);
    return NULL;
}

/* Joint-frame position of an actuator-frame one. */
static double joint_position(const roz_can_joint_t *jt, double actuator)
{
    return (double)jt->direction * actuator + jt->zero_offset;
}

static void test_can_hold_keeps_the_torque(void **state)
{
    roz_mit_command_t c;
    (void)state;
    /* the knee: direction -1, zero offset -1.2, limits [-2.7, -0.5]; held at
     * 20 after kp 30 at -1.0 measured at -1.2: 20 (q - -1.2) = 30 (-1.0 - -1.2) */
    const roz_can_joint_t *knee = leg_with_hold(20.0, "knee");
    roz_can_last_t last = { 1, -1.0, 30.0, -1.2 };
    roz_can_watchdog_hold(&hold_leg, knee, &last, -1.25, &c);
    assert_float_equal(joint_position(knee, c.position), -0.9, 1e-12);
    assert_float_equal(c.kp, 20.0, 0.0);
    assert_float_equal(c.kd, 0.5, 0.0); /* the damping channel's default */
    assert_float_equal(c.velocity, 0.0, 0.0);
    assert_float_equal(c.torque, 0.0, 0.0);
    assert_float_equal(20.0 * (joint_position(knee, c.position) - -1.2), 30.0 * (-1.0 - -1.2),
                       1e-12);

    /* far from the joint: within the band (0.5 rad) of the position
     * measured with the last command: 20 (q + 1.2) = 30 (-0.3 + 1.2) gives
     * 0.15, past the last setpoint, and the band stops it at -0.7 */
    last = (roz_can_last_t){ 1, -0.3, 30.0, -1.2 };
    roz_can_watchdog_hold(&hold_leg, knee, &last, -1.25, &c);
    assert_float_equal(joint_position(knee, c.position), -0.7, 1e-12);
    assert_true(20.0 * (joint_position(knee, c.position) - -1.2) <= 30.0 * (-0.3 - -1.2));

    /* a setpoint that would keep it lies outside the limits: at the limit */
    last = (roz_can_last_t){ 1, -0.6, 60.0, -1.0 }; /* -1.0 + 3 * 0.4 = 0.2 */
    roz_can_watchdog_hold(&hold_leg, knee, &last, -1.0, &c);
    assert_float_equal(joint_position(knee, c.position), -0.5, 1e-12);

    /* the leg's own hold stiffness, 0: damping at the position last sent */
    knee = leg_with_hold(0.0, "knee");
    last = (roz_can_last_t){ 1, -1.0, 30.0, -1.2 };
    roz_can_watchdog_hold(&hold_leg, knee, &last, -1.25, &c);
    assert_float_equal(c.kp, 0.0, 0.0);
    assert_float_equal(c.kd, 0.5, 0.0);
    assert_float_equal(joint_position(knee, c.position), -1.0, 1e-12);
}

static void test_can_hold_without_a_command_or_finite_values(void **state)
{
    roz_mit_command_t c;
    (void)state;
    const roz_can_joint_t *knee = leg_with_hold(20.0, "knee");
    /* nothing commanded yet: at the measured position */
    roz_can_last_t last = { 0, 0.0, 0.0, 0.0 };
    roz_can_watchdog_hold(&hold_leg, knee, &last, -1.7, &c);
    assert_float_equal(joint_position(knee, c.position), -1.7, 1e-12);
    assert_float_equal(c.kp, 20.0, 0.0);
    /* a measurement that is not finite: the position last sent */
    last = (roz_can_last_t){ 1, -1.0, 30.0, NAN };
    roz_can_watchdog_hold(&hold_leg, knee, &last, NAN, &c);
    assert_float_equal(joint_position(knee, c.position), -1.0, 1e-12);
    last = (roz_can_last_t){ 1, -1.0, INFINITY, -1.2 };
    roz_can_watchdog_hold(&hold_leg, knee, &last, -1.2, &c);
    assert_float_equal(joint_position(knee, c.position), -1.0, 1e-12);
    /* nothing known at all: no hold to compute, no stiffness */
    last = (roz_can_last_t){ 0, 0.0, 0.0, 0.0 };
    roz_can_watchdog_hold(&hold_leg, knee, &last, NAN, &c);
    assert_float_equal(c.kp, 0.0, 0.0);
    /* every value of every joint finite and inside its channel */
    static const double measured[] = { -3.0, -0.6, 0.0, 0.9, 5.0, NAN, INFINITY, -INFINITY };
    for (uint16_t j = 0; j < cfg.n_joints; j++) {
        const roz_can_joint_t *jt = &cfg.joints[j];
        for (size_t k = 0; k < sizeof measured / sizeof measured[0]; k++) {
            last = (roz_can_last_t){ 1, measured[(k + 3) % 8], 60.0, measured[k] };
            roz_can_watchdog_hold(&hold_leg, jt, &last, measured[(k + 1) % 8], &c);
            const roz_channel_t *p = &hold_leg.commands[jt->pos_cmd];
            double q = joint_position(jt, c.position);
            assert_true(q >= p->min - 1e-12 && q <= p->max + 1e-12);
            assert_true(isfinite(c.velocity) && isfinite(c.torque) && isfinite(c.kd));
        }
    }
}

ROZ_TEST_MAIN(cmocka_unit_test(test_can_config_the_leg),
              cmocka_unit_test(test_can_config_caller_params_win),
              cmocka_unit_test(test_can_config_round_robin),
              cmocka_unit_test(test_can_config_not_a_can_robot),
              cmocka_unit_test(test_can_config_any_locale),
              cmocka_unit_test(test_can_config_command_timeout),
              cmocka_unit_test(test_can_config_rules_and_keys),
              cmocka_unit_test(test_can_hold_keeps_the_torque),
              cmocka_unit_test(test_can_hold_without_a_command_or_finite_values))
