/* SPDX-License-Identifier: Apache-2.0 */
/* A model-based walking controller for the 12-joint Unitree G1
 * (unitree_g1_12dof: the legs driven, the upper body locked), built from
 * this repository's own sources, no learned network; it reads the
 * operator's velocity command (operator/velocity.x, operator/velocity.y,
 * operator/yaw_rate).
 *
 * In MuJoCo, under examples/operators/g1_walk.csv (make demo's; the test
 * demo_plot_walker) it crouches, shifts its weight, walks forward at
 * 0.5 m/s (0.569 achieved), stops and stands (drifting 0.008 m), turns on
 * the spot at 0.5 rad/s (0.506, drifting 0.048 m/s sideways) and stops and
 * stands (0.001 m), 21 s without a fault, the pelvis never below 0.74 m;
 * it also keeps up at 0.3 and 0.6 m/s and turns at 0.8 rad/s. It runs
 * inside roz's default budget (at most 19,292 fuel units a tick of the
 * 20,000 at 500 Hz, docs/budget.md: one leg's inverse kinematics a tick,
 * linearised at the measured joints) and replays bit for bit; it moves no command faster than the manifest's rate caps, so
 * the safety filter holds none back.
 *
 * The body is a linear inverted pendulum over the stance foot
 * (omega = sqrt(g / COM_HEIGHT)). Each tick:
 *  - the state: the pelvis's tilt and heading from the IMU, both ankles
 *    from the legs' joints (g1_legs.h), so the centre of mass (a model of
 *    the body's and legs' masses) relative to each ankle in that foot's
 *    heading frame, and its velocity (a filtered difference); the
 *    divergent component of motion xi = c + v / omega over the stance sole;
 *  - the next foothold: xi predicted to the end of the step (sagittally by
 *    SAG_GAIN of the growth), less the offset a steady gait at the commanded
 *    velocity has then (v T / (e^(omega T) - 1) ahead; the step width over
 *    1 + e^(omega T), inward), turning, shifted so the feet pivot about
 *    their midpoint, clamped so the feet never cross; each step's mean
 *    velocity against the command trims the velocity the plan is for
 *    (TRIM_I, an integral over steps, forward and sideways);
 *  - the swing foot: after a double support of DOUBLE_S, from where it
 *    lifted to the foothold, STEP_LIFT high on a sine, flat, turned by half
 *    the step's yaw (the operator's yaw rate, plus HEADING_P back to the
 *    heading it integrates to); the feet swap when the swing ankle is down
 *    to the stance ankle's height late in the swing, or LATE_S after the
 *    step's time (the swing leg counts as the stance leg mirrored in the
 *    centre of mass the footholds use: SWING_MIRROR); steps of STEP_S,
 *    0.22 s: at 0.3 s the swing leg's reaction spins the G1 about its
 *    vertical (the feet slip in yaw) and at 0.5 m/s it falls;
 *  - stopping: told to stop for STILL_S and slower than STILL_V at a
 *    touch-down, it stands: both feet stay where they are, the pelvis
 *    upright over them, moved sideways until the centre of mass is between
 *    them, the ankles holding it over the soles lengthwise; told to move
 *    again, it shifts its weight onto one foot for RESUME_S (the one away
 *    from the turn asked for) and steps off with the other; pushed (the
 *    divergent component STAND_XI_X or STAND_XI_Y off the feet's middle)
 *    it steps at once, the foot on the side the push sends it swinging
 *    (standing, it took a 15 N.s push backward only by stepping; it falls
 *    to 12 N.s sideways toward the right, stepping or not);
 *  - the stance foot: the pelvis held STAND_HEIGHT above it and upright,
 *    the foot turned by the other half of the yaw; the stance hip rights the
 *    torso beyond that (TORSO_P, TORSO_RATE), the stance ankle pushes the
 *    centre of mass toward the sole (WALK_ANKLE_P, WALK_ANKLE_D);
 *  - joint targets by inverse kinematics (one Gauss-Newton step a tick,
 *    the legs in turn, warm-started, linearised at the measured joints),
 *    sent with fixed gains inside the manifest's limits, and feed-forward
 *    torques that carry the body's weight (J' f, the ground's force
 *    pointing from the ankle to the centre of mass, shared between the feet
 *    in double support, or standing by where the centre of mass is); every
 *    command moves by less than its rate cap a tick (send()).
 * What was learnt in MuJoCo: the joint PD alone does not hold the weight
 * (the feed-forward is needed; with the force only vertical the stance hip
 * roll sags 0.1 rad and the pelvis drops toward the swing side), the narrow feet need a stiff ankle roll
 * (kp 100; at 20-60 the body sways off sideways once its weight is shifted),
 * the ankle pitch needs the centre of mass fed back, the torso needs
 * more than the kinematic uprighting (TORSO_P 1), short steps hold the
 * heading (above), and a trim on the centre of mass the footholds see (an
 * earlier design) settled 0.1 m/s fast at 0.5 m/s and, carried into the
 * turn, walked the G1 backward and sideways; the trim on the planned
 * velocity settles within 0.07 m/s. */
