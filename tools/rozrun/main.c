/* SPDX-License-Identifier: Apache-2.0 */
/*
 * rozrun: run a WebAssembly controller on a robot through a port.
 *
 *   rozrun --robot ur5 --controller sine.wasm --port loopback --ticks 500
 *          [--realtime] [--param k=v]... [--trace out.csv] [--record run.mcap]
 *          [--live FIFO]
 *          [--allow-other-robot]
 *          [--estop-at T] [--estop-release-at T] [--clear-at T] [--swap-at T:FILE]...
 *          [--deploy FILE] [--stage-at T:STAGE]...
 *   rozrun --robot path/to/robot.toml --controller sine.wasm ...
 *   rozrun --robot unitree_g1 --port unitree/G1 --param network_interface=eth0
 *          --controller g1_stand.wasm
 *   rozrun --robot engineai_pm01 --port engineai/PM01 --param network_interface=eth0
 *          --controller pm01_stand.wasm
 *   rozrun --robot leg.toml --port socketcan --param network_interface=can0
 *          --controller leg_pd.wasm
 *   rozrun --replay run.mcap --controller ctl.wasm [--record new.mcap] [--trace new.csv]
 *
 * On the loopback, without --realtime, the ticks run back to back
 * (simulated time, as fast as the machine goes); with it a periodic thread
 * runs them at the manifest's rate, with SCHED_FIFO and locked memory where
 * permitted. A robot's port always runs at the manifest's rate (the robot
 * keeps its own time); --realtime adds SCHED_FIFO and locked memory. The
 * scheduled interventions are schedule.c's. Exit status: 0 when no fault is
 * latched at the end, 1 when one is, 2 for bad arguments or a refused
 * controller, 3 when the trace could not be written.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include <stdatomic.h>
#include <time.h>

#include "roz/builtin.h"
#include "roz/hal/clock.h"
#include "roz/module.h"
#include "roz/hal/params.h"
#include "roz/runner.h"
#include "roz/hal/thread.h"
#include "roz/ports.h"
#include "roz/record_file.h"
#include "roz/record_live.h"
#include "roz/runtime.h"
#include "replay.h"
#include "deploy.h"
#include "operator.h"
#include "teleop.h"
#include "schedule.h"
#include "summary_json.h"
#include "trace.h"
#if ROZRUN_HAS_MUJOCO
#include "roz/port/mujoco.h"
#endif
#if ROZ_HAS_TOML
#include "roz/manifest_toml.h"
#endif
#if ROZRUN_HAS_GAMEPAD
#include "roz/gamepad.h"
#endif

#define MAX_PARAMS 32

typedef struct {
    const char *robot;
    const char *controller;
    const char *port;
    int         port_given; /* --port was named: --help adds the port's section */
    const char *trace;
    const char *record;
    const char *live;   /* --live: the recording streamed to a viewer (docs/live.md) */
    const char *replay;
    const char *operator_file; /* --operator: a scripted operator (operator.h) */
    const char *deploy_file;   /* --deploy: the deploy sequence (deploy.h) */
    const char *gamepad;       /* --gamepad: an evdev gamepad as the remote (roz/gamepad.h) */
    const char *teleop;        /* --teleop: an operator's twists on a socket (teleop.h) */
    const char *summary_json; /* --summary-json: the summary as JSON (summary_json.h) */
    uint64_t    ticks;
    int         realtime;
    int         check;      /* --check: open the port, close it, run nothing */
    int         allow_other_robot;
    int         priority;
    uint64_t    budget_us;
    int         budget_set;
    uint64_t    fuel;
    int         fuel_set;
    uint64_t    fuel_max;
    int         fuel_max_set;
    uint32_t    stale_ticks;
    uint32_t    record_every;
    int         record_compression; /* ROZ_MCAP_COMPRESS_*; -1: zstd when built with it */
    roz_param_t params[MAX_PARAMS];
    size_t      n_params;
} options_t;

static roz_runtime_t rt;
#if ROZRUN_HAS_GAMEPAD
static roz_gamepad_t gamepad; /* --gamepad: its reader thread feeds rt's inputs */
#endif

/* ---- the ports this build holds (roz/ports.h) ------------------------------ */

static void log_stderr(void *ctx, roz_log_level_t level, const char *msg);

static const roz_port_entry_t *find_port(const char *name)
{
    const roz_port_entry_t *pe = roz_ports_find(name);
    if (pe != NULL && strcmp(pe->ops->name, name) == 0)
        return pe;
    fprintf(stderr, "rozrun: --port \"%s\": not available in this build; known:", name);
    for (size_t i = 0; i < ROZ_PORTS_COUNT; i++)
        fprintf(stderr, " %s", roz_ports[i].ops->name);
    fprintf(stderr, "\n");
    return NULL;
}

/* The chosen port's instance: allocated once, at start-up, as the registry
 * says (size and alignment); nothing in the tick allocates. Kept here until
 * the end of main(). */
static void *port_self;

static int make_port(const roz_port_entry_t *pe, roz_port_t *out)
{
    size_t align = pe->align > 0 ? pe->align : 1;
    size_t size = (pe->size + align - 1) / align * align;
    void *self = NULL;
    if (align <= _Alignof(max_align_t))
        self = calloc(1, size > 0 ? size : 1);
    if (self == NULL || (uintptr_t)self % align != 0) {
        fprintf(stderr, "rozrun: no memory for port %s (%lu bytes)\n", pe->ops->name,
                (unsigned long)pe->size);
        free(self);
        return -1;
    }
    port_self = self;
    *out = pe->construct(self, log_stderr, NULL);
    return 0;
}

/* The port's own lines (roz_port_report()): after open, "rozrun: " and the
 * line; in the summary, each line indented as the summary's. */
static void print_report(const roz_port_t *port, roz_port_report_when_t when)
{
    static char text[2048];
    if (roz_port_report(port, when, text, sizeof text) <= 0)
        return;
    for (char *line = text; *line != '\0';) {
        char *end = strchr(line, '\n');
        if (end != NULL)
            *end = '\0';
        printf("%s%s\n", when == ROZ_PORT_REPORT_OPENED ? "rozrun: " : "  ", line);
        if (end == NULL)
            break;
        line = end + 1;
    }
}

static rozrun_trace_t trace;
static int tracing;
/* the flight recorder: ring storage (the heap, at start-up), its file */
static roz_recorder_t recorder;
static roz_record_file_t recfile;
static int recording;
static int record_failed; /* main thread: the recording's first write error was reported */
static roz_record_live_t live;
static int living;
/* after the run: how long the viewer may take to read the last ticks */
#define LIVE_CLOSE_WAIT_MS 2000u
static rozrun_watch_t watch; /* --summary-json: the tick's thread's, read after the run */
static int watching;
static int trace_failed; /* main thread: the trace's first write error was reported */
static rozrun_schedule_t sched;
static rozrun_operator_t op; /* --operator: set by the tick's thread */
static rozrun_teleop_t teleop; /* --teleop: its own thread */
static int operating;
static atomic_int interrupted; /* lock-free: set by the signal handler */
static int realtime_degraded; /* --realtime refused: the deadline on the CPU time */
static atomic_uint loader_events; /* trace events of the loader's actions, taken by the tick */
static _Atomic uint64_t ticks_done; /* written by the tick's thread after each tick */

/* The port's own section of --help: what it is, its pages and its
 * parameters, from the port itself (roz_port_info_t) and its registration. */
static void usage_port(FILE *f, const roz_port_entry_t *pe)
{
    const roz_port_info_t *info = roz_port_ops_info(pe->ops);
    fprintf(f, "\nPort %s: %s (%s)\n", pe->ops->name, info->summary, info->header);
    fprintf(f, "  documented in: %s\n", pe->docs);
    if (info->n_params > 0)
        fprintf(f, "  parameters (--param KEY=VALUE):\n");
    for (size_t i = 0; i < info->n_params; i++) {
        const roz_port_param_info_t *pi = &info->params[i];
        fprintf(f, "    %-24s %s%s%s%s\n", pi->key, pi->range,
                pi->def[0] != '\0' ? " (default " : "", pi->def, pi->def[0] != '\0' ? ")" : "");
        fprintf(f, "    %-24s %s\n", "", pi->help);
    }
}

