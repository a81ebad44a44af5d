/* SPDX-License-Identifier: Apache-2.0 */
/* The Unitree G1's legs as kinematic chains, for a controller: forward
 * kinematics of one leg (the ankle roll link's pose in the pelvis frame
 * from the six joint angles) and one damped Gauss-Newton step of inverse
 * kinematics toward a pose, warm-started from the last solution.
 *
 * The chain is the MuJoCo model's (Menagerie's unitree_g1/g1.xml, the
 * model the mujoco port runs): per link its position in the parent link's
 * frame, a fixed tilt about y (the hip roll link leans 10 degrees back and
 * the knee link undoes it), and its joint's axis (x, y or z). The right
 * leg is the left mirrored in y. Joint order as on the G1: hip pitch,
 * roll, yaw, knee, ankle pitch, ankle roll.
 *
 * Every loop is bounded (6 joints, 3 or 6 rows); no allocation. */
#ifndef ROZ_EXAMPLE_G1_LEGS_H
#define ROZ_EXAMPLE_G1_LEGS_H

#include "roz_controller.h"
#include "roz_math.h"

#define LEGS_JOINTS 6

typedef struct {
    double p[3];    /* ankle roll link origin, pelvis frame, m */
    double r[3][3]; /* its orientation: columns are its axes in the pelvis frame */
} legs_pose_t;

/* the link offsets of the left leg (m), the fixed tilt about y (rad) and the
 * joint axis (0 x, 1 y, 2 z) */
static const double legs__pos[LEGS_JOINTS][3] = {
    { 0.0, 0.064452, -0.1027 },         /* hip pitch link, from the pelvis */
    { 0.0, 0.052, -0.030465 },          /* hip roll link */
    { 0.025001, 0.0, -0.12412 },        /* hip yaw link */
    { -0.078273, 0.0021489, -0.17734 }, /* knee link */
    { 0.0, -9.4445e-05, -0.30001 },     /* ankle pitch link */
    { 0.0, 0.0, -0.017558 },            /* ankle roll link */
};
/* the tilt: 2 asin(0.0873386) = 0.174820 rad (the model's quaternions), as
 * its sine (signed) and cosine per link; 0 none */
#define LEGS_TILT_C 0.98475657
#define LEGS_TILT_S 0.17393023
static const double legs__tilt[LEGS_JOINTS] = { 0.0, -LEGS_TILT_S, 0.0, LEGS_TILT_S, 0.0, 0.0 };
static const int legs__axis[LEGS_JOINTS] = { 1, 0, 2, 1, 1, 0 };

/* r = r rot(axis, c, s), in place: only the two columns the rotation mixes
 * change (written out per axis: a loop over a table costs a controller
 * several times the fuel) */
static inline void legs__mix(double r[3][3], int u, int v, double c, double s)
{
    double a0 = r[0][u], b0 = r[0][v], a1 = r[1][u], b1 = r[1][v], a2 = r[2][u], b2 = r[2][v];
    r[0][u] = c * a0 + s * b0, r[0][v] = c * b0 - s * a0;
    r[1][u] = c * a1 + s * b1, r[1][v] = c * b1 - s * a1;
    r[2][u] = c * a2 + s * b2, r[2][v] = c * b2 - s * a2;
}

static inline void legs__rot(double r[3][3], int axis, double c, double s)
{
    if (axis == 0)
        legs__mix(r, 1, 2, c, s);
    else if (axis == 1)
        legs__mix(r, 2, 0, c, s);
    else
        legs__mix(r, 0, 1, c, s);
}

/* Forward kinematics of leg @p side (0 left, 1 right) at joints @p q; with
 * @p axes and @p origins non-NULL, each joint's axis and origin in the
 * pelvis frame too (the Jacobian's). */
