/* SPDX-License-Identifier: Apache-2.0 */
/*
 * bench/fuel: what one fuel unit costs, and how long a process() call can
 * really run under its budget.
 *
 * Fuel is roz's measure of work (roz/controller.h): one unit per WebAssembly
 * instruction, more for the costly ones (a call 8 more, a loop entry 6, a
 * back-edge 1, br_table, float sqrt/div, bulk memory ops, saturating truncation 2), one
 * per 16 bytes of memory.fill/copy or
 * of a called function's locals and constants. For each kind of work a
 * hostile controller could pile up,
 * a module does nothing else in an endless loop; the bench runs it
 * (Fuel figures are in the thread's CPU time, so preemption by other
 * processes does not count; deadline figures in wall-clock time.)
 *   1. on fuel alone (ROZ_BENCH_FUEL units, no deadline) and prints the
 *      nanoseconds per 1000 units: the cost of the unit on this machine,
 *      per kind, the spread between kinds being what a budget in units can
 *      promise in time;
 *   2. on the default budgets of a 100 Hz and a 500 Hz robot, fuel alone (a
 *      firmware without a clock), and prints the median and the longest
 *      call against the time the budget stands for (units x the median
 *      cost of a unit);
 *   3. with the fuel off and the deadline of a 100 Hz and a 500 Hz robot
 *      (half the period, the runtime's default) and prints the median and
 *      the longest call against the deadline.
 * A benchmark, not a test: it prints, it never fails on a time.
 *
 *   roz_bench_fuel [CALLS] [--json FILE]   (calls per figure, default 9)
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "roz/abi.h"
#include "roz/controller.h"
#include "bench_json.h"
#include "roz/hal/clock.h"
#include "roz/module.h"
#include "ur5_manifest.h"

#define ROZ_BENCH_FUEL 50000000ull

/* ---- the modules ------------------------------------------------------------ */

typedef struct {
    const char *name;
    const char *what;
    const char *decls; /* functions, memory, table before process */
    const char *body;  /* one repetition of the loop's work */
    int         reps;  /* repetitions inside the loop body */
} work_t;

/* six f64 1e9 (0x41cdcd6500000000), little-endian, as a WAT string */
#define F64_1E9  "\\00\\00\\00\\65\\cd\\cd\\cd\\41"
#define CLAMPED6 F64_1E9 F64_1E9 F64_1E9 F64_1E9 F64_1E9 F64_1E9

