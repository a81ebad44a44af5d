/* SPDX-License-Identifier: Apache-2.0 */
#include "support_blocking_log.h"

#include <pthread.h>
#include <stdatomic.h>
#include <string.h>

static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t cv = PTHREAD_COND_INITIALIZER;
static pthread_t test_thread;
static int armed;
static atomic_uint blocked;
static unsigned lines;
static char kept[64][200];

void roz_test_blocking_log_arm(void)
{
    pthread_mutex_lock(&mu);
    test_thread = pthread_self();
    armed = 1;
    lines = 0;
    atomic_store(&blocked, 0u);
    pthread_mutex_unlock(&mu);
}

void roz_test_blocking_log_release(void)
{
    pthread_mutex_lock(&mu);
    armed = 0;
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

void roz_test_blocking_log(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    (void)level;
    pthread_mutex_lock(&mu);
    if (armed && !pthread_equal(pthread_self(), test_thread)) {
        atomic_fetch_add(&blocked, 1u);
        while (armed)
            pthread_cond_wait(&cv, &mu);
    } else if (lines < 64) {
        strncpy(kept[lines], msg, sizeof kept[0] - 1);
        kept[lines][sizeof kept[0] - 1] = '\0';
        lines++;
    }
    pthread_mutex_unlock(&mu);
}

unsigned roz_test_blocking_log_blocked(void)
{
    return atomic_load(&blocked);
}

unsigned roz_test_blocking_log_lines(void)
{
    pthread_mutex_lock(&mu);
    unsigned n = lines;
    pthread_mutex_unlock(&mu);
    return n;
}

int roz_test_blocking_log_saw(const char *text)
{
    int saw = 0;
    pthread_mutex_lock(&mu);
    for (unsigned i = 0; i < lines && !saw; i++)
        saw = strstr(kept[i], text) != NULL;
    pthread_mutex_unlock(&mu);
    return saw;
}