static void usage(FILE *f, const char *port)
{
    char known[256] = "";
    size_t used = 0;
    for (size_t i = 0; i < ROZ_PORTS_COUNT; i++) {
        int n = snprintf(known + used, sizeof known - used, "%s%s", i > 0 ? ", " : "",
                         roz_ports[i].ops->name);
        if (n < 0 || (size_t)n >= sizeof known - used)
            break;
        used += (size_t)n;
    }
    fprintf(f,
        "usage: rozrun --robot ID|FILE --controller FILE [options]\n"
        "\n"
        "Runs a WebAssembly controller (.wasm, or .wat assembled with wat2wasm) on a\n"
        "robot through a port, behind roz's safety filter, and prints a summary.\n"
        "\n"
        "  --robot ID|FILE      built-in manifest id (see roz_manifest_info), or a\n"
        "                       robot.toml read at run time (a path with / or .toml)\n"
        "  --controller FILE    controller module, .wasm or .wat\n"
        "  --port NAME          port to drive (default loopback; known: %s)\n",
        known);
    fprintf(f,
        "  --ticks N            ticks to run (default 1000; 0 = until Ctrl-C)\n"
        "  --realtime           run at the manifest's rate on a periodic thread,\n"
        "                       SCHED_FIFO and locked memory where permitted\n"
        "  --priority P         SCHED_FIFO priority with --realtime (default 80)\n"
        "  --check              open the robot's port and close it: every check the port\n"
        "                       makes of the robot at open (mujoco: the model compiled,\n"
        "                       its joints, actuators and ranges), no controller, nothing\n"
        "                       run; exit 0, or 2 with the port's refusal (rozgen --check\n"
        "                       asks the mujoco port this way)\n"
        "  --allow-other-robot  run a controller built for another robot, or for an older\n"
        "                       channel table of this one (refused by default)\n"
        "  --param KEY=VALUE    port parameter, repeatable; --port NAME --help lists\n"
        "                       the port's\n"
        "  --budget-us US|off   controller wall-clock deadline per tick (default: half the\n"
        "                       period with --realtime; off in simulated time, where the\n"
        "                       fuel alone decides, so a run is the same on any machine)\n"
        "  --fuel N|off         controller fuel per tick, in work units (about one wasm\n"
        "                       instruction each; default ROZ_CFG_FUEL_PER_SECOND / rate);\n"
        "                       off: unmetered\n"
        "  --fuel-max N|off     the most fuel per tick a controller may declare it needs\n"
        "                       (ROZ_FUEL_PER_TICK; default ROZ_CFG_FUEL_MAX_PER_SECOND /\n"
        "                       rate); a larger declaration is refused at load; off: any\n"
        "  --stale-ticks N      ticks without fresh state before the stale fault (default 10)\n"
        "  --trace FILE         write every tick (targets, applied commands, state, latched\n"
        "                       faults, events) as CSV\n"
        "  --record FILE        record every tick as MCAP (state, freshness, targets,\n"
        "                       applied commands, faults, fuel, times; the manifest and\n"
        "                       configuration once): roz-recording (tools/recording.py),\n"
        "                       Foxglove, ros2 bag\n"
        "  --live PATH          stream what --record writes (the same MCAP channels and\n"
        "                       messages, a chunk per tick) to a FIFO or pipe a viewer\n"
        "                       reads, roz-live (tools/live.py) serving it to Foxglove:\n"
        "                       never waited for; ticks the viewer is too slow for are\n"
        "                       dropped from the stream and counted (docs/live.md)\n"
        "  --record-every N     record every Nth tick only (and every tick where the faults\n"
        "                       change or an input arrives); such a recording is not\n"
        "                       replayed (default 1)\n"
        "  --record-compress C  the recording's chunks: zstd (the default when built with\n"
        "                       libzstd) or none\n"
        "  --summary-json FILE  write the summary as JSON too (counters, faults, the\n"
        "                       simulator's base height: lowest, final, a series; the\n"
        "                       peak joint speed), for programs that judge runs\n"
        "                       (roz-campaign)\n"
        "  --replay FILE        feed a recording's states, tick by tick, to --controller\n"
        "                       (no port; --robot optional, checked against the recording)\n"
        "                       and compare its targets and applied commands bit for bit:\n"
        "                       the first divergence is reported (tick, channel, both\n"
        "                       values); with another controller than the recorded one,\n"
        "                       --record and --trace keep the new run for a comparison;\n"
        "                       a recorded deploy sequence runs again, its stage requests\n"
        "                       at their ticks (--deploy FILE: another sequence instead)\n");
    fprintf(f,
        "  --operator FILE      a scripted operator: CSV, a header \"time_s\" then the\n"
        "                       robot's input names ([[manifest.inputs]]), one row per\n"
        "                       change (seconds of simulated time, a value per input),\n"
        "                       each row's values held until the next (docs/rozrun.md)\n"
        "  --deploy FILE        run the deploy sequence of FILE around the controller\n"
        "                       (docs/deploy.md): zero torque until start, the stand pose\n"
        "                       over move_s, held until run, the controller, stand back\n"
        "                       to the pose, stop in damping; switched by the inputs FILE\n"
        "                       names (--operator) or --stage-at\n"
        "                       (with --check: FILE checked against the robot, not run)\n"
        "  --stage-at T:STAGE   ask for a stage before tick T (--deploy): move (start, or\n"
        "                       back to the stand from run), run, stop, zero (from stop)\n"
        "  --gamepad DEV        a Linux gamepad (/dev/input/eventN) as the operator's\n"
        "                       remote: its sticks, triggers and buttons feed the inputs\n"
        "                       whose source is a remote.* field, and the remote's e-stop;\n"
        "                       with a simulator, --realtime keeps its time the wall's\n"
        "  --teleop SOCKET      an operator's twists and joysticks (roz-live --teleop:\n"
        "                       Foxglove's Teleop and Joystick panels): a UNIX datagram\n"
        "                       socket made here (mode 0600), a twist handed to the inputs\n"
        "                       whose source is a twist field, a joystick to those of a\n"
        "                       remote.* field, by the map it carries (roz-live --joy-map)\n"
        "                       or the Joystick panel's gamepad layout (docs/live.md)\n"
        "  --estop-at T         press the e-stop input before tick T: e-stop latches at T\n"
        "                       and stays latched, even through clears, while pressed\n"
        "  --estop-release-at T release it before tick T (the fault stays latched until\n"
        "                       a clear)\n"
        "  --clear-at T         clear the latched faults before tick T (a controller that\n"
        "                       trapped is rebuilt and verified first)\n"
        "  --swap-at T:FILE     load, verify and install another controller to drive from\n"
        "                       tick T (from 1); refused, the running one stays\n"
        "                       These five are repeatable; at one tick the e-stop input\n"
        "                       comes first, then the stage, the swap, the clear. In simulated\n"
        "                       time each takes effect exactly at tick T; with --realtime\n"
        "                       or a robot's port clears and swaps run on a loader thread\n"
        "                       once tick T-1 is done and take effect at the next tick\n"
        "                       boundary after.\n"
        "  --help               this text\n"
        "\n"
        "Exit status: 0 no fault latched at the end, 1 a fault latched at the end, 2 bad\n"
        "arguments or refused controller, 3 the trace or recording could not be written;\n"
        "--replay: 0 identical (or another controller ran through), 4 diverged, 2 a\n"
        "recording that cannot be read.\n");
    const roz_port_entry_t *pe = port != NULL ? roz_ports_find(port) : NULL;
    if (pe != NULL)
        usage_port(f, pe);
}

static void log_stderr(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    fprintf(stderr, "rozrun: %s: %s\n",
            level == ROZ_LOG_ERROR ? "error" : level == ROZ_LOG_WARN ? "warning" : "info", msg);
}

static void on_signal(int sig)
{
    (void)sig;
    atomic_store(&interrupted, 1);
}

static int parse_u64(const char *opt, const char *v, uint64_t max, uint64_t *out)
{
    char *end;
    if (v == NULL || v[0] < '0' || v[0] > '9') {
        fprintf(stderr, "rozrun: %s needs a non-negative integer, got \"%s\"\n", opt,
                v ? v : "");
        return -1;
    }
    errno = 0; /* strtoull reports overflow only through errno */
    unsigned long long x = strtoull(v, &end, 10);
    if (errno != 0 || *end != '\0' || x > max) {
        fprintf(stderr, "rozrun: %s \"%s\": expected an integer in 0..%llu\n", opt, v,
                (unsigned long long)max);
        return -1;
    }
    *out = x;
    return 0;
}

/* @p opt's value in 1..max, or when @p off also "off", read as UINT64_MAX;
 * -1 after saying what it must be. */
static int parse_positive(const char *opt, const char *v, uint64_t max, int off, uint64_t *out)
{
    if (off && v != NULL && !strcmp(v, "off")) {
        *out = UINT64_MAX;
        return 0;
    }
    if (parse_u64(opt, v, max, out) || *out == 0) {
        fprintf(stderr, "rozrun: %s must be in 1..%llu%s\n", opt, (unsigned long long)max,
                off ? ", or off" : "");
        return -1;
    }
    return 0;
}

/* --record-compress, or zstd when this build has it */
static int record_compression(const options_t *o)
{
    if (o->record_compression >= 0)
        return o->record_compression;
    return roz_mcap_compression_supported(ROZ_MCAP_COMPRESS_ZSTD) ? ROZ_MCAP_COMPRESS_ZSTD
                                                                   : ROZ_MCAP_COMPRESS_NONE;
}

