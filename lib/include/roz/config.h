/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/config.h
 * @brief Compile-time configuration of roz, with documented defaults.
 *
 * Every roz header includes this file first. An application overrides any
 * option by defining ROZ_CONFIG_FILE (a quoted header name, e.g.
 * -DROZ_CONFIG_FILE='"my_roz_config.h"') whose file defines the options it
 * wants; everything it leaves out takes the default below. Options are always
 * defined and tested with #if, so a build with -Wundef catches typos.
 */
#ifndef ROZ_CONFIG_H
#define ROZ_CONFIG_H

#if defined(ROZ_CONFIG_FILE)
#include ROZ_CONFIG_FILE
#endif

#include "roz/features.h"

/** Command channels per manifest. Range 1..4096. A humanoid needs ~150. */
#ifndef ROZ_CFG_MAX_COMMANDS
#define ROZ_CFG_MAX_COMMANDS 256
#endif

/** State channels per manifest. Range 0..4096. A humanoid needs ~100. */
#ifndef ROZ_CFG_MAX_STATES
#define ROZ_CFG_MAX_STATES 256
#endif

/** Operator inputs per manifest ([[manifest.inputs]]; they also count, with
 *  the states, against ROZ_CFG_MAX_STATES). Range 0..4096. Each costs a
 *  runtime about 48 bytes (roz/inputs.h). */
#ifndef ROZ_CFG_MAX_INPUTS
#define ROZ_CFG_MAX_INPUTS 32
#endif

/** Bytes of name storage in a roz_manifest_storage_t (channel names, units,
 *  ids of manifests built at run time). Range 64..1048576. */
#ifndef ROZ_CFG_NAME_ARENA_BYTES
#define ROZ_CFG_NAME_ARENA_BYTES 16384
#endif

/** Longest channel name in bytes, without the terminating NUL. Range 8..255. */
#ifndef ROZ_CFG_MAX_NAME_LEN
#define ROZ_CFG_MAX_NAME_LEN 63
#endif

/** Joints of a [hardware] table that a roz_manifest_storage_t holds (a
 *  robot.toml read at run time, roz/manifest_toml.h). Range 0..4096. The
 *  built-in humanoids have 24..30. */
#ifndef ROZ_CFG_MAX_JOINTS
#define ROZ_CFG_MAX_JOINTS 64
#endif

/** [hardware.params] entries that a roz_manifest_storage_t holds.
 *  Range 0..1024. */
#ifndef ROZ_CFG_MAX_PARAMS
#define ROZ_CFG_MAX_PARAMS 32
#endif

/** Bytes of one problem message of the robot.toml loader
 *  (roz/manifest_toml.h), NUL included; longer messages end in "...".
 *  Range 64..65536. */
#ifndef ROZ_CFG_PROBLEM_LEN
#define ROZ_CFG_PROBLEM_LEN 384
#endif

/** wasm3 value stack per controller instance, bytes. Range 4096..16777216. */
#ifndef ROZ_CFG_WASM_STACK_BYTES
#define ROZ_CFG_WASM_STACK_BYTES 65536
#endif

/** Native (C) stack a controller's process() call may use, bytes, measured
 *  from where roz calls into the engine. wasm3 nests a C frame for every
 *  wasm call and every loop it enters, so a deep or endless recursion needs
 *  stack in proportion to its depth; roz checks the depth at every function
 *  and loop entry and traps past this limit, at most one frame late. Leave
 *  headroom below the thread's real stack for the host functions and the
 *  runtime (size the task stack to this plus 16 KiB). Range
 *  4096..67108864. */
#ifndef ROZ_CFG_NATIVE_STACK_BYTES
#define ROZ_CFG_NATIVE_STACK_BYTES 262144
#endif

/** Ahead-of-time controllers (roz/aot.h): instances of one compiled
 *  controller that may exist at once, each with static storage for its
 *  linear memory in the image (a runtime needs 2: the one driving the
 *  robot and the one a swap verifies). Range 1..16. */
#ifndef ROZ_CFG_AOT_INSTANCES
#define ROZ_CFG_AOT_INSTANCES 2
#endif

/** Ahead-of-time controllers: wasm calls nested at most (wasm2c's
 *  WASM_RT_MAX_CALL_STACK_DEPTH; a deeper call traps "[trap] stack
 *  overflow"). Each level is one C frame of the compiled function: size the
 *  task stack for it. Range 8..100000. */
#ifndef ROZ_CFG_AOT_CALL_DEPTH
#define ROZ_CFG_AOT_CALL_DEPTH 500
#endif

