/* SPDX-License-Identifier: Apache-2.0 */
#define _GNU_SOURCE /* sched_getaffinity: roz_test_thread_probe() */
#include "proc_threads.h"

#include <dirent.h>
#include <sched.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#include <cmocka.h>

#include "roz/error.h"
#include "roz/hal/thread.h"

void roz_test_proc_threads(long pid, roz_test_thread_fn fn, void *ctx)
{
    char dir[64];
    if (pid == 0)
        snprintf(dir, sizeof dir, "/proc/self/task");
    else
        snprintf(dir, sizeof dir, "/proc/%ld/task", pid);
    DIR *d = opendir(dir);
    struct dirent *e;
    while (d != NULL && (e = readdir(d)) != NULL) {
        char path[96], comm[32] = "";
        struct sched_param sp;
        if (e->d_name[0] == '.')
            continue;
        snprintf(path, sizeof path, "%s/%s/comm", dir, e->d_name);
        FILE *f = fopen(path, "r");
        if (f == NULL)
            continue;
        if (fgets(comm, sizeof comm, f) != NULL)
            comm[strcspn(comm, "\n")] = '\0';
        fclose(f);
        pid_t tid = (pid_t)atoi(e->d_name);
        int policy = sched_getscheduler(tid);
        if (policy < 0 || sched_getparam(tid, &sp) != 0)
            continue; /* gone meanwhile */
        fn(ctx, comm, policy, sp.sched_priority);
    }
    if (d != NULL)
        closedir(d);
}

static void *nothing(void *arg)
{
    return arg;
}

int roz_test_last_cpu(void)
{
    cpu_set_t set;
    int last = 0;
    assert_int_equal(sched_getaffinity(0, sizeof set, &set), 0);
    for (int c = 0; c < ROZ_THREAD_MAX_CPUS; c++)
        if (CPU_ISSET(c, &set))
            last = c;
    return last;
}

int roz_test_thread_probe(int priority, char *cpus, size_t n, int *may_fifo)
{
    roz_thread_config_t fifo = { ROZ_THREAD_FIFO, priority, 0, 0 };
    unsigned long th;
    char err[200];
    int cpu = roz_test_last_cpu();
    snprintf(cpus, n, "%d", cpu);
    *may_fifo = roz_thread_start(&th, &fifo, "probe", nothing, NULL, err, sizeof err) == ROZ_OK;
    if (*may_fifo)
        roz_thread_join(th);
    return cpu;
}