static int parse_args(int argc, char **argv, options_t *o)
{
    memset(o, 0, sizeof *o);
    o->record_compression = -1;
    o->port = "loopback";
    o->ticks = 1000;
    o->priority = 80;
    o->stale_ticks = 10;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        uint64_t x;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout, o->port_given ? o->port : NULL);
            exit(0);
        } else if (!strcmp(a, "--realtime")) {
            o->realtime = 1;
            continue;
        } else if (!strcmp(a, "--allow-other-robot")) {
            o->allow_other_robot = 1;
            continue;
        } else if (!strcmp(a, "--check")) {
            o->check = 1;
            continue;
        }
        static const char *const valued[] = { "--robot", "--controller", "--port", "--trace",
                                              "--record", "--live", "--replay", "--record-every", "--record-compress",
                                              "--summary-json",
                                              "--ticks", "--priority", "--budget-us",
                                              "--stale-ticks", "--param", "--fuel", "--fuel-max",
                                              "--estop-at", "--estop-release-at", "--clear-at",
                                              "--swap-at", "--operator", "--deploy",
                                              "--stage-at", "--gamepad", "--teleop", NULL };
        int known = 0;
        for (const char *const *k = valued; *k != NULL && !known; k++)
            known = strcmp(*k, a) == 0;
        if (!known) {
            fprintf(stderr, "rozrun: unknown option \"%s\" (see --help)\n", a);
            return -1;
        }
        if (v == NULL) {
            fprintf(stderr, "rozrun: %s needs a value (see --help)\n", a);
            return -1;
        }
        i++;
        if (!strcmp(a, "--robot")) {
            o->robot = v;
        } else if (!strcmp(a, "--controller")) {
            o->controller = v;
        } else if (!strcmp(a, "--port")) {
            o->port = v;
            o->port_given = 1;
        } else if (!strcmp(a, "--trace")) {
            o->trace = v;
        } else if (!strcmp(a, "--record")) {
            o->record = v;
        } else if (!strcmp(a, "--live")) {
            o->live = v;
        } else if (!strcmp(a, "--record-every")) {
            if (parse_positive(a, v, 1000000, 0, &x))
                return -1;
            o->record_every = (uint32_t)x;
        } else if (!strcmp(a, "--record-compress")) {
            o->record_compression = !strcmp(v, "zstd") ? ROZ_MCAP_COMPRESS_ZSTD
                                    : !strcmp(v, "none") ? ROZ_MCAP_COMPRESS_NONE : -2;
            if (o->record_compression == -2 ||
                !roz_mcap_compression_supported(o->record_compression)) {
                fprintf(stderr, "rozrun: --record-compress \"%s\": %s\n", v,
                        o->record_compression == -2 ? "zstd or none"
                                                    : "this build has no libzstd");
                return -1;
            }
        } else if (!strcmp(a, "--operator")) {
            o->operator_file = v;
        } else if (!strcmp(a, "--deploy")) {
            o->deploy_file = v;
        } else if (!strcmp(a, "--gamepad")) {
            o->gamepad = v;
        } else if (!strcmp(a, "--teleop")) {
            o->teleop = v;
        } else if (!strcmp(a, "--replay")) {
            o->replay = v;
        } else if (!strcmp(a, "--summary-json")) {
            o->summary_json = v;
        } else if (!strcmp(a, "--ticks")) {
            if (parse_u64(a, v, UINT64_MAX / 2, &o->ticks))
                return -1;
        } else if (!strcmp(a, "--priority")) {
            if (parse_positive(a, v, 99, 0, &x))
                return -1;
            o->priority = (int)x;
        } else if (!strcmp(a, "--budget-us")) {
            if (parse_positive(a, v, 10000000, 1, &o->budget_us))
                return -1;
            o->budget_set = 1;
        } else if (!strcmp(a, "--fuel")) {
            /* "off" is the only way to run unmetered: 0 allows nothing */
            if (parse_positive(a, v, UINT64_MAX - 1, 1, &o->fuel))
                return -1;
            o->fuel_set = 1;
        } else if (!strcmp(a, "--fuel-max")) {
            /* as --fuel: "off" lets any declaration through, 0 none */
            if (parse_positive(a, v, UINT64_MAX - 1, 1, &o->fuel_max))
                return -1;
            o->fuel_max_set = 1;
        } else if (!strcmp(a, "--stale-ticks")) {
            if (parse_positive(a, v, 1000000, 0, &x))
                return -1;
            o->stale_ticks = (uint32_t)x;
        } else if (!strcmp(a, "--param")) {
            if (o->n_params == MAX_PARAMS) {
                fprintf(stderr, "rozrun: at most %d --param options\n", MAX_PARAMS);
                return -1;
            }
            if (roz_params_split(argv[i], &o->params[o->n_params]) != ROZ_OK) {
                fprintf(stderr, "rozrun: --param \"%s\": expected KEY=VALUE\n", v);
                return -1;
            }
            o->n_params++;
        } else if (!strcmp(a, "--estop-at") || !strcmp(a, "--estop-release-at") ||
                   !strcmp(a, "--clear-at") || !strcmp(a, "--swap-at") ||
                   !strcmp(a, "--stage-at")) {
            if (rozrun_schedule_add(&sched, a, v) != 0)
                return -1;
        } else {
            fprintf(stderr, "rozrun: unknown option \"%s\" (see --help)\n", a);
            return -1;
        }
    }
    if (o->replay != NULL && o->gamepad != NULL) {
        fprintf(stderr, "rozrun: --gamepad and --replay: a replay feeds the recorded states "
                        "only\n");
        return -1;
    }
#if !ROZRUN_HAS_GAMEPAD
    if (o->gamepad != NULL) {
        fprintf(stderr, "rozrun: --gamepad %s: this build has no gamepad support (Linux's "
                        "linux/input.h)\n", o->gamepad);
        return -1;
    }
#endif
    if (o->replay != NULL && o->teleop != NULL) {
        fprintf(stderr, "rozrun: --teleop and --replay: a replay feeds the recorded states "
                        "only\n");
        return -1;
    }
    if (o->replay != NULL && o->operator_file != NULL) {
        fprintf(stderr, "rozrun: --operator and --replay: a replay feeds the recorded "
                        "states and inputs\n");
        return -1;
    }
    for (size_t k = 0; k < sched.n && o->replay != NULL; k++) {
        if (sched.a[k].kind == ROZRUN_STAGE) {
            fprintf(stderr, "rozrun: --stage-at and --replay: a replay takes the recorded "
                            "stage requests\n");
            return -1;
        }
    }
    for (size_t k = 0; k < sched.n && o->deploy_file == NULL; k++) {
        if (sched.a[k].kind == ROZRUN_STAGE) {
            fprintf(stderr, "rozrun: --stage-at needs --deploy (the sequence it switches)\n");
            return -1;
        }
    }
    if (o->replay != NULL && o->controller != NULL)
        return 0; /* the robot comes from the recording */
    if (o->check) {
        if (o->robot == NULL || o->controller != NULL || o->replay != NULL) {
            fprintf(stderr, "rozrun: --check takes --robot and --port (and --param), no "
                            "controller (see --help)\n");
            return -1;
        }
        return 0;
    }
    if (o->robot == NULL || o->controller == NULL) {
        fprintf(stderr, "rozrun: --robot and --controller are required (see --help)\n");
        return -1;
    }
    return rozrun_schedule_check(&sched, o->ticks);
}

#if ROZ_HAS_TOML
/* A robot.toml read at run time lives in static storage, like everything
 * else rozrun keeps. */
#define ROBOT_TOML_MAX_BYTES (4u << 20)
#define ROBOT_TOML_MAX_PROBLEMS 64u
static char robot_text[ROBOT_TOML_MAX_BYTES];
static roz_manifest_storage_t robot_storage;
static roz_manifest_toml_problem_t robot_problems[ROBOT_TOML_MAX_PROBLEMS];
ROZ_TOML_DOC_DEFINE(robot_doc, 1u << 16, 1u << 20);

/* Loads a robot.toml; on problems prints them as rozgen does. */
static const roz_manifest_t *load_robot_toml(const char *path)
{
    size_t found = 0, shown;
    roz_toml_init(&robot_doc, robot_doc_nodes, sizeof robot_doc_nodes / sizeof robot_doc_nodes[0],
                  robot_doc_arena, sizeof robot_doc_arena);
    int rc = roz_manifest_toml_load_file(path, robot_text, sizeof robot_text, &robot_storage,
                                         &robot_doc, robot_problems, ROBOT_TOML_MAX_PROBLEMS,
                                         &found);
    if (rc == ROZ_OK)
        return &robot_storage.manifest;
    shown = found < ROBOT_TOML_MAX_PROBLEMS ? found : ROBOT_TOML_MAX_PROBLEMS;
    for (size_t i = 0; i < shown; i++)
        fprintf(stderr, "%s%s\n", path, robot_problems[i].text);
    if (found > shown)
        fprintf(stderr, "rozrun: %lu more problems in %s\n", (unsigned long)(found - shown), path);
    if (found == 0)
        fprintf(stderr, "rozrun: --robot %s: %s\n", path, roz_strerror(rc));
    return NULL;
}
#endif

