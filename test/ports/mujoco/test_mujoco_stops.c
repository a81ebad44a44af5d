/* SPDX-License-Identifier: Apache-2.0 */
/* Every stop judged by what it does to a standing humanoid (SAFETY.md,
 * "Stops in physics"): the 29-DoF G1 stands on a stiff stand for 2
 * simulated seconds, then each stop in turn (e-stop, the controller's
 * e-stop request, a dropped stream, a trap, an overrun, the robot's board
 * restarting, the tick falling silent under the command watchdog, a
 * controller swap); 2 s later the pelvis must be up and no joint may have
 * moved fast. The PM01 the same, on its example balancing stand
 * (test_mujoco_stops_pm01), and the X2 on its stiff stand and its example
 * balancing stand (test_mujoco_stops_x2). Simulated time: the same numbers
 * on every run. */
/* white-box in part: reads the port's truth history (roz/private.h) */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "roz/builtin.h"
#include "roz/hal/joints.h"
#include "roz/port/mujoco.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_runtime.h"

/* ---- the cases ------------------------------------------------------------------ */

#define RATE 500
#define STOP_TICK 1000      /* stops_stand.h: 2 s, the stand has settled */
#define AFTER (2 * RATE)    /* judged 2 s after the stop */
#define WATCHDOG_TICKS 25   /* command_timeout_us' default, 50 ms, in ticks */

typedef enum {
    STOP_NONE,     /* the baseline: no stop */
    STOP_ESTOP,    /* the application's e-stop input, pressed and held */
    STOP_FROM_CTL, /* the controller stops itself (request, trap, overrun) */
    STOP_PORT,     /* the port's fault parameter (drop, restart) */
    STOP_SILENT,   /* the tick stops; the port's watchdog acts */
    STOP_SWAP,     /* another controller swapped in */
    STOP_EXIT,     /* the application exits: the port's exit, the stop's hold, at once */
    STOP_TWICE,    /* the tick stops, comes back for one write, and stops again */
} stop_how_t;

typedef struct {
    const char *name;
    stop_how_t  how;
    const char *controller; /* test/ports/mujoco/controllers, or the examples' */
    const char *param;      /* the port's, or NULL */
    const char *swap_in;    /* STOP_SWAP: the controller swapped in */
    unsigned    fault;      /* the fault that latches, 0: none */
} stop_case_t;

typedef struct {
    double   height;      /* pelvis, 2 s after the stop, m */
    double   lowest;      /* the lowest pelvis over those 2 s, m */
    double   peak_speed;  /* the fastest joint over those 2 s, rad/s (simulator's truth) */
    int      peak_joint;
    unsigned faults;
} stop_outcome_t;

static roz_mujoco_t mj;
static roz_runtime_t rt;

/* A controller of test/ports/mujoco/controllers, else the examples'. */
static const uint8_t *stops_controller(const char *name, size_t *len)
{
    const uint8_t *w = roz_test_wasm_or_null(ROZ_TEST_STOPS_DIR, name, len);
    return w != NULL ? w : roz_test_controller(name, len);
}

/* The truth sample of the last read (before any fault or latency). */
static const double *truth(void)
{
    return mj.hist[(mj.tick - 1) % (ROZ_MUJOCO_MAX_DELAY + 1)];
}

/* The truth sample of the last read; NULL before the first. */
static const double *truth_or_null(void)
{
    return mj.tick > 0 ? truth() : NULL;
}

/* What the DDS ports' command watchdogs send once the tick has been silent
 * for command_timeout_us: the ports' own hold (roz_joints_hold_keep(), the
 * hold the DDS ports send when the tick comes back after a trip, each
 * joint's setpoint roz_joints_hold_setpoint() as g1_watchdog() and the ROS 2
 * ports' bridge_watchdog() compute it) from the last command, kd the
 * damping default (shutdown_damping's default). The mujoco port has no
 * sender of its own: the test writes it in the port's place, every tick. */
static void watchdog_command(const roz_manifest_t *m, const double *last, const double *state,
                             double *cmd)
{
    static roz_joint_channels_t j[ROZ_MUJOCO_MAX_JOINTS];
    double q[ROZ_MUJOCO_MAX_JOINTS];
    for (uint16_t k = 0; k < mj.n_joints; k++) {
        j[k] = mj.joints[k].ch;
        q[k] = state[j[k].q_state];
    }
    double kd = j[0].kd_cmd >= 0 ? m->commands[j[0].kd_cmd].default_value : 0.0;
    roz_joints_hold_keep(m, j, mj.n_joints, last, q, kd, cmd);
}

