/* SPDX-License-Identifier: Apache-2.0 */
/* The team's own learned policy in physics: the UR5 hold behaviour-cloned
 * from pd_hold.c (examples/controllers/ur5_bc/, trained on a kinematic
 * teacher in numpy) on the built-in MuJoCo UR5 (a UR5e from its home
 * keyframe, the velocity servo of docs/ports/mujoco.md), against its teacher
 * on the same model. Both start 3.14 rad from pd_hold's pose (wrist 2).
 * Measured here (5 simulated seconds): the teacher ends within 0.5 mrad of
 * the pose, the policy within 5.3 mrad on every joint (its fit's residual);
 * bounded at 20 mrad, four times that, with no fault, no torque saturated
 * and no value outside the manifest. */
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
#include "support.h"
#include "support_runtime.h"

#define TICKS 500       /* 5 s at the UR5's 100 Hz */
#define BOUND_RAD 0.020 /* per joint, from the pose and from the teacher */

static const double pose[6] = { 0.0, -1.2, 1.5, -0.3, 1.57, 0.0 }; /* pd_hold.c's */

static roz_mujoco_t mj;
static roz_runtime_t rt;

/* @p controller on the built-in UR5 for TICKS ticks; its joint positions
 * at the end in @p q. */
static void run(const char *controller, double q[6])
{
    const roz_manifest_t *m = roz_builtin_find("ur5");
    assert_non_null(m);
    roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
    roz_test_port_open(&p, m, NULL);

    roz_runtime_config_t cfg;
    roz_test_clock_t clk;
    roz_test_physics_config(&cfg, m, p, &clk);
    roz_test_runtime_start(&rt, &cfg, controller);
    double st[ROZ_CFG_MAX_STATES];
    for (int t = 0; t < TICKS; t++)
        assert_int_equal(roz_runtime_tick(&rt), ROZ_OK);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_true(roz_port_read(&p, st, m->n_states) >= 0);
    memcpy(q, st, 6 * sizeof q[0]);
    assert_int_equal(mj.saturated, 0);
    assert_int_equal(mj.clamped, 0);
    roz_runtime_deinit(&rt);
    roz_port_close(&p);
}

static void test_mujoco_bc_reaches_the_pose(void **state)
{
    double learned[6], teacher[6], worst = 0.0;
    (void)state;
    run("pd_hold", teacher);
    run("ur5_bc", learned);
    for (int j = 0; j < 6; j++) {
        double e = fabs(learned[j] - pose[j]);
        print_message("joint %d after %.0f s: ur5_bc %+.5f, pd_hold %+.5f, pose %+.5f "
                      "(error %.2f mrad)\n",
                      j, TICKS / 100.0, learned[j], teacher[j], pose[j], 1e3 * e);
        worst = e > worst ? e : worst;
        assert_true(fabs(teacher[j] - pose[j]) < BOUND_RAD);
        assert_true(e < BOUND_RAD);
        assert_true(fabs(learned[j] - teacher[j]) < BOUND_RAD);
    }
    print_message("ur5_bc in MuJoCo: largest joint error %.2f mrad (bound %.0f)\n", 1e3 * worst,
                  1e3 * BOUND_RAD);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_mujoco_bc_reaches_the_pose))
