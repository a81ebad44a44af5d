/* SPDX-License-Identifier: Apache-2.0 */
/* The mujoco port: what open refuses and how it says so; the robot's own
 * actuator law; the G1 standing on the example stand controller; the same
 * bits on every run; the gantry and a push. Simulated time throughout: a
 * few simulated seconds a case. */
/* white-box in part: reads the port's command, history and counters (roz/private.h) */
#define ROZ_PRIVATE_ACCESS
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "roz/builtin.h"
#include "roz/manifest_toml.h"
#include "mujoco_robot_file.h"
#include "roz/port/mujoco.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_runtime.h"

/* ---- fixtures ------------------------------------------------------------------ */

static roz_mujoco_t mj;
static roz_runtime_t rt;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts); /* figures only; nothing is judged by them */
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Room for the parameters one caller passes. */
typedef struct {
    roz_param_t items[8];
    char        buf[8][256];
} param_room_t;

/* The @p n "key=value" strings of @p ap as parameters, in @p room. */
static roz_params_t params_of(param_room_t *room, int n, va_list ap)
{
    for (int i = 0; i < n; i++) {
        snprintf(room->buf[i], sizeof room->buf[i], "%s", va_arg(ap, const char *));
        char *eq = strchr(room->buf[i], '=');
        *eq = '\0';
        room->items[i].key = room->buf[i];
        room->items[i].value = eq + 1;
    }
    return (roz_params_t){ room->items, (size_t)n };
}

/* Opens @p m on the port with @p n "key=value" parameters; returns open's
 * result, its message in @p err. */
static int open_with(roz_port_t *p, const roz_manifest_t *m, char *err, size_t errlen, int n, ...)
{
    static param_room_t room;
    va_list ap;
    va_start(ap, n);
    roz_params_t params = params_of(&room, n, ap);
    va_end(ap);
    err[0] = '\0';
    return roz_port_open(p, m, &params, err, errlen);
}

static void expect_refused(const roz_manifest_t *m, const char *file, const char *want1,
                           const char *want2, int n, ...)
{
    char err[512];
    static param_room_t room;
    va_list ap;
    va_start(ap, n);
    roz_params_t params = params_of(&room, n, ap);
    va_end(ap);
    roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
    if (file != NULL)
        roz_mujoco_set_robot_file(&mj, file);
    int rc = roz_port_open(&p, m, &params, err, sizeof err);
    print_message("refused: %s\n", err);
    assert_int_not_equal(rc, ROZ_OK);
    assert_non_null(strstr(err, want1));
    if (want2 != NULL)
        assert_non_null(strstr(err, want2));
    roz_port_close(&p);
}

/* The pendulum's manifest (pendulum.toml), *p open on its robot file (put
 * in *file unless NULL) with @p model ("model=..."; NULL: the robot file's), failing the
 * test with open's message. */
static const roz_manifest_t *open_pendulum(roz_port_t *p, const char **file, const char *model)
{
    const roz_manifest_t *m = roz_test_mujoco_robot_file(&mj, "pendulum.toml");
    char err[512];
    const char *robot_file = mj.robot_file;
    *p = roz_mujoco_port(&mj, NULL, NULL);
    roz_mujoco_set_robot_file(&mj, robot_file);
    if (file != NULL)
        *file = robot_file;
    if ((model != NULL ? open_with(p, m, err, sizeof err, 1, model)
                       : open_with(p, m, err, sizeof err, 0)) != ROZ_OK)
        fail_msg("%s", err);
    return m;
}

/* The fault of @p p after a read that returned @p rc, which must be
 * ROZ_EROBOT. */
static roz_port_fault_t fault_after(roz_port_t *p, int rc)
{
    roz_port_fault_t f;
    assert_int_equal(rc, ROZ_EROBOT);
    assert_int_equal(p->ops->fault(p->self, &f), ROZ_OK);
    return f;
}

/* ---- open --------------------------------------------------------------------- */