static const work_t works[] = {
    { "i32_arith", "i32.add/mul/xor on locals", "",
      "(local.set $a (i32.xor (i32.mul (i32.add (local.get $a) (i32.const 7)) (local.get $a)) "
      "(i32.const 5)))",
      64 },
    { "i64_div", "i64.div_s and i64.rem_u", "",
      "(local.set $x (i64.add (i64.div_s (local.get $x) (local.get $y)) "
      "(i64.rem_u (local.get $x) (local.get $y))))",
      64 },
    { "f64_sqrt_div", "f64.sqrt and f64.div", "",
      "(local.set $f (f64.div (f64.sqrt (local.get $f)) (f64.const 0.999)))", 64 },
    /* float arithmetic on normal numbers, and the same on subnormal ones
     * (many CPUs' slow path; each value stays subnormal: 1e-39 x 0.999 +
     * 1e-45 converges to about 1e-42) */
    { "f32_arith", "f32.mul and f32.add", "(global $g (mut f32) (f32.const 0.5))",
      "(global.set $g (f32.add (f32.mul (global.get $g) (f32.const 0.999)) (f32.const 1e-3)))",
      64 },
    { "f32_subnormal", "f32.mul and f32.add on subnormal numbers",
      "(global $g (mut f32) (f32.const 1e-39))",
      "(global.set $g (f32.add (f32.mul (global.get $g) (f32.const 0.999)) (f32.const 1e-45)))",
      64 },
    { "f64_arith", "f64.mul and f64.add", "(global $g (mut f64) (f64.const 0.5))",
      "(global.set $g (f64.add (f64.mul (global.get $g) (f64.const 0.999)) (f64.const 1e-3)))",
      64 },
    { "f64_subnormal", "f64.mul and f64.add on subnormal numbers",
      "(global $g (mut f64) (f64.const 1e-310))",
      "(global.set $g (f64.add (f64.mul (global.get $g) (f64.const 0.999)) (f64.const 5e-324)))",
      64 },
    { "f64_trunc", "checked float to int conversions", "",
      "(local.set $a (i32.trunc_f64_s (f64.const 12345.5)))", 64 },
    { "load_store", "i64 loads and stores", "(memory 1)",
      "(i64.store offset=8 (i32.const 64) (i64.load offset=16 (i32.const 64)))", 64 },
    { "select_global", "select, global.get/set", "(global $g (mut i32) (i32.const 1))",
      "(global.set $g (select (global.get $g) (local.get $a) (local.get $a)))", 64 },
    { "br_table", "br_table into nested blocks", "",
      "(block $b0 (block $b1 (block $b2 (br_table $b0 $b1 $b2 (i32.and (local.get $a) "
      "(i32.const 3))))))",
      16 },
    { "empty_loops", "entering loops that exit at once", "", "(loop $inner)", 64 },
    { "back_edges", "a loop whose body is a nop", "", "(nop)", 1 },
    { "call_empty", "calls of an empty function", "(func $nop)", "(call $nop)", 16 },
    { "call_1000_locals", "calls of a function with 1000 i64 locals",
      "(func $big (local i64 i64 i64 i64 i64 i64 i64 i64 i64 i64) " /* 10 declared... */
      "(local " /* ...and 990 more: see locals_990 below */ "LOCALS990))",
      "(call $big)", 4 },
    { "call_indirect", "call_indirect through a table",
      "(type $t (func)) (func $nop) (table 1 funcref) (elem (i32.const 0) $nop)",
      "(call_indirect (type $t) (i32.const 0))", 16 },
    { "host_sin", "host calls: math.sin", "", "(local.set $f (call $sin (local.get $f)))", 16 },
    { "host_sin_large", "host calls: math.sin of 1e22 (range reduction)", "",
      "(local.set $f (call $sin (f64.add (local.get $f) (f64.const 1e22))))", 16 },
    { "host_cos", "host calls: math.cos", "", "(local.set $f (call $cos (local.get $f)))", 16 },
    { "host_cos_large", "host calls: math.cos of -3e300 (range reduction)", "",
      "(local.set $f (call $cos (f64.sub (local.get $f) (f64.const 3e300))))", 16 },
    { "host_count", "host calls: command.count, state.count", "",
      "(local.set $a (i32.add (call $ccount) (call $scount)))", 16 },
    { "host_limits", "host calls: command.limit_min, limit_max", "",
      "(local.set $f (f64.add (call $lmin (i32.const 1)) (call $lmax (i32.const 1))))", 16 },
    { "host_now", "host calls: timing.now_ns", "", "(local.set $x (call $now))", 16 },
    { "host_sim_time", "host calls: timing.sim_time_ns", "", "(local.set $x (call $sim))", 16 },
    { "host_metric", "host calls: telemetry.emit_metric", "", "(call $metric (local.get $f))",
      16 },
    { "host_estop", "host calls: safety.request_estop", "", "(call $estop)", 16 },
    { "host_set_clamped", "host calls: command.set, clamped", "",
      "(drop (call $set (i32.const 0) (f64.const 1e9)))", 16 },
    { "host_set", "host calls: command.set",
      "", "(drop (call $set (i32.const 0) (local.get $f)))", 16 },
    { "host_get", "host calls: state.get", "", "(local.set $f (call $get (i32.const 0)))", 16 },
    { "host_get_all", "host calls: state.get_all of 12 values", "(memory 1)",
      "(drop (call $get_all (i32.const 64) (i32.const 12)))", 16 },
    { "host_set_all", "host calls: command.set_all of 6 values", "(memory 1)",
      "(drop (call $set_all (i32.const 64) (i32.const 6)))", 16 },
    { "host_set_all_clamped", "host calls: command.set_all of 6 values, all clamped",
      "(memory 1) (data (i32.const 64) \"" CLAMPED6 "\")",
      "(drop (call $set_all (i32.const 64) (i32.const 6)))", 16 },
    { "memory_fill", "memory.fill of 1 MiB", "(memory 16)",
      "(memory.fill (i32.const 0) (local.get $a) (i32.const 1048576))", 1 },
    { "memory_copy", "memory.copy of 512 KiB", "(memory 16)",
      "(memory.copy (i32.const 0) (i32.const 524288) (i32.const 524288))", 1 },
    { "memory_fill_small", "memory.fill of 16 bytes", "(memory 1)",
      "(memory.fill (i32.const 0) (local.get $a) (i32.const 16))", 64 },
};
#define N_WORKS (sizeof works / sizeof works[0])