/** Ahead-of-time controllers: distinct function types the compiled
 *  controllers loaded at once register together (call_indirect checks
 *  them); about 28 bytes of static memory each. Range 8..2048. */
#ifndef ROZ_CFG_AOT_MAX_TYPES
#define ROZ_CFG_AOT_MAX_TYPES 128
#endif

/** Largest linear memory a controller may declare, in 64 KiB pages.
 *  Range 1..65536. Memory never grows after load (growing would allocate
 *  inside the tick): memory.grow returns -1. */
#ifndef ROZ_CFG_WASM_MAX_PAGES
#define ROZ_CFG_WASM_MAX_PAGES 16
#endif

/** Largest table a controller may declare, in entries (function
 *  references), and the highest entry its element segments may fill.
 *  Range 0..100000 (wasm3's own ceiling). wasm3 ignores the declared size
 *  and allocates the table from the element segments, 8 bytes per entry on
 *  64-bit hosts; roz checks both at load. */
#ifndef ROZ_CFG_WASM_MAX_TABLE_ENTRIES
#define ROZ_CFG_WASM_MAX_TABLE_ENTRIES 4096
#endif

/** Deepest nesting of blocks (block, loop, if) in a controller function,
 *  counting the outermost block as 1. Range 1..255. wasm3 compiles nested
 *  blocks recursively on the C stack of the thread that loads (about 200
 *  bytes a level, 272 for if/else, in the normal build; about 1 KiB under
 *  ASan), so this bounds the stack roz_controller_load() needs. With the
 *  default, loading any accepted module needs at most about 28 KiB of C
 *  stack below the caller's frame (about 101 KiB under ASan): it fits a
 *  64 KiB thread (256 KiB under ASan). roz_controller_load() puts the
 *  validator's scratch (ROZ_CONTROLLER_SCRATCH_BYTES, about 22 KiB) on the
 *  same stack, but only while it validates, before the engine compiles; a
 *  firmware passes static storage instead (roz_controller_load_in(),
 *  roz_runtime_config_t.load_scratch). A C switch of N cases compiles to
 *  N + 1 nested blocks. Deeper nesting is refused with a message naming
 *  this option. */
#ifndef ROZ_CFG_WASM_MAX_BLOCK_DEPTH
#define ROZ_CFG_WASM_MAX_BLOCK_DEPTH 100
#endif

/** Limits of roz's module validator, which checks every controller before
 *  the engine sees it; a module beyond one is refused at load with a
 *  message naming the option. Together they size the validator's scratch,
 *  ROZ_CONTROLLER_SCRATCH_BYTES (roz/controller.h): about 22 KiB with the
 *  defaults, about 1.5 KiB with limits sized for one small controller (a
 *  firmware's). Function types per module, 1..65535. */
#ifndef ROZ_CFG_WASM_MAX_TYPES
#define ROZ_CFG_WASM_MAX_TYPES 1024
#endif
/** Functions per module, imported and defined. Range 1..1048576. */
#ifndef ROZ_CFG_WASM_MAX_FUNCS
#define ROZ_CFG_WASM_MAX_FUNCS 4096
#endif
/** Globals per module. Range 1..1048576. */
#ifndef ROZ_CFG_WASM_MAX_GLOBALS
#define ROZ_CFG_WASM_MAX_GLOBALS 1024
#endif
/** Parameters and locals per function. Range 1..1048576. */
#ifndef ROZ_CFG_WASM_MAX_LOCALS
#define ROZ_CFG_WASM_MAX_LOCALS 4096
#endif
/** Exports per module. Range 1..1048576. */
#ifndef ROZ_CFG_WASM_MAX_EXPORTS
#define ROZ_CFG_WASM_MAX_EXPORTS 1024
#endif
/** The engine's compile work a module may need, in steps: one per
 *  instruction, plus at every block, loop and if entered with values on the
 *  operand stack (locals x values: wasm3 compares each local with the
 *  stack there), plus at every local.set and local.tee (values). Refused at
 *  validation, before the engine compiles (docs/load-bound.md). Range
 *  1024..2^40; the default, 2^24, is about 30 ms of wasm3's compiler here. */
#ifndef ROZ_CFG_WASM_MAX_COMPILE_WORK
#define ROZ_CFG_WASM_MAX_COMPILE_WORK 16777216
#endif
/** Tables of roz_crc32_words() (roz/hal/crc32.h, the link checks): 4
 *  (slicing by four, 4 KiB of flash, four independent lookups a word), 1
 *  (1 KiB, four dependent lookups a word: for a small flash) or 0 (a
 *  nibble table of 64 bytes, eight dependent lookups a word: the smallest
 *  flash). */
