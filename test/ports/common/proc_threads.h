/* SPDX-License-Identifier: Apache-2.0 */
/* A process's threads as Linux shows them in /proc: each one's name (the
 * first 15 bytes, roz_thread_start() names roz's), scheduling policy and
 * priority, read back from the running thread (test_dds_cyclone_threads,
 * test_rozrun_g1_realtime). */
#ifndef ROZ_TEST_PROC_THREADS_H
#define ROZ_TEST_PROC_THREADS_H

#include <stddef.h>

typedef void (*roz_test_thread_fn)(void *ctx, const char *name, int policy, int priority);

/* Calls @p fn for every thread of process @p pid (0: this one) that is
 * still there when it is read. */
void roz_test_proc_threads(long pid, roz_test_thread_fn fn, void *ctx);

/* The last CPU this process may run on (its affinity). */
int roz_test_last_cpu(void);

/* What this process may ask of a thread here: roz_test_last_cpu()
 * (returned, and as text in @p cpus of @p n bytes) and, in @p may_fifo,
 * whether a thread of SCHED_FIFO priority @p priority starts. */
int roz_test_thread_probe(int priority, char *cpus, size_t n, int *may_fifo);

#endif /* ROZ_TEST_PROC_THREADS_H */
