/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz_controller.h
 * @brief The roz controller ABI for controllers written in C.
 *
 * Compile for WebAssembly with clang:
 *   clang --target=wasm32 -O2 -nostdlib -Wl,--no-entry -Wl,-z,stack-size=16384 \
 *       -o ctl.wasm ctl.c
 * (the stack as roz_add_wasm_controller() sets it; Rust: docs/rust.md)
 * and export the entry point with ROZ_PROCESS:
 *   ROZ_PROCESS(tick) { roz_command_set(0, 0.1); }
 *
 * Channel indices come from the manifest's generated header
 * (<robot_id>_channels.h, freestanding), e.g. ROZ_UR5_CMD_ELBOW_JOINT_VELOCITY.
 *
 * The robot a controller is built for: compiled for wasm32, that header
 * also puts the robot's identity (robot_id and the hash of its channel
 * table, ROZ_<ID>_ROBOT_ID and ROZ_<ID>_INTERFACE_HASH) into the module's
 * custom section "roz.manifest". roz then refuses to load the controller on
 * another robot, or on this one once its channel table has changed, unless
 * told otherwise (rozrun --allow-other-robot; the runtime configuration's
 * allow_foreign_controller). Nothing to call: including the header is
 * enough. A controller that includes no channel header (one that works from
 * command.count and the limits alone, like examples/controllers/sine.c)
 * carries no identity and loads on any robot; so does one that defines
 * ROZ_NO_ROBOT_IDENTITY before including a channel header. To see it:
 *   wasm-objdump -x -j roz.manifest ctl.wasm
 *
 * Built natively (not for wasm32), the same source calls plain C functions
 * of these names, which a host program provides; the benchmark uses this to
 * run one controller both ways.
 */
#ifndef ROZ_CONTROLLER_SDK_H
#define ROZ_CONTROLLER_SDK_H

#ifdef __wasm__
#define ROZ_IMPORT(module, name) __attribute__((import_module(module), import_name(name)))
#define ROZ_PROCESS(tick) __attribute__((export_name("process"))) void process(long long tick)
#else
#define ROZ_IMPORT(module, name)
#define ROZ_PROCESS(tick) void roz_native_process(long long tick)
void roz_native_process(long long tick);
#endif

#ifdef __cplusplus
extern "C" {
#endif

/** Return codes of roz_command_set(). */
#define ROZ_SET_TAKEN    0
#define ROZ_SET_CLAMPED  1
#define ROZ_SET_REFUSED (-1)

/** Write command channel @p index; 0 taken, 1 clamped, -1 refused. */
ROZ_IMPORT("command", "set") int roz_command_set(int index, double value);
/** Number of command channels. */
ROZ_IMPORT("command", "count") int roz_command_count(void);
/** Limits of a command channel; NaN for a bad index. */
ROZ_IMPORT("command", "limit_min") double roz_command_limit_min(int index);
ROZ_IMPORT("command", "limit_max") double roz_command_limit_max(int index);
/** Value of state channel @p index in this tick's snapshot; NaN for a bad index. */
ROZ_IMPORT("state", "get") double roz_state_get(int index);
/** Number of state channels. */
ROZ_IMPORT("state", "count") int roz_state_count(void);
/** Trigonometry (WebAssembly has none). */
ROZ_IMPORT("math", "sin") double roz_sin(double x);
ROZ_IMPORT("math", "cos") double roz_cos(double x);
/** Ask for an emergency stop. */
ROZ_IMPORT("safety", "request_estop") void roz_request_estop(void);
/** Wall-clock nanoseconds. */
ROZ_IMPORT("timing", "now_ns") long long roz_now_ns(void);
/** Control time: tick * period, in nanoseconds. */
ROZ_IMPORT("timing", "sim_time_ns") long long roz_sim_time_ns(void);
/** Record a scalar for observability. */
ROZ_IMPORT("telemetry", "emit_metric") void roz_emit_metric(double value);

/*
 * The bulk extension (optional): one host call each way per tick instead of
 * one per channel, for controllers that read or write many channels (a
 * humanoid's 145 commands). Same results bit for bit as the calls above:
 *   double s[ROZ_UNITREE_G1_N_STATES], c[ROZ_UNITREE_G1_N_COMMANDS];
 *   roz_state_get_all(s, ROZ_UNITREE_G1_N_STATES);
 *   ... fill every c[i] ...
 *   roz_command_set_all(c, ROZ_UNITREE_G1_N_COMMANDS);
 */
/** Copy state channels 0..count-1 of this tick's snapshot into @p values;
 *  returns count, or -1 (nothing copied) for a count outside 0..state
 *  count or an array outside the controller's memory. */
ROZ_IMPORT("state", "get_all") int roz_state_get_all(double *values, int count);
/** Set command channels 0..count-1 from @p values, each exactly as
 *  roz_command_set(i, values[i]) would (clamp, refusal of NaN/Inf, the
 *  counters); returns how many were clamped or refused, or -1 (no channel
 *  changed) for a count outside 0..command count or an array outside the
 *  controller's memory. Channels from count on keep their values. */
ROZ_IMPORT("command", "set_all") int roz_command_set_all(const double *values, int count);

/*
 * The fuel a heavy controller needs per tick (a learned policy's inference
 * tick), in work units: roz runs it, and verifies it, under that budget
 * instead of the runtime's default, up to the most the runtime allows
 * (roz/runtime.h, fuel_per_tick_max; a declaration above it is refused at
 * load). Once, in one file, at file scope, with a plain integer:
 *   ROZ_FUEL_PER_TICK(60000);
 * It lands in the module's custom section "roz.fuel". Natively it is
 * nothing.
 */
#define ROZ__STR(x) #x
#define ROZ__XSTR(x) ROZ__STR(x)
#ifdef __wasm__
#define ROZ_FUEL_PER_TICK(units)                                                           \
    __asm__(".section .custom_section.roz.fuel,\"\",@\n.int8 1\n.int64 " ROZ__XSTR(units) \
            "\n.text")
#else
#define ROZ_FUEL_PER_TICK(units) typedef char roz__fuel_per_tick_declared
#endif

#ifdef __cplusplus
}
#endif

#endif /* ROZ_CONTROLLER_SDK_H */