static const roz_manifest_t *find_robot(const char *id)
{
    const roz_manifest_t *m = roz_builtin_find(id);
    if (m != NULL)
        return m;
    size_t n = strlen(id);
    int is_file = strchr(id, '/') != NULL || (n > 5 && strcmp(id + n - 5, ".toml") == 0);
#if ROZ_HAS_TOML
    if (is_file)
        return load_robot_toml(id);
#endif
    if (is_file)
        fprintf(stderr, "rozrun: --robot %s: this build reads no robot.toml at run time "
                        "(ROZ_TOML is OFF); generate its tables with rozgen, or use a built-in "
                        "id:", id);
    else
        fprintf(stderr, "rozrun: --robot \"%s\": no such built-in manifest; known:", id);
    for (size_t i = 0; i < roz_builtin_count(); i++)
        fprintf(stderr, " %s", roz_builtin_at(i)->robot_id);
    fprintf(stderr, "\n");
    return NULL;
}

static uint64_t ticks_run;   /* roz_runtime_tick() calls */
static int last_tick_rc;     /* its last result */
static uint64_t metrics_seen;
static double metric_last = NAN;

/* Telemetry is kept off the tick: drained here, outside it. */
static void drain_metrics(void)
{
    roz_metric_t mt;
    while (roz_runtime_metric_pop(&rt, &mt)) {
        metrics_seen++;
        metric_last = mt.value;
    }
}

static void record_tick(unsigned events)
{
    if (!tracing)
        return;
    const roz_runtime_config_t *cfg = roz_runtime_config(&rt);
    const roz_manifest_t *m = cfg->manifest;
    uint64_t tick = ticks_run - 1;
    double truth[ROZRUN_TRUTH_VALUES];
    int have_truth = trace.truth && rozrun_trace_truth(&cfg->port, truth);
    rozrun_trace_push(&trace, tick, (double)tick / m->control_rate_hz,
                      roz_runtime_last_targets(&rt), roz_runtime_last_commands(&rt),
                      roz_runtime_last_state(&rt), have_truth ? truth : NULL,
                      roz_runtime_faults(&rt), events);
}

/* The tick's thread: the events of this tick are the e-stop input set after
 * the last one and what the loader did before this one started. */
static unsigned input_events; /* the tick's thread's (start-up's before it starts) */

static int tick_fn(void *ctx)
{
    unsigned events = input_events | atomic_exchange(&loader_events, 0u);
    (void)ctx;
    last_tick_rc = roz_runtime_tick(&rt); /* faults are read from the latch */
    ticks_run++;
    record_tick(events);
    if (watching) {
        const roz_runtime_config_t *cfg = roz_runtime_config(&rt);
        rozrun_watch_tick(&watch, &cfg->port, cfg->manifest,
                          last_tick_rc != ROZ_ESTATE ? roz_runtime_last_commands(&rt) : NULL,
                          last_tick_rc != ROZ_ESTATE ? roz_runtime_last_state(&rt) : NULL);
    }
    input_events = rozrun_schedule_inputs(&sched, &rt, ticks_run);
    if (operating)
        rozrun_operator_tick(&op, &rt, ticks_run, roz_runtime_config(&rt)->manifest->control_rate_hz);
    atomic_store(&ticks_done, ticks_run); /* after the inputs: the loader acts on top of them */
    return atomic_load(&interrupted) ? 1 : 0;
}

/* The loader's turn (never the tick's thread while it ticks): the clears
 * and swaps due once @p done ticks have run. */
static void loader_step(uint64_t done)
{
    if (rozrun_schedule_loader_due(&sched, done))
        atomic_fetch_or(&loader_events, rozrun_schedule_loader(&sched, &rt, done));
}

/* One drained tick: to the file and to the live stream. */
static int record_one(void *ctx, const roz_record_t *r)
{
    (void)ctx;
    if (recording && roz_record_file_put(&recfile, r) != ROZ_OK && !record_failed) {
        record_failed = 1;
        fprintf(stderr, "rozrun: %s; the rest of the run goes on without it\n",
                roz_record_file_error(&recfile));
    }
    if (living)
        roz_record_live_put(&live, r);
    return 0;
}

/* Writes the recorder's queued ticks (main thread), then what the live
 * stream's pipe takes without waiting; says once if the file broke. */
static void record_drain(void)
{
    if (!recording && !living)
        return;
    (void)roz_recorder_drain(&recorder, record_one, NULL, 0);
    if (living)
        roz_record_live_flush(&live);
}

/* Writes the queued trace rows (main thread); says once if the file broke. */
static void trace_drain(void)
{
    if (tracing && rozrun_trace_drain(&trace) != 0 && !trace_failed) {
        trace_failed = 1;
        fprintf(stderr, "rozrun: %s; the rest of the run goes on without it\n", trace.error);
    }
}

static void print_ns(const char *label, const roz_monitor_t *mon, roz_monitor_kind_t k)
{
    static roz_monitor_stat_t s; /* 2 KiB: not on the stack */
    if (roz_monitor_snapshot(mon, k, &s) != ROZ_OK || s.count == 0) {
        printf("  %-22s -\n", label);
        return;
    }
    printf("  %-22s p50 %8.1f us   p99 %8.1f us   max %8.1f us\n", label,
           roz_monitor_stat_percentile(&s, 50.0) / 1000.0,
           roz_monitor_stat_percentile(&s, 99.0) / 1000.0, s.max_ns / 1000.0);
}

/* The summary's line on the robot the controller was built for. */
static void print_identity(const roz_verify_report_t *rep)
{
    const roz_identity_t *id = &rep->identity;
    static const char *const verdict[] = {
        [ROZ_IDENTITY_SAME] = "this robot",
        [ROZ_IDENTITY_OTHER_ROBOT] = "another robot, allowed by --allow-other-robot",
        [ROZ_IDENTITY_TABLE_CHANGED] = "an older channel table, allowed by --allow-other-robot",
    };
    if (rep->identity_match == ROZ_IDENTITY_NONE || !id->present) {
        printf("  built for              unknown: the controller carries no robot identity\n");
        return;
    }
    printf("  built for              %s (hash %016llx): %s\n", id->robot_id,
           (unsigned long long)id->hash, verdict[rep->identity_match]);
}

/* A joint the controller keeps pushing against a position limit for a
 * second or more in a row, or for half the run (of @ticks): say which,
 * where it is and what the filter holds it to, since the run itself looks
 * normal (the filter's limit stops are no fault). Called once the tick has
 * stopped (roz_runtime_channel_counters()' context). */
#define HELD_WARN_SECONDS 1u
#define HELD_WARN_LINES 8u

static void warn_held_at_limits(uint64_t ticks)
{
    const roz_manifest_t *m = roz_runtime_config(&rt)->manifest;
    const double *state = roz_runtime_last_state(&rt);
    uint64_t long_run = (uint64_t)HELD_WARN_SECONDS * m->control_rate_hz;
    unsigned held = 0;

    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        roz_filter_channel_counters_t cc;
        if (c->type != ROZ_IF_VELOCITY || c->position_state == ROZ_CHANNEL_UNPAIRED ||
            roz_runtime_channel_counters(&rt, i, &cc) != ROZ_OK)
            continue;
        uint64_t longest = cc.stop_longest, all = cc.limit_stops;
        if (!(longest >= long_run || (all >= long_run && 2u * all >= ticks)))
            continue;
        if (held++ >= HELD_WARN_LINES)
            continue;
        const roz_channel_t *p = &m->states[c->position_state];
        printf("  warning                %s held back at a position limit for %llu ticks in a "
               "row (%.2f s), %llu of %llu ticks in all: %s at %g %s, limits [%g, %g] %s less "
               "a margin of %g %s\n",
               c->name, (unsigned long long)longest, (double)longest / m->control_rate_hz,
               (unsigned long long)all, (unsigned long long)ticks, p->name,
               state[c->position_state], p->unit, p->min, p->max, p->unit,
               roz_manifest_limit_margin(p), p->unit);
    }
    if (held > HELD_WARN_LINES)
        printf("  warning                and %u more held back at a position limit\n",
               held - HELD_WARN_LINES);
}

/* Waiting: the ticks are the first ones, before the port's first usable
 * state frame (the runtime sends nothing until then). */
static void print_waiting(uint64_t waiting, uint64_t ticks)
{
    if (ticks == 0)
        printf("  waiting for state      - (no tick ran)\n");
    else if (waiting == 0)
        printf("  waiting for state      none: the port's first state frame came at tick 0\n");
    else if (waiting < ticks)
        printf("  waiting for state      %llu ticks before the port's first usable state frame "
               "(tick %llu); nothing is sent until the robot's state is known\n",
               (unsigned long long)waiting, (unsigned long long)waiting);
    else
        printf("  waiting for state      all %llu ticks: the port never gave a usable state "
               "frame, so nothing was sent (nothing is until the robot's state is known)\n",
               (unsigned long long)waiting);
}

