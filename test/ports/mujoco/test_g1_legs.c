/* SPDX-License-Identifier: Apache-2.0 */
/* The G1 leg kinematics of examples/controllers/g1_legs.h against MuJoCo's
 * own: the ankle roll link's pose in the pelvis frame at four leg poses, as
 * MuJoCo 3.3.7's mj_forward gave it on the model the mujoco port runs
 * (Menagerie's unitree_g1/g1.xml); and the inverse kinematics' step, which
 * from the crouch must reach each of those poses again. Compiled natively:
 * the header's math imports are the host's sin and cos here. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "g1_legs.h"
#include "support.h"

double roz_sin(double x)
{
    return sin(x);
}

double roz_cos(double x)
{
    return cos(x);
}

typedef struct {
    int side;
    double q[LEGS_JOINTS];
    double p[3], r[9]; /* MuJoCo's xpos (less the pelvis's) and xmat, row-major */
} legs_case_t;

static const legs_case_t cases[] = {
    { 0, { 0.007093, 0.270278, -0.213504, 0.469190, -0.112901, -0.046004 },
      { -0.145755, 0.321556, -0.685875 },
      { 0.920474, 0.148868, 0.361340, -0.040806, 0.956163, -0.289979, -0.388668, 0.252174,
        0.886197 } },
    { 1, { 0.196622, -0.054481, 0.029756, 0.483465, 0.152108, 0.022886 },
      { -0.267193, -0.156655, -0.676525 },
      { 0.672949, -0.014007, 0.739556, -0.018985, 0.999164, 0.036198, -0.739445, -0.038400,
        0.672121 } },
    { 0, { -0.102161, 0.173057, -0.118083, 0.227901, -0.219575, -0.058132 },
      { -0.003718, 0.243972, -0.739451 },
      { 0.993726, 0.071654, -0.085871, -0.082732, 0.987616, -0.133302, 0.075256, 0.139570,
        0.987348 } },
    { 1, { -0.177927, -0.142612, 0.150219, 0.331755, -0.008885, 0.288442 },
      { 0.009972, -0.235188, -0.736389 },
      { 0.985012, -0.046555, 0.166086, 0.062297, 0.993912, -0.090870, -0.160844, 0.099855,
        0.981916 } },
};
#define N_CASES (sizeof cases / sizeof cases[0])

/* forward kinematics within 0.1 mm and 1e-4 of each rotation entry */
static void test_fk_matches_mujoco(void **state)
{
    (void)state;
    for (size_t c = 0; c < N_CASES; c++) {
        legs_pose_t got;
        legs_fk(cases[c].side, cases[c].q, &got, NULL, NULL);
        for (int i = 0; i < 3; i++) {
            if (fabs(got.p[i] - cases[c].p[i]) > 1e-4)
                fail_msg("case %zu: p[%d] %.6f, MuJoCo %.6f", c, i, got.p[i], cases[c].p[i]);
            for (int k = 0; k < 3; k++)
                if (fabs(got.r[i][k] - cases[c].r[3 * i + k]) > 1e-4)
                    fail_msg("case %zu: r[%d][%d] %.6f, MuJoCo %.6f", c, i, k, got.r[i][k],
                             cases[c].r[3 * i + k]);
        }
    }
}

/* from the crouch the controller starts its solution at, repeated steps
 * reach MuJoCo's pose within 0.1 mm, on the bent-knee branch */
static void test_ik_reaches_the_pose(void **state)
{
    (void)state;
    for (size_t c = 0; c < N_CASES; c++) {
        legs_pose_t want;
        for (int i = 0; i < 3; i++) {
            want.p[i] = cases[c].p[i];
            for (int k = 0; k < 3; k++)
                want.r[i][k] = cases[c].r[3 * i + k];
        }
        double q[LEGS_JOINTS] = { -0.1, 0.0, 0.0, 0.3, -0.2, 0.0 };
        double err = 1.0;
        for (int it = 0; it < 20; it++)
            err = legs_ik_step(cases[c].side, q, &want, 0.3);
        if (!(err < 1e-4))
            fail_msg("case %zu: position error %.6f m after 20 steps", c, err);
        for (int j = 0; j < LEGS_JOINTS; j++)
            if (fabs(q[j] - cases[c].q[j]) > 1e-3)
                fail_msg("case %zu: joint %d %.5f, the pose's %.5f", c, j, q[j], cases[c].q[j]);
    }
}

/* the step linearised at the measured joints reaches them from the crouch
 * (its prediction is exact there) */
static void test_ik_from_the_measured_pose(void **state)
{
    (void)state;
    for (size_t c = 0; c < N_CASES; c++) {
        legs_pose_t want, now;
        double ax[LEGS_JOINTS][3], org[LEGS_JOINTS][3];
        legs_fk(cases[c].side, cases[c].q, &now, ax, org);
        for (int i = 0; i < 3; i++) {
            want.p[i] = cases[c].p[i];
            for (int k = 0; k < 3; k++)
                want.r[i][k] = cases[c].r[3 * i + k];
        }
        double q[LEGS_JOINTS] = { -0.1, 0.0, 0.0, 0.3, -0.2, 0.0 };
        for (int it = 0; it < 20; it++)
            legs_ik_step_from(q, &want, 0.3, &now, cases[c].q, ax, org);
        for (int j = 0; j < LEGS_JOINTS; j++)
            if (fabs(q[j] - cases[c].q[j]) > 1e-3)
                fail_msg("case %zu: joint %d %.5f, the pose's %.5f", c, j, q[j], cases[c].q[j]);
    }
}

ROZ_TEST_MAIN(cmocka_unit_test(test_fk_matches_mujoco),
              cmocka_unit_test(test_ik_reaches_the_pose),
              cmocka_unit_test(test_ik_from_the_measured_pose))