#ifndef ROZ_CFG_CRC32_SLICES
#define ROZ_CFG_CRC32_SLICES 4
#endif
/** Largest controller module accepted, bytes. Range 64..67108864. */
#ifndef ROZ_CFG_WASM_MAX_MODULE_BYTES
#define ROZ_CFG_WASM_MAX_MODULE_BYTES 1048576
#endif

/** Length of the error message buffers in controllers and the runtime,
 *  bytes including the NUL. Range 32..4096. */
#ifndef ROZ_CFG_ERROR_LEN
#define ROZ_CFG_ERROR_LEN 192
#endif

/** Default controller fuel for one second of control time, in units of
 *  work (about one WebAssembly instruction each, see roz/controller.h); a
 *  tick gets this divided by control_rate_hz, and a rate that leaves a tick
 *  no fuel is refused at roz_runtime_init(). Range 1000..4000000000. */
#ifndef ROZ_CFG_FUEL_PER_SECOND
#define ROZ_CFG_FUEL_PER_SECOND 10000000
#endif

/** The most fuel a controller may declare it needs (ROZ_FUEL_PER_TICK),
 *  for one second of control time: a tick's ceiling is this divided by
 *  control_rate_hz unless the runtime configuration sets its own
 *  (fuel_per_tick_max). Four times the default budget: a 50 Hz policy in a
 *  500 Hz loop gets up to 80,000 units on its inference ticks, about 100 us
 *  of a host core, within the default deadline of half the period.
 *  Range ROZ_CFG_FUEL_PER_SECOND..4000000000. */
#ifndef ROZ_CFG_FUEL_MAX_PER_SECOND
#define ROZ_CFG_FUEL_MAX_PER_SECOND 40000000
#endif

/** Fuel units between two wall-clock deadline checks: the clock is read
 *  once this many units have been charged since the last reading (the work
 *  between two readings is at most this plus one charge: a run of at most
 *  256 instructions, or one memory.fill/copy). Power of two, 1..65536.
 *  Smaller stops an overrun sooner and costs more clock reads. */
#ifndef ROZ_CFG_DEADLINE_CHECK_UNITS
#define ROZ_CFG_DEADLINE_CHECK_UNITS 4096
#endif

/** Telemetry ring entries (telemetry.emit_metric values waiting to be
 *  drained off the tick). Power of two, 2..65536. */
#ifndef ROZ_CFG_TELEMETRY_RING
#define ROZ_CFG_TELEMETRY_RING 256
#endif

/* ---- what a build leaves out ------------------------------------------
 * A firmware that does not use a part leaves it out of its image, as
 * FreeRTOSConfig.h's configUSE_* options do; each is 1 (in, the default: a
 * host build has everything) or 0 (out). docs/firmware.md has each one's
 * saving on the Cortex-M images. */

/** The math imports math.sin and math.cos (roz/abi.h) and the argument
 *  reduction behind them. 0 leaves them out, as ROZ_CFG_NN_IMPORTS. */
#ifndef ROZ_CFG_MATH_IMPORTS
#define ROZ_CFG_MATH_IMPORTS 1
#endif

/** The bulk imports state.get_all and command.set_all (roz/abi.h). 0 leaves
 *  them out, as ROZ_CFG_NN_IMPORTS. */
#ifndef ROZ_CFG_BULK_IMPORTS
#define ROZ_CFG_BULK_IMPORTS 1
#endif

/** The neural-network imports nn.matvec and nn.act (roz/abi.h) and the
 *  activation functions behind them. 0 leaves them out: a controller that
 *  imports one is refused at load, the message naming the import and this
 *  option (an ahead-of-time controller that imports one does not link). */
#ifndef ROZ_CFG_NN_IMPORTS
#define ROZ_CFG_NN_IMPORTS 1
#endif

/** Doubles as decimal text: roz_format()'s `%g`, roz_format_double() and
 *  roz_text_put_double(). 0 leaves the decimal conversion out: they print
 *  the value's IEEE-754 bits instead, "f64:3ff0000000000000" for 1.0
 *  (exact, the same on every target). A firmware's messages print a double
 *  only for a port parameter out of its range (roz/hal/params.h). */
#ifndef ROZ_CFG_FORMAT_DOUBLE
#define ROZ_CFG_FORMAT_DOUBLE 1
#endif

