/* SPDX-License-Identifier: Apache-2.0 */
/* rozrun end to end against a fake robot (test_rozrun_g1.c,
 * test_rozrun_ros2.c): one run of a stand controller through a hardware
 * port on loopback DDS,
 *   rozrun --robot R --port P --param network_interface=lo
 *          --param dds_domain=D --param peer_timeout_ms=5000
 *          --controller C --ticks N --budget-us off --stale-ticks 250
 * (deadline off, 0.5 s to stale, 5 s before a silent robot counts as lost:
 * a loaded machine, or TSan, must not fail the run on time; at a load of 8
 * to 11 on two cores, runs latched STALE after 100 ms and LINK after a fake
 * starved for half a second), its output to a file. */
#ifndef ROZ_TEST_ROZRUN_STAND_H
#define ROZ_TEST_ROZRUN_STAND_H

#include <stddef.h>
#include <stdint.h>

/* Runs rozrun (path @p rozrun) as above, its stdout and stderr to @p out,
 * with --record @p record unless it is NULL; calls @p watch(@p ctx) every
 * 20 ms while it runs (a hang guard of 60 s fails the test). Then @p text
 * holds its output (printed), and the test has failed unless it exited 0. */
void roz_rozrun_stand(const char *rozrun, const char *robot, const char *port,
                      const char *controller, uint32_t domain, int ticks, const char *out,
                      const char *record, void (*watch)(void *ctx), void *ctx, char *text,
                      size_t len);

/* Runs @p argv (argv[0] the program, NULL-terminated) as
 * roz_rozrun_stand() runs rozrun: output to @p out and @p text (printed),
 * @p watch (may be NULL) every 20 ms, a hang guard of 60 s. Returns its
 * exit status; the test has failed if it was killed. */
int roz_rozrun_spawn(const char *const *argv, const char *out, void (*watch)(void *ctx),
                     void *ctx, char *text, size_t len);

/* The process roz_rozrun_spawn() runs, for its @p watch (its threads are in
 * /proc/PID/task); 0 when it runs none. */
long roz_rozrun_pid(void);

/* rozrun --replay @p recording --controller @p controller, its output to
 * @p out and @p text (printed); the test has failed unless it exited 0
 * having replayed @p ticks ticks identically. */
void roz_rozrun_replay(const char *rozrun, const char *recording, const char *controller,
                       int ticks, const char *out, char *text, size_t len);

#endif /* ROZ_TEST_ROZRUN_STAND_H */