static void test_mujoco_refusals(void **state)
{
    (void)state;
    const roz_manifest_t *m = roz_test_mujoco_robot_file(&mj, "pendulum.toml");
    const char *f = mj.robot_file;
    expect_refused(m, f, "\"modle\"", NULL, 1, "modle=x.xml");
    expect_refused(m, f, "pendulum.toml", "nothere.xml", 1, "model=nothere.xml");
    expect_refused(m, f, "joint \"swing\"", "\"nohinge\"", 1, "joint_names=swing=nohinge");
    expect_refused(m, f, "joint_names", "\"elbow\" is not a joint", 1, "joint_names=elbow=hinge");
    expect_refused(m, f, "keyframe = \"nokey\"", "pendulum.xml", 1, "keyframe=nokey");
    expect_refused(m, f, "timestep = 0.003", "whole number", 1, "timestep=0.003");
    expect_refused(m, f, "push", "no body", 1, "push=1,0,0@nobody@0:10");
    expect_refused(m, f, "gantry", "no floating base", 1, "gantry=0");
    expect_refused(m, f, "delay", "K@FROM:TO", 1, "delay=99@0:10");
    /* the simulators' one grammar (roz/hal/inject.h): a written TO of 0 is
     * no "forever" (this port used to take 5:0 and 0:0 as that) */
    expect_refused(m, f, "parameter drop = \"5:0\"", "FROM 5 after TO 0", 1, "drop=5:0");
    expect_refused(m, f, "parameter drop = \"1:2;0:0\"", "FROM 0 equals TO", 1, "drop=1:2;0:0");
    expect_refused(m, f, "parameter restart = \"5\"", "no TO", 1, "restart=5");
}

/* The model's includes within rozgen's limits, checked before MuJoCo reads
 * them (fifteen files each including the next four times once grew MuJoCo
 * to 4 GB and std::bad_alloc; /dev/zero was read until memory ran out). */
static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static void test_mujoco_include_bounds(void **state)
{
    char dir[] = "/tmp/roz_mjcf_XXXXXX", path[256], text[512], param[300];
    (void)state;
    const roz_manifest_t *m = roz_test_mujoco_robot_file(&mj, "pendulum.toml");
    const char *f = mj.robot_file;
    assert_non_null(mkdtemp(dir));
    for (int k = 0; k < 15; k++) {
        char inc[200] = "<body/>";
        if (k < 14)
            snprintf(inc, sizeof inc, "<!-- <include file=\"x.xml\"/> -->"
                     "%s<include file=\"f%d.xml\"/><include file='f%d.xml' />"
                     "<include\n file=\"f%d.xml\"/><include file=\"f%d.xml\"/>", "", k + 1,
                     k + 1, k + 1, k + 1);
        snprintf(path, sizeof path, "%s/f%d.xml", dir, k);
        snprintf(text, sizeof text, "<mujoco><worldbody>%s</worldbody></mujoco>", inc);
        write_file(path, text);
    }
    snprintf(param, sizeof param, "model=%s/f0.xml", dir);
    expect_refused(m, f, "more than 256 includes in all", "f0.xml", 1, param);
    snprintf(path, sizeof path, "%s/zero.xml", dir);
    write_file(path, "<mujoco><include file=\"/dev/zero\"/></mujoco>");
    snprintf(param, sizeof param, "model=%s", path);
    expect_refused(m, f, "<include file=\"/dev/zero\">: not a regular file", NULL, 1, param);
    snprintf(path, sizeof path, "%s/loop.xml", dir);
    write_file(path, "<mujoco><include file=\"loop.xml\"/></mujoco>");
    snprintf(param, sizeof param, "model=%s", path);
    expect_refused(m, f, "includes nested more than 16 deep", NULL, 1, param);
    for (int k = 0; k < 15; k++) {
        snprintf(path, sizeof path, "%s/f%d.xml", dir, k);
        remove(path);
    }
    snprintf(path, sizeof path, "%s/zero.xml", dir);
    remove(path);
    snprintf(path, sizeof path, "%s/loop.xml", dir);
    remove(path);
    remove(dir);
}

static void test_mujoco_refuses_effort_beyond_the_actuator(void **state)
{
    (void)state;
    const roz_manifest_t *m = roz_test_mujoco_robot_file(&mj, "pendulum_strong.toml");
    expect_refused(m, mj.robot_file, "pendulum_strong.toml", "[-8, 8] N.m exceed", 0);
}

/* ---- the actuator law ------------------------------------------------------------ */