/** Fall detection: the manifest's fall rule (roz/fall.h, [manifest.fall]).
 *  0 leaves it out, for a robot that cannot fall (an arm): a manifest with
 *  a fall rule is then refused, never run without it: its generated table
 *  does not compile (rozgen's manifest.c), and roz_runtime_init() refuses
 *  one built otherwise (ROZ_EINVAL, the message naming this option). */
#ifndef ROZ_CFG_FALL
#define ROZ_CFG_FALL 1
#endif

/* ---- checks --------------------------------------------------------- */
#if ROZ_CFG_MAX_COMMANDS < 1 || ROZ_CFG_MAX_COMMANDS > 4096
#error "ROZ_CFG_MAX_COMMANDS must be in 1..4096"
#endif
#if ROZ_CFG_MAX_STATES < 0 || ROZ_CFG_MAX_STATES > 4096
#error "ROZ_CFG_MAX_STATES must be in 0..4096"
#endif
#if ROZ_CFG_MAX_INPUTS < 0 || ROZ_CFG_MAX_INPUTS > 4096
#error "ROZ_CFG_MAX_INPUTS must be in 0..4096"
#endif
#if ROZ_CFG_NAME_ARENA_BYTES < 64 || ROZ_CFG_NAME_ARENA_BYTES > 1048576
#error "ROZ_CFG_NAME_ARENA_BYTES must be in 64..1048576"
#endif
#if ROZ_CFG_MAX_NAME_LEN < 8 || ROZ_CFG_MAX_NAME_LEN > 255
#error "ROZ_CFG_MAX_NAME_LEN must be in 8..255"
#endif
#if ROZ_CFG_MAX_JOINTS < 0 || ROZ_CFG_MAX_JOINTS > 4096
#error "ROZ_CFG_MAX_JOINTS must be in 0..4096"
#endif
#if ROZ_CFG_MAX_PARAMS < 0 || ROZ_CFG_MAX_PARAMS > 1024
#error "ROZ_CFG_MAX_PARAMS must be in 0..1024"
#endif
#if ROZ_CFG_PROBLEM_LEN < 64 || ROZ_CFG_PROBLEM_LEN > 65536
#error "ROZ_CFG_PROBLEM_LEN must be in 64..65536"
#endif

#if ROZ_CFG_WASM_MAX_BLOCK_DEPTH < 1 || ROZ_CFG_WASM_MAX_BLOCK_DEPTH > 255
#error "ROZ_CFG_WASM_MAX_BLOCK_DEPTH must be in 1..255"
#endif
#if ROZ_CFG_WASM_STACK_BYTES < 4096 || ROZ_CFG_WASM_STACK_BYTES > 16777216
#error "ROZ_CFG_WASM_STACK_BYTES must be in 4096..16777216"
#endif
#if ROZ_CFG_NATIVE_STACK_BYTES < 4096 || ROZ_CFG_NATIVE_STACK_BYTES > 67108864
#error "ROZ_CFG_NATIVE_STACK_BYTES must be in 4096..67108864"
#endif
#if ROZ_CFG_AOT_INSTANCES < 1 || ROZ_CFG_AOT_INSTANCES > 16
#error "ROZ_CFG_AOT_INSTANCES must be in 1..16"
#endif
#if ROZ_CFG_AOT_CALL_DEPTH < 8 || ROZ_CFG_AOT_CALL_DEPTH > 100000
#error "ROZ_CFG_AOT_CALL_DEPTH must be in 8..100000"
#endif
#if ROZ_CFG_AOT_MAX_TYPES < 8 || ROZ_CFG_AOT_MAX_TYPES > 2048
#error "ROZ_CFG_AOT_MAX_TYPES must be in 8..2048"
#endif
#if ROZ_CFG_WASM_MAX_PAGES < 1 || ROZ_CFG_WASM_MAX_PAGES > 65536
#error "ROZ_CFG_WASM_MAX_PAGES must be in 1..65536"
#endif
#if ROZ_CFG_CRC32_SLICES != 0 && ROZ_CFG_CRC32_SLICES != 1 && ROZ_CFG_CRC32_SLICES != 4
#error "ROZ_CFG_CRC32_SLICES must be 0, 1 or 4"
#endif
#if ROZ_CFG_WASM_MAX_COMPILE_WORK < 1024 || ROZ_CFG_WASM_MAX_COMPILE_WORK > 1099511627776
#error "ROZ_CFG_WASM_MAX_COMPILE_WORK must be in 1024..2^40"
#endif
#if ROZ_CFG_WASM_MAX_TYPES < 1 || ROZ_CFG_WASM_MAX_TYPES > 65535
#error "ROZ_CFG_WASM_MAX_TYPES must be in 1..65535"
#endif
#if ROZ_CFG_WASM_MAX_FUNCS < 1 || ROZ_CFG_WASM_MAX_FUNCS > 1048576
#error "ROZ_CFG_WASM_MAX_FUNCS must be in 1..1048576"
#endif
#if ROZ_CFG_WASM_MAX_GLOBALS < 1 || ROZ_CFG_WASM_MAX_GLOBALS > 1048576
#error "ROZ_CFG_WASM_MAX_GLOBALS must be in 1..1048576"
#endif
#if ROZ_CFG_WASM_MAX_LOCALS < 1 || ROZ_CFG_WASM_MAX_LOCALS > 1048576
#error "ROZ_CFG_WASM_MAX_LOCALS must be in 1..1048576"
#endif
#if ROZ_CFG_WASM_MAX_EXPORTS < 1 || ROZ_CFG_WASM_MAX_EXPORTS > 1048576
#error "ROZ_CFG_WASM_MAX_EXPORTS must be in 1..1048576"
#endif
#if ROZ_CFG_WASM_MAX_TABLE_ENTRIES < 0 || ROZ_CFG_WASM_MAX_TABLE_ENTRIES > 100000
#error "ROZ_CFG_WASM_MAX_TABLE_ENTRIES must be in 0..100000"
#endif
#if ROZ_CFG_WASM_MAX_MODULE_BYTES < 64 || ROZ_CFG_WASM_MAX_MODULE_BYTES > 67108864
#error "ROZ_CFG_WASM_MAX_MODULE_BYTES must be in 64..67108864"
#endif
#if ROZ_CFG_ERROR_LEN < 32 || ROZ_CFG_ERROR_LEN > 4096
#error "ROZ_CFG_ERROR_LEN must be in 32..4096"
#endif

