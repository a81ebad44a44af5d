/* SPDX-License-Identifier: Apache-2.0 */
/* The team's own learned policy does its job: the UR5 hold distilled from
 * pd_hold.c by behaviour cloning (examples/controllers/ur5_bc/) drives the
 * loopback UR5 from its start to pd_hold's pose and holds it there, as
 * pd_hold does, without a fault or a value outside the manifest. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/runtime.h"
#include "support.h"
#include "support_runtime.h"
#include "ur5_manifest.h"

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_test_clock_t clk;

static void run(const char *controller, double *q)
{
    roz_runtime_config_t cfg;
    double state[ROZ_CFG_MAX_STATES];
    size_t len;
    clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_loopback_config(&cfg, &lb, &roz_manifest_ur5, NULL, &clk);
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    const uint8_t *w = roz_test_controller(controller, &len);
    if (roz_runtime_load(&rt, w, len, NULL) != ROZ_OK)
        fail_msg("%s: %s", controller, roz_runtime_error(&rt));
    for (int i = 0; i < 800; i++) { /* 8 s */
        assert_int_equal(roz_runtime_tick(&rt), ROZ_OK);
        assert_int_equal(roz_loopback_counters(&lb).violations, 0);
    }
    assert_int_equal(roz_runtime_faults(&rt), 0);
    roz_loopback_true_state(&lb, state);
    memcpy(q, state, 6 * sizeof q[0]);
    roz_runtime_deinit(&rt);
}

static void test_nn_bc_holds_the_pose(void **st)
{
    static const double pose[6] = { 0.0, -1.2, 1.5, -0.3, 1.57, 0.0 };
    double learned[6], teacher[6];
    (void)st;
    run("pd_hold", teacher);
    run("ur5_bc", learned);
    for (int j = 0; j < 6; j++) {
        print_message("joint %d: learned %+.4f, pd_hold %+.4f, pose %+.4f\n", j, learned[j],
                      teacher[j], pose[j]);
        assert_true(fabs(learned[j] - pose[j]) < 0.02);
        assert_true(fabs(learned[j] - teacher[j]) < 0.02);
    }
}

ROZ_TEST_MAIN(cmocka_unit_test(test_nn_bc_holds_the_pose))
