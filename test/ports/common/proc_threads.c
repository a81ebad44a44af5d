/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L
#include "proc_threads.h"

#include <dirent.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

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