#if ROZ_CFG_FUEL_PER_SECOND < 1000 || ROZ_CFG_FUEL_PER_SECOND > 4000000000
#error "ROZ_CFG_FUEL_PER_SECOND must be in 1000..4000000000"
#endif
#if ROZ_CFG_FUEL_MAX_PER_SECOND < ROZ_CFG_FUEL_PER_SECOND || ROZ_CFG_FUEL_MAX_PER_SECOND > 4000000000
#error "ROZ_CFG_FUEL_MAX_PER_SECOND must be in ROZ_CFG_FUEL_PER_SECOND..4000000000"
#endif
#if ROZ_CFG_DEADLINE_CHECK_UNITS < 1 || ROZ_CFG_DEADLINE_CHECK_UNITS > 65536 || \
    (ROZ_CFG_DEADLINE_CHECK_UNITS & (ROZ_CFG_DEADLINE_CHECK_UNITS - 1)) != 0
#error "ROZ_CFG_DEADLINE_CHECK_UNITS must be a power of two in 1..65536"
#endif

#if ROZ_CFG_MATH_IMPORTS != 0 && ROZ_CFG_MATH_IMPORTS != 1
#error "ROZ_CFG_MATH_IMPORTS must be 0 or 1"
#endif
#if ROZ_CFG_BULK_IMPORTS != 0 && ROZ_CFG_BULK_IMPORTS != 1
#error "ROZ_CFG_BULK_IMPORTS must be 0 or 1"
#endif
#if ROZ_CFG_NN_IMPORTS != 0 && ROZ_CFG_NN_IMPORTS != 1
#error "ROZ_CFG_NN_IMPORTS must be 0 or 1"
#endif
#if ROZ_CFG_FORMAT_DOUBLE != 0 && ROZ_CFG_FORMAT_DOUBLE != 1
#error "ROZ_CFG_FORMAT_DOUBLE must be 0 or 1"
#endif
#if ROZ_CFG_FALL != 0 && ROZ_CFG_FALL != 1
#error "ROZ_CFG_FALL must be 0 or 1"
#endif

#if ROZ_CFG_TELEMETRY_RING < 2 || ROZ_CFG_TELEMETRY_RING > 65536 || \
    (ROZ_CFG_TELEMETRY_RING & (ROZ_CFG_TELEMETRY_RING - 1)) != 0
#error "ROZ_CFG_TELEMETRY_RING must be a power of two in 2..65536"
#endif

#endif /* ROZ_CONFIG_H */
