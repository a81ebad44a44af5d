/* SPDX-License-Identifier: Apache-2.0 */
/* Reach (UR5): the wrist follows a circle in the arm's vertical plane while
 * the base sweeps slowly, by inverse kinematics computed inside the sandbox
 * with roz_math.h -- no host call for the math, so the module commands the
 * same bits on every host.
 *
 * Shoulder and elbow are a planar two-link arm (upper arm 0.425 m, forearm
 * 0.39225 m: UR5's a2 and a3) reaching a point (r, h) from the shoulder; the
 * first wrist joint keeps the tool level, the other two hold. Each joint
 * gets its target's rate (feed-forward) plus a saturating P law,
 * v = VMAX tanh(KP (target - q) / VMAX), all faded in by 1 - exp(-t / TAU).
 * The tracking error (the norm over the joints, rad) is emitted as a
 * metric each tick. */
#include "roz_controller.h"
#include "roz_math.h"
#include "ur5_channels.h"

#define L1    0.425   /* m, shoulder to elbow */
#define L2    0.39225 /* m, elbow to wrist */
#define KP    3.0     /* 1/s */
#define VMAX  1.0     /* rad/s */
#define TAU   0.5     /* s, fade-in */
#define OMEGA 0.5     /* rad/s along the circle */
#define DT    (1.0 / ROZ_UR5_CONTROL_RATE_HZ)

/* The joint targets at time t (s). */
static void targets(double t, double q[6])
{
    double r = 0.55 + 0.10 * roz_math_cos(OMEGA * t); /* m, from the shoulder */
    double h = 0.15 + 0.10 * roz_math_sin(OMEGA * t);
    double c = roz_math_clamp((r * r + h * h - L1 * L1 - L2 * L2) / (2.0 * L1 * L2), -1.0, 1.0);
    double elbow = roz_math_atan2(roz_math_sqrt(1.0 - c * c), c); /* bend, 0..pi */
    double lift = roz_math_atan2(h, r) + roz_math_atan2(L2 * roz_math_sin(elbow),
                                                        L1 + L2 * roz_math_cos(elbow));
    q[0] = 0.4 * roz_math_sin(0.2 * t); /* base sweep */
    q[1] = -lift;                       /* UR5: negative lifts the arm */
    q[2] = elbow;
    q[3] = lift - elbow;                /* the tool stays level */
    q[4] = 0.0;
    q[5] = 0.0;
}

ROZ_PROCESS(tick)
{
    double t = (double)roz_sim_time_ns() * 1e-9, now[6], next[6], err2 = 0.0;
    double fade = 1.0 - roz_math_exp(-t / TAU);
    (void)tick;
    targets(t, now);
    targets(t + DT, next);
    for (int j = 0; j < 6; j++) {
        double e = now[j] - roz_state_get(ROZ_UR5_STATE_SHOULDER_PAN_JOINT_POSITION + j);
        double v = (next[j] - now[j]) / DT + VMAX * roz_math_tanh(KP * e / VMAX);
        roz_command_set(ROZ_UR5_CMD_SHOULDER_PAN_JOINT_VELOCITY + j, fade * v);
        err2 += e * e;
    }
    roz_emit_metric(roz_math_sqrt(err2));
}