static inline void legs_fk(int side, const double q[LEGS_JOINTS], legs_pose_t *out,
                           double axes[LEGS_JOINTS][3], double origins[LEGS_JOINTS][3])
{
    double r[3][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
    double p[3] = { 0.0, 0.0, 0.0 };
    double mirror = side ? -1.0 : 1.0;
    for (int j = 0; j < LEGS_JOINTS; j++) {
        double off[3] = { legs__pos[j][0], mirror * legs__pos[j][1], legs__pos[j][2] };
        for (int i = 0; i < 3; i++)
            p[i] += r[i][0] * off[0] + r[i][1] * off[1] + r[i][2] * off[2];
        if (legs__tilt[j] != 0.0)
            legs__rot(r, 1, LEGS_TILT_C, legs__tilt[j]);
        int a = legs__axis[j];
        if (axes) {
            for (int i = 0; i < 3; i++) {
                axes[j][i] = r[i][a];
                origins[j][i] = p[i];
            }
        }
        legs__rot(r, a, roz_cos(q[j]), roz_sin(q[j]));
    }
    for (int i = 0; i < 3; i++) {
        out->p[i] = p[i];
        for (int k = 0; k < 3; k++)
            out->r[i][k] = r[i][k];
    }
}

/* The pose error (position, then orientation weighted by @p wr m/rad: half
 * the sum of the axes' cross products) of @p now from @p want, and the
 * Jacobian there, from the joints' axes and origins. */
static inline void legs__error(const legs_pose_t *now, const legs_pose_t *want, double wr,
                               double ax[LEGS_JOINTS][3], double org[LEGS_JOINTS][3],
                               double e[6], double jac[6][LEGS_JOINTS])
{
    for (int i = 0; i < 3; i++)
        e[i] = want->p[i] - now->p[i];
    for (int i = 0; i < 3; i++)
        e[3 + i] = 0.0;
    for (int k = 0; k < 3; k++) {
        double a0 = now->r[0][k], a1 = now->r[1][k], a2 = now->r[2][k];
        double b0 = want->r[0][k], b1 = want->r[1][k], b2 = want->r[2][k];
        e[3] += 0.5 * (a1 * b2 - a2 * b1);
        e[4] += 0.5 * (a2 * b0 - a0 * b2);
        e[5] += 0.5 * (a0 * b1 - a1 * b0);
    }
    for (int i = 3; i < 6; i++)
        e[i] *= wr;
    for (int j = 0; j < LEGS_JOINTS; j++) {
        double d0 = now->p[0] - org[j][0], d1 = now->p[1] - org[j][1];
        double d2 = now->p[2] - org[j][2];
        jac[0][j] = ax[j][1] * d2 - ax[j][2] * d1;
        jac[1][j] = ax[j][2] * d0 - ax[j][0] * d2;
        jac[2][j] = ax[j][0] * d1 - ax[j][1] * d0;
        jac[3][j] = wr * ax[j][0];
        jac[4][j] = wr * ax[j][1];
        jac[5][j] = wr * ax[j][2];
    }
}

/* q += the damped least-squares step dq of J dq = e, each joint's at most
 * 0.2 rad */
static inline void legs__solve(double jac[6][LEGS_JOINTS], const double e[6],
                               double q[LEGS_JOINTS]);

/* One damped Gauss-Newton step of leg @p side's joints @p q toward the pose
 * @p want (position and orientation, orientation errors weighted by
 * @p wr m/rad); @p q is updated in place. Returns the position error
 * before the step (m). */
static inline double legs_ik_step(int side, double q[LEGS_JOINTS], const legs_pose_t *want,
                                  double wr)
{
    legs_pose_t now;
    double ax[LEGS_JOINTS][3], org[LEGS_JOINTS][3], e[6], jac[6][LEGS_JOINTS];
    legs_fk(side, q, &now, ax, org);
    legs__error(&now, want, wr, ax, org, e, jac);
    legs__solve(jac, e, q);
    return roz_math_sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
}

/* The same step without a forward kinematics of its own: linearised at the
 * measured joints @p q_now, whose pose @p now and joint axes and origins
 * legs_fk() gave (the pose at @p q predicted as now + J (q - q_now)). What
 * a controller that computes the measured pose anyway saves: a forward
 * kinematics a tick (a tenth of a 500 Hz tick's fuel). Returns the
 * predicted position error (m). */
static inline double legs_ik_step_from(double q[LEGS_JOINTS], const legs_pose_t *want, double wr,
                                       const legs_pose_t *now, const double q_now[LEGS_JOINTS],
                                       double ax[LEGS_JOINTS][3], double org[LEGS_JOINTS][3])
{
    double e[6], jac[6][LEGS_JOINTS];
    legs__error(now, want, wr, ax, org, e, jac);
    for (int i = 0; i < 6; i++) {
        double s = 0.0;
        for (int j = 0; j < LEGS_JOINTS; j++)
            s += jac[i][j] * (q[j] - q_now[j]);
        e[i] -= s;
    }
    legs__solve(jac, e, q);
    return roz_math_sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
}

static inline void legs__solve(double jac[6][LEGS_JOINTS], const double e[6],
                               double q[LEGS_JOINTS])
{
    /* (J'J + lambda I) dq = J'e, by Cholesky */
    double m[LEGS_JOINTS][LEGS_JOINTS], b[LEGS_JOINTS];
    for (int i = 0; i < LEGS_JOINTS; i++) {
        for (int k = 0; k <= i; k++) {
            double s = 0.0;
            for (int r = 0; r < 6; r++)
                s += jac[r][i] * jac[r][k];
            m[i][k] = s;
        }
        m[i][i] += 1e-4;
        double s = 0.0;
        for (int r = 0; r < 6; r++)
            s += jac[r][i] * e[r];
        b[i] = s;
    }
    for (int i = 0; i < LEGS_JOINTS; i++) {
        for (int k = 0; k <= i; k++) {
            double s = m[i][k];
            for (int r = 0; r < k; r++)
                s -= m[i][r] * m[k][r];
            if (i == k)
                m[i][i] = roz_math_sqrt(s > 1e-12 ? s : 1e-12);
            else
                m[i][k] = s / m[k][k];
        }
    }
    for (int i = 0; i < LEGS_JOINTS; i++) { /* L y = b */
        double s = b[i];
        for (int r = 0; r < i; r++)
            s -= m[i][r] * b[r];
        b[i] = s / m[i][i];
    }
    for (int i = LEGS_JOINTS - 1; i >= 0; i--) { /* L' x = y */
        double s = b[i];
        for (int r = i + 1; r < LEGS_JOINTS; r++)
            s -= m[r][i] * b[r];
        b[i] = s / m[i][i];
    }
    for (int j = 0; j < LEGS_JOINTS; j++)
        q[j] += roz_math_clamp(b[j], -0.2, 0.2);
}

#endif /* ROZ_EXAMPLE_G1_LEGS_H */