/* After "faults none": the faults that latched and were cleared. */
static void print_cleared(const roz_runtime_counters_t *c)
{
    int any = 0;
    for (unsigned b = 0; b < ROZ_FAULT_KIND_COUNT; b++) {
        if (c->faults[b] != 0) {
            printf("%s%s %llu time%s", any ? ", " : " latched at the end (cleared during the run: ",
                   roz_fault_name(1u << b), (unsigned long long)c->faults[b],
                   c->faults[b] == 1 ? "" : "s");
            any = 1;
        }
    }
    if (any)
        printf(")");
}

static void summary(const options_t *o, const roz_port_t *port, const roz_verify_report_t *rep,
                    const roz_runner_t *runner)
{
    roz_port_link_counters_t link;
    (void)roz_port_link_counters(port, &link);
    int robot = (roz_port_caps(port) & ROZ_PORT_CAP_ROBOT) != 0;
    const roz_manifest_t *m = roz_runtime_config(&rt)->manifest;
    roz_runtime_stats_t st;
    if (roz_runtime_stats(&rt, &st) != ROZ_OK)
        memset(&st, 0, sizeof st);
    const roz_filter_counters_t *fc = &st.filter;
    const roz_abi_counters_t *c = &st.abi;
    uint64_t clamped = fc->clamps + c->set_clamped, nonfinite = fc->nonfinite;
    uint64_t bad_index = c->set_bad_index + c->get_bad_index, sets = c->sets;
    uint64_t metrics = c->metrics;
    unsigned faults = roz_runtime_faults(&rt);

    printf("\n== rozrun summary ==\n");
    printf("  robot                  %s (%s, %u Hz, %u commands, %u states)\n", m->robot_id,
           m->robot_class, (unsigned)m->control_rate_hz, (unsigned)m->n_commands,
           (unsigned)m->n_states);
    printf("  controller             %s\n", o->controller);
    print_identity(rep);
    printf("  port                   %s%s\n", o->port,
           o->realtime ? " (realtime)" : robot ? " (the robot's time)" : " (simulated time)");
    printf("  verify                 %u ticks, max %.1f us, mean %.1f us per tick\n",
           (unsigned)rep->ticks_run, rep->max_process_ns / 1000.0,
           rep->ticks_run ? rep->total_process_ns / 1000.0 / rep->ticks_run : 0.0);
    char budget[32] = "off";
    if (rep->fuel_budget != ROZ_BUDGET_OFF)
        snprintf(budget, sizeof budget, "%llu", (unsigned long long)rep->fuel_budget);
    printf("  fuel per tick          verify max %llu, run max %llu, last %llu units; budget %s\n",
           (unsigned long long)rep->max_fuel, (unsigned long long)st.runtime.max_fuel,
           (unsigned long long)st.runtime.last_fuel, budget);
    printf("  native stack           verify max %llu, run max %llu bytes; limit %u\n",
           (unsigned long long)rep->max_stack, (unsigned long long)st.runtime.max_stack,
           (unsigned)ROZ_CFG_NATIVE_STACK_BYTES);
    printf("  ticks                  %llu (the controller ran in %llu)\n",
           (unsigned long long)st.runtime.ticks, (unsigned long long)st.runtime.controller_ticks);
    print_waiting(st.runtime.waiting_ticks, st.runtime.ticks);
    printf("  commands written       %llu frames, %llu command.set calls\n",
           (unsigned long long)st.runtime.writes, (unsigned long long)sets);
    printf("  clamps                 %llu\n", (unsigned long long)clamped);
    printf("  rate caps              %llu\n", (unsigned long long)fc->rate_caps);
    printf("  limit stops            %llu\n", (unsigned long long)fc->limit_stops);
    warn_held_at_limits(fc->ticks); /* after the run: the tick has stopped */
    printf("  refused values         %llu non-finite, %llu bad indices\n",
           (unsigned long long)nonfinite, (unsigned long long)bad_index);
    printf("  stale reads            %llu\n", (unsigned long long)st.runtime.stale_reads);
    if (roz_port_caps(port) & ROZ_PORT_CAP_CRC)
        printf("  state link             %llu frames taken, %llu bad CRC, %llu replays, %llu "
               "missing, %llu peer restarts\n",
               (unsigned long long)link.accepted, (unsigned long long)link.crc_errors,
               (unsigned long long)link.replays, (unsigned long long)link.missing,
               (unsigned long long)(link.restarts + link.returns));
    else /* ROS 2 topics: no CRC; what the port checks instead */
        printf("  state link             %llu samples taken, no CRC on the wire, %llu malformed, "
               "%llu replays, %llu missing, %llu peer restarts\n",
               (unsigned long long)link.accepted, (unsigned long long)link.malformed,
               (unsigned long long)link.replays, (unsigned long long)link.missing,
               (unsigned long long)(link.restarts + link.returns));
    drain_metrics();
    printf("  metrics                %llu emitted, %llu received (last %g), %llu dropped\n",
           (unsigned long long)metrics, (unsigned long long)metrics_seen, metric_last,
           (unsigned long long)roz_runtime_metrics_dropped(&rt));
    if (faults == 0) {
        printf("  faults                 none");
        print_cleared(&st.runtime);
        printf("\n");
    } else {
        printf("  faults                 latched:");
        for (unsigned b = 0; b < ROZ_FAULT_KIND_COUNT; b++) {
            if (faults & (1u << b))
                printf(" %s", roz_fault_name(1u << b));
        }
        printf(" (first: %s)\n", roz_runtime_fault_message(&rt));
    }
    char line[256];
    rozrun_schedule_summary(&sched, line, sizeof line);
    if (line[0] != '\0')
        printf("  interventions          %s\n", line);
    if (roz_runtime_stage(&rt) != ROZ_STAGE_NONE) {
        const roz_stages_counters_t *sc = roz_runtime_stages_counters(&rt);
        printf("  deploy                 stage %s at the end; %llu stage changes, %llu "
               "requests refused; hand-overs %llu (gain targets raised %llu)\n",
               roz_stage_name(roz_runtime_stage(&rt)), (unsigned long long)sc->transitions,
               (unsigned long long)sc->refused, (unsigned long long)sc->handovers,
               (unsigned long long)sc->handover_raised);
    }
    if (o->teleop != NULL) {
        const roz_inputs_counters_t *ic = roz_runtime_input_counters(&rt);
        printf("  teleop                 %llu twists from %s, %llu joysticks, %llu malformed "
               "refused; inputs clamped %llu, refused (non-finite) %llu, gone stale %llu\n",
               (unsigned long long)atomic_load(&teleop.twists), o->teleop,
               (unsigned long long)atomic_load(&teleop.joys),
               (unsigned long long)atomic_load(&teleop.refused),
               (unsigned long long)ic->clamped, (unsigned long long)ic->nonfinite,
               (unsigned long long)ic->stale);
    }
    if (operating) {
        const roz_inputs_counters_t *ic = roz_runtime_input_counters(&rt);
        printf("  operator               %lu rows from %s; inputs clamped %llu, refused "
               "(non-finite) %llu, gone stale %llu\n", (unsigned long)op.n_rows, op.path,
               (unsigned long long)ic->clamped, (unsigned long long)ic->nonfinite,
               (unsigned long long)ic->stale);
    }
    print_ns("process() time", roz_runtime_monitor(&rt), ROZ_MON_PROCESS);
    print_ns("tick time", roz_runtime_monitor(&rt), ROZ_MON_TICK);
    if (runner != NULL) {
        print_ns("wake-up jitter", &runner->monitor, ROZ_MON_JITTER);
        printf("  scheduling             %s, memory %s, %llu deadlines missed%s\n",
               runner->realtime ? "SCHED_FIFO"
               : o->realtime   ? "normal (SCHED_FIFO not permitted)"
                               : "normal (no --realtime)",
               runner->locked ? "locked" : "not locked",
               (unsigned long long)runner->missed,
               realtime_degraded ? "; the deadline on the controller's CPU time" : "");
    }
    print_report(port, ROZ_PORT_REPORT_SUMMARY);
    if (recording && roz_recorder_dropped(&recorder) == 0)
        printf("  recording              %s (%llu ticks, none dropped)%s\n", o->record,
               (unsigned long long)roz_record_file_ticks(&recfile),
               record_failed ? ", incomplete" : "");
    else if (recording)
        printf("  recording              %s (%llu ticks; %lu dropped, the ring had no room for "
               "them)%s\n",
               o->record, (unsigned long long)roz_record_file_ticks(&recfile),
               (unsigned long)roz_recorder_dropped(&recorder),
               record_failed ? ", incomplete" : "");
    if (living) {
        uint64_t ld = roz_record_live_dropped(&live);
        printf("  live                   %s: %llu of %llu ticks sent, %llu dropped", o->live,
               (unsigned long long)roz_record_live_sent(&live),
               (unsigned long long)roz_record_live_ticks(&live), (unsigned long long)ld);
        if (roz_record_live_error(&live)[0] != '\0')
            printf(" (%s)", roz_record_live_error(&live));
        else if (ld != 0)
            printf(" (the viewer did not keep up)");
        if (!recording && roz_recorder_dropped(&recorder) != 0)
            printf("; %lu more the ring had no room for",
                   (unsigned long)roz_recorder_dropped(&recorder));
        printf("\n");
    }
    if (tracing && trace.error[0] != '\0')
        printf("  trace                  %s is incomplete: %s\n", o->trace, trace.error);
    else if (tracing)
        printf("  trace                  %s (%llu rows, %llu dropped)\n", o->trace,
               (unsigned long long)trace.written, (unsigned long long)trace.dropped);
}