static char text[256 * 1024];

/* The WAT of one work: an endless loop around reps copies of its body. */
static void module_text(const work_t *w)
{
    char decls[16384];
    size_t n = 0;
    const char *hole = strstr(w->decls, "LOCALS990");

    if (hole != NULL) {
        n = (size_t)snprintf(decls, sizeof decls, "%.*s", (int)(hole - w->decls), w->decls);
        for (int i = 0; i < 990; i++)
            n += (size_t)snprintf(decls + n, sizeof decls - n, "i64 ");
        snprintf(decls + n, sizeof decls - n, "%s", hole + strlen("LOCALS990"));
    } else {
        snprintf(decls, sizeof decls, "%s", w->decls);
    }
    n = (size_t)snprintf(text, sizeof text,
                         "(module\n"
                         " (import \"command\" \"set\" (func $set (param i32 f64) (result i32)))\n"
                         " (import \"state\" \"get\" (func $get (param i32) (result f64)))\n"
                         " (import \"math\" \"sin\" (func $sin (param f64) (result f64)))\n"
                         " (import \"math\" \"cos\" (func $cos (param f64) (result f64)))\n"
                         " (import \"command\" \"count\" (func $ccount (result i32)))\n"
                         " (import \"state\" \"count\" (func $scount (result i32)))\n"
                         " (import \"command\" \"limit_min\" (func $lmin (param i32) (result f64)))\n"
                         " (import \"command\" \"limit_max\" (func $lmax (param i32) (result f64)))\n"
                         " (import \"timing\" \"now_ns\" (func $now (result i64)))\n"
                         " (import \"timing\" \"sim_time_ns\" (func $sim (result i64)))\n"
                         " (import \"telemetry\" \"emit_metric\" (func $metric (param f64)))\n"
                         " (import \"safety\" \"request_estop\" (func $estop))\n"
                         " (import \"state\" \"get_all\" (func $get_all (param i32 i32) (result i32)))\n"
                         " (import \"command\" \"set_all\" (func $set_all (param i32 i32) (result i32)))\n"
                         " %s\n"
                         " (func (export \"process\") (param $tick i64)\n"
                         "  (local $a i32) (local $x i64) (local $y i64) (local $f f64)\n"
                         "  (local.set $a (i32.const 3)) (local.set $x (i64.const 1000000007))\n"
                         "  (local.set $y (i64.const 3)) (local.set $f (f64.const 0.5))\n"
                         "  (loop $l\n",
                         decls);
    for (int r = 0; r < w->reps; r++)
        n += (size_t)snprintf(text + n, sizeof text - n, "   %s\n", w->body);
    snprintf(text + n, sizeof text - n, "   (br $l))))\n");
}

static uint8_t wasms[sizeof works / sizeof works[0]][64 * 1024];
static uint8_t *wasm;

static size_t build(const work_t *w)
{
    char dir[] = "/tmp/roz_bench_fuel_XXXXXX", path[64], err[256];
    size_t len = 0;
    FILE *f;

    module_text(w);
    if (mkdtemp(dir) == NULL) {
        fprintf(stderr, "roz_bench_fuel: cannot make a temporary folder\n");
        exit(1);
    }
    snprintf(path, sizeof path, "%s/%s.wat", dir, w->name);
    f = fopen(path, "w");
    if (f == NULL || fputs(text, f) == EOF || fclose(f) != 0) {
        fprintf(stderr, "roz_bench_fuel: cannot write %s\n", path);
        exit(1);
    }
    int rc = roz_module_read_file(path, wasms[w - works], sizeof wasms[0], &len, err, sizeof err);
    unlink(path);
    rmdir(dir);
    if (rc != ROZ_OK) {
        fprintf(stderr, "roz_bench_fuel: %s: %s\n", w->name, err);
        exit(1);
    }
    return len;
}

