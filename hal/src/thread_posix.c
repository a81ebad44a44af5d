/* SPDX-License-Identifier: Apache-2.0 */
/* Threads as roz/hal/thread.h configures them, on POSIX threads (the
 * affinity calls are Linux's, glibc and musl). */
#define _GNU_SOURCE
#include "roz/hal/thread.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <string.h>
#include <unistd.h>

#include "roz/error.h"
#include "roz/format.h"

_Static_assert(sizeof(pthread_t) <= sizeof(unsigned long), "pthread_t must fit the handle");

/* ---- public -------------------------------------------------------------- */

int roz_thread_start(unsigned long *handle, const roz_thread_config_t *cfg, const char *prefix,
                     void *(*fn)(void *), void *arg, char *err, size_t errlen)
{
    static const roz_thread_config_t none = { ROZ_THREAD_OTHER, 0, 0, 0 };
    pthread_attr_t attr;
    pthread_t th;
    int rc;

    if (cfg == NULL)
        cfg = &none;
    if (pthread_attr_init(&attr) != 0) {
        roz_format(err, errlen, "%s: no thread attributes", prefix);
        return ROZ_EIO;
    }
    rc = 0;
    if (cfg->sched != ROZ_THREAD_OTHER) {
        struct sched_param sp = { .sched_priority = cfg->priority };
        rc = pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED);
        if (rc == 0)
            rc = pthread_attr_setschedpolicy(&attr,
                                             cfg->sched == ROZ_THREAD_FIFO ? SCHED_FIFO : SCHED_RR);
        if (rc == 0)
            rc = pthread_attr_setschedparam(&attr, &sp);
    }
    if (rc == 0 && cfg->cpus != 0) {
        cpu_set_t set;
        CPU_ZERO(&set);
        for (int c = 0; c < ROZ_THREAD_MAX_CPUS; c++)
            if (cfg->cpus & (1ull << c))
                CPU_SET(c, &set);
        rc = pthread_attr_setaffinity_np(&attr, sizeof set, &set);
    }
    if (rc == 0 && cfg->stack_kib != 0) {
        /* at least ROZ_THREAD_STACK_MIN_KIB (roz_thread_params()), which
         * covers the C libraries roz knows; another's least is named */
        long least = sysconf(_SC_THREAD_STACK_MIN);
        if (least > 0 && (size_t)cfg->stack_kib * 1024u < (size_t)least) {
            pthread_attr_destroy(&attr);
            roz_format(err, errlen, "%s_stack_kib = %lu: under this system's least thread stack "
                       "(%ld KiB)", prefix, (unsigned long)cfg->stack_kib, (least + 1023) / 1024);
            return ROZ_EINVAL;
        }
        rc = pthread_attr_setstacksize(&attr, (size_t)cfg->stack_kib * 1024u);
    }
    if (rc != 0) {
        pthread_attr_destroy(&attr);
        roz_format(err, errlen, "%s: the thread's attributes are refused: %s", prefix, strerror(rc));
        return ROZ_EINVAL;
    }
    rc = pthread_create(&th, &attr, fn, arg);
    pthread_attr_destroy(&attr);
    if (rc != 0) {
        roz_format(err, errlen, "%s: thread not created: %s%s", prefix, strerror(rc),
                 rc == EPERM ? " (fifo and rr need CAP_SYS_NICE or an RLIMIT_RTPRIO)"
                 : rc == EINVAL && cfg->cpus != 0 ? " (a CPU the system does not offer?)"
                 : "");
        return rc == EINVAL ? ROZ_EINVAL : ROZ_EIO;
    }
    /* named for ps -L, top -H and the tests that find it in /proc
     * (test_rozrun_g1_realtime): the prefix, cut to Linux's 15 bytes */
    char name[16];
    size_t n = strlen(prefix);
    n = n < sizeof name - 1u ? n : sizeof name - 1u;
    memcpy(name, prefix, n);
    name[n] = '\0';
    (void)pthread_setname_np(th, name);
    *handle = (unsigned long)th;
    return ROZ_OK;
}

void roz_thread_join(unsigned long handle)
{
    pthread_join((pthread_t)handle, NULL);
}

int roz_thread_describe(unsigned long handle, roz_thread_config_t *out)
{
    pthread_t th = (pthread_t)handle;
    struct sched_param sp;
    pthread_attr_t attr;
    cpu_set_t set;
    size_t stack = 0;
    int policy;

    memset(out, 0, sizeof *out);
    if (pthread_getschedparam(th, &policy, &sp) != 0 ||
        pthread_getaffinity_np(th, sizeof set, &set) != 0 || pthread_getattr_np(th, &attr) != 0)
        return ROZ_EIO;
    (void)pthread_attr_getstacksize(&attr, &stack);
    pthread_attr_destroy(&attr);
    out->sched = policy == SCHED_FIFO ? ROZ_THREAD_FIFO
               : policy == SCHED_RR   ? ROZ_THREAD_RR
                                      : ROZ_THREAD_OTHER;
    out->priority = out->sched != ROZ_THREAD_OTHER ? sp.sched_priority : 0;
    for (int c = 0; c < ROZ_THREAD_MAX_CPUS; c++)
        if (CPU_ISSET(c, &set))
            out->cpus |= 1ull << c;
    out->stack_kib = (uint32_t)(stack / 1024u);
    return ROZ_OK;
}
