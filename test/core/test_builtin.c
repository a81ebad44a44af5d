/* SPDX-License-Identifier: Apache-2.0 */
/* The built-in manifests as rozgen generated them from manifests/:
 * registry, documented values, index constants, humanoid layout. */
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
#include "quadcopter_manifest.h"
#include "roz/builtin.h"
#include "roz/manifest.h"
#include "support.h"
#include "unitree_g1_12dof_manifest.h"
#include "unitree_g1_23dof_manifest.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"

static void test_builtin_registry(void **state)
{
    static const char *const ids[] = { "agibot_x2", "diff_drive", "engineai_pm01",
                                       "quadcopter", "unitree_g1", "unitree_g1_12dof",
                                       "unitree_g1_23dof",
                                       "ur5" };
    (void)state;
    assert_int_equal(roz_builtin_count(), sizeof ids / sizeof ids[0]);
    for (size_t i = 0; i < sizeof ids / sizeof ids[0]; i++) {
        const roz_manifest_t *m = roz_builtin_at(i);
        roz_manifest_problem_t p;
        assert_non_null(m);
        assert_string_equal(m->robot_id, ids[i]); /* sorted by id */
        assert_ptr_equal(roz_builtin_find(ids[i]), m);
        if (roz_manifest_validate(m, &p) != ROZ_OK)
            fail_msg("%s: rule %d, %s %d", ids[i], (int)p.rule,
                     p.is_state ? "state" : "command", (int)p.index);
    }
    assert_null(roz_builtin_at(roz_builtin_count()));
    assert_null(roz_builtin_find("ur10"));
    assert_null(roz_builtin_find(""));
    assert_null(roz_builtin_find(NULL));
    assert_ptr_equal(roz_builtin_find("ur5"), &roz_manifest_ur5);
}

static void test_builtin_ur5(void **state)
{
    static const char *const joints[] = { "shoulder_pan_joint", "shoulder_lift_joint",
                                          "elbow_joint",        "wrist_1_joint",
                                          "wrist_2_joint",      "wrist_3_joint" };
    const roz_manifest_t *m = &roz_manifest_ur5;
    (void)state;
    assert_string_equal(m->robot_class, "manipulator");
    assert_int_equal(m->control_rate_hz, 100);
    assert_int_equal(m->n_commands, 6);
    assert_int_equal(m->n_states, 12);
    assert_null(m->hardware);

    /* the documented spot check: channel 3 */
    const roz_channel_t *c = &m->commands[3];
    assert_string_equal(c->name, "wrist_1_joint/velocity");
    assert_int_equal(c->type, ROZ_IF_VELOCITY);
    assert_string_equal(c->unit, "rad/s");
    assert_true(c->min == -3.14 && c->max == 3.14);
    assert_true(c->max_rate == 0.5);
    assert_true(c->default_value == 0.0);
    assert_int_equal(c->position_state, 3);
    assert_int_equal(ROZ_UR5_CMD_WRIST_1_JOINT_VELOCITY, 3);
    assert_int_equal(ROZ_UR5_STATE_WRIST_1_JOINT_POSITION, 3);

    for (int i = 0; i < 6; i++) {
        char name[64];
        snprintf(name, sizeof name, "%s/velocity", joints[i]);
        assert_int_equal(roz_manifest_find_command(m, name), i);
        assert_int_equal(m->commands[i].position_state, i);
        snprintf(name, sizeof name, "%s/position", joints[i]);
        assert_int_equal(roz_manifest_find_state(m, name), i);
        assert_int_equal(m->states[i].type, ROZ_IF_POSITION);
        assert_true(m->states[i].max == 6.283185307179586 && m->states[i].min == -m->states[i].max);
        snprintf(name, sizeof name, "%s/velocity", joints[i]);
        assert_int_equal(roz_manifest_find_state(m, name), 6 + i);
    }
    assert_int_equal(ROZ_UR5_N_COMMANDS, 6);
    assert_int_equal(ROZ_UR5_N_STATES, 12);
    assert_int_equal(ROZ_UR5_CONTROL_RATE_HZ, 100);
}

