/* SPDX-License-Identifier: Apache-2.0 */
/* The common DDS parameters and the Cyclone configuration built from them:
 * pure functions, no Cyclone call. */
#include "roz/port/dds.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "roz/hal/params.h"

/* ---- public -------------------------------------------------------------- */

int roz_dds_check_interface(const char *name, char *err, size_t errlen)
{
    if (!roz_params_ifname_valid(roz_params_span(name), ROZ_DDS_IFNAME_MAX,
                                 ROZ_PARAMS_IFNAME_PORTABLE)) {
        char what[128];
        roz_params_ifname_expected(what, sizeof what, ROZ_DDS_IFNAME_MAX,
                                   ROZ_PARAMS_IFNAME_PORTABLE);
        snprintf(err, errlen, "parameter network_interface = \"%s\": %s",
                 name != NULL ? name : "", what);
        return ROZ_EINVAL;
    }
    return ROZ_OK;
}

/* The rows the ports' info shows (ROZ_DDS_PARAM_INFO()): the bounds and
 * defaults read here. */
static const roz_port_param_info_t rows[] = { ROZ_DDS_PARAM_INFO("") };
#define ROWS rows, sizeof rows / sizeof rows[0]

int roz_dds_params_parse(roz_dds_params_t *out, const roz_params_t *p, uint32_t default_domain,
                         uint32_t control_rate_hz, char *err, size_t errlen)
{
    const char *iface = roz_params_get_str(p, "network_interface", "lo");
    int rc;

    memset(out, 0, sizeof *out);
    rc = roz_dds_check_interface(iface, err, errlen);
    if (rc != ROZ_OK)
        return rc;
    memcpy(out->network_interface, iface, strlen(iface) + 1);
    if (default_domain > ROZ_DDS_MAX_DOMAIN)
        default_domain = 0;
    rc = roz_params_get_u32(p, "dds_domain", default_domain, 0, ROZ_DDS_MAX_DOMAIN, &out->domain,
                            err, errlen);
    if (rc == ROZ_OK)
        rc = roz_params_get_bool(p, "enable_monitor", 1, &out->enable_monitor, err, errlen);
    if (rc == ROZ_OK) {
        /* the last command on the way out: the robot class's stop (the
         * hold) unless damping is chosen (test_g1_exit_is_the_hold) */
        static const roz_params_word_t words[] = { { "hold", 0 }, { "damping", 1 } };
        rc = roz_params_get_choice(p, "exit_stop", "hold", words, 2,
                                   "hold (the stop's hold at the hold gains, the default) or "
                                   "damping (kp 0, kd shutdown_damping)",
                                   &out->exit_damping, err, errlen);
    }
    if (rc == ROZ_OK)
        rc = roz_params_get_row_u32(p, ROWS, "state_decimation", &out->state_decimation, err,
                                    errlen);
    if (rc != ROZ_OK)
        return rc;
    rc = roz_params_get_u32(p, "command_writer_period_us", 2000, 0, ROZ_DDS_MAX_PERIOD_US,
                            &out->command_writer_period_us, err, errlen);
    if (rc == ROZ_OK && out->command_writer_period_us != 0 &&
        out->command_writer_period_us < ROZ_DDS_MIN_PERIOD_US)
        rc = ROZ_EINVAL;
    if (rc != ROZ_OK) {
        snprintf(err, errlen,
                 "parameter command_writer_period_us = \"%s\": expected 0 (publish as soon as "
                 "the tick writes) or a period in %u..%u us",
                 roz_params_get_str(p, "command_writer_period_us", ""), ROZ_DDS_MIN_PERIOD_US,
                 ROZ_DDS_MAX_PERIOD_US);
        return ROZ_EINVAL;
    }
    rc = roz_params_get_row_u32(p, ROWS, "command_writer_spin_us", &out->command_writer_spin_us,
                                err, errlen);
    if (rc != ROZ_OK)
        return rc;
    if (out->command_writer_spin_us != 0 && out->command_writer_period_us != 0) {
        snprintf(err, errlen,
                 "parameter command_writer_spin_us = \"%s\": only with an event-driven writer "
                 "(command_writer_period_us = 0); this one publishes every %u us",
                 roz_params_get_str(p, "command_writer_spin_us", ""),
                 (unsigned)out->command_writer_period_us);
        return ROZ_EINVAL;
    }
    rc = roz_thread_params(p, "command_writer", &out->writer_thread, err, errlen);
    if (rc == ROZ_OK)
        rc = roz_thread_params(p, "dds_threads", &out->cyclone_threads, err, errlen);
    if (rc == ROZ_OK && out->cyclone_threads.sched == ROZ_THREAD_RR) {
        snprintf(err, errlen, "parameter dds_threads_sched = \"rr\": expected other or fifo "
                              "(Cyclone DDS has no round-robin class)");
        rc = ROZ_EINVAL;
    }
    if (rc != ROZ_OK)
        return rc;
    return roz_cmd_watchdog_param(p, control_rate_hz, out->command_writer_period_us,
                                  &out->command_timeout_us, err, errlen);
}