static void test_mujoco_pendulum_law(void **state)
{
    (void)state;
    roz_port_t p;
    open_pendulum(&p, NULL, NULL);
    assert_int_equal(mj.steps_per_tick, 10); /* 100 Hz, 1 ms steps */
    double st[3], cmd[5] = { 0.0, 0.0, 0.0, 0.0, 0.0 };
    assert_int_equal(roz_port_read(&p, st, 3), 1);
    assert_near(st[0], 1.0, 1e-12); /* the keyframe "out" */
    /* no command yet: the motor is limp, the bob falls toward 0 */
    assert_int_equal(roz_port_read(&p, st, 3), 1);
    assert_true(st[0] < 1.0);
    assert_near(st[2], 0.0, 0.0);
    /* a stiff hold at 1 rad: kp 100, kd 5, which needs more than 4 N.m at first
     * (saturated at the manifest's limit) and then holds against gravity */
    cmd[0] = 1.0;
    cmd[2] = 100.0;
    cmd[3] = 5.0;
    for (int t = 0; t < 300; t++) {
        assert_int_equal(roz_port_write(&p, cmd, 5), ROZ_OK);
        assert_int_equal(roz_port_read(&p, st, 3), 1);
        assert_true(fabs(st[2]) <= 4.0);
    }
    /* gravity's torque at 1 rad: m g l sin(q) = 1.01 * 9.81 * ~0.5 * sin(1) ~ 4.1 N.m
     * > 4: the hold sags until kp * error plus 4 N.m balances it */
    print_message("pendulum held at %.4f rad with %.3f N.m (%llu saturated steps)\n", st[0], st[2],
                  (unsigned long long)mj.saturated);
    assert_true(st[0] < 1.0 && st[0] > 0.8);
    assert_true(mj.saturated > 0);
    /* a value outside the manifest never reaches the motor, and is
     * counted as one the filter upstream should have stopped: the count
     * the physics tests assert 0 can fail */
    assert_int_equal(mj.violations, 0);
    cmd[4] = 50.0;
    assert_int_equal(roz_port_write(&p, cmd, 5), ROZ_OK);
    assert_int_equal(mj.clamped, 1);
    assert_int_equal(mj.violations, 1);
    cmd[4] = NAN;
    assert_int_equal(roz_port_write(&p, cmd, 5), ROZ_OK);
    assert_int_equal(mj.violations, 2);
    roz_mujoco_counters_t c;
    roz_mujoco_counters(&mj, &c);
    assert_int_equal(c.violations, 2);
    assert_near(mj.cmd[4], 0.0, 0.0);
    roz_port_close(&p);
}

/* A simulation that diverges is never reset behind the run's back (MuJoCo's
 * automatic reset is off): its warning fails every read after it, named. A
 * spring far too stiff for the time step (pendulum_diverge.xml). */
static void test_mujoco_warning_fails_the_run(void **state)
{
    (void)state;
    roz_port_t p;
    double st[3];
    open_pendulum(&p, NULL, "model=pendulum_diverge.xml");
    int rc = 1, t = 0;
    for (; t < 100 && rc == 1; t++)
        rc = roz_port_read(&p, st, 3);
    roz_port_fault_t f = fault_after(&p, rc);
    print_message("after %d reads: %s, %s (step %u); the swing read back at %g rad\n", t, f.what,
                  f.kind, (unsigned)f.code, st[0]);
    assert_non_null(strstr(f.kind, "MuJoCo warning"));
    assert_false(fabs(st[0] - 1.0) < 0.5); /* not reset to the keyframe's start */
    assert_int_equal(roz_port_read(&p, st, 3), ROZ_EROBOT); /* and it stays failed */
    roz_mujoco_counters_t c;
    roz_mujoco_counters(&mj, &c);
    assert_int_equal(c.warnings, 1);
    roz_port_close(&p);
}

/* MuJoCo raises an error (mju_error, whose default handler waits for Enter
 * and exits the process) or throws a C++ exception: the port turns either
 * into a fault naming the model and what MuJoCo said, and the process goes
 * on (ports/mujoco/src/mj_guard.cc): a model whose solver runs out of
 * stack once its bob touches the floor (pendulum_arena.xml), in a tick and
 * in open. */
