/* SPDX-License-Identifier: Apache-2.0 */
/* A native controller's imports for the benches that run one beside its
 * wasm build: roz's ABI functions called directly on native_abi, which the
 * bench initialises and begins each tick on. Include it once per program. */
#ifndef ROZ_BENCH_NATIVE_ABI_H
#define ROZ_BENCH_NATIVE_ABI_H

#include <stddef.h>
#include <stdint.h>

#include "roz/abi.h"

static roz_abi_t native_abi;

int roz_command_set(int i, double v);
int roz_command_count(void);
double roz_command_limit_min(int i);
double roz_command_limit_max(int i);
double roz_state_get(int i);
int roz_state_count(void);
double roz_sin(double x);
double roz_cos(double x);
void roz_request_estop(void);
long long roz_now_ns(void);
long long roz_sim_time_ns(void);
void roz_emit_metric(double v);
int roz_state_get_all(double *v, int n);
int roz_command_set_all(const double *v, int n);

int roz_command_set(int i, double v) { return roz_abi_command_set(&native_abi, i, v); }
int roz_command_count(void) { return roz_abi_command_count(&native_abi); }
double roz_command_limit_min(int i) { return roz_abi_command_limit_min(&native_abi, i); }
double roz_command_limit_max(int i) { return roz_abi_command_limit_max(&native_abi, i); }
double roz_state_get(int i) { return roz_abi_state_get(&native_abi, i); }
int roz_state_count(void) { return roz_abi_state_count(&native_abi); }
double roz_sin(double x) { return roz_abi_math_sin(x); }
double roz_cos(double x) { return roz_abi_math_cos(x); }
void roz_request_estop(void) { roz_abi_safety_request_estop(&native_abi); }
long long roz_now_ns(void) { return roz_abi_timing_now_ns(&native_abi); }
long long roz_sim_time_ns(void) { return roz_abi_timing_sim_time_ns(&native_abi); }
void roz_emit_metric(double v) { roz_abi_telemetry_emit_metric(&native_abi, v); }
/* the bulk extension: natively, the controller's memory is its own array */
int roz_state_get_all(double *v, int n)
{
    return roz_abi_state_get_all(&native_abi, (uint8_t *)v, n > 0 ? (size_t)n * 8u : 0u, 0, n);
}
int roz_command_set_all(const double *v, int n)
{
    return roz_abi_command_set_all(&native_abi, (const uint8_t *)v, n > 0 ? (size_t)n * 8u : 0u,
                                   0, n);
}

#endif /* ROZ_BENCH_NATIVE_ABI_H */