/* --summary-json: the summary's figures as JSON (summary_json.h), written to
 * FILE.tmp and renamed; after the run. 0, or -1 (said on stderr). */
static int summary_json(const options_t *o, const roz_port_t *port, const roz_verify_report_t *rep,
                        int status)
{
    static char tmp[ROZRUN_PATH_MAX + 8];
    if (snprintf(tmp, sizeof tmp, "%s.tmp", o->summary_json) >= (int)sizeof tmp) {
        fprintf(stderr, "rozrun: --summary-json %s: the path is too long\n", o->summary_json);
        return -1;
    }
    FILE *f = fopen(tmp, "w");
    if (f == NULL) {
        fprintf(stderr, "rozrun: --summary-json: cannot write %s\n", tmp);
        return -1;
    }
    const roz_manifest_t *m = roz_runtime_config(&rt)->manifest;
    roz_runtime_stats_t st;
    if (roz_runtime_stats(&rt, &st) != ROZ_OK)
        memset(&st, 0, sizeof st);
    unsigned faults = roz_runtime_faults(&rt);
    int first = 1;
    fputc('{', f);
    rozrun_json_key(f, &first, "format");
    rozrun_json_str(f, "rozrun-summary/1");
    rozrun_json_key(f, &first, "robot");
    rozrun_json_str(f, m->robot_id);
    rozrun_json_key(f, &first, "controller");
    rozrun_json_str(f, o->controller);
    rozrun_json_key(f, &first, "built_for");
    rozrun_json_str(f, rep->identity.present ? rep->identity.robot_id : "");
    rozrun_json_key(f, &first, "port");
    rozrun_json_str(f, o->port);
    rozrun_json_key(f, &first, "params");
    fputc('[', f);
    for (size_t i = 0; i < o->n_params; i++) {
        fputs(i > 0 ? ", " : "", f);
        fputc('[', f);
        rozrun_json_str(f, o->params[i].key);
        fputs(", ", f);
        rozrun_json_str(f, o->params[i].value);
        fputc(']', f);
    }
    fputc(']', f);
    rozrun_json_key(f, &first, "rate_hz");
    fprintf(f, "%u", (unsigned)m->control_rate_hz);
    rozrun_json_key(f, &first, "ticks");
    fprintf(f, "%llu", (unsigned long long)st.runtime.ticks);
    rozrun_json_key(f, &first, "controller_ticks");
    fprintf(f, "%llu", (unsigned long long)st.runtime.controller_ticks);
    rozrun_json_key(f, &first, "waiting_ticks");
    fprintf(f, "%llu", (unsigned long long)st.runtime.waiting_ticks);
    rozrun_json_key(f, &first, "exit_status");
    fprintf(f, "%d", status);
    rozrun_json_key(f, &first, "faults");
    fputs("{\"latched\": [", f);
    for (unsigned b = 0, n = 0; b < ROZ_FAULT_KIND_COUNT; b++) {
        if (faults & (1u << b)) {
            fputs(n++ > 0 ? ", " : "", f);
            rozrun_json_str(f, roz_fault_name(1u << b));
        }
    }
    fputs("], \"bits\": ", f);
    fprintf(f, "%u", faults);
    fputs(", \"first\": ", f);
    rozrun_json_str(f, faults != 0 ? roz_runtime_fault_message(&rt) : "");
    fputs(", \"times_latched\": {", f);
    for (unsigned b = 0, n = 0; b < ROZ_FAULT_KIND_COUNT; b++) {
        if (st.runtime.faults[b] != 0) {
            fputs(n++ > 0 ? ", " : "", f);
            rozrun_json_str(f, roz_fault_name(1u << b));
            fprintf(f, ": %llu", (unsigned long long)st.runtime.faults[b]);
        }
    }
    fputs("}}", f);
    const roz_filter_counters_t *fc = &st.filter;
    rozrun_json_key(f, &first, "counters");
    fprintf(f, "{\"clamps\": %llu, \"rate_caps\": %llu, \"limit_stops\": %llu, "
               "\"nonfinite\": %llu, \"bad_indices\": %llu, \"stale_reads\": %llu, "
               "\"read_errors\": %llu, \"write_errors\": %llu, \"writes\": %llu, "
               "\"swaps\": %llu, \"swaps_refused\": %llu, \"rebuilds\": %llu}",
            (unsigned long long)(fc->clamps + st.abi.set_clamped),
            (unsigned long long)fc->rate_caps, (unsigned long long)fc->limit_stops,
            (unsigned long long)fc->nonfinite,
            (unsigned long long)(st.abi.set_bad_index + st.abi.get_bad_index),
            (unsigned long long)st.runtime.stale_reads, (unsigned long long)st.runtime.read_errors,
            (unsigned long long)st.runtime.write_errors, (unsigned long long)st.runtime.writes,
            (unsigned long long)st.runtime.swaps, (unsigned long long)st.runtime.swaps_refused,
            (unsigned long long)st.runtime.rebuilds);
    rozrun_json_key(f, &first, "fuel");
    fprintf(f, "{\"verify_max\": %llu, \"run_max\": %llu, \"last\": %llu, \"budget\": ",
            (unsigned long long)rep->max_fuel, (unsigned long long)st.runtime.max_fuel,
            (unsigned long long)st.runtime.last_fuel);
    if (rep->fuel_budget != ROZ_BUDGET_OFF)
        fprintf(f, "%llu}", (unsigned long long)rep->fuel_budget);
    else
        fputs("null}", f);
    roz_port_link_counters_t link;
    (void)roz_port_link_counters(port, &link);
    rozrun_json_key(f, &first, "link");
    fprintf(f, "{\"accepted\": %llu, \"missing\": %llu, \"restarts\": %llu}",
            (unsigned long long)link.accepted, (unsigned long long)link.missing,
            (unsigned long long)(link.restarts + link.returns));
    rozrun_json_key(f, &first, "port_counters");
#if ROZRUN_HAS_MUJOCO
    if (port->ops == &roz_mujoco_ops) {
        roz_mujoco_counters_t mc;
        roz_mujoco_counters(port->self, &mc);
        fprintf(f, "{\"frames\": %llu, \"frames_dropped\": %llu, \"clamped\": %llu, "
                   "\"saturated\": %llu, \"violations\": %llu}",
                (unsigned long long)mc.frames, (unsigned long long)mc.frames_dropped,
                (unsigned long long)mc.clamped, (unsigned long long)mc.saturated,
                (unsigned long long)mc.violations);
    } else
#endif
        fputs("null", f);
    rozrun_watch_json(f, &first, &watch, m, m->control_rate_hz);
    fputs("\n}\n", f);
    int bad = ferror(f);
    if (fclose(f) != 0 || bad || rename(tmp, o->summary_json) != 0) {
        fprintf(stderr, "rozrun: --summary-json: cannot write %s\n", o->summary_json);
        remove(tmp);
        return -1;
    }
    return 0;
}

static void *no_work(void *arg)
{
    return arg;
}

/* --realtime asks for SCHED_FIFO at @p priority and locked memory; where
 * either is refused the tick would run at normal priority on the wall
 * clock's deadline, which a loaded machine passes by itself. Asked here,
 * before the runtime is set up: 0 when both are granted (the memory stays
 * locked), else 1 with @p why naming what was refused. */
static int realtime_refused(int priority, char *why, size_t len)
{
    roz_thread_config_t tc = { ROZ_THREAD_FIFO, priority, 0, 0 };
    unsigned long t;
    char err[200];
    int fifo = roz_thread_start(&t, &tc, "probe", no_work, NULL, err, sizeof err) == ROZ_OK;
    if (fifo)
        roz_thread_join(t);
    int locked = mlockall(MCL_CURRENT | MCL_FUTURE) == 0;
    if (fifo && locked)
        return 0;
    snprintf(why, len, "%s%s%s refused", fifo ? "" : "SCHED_FIFO", fifo || locked ? "" : " and ",
             locked ? "" : "locked memory");
    return 1;
}

/* --realtime: the port's threads that take a scheduling (roz/hal/thread.h)
 * run SCHED_FIFO one below the tick's priority, unless the command line
 * says otherwise; only where the process may have SCHED_FIFO (elsewhere
 * the runner warns, and the port would refuse to start them). */
