/* SPDX-License-Identifier: Apache-2.0 */
/* End to end: rozrun drives the fake ROS 2 robot (fake_ros2 publishing
 * every state topic every 2 ms from its own thread) with the robot's stand
 * controller through its port, on loopback DDS:
 *   rozrun --robot engineai_pm01 --port engineai/PM01 --param network_interface=lo
 *          --param dds_domain=D --controller pm01_stand.wasm --ticks 1500
 *   rozrun --robot agibot_x2 --port agibot/X2 ... --controller x2_stand.wasm
 * (rozrun_stand.c). Under TSan (label threads) this is the tick on
 * rozrun's periodic thread, the port's writer thread and Cyclone's threads
 * running every topic's receive path, all at once.
 * Asserted: rozrun exits 0 with no fault latched, the state link taking
 * samples with none malformed; while it runs, the robot receives the
 * stand's commands on every group (a knee's gain reaches the controller's,
 * its target the pose's); after it, every group's last command is the
 * port's exit, the stop's hold (the hold gains, kd the manifest's damping default). The
 * run is recorded (--record) and replayed: rozrun --replay gives the same
 * targets, applied commands and faults bit for bit at each tick. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "fake_ros2_client.h"
#include "rozrun_stand.h"

#ifndef ROZRUN
#error "ROZRUN, CONTROLLER_DIR, OUT_DIR: set by the build"
#endif

typedef struct {
    const char *fake;       /* fake_ros2 --robot */
    const char *robot;      /* manifest */
    const char *port;
    const char *controller; /* in CONTROLLER_DIR */
    const char *knee_group; /* the fake's group of the knee watched */
    int         knee_slot;
    double      knee_kp, knee_q; /* what the stand asks of it */
    double      damping;    /* the manifest's damping default */
    const char *placeholder; /* a slot without a joint of the manifest (kd 0); NULL: none */
} robot_case_t;

/* The knee's largest gain seen, and its target then. */
typedef struct {
    roz_fake_ros2_t     *fake;
    const robot_case_t *rc;
    int                  group;
    double               kp, q;
} knee_t;

static void watch_knee(void *ctx)
{
    knee_t *k = ctx;
    roz_fake_ros2_cmd_t c;
    /* kp 200, the knee's hold gain, is only the exit's hold: not the stand's */
    if (roz_fake_ros2_command(k->fake, (unsigned)k->group, &c) == 1 &&
        c.kp[k->rc->knee_slot] > k->kp && c.kp[k->rc->knee_slot] != 200.0) {
        k->kp = c.kp[k->rc->knee_slot];
        k->q = c.q[k->rc->knee_slot];
    }
}

static void run_stand(const robot_case_t *rc)
{
    static roz_fake_ros2_t fake;
    roz_fake_ros2_cmd_t c;
    char err[256] = "", text[16384], out[4096], controller[4096], rec[4096];
    static const char *const extra[] = { "--period-us", "2000", NULL };

    snprintf(out, sizeof out, "%s/rozrun_%s.txt", OUT_DIR, rc->robot);
    snprintf(rec, sizeof rec, "%s/rozrun_%s.mcap", OUT_DIR, rc->robot);
    snprintf(controller, sizeof controller, "%s/%s", CONTROLLER_DIR, rc->controller);
    if (roz_fake_ros2_start(&fake, rc->fake, ROZ_TEST_DDS_DOMAIN, extra, err, sizeof err) != 0)
        fail_msg("%s", err);
    knee_t knee = { &fake, rc, roz_fake_ros2_group(&fake, rc->knee_group), 0.0, 0.0 };
    assert_true(knee.group >= 0);
    roz_rozrun_stand(ROZRUN, rc->robot, rc->port, controller, ROZ_TEST_DDS_DOMAIN, 1500, out,
                     rec, watch_knee, &knee, text, sizeof text);
    assert_non_null(strstr(text, "faults                 none"));
    char want[128];
    snprintf(want, sizeof want, "port                   %s", rc->port);
    assert_non_null(strstr(text, want));
    unsigned long long taken = 0, malformed = 1;
    const char *link = strstr(text, "state link");
    assert_non_null(link);
    assert_int_equal(sscanf(link, "state link %llu samples taken, no CRC on the wire, %llu "
                                  "malformed",
                            &taken, &malformed),
                     2);
    assert_true(taken > 100);
    assert_int_equal(malformed, 0);

    /* the stand's gains and pose reached the robot */
    assert_true(knee.kp == rc->knee_kp);
    assert_true(knee.q > 0.0 && knee.q <= rc->knee_q + 1e-9);
    uint64_t counts[FAKE_ROS2_MAX_GROUPS];
    assert_int_equal(roz_fake_ros2_commands(&fake, counts), 0);
    for (unsigned g = 0; g < fake.n_groups; g++) {
        assert_true(counts[g] > 500);
        /* the last command of every group: the port's exit, the stop's hold
         * at the hold gains (acknowledged before rozrun exited, it may still
         * be on its way through the fake's own process on a loaded machine:
         * look again a while) */
        for (int ms = 0; ms < 5000; ms += 20) {
            assert_int_equal(roz_fake_ros2_command(&fake, g, &c), 1);
            int held = 1;
            for (unsigned j = 0; j < c.n; j++) {
                int idle = rc->placeholder != NULL &&
                           strcmp(fake.joint[g][j], rc->placeholder) == 0;
                held &= idle || c.kd[j] == rc->damping;
            }
            if (held)
                break;
            roz_fake_sleep_ms(20);
        }
        assert_int_equal(c.min_len, fake.n_joints[g]);
        for (unsigned j = 0; j < c.n; j++) {
            int idle = rc->placeholder != NULL && strcmp(fake.joint[g][j], rc->placeholder) == 0;
            assert_true(c.tau[j] == 0.0 && c.dq[j] == 0.0);
            assert_true(idle ? c.kp[j] == 0.0 : c.kp[j] > 0.0);
            assert_true(c.kd[j] == (idle ? 0.0 : rc->damping));
        }
    }
    assert_int_equal(roz_fake_ros2_stop(&fake), 0);

    /* the run was recorded; it replays bit for bit, without the robot */
    char want_rec[4200];
    snprintf(want_rec, sizeof want_rec, "recording              %s (1500 ticks, none dropped)", rec);
    assert_non_null(strstr(text, want_rec));
    snprintf(out, sizeof out, "%s/rozrun_%s.replay.txt", OUT_DIR, rc->robot);
    roz_rozrun_replay(ROZRUN, rec, controller, 1500, out, text, sizeof text);
}

static void test_rozrun_pm01_stand(void **st)
{
    static const robot_case_t pm01 = { "pm01", "engineai_pm01", "engineai/PM01",
                                       "pm01_stand.wasm", "body", 3, 70.0, 0.48, 5.0, NULL };
    (void)st;
    run_stand(&pm01);
}

#ifdef ROZ_TEST_HAVE_AGIBOT_X2
static void test_rozrun_x2_stand(void **st)
{
    /* the head's second slot is a placeholder: no joint of the manifest */
    static const robot_case_t x2 = { "x2", "agibot_x2", "agibot/X2", "x2_stand.wasm", "leg", 3,
                                     150.0, 0.6, 4.0, "head_pitch_joint" };
    (void)st;
    run_stand(&x2);
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rozrun_pm01_stand),
#ifdef ROZ_TEST_HAVE_AGIBOT_X2
        cmocka_unit_test(test_rozrun_x2_stand),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