#include "g1_legs.h"
#include "roz_controller.h"
#include "roz_math.h"
#include "unitree_g1_12dof_channels.h"

#define RATE_HZ ((double)ROZ_UNITREE_G1_12DOF_CONTROL_RATE_HZ)
#define DT (1.0 / RATE_HZ)
#define GRAVITY 9.81

/* ---- the gait's parameters ---- */
#ifndef STAND_HEIGHT
#define STAND_HEIGHT 0.72 /* m: pelvis origin above the ankle roll origin */
#endif
#ifndef STEP_S
#define STEP_S 0.22       /* s: one step */
#endif
#ifndef DOUBLE_S
#define DOUBLE_S 0.05 /* s: both feet down at the start of each step */
#endif
#ifndef TOUCH_H
#define TOUCH_H 0.008 /* m: a swing ankle this close to the stance one's height is down */
#endif
#define TOUCH_PHASE 0.6 /* of the swing, before which no touch-down counts */
#define LATE_S 0.06 /* s: how long a swing may overrun, lowering, before the swap */
#ifndef STEP_LIFT
#define STEP_LIFT 0.05    /* m: the swing foot's apex */
#endif
#ifndef STEP_WIDTH
#define STEP_WIDTH 0.22   /* m: between the ankles */
#endif
#define SOLE_X 0.035      /* m: the sole's centre ahead of the ankle */
#define COM_X 0.02        /* m: the centre of mass ahead of the pelvis, standing */
#ifndef COM_HEIGHT
#define COM_HEIGHT 0.65   /* m: the centre of mass above the ground, walking */
#endif
/* the masses (kg) and centres of mass (m, pelvis frame) of the model: the
 * pelvis with the locked upper body, and a leg's, from the middle of its hip
 * and ankle (in the model's zero pose) */
#ifndef COM_BIAS_X
#define COM_BIAS_X 0.045 /* m: what the model above misses (the bent knees), measured in MuJoCo */
#endif
#ifndef WEIGHT_N
#define WEIGHT_N 260.0 /* N: what the legs carry (33.3 kg, less a leg's own) */
#endif
#define MASS_BODY 18.969
#define MASS_LEG 7.186
static const double body_com[3] = { 0.0226, 0.0, 0.1396 };
static const double leg_com[3] = { 0.0173, 0.0232, 0.0398 };
#define CROUCH_S 0.6 /* s: from the start pose to the crouch */
#ifndef STILL_S
#define STILL_S 0.6 /* s: the command this long at zero, the feet stop at a touch-down */
#endif
#ifndef STILL_V
#define STILL_V 0.15 /* m/s: ... with the centre of mass this slow forward */
#endif
#define STAND_Y_I 2.0 /* standing: m/s of the feet's shift per m of the centre of mass astray */
#ifndef STAND_XI_X
#define STAND_XI_X 0.06 /* m: standing, the DCM this far off the soles' middle lengthwise: step */
#endif
#ifndef STAND_XI_Y
#define STAND_XI_Y 0.08 /* m: ... or sideways off the feet's middle */
#endif
#ifndef RESUME_S
#define RESUME_S 0.3 /* s: standing, the weight onto the stance foot before the first step */
#endif
#define SHIFT_S 0.6  /* s: the weight onto the right foot (and 0.2 s still) */
#ifndef SHIFT_M
#define SHIFT_M 0.05 /* m: how far */
#endif
#define ANKLE_P 4.0  /* rad of ankle target per m of the centre of mass off the feet */
#define ANKLE_D 0.5  /* per m/s */
#define ANKLE_ROLL_P 0.0 /* the same sideways: the feet are narrow */
#define ANKLE_ROLL_D 0.0
#define STAND_Y_P 1.0 /* m of the feet's targets per m of the centre of mass astray sideways */
#define STAND_Y_D 0.1 /* per m/s */
#ifndef WALK_ANKLE_P
#define WALK_ANKLE_P 4.0
#endif
#ifndef WALK_ANKLE_D
#define WALK_ANKLE_D 0.5
#endif
#ifndef HEADING_P
#define HEADING_P 1.0 /* rad/s of turn per rad off the heading */
#endif
#ifndef TORSO_P
#define TORSO_P 1.0 /* rad of stance hip target per rad of the pelvis's tilt, beyond the kinematics */
#endif
#ifndef TRIM_I
#define TRIM_I 0.1 /* m/s of velocity trim per m/s of a step's mean velocity off the command */
#endif
#define TRIM_MAX 0.2 /* m/s: the trim's bound */
#ifndef SWING_MIRROR
#define SWING_MIRROR 1
#endif
#ifndef LAT_GAIN
#define LAT_GAIN 0.7 /* of the DCM's error sideways into the foothold */
#endif
#ifndef SAG_GAIN
#define SAG_GAIN 1.0
#endif
#ifndef TORSO_RATE
#define TORSO_RATE 0.05 /* rad of hip target per rad/s of the pelvis's tilt rate */
#endif

