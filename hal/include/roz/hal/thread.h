/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/hal/thread.h
 * @brief How a thread roz creates is scheduled: policy, priority, CPU
 *        affinity and stack size, from a port's parameters (one prefix per
 *        thread: `command_writer_sched`, `..._priority`, `..._cpus`,
 *        `..._stack_kib`), applied when the thread is created and read back
 *        from the running thread.
 *
 * A thread asked for SCHED_FIFO or SCHED_RR that the process may not have
 * is not created: the start fails naming the parameter (it never runs at
 * another priority than the one asked for without saying so).
 */
#ifndef ROZ_HAL_THREAD_H
#define ROZ_HAL_THREAD_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/port.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Scheduling policy. */
typedef enum roz_thread_sched {
    ROZ_THREAD_OTHER = 0, /**< the system's normal scheduling (default) */
    ROZ_THREAD_FIFO,      /**< SCHED_FIFO at @c priority */
    ROZ_THREAD_RR,        /**< SCHED_RR at @c priority */
} roz_thread_sched_t;

/** Highest CPU an affinity names (a 64-bit mask). */
#define ROZ_THREAD_MAX_CPUS 64

/**
 * The least stack, KiB, a thread roz creates may ask for (every
 * `..._stack_kib` parameter, the runner's stack_kib): 64, or the C
 * library's least where that is more. glibc on aarch64 refuses a stack
 * under 128 KiB (its PTHREAD_STACK_MIN, which holds with the 64 KiB pages
 * some aarch64 kernels use); on x86-64 its least is 16 KiB. The most is
 * ROZ_THREAD_STACK_MAX_KIB. roz_thread_start() checks against the C
 * library's own least too, for a target this does not know.
 */
#if defined(__aarch64__) && defined(__linux__)
#define ROZ_THREAD_STACK_MIN_KIB 128
#else
#define ROZ_THREAD_STACK_MIN_KIB 64
#endif
/** The most stack, KiB, a thread roz creates may ask for (64 MiB). */
#define ROZ_THREAD_STACK_MAX_KIB 65536
/** "MIN..MAX", the range's words in the parameters' help. */
#define ROZ_THREAD_STACK_RANGE ROZ_THREAD_STR_(ROZ_THREAD_STACK_MIN_KIB) ".." \
                               ROZ_THREAD_STR_(ROZ_THREAD_STACK_MAX_KIB)
#define ROZ_THREAD_STR_(x) ROZ_THREAD_STR2_(x)
#define ROZ_THREAD_STR2_(x) #x

/** What a thread gets; all zero: the system's defaults. */
typedef struct roz_thread_config {
    roz_thread_sched_t sched;
    int                priority;  /**< 1..99 with FIFO or RR; 0 with OTHER */
    uint64_t           cpus;      /**< bit i: may run on CPU i; 0: any CPU */
    uint32_t           stack_kib; /**< 0: the system's default; else
                                       ROZ_THREAD_STACK_MIN_KIB..ROZ_THREAD_STACK_MAX_KIB */
} roz_thread_config_t;

/** The parameter rows of one thread (roz_port_info_t::params), keys
 *  PREFIX_sched, PREFIX_priority, PREFIX_cpus, PREFIX_stack_kib; @p what:
 *  the thread, for the help text. */
#define ROZ_THREAD_PARAM_INFO(prefix, what)                                                 \
    ROZ_PORT_PARAM_TEXT_ROW(prefix "_sched", "other|fifo|rr", "other",                      \
                            "scheduling policy of " what),                                  \
    ROZ_PORT_PARAM_TEXT_ROW(prefix "_priority", "1..99", "", "its priority with fifo or rr"), \
    ROZ_PORT_PARAM_TEXT_ROW(prefix "_cpus", "a list: 0,2-3", "",                            \
                            "the CPUs it may run on (default: any)"),                       \
    ROZ_PORT_PARAM_TEXT_ROW(prefix "_stack_kib", ROZ_THREAD_STACK_RANGE, "",                  \
                            "its stack size (default: the system's)")

/** The keys of ROZ_THREAD_PARAM_INFO, for a port's list of known keys. */
#define ROZ_THREAD_PARAM_KEYS(prefix)                                                        \
    prefix "_sched", prefix "_priority", prefix "_cpus", prefix "_stack_kib"

/**
 * @brief Read one thread's parameters (keys @p prefix_sched, ...); each
 *        absent key keeps @p out's value (start from zero or a default).
 * @retval ROZ_OK
 * @retval ROZ_EINVAL a bad value; @p err names the key and says what it takes
 * Context: a port's open(); not the tick.
 */
int roz_thread_params(const roz_params_t *p, const char *prefix, roz_thread_config_t *out,
                      char *err, size_t errlen);

/**
 * @brief Create a thread that runs @p fn(@p arg) as @p cfg says.
 * @param[out] handle the thread (a pthread_t), for roz_thread_join()
 * @param[in]  prefix the parameters' prefix, for the error message; also the
 *                    thread's name (its first 15 bytes: ps -L, top -H)
 * @retval ROZ_OK     running, as asked
 * @retval ROZ_EINVAL a configuration the system refuses (a CPU it has not)
 * @retval ROZ_EIO    not created (not permitted: SCHED_FIFO without the
 *                    privilege); @p err names @p prefix and the reason
 * Context: start-up.
 */
int roz_thread_start(unsigned long *handle, const roz_thread_config_t *cfg, const char *prefix,
                     void *(*fn)(void *), void *arg, char *err, size_t errlen);

/** @brief Wait for a thread roz_thread_start() created. Context: shut-down. */
void roz_thread_join(unsigned long handle);

/**
 * @brief What a running thread carries: its policy and priority, its
 *        affinity (CPUs 0..63) and its stack size in KiB.
 * @retval ROZ_OK, ROZ_EIO (the system would not say)
 * Context: any thread.
 */
int roz_thread_describe(unsigned long handle, roz_thread_config_t *out);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_HAL_THREAD_H */