static void test_mujoco_engine_error_is_a_fault(void **state)
{
    (void)state;
    const char *file;
    roz_port_t p;
    const roz_manifest_t *m = open_pendulum(&p, &file, "model=pendulum_arena.xml");
    double st[3], cmd[5] = { 0.0, 0.0, 0.0, 0.0, 0.0 };
    int rc = 1, t = 0;
    for (; t < 100 && rc >= 0; t++) {
        rc = roz_port_read(&p, st, 3);
        if (rc >= 0)
            assert_int_equal(roz_port_write(&p, cmd, 5), ROZ_OK);
    }
    roz_port_fault_t f = fault_after(&p, rc);
    print_message("after %d reads: %s, %s (step %u)\n", t, f.what, f.kind, (unsigned)f.code);
    assert_string_equal(f.what, "physics");
    assert_non_null(strstr(f.kind, "MuJoCo error: mj_stackAlloc: out of memory"));
    assert_non_null(strstr(f.kind, "pendulum_arena.xml"));
    assert_int_equal(roz_port_read(&p, st, 3), ROZ_EROBOT); /* and it stays failed */
    roz_port_close(&p);
    /* resting on the floor from the start: open's own first step fails,
     * and open refuses, naming the model and what MuJoCo said */
    expect_refused(m, file, "pendulum_arena.xml", "MuJoCo error: mj_stackAlloc: out of memory", 2,
                   "model=pendulum_arena.xml", "keyframe=down");
    /* and the port opens again afterwards: nothing of MuJoCo's was left
     * half-done */
    char err[512];
    assert_int_equal(open_with(&p, m, err, sizeof err, 0), ROZ_OK);
    assert_int_equal(roz_port_read(&p, st, 3), 1);
    roz_port_close(&p);
}

/* ---- the G1 ------------------------------------------------------------------------ */

typedef struct {
    double   height, roll, pitch, min_height;
    uint64_t hash;
    double   open_s, run_s;
    uint64_t steps;
} g1_run_t;

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 0x100000001B3ull;
    return h;
}

/* The G1 on the example stand controller for @p ticks (500 a simulated
 * second), with @p param (NULL: none). */
static void run_g1(int ticks, const char *param, g1_run_t *out)
{
    const roz_manifest_t *m = roz_builtin_find("unitree_g1");
    assert_non_null(m);
    roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
    char err[512];
    double t0 = now_s();
    int rc = param != NULL ? open_with(&p, m, err, sizeof err, 1, param)
                           : open_with(&p, m, err, sizeof err, 0);
    if (rc != ROZ_OK)
        fail_msg("%s", err);
    out->open_s = now_s() - t0;

    roz_runtime_config_t cfg;
    roz_test_clock_t clk;
    roz_test_physics_config(&cfg, m, p, &clk);
    roz_test_runtime_start(&rt, &cfg, "g1_stand");
    uint64_t h = 0xCBF29CE484222325ull;
    double st[ROZ_CFG_MAX_STATES];
    t0 = now_s();
    for (int t = 0; t < ticks; t++) {
        { int rc_ = roz_runtime_tick(&rt); (void)rc_; }
        roz_mujoco_base_t b;
        roz_mujoco_base(&mj, &b);
        h = fnv(h, b.pos, sizeof b.pos);
        if (getenv("ROZ_TEST_MUJOCO_TRACE") != NULL && t % 100 == 0)
            print_message("  tick %4d: pelvis %.3f m, roll %6.2f, pitch %6.2f deg\n", t, b.pos[2],
                          b.roll * 57.2958, b.pitch * 57.2958);
        h = fnv(h, mj.hist[mj.tick > 0 ? (mj.tick - 1) % (ROZ_MUJOCO_MAX_DELAY + 1) : 0],
                m->n_states * sizeof(double));
    }
    out->run_s = now_s() - t0;
    (void)st;
    assert_int_equal(roz_runtime_faults(&rt), 0);
    roz_mujoco_base_t b;
    roz_mujoco_base(&mj, &b);
    out->height = b.pos[2];
    out->roll = b.roll;
    out->pitch = b.pitch;
    out->min_height = b.min_height;
    out->hash = h;
    out->steps = b.steps;
    print_message("G1 %s: open %.2f s; %d ticks (%.1f s simulated, %llu steps) in %.3f s: "
                  "%.1f us a step, %.1fx real time; pelvis %.3f m (lowest %.3f), roll %.2f, "
                  "pitch %.2f deg; %u ground contacts (%s%s%s); %llu saturated; trace %016llx\n",
                  param != NULL ? param : "", out->open_s, ticks, ticks / 500.0,
                  (unsigned long long)b.steps, out->run_s, 1e6 * out->run_s / (double)b.steps,
                  ticks / 500.0 / out->run_s, b.pos[2], b.min_height, b.roll * 57.2958,
                  b.pitch * 57.2958, (unsigned)b.contacts, b.n_bodies > 0 ? b.bodies[0] : "",
                  b.n_bodies > 1 ? ", " : "", b.n_bodies > 1 ? b.bodies[1] : "",
                  (unsigned long long)mj.saturated, (unsigned long long)h);
    roz_runtime_deinit(&rt);
    roz_port_close(&p);
}