#ifndef KP_YAW
#define KP_YAW 200
#endif
#ifndef IK_WR
#define IK_WR 1.0
#endif
static const double kp[LEGS_JOINTS] = { 200, 200, KP_YAW, 200, 100, 100 };
static const double kd[LEGS_JOINTS] = { 5, 5, 4, 6, 3, 1 };
static const double crouch[LEGS_JOINTS] = { -0.1, 0.0, 0.0, 0.3, -0.2, 0.0 };
/* the targets' range per leg, inside the manifest's limits (the knee kept bent) */
static const double qmin[2][LEGS_JOINTS] = { { -2.5, -0.5, -2.7, 0.05, -0.85, -0.26 },
                                             { -2.5, -2.9, -2.7, 0.05, -0.85, -0.26 } };
static const double qmax[2][LEGS_JOINTS] = { { 2.85, 2.9, 2.7, 2.85, 0.5, 0.26 },
                                             { 2.85, 0.5, 2.7, 2.85, 0.5, 0.26 } };

/* ---- small vector helpers (3-vectors, 3x3 rotations) ---- */
static void rz_cs(double r[3][3], double c, double s) /* about z, by cos c and sin s */
{
    r[0][0] = c, r[0][1] = -s, r[0][2] = 0.0;
    r[1][0] = s, r[1][1] = c, r[1][2] = 0.0;
    r[2][0] = 0.0, r[2][1] = 0.0, r[2][2] = 1.0;
}

static void rz(double r[3][3], double a)
{
    rz_cs(r, roz_cos(a), roz_sin(a));
}

static void copy3(double out[3][3], const double a[3][3])
{
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            out[i][k] = a[i][k];
}

static void mv(double out[3], const double r[3][3], const double v[3]) /* r v */
{
    for (int i = 0; i < 3; i++)
        out[i] = r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2];
}

static void mtv(double out[3], const double r[3][3], const double v[3]) /* r' v */
{
    for (int i = 0; i < 3; i++)
        out[i] = r[0][i] * v[0] + r[1][i] * v[1] + r[2][i] * v[2];
}

static void mtm(double out[3][3], const double a[3][3], const double b[3][3]) /* a' b */
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            out[i][j] = a[0][i] * b[0][j] + a[1][i] * b[1][j] + a[2][i] * b[2][j];
}

static double smooth(double s) /* 0..1, zero slope at both ends */
{
    s = roz_math_clamp(s, 0.0, 1.0);
    return s * s * (3.0 - 2.0 * s);
}

/* ---- the controller's state (static: one robot per module instance) ---- */
static double q_ik[2][LEGS_JOINTS]; /* each leg's last inverse kinematics */
static double q_sent[2][LEGS_JOINTS];
static legs_pose_t start[2];        /* both ankles at tick 0 */
static double com_prev[2][2], vel[2][2]; /* per stance choice: com, filtered velocity */
static int have_prev;
static int stance;                  /* 0 left, 1 right */
static double step_t;               /* s into this step */
static int walking;
static int standing; /* both feet down after walking, until the command moves again */
static double still_t; /* s: the command at zero */
static double stand_t, resume_t; /* s: standing; told to walk again */
static double stand_p[2][3], stand_yaw[2]; /* the feet where they stopped, heading frame */
static double stand_sh; /* m: the feet's shift under the centre of mass sideways (an integral) */
static double foot_h[2][3]; /* this tick's ankles in the heading frame */
static double swing0[3], swing_yaw0, stance_yaw0; /* at lift-off */
static double foothold[2];
static double heading; /* rad: the heading walking holds */
/* e^(omega T), e^(-omega dt), and e^(omega (T - t)) this tick: a product a
 * tick, not an exp (230 fuel units each) */
static double e_step, grow_tick, grow_now;
static double vsum[2]; /* the step's velocity sums, forward and sideways */
static double trim[2]; /* m/s: the velocity trim, forward and sideways */
static int vn;

/* atan2 to about 1e-5 rad, in some 40 fuel units (roz_math_atan2's exact
 * one is some 400): the octant, then an odd polynomial on [0, 1] */
static double fast_atan2(double y, double x)
{
    double ax = roz_math_fabs(x), ay = roz_math_fabs(y);
    double mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax;
    if (!(mx > 0.0))
        return 0.0;
    double t = mn / mx, t2 = t * t;
    double a = t * (0.99997726 + t2 * (-0.33262347 + t2 * (0.19354346 + t2 * (-0.11643287 +
               t2 * (0.05265332 + t2 * -0.01172120)))));
    if (ay > ax)
        a = 1.5707963267948966 - a;
    if (x < 0.0)
        a = 3.141592653589793 - a;
    return y < 0.0 ? -a : a;
}

static double clampv(double v, double lo, double hi)
{
    return v == v ? roz_math_clamp(v, lo, hi) : 0.0;
}

