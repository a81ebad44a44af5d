/* SPDX-License-Identifier: Apache-2.0 */
/* The G1 port's peer = unitree_mujoco (docs/ports/unitree_g1.md, "In
 * Unitree's simulator"), end to end through rozrun, against the fake G1
 * behaving as Unitree's simulator does (fake_g1 --unitree-mujoco: LowState_
 * every 5 ms with tick, crc and mode_machine 0; every command applied
 * whatever its CRC, on a unit inertia per joint), on domain 1 as the
 * simulator's config has it, in a network namespace on lo.
 * Asserted:
 *  - with the setting (and dds_domain 1) the stand runs with no fault, the robot receives its commands (the
 *    knee's gain reaches 150), the simulated knee ends within 0.1 rad of the
 *    pose's 0.3, the last command is the port's exit hold, and rozrun says
 *    the setting at open and in its summary;
 *  - without it nothing is sent, every frame is dropped for its CRC, and
 *    the summary names the setting;
 *  - with it, what remains of the link checks: the simulator silent for
 *    longer than peer_timeout_ms (200 ms here, the silence 350 ms, less than
 *    --stale-ticks' 500 ms) and back latches LINK, counted as a return;
 *  - with it, a peer that answers as a robot (the fake G1 as it is: a CRC,
 *    a tick, mode_machine 5) gets nothing and the run stops with ROBOT
 *    naming the setting;
 *  - with it, open refuses an interface other than lo and a set
 *    CYCLONEDDS_URI, and an unknown value of peer, naming the parameter. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "fake_g1_client.h"
#include "rozrun_stand.h"
#include "support.h"

#ifndef ROZRUN
#error "ROZRUN, CONTROLLER, OUT: set by the build"
#endif

#define KNEE 3 /* left_knee_joint's motor slot */

/* rozrun against the G1 with @p p1, @p p2, @p p3 (extra --param values, or
 * NULL; a later one wins) for @p ticks; output in @p text; returns rozrun's
 * exit status. */
static int run3(const char *p1, const char *p2, const char *p3, int ticks, const char *out,
                void (*watch)(void *), void *ctx, char *text, size_t len)
{
    char nticks[16];
    snprintf(nticks, sizeof nticks, "%d", ticks);
    const char *argv[32];
    size_t n = 0;
    const char *fixed[] = { ROZRUN, "--robot", "unitree_g1", "--port", "unitree/G1",
                            "--param", "network_interface=lo",
                            /* a loaded machine must not fail the run on time
                             * (rozrun_stand.h) */
                            "--param", "peer_timeout_ms=5000",
                            "--param", "command_timeout_us=60000000",
                            "--controller", CONTROLLER, "--ticks", nticks,
                            "--budget-us", "off", "--stale-ticks", "250" };
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++)
        argv[n++] = fixed[i];
    if (p1 != NULL) {
        argv[n++] = "--param";
        argv[n++] = p1;
    }
    if (p2 != NULL) {
        argv[n++] = "--param";
        argv[n++] = p2;
    }
    if (p3 != NULL) {
        argv[n++] = "--param";
        argv[n++] = p3;
    }
    argv[n] = NULL;
    return roz_rozrun_spawn(argv, out, watch, ctx, text, len);
}

static int run(const char *p1, const char *p2, int ticks, const char *out, void (*watch)(void *),
               void *ctx, char *text, size_t len)
{
    return run3(p1, p2, NULL, ticks, out, watch, ctx, text, len);
}

static void start_fake(roz_fake_g1_t *fake, int sim)
{
    char err[256] = "";
    static const char *const as_sim[] = { "--unitree-mujoco", "--period-us", "5000", NULL };
    static const char *const as_robot[] = { "--period-us", "2000", NULL };
    if (roz_fake_g1_start(fake, ROZ_TEST_DDS_DOMAIN, sim ? as_sim : as_robot, err, sizeof err) !=
        0)
        fail_msg("%s", err);
}

typedef struct {
    roz_fake_g1_t *fake;
    double         kp; /* the knee's largest gain seen */
} watch_t;

static void watch_knee(void *ctx)
{
    watch_t *w = ctx;
    roz_fake_g1_cmd_t c;
    /* kp 200, the knee's hold gain, is only the exit's hold: not the stand's */
    if (roz_fake_g1_command(w->fake, &c) == 1 && c.kp[KNEE] > w->kp && c.kp[KNEE] != 200.0f)
        w->kp = c.kp[KNEE];
}