static void test_builtin_mobile_and_drone(void **state)
{
    const roz_manifest_t *q = &roz_manifest_quadcopter;
    const roz_manifest_t *d = &roz_manifest_diff_drive;
    (void)state;
    assert_string_equal(q->robot_class, "drone");
    assert_int_equal(q->n_commands, 4);
    assert_int_equal(q->n_states, 4);
    assert_int_equal(ROZ_QUADCOPTER_CMD_BODY_VELOCITY_Z, 2);
    assert_true(q->commands[ROZ_QUADCOPTER_CMD_BODY_VELOCITY_Z].max == 3.0);
    assert_true(q->commands[ROZ_QUADCOPTER_CMD_BODY_VELOCITY_X].max == 5.0);
    assert_true(q->commands[ROZ_QUADCOPTER_CMD_BODY_YAW_RATE].max == 1.57);
    assert_int_equal(roz_manifest_find_state(q, "body/yaw"), ROZ_QUADCOPTER_STATE_BODY_YAW);
    for (int i = 0; i < q->n_states; i++)
        assert_int_equal(q->states[i].type, ROZ_IF_POSITION);

    assert_string_equal(d->robot_class, "mobile");
    assert_int_equal(d->n_commands, 2);
    assert_int_equal(d->n_states, 3);
    assert_true(d->commands[ROZ_DIFF_DRIVE_CMD_BASE_LINEAR_X].max == 1.0);
    assert_true(d->commands[ROZ_DIFF_DRIVE_CMD_BASE_ANGULAR_Z].min == -2.0);
    assert_int_equal(roz_manifest_find_state(d, "base/odom.yaw"), ROZ_DIFF_DRIVE_STATE_BASE_ODOM_YAW);
}

/* Humanoid layout: blocks by type, each in the SDK's joint order; position
 * and velocity commands pair with the joint's position state; gains and
 * effort are unpaired; IMU last. */
static void check_humanoid(const roz_manifest_t *m, uint16_t joints, const char *port,
                           const char *first, const char *last, double kd_default)
{
    static const char *const cmd_suffix[] = { "position", "velocity", "stiffness", "damping",
                                              "effort" };
    static const roz_interface_t cmd_type[] = { ROZ_IF_POSITION, ROZ_IF_VELOCITY,
                                                ROZ_IF_STIFFNESS, ROZ_IF_DAMPING,
                                                ROZ_IF_EFFORT };
    static const char *const imu[] = {
        "base_imu/orientation.x", "base_imu/orientation.y", "base_imu/orientation.z",
        "base_imu/orientation.w", "base_imu/angular_velocity.x", "base_imu/angular_velocity.y",
        "base_imu/angular_velocity.z", "base_imu/linear_acceleration.x",
        "base_imu/linear_acceleration.y", "base_imu/linear_acceleration.z",
    };
    char name[96];

    assert_string_equal(m->robot_class, "humanoid");
    assert_int_equal(m->control_rate_hz, 500);
    assert_int_equal(m->n_commands, 5 * joints);
    assert_int_equal(m->n_states, 3 * joints + 10);
    assert_non_null(m->hardware);
    assert_string_equal(m->hardware->port, port);
    assert_int_equal(m->hardware->n_joints, joints);
    assert_string_equal(m->hardware->joints[0], first);
    assert_string_equal(m->hardware->joints[joints - 1], last);

    for (uint16_t j = 0; j < joints; j++) {
        const char *jn = m->hardware->joints[j];
        for (int b = 0; b < 5; b++) {
            const roz_channel_t *c = &m->commands[b * joints + j];
            snprintf(name, sizeof name, "%s/%s", jn, cmd_suffix[b]);
            assert_string_equal(c->name, name);
            assert_int_equal(c->type, cmd_type[b]);
            /* position, velocity and effort are paired with the joint's
             * position; the gains are not */
            if (c->type == ROZ_IF_POSITION || c->type == ROZ_IF_VELOCITY ||
                c->type == ROZ_IF_EFFORT)
                assert_int_equal(c->position_state, j);
            else
                assert_int_equal(c->position_state, ROZ_CHANNEL_UNPAIRED);
        }
        const roz_channel_t *pos_cmd = &m->commands[j];
        const roz_channel_t *pos_state = &m->states[j];
        snprintf(name, sizeof name, "%s/position", jn);
        assert_string_equal(pos_state->name, name);
        assert_int_equal(pos_state->type, ROZ_IF_POSITION);
        assert_true(pos_cmd->min == pos_state->min && pos_cmd->max == pos_state->max);
        assert_true(pos_cmd->max_rate > 0.0); /* position targets never jump */
        /* stop defaults: a hold (SAFETY.md, "Stops in physics"): the position
         * setpoint latched, a hold stiffness inside the channel, no effort */
        assert_int_equal(pos_cmd->safe_default, ROZ_SAFE_HOLD);
        assert_true(m->commands[2 * joints + j].default_value > 0.0);
        assert_true(m->commands[2 * joints + j].default_value <= m->commands[2 * joints + j].max);
        assert_true(m->commands[2 * joints + j].min == 0.0);
        assert_true(m->commands[3 * joints + j].default_value == kd_default);
        assert_true(m->commands[4 * joints + j].default_value == 0.0);
        assert_true(m->commands[4 * joints + j].min == -m->commands[4 * joints + j].max);
        snprintf(name, sizeof name, "%s/velocity", jn);
        assert_int_equal(roz_manifest_find_state(m, name), joints + j);
        snprintf(name, sizeof name, "%s/effort", jn);
        assert_int_equal(roz_manifest_find_state(m, name), 2 * joints + j);
    }
    for (int i = 0; i < 10; i++)
        assert_string_equal(m->states[3 * joints + i].name, imu[i]);
    assert_true(m->states[3 * joints + 3].default_value == 1.0); /* w */
}

