/* SPDX-License-Identifier: Apache-2.0 */
/* Two compiled controllers run on two threads at once, as a runtime runs
 * one on its tick thread while its loader thread verifies another: each
 * thread's traps land in its own call (the engine's trap target and call
 * depth are per thread), and each trap reads right. One thread recurses
 * until the call depth traps, the other traps on unreachable, on every
 * other call. Run under TSan in the sanitizer build (label threads). */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/aot.h"
#include "roz/builtin.h"
#include "roz/controller.h"
#include "support.h"

ROZ_AOT_DECLARE(hostile_recursion);
ROZ_AOT_DECLARE(hostile_trap_run);

enum { CALLS = 20000 };

static pthread_barrier_t go; /* both threads start together */

typedef struct {
    const roz_aot_module_t *m;
    const char             *trap; /* what tick 150 traps with */
    roz_controller_t        c;
    roz_abi_t               abi;
    double                  target[ROZ_CFG_MAX_COMMANDS];
    double                  state[ROZ_CFG_MAX_STATES];
    int                     wrong; /* calls that did not end as they should */
} worker_t;

static void *work(void *arg)
{
    worker_t *w = arg;
    pthread_barrier_wait(&go);
    for (int i = 0; i < CALLS; i++) {
        int64_t tick = (i & 1) ? 150 : 149;
        roz_abi_begin_tick(&w->abi, tick, w->state);
        int rc = roz_controller_process(&w->c, tick);
        if (tick == 149)
            w->wrong += rc != ROZ_OK;
        else
            w->wrong += rc != ROZ_ETRAP || strstr(roz_controller_error(&w->c), w->trap) == NULL;
    }
    return NULL;
}

static void test_aot_threads_traps_stay_on_their_thread(void **state)
{
    (void)state;
    const roz_manifest_t *m = roz_builtin_find("ur5");
    static worker_t w[2] = {
        { .m = &roz_aot_hostile_recursion, .trap = "[trap] stack overflow" },
        { .m = &roz_aot_hostile_trap_run, .trap = "[trap] unreachable executed" },
    };
    pthread_t th[2];
    assert_int_equal(pthread_barrier_init(&go, NULL, 2), 0);
    for (int k = 0; k < 2; k++) {
        roz_abi_init(&w[k].abi, m, w[k].target, NULL);
        roz_controller_init(&w[k].c);
        assert_int_equal(roz_controller_load_aot(&w[k].c, w[k].m, &w[k].abi), ROZ_OK);
    }
    for (int k = 0; k < 2; k++)
        assert_int_equal(pthread_create(&th[k], NULL, work, &w[k]), 0);
    for (int k = 0; k < 2; k++)
        assert_int_equal(pthread_join(th[k], NULL), 0);
    pthread_barrier_destroy(&go);
    for (int k = 0; k < 2; k++) {
        assert_int_equal(w[k].wrong, 0);
        roz_controller_unload(&w[k].c);
    }
}

ROZ_TEST_MAIN(cmocka_unit_test(test_aot_threads_traps_stay_on_their_thread))