/* the IMU's orientation as a rotation; 0 if not a unit quaternion */
static int pelvis_rotation(double r[3][3])
{
    double x = roz_state_get(ROZ_UNITREE_G1_12DOF_STATE_BASE_IMU_ORIENTATION_X);
    double y = roz_state_get(ROZ_UNITREE_G1_12DOF_STATE_BASE_IMU_ORIENTATION_Y);
    double z = roz_state_get(ROZ_UNITREE_G1_12DOF_STATE_BASE_IMU_ORIENTATION_Z);
    double w = roz_state_get(ROZ_UNITREE_G1_12DOF_STATE_BASE_IMU_ORIENTATION_W);
    double n = x * x + y * y + z * z + w * w;
    if (!(n > 0.5 && n < 1.5))
        return 0;
    r[0][0] = 1 - 2 * (y * y + z * z), r[0][1] = 2 * (x * y - w * z), r[0][2] = 2 * (x * z + w * y);
    r[1][0] = 2 * (x * y + w * z), r[1][1] = 1 - 2 * (x * x + z * z), r[1][2] = 2 * (y * z - w * x);
    r[2][0] = 2 * (x * z - w * y), r[2][1] = 2 * (y * z + w * x), r[2][2] = 1 - 2 * (x * x + y * y);
    return 1;
}

static double tau_ff[2][LEGS_JOINTS]; /* feed-forward torques this tick, N.m */
static const double tau_max[LEGS_JOINTS] = { 60, 60, 40, 100, 35, 15 };

/* the torques with which leg @p leg carries the share @p share of the
 * body's weight (J' f): the ground's force on the foot points from the
 * ankle to the centre of mass @p com (as on an inverted pendulum), its
 * vertical part the weight; from the leg's joint axes and origins and its
 * ankle in the pelvis frame; @p up: the world's up in the pelvis frame */
static void carry(int leg, double share, const double up[3], const double com[3],
                  const legs_pose_t *foot, double axes[LEGS_JOINTS][3],
                  double origins[LEGS_JOINTS][3])
{
    double d[3] = { com[0] - foot->p[0], com[1] - foot->p[1], com[2] - foot->p[2] };
    double h = d[0] * up[0] + d[1] * up[1] + d[2] * up[2];
    double f = -share * WEIGHT_N / (h > 0.3 ? h : 0.3);
    for (int j = 0; j < LEGS_JOINTS; j++) {
        const double *a = axes[j];
        double d0 = foot->p[0] - origins[j][0], d1 = foot->p[1] - origins[j][1];
        double d2 = foot->p[2] - origins[j][2];
        double c0 = a[1] * d2 - a[2] * d1, c1 = a[2] * d0 - a[0] * d2, c2 = a[0] * d1 - a[1] * d0;
        tau_ff[leg][j] = f * (c0 * d[0] + c1 * d[1] + c2 * d[2]);
    }
}

/* what the safety filter lets a command change by in a tick (the manifest's
 * max_rate_of_change), with a margin: the walker moves its own commands no
 * faster, so the filter never has to hold one back */
#define POS_STEP 0.035 /* rad: the positions' caps are 0.04 to 0.064 */
static const double tau_step[LEGS_JOINTS] = { 0.8, 1.3, 0.8, 1.3, 0.32, 0.32 }; /* N.m */
#define GAIN_RAMP_S 0.6 /* s: the gains from zero (kp 200 in 300 ticks: 0.67 a tick, cap 0.8) */
static double tau_sent[2][LEGS_JOINTS];

static void send(long long tick)
{
    double ramp = roz_math_clamp((double)tick / (GAIN_RAMP_S * RATE_HZ), 0.0, 1.0);
    for (int leg = 0; leg < 2; leg++)
        for (int j = 0; j < LEGS_JOINTS; j++) {
            int c = leg * LEGS_JOINTS + j;
            double want = roz_math_clamp(q_ik[leg][j], qmin[leg][j], qmax[leg][j]);
            q_sent[leg][j] += roz_math_clamp(want - q_sent[leg][j], -POS_STEP, POS_STEP);
            double tau = ramp * roz_math_clamp(tau_ff[leg][j], -tau_max[j], tau_max[j]);
            tau_sent[leg][j] += roz_math_clamp(tau - tau_sent[leg][j], -tau_step[j], tau_step[j]);
            roz_command_set(ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_POSITION + c,
                            q_sent[leg][j]);
            roz_command_set(ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_VELOCITY + c, 0.0);
            roz_command_set(ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS + c,
                            ramp * kp[j]);
            roz_command_set(ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_DAMPING + c, kd[j]);
            roz_command_set(ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_EFFORT + c,
                            tau_sent[leg][j]);
        }
}

static void set_pose(legs_pose_t *p, const double pos[3], const double r[3][3])
{
    for (int i = 0; i < 3; i++) {
        p->p[i] = pos[i];
        for (int k = 0; k < 3; k++)
            p->r[i][k] = r[i][k];
    }
}

/* a step begins: foot @p up lifts, foot @p down bears the weight; where
 * the lifting ankle is, from the other, in the other's heading frame
 * (com_f[x]: the centre of mass from ankle x, in x's frame) */