/* The pelvis height (m) the stand stands above before the stop: the G1's
 * stand is at 0.783 m, the PM01's crouch lower (0.68 m its lowest in 30 s,
 * test_mujoco_stand.c), the smaller X2's at 0.640 m (down below 0.55 m in
 * test_mujoco_stand.c). */
static double standing_height(const char *robot)
{
    if (strcmp(robot, "agibot_x2") == 0)
        return 0.55;
    return strcmp(robot, "engineai_pm01") == 0 ? 0.6 : 0.7;
}

/* Case @p c on built-in @p robot. */
static void run_case_on(const char *robot, const stop_case_t *c, stop_outcome_t *o)
{
    const roz_manifest_t *m = roz_builtin_find(robot);
    assert_non_null(m);
    uint16_t n = (uint16_t)(m->n_commands / 5);
    roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
    roz_param_t item;
    char key[64];
    roz_params_t params = roz_test_params_kv(c->param, &item, key, sizeof key);
    roz_test_port_open(&p, m, &params);

    roz_runtime_config_t cfg;
    roz_test_clock_t clk;
    roz_test_physics_config(&cfg, m, p, &clk);
    size_t len;
    const uint8_t *w = stops_controller(c->controller, &len);
    roz_test_runtime_start_wasm(&rt, &cfg, w, len, c->controller);

    static double st[ROZ_CFG_MAX_STATES], wd[ROZ_CFG_MAX_COMMANDS];
    roz_mujoco_base_t b;
    memset(o, 0, sizeof *o);
    o->lowest = INFINITY;
    for (int t = 0; t < STOP_TICK + AFTER; t++) {
        if (t == STOP_TICK && c->how == STOP_ESTOP)
            roz_runtime_estop_set(&rt, 1);
        if (t == STOP_TICK && c->how == STOP_SWAP) {
            const uint8_t *w2 = stops_controller(c->swap_in, &len);
            roz_test_runtime_load(&rt, w2, len, c->swap_in);
        }
        if ((c->how == STOP_SILENT || c->how == STOP_TWICE) && t >= STOP_TICK) {
            /* the tick is gone: the robot keeps the last command until the
             * watchdog trips, then gets the watchdog's, every period */
            if (t == STOP_TICK + WATCHDOG_TICKS)
                watchdog_command(m, roz_runtime_last_commands(&rt), roz_runtime_last_state(&rt),
                                 wd);
            /* twice: 100 ms later the tick writes once (the port sends the
             * stop's hold from the controller's last command, about where
             * the joints are then) and is gone again: the second trip's
             * hold is the same, from the controller's last command */
            if (c->how == STOP_TWICE && t == STOP_TICK + WATCHDOG_TICKS + 50)
                watchdog_command(m, roz_runtime_last_commands(&rt), st, wd);
            if (t >= STOP_TICK + WATCHDOG_TICKS)
                assert_int_equal(roz_port_write(&p, wd, m->n_commands), ROZ_OK);
            (void)roz_port_read(&p, st, m->n_states);
        } else if (c->how == STOP_EXIT && t >= STOP_TICK) {
            /* the application exits: the DDS ports' exit, the stop's hold
             * (g1_safe(), bridge_safe()), every period from then on */
            if (t == STOP_TICK)
                watchdog_command(m, roz_runtime_last_commands(&rt), roz_runtime_last_state(&rt),
                                 wd);
            assert_int_equal(roz_port_write(&p, wd, m->n_commands), ROZ_OK);
            (void)roz_port_read(&p, st, m->n_states);
        } else {
            { int rc_ = roz_runtime_tick(&rt); (void)rc_; }
        }
        if (getenv("ROZ_TEST_MUJOCO_TRACE") != NULL && t % 100 == 0) {
            roz_mujoco_base(&mj, &b);
            print_message("  %s, tick %4d: pelvis %.3f m, roll %6.2f, pitch %6.2f deg\n", c->name,
                          t, b.pos[2], b.roll * 57.2958, b.pitch * 57.2958);
        }
        if (t == STOP_TICK - 1) {
            roz_mujoco_base(&mj, &b);
            if (!(b.pos[2] > standing_height(robot)))
                fail_msg("%s: the stand is down before the stop: pelvis %.3f m", c->name,
                         b.pos[2]);
            assert_int_equal(roz_runtime_faults(&rt), 0);
        }
        if (t >= STOP_TICK) {
            roz_mujoco_base(&mj, &b);
            if (b.pos[2] < o->lowest)
                o->lowest = b.pos[2];
            const double *s = truth();
            for (uint16_t k = 0; k < n; k++) {
                if (fabs(s[n + k]) > o->peak_speed) {
                    o->peak_speed = fabs(s[n + k]);
                    o->peak_joint = k;
                }
            }
        }
    }
    roz_mujoco_base(&mj, &b);
    o->height = b.pos[2];
    o->faults = roz_runtime_faults(&rt);
    assert_int_equal(mj.violations, 0);
    print_message("%-26s pelvis %.3f m 2 s later (lowest %.3f), peak joint speed %.2f rad/s (%s), "
                  "faults 0x%02x\n",
                  c->name, o->height, o->lowest, o->peak_speed,
                  m->states[n + o->peak_joint].name, o->faults);
    roz_runtime_deinit(&rt);
    roz_port_close(&p);
}