static void realtime_thread_defaults(options_t *o, const roz_port_info_t *info)
{
    static const char *const threads[] = { "command_writer", "receive_thread", "dds_threads" };
    static char keys[3][2][40], prio[8];
    roz_thread_config_t probe = { ROZ_THREAD_FIFO, o->priority > 1 ? o->priority - 1 : 1, 0, 0 };
    roz_params_t given = { o->params, o->n_params };
    unsigned long th;
    char err[160];

    if (roz_thread_start(&th, &probe, "probe", no_work, NULL, err, sizeof err) != ROZ_OK)
        return;
    roz_thread_join(th);
    snprintf(prio, sizeof prio, "%d", probe.priority);
    for (size_t t = 0; t < sizeof threads / sizeof threads[0]; t++) {
        snprintf(keys[t][0], sizeof keys[t][0], "%s_sched", threads[t]);
        snprintf(keys[t][1], sizeof keys[t][1], "%s_priority", threads[t]);
        int takes = 0;
        for (size_t i = 0; i < info->n_params; i++)
            takes |= strcmp(info->params[i].key, keys[t][0]) == 0;
        /* with CYCLONEDDS_URI set, Cyclone's threads are that file's to
         * set: the port would refuse roz's (docs/ports/dds.md) */
        if (t == 2 && takes && getenv("CYCLONEDDS_URI") != NULL &&
            getenv("CYCLONEDDS_URI")[0] != '\0') {
            fprintf(stderr, "rozrun: --realtime: CYCLONEDDS_URI is set: Cyclone DDS's own "
                            "threads run as that file sets them (<Threads>), not at "
                            "SCHED_FIFO\n");
            continue;
        }
        if (!takes || roz_params_find(&given, keys[t][0]) != NULL ||
            roz_params_find(&given, keys[t][1]) != NULL || o->n_params + 2 > MAX_PARAMS)
            continue;
        o->params[o->n_params++] = (roz_param_t){ keys[t][0], "fifo" };
        o->params[o->n_params++] = (roz_param_t){ keys[t][1], prio };
    }
}

/* --check: every check the port makes of the robot at open, and nothing
 * run: rozgen --check asks the port this way (rozgen.mujoco). The exit
 * status: 0, or 2 with the port's message. */
static int check_port(const options_t *o, const roz_port_entry_t *pe, const roz_manifest_t *m,
                      char *err, size_t errlen)
{
    roz_port_t port;
    if (make_port(pe, &port) != 0)
        return 2;
    if (roz_builtin_find(o->robot) == NULL)
        roz_port_set_origin(&port, o->robot);
    roz_params_t params = { o->params, o->n_params };
    if (roz_port_open(&port, m, &params, err, errlen) != ROZ_OK) {
        fprintf(stderr, "rozrun: port %s: %s\n", o->port, err);
        return 2;
    }
    roz_port_close(&port);
    printf("rozrun: port %s: %s opens\n", o->port, m->robot_id);
    /* and the deploy file, by the rules a run reads it with */
    static rozrun_deploy_t checked;
    if (o->deploy_file != NULL) {
        if (rozrun_deploy_load(&checked, o->deploy_file, m) != 0)
            return 2;
        printf("rozrun: %s: the deploy sequence fits %s\n", o->deploy_file, m->robot_id);
    }
    return 0;
}

/* The runtime's configuration for this run of @p m on @p port, the
 * recorder's ring allocated when a recording or a live stream is asked
 * for. Returns whether the tick is paced (real time, or a robot's own),
 * or -1 when the ring cannot be had (said). */
static int configure(const options_t *o, const roz_manifest_t *m, const roz_port_t *port,
                     roz_runtime_config_t *cfg)
{
    roz_runtime_config_default(cfg);
    cfg->manifest = m;
    cfg->port = *port;
    cfg->clock = roz_clock_monotonic_ns;
    /* the deadline counts the controller's own time unless the tick is
     * real-time, where the wall clock is the requirement (docs/budget.md);
     * --realtime without the privilege fails closed: said now, and judged
     * on the CPU time (rozrun_realtime_refused) */
    char why[80];
    if (o->realtime && realtime_refused(o->priority, why, sizeof why)) {
        fprintf(stderr, "rozrun: --realtime: %s: the tick runs at normal priority, and its "
                        "deadline counts the controller's CPU time, not the wall clock\n",
                why);
        realtime_degraded = 1;
    }
    if (!o->realtime || realtime_degraded)
        cfg->deadline_clock = roz_clock_thread_cpu_ns;
    cfg->log = log_stderr;
    cfg->stale_ticks = o->stale_ticks;
    /* a robot keeps its own time */
    int paced = o->realtime || (roz_port_caps(port) & ROZ_PORT_CAP_ROBOT) != 0;
    /* the deadline is wall-clock time, which simulated time is not: there
     * the fuel alone decides unless asked, so a run is deterministic */
    if (o->budget_set)
        cfg->budget_ns = o->budget_us == UINT64_MAX ? UINT64_MAX : o->budget_us * 1000u;
    else if (!paced)
        cfg->budget_ns = UINT64_MAX;
    if (o->fuel_set)
        cfg->fuel_per_tick = o->fuel; /* UINT64_MAX: off */
    if (o->fuel_max_set)
        cfg->fuel_per_tick_max = o->fuel_max; /* UINT64_MAX: any declaration */
    cfg->monitor_jitter = paced; /* simulated time runs ticks back to back */
    cfg->allow_foreign_controller = o->allow_other_robot;
    if (o->record != NULL || o->live != NULL) {
        /* 1024 ticks of room: the main thread drains every 20 ms at most */
        size_t bytes = 1024u * roz_recorder_slot_bytes(m);
        void *ring = malloc(bytes);
        if (ring == NULL ||
            roz_recorder_init(&recorder, m, ring, bytes, o->record_every) != ROZ_OK) {
            fprintf(stderr, "rozrun: no memory for the recorder's ring (%lu bytes)\n",
                    (unsigned long)bytes);
            return -1;
        }
        cfg->recorder = &recorder;
    }
    return paced;
}

/* What the run writes, opened before its first tick: the recording, the
 * live stream, the trace and the summary's watch. 0, or 2 (said). */
static int open_outputs(const options_t *o, const roz_manifest_t *m, roz_port_t *port, char *err,
                        size_t errlen)
{
    /* log times: the wall clock now plus simulated time
     * (docs/recording-format.md), the same in the file and the live stream */
    struct timespec now = { 0, 0 };
    (void)timespec_get(&now, TIME_UTC);
    uint64_t start_ns = (uint64_t)now.tv_sec * 1000000000u + (uint64_t)now.tv_nsec;
    if (o->record != NULL) {
        roz_record_file_options_t ro = { o->controller, start_ns, record_compression(o) };
        if (roz_record_file_open(&recfile, o->record, &rt, &recorder, &ro, err, errlen) !=
            ROZ_OK) {
            fprintf(stderr, "rozrun: cannot record: %s\n", err);
            return 2;
        }
        recording = 1;
    }
    if (o->live != NULL) {
        /* uncompressed: a chunk a tick has little to gain */
        roz_record_file_options_t lo = { o->controller, start_ns, ROZ_MCAP_COMPRESS_NONE };
        /* a viewer that went away must end the stream, not the run */
        signal(SIGPIPE, SIG_IGN);
        if (roz_record_live_open(&live, o->live, &rt, &recorder, &lo, err, errlen) != ROZ_OK) {
            fprintf(stderr, "rozrun: --live: %s\n", err);
            return 2;
        }
        living = 1;
    }
    if (o->trace != NULL) {
        double truth[ROZRUN_TRUTH_VALUES]; /* a simulator's base pose: traced too */
        int has_truth = rozrun_trace_truth(port, truth);
        if (rozrun_trace_open(&trace, o->trace, m, has_truth, err, errlen) != 0) {
            fprintf(stderr, "rozrun: %s\n", err);
            return 2;
        }
        tracing = 1;
    }
    if (o->summary_json != NULL) {
        rozrun_watch_init(&watch, o->ticks);
        watching = 1;
    }
    return 0;
}

/* The ticks: paced by the periodic thread (this thread the loader, and
 * the one that writes) until o->ticks or Ctrl-C, or back to back in
 * simulated time. 0, or 2 when the thread cannot start (said). */