static void test_g1_sim_runs_with_the_setting(void **st)
{
    roz_fake_g1_t fake;
    roz_fake_g1_cmd_t c;
    char text[16384];
    double q, dq, tau;
    (void)st;

    start_fake(&fake, 1);
    watch_t w = { &fake, 0.0 };
    assert_int_equal(run("peer=unitree_mujoco", "dds_domain=1", 1500, OUT, watch_knee, &w, text,
                         sizeof text),
                     0);
    assert_non_null(strstr(text, "rozrun: unitree/G1: peer = unitree_mujoco (Unitree's "
                                 "simulator, domain 1 on lo)"));
    assert_non_null(strstr(text, "peer = unitree_mujoco: no state CRC and no tick checks"));
    assert_non_null(strstr(text, "  peer                   unitree_mujoco (simulator)"));
    assert_non_null(strstr(text, "faults                 none"));
    unsigned long long taken = 0, bad = 1;
    const char *link = strstr(text, "state link");
    assert_non_null(link);
    assert_int_equal(sscanf(link, "state link %llu frames taken, %llu bad CRC", &taken, &bad), 2);
    assert_true(taken > 100); /* 3 s at 200 Hz: about 600 */
    assert_int_equal(bad, 0);

    /* the robot got the stand, and the simulated knee followed it */
    assert_true(w.kp == 150.0);
    uint64_t good = 0, badcrc = 1;
    assert_int_equal(roz_fake_g1_commands(&fake, &good, &badcrc), 0);
    assert_true(good > 500);
    assert_int_equal(roz_fake_g1_motor_state(&fake, KNEE, &q, &dq, &tau), 0);
    print_message("simulated knee at the end: q %.4f rad (pose 0.3), dq %.4f rad/s\n", q, dq);
    assert_true(q > 0.2 && q < 0.4);
    /* the last command is the port's exit, the stop's hold, which the
     * simulator holds */
    for (int ms = 0; ms < 5000; ms += 20) {
        assert_int_equal(roz_fake_g1_command(&fake, &c), 1);
        if (c.kp[KNEE] == 200.0f)
            break;
        roz_fake_g1_sleep_ms(20);
    }
    for (int j = 0; j < 29; j++)
        if (!(c.mode[j] == 1 && c.kp[j] > 0.0 && c.kd[j] == 8.0 && c.tau[j] == 0.0))
            fail_msg("the last command, joint %d: mode %u kp %g kd %g tau %g (want the hold)", j,
                     c.mode[j], c.kp[j], c.kd[j], c.tau[j]);
    assert_int_equal(c.mode_machine, 0);
    assert_int_equal(roz_fake_g1_stop(&fake), 0);
}

static void test_g1_sim_refused_without_the_setting(void **st)
{
    roz_fake_g1_t fake;
    char text[16384];
    (void)st;

    start_fake(&fake, 1);
    (void)run("dds_domain=1", NULL, 500, OUT ".without", NULL, NULL, text, sizeof text);
    uint64_t good = 1, badcrc = 1;
    assert_int_equal(roz_fake_g1_commands(&fake, &good, &badcrc), 0);
    assert_int_equal(good, 0); /* nothing was sent */
    assert_non_null(strstr(text, "waiting for state      all 500 ticks"));
    unsigned long long taken = 1, bad = 0, like = 0;
    const char *link = strstr(text, "state link");
    assert_non_null(link);
    assert_int_equal(sscanf(link, "state link %llu frames taken, %llu bad CRC", &taken, &bad), 2);
    assert_int_equal(taken, 0);
    assert_true(bad > 10);
    const char *warn = strstr(text, "  warning                ");
    assert_non_null(warn);
    assert_int_equal(sscanf(warn, "  warning                %llu state frames dropped", &like), 1);
    assert_true(like == bad);
    assert_non_null(strstr(warn, "as unitree_mujoco sends them: for that simulator, "
                                 "--param peer=unitree_mujoco"));
    assert_int_equal(roz_fake_g1_stop(&fake), 0);
}