/* Cyclone knows recv, not the recvUC and recvMC of several receive threads
 * (test_dds_cyclone_threads: it refuses a name it does not know) */
const char *const roz_dds_cyclone_threads[] = { "recv", "dq.user", "tev", NULL };

/* <Threads> for roz_dds_cyclone_threads, as @p t asks; "" when it asks
 * nothing. Returns the length, or < 0. With several receive threads
 * Cyclone puts the data on one named recvUC, which its 0.10 refuses to
 * configure: one receive thread, "recv", takes all traffic instead, so
 * that what is asked reaches the thread that runs the ports' state path
 * (test_dds_cyclone_threads). */
static int threads_xml(const roz_thread_config_t *t, char *out, size_t len)
{
    char sched[96] = "", stack[48] = "";
    size_t at = 0;

    out[0] = '\0';
    if (t == NULL || (t->sched == ROZ_THREAD_OTHER && t->stack_kib == 0))
        return 0;
    if (t->sched == ROZ_THREAD_RR)
        return ROZ_EINVAL;
    if (t->sched == ROZ_THREAD_FIFO)
        snprintf(sched, sizeof sched,
                 "<Scheduling><Class>realtime</Class><Priority>%d</Priority></Scheduling>",
                 t->priority);
    if (t->stack_kib != 0)
        snprintf(stack, sizeof stack, "<StackSize>%lukB</StackSize>",
                 (unsigned long)t->stack_kib);
    int n = snprintf(out, len, "<Threads>");
    for (size_t i = 0; roz_dds_cyclone_threads[i] != NULL && n >= 0 && (size_t)n < len; i++) {
        at = (size_t)n;
        n += snprintf(out + at, len - at, "<Thread Name=\"%s\">%s%s</Thread>",
                      roz_dds_cyclone_threads[i], sched, stack);
    }
    if (n >= 0 && (size_t)n < len)
        n += snprintf(out + n, len - (size_t)n,
                      "</Threads><Internal><MultipleReceiveThreads>false</MultipleReceiveThreads>"
                      "</Internal>");
    return n < 0 || (size_t)n >= len ? ROZ_ENOSPC : n;
}

int roz_dds_config_xml(const char *iface, const roz_thread_config_t *threads, char *out,
                       size_t len)
{
    char err[8], th[ROZ_DDS_CONFIG_MAX];
    int n;

    if (roz_dds_check_interface(iface, err, sizeof err) != ROZ_OK)
        return ROZ_EINVAL;
    n = threads_xml(threads, th, sizeof th);
    if (n < 0)
        return n;
    if (strcmp(iface, "lo") == 0)
        n = snprintf(out, len,
                     "<CycloneDDS><Domain Id=\"any\">"
                     "<General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
                     "<AllowMulticast>false</AllowMulticast></General>"
                     "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
                     "<MaxAutoParticipantIndex>%d</MaxAutoParticipantIndex>"
                     "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>%s"
                     "</Domain></CycloneDDS>",
                     ROZ_DDS_MAX_PARTICIPANT_INDEX, th);
    else
        n = snprintf(out, len,
                     "<CycloneDDS><Domain Id=\"any\">"
                     "<General><Interfaces><NetworkInterface name=\"%s\"/></Interfaces></General>"
                     "%s</Domain></CycloneDDS>",
                     iface, th);
    if (n < 0 || (size_t)n >= len)
        return ROZ_ENOSPC;
    return n;
}

int roz_dds_params_damping(const roz_params_t *p, const roz_manifest_t *m,
                           const roz_joint_channels_t *joint, uint16_t n, double *startup_kd,
                           double *shutdown_kd, const char *rule, roz_params_problem_fn report,
                           void *ctx, char *err, size_t errlen)
{
    double lo, hi;
    int bad = 0;
    (void)roz_joints_damping_range(m, joint, n, &lo, &hi);
    ROZ_PARAMS_STEP(rule, roz_params_get_double(p, "startup_damping",
                                                0.0 >= lo && 0.0 <= hi ? 0.0 : lo, lo, hi,
                                                startup_kd, err, errlen));
    *shutdown_kd = NAN; /* each joint's damping default */
    if (roz_params_find(p, "shutdown_damping") != NULL)
        ROZ_PARAMS_STEP(rule, roz_params_get_double(p, "shutdown_damping", 0.0, lo, hi,
                                                    shutdown_kd, err, errlen));
    return bad ? ROZ_EINVAL : ROZ_OK;
}