/* The checks every case shares: @p o latched @p c's fault (none when it
 * expects none) and no joint moved at 1 rad/s; the failures, each printed. */
static int stop_failures(const stop_case_t *c, const stop_outcome_t *o)
{
    int bad = 0;
    if ((o->faults & c->fault) != c->fault || (c->fault == 0 && o->faults)) {
        print_error("%s: faults 0x%02x, expected 0x%02x\n", c->name, o->faults, c->fault);
        bad++;
    }
    if (!(o->peak_speed < 1.0)) {
        print_error("%s: a joint moved at %.2f rad/s\n", c->name, o->peak_speed);
        bad++;
    }
    return bad;
}

/* The @p n @p cases on @p robot (named @p who): each as stop_failures()
 * has it, the pelvis 2 s after the stop above @p height and never below
 * @p lowest. */
static void run_standing(const char *robot, const char *who, const stop_case_t *cases, size_t n,
                         double height, double lowest)
{
    int bad = 0;
    for (size_t i = 0; i < n; i++) {
        stop_outcome_t o;
        run_case_on(robot, &cases[i], &o);
        bad += stop_failures(&cases[i], &o);
        if (!(o.height > height && o.lowest > lowest)) {
            print_error("%s: the %s fell: pelvis %.3f m (lowest %.3f)\n", cases[i].name, who,
                        o.height, o.lowest);
            bad++;
        }
    }
    assert_int_equal(bad, 0);
}

/* ---- tests ------------------------------------------------------------------------ */

/* Every stop on a robot's stiff stand (controllers/<ctl>stops_stand.h, whose
 * siblings stop themselves or swap in), then on its example balancing stand
 * @p stand; each named after @p who. */
#define STOP_CASES(who, ctl, stand)                                                            \
    { who "no stop", STOP_NONE, ctl "stops_stand", NULL, NULL, 0 },                            \
        { who "e-stop", STOP_ESTOP, ctl "stops_stand", NULL, NULL, ROZ_FAULT_ESTOP },          \
        { who "e-stop request", STOP_FROM_CTL, ctl "stops_estop_request", NULL, NULL,         \
          ROZ_FAULT_ESTOP_REQUEST },                                                           \
        { who "stale (stream dropped)", STOP_PORT, ctl "stops_stand", "drop=1000:1100", NULL, \
          ROZ_FAULT_STALE },                                                                   \
        { who "trap", STOP_FROM_CTL, ctl "stops_trap", NULL, NULL, ROZ_FAULT_TRAP },           \
        { who "overrun (fuel)", STOP_FROM_CTL, ctl "stops_overrun", NULL, NULL,               \
          ROZ_FAULT_OVERRUN },                                                                 \
        { who "link (board restart)", STOP_PORT, ctl "stops_stand", "restart=1000:1002", NULL, \
          ROZ_FAULT_LINK },                                                                    \
        { who "command watchdog", STOP_SILENT, ctl "stops_stand", NULL, NULL, 0 },             \
        { who "swap (stiff stand)", STOP_SWAP, ctl "stops_stand", NULL, ctl "stops_swap_in",  \
          0 },                                                                                 \
        { who "e-stop (balancing stand)", STOP_ESTOP, stand, NULL, NULL, ROZ_FAULT_ESTOP },    \
        { who "stale (balancing stand)", STOP_PORT, stand, "drop=1000:1100", NULL,            \
          ROZ_FAULT_STALE },                                                                   \
        { who "link (balancing stand)", STOP_PORT, stand, "restart=1000:1002", NULL,          \
          ROZ_FAULT_LINK },                                                                    \
        { who "watchdog (balancing stand)", STOP_SILENT, stand, NULL, NULL, 0 }