/* The example stand (examples/controllers/g1_stand.c), let go at tick 0, limp
 * while its gains ramp in over its first second: the first 1.4 s, pelvis up
 * and level (test_mujoco_stand.c judges it over 30 s and pushed). */
static void test_mujoco_g1_stands(void **state)
{
    (void)state;
    g1_run_t r;
    run_g1(700, NULL, &r);
    assert_true(r.height > 0.6);
    assert_true(r.min_height > 0.6);
    assert_true(fabs(r.roll) < 0.2 && fabs(r.pitch) < 0.2);
}

static void test_mujoco_deterministic(void **state)
{
    (void)state;
    g1_run_t a, b;
    run_g1(500, "push=0,60,0@torso_link@200:260", &a);
    run_g1(500, "push=0,60,0@torso_link@200:260", &b);
    assert_true(a.hash == b.hash);
    assert_true(a.height == b.height);
}

/* Hung by its pelvis, limp (no controller), the G1 stays where it hangs. */
static void test_mujoco_gantry(void **state)
{
    (void)state;
    const roz_manifest_t *m = roz_builtin_find("unitree_g1");
    roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
    char err[512];
    if (open_with(&p, m, err, sizeof err, 1, "gantry=0:400") != ROZ_OK)
        fail_msg("%s", err);
    static double st[ROZ_CFG_MAX_STATES];
    roz_mujoco_base_t b0, b;
    assert_int_equal(roz_port_read(&p, st, m->n_states), 1);
    roz_mujoco_base(&mj, &b0);
    for (int t = 1; t < 400; t++)
        assert_int_equal(roz_port_read(&p, st, m->n_states), 1);
    roz_mujoco_base(&mj, &b);
    print_message("gantry: pelvis %.4f -> %.4f m over 0.8 s, limp\n", b0.pos[2], b.pos[2]);
    assert_true(fabs(b.pos[2] - b0.pos[2]) < 0.01);
    /* let go: it falls */
    for (int t = 0; t < 500; t++)
        assert_int_equal(roz_port_read(&p, st, m->n_states), 1);
    roz_mujoco_base(&mj, &b);
    print_message("let go: pelvis %.3f m after 1 s\n", b.pos[2]);
    assert_true(b.pos[2] < 0.5);
    roz_port_close(&p);
}

/* The IMU reads as the real one: level and still, gravity up. */
static void test_mujoco_g1_imu_and_faults(void **state)
{
    (void)state;
    const roz_manifest_t *m = roz_builtin_find("unitree_g1");
    roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
    char err[512];
    if (open_with(&p, m, err, sizeof err, 2, "drop=5:8", "restart=20:30") != ROZ_OK)
        fail_msg("%s", err);
    static double st[ROZ_CFG_MAX_STATES];
    int base = m->n_states - 10;
    assert_int_equal(roz_port_read(&p, st, m->n_states), 1);
    assert_near(st[base + 3], 1.0, 1e-3); /* w: level */
    assert_true(st[base + 9] > 5.0);       /* specific force: gravity up (and the landing) */
    int rcs[40];
    for (int t = 1; t < 40; t++)
        rcs[t] = roz_port_read(&p, st, m->n_states);
    assert_int_equal(rcs[4], 1);
    assert_int_equal(rcs[5], 0);
    assert_int_equal(rcs[7], 0);
    assert_int_equal(rcs[8], 1);
    assert_int_equal(rcs[20], 0);
    assert_int_equal(rcs[29], 0);
    assert_int_equal(rcs[30], ROZ_ELINK);
    assert_int_equal(rcs[31], 1);
    roz_port_close(&p);
}