/* Once the robot has had commands, the simulator falls silent once. */
typedef struct {
    roz_fake_g1_t *fake;
    int            paused;
} pause_t;

static void pause_once(void *ctx)
{
    pause_t *p = ctx;
    uint64_t good = 0, bad = 0;
    if (p->paused || roz_fake_g1_commands(p->fake, &good, &bad) != 0 || good < 100)
        return;
    assert_int_equal(roz_fake_g1_ask(p->fake, "pause 350"), 0);
    p->paused = 1;
}

static void test_g1_sim_silence_latches_link(void **st)
{
    roz_fake_g1_t fake;
    char text[16384];
    (void)st;

    start_fake(&fake, 1);
    pause_t p = { &fake, 0 };
    assert_int_equal(run3("peer=unitree_mujoco", "dds_domain=1", "peer_timeout_ms=200", 1500,
                          OUT ".silence", pause_once, &p, text, sizeof text),
                     1);
    assert_true(p.paused);
    const char *faults = strstr(text, "faults                 latched:");
    assert_non_null(faults);
    assert_non_null(strstr(faults, "port link"));
    unsigned long long taken = 0, bad = 1, replays = 1, missing = 1, restarts = 0;
    const char *link = strstr(text, "state link");
    assert_non_null(link);
    assert_int_equal(sscanf(link, "state link %llu frames taken, %llu bad CRC, %llu replays, "
                                  "%llu missing, %llu peer restarts",
                            &taken, &bad, &replays, &missing, &restarts),
                     5);
    assert_int_equal(bad, 0);
    assert_int_equal(replays, 0);
    assert_int_equal(missing, 0); /* arrivals have no gaps: no tick to count them by */
    assert_true(restarts >= 1);
    assert_int_equal(roz_fake_g1_stop(&fake), 0);
}

static void test_g1_sim_refuses_a_robot(void **st)
{
    roz_fake_g1_t fake;
    char text[16384];
    (void)st;

    start_fake(&fake, 0); /* the fake G1 as a robot: CRC, tick, mode_machine 5 */
    assert_int_equal(run("peer=unitree_mujoco", "dds_domain=1", 500, OUT ".robot", NULL, NULL, text,
                         sizeof text),
                     1);
    assert_non_null(strstr(text, "faults                 latched: robot fault"));
    assert_non_null(strstr(text, "peer = unitree_mujoco: but the peer reports a robot's "
                                 "mode_machine"));
    uint64_t good = 1, badcrc = 1;
    assert_int_equal(roz_fake_g1_commands(&fake, &good, &badcrc), 0);
    assert_int_equal(good + badcrc, 0); /* not even the start-up hold */
    assert_int_equal(roz_fake_g1_stop(&fake), 0);
}

static void test_g1_sim_open_refusals(void **st)
{
    char text[16384];
    (void)st;

    assert_int_equal(run("peer=unitree_mujoco", "network_interface=eth0", 10, OUT ".iface",
                         NULL, NULL, text, sizeof text),
                     2);
    assert_non_null(strstr(text, "parameter peer = \"unitree_mujoco\" with network_interface = "
                                 "\"eth0\": the simulator's checks are off, so roz takes them "
                                 "only on lo"));
    assert_int_equal(run("peer=mujoco", NULL, 10, OUT ".value", NULL, NULL, text, sizeof text),
                     2);
    assert_non_null(strstr(text, "parameter peer = \"mujoco\": expected robot"));

    assert_int_equal(setenv("CYCLONEDDS_URI", "<CycloneDDS/>", 1), 0);
    int rc = run("peer=unitree_mujoco", NULL, 10, OUT ".uri", NULL, NULL, text, sizeof text);
    assert_int_equal(unsetenv("CYCLONEDDS_URI"), 0);
    assert_int_equal(rc, 2);
    assert_non_null(strstr(text, "parameter peer = \"unitree_mujoco\": CYCLONEDDS_URI is set"));
}

ROZ_TEST_MAIN(cmocka_unit_test(test_g1_sim_open_refusals),
              cmocka_unit_test(test_g1_sim_runs_with_the_setting),
              cmocka_unit_test(test_g1_sim_refused_without_the_setting),
              cmocka_unit_test(test_g1_sim_refuses_a_robot),
              cmocka_unit_test(test_g1_sim_silence_latches_link))