static void lift_off(int up, int down, double com_f[2][3], const double fyaw[2])
{
    double ru[3][3], rd[3][3], cu[3], cd[3], d[3];
    rz(ru, fyaw[up]);
    rz(rd, fyaw[down]);
    mv(cu, ru, com_f[up]);
    mv(cd, rd, com_f[down]);
    for (int i = 0; i < 3; i++)
        d[i] = cd[i] - cu[i]; /* ankle up - ankle down */
    mtv(swing0, rd, d);
    swing_yaw0 = fyaw[up];
    stance_yaw0 = fyaw[down];
    vel[down][0] = vel[up][0]; /* the lifting foot's estimate was the one standing */
    vel[down][1] = vel[up][1];
}

ROZ_PROCESS(tick)
{
    double q[2][LEGS_JOINTS];
    for (int leg = 0; leg < 2; leg++)
        for (int j = 0; j < LEGS_JOINTS; j++) {
            double v = roz_state_get(ROZ_UNITREE_G1_12DOF_STATE_LEFT_HIP_PITCH_JOINT_POSITION +
                                     leg * LEGS_JOINTS + j);
            q[leg][j] = v == v ? v : 0.0;
        }
    legs_pose_t foot[2];
    double axes[2][LEGS_JOINTS][3], origins[2][LEGS_JOINTS][3];
    legs_fk(0, q[0], &foot[0], axes[0], origins[0]);
    legs_fk(1, q[1], &foot[1], axes[1], origins[1]);
    if (tick == 0) {
        for (int leg = 0; leg < 2; leg++) {
            set_pose(&start[leg], foot[leg].p, foot[leg].r);
            for (int j = 0; j < LEGS_JOINTS; j++) {
                q_sent[leg][j] = q[leg][j];
                q_ik[leg][j] = crouch[j]; /* the knee bent: the branch to solve on */
            }
        }
    }
    double r[3][3], rt[3][3], h[3][3];
    if (!pelvis_rotation(r)) { /* no orientation to walk on: hold the last targets */
        send(tick);
        return;
    }
    double yaw = fast_atan2(r[1][0], r[0][0]);
    {
        double n = roz_math_sqrt(r[0][0] * r[0][0] + r[1][0] * r[1][0]);
        if (!(n > 1e-6)) { /* the pelvis's x axis vertical: no heading */
            send(tick);
            return;
        }
        rz_cs(h, r[0][0] / n, r[1][0] / n);
    }
    mtm(rt, h, r); /* the pelvis's tilt: heading frame from pelvis frame */
    double gx = clampv(roz_state_get(ROZ_UNITREE_G1_12DOF_STATE_BASE_IMU_ANGULAR_VELOCITY_X), -10, 10);
    double gy = clampv(roz_state_get(ROZ_UNITREE_G1_12DOF_STATE_BASE_IMU_ANGULAR_VELOCITY_Y), -10, 10);
    double cmd_vx = clampv(roz_state_get(ROZ_UNITREE_G1_12DOF_INPUT_OPERATOR_VELOCITY_X), -0.8, 0.8);
    double cmd_vy = clampv(roz_state_get(ROZ_UNITREE_G1_12DOF_INPUT_OPERATOR_VELOCITY_Y), -0.5, 0.5);
    double cmd_wz = clampv(roz_state_get(ROZ_UNITREE_G1_12DOF_INPUT_OPERATOR_YAW_RATE), -1.57, 1.57);
    int still = roz_math_fabs(cmd_vx) < 0.02 && roz_math_fabs(cmd_vy) < 0.02 &&
                roz_math_fabs(cmd_wz) < 0.05; /* told to stop */
    still_t = still ? still_t + DT : 0.0;

    /* each foot in the heading frame, its yaw, and the centre of mass over it
     * in its own heading frame */
    double com_off[3], com_h[3], fyaw[2], com_f[2][3];
    for (int i = 0; i < 3; i++)
        com_off[i] = MASS_BODY * body_com[i];
    /* walking, the swing leg counts as the stance leg mirrored: its own
     * swing would move the divergent component, and the footholds with it,
     * by the leg's motion (a feedback on itself) */
    for (int leg = 0; leg < 2; leg++) {
        double side = leg ? -1.0 : 1.0;
        const legs_pose_t *fl =
            walking && !standing && SWING_MIRROR && leg != stance ? &foot[stance] : &foot[leg];
        double fy = fl == &foot[leg] ? fl->p[1] : -fl->p[1];
        double mid[3] = { 0.5 * fl->p[0] + leg_com[0],
                          0.5 * (fy + side * legs__pos[0][1]) + side * leg_com[1],
                          0.5 * (fl->p[2] + legs__pos[0][2]) + leg_com[2] };
        for (int i = 0; i < 3; i++)
            com_off[i] += MASS_LEG * mid[i];
    }
    for (int i = 0; i < 3; i++)
        com_off[i] /= MASS_BODY + 2.0 * MASS_LEG;
    com_off[0] += COM_BIAS_X;
    mv(com_h, rt, com_off);
    double frot[2][3][3]; /* each foot's heading, as a rotation about z */
    for (int leg = 0; leg < 2; leg++) {
        double a[3], d[3];
        double (*rf)[3] = frot[leg];
        mv(a, rt, foot[leg].p);
        for (int i = 0; i < 3; i++)
            foot_h[leg][i] = a[i];
        /* the foot's x axis in the heading frame, level */
        double fx = rt[0][0] * foot[leg].r[0][0] + rt[0][1] * foot[leg].r[1][0] +
                    rt[0][2] * foot[leg].r[2][0];
        double fy = rt[1][0] * foot[leg].r[0][0] + rt[1][1] * foot[leg].r[1][0] +
                    rt[1][2] * foot[leg].r[2][0];
        double n = roz_math_sqrt(fx * fx + fy * fy);
        if (!(n > 1e-6))
            fx = 1.0, fy = 0.0, n = 1.0;
        fyaw[leg] = fast_atan2(fy, fx);
        rz_cs(rf, fx / n, fy / n);
        for (int i = 0; i < 3; i++)
            d[i] = com_h[i] - a[i];
        mtv(com_f[leg], rf, d);
        for (int i = 0; i < 2; i++) {
            double raw = have_prev ? (com_f[leg][i] - com_prev[leg][i]) * RATE_HZ : 0.0;
            vel[leg][i] += 0.1 * (roz_math_clamp(raw, -3.0, 3.0) - vel[leg][i]);
            com_prev[leg][i] = com_f[leg][i];
        }
    }
    have_prev = 1;

    double t = (double)tick * DT;
    double up[3][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
    legs_pose_t want[2];
    if (!walking) {
        /* crouch from the start pose, then shift the weight onto the right foot */
        double s = smooth(t / CROUCH_S), shift = SHIFT_M * smooth((t - CROUCH_S) / SHIFT_S);
        /* the centre of mass sideways from where the shift wants it, and its
         * rate: the feet move under it by as much */
        double ey = 0.5 * (com_f[0][1] + com_f[1][1]) + shift;
        double vy = 0.5 * (vel[0][1] + vel[1][1]);
        shift += s * roz_math_clamp(STAND_Y_P * ey + STAND_Y_D * vy, -0.05, 0.05);
        for (int leg = 0; leg < 2; leg++) {
            double nom[3] = { COM_X + COM_BIAS_X - SOLE_X, start[leg].p[1] + shift, -STAND_HEIGHT };
            double pos[3];
            for (int i = 0; i < 3; i++)
                pos[i] = start[leg].p[i] + s * (nom[i] - start[leg].p[i]);
            set_pose(&want[leg], pos, up);
        }
        if (t >= CROUCH_S + SHIFT_S + 0.2) {
            walking = 1;
            e_step = roz_math_exp(roz_math_sqrt(GRAVITY / COM_HEIGHT) * STEP_S);
            grow_tick = roz_math_exp(-roz_math_sqrt(GRAVITY / COM_HEIGHT) * DT);
            grow_now = e_step;
            heading = yaw;
            stance = 1;
            step_t = 0.0;
            lift_off(0, 1, com_f, fyaw);
        }
    } else if (standing) {
        /* both feet where they stopped, the pelvis upright over them, moved
         * sideways until the centre of mass is between them (the ankles
         * keep it over the soles lengthwise, below); told to walk again,
         * the weight first onto the stance foot */
        stand_t += DT;
        if (!still) {
            /* the stance foot of the first step: the one away from the turn
             * (or the sideways walk) the command asks for */
            if (resume_t == 0.0)
                stance = cmd_wz < -0.05 || cmd_vy < -0.02 ? 0 : 1;
            resume_t += DT;
        }
        double to = stance ? 1.0 : -1.0; /* toward the stance foot: + right */
        double ey = 0.5 * (com_f[0][1] + com_f[1][1]) + to * SHIFT_M * smooth(resume_t / RESUME_S);
        double vy = 0.5 * (vel[0][1] + vel[1][1]);
        stand_sh = roz_math_clamp(stand_sh + STAND_Y_I * ey * DT, -0.08, 0.08);
        double shy = stand_sh + roz_math_clamp(STAND_Y_P * ey + STAND_Y_D * vy, -0.05, 0.05);
        double ramp = smooth(stand_t / 0.2);
        for (int leg = 0; leg < 2; leg++) {
            double pos[3] = { stand_p[leg][0], stand_p[leg][1] + ramp * shy,
                              stand_p[leg][2] + ramp * (-STAND_HEIGHT - stand_p[leg][2]) };
            double rw[3][3];
            rz(rw, stand_yaw[leg]);
            set_pose(&want[leg], pos, rw);
        }
        /* pushed: the divergent component off the feet (a standing
         * balance cannot bring it back): step at once, the foot on the side
         * it heads to swinging (outward, where it can catch it) */
        double omega = roz_math_sqrt(GRAVITY / COM_HEIGHT);
        double xix = 0.5 * (com_f[0][0] + com_f[1][0]) - SOLE_X +
                     0.5 * (vel[0][0] + vel[1][0]) / omega;
        double xiy = 0.5 * (com_f[0][1] + com_f[1][1]) + vy / omega;
        if (roz_math_fabs(xix) > STAND_XI_X || roz_math_fabs(xiy) > STAND_XI_Y) {
            stance = xiy > 0.0 ? 1 : 0;
            resume_t = RESUME_S;
        }
        if (resume_t >= RESUME_S) { /* the first step: the other foot lifts */
            standing = 0;
            heading = yaw;
            step_t = 0.0;
            grow_now = e_step;
            vsum[0] = vsum[1] = 0.0;
            vn = 0;
            lift_off(1 - stance, stance, com_f, fyaw);
        }
    } else {
        int sw = 1 - stance;
        double side = sw == 0 ? 1.0 : -1.0; /* the swing foot's side: + left */
        double s = step_t / STEP_S;
        double omega = roz_math_sqrt(GRAVITY / COM_HEIGHT);
        double e = e_step;
        /* the DCM over the stance foot's sole, and the foothold */
        double xi[2];
        xi[0] = com_f[stance][0] - SOLE_X + vel[stance][0] / omega;
        vsum[0] += vel[stance][0];
        vsum[1] += vel[stance][1];
        vn += 1;
        xi[1] = com_f[stance][1] + vel[stance][1] / omega;
        double grow = roz_math_fmax(grow_now, 1.0);
        grow_now *= grow_tick;
        /* the heading the operator's yaw rate integrates to, held: the feet
         * turn the pelvis back to it */
        heading += cmd_wz * DT;
        double herr = yaw - heading;
        herr -= 6.283185307179586 * roz_math_floor(herr / 6.283185307179586 + 0.5);
        double dyaw = roz_math_clamp((cmd_wz - HEADING_P * herr) * STEP_S, -0.3, 0.3);
        if (s < 0.8) {
            /* a steady gait's step and its DCM at the step's end; the
             * foothold moves by the gains times the DCM's error from that */
            double lx = (cmd_vx - trim[0]) * STEP_S, ly = (cmd_vy - trim[1]) * STEP_S;
            double nom_x = lx * e / (e - 1.0);
            double nom_y = side * STEP_WIDTH * e / (1.0 + e) + ly * e / (e - 1.0);
            /* turning, the feet pivot about their midpoint: the swing foot
             * lands behind the stance one turning toward its side, ahead
             * turning away (half the width times the step's yaw) */
            foothold[0] = roz_math_clamp(lx + SAG_GAIN * (xi[0] * grow - nom_x) -
                                             side * 0.5 * STEP_WIDTH * dyaw, -0.25, 0.30);
            foothold[1] = side * STEP_WIDTH + ly + LAT_GAIN * (xi[1] * grow - nom_y);
            if (side > 0)
                foothold[1] = roz_math_clamp(foothold[1], 0.12, 0.40);
            else
                foothold[1] = roz_math_clamp(foothold[1], -0.40, -0.12);
        }
        /* the swing ankle in the stance foot's frame, then from the pelvis */
        /* the swing: after the double support, to the foothold by 85% */
        double ss = roz_math_clamp((step_t - DOUBLE_S) / (STEP_S - DOUBLE_S), 0.0, 1.0);
        double a = smooth(ss / 0.85);
        double sw_pos[3] = {
            swing0[0] + (foothold[0] - swing0[0]) * a,
            swing0[1] + (foothold[1] - swing0[1]) * a,
            swing0[2] * (1.0 - ss) + STEP_LIFT * roz_sin(3.14159265358979 * ss) - 0.01 * ss -
                0.3 * roz_math_fmax(step_t - STEP_S, 0.0),
        };
        double rf[3][3], d[3], dh[3], pos[3], rw[3][3], rwt[3][3];
        copy3(rf, frot[stance]);
        /* pelvis from the stance ankle: com_f less the com's offset */
        double com_off_f[3];
        mtv(com_off_f, rf, com_h);
        double pel[3] = { com_f[stance][0] - com_off_f[0], com_f[stance][1] - com_off_f[1],
                          com_f[stance][2] - com_off_f[2] };
        for (int i = 0; i < 3; i++)
            d[i] = sw_pos[i] - pel[i];
        mv(dh, rf, d);
        mtv(pos, rt, dh); /* into the pelvis frame, the pelvis as it is */
        double sw_yaw = swing_yaw0 + (0.5 * dyaw - swing_yaw0) * a;
        rz(rw, sw_yaw);
        mtm(rwt, rt, rw);
        set_pose(&want[sw], pos, rwt);
        /* the stance ankle: the pelvis upright at STAND_HEIGHT over it */
        double st_yaw = stance_yaw0 + (-0.5 * dyaw - stance_yaw0) * s;
        double dst[3] = { -pel[0], -pel[1], -STAND_HEIGHT };
        mv(pos, rf, dst);
        rz(rw, st_yaw);
        set_pose(&want[stance], pos, rw);

        step_t += DT;
        /* the swing foot is down (its ankle as low as the stance one, late in
         * the swing) or overdue: swap */
        double sw_h = com_f[stance][2] - com_f[sw][2];
        int touched = ss > TOUCH_PHASE && sw_h < TOUCH_H;
        if (touched || step_t >= STEP_S + LATE_S) {
            lift_off(stance, sw, com_f, fyaw);
            /* the step's mean velocity (the centre of mass over the stance
             * ankle) against the command trims the velocity the footholds
             * plan for (an integral over steps: the model's errors walk the
             * G1 off at a steady speed otherwise; a steady gait's mean
             * sideways velocity over a step is zero, either foot) */
            if (vn > 0) {
                trim[0] = roz_math_clamp(trim[0] + TRIM_I * (vsum[0] / vn - cmd_vx), -TRIM_MAX,
                                         TRIM_MAX);
                trim[1] = roz_math_clamp(trim[1] + TRIM_I * (vsum[1] / vn - cmd_vy), -TRIM_MAX,
                                         TRIM_MAX);
            }
            vsum[0] = vsum[1] = 0.0;
            vn = 0;
            stance = sw;
            step_t = 0.0;
            grow_now = e_step;
            /* told to stop a while ago and slow: the feet stay down */
            if (touched && still_t >= STILL_S && roz_math_fabs(vel[stance][0]) < STILL_V) {
                standing = 1;
                stand_t = resume_t = 0.0;
                stand_sh = 0.0;
                for (int leg = 0; leg < 2; leg++) {
                    for (int i = 0; i < 3; i++)
                        stand_p[leg][i] = foot_h[leg][i];
                    stand_yaw[leg] = fyaw[leg];
                }
            }
        }
    }
    /* one inverse-kinematics step a tick, the legs in turn, linearised at
     * the measured joints (two full steps would cost 17,000 of the tick's
     * 20,000 fuel units) */
    for (int leg = 0; leg < 2; leg++) {
        if ((tick & 1) != leg)
            continue;
        legs_ik_step_from(q_ik[leg], &want[leg], IK_WR, &foot[leg], q[leg], axes[leg], origins[leg]);
        for (int j = 0; j < LEGS_JOINTS; j++)
            q_ik[leg][j] = roz_math_clamp(q_ik[leg][j], qmin[leg][j], qmax[leg][j]);
    }
    /* balance offsets on top of the kinematic targets, for this tick only:
     * standing, the ankles push the centre of mass back over the feet;
     * walking, the stance hip damps the torso's tilt */
    double off[2][LEGS_JOINTS];
    for (int leg = 0; leg < 2; leg++)
        for (int j = 0; j < LEGS_JOINTS; j++)
            off[leg][j] = 0.0;
    if (!walking || standing) {
        double shift = standing ? 0.0 : SHIFT_M * smooth((t - CROUCH_S) / SHIFT_S);
        double ex = 0.5 * (com_f[0][0] + com_f[1][0]) - SOLE_X;
        double ey = 0.5 * (com_f[0][1] + com_f[1][1]) + shift;
        double vx = 0.5 * (vel[0][0] + vel[1][0]), vy = 0.5 * (vel[0][1] + vel[1][1]);
        double ramp = standing ? smooth(stand_t / 0.2) : smooth(t / CROUCH_S);
        for (int leg = 0; leg < 2; leg++) {
            off[leg][4] = ramp * roz_math_clamp(ANKLE_P * ex + ANKLE_D * vx, -0.3, 0.3);
            off[leg][5] = -ramp * roz_math_clamp(ANKLE_ROLL_P * ey + ANKLE_ROLL_D * vy, -0.05, 0.05);
        }
    } else {
        /* the pelvis's pitch and roll (small angles): world up seen from it */
        /* the stance ankle pushes the divergent component toward where the
         * gait wants it over the sole (the ankle strategy within the foot) */
        double want_x = 0.5 * cmd_vx * STEP_S;
        double ex = com_f[stance][0] - SOLE_X - want_x;
        off[stance][4] = roz_math_clamp(WALK_ANKLE_P * ex + WALK_ANKLE_D * vel[stance][0], -0.3, 0.3);
        off[stance][0] = roz_math_clamp(TORSO_P * -rt[2][0] + TORSO_RATE * gy, -0.3, 0.3);
        off[stance][1] = roz_math_clamp(TORSO_P * rt[2][1] + TORSO_RATE * gx, -0.2, 0.2);
    }
    double up_p[3] = { rt[2][0], rt[2][1], rt[2][2] }; /* world up, pelvis frame */
    double share_left;
    if (!walking || standing) {
        double span = com_f[1][1] - com_f[0][1]; /* left ankle from the right */
        share_left = span > 0.05 ? roz_math_clamp(com_f[1][1] / span, 0.0, 1.0) : 0.5;
    } else {
        double w = smooth(step_t / DOUBLE_S); /* the weight passes in double support */
        share_left = stance == 0 ? w : 1.0 - w;
    }
    carry(0, share_left, up_p, com_off, &foot[0], axes[0], origins[0]);
    carry(1, 1.0 - share_left, up_p, com_off, &foot[1], axes[1], origins[1]);
    for (int leg = 0; leg < 2; leg++)
        for (int j = 0; j < LEGS_JOINTS; j++)
            q_ik[leg][j] += off[leg][j];
    send(tick);
    for (int leg = 0; leg < 2; leg++)
        for (int j = 0; j < LEGS_JOINTS; j++)
            q_ik[leg][j] -= off[leg][j];
}
