/* SPDX-License-Identifier: Apache-2.0 */
/* Helpers shared by the C tests. */
#ifndef ROZ_TEST_SUPPORT_H
#define ROZ_TEST_SUPPORT_H

#include <stddef.h>
#include <stdint.h>

/* Reads ROZ_CONTROLLER_DIR/<name>.wasm into static storage (one of 8
 * rotating buffers, so a few modules can be live at once); fails the test
 * when missing. Sets *len. */
const uint8_t *roz_test_controller(const char *name, size_t *len);

/* Reads <dir>/<name>.wasm the same way, for the controllers a test builds
 * beside itself; fails the test when missing, empty or too large. */
const uint8_t *roz_test_wasm(const char *dir, const char *name, size_t *len);

/* The wasm file at @p path, the same way. */
const uint8_t *roz_test_wasm_file(const char *path, size_t *len);

/* roz_test_wasm(), but NULL (the test going on) when the file is missing. */
const uint8_t *roz_test_wasm_or_null(const char *dir, const char *name, size_t *len);

/* A test clock: returns the current value and advances by `step` ns per call
 * (ctx is a roz_test_clock_t*). */
typedef struct {
    uint64_t now;
    uint64_t step;
} roz_test_clock_t;
uint64_t roz_test_clock(void *ctx);

/* The next number of the xorshift64* sequence in *@p state (never 0): the
 * pseudo-random inputs of property tests, the same from the same seed. */
static inline uint64_t roz_test_rng(uint64_t *state)
{
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    return *state * 2685821657736338717ull;
}

/* Uniform in [@p lo, @p hi), from roz_test_rng(@p state). */
static inline double roz_test_uniform(uint64_t *state, double lo, double hi)
{
    return lo + (hi - lo) * ((double)(roz_test_rng(state) >> 11) / 9007199254740992.0);
}

/* |a - b| <= eps, with both values in the failure message (cmocka 1.1.5,
 * Debian 12's, has no assert_double_equal). Needs <cmocka.h> and <math.h>. */
#define assert_near(a, b, eps)                                                        \
    do {                                                                              \
        double roz_a_ = (a), roz_b_ = (b);                                            \
        if (!(fabs(roz_a_ - roz_b_) <= (eps)))                                        \
            fail_msg("%s = %.17g, expected %.17g (+-%g)", #a, roz_a_, roz_b_, (double)(eps)); \
    } while (0)

/* Until @p cond, doing @p step between two looks (a 1 ms sleep; a tick,
 * then a sleep), at most @p n times: a hang guard, past which the test
 * fails naming the condition and where it waited. @p cond is evaluated
 * once a look (it may be a read that takes what it sees). Never a time
 * asserted. */
#define ROZ_TEST_WAIT(cond, step, n)                                                  \
    do {                                                                              \
        unsigned long roz_w_ = 0;                                                     \
        int roz_met_;                                                                 \
        while (!(roz_met_ = (cond) != 0) && roz_w_ < (unsigned long)(n)) {            \
            step;                                                                     \
            roz_w_++;                                                                 \
        }                                                                             \
        if (!roz_met_)                                                                \
            fail_msg("%s:%d: waited %lu times for %s", __FILE__, __LINE__,           \
                     (unsigned long)(n), #cond);                                      \
    } while (0)

/* main() for a test file: runs the cmocka_unit_test() entries given, one
 * group. Needs <cmocka.h>. */
#define ROZ_TEST_MAIN(...)                                                            \
    int main(void)                                                                    \
    {                                                                                 \
        const struct CMUnitTest tests[] = { __VA_ARGS__ };                            \
        return cmocka_run_group_tests(tests, NULL, NULL);                             \
    }

#endif /* ROZ_TEST_SUPPORT_H */