/* The G1's balancing stand: soft ankles (kp 40) whose setpoints sit away
 * from where the joints are; the hold keeps the torque it had. */
static const stop_case_t cases[] = {
    STOP_CASES("", "", "g1_stand"),
    { "watchdog twice (balancing)", STOP_TWICE, "g1_stand", NULL, NULL, 0 },
    { "exit (balancing stand)", STOP_EXIT, "g1_stand", NULL, NULL, 0 },
};

static void test_mujoco_stops_g1(void **state)
{
    (void)state;
    run_standing("unitree_g1", "G1", cases, sizeof cases / sizeof cases[0], 0.7, 0.65);
}

/* The PM01 on its example balancing stand (pm01_stand: ankles kp 100, its
 * setpoints moved by the IMU balance), each stop at 2 s; the controllers
 * that stop themselves wrap it (controllers/stops_pm01.h). The watchdog's
 * hold is the ROS 2 ports' (bridge_watchdog() in ports/ros2), written in
 * the mujoco port's place. */
#define PM01 "engineai_pm01"
static const stop_case_t pm01_cases[] = {
    { "pm01: no stop", STOP_NONE, "pm01_stand", NULL, NULL, 0 },
    { "pm01: e-stop", STOP_ESTOP, "pm01_stand", NULL, NULL, ROZ_FAULT_ESTOP },
    { "pm01: e-stop request", STOP_FROM_CTL, "stops_pm01_estop_request", NULL, NULL,
      ROZ_FAULT_ESTOP_REQUEST },
    { "pm01: stale", STOP_PORT, "pm01_stand", "drop=1000:1100", NULL, ROZ_FAULT_STALE },
    { "pm01: trap", STOP_FROM_CTL, "stops_pm01_trap", NULL, NULL, ROZ_FAULT_TRAP },
    { "pm01: overrun (fuel)", STOP_FROM_CTL, "stops_pm01_overrun", NULL, NULL,
      ROZ_FAULT_OVERRUN },
    { "pm01: link (restart)", STOP_PORT, "pm01_stand", "restart=1000:1002", NULL,
      ROZ_FAULT_LINK },
    { "pm01: command watchdog", STOP_SILENT, "pm01_stand", NULL, NULL, 0 },
    { "pm01: swap", STOP_SWAP, "pm01_stand", NULL, "stops_pm01_swap_in", 0 },
    { "pm01: watchdog twice", STOP_TWICE, "pm01_stand", NULL, NULL, 0 },
    { "pm01: exit", STOP_EXIT, "pm01_stand", NULL, NULL, 0 },
};

/* The PM01's crouch on pm01_stand settles slowly (0.75 m at 4 s, 0.68 m
 * its lowest in 30 s: test_mujoco_stand.c): each stop must leave its
 * pelvis, over the 2 s after the stop, within PM01_SAG (m) of where the
 * stand without a stop has it 2 s after (the first case), the fault
 * latched, no joint fast. */
#define PM01_SAG 0.03
static void test_mujoco_stops_pm01(void **state)
{
    (void)state;
    int bad = 0;
    double up = NAN;
    for (size_t i = 0; i < sizeof pm01_cases / sizeof pm01_cases[0]; i++) {
        stop_outcome_t o;
        run_case_on(PM01, &pm01_cases[i], &o);
        if (i == 0)
            up = o.height; /* no stop: where the stand stands */
        bad += stop_failures(&pm01_cases[i], &o);
        if (!(o.height > up - PM01_SAG && o.lowest > up - PM01_SAG)) {
            print_error("%s: the PM01 sank: pelvis %.3f m (lowest %.3f), %.3f m unstopped\n",
                        pm01_cases[i].name, o.height, o.lowest, up);
            bad++;
        }
    }
    assert_true(up > standing_height(PM01));
    assert_int_equal(bad, 0);
}

/* The same stops on the standing X2 (the team's model from AgiBot's URDF
 * facts, models/agibot_x2.xml): its stiff stand (controllers/
 * x2_stops_stand.h: x2_stand's pose at the hold gains) and x2_stand, the
 * example's balancing stand. The watchdog's hold is the ROS 2 ports'
 * (bridge_watchdog() in ports/ros2), written in the mujoco port's place. */
