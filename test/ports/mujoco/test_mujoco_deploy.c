/* SPDX-License-Identifier: Apache-2.0 */
/* A policy deployed by rozgen-nn deploy, in physics, built once per
 * controller (DEPLOYED_CONTROLLER on DEPLOYED_ROBOT): g1_deployed.wasm
 * (examples/controllers: examples/policies/g1's small network with the
 * deploy_real configuration, the waist held at kp 300) on the built-in
 * 29-DoF G1, and g1_12dof_deployed.wasm (the same network with the
 * deploy_mujoco configuration) on unitree_g1_12dof, the model the policy
 * was trained on; each in MuJoCo for 6 simulated seconds, behind the
 * runtime and its filter. Every tick the same generated C built natively (this test's
 * second source, roz_policy.h with roz_nn.h's plain-C imports) is given the
 * state the module saw, and must send the module's targets bit for bit.
 * No fault, nothing outside the manifest reaches the model, and no gain of
 * the vendor's hold is clamped (the manifest carries Unitree's own deploy
 * gains). The small network walks nowhere: it is the mechanics; the figures
 * of a trained policy are on docs/policies.md. g1_deployed_full, the same at
 * the real policy's size, runs within the fuel the tool declared. */
/* white-box in part: reads the port's counters (roz/private.h) */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/builtin.h"
#include "roz/port/mujoco.h"
#include "roz/runtime.h"
#include "roz_controller.h" /* the native build's imports, defined below */
#include "support.h"
#include "support_runtime.h"

#define TICKS 3000 /* 6 s at 500 Hz */

#ifndef DEPLOYED_CONTROLLER /* the build says which (test/ports/mujoco/CMakeLists.txt) */
#define DEPLOYED_CONTROLLER "g1_deployed"
#define DEPLOYED_ROBOT "unitree_g1"
#endif

/* ---- the native build's imports ------------------------------------------------ */

static const double *native_state;
static double native_cmd[ROZ_CFG_MAX_COMMANDS];
static int native_estop;

int roz_state_get_all(double *values, int count)
{
    memcpy(values, native_state, sizeof values[0] * (size_t)count);
    return count;
}

int roz_command_set_all(const double *values, int count)
{
    memcpy(native_cmd, values, sizeof values[0] * (size_t)count);
    return 0;
}

void roz_request_estop(void)
{
    native_estop = 1;
}

/* ---- the test ------------------------------------------------------------------- */

static roz_mujoco_t mj;
static roz_runtime_t rt;

/* @p controller on the built-in @p robot for @p ticks; with @p native,
 * every tick's targets against the native build of the same C. Returns the
 * most fuel a tick took. */
static uint64_t run(const char *robot, const char *controller, long long ticks, int native);

static void test_mujoco_deploy(void **state)
{
    (void)state;
    (void)run(DEPLOYED_ROBOT, DEPLOYED_CONTROLLER, TICKS, 1);
}

/* The same configuration at the real policy's size (47 -> LSTM 64 -> 32 ELU
 * -> 12, random weights): its declared fuel holds the inference tick under
 * verification and in the run (a shortfall latches a fault). */
static void test_mujoco_deploy_g1_full_size(void **state)
{
    (void)state;
    if (strcmp(DEPLOYED_ROBOT, "unitree_g1") != 0)
        skip();
    uint64_t fuel = run("unitree_g1", "g1_deployed_full", 500, 0);
    assert_true(fuel > 40000); /* the inference ticks ran the whole network */
}

static uint64_t run(const char *robot, const char *controller, long long ticks, int native)
{
    const roz_manifest_t *builtin = roz_builtin_find(robot);
    assert_non_null(builtin);
    /* the small network is no trained policy and falls over in these
     * seconds: the built-in's fall rule would stop it (test_mujoco_fall
     * judges that); here the mechanics are judged to the end, so without
     * the rule (not part of the identity: the controller still loads) */
    static roz_manifest_t no_fall;
    no_fall = *builtin;
    no_fall.fall = NULL;
    const roz_manifest_t *m = &no_fall;
    roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
    roz_test_port_open(&p, m, NULL);
    roz_runtime_config_t cfg;
    roz_test_clock_t clk;
    roz_test_physics_config(&cfg, m, p, &clk);
    roz_test_runtime_start(&rt, &cfg, controller); /* its identity: this G1's */

    int inferences = 0;
    double last_target = NAN, lowest = INFINITY;
    for (long long t = 0; t < ticks; t++) {
        assert_int_equal(roz_runtime_tick(&rt), ROZ_OK);
        const double *targets = roz_runtime_last_targets(&rt);
        assert_non_null(targets);
        native_state = roz_runtime_last_state(&rt);
        if (native)
            roz_native_process(t);
        if (native && memcmp(native_cmd, targets, sizeof targets[0] * m->n_commands) != 0) {
            for (size_t i = 0; i < m->n_commands; i++)
                if (memcmp(&native_cmd[i], &targets[i], sizeof targets[i]) != 0)
                    fail_msg("tick %lld: %s: wasm %a, native %a", t, m->commands[i].name,
                             targets[i], native_cmd[i]);
        }
        if (targets[0] != last_target) /* left hip pitch: moves at an inference */
            inferences++;
        last_target = targets[0];
        roz_port_truth_t truth;
        if (roz_port_truth(&p, &truth) == ROZ_OK && truth.pos[2] < lowest)
            lowest = truth.pos[2];
    }
    roz_runtime_stats_t st;
    assert_int_equal(roz_runtime_stats(&rt, &st), ROZ_OK);
    print_message("%s on %s: %d target changes in %lld ticks (an inference every 10), "
                  "pelvis lowest %.3f m, fuel max %llu units a tick\n", controller, robot,
                  inferences, ticks, lowest, (unsigned long long)st.runtime.max_fuel);
    assert_true(inferences > ticks / 10 / 2);
    assert_int_equal(native_estop, 0);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(mj.violations, 0);
    /* the vendor's hold and the policy's gains pass the filter unclamped */
    for (size_t i = 0; i < m->n_commands; i++) {
        roz_filter_channel_counters_t c;
        assert_int_equal(roz_runtime_channel_counters(&rt, i, &c), ROZ_OK);
        if (m->commands[i].type == ROZ_IF_STIFFNESS || m->commands[i].type == ROZ_IF_DAMPING) {
            if (c.clamps != 0)
                fail_msg("%s: %u clamps", m->commands[i].name, (unsigned)c.clamps);
        }
    }
    roz_runtime_deinit(&rt);
    roz_port_close(&p);
    return st.runtime.max_fuel;
}

ROZ_TEST_MAIN(cmocka_unit_test(test_mujoco_deploy),
              cmocka_unit_test(test_mujoco_deploy_g1_full_size))