/* ---- running ---------------------------------------------------------------- */

static roz_controller_t ctl;
static roz_abi_t abi;

static double state[ROZ_CFG_MAX_STATES];
static double targets[ROZ_CFG_MAX_COMMANDS];

static uint64_t wall_ns(void)
{
    return roz_clock_monotonic_ns(NULL);
}

/* CPU time of this thread: a call's own work, not the time the scheduler
 * gave to others meanwhile (the fuel figures are about work). */
static uint64_t cpu_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

typedef struct {
    uint64_t p50, max; /* the median and the longest call */
    uint64_t units;    /* what the median call used */
} run_t;

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

#define MAX_REPEATS 64

/* Loads the work afresh for each of `repeats` calls within `budget`; each
 * is stopped by the budget (the work never ends). Timed in this thread's CPU
 * time on fuel alone, in wall-clock time (what a deadline is about) with a
 * deadline. */
static run_t run(const work_t *w, size_t len, uint64_t fuel, uint64_t deadline_ns, int repeats)
{
    uint64_t (*now)(void) = deadline_ns == ROZ_BUDGET_OFF ? cpu_ns : wall_ns;
    roz_budget_t b = { fuel, deadline_ns, roz_clock_monotonic_ns, NULL };
    uint64_t ns[MAX_REPEATS], units = 0;

    wasm = wasms[w - works];
    for (int i = 0; i < repeats; i++) {
        roz_controller_init(&ctl);
        roz_abi_init(&abi, &roz_manifest_ur5, targets, NULL);
        roz_abi_set_clock(&abi, roz_clock_monotonic_ns, NULL, 0); /* now_ns as on a host */
        roz_abi_begin_tick(&abi, 0, state);
        if (roz_controller_load(&ctl, wasm, len, &abi) != ROZ_OK) {
            fprintf(stderr, "roz_bench_fuel: %s: %s\n", w->name, roz_controller_error(&ctl));
            exit(1);
        }
        if (roz_controller_set_budget(&ctl, &b) != ROZ_OK) {
            fprintf(stderr, "roz_bench_fuel: bad budget\n");
            exit(1);
        }
        uint64_t t0 = now();
        if (roz_controller_process(&ctl, 0) != ROZ_ETIMEDOUT) { /* the work never ends */
            fprintf(stderr, "roz_bench_fuel: %s: not stopped by its budget\n", w->name);
            exit(1);
        }
        ns[i] = now() - t0;
        units = roz_controller_fuel_used(&ctl); /* the same every call */
        roz_controller_unload(&ctl);
    }
    qsort(ns, (size_t)repeats, sizeof ns[0], cmp_u64);
    return (run_t){ ns[repeats / 2], ns[repeats - 1], units };
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
    bench_json_t json;
    char jn[96];
    argc = bench_json_args(&json, "fuel", argc, argv);
    if (argc < 0)
        return 2;
    int repeats = argc > 1 ? atoi(argv[1]) : 9;
    static size_t lens[N_WORKS];
    double ns_per_k[N_WORKS], sorted[N_WORKS];

    if (repeats < 1)
        repeats = 1;
    if (repeats > MAX_REPEATS)
        repeats = MAX_REPEATS;
    for (size_t i = 0; i < N_WORKS; i++)
        lens[i] = build(&works[i]);

    printf("roz_bench_fuel: %d calls per figure (a fresh instance each); a unit is about one "
           "WebAssembly instruction\n\n",
           repeats);
    printf("1. the cost of fuel, %llu units per call, no deadline (median call, CPU time)\n",
           (unsigned long long)ROZ_BENCH_FUEL);
    printf("   %-18s %-44s %12s\n", "work", "", "ns/1000 units");
    for (size_t i = 0; i < N_WORKS; i++) {
        run_t r = run(&works[i], lens[i], ROZ_BENCH_FUEL, ROZ_BUDGET_OFF, repeats);
        ns_per_k[i] = r.units ? 1000.0 * (double)r.p50 / (double)r.units : 0.0;
        sorted[i] = ns_per_k[i];
        printf("   %-18s %-44s %12.1f\n", works[i].name, works[i].what, ns_per_k[i]);
        snprintf(jn, sizeof jn, "cost of 1000 units, %s", works[i].name);
        bench_json_value(&json, jn, ns_per_k[i], "ns");
    }
    qsort(sorted, N_WORKS, sizeof sorted[0], cmp_double);
    double median = sorted[N_WORKS / 2], slowest = sorted[N_WORKS - 1];
    printf("   median %.1f ns, slowest %.1f ns per 1000 units (%.2fx the median)\n\n", median,
           slowest, slowest / median);
    bench_json_value(&json, "cost of 1000 units, median over the kinds of work", median, "ns");

    /* the median call is the work the budget allowed; the longest also
     * holds what the machine did meanwhile (a cold cache, an interrupt) */
    static const unsigned rates[] = { 100, 500 };
    printf("2. fuel alone (no clock): the default budget, ROZ_CFG_FUEL_PER_SECOND / rate, against\n"
           "   the time it stands for at the median cost of a unit (CPU time)\n");
    printf("   %-18s %14s %12s %12s %8s %8s\n", "work", "budget stands", "median call",
           "longest", "ratio", "longest");
    for (size_t k = 0; k < 2; k++) {
        uint64_t fuel = (uint64_t)ROZ_CFG_FUEL_PER_SECOND / rates[k];
        double stands_ns = (double)fuel * median / 1000.0;
        double worst_ratio = 0, worst_max = 0;
        printf("   %u Hz: %llu units, %.0f us at the median cost\n", rates[k],
               (unsigned long long)fuel, stands_ns / 1000.0);
        for (size_t i = 0; i < N_WORKS; i++) {
            run_t r = run(&works[i], lens[i], fuel, ROZ_BUDGET_OFF, repeats);
            double ratio = (double)r.p50 / stands_ns, rmax = (double)r.max / stands_ns;
            if (ratio > worst_ratio)
                worst_ratio = ratio;
            if (rmax > worst_max)
                worst_max = rmax;
            printf("   %-18s %11.0f us %9.0f us %9.0f us %7.2fx %7.2fx\n", works[i].name,
                   stands_ns / 1000.0, (double)r.p50 / 1000.0, (double)r.max / 1000.0, ratio,
                   rmax);
        }
        snprintf(jn, sizeof jn, "fuel alone, %u Hz: longest call / time the budget stands for",
                 rates[k]);
        bench_json_value(&json, jn, worst_max, "ratio");
        printf("   %u Hz worst: median call %.2fx, longest call %.2fx the time the budget stands "
               "for\n",
               rates[k], worst_ratio, worst_max);
    }

    printf("\n3. deadline alone (fuel off): half the period, the runtime's default; the clock\n"
           "   is read every %u units (wall-clock time)\n",
           (unsigned)ROZ_CFG_DEADLINE_CHECK_UNITS);
    printf("   %-18s %14s %12s %12s %8s %8s\n", "work", "deadline", "median call", "longest",
           "ratio", "longest");
    for (size_t k = 0; k < 2; k++) {
        uint64_t deadline = 1000000000ull / rates[k] / 2u;
        double worst_ratio = 0, worst_max = 0;
        for (size_t i = 0; i < N_WORKS; i++) {
            run_t r = run(&works[i], lens[i], ROZ_BUDGET_OFF, deadline, repeats);
            double ratio = (double)r.p50 / (double)deadline, rmax = (double)r.max / (double)deadline;
            if (ratio > worst_ratio)
                worst_ratio = ratio;
            if (rmax > worst_max)
                worst_max = rmax;
            printf("   %-18s %11.0f us %9.0f us %9.0f us %7.2fx %7.2fx\n", works[i].name,
                   (double)deadline / 1000.0, (double)r.p50 / 1000.0, (double)r.max / 1000.0,
                   ratio, rmax);
        }
        snprintf(jn, sizeof jn, "deadline alone, %u Hz: longest call / deadline", rates[k]);
        bench_json_value(&json, jn, worst_max, "ratio");
        printf("   %u Hz worst: median call %.2fx, longest call %.2fx the deadline\n", rates[k],
               worst_ratio, worst_max);
    }
    bench_json_close(&json);
    return 0;
}