static int run_ticks(const options_t *o, const roz_manifest_t *m, int paced, roz_runner_t *runner)
{
    if (paced) {
        roz_runner_config_t rc = {
            .period_ns = 1000000000ull / m->control_rate_hz,
            .max_ticks = o->ticks,
            .realtime_priority = o->realtime ? o->priority : 0,
            .lock_memory = o->realtime,
            .log = NULL, /* the runtime warns about command jitter itself */
        };
        if (roz_runner_start(runner, &rc, tick_fn, NULL) != ROZ_OK) {
            fprintf(stderr, "rozrun: cannot start the periodic thread\n");
            return 2;
        }
        /* the runner ends by itself after max_ticks, or on Ctrl-C; this
         * thread is the loader, and the one that writes */
        uint64_t period_ns = 1000000000ull / m->control_rate_hz;
        while (!atomic_load(&interrupted) && !atomic_load(&runner->finished)) {
            /* every 20 ms; every half period while a loader action is due
             * within the next 20 ms */
            struct timespec ts = { 0, 20000000 };
            uint64_t done = atomic_load(&ticks_done);
            loader_step(done);
            if (period_ns / 2u < 20000000u &&
                rozrun_schedule_loader_due(&sched, done + 20000000u / period_ns + 1u))
                ts.tv_nsec = (long)(period_ns / 2u);
            trace_drain();
            record_drain();
            drain_metrics();
            roz_runtime_log_drain(&rt); /* the log is written here, never in the tick */
            nanosleep(&ts, NULL);
        }
        roz_runner_stop(runner);
        roz_runner_join(runner);
    } else {
        for (uint64_t t = 0; (o->ticks == 0 || t < o->ticks) && !atomic_load(&interrupted); t++) {
            /* between ticks the loader acts: each clear or swap takes
             * effect exactly at its tick, and runs are deterministic */
            loader_step(t);
            tick_fn(NULL);
            trace_drain();
            record_drain();
            drain_metrics();
            roz_runtime_log_drain(&rt); /* between ticks: the application's idle time */
        }
    }
    return 0;
}

/* After the last tick: the outputs closed, the summary printed, everything
 * released. Returns the exit status: 0, 1 when a fault latched, 3 when the
 * run's record (trace, recording, summary) is incomplete. */
static int finish(const options_t *o, roz_port_t *port, const roz_verify_report_t *rep,
                  const roz_runner_t *runner, char *err, size_t errlen)
{
    roz_runtime_log_drain(&rt);
    rozrun_teleop_close(&teleop); /* no twist after the last tick */
    if (rozrun_schedule_left(&sched) != 0)
        fprintf(stderr, "rozrun: %lu scheduled interventions not carried out: the run ended "
                        "first\n", (unsigned long)rozrun_schedule_left(&sched));
    roz_port_deactivate(port);
    if (tracing && rozrun_trace_close(&trace) != 0 && !trace_failed)
        fprintf(stderr, "rozrun: %s\n", trace.error);
    record_drain(); /* the rest, into the file and the stream */
    if (living)
        roz_record_live_close(&live, LIVE_CLOSE_WAIT_MS);
    if (recording && roz_record_file_close(&recfile, err, errlen) != ROZ_OK) {
        if (!record_failed)
            fprintf(stderr, "rozrun: %s\n", err);
        record_failed = 1;
    }
    summary(o, port, rep, runner);
    unsigned faults = roz_runtime_faults(&rt);
    int status = (tracing && trace.error[0] != '\0') || record_failed ? 3 : faults != 0 ? 1 : 0;
    if (watching && summary_json(o, port, rep, status) != 0)
        status = 3;
#if ROZRUN_HAS_GAMEPAD
    roz_gamepad_close(&gamepad); /* before the runtime its sink writes to */
#endif
    roz_runtime_deinit(&rt);
    roz_port_close(port);
    free(port_self);
    port_self = NULL;
    rozrun_schedule_free(&sched); /* the runtime has let go of the swapped controllers */
    rozrun_operator_free(&op);
    /* 3: the run's record is incomplete: not a success, whatever latched */
    return status;
}

int main(int argc, char **argv)
{
    options_t o;
    roz_runtime_config_t cfg;
    roz_verify_report_t rep;
    static char err[ROZRUN_PATH_MAX + 256]; /* start-up; messages quote paths whole */
    size_t len = 0;

    if (parse_args(argc, argv, &o) != 0)
        return 2;
    if (o.replay != NULL && o.live != NULL) {
        fprintf(stderr, "rozrun: --live streams a run on a port, not a --replay\n");
        return 2;
    }
    if (o.replay != NULL) {
        rozrun_replay_options_t ro = { o.replay, o.controller, o.robot, o.record, o.trace,
                                       record_compression(&o), o.deploy_file };
        if (o.robot != NULL && find_robot(o.robot) == NULL)
            return 2;
        return rozrun_replay(&ro, o.robot != NULL ? find_robot(o.robot) : NULL);
    }
    const roz_manifest_t *m = find_robot(o.robot);
    if (m == NULL)
        return 2;
    const roz_port_entry_t *pe = find_port(o.port);
    if (pe == NULL)
        return 2;
    if (o.check)
        return check_port(&o, pe, m, err, sizeof err);
    static uint8_t wasm[ROZ_CFG_WASM_MAX_MODULE_BYTES];
    if (roz_module_read_file(o.controller, wasm, sizeof wasm, &len, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "rozrun: %s\n", err);
        return 2;
    }
    if (rozrun_schedule_read_modules(&sched) != 0)
        return 2;
    if (o.operator_file != NULL) {
        if (rozrun_operator_load(&op, o.operator_file, m) != 0)
            return 2;
        operating = 1;
    }
    /* before the port opens: a socket that cannot be made stops the run
     * before the robot is touched */
    if (o.teleop != NULL && rozrun_teleop_open(&teleop, o.teleop) != 0)
        return 2;

    static rozrun_deploy_t deploy;
    if (o.deploy_file != NULL && rozrun_deploy_load(&deploy, o.deploy_file, m) != 0)
        return 2;

    roz_port_t port;
    if (make_port(pe, &port) != 0)
        return 2;
    if (roz_builtin_find(o.robot) == NULL)
        roz_port_set_origin(&port, o.robot); /* a robot.toml: its paths are relative to it */
    if (o.realtime)
        realtime_thread_defaults(&o, roz_port_ops_info(pe->ops));
    roz_params_t params = { o.params, o.n_params };
    if (roz_port_open(&port, m, &params, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "rozrun: port %s: %s\n", o.port, err);
        return 2;
    }
    print_report(&port, ROZ_PORT_REPORT_OPENED);
    int paced = configure(&o, m, &port, &cfg);
    if (paced < 0)
        return 2;
    if (roz_runtime_init(&rt, &cfg) != ROZ_OK) {
        fprintf(stderr, "rozrun: cannot set up the runtime for %s\n", m->robot_id);
        roz_port_close(&port);
        return 2;
    }
    if (o.deploy_file != NULL &&
        roz_runtime_stages_set(&rt, &deploy.cfg, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "rozrun: %s: %s\n", o.deploy_file, err); /* checked when read */
        roz_port_close(&port);
        return 2;
    }
    if (roz_runtime_load(&rt, wasm, len, &rep) != ROZ_OK) {
        fprintf(stderr, "rozrun: controller %s refused: %s\n", o.controller,
                roz_runtime_error(&rt));
        if (!o.allow_other_robot && (rep.identity_match == ROZ_IDENTITY_OTHER_ROBOT ||
                                     rep.identity_match == ROZ_IDENTITY_TABLE_CHANGED))
            fprintf(stderr, "rozrun: --allow-other-robot runs it anyway\n");
        roz_port_close(&port);
        return 2;
    }
    if (open_outputs(&o, m, &port, err, sizeof err) != 0)
        return 2;
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    /* an operator device the port reads (the G1's wireless remote) goes to
     * the inputs that name its fields; a port that reads none says so */
    roz_operator_sink_t sink = roz_runtime_operator_sink(&rt);
    int sink_rc = roz_port_set_operator(&port, &sink);
    if (sink_rc != ROZ_OK && sink_rc != ROZ_ENOTSUP) {
        fprintf(stderr, "rozrun: port %s: cannot take the operator's devices\n", o.port);
        return 2;
    }
#if ROZRUN_HAS_GAMEPAD
    if (o.gamepad != NULL) {
        if (roz_gamepad_open(&gamepad, o.gamepad, err, sizeof err) != 0 ||
            roz_gamepad_start(&gamepad, &sink, err, sizeof err) != 0) {
            fprintf(stderr, "rozrun: --gamepad %s\n", err);
            roz_gamepad_close(&gamepad);
            return 2;
        }
    }
#endif
    if (roz_port_activate(&port) != ROZ_OK || roz_runtime_start(&rt) != ROZ_OK) {
        fprintf(stderr, "rozrun: cannot start port %s\n", o.port);
        return 2;
    }
    if (o.teleop != NULL && rozrun_teleop_start(&teleop, &rt) != 0)
        return 2;

    static roz_runner_t runner;
    sched.simulated = !paced;
    input_events = rozrun_schedule_inputs(&sched, &rt, 0); /* the e-stop input at tick 0 */
    if (operating)
        rozrun_operator_tick(&op, &rt, 0, m->control_rate_hz);
    if (run_ticks(&o, m, paced, &runner) != 0)
        return 2;
    return finish(&o, &port, &rep, paced ? &runner : NULL, err, sizeof err);
}
