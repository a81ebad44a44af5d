/* SPDX-License-Identifier: Apache-2.0 */
/* The twin controllers of test_rust_controller.c (twin.c in C, twin.rs in
 * Rust, UR5): what they share. Each tick both read every state with the
 * bulk pair's state.get_all, compute the six joint velocities from the
 * states and the control time with every function of the SDK's math and
 * the host's math.sin/math.cos, command them with command.set_all (the
 * first joint often beyond its limits, so the filter clamps), overwrite the
 * last one with command.set, and emit three metrics: set_all's return
 * value, set's, and a sum of the floor, ceil, trunc, fmin and fmax of the
 * time. Both declare their fuel per tick. */
#ifndef ROZ_TEST_TWIN_H
#define ROZ_TEST_TWIN_H

#define TWIN_METRICS 3
#define TWIN_FUEL    200000 /* units a tick: Rust's portable sqrt costs more */

#endif /* ROZ_TEST_TWIN_H */
