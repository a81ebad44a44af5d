/* SPDX-License-Identifier: Apache-2.0 */
/* The operator-inputs bench (roz/inputs.h): the inputs of a test's own
 * manifest, a one-wheel robot at 500 Hz, stepped a tick at a time. */
#ifndef ROZ_TEST_SUPPORT_INPUTS_H
#define ROZ_TEST_SUPPORT_INPUTS_H

#include <stdint.h>

#include "roz/inputs.h"

#define ROZ_TEST_INPUTS_RATE_HZ 500u
#define ROZ_TEST_INPUTS_TICK_NS (1000000000ull / ROZ_TEST_INPUTS_RATE_HZ)

/* The robot's one command: a wheel's velocity, no operator field. */
#define ROZ_TEST_WHEEL_VELOCITY                                                           \
    { .name = "wheel/velocity", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = -2.0, \
      .max = 2.0, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED }

typedef struct {
    roz_inputs_t in;
    uint64_t     tick;                     /* the last tick stepped, 0: none */
    double       out[ROZ_CFG_MAX_INPUTS]; /* the inputs the last tick gave */
} roz_test_inputs_t;

/* The inputs of @p m, before their first tick. */
static inline void roz_test_inputs_init(roz_test_inputs_t *b, const roz_manifest_t *m)
{
    roz_inputs_init(&b->in, m);
    b->tick = 0;
}

/* One tick: the next, ROZ_TEST_INPUTS_TICK_NS after the last. */
static inline void roz_test_inputs_step(roz_test_inputs_t *b)
{
    b->tick++;
    roz_inputs_tick(&b->in, b->tick * ROZ_TEST_INPUTS_TICK_NS, b->out);
}

/* A test file's one bench over its manifest @p man: `ib`, step() (one tick)
 * and setup() (a cmocka setup: the inputs before their first tick). */
#define ROZ_TEST_INPUTS_BENCH(man)                 \
    static roz_test_inputs_t ib;                   \
    static void step(void)                         \
    {                                              \
        roz_test_inputs_step(&ib);                 \
    }                                              \
    static int setup(void **st)                    \
    {                                              \
        (void)st;                                  \
        roz_test_inputs_init(&ib, &(man));         \
        return 0;                                  \
    }

#endif /* ROZ_TEST_SUPPORT_INPUTS_H */