#define X2 "agibot_x2"
static const stop_case_t x2_cases[] = { STOP_CASES("X2 ", "x2_", "x2_stand") };

/* 2 s after each stop the X2's pelvis must still be above
 * standing_height() all along, the fault latched, no joint at 1 rad/s. */
static void test_mujoco_stops_x2(void **state)
{
    (void)state;
    double up = standing_height(X2);
    run_standing(X2, "X2", x2_cases, sizeof x2_cases / sizeof x2_cases[0], up, up);
}

/* The filter's limit stops in physics: constant_velocity drives every
 * command at a fifth of its upper limit, so every joint runs toward its
 * upper limit, on @p robot (@p param: the port's, or NULL) for @p ticks.
 * Each paired joint must stay inside its limit plus its margin (the margin
 * covers a velocity servo's lag against gravity, or the coasting of an
 * effort cut, which is reactive: SAFETY.md section 1); returns the closest any came to its
 * limit less margin, so the caller knows the limit was reached. */
static double run_into_limits(const char *robot, const char *param, int ticks)
{
    const roz_manifest_t *m = roz_builtin_find(robot);
    assert_non_null(m);
    roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
    roz_param_t item;
    char key[64];
    roz_params_t params = roz_test_params_kv(param, &item, key, sizeof key);
    roz_test_port_open(&p, m, &params);
    roz_runtime_config_t cfg;
    roz_test_clock_t clk;
    roz_test_physics_config(&cfg, m, p, &clk);
    roz_test_runtime_start(&rt, &cfg, "constant_velocity");
    double closest = INFINITY, worst = -INFINITY;
    const char *worst_name = "";
    for (int t = 0; t < ticks; t++) {
        { int rc_ = roz_runtime_tick(&rt); (void)rc_; }
        const double *s = truth();
        for (uint16_t c = 0; c < m->n_commands; c++) {
            const roz_channel_t *cc = &m->commands[c];
            if ((cc->type != ROZ_IF_VELOCITY && cc->type != ROZ_IF_EFFORT) ||
                cc->position_state == ROZ_CHANNEL_UNPAIRED)
                continue;
            const roz_channel_t *ps = &m->states[cc->position_state];
            double over = s[cc->position_state] - ps->max; /* > 0: past the limit */
            double left = ps->max - roz_manifest_limit_margin(ps) - s[cc->position_state];
            if (over > worst) {
                worst = over;
                worst_name = ps->name;
            }
            if (left < closest)
                closest = left;
            if (over > roz_manifest_limit_margin(ps))
                fail_msg("%s tick %d: %s at %.4f, %.4f past its limit %.4f", robot, t,
                         ps->name, s[cc->position_state], over, ps->max);
        }
    }
    assert_int_equal(mj.violations, 0);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    print_message("%s into its limits: closest %.4f inside the limit less margin, furthest "
                  "%.4f past a limit (%s)\n", robot, closest, worst, worst_name);
    roz_runtime_deinit(&rt);
    roz_port_close(&p);
    return closest;
}

/* A velocity-commanded UR5 joint stops inside its limit less margin (the
 * filter brakes in time); the G1 hung on a gantry, every joint pushed by a
 * feed-forward effort toward its upper limit, gets no effort past it. */
static void test_mujoco_stops_at_limits(void **state)
{
    (void)state;
    double ur5 = run_into_limits("ur5", NULL, 2500);
    assert_true(ur5 < 0.05); /* a joint got there */
    double g1 = run_into_limits("unitree_g1", "gantry=0", 1000);
    assert_true(g1 < 0.1);
}

/* Joints without a position command (the UR5's: velocity only) under the
 * stops: the arm moving every joint at a fifth of its speed limit
 * (`constant_velocity`) is stopped by an e-stop (the filter: velocity 0 at
 * once), by the ports' watchdog hold 50 ms after its tick fell silent, and
 * by the ports' exit (both roz_joints_hold_keep(), written in the mujoco
 * port's place); a second after the stop every joint is at rest where it
 * stopped: no stop drives a joint toward a position it was never
 * commanded (a hold without a position command holds where the joint
 * is). */