/* A built-in robot on the port alone: open it, @p ticks of @p cmd. */
static void run_builtin(const char *id, roz_port_t *p, const double *cmd, int ticks, double *st)
{
    const roz_manifest_t *m = roz_builtin_find(id);
    char err[512];
    if (ticks < 0) {
        *p = roz_mujoco_port(&mj, NULL, NULL);
        if (open_with(p, m, err, sizeof err, 0) != ROZ_OK)
            fail_msg("%s", err);
        assert_int_equal(roz_port_read(p, st, m->n_states), 1);
        return;
    }
    for (int t = 0; t < ticks; t++) {
        assert_int_equal(roz_port_write(p, cmd, m->n_commands), ROZ_OK);
        assert_int_equal(roz_port_read(p, st, m->n_states), 1);
    }
}

/* The diff drive's wheels follow the twist; its odometry is the wheel
 * encoders', and agrees with the simulator's truth while nothing slips. */
static void test_mujoco_diff_drive(void **state)
{
    (void)state;
    roz_port_t p;
    double st[3], go[2] = { 0.5, 0.0 }, turn[2] = { 0.0, 1.0 };
    run_builtin("diff_drive", &p, NULL, -1, st);
    run_builtin("diff_drive", &p, go, 200, st); /* 2 s at 0.5 m/s */
    roz_mujoco_base_t b;
    roz_mujoco_base(&mj, &b);
    print_message("diff_drive: 2 s at 0.5 m/s: odom x %.3f y %.3f yaw %.3f; truth x %.3f y %.3f\n",
                  st[0], st[1], st[2], b.pos[0], b.pos[1]);
    assert_true(st[0] > 0.85 && st[0] < 1.05);
    assert_true(fabs(st[1]) < 0.02 && fabs(st[2]) < 0.02);
    assert_near(b.pos[0], st[0], 0.03);
    run_builtin("diff_drive", &p, turn, 100, st); /* 1 s at 1 rad/s */
    print_message("diff_drive: then 1 s at 1 rad/s: odom yaw %.3f\n", st[2]);
    assert_true(st[2] > 0.8 && st[2] < 1.05);
    roz_port_close(&p);
}

/* The quadcopter's autopilot climbs, holds and flies where it is told. */
static void test_mujoco_quadcopter(void **state)
{
    (void)state;
    roz_port_t p;
    double st[4], up[4] = { 0.0, 0.0, 1.0, 0.0 }, hold[4] = { 0, 0, 0, 0 };
    double fwd[4] = { 1.0, 0.0, 0.0, 0.5 };
    run_builtin("quadcopter", &p, NULL, -1, st);
    assert_near(st[2], 0.05, 0.01); /* on the ground */
    run_builtin("quadcopter", &p, up, 150, st);
    run_builtin("quadcopter", &p, hold, 100, st);
    print_message("quadcopter: 1.5 s at 1 m/s up, 1 s holding: z %.3f m\n", st[2]);
    assert_true(st[2] > 1.2 && st[2] < 1.7);
    double z = st[2];
    run_builtin("quadcopter", &p, hold, 100, st);
    assert_near(st[2], z, 0.05);
    run_builtin("quadcopter", &p, fwd, 200, st);
    roz_mujoco_base_t b;
    roz_mujoco_base(&mj, &b);
    print_message("quadcopter: 2 s at 1 m/s forward turning 0.5 rad/s: x %.3f y %.3f z %.3f "
                  "yaw %.3f, largest tilt %.1f deg\n", st[0], st[1], st[2], st[3],
                  b.max_tilt * 57.2958);
    assert_true(st[0] > 0.8);
    assert_near(st[3], 1.0, 0.15);
    assert_near(st[2], z, 0.2);
    assert_true(b.max_tilt < 0.6);
    roz_port_close(&p);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_mujoco_refusals),
              cmocka_unit_test(test_mujoco_include_bounds),
              cmocka_unit_test(test_mujoco_refuses_effort_beyond_the_actuator),
              cmocka_unit_test(test_mujoco_pendulum_law),
              cmocka_unit_test(test_mujoco_warning_fails_the_run),
              cmocka_unit_test(test_mujoco_engine_error_is_a_fault),
              cmocka_unit_test(test_mujoco_g1_imu_and_faults),
              cmocka_unit_test(test_mujoco_gantry),
              cmocka_unit_test(test_mujoco_g1_stands),
              cmocka_unit_test(test_mujoco_deterministic),
              cmocka_unit_test(test_mujoco_diff_drive),
              cmocka_unit_test(test_mujoco_quadcopter))