static void test_builtin_humanoids(void **state)
{
    (void)state;
    check_humanoid(&roz_manifest_unitree_g1, 29, "unitree/G1", "left_hip_pitch_joint",
                   "right_wrist_yaw_joint", 8.0);
    check_humanoid(&roz_manifest_unitree_g1_23dof, 23, "unitree/G1", "left_hip_pitch_joint",
                   "right_wrist_roll_joint", 8.0);
    check_humanoid(&roz_manifest_agibot_x2, 30, "agibot/X2", "left_hip_pitch_joint",
                   "head_yaw_joint", 4.0);
    check_humanoid(&roz_manifest_engineai_pm01, 24, "engineai/PM01", "J00_HIP_PITCH_L",
                   "J23_HEAD_YAW", 5.0);

    /* the 12-joint G1 (a simulation robot: no [hardware]): the 29-DoF G1's
     * leg channels, block by block, and its IMU */
    const roz_manifest_t *g12 = &roz_manifest_unitree_g1_12dof;
    const roz_manifest_t *g29 = &roz_manifest_unitree_g1;
    assert_null(g12->hardware);
    assert_int_equal(g12->n_commands, 5 * 12);
    assert_int_equal(g12->n_states, 3 * 12 + 10);
    for (int i = 0; i < g12->n_commands + g12->n_states; i++) {
        int st = i >= g12->n_commands, k = st ? i - g12->n_commands : i;
        const roz_channel_t *c = st ? &g12->states[k] : &g12->commands[k];
        int k29 = k < (st ? 36 : 60) ? k / 12 * 29 + k % 12 : k - 36 + 87;
        const roz_channel_t *c29 = st ? &g29->states[k29] : &g29->commands[k29];
        assert_string_equal(c->name, c29->name);
        assert_int_equal(c->type, c29->type);
        assert_true(c->min == c29->min && c->max == c29->max && c->max_rate == c29->max_rate);
        assert_true(c->default_value == c29->default_value);
        assert_int_equal(c->position_state, c29->position_state);
        assert_int_equal(c->safe_default, c29->safe_default);
    }

    /* G1 spot checks from reference/robots.md 1.6 */
    const roz_manifest_t *g1 = &roz_manifest_unitree_g1;
    assert_int_equal(ROZ_UNITREE_G1_N_COMMANDS, 145);
    assert_int_equal(ROZ_UNITREE_G1_N_STATES, 97);
    const roz_channel_t *knee = &g1->commands[ROZ_UNITREE_G1_CMD_LEFT_KNEE_JOINT_POSITION];
    assert_string_equal(knee->name, "left_knee_joint/position");
    assert_true(knee->min == -0.087267 && knee->max == 2.8798);
    const roz_channel_t *rhr = &g1->states[ROZ_UNITREE_G1_STATE_RIGHT_HIP_ROLL_JOINT_POSITION];
    assert_true(rhr->min == -2.9671 && rhr->max == 0.5236); /* right mirror */
    assert_true(g1->commands[ROZ_UNITREE_G1_CMD_LEFT_ANKLE_PITCH_JOINT_EFFORT].max == 35.0);
    assert_int_equal(ROZ_UNITREE_G1_CMD_WAIST_YAW_JOINT_POSITION, 12);
    assert_string_equal(g1->hardware->joints[12], "waist_yaw_joint");
    assert_int_equal(g1->hardware->n_params, 1);
    assert_string_equal(g1->hardware->params[0].key, "dds_domain");
    assert_string_equal(g1->hardware->params[0].value, "0");

    const roz_manifest_t *pm = &roz_manifest_engineai_pm01;
    assert_string_equal(pm->hardware->params[0].value, "69");
    assert_int_equal(ROZ_ENGINEAI_PM01_CMD_J12_WAIST_YAW_POSITION, 12);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_builtin_registry),
              cmocka_unit_test(test_builtin_ur5),
              cmocka_unit_test(test_builtin_mobile_and_drone),
              cmocka_unit_test(test_builtin_humanoids))