static void test_mujoco_stops_velocity_only(void **state)
{
    (void)state;
    static const struct {
        const char *name;
        stop_how_t  how;
        unsigned    fault;
        double      travel; /* the most a joint may move after the stop, rad */
    } rows[] = {
        /* the drives' own servo brakes from 0.63 rad/s in about 0.03 rad;
         * a joint still moving would go 0.63 rad in the second */
        { "e-stop", STOP_ESTOP, ROZ_FAULT_ESTOP, 0.05 },
        { "command watchdog", STOP_SILENT, 0, 0.1 }, /* 50 ms more at speed first */
        { "exit", STOP_EXIT, 0, 0.05 },
    };
    enum { UR5_RATE = 100, STOP = 100, JUDGED = 100 };
    const roz_manifest_t *m = roz_builtin_find("ur5");
    assert_non_null(m);
    for (size_t r = 0; r < sizeof rows / sizeof rows[0]; r++) {
        roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
        roz_test_port_open(&p, m, NULL);
        roz_runtime_config_t cfg;
        roz_test_clock_t clk;
        roz_test_physics_config(&cfg, m, p, &clk);
        clk.step = 1000000000u / UR5_RATE;
        roz_test_runtime_start(&rt, &cfg, "constant_velocity");
        static double st[ROZ_CFG_MAX_STATES], wd[ROZ_CFG_MAX_COMMANDS];
        double at_stop[ROZ_MUJOCO_MAX_JOINTS], moving = 0.0, travel = 0.0, rest = 0.0;
        for (int t = 0; t < STOP + JUDGED; t++) {
            const double *s = truth_or_null();
            if (t == STOP) {
                for (uint16_t k = 0; k < mj.n_joints; k++) {
                    at_stop[k] = s[mj.joints[k].ch.q_state];
                    moving = fmax(moving, fabs(s[mj.joints[k].ch.dq_state]));
                }
            }
            if (t == STOP && rows[r].how == STOP_ESTOP)
                roz_runtime_estop_set(&rt, 1);
            int silent = rows[r].how == STOP_SILENT && t >= STOP;
            if ((silent && t >= STOP + WATCHDOG_TICKS / 5) ||
                (rows[r].how == STOP_EXIT && t >= STOP)) {
                /* the ports' hold from the last command, every period */
                if (t == STOP || t == STOP + WATCHDOG_TICKS / 5)
                    watchdog_command(m, roz_runtime_last_commands(&rt),
                                     roz_runtime_last_state(&rt), wd);
                assert_int_equal(roz_port_write(&p, wd, m->n_commands), ROZ_OK);
                (void)roz_port_read(&p, st, m->n_states);
            } else if (silent) {
                (void)roz_port_read(&p, st, m->n_states); /* the last command goes on */
            } else {
                int rc_ = roz_runtime_tick(&rt);
                (void)rc_;
            }
            s = truth_or_null();
            if (t >= STOP && s != NULL) {
                for (uint16_t k = 0; k < mj.n_joints; k++) {
                    travel = fmax(travel, fabs(s[mj.joints[k].ch.q_state] - at_stop[k]));
                    if (t >= STOP + JUDGED / 2)
                        rest = fmax(rest, fabs(s[mj.joints[k].ch.dq_state]));
                }
            }
        }
        print_message("UR5, %-17s moving at %.2f rad/s: a joint moved %.4f rad after the stop, "
                      "fastest %.4f rad/s from 0.5 s on, faults 0x%02x\n",
                      rows[r].name, moving, travel, rest, roz_runtime_faults(&rt));
        assert_true(moving > 0.5); /* it was moving: constant_velocity, a fifth of 3.14 */
        if (!(travel < rows[r].travel))
            fail_msg("UR5, %s: a joint moved %.4f rad after the stop (at most %.2f)",
                     rows[r].name, travel, rows[r].travel);
        assert_true(rest < 0.02); /* the shoulder's servo sags a little under gravity */
        assert_int_equal(roz_runtime_faults(&rt), rows[r].fault);
        assert_int_equal(mj.violations, 0);
        roz_runtime_deinit(&rt);
        roz_port_close(&p);
    }
}

int main(int argc, char **argv)
{
    if (argc > 1) /* a test's name (a pattern): that one only */
        cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mujoco_stops_g1),
        cmocka_unit_test(test_mujoco_stops_pm01),
        cmocka_unit_test(test_mujoco_stops_x2),
        cmocka_unit_test(test_mujoco_stops_at_limits),
        cmocka_unit_test(test_mujoco_stops_velocity_only),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
