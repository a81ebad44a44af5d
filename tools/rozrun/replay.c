/* SPDX-License-Identifier: Apache-2.0 */
#include "replay.h"
#include "deploy.h"
#include "schedule.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "roz/builtin.h"
#include "roz/hal/clock.h"
#include "roz/module.h"
#include "roz/identity.h"
#include "roz/record_file.h"
#include "roz/runtime.h"
#include "trace.h"

/* ---- the replay port: read() plays the recorded tick back ------------------- */

typedef struct {
    const roz_record_t *rec; /* the tick being replayed */
    uint16_t            n_states;
} replay_port_t;

static int replay_read(void *self, double *state, size_t n)
{
    replay_port_t *p = self;
    const roz_record_t *r = p->rec;
    (void)n;
    /* a fresh frame then is a fresh frame now, with the same values; the
     * recorded result otherwise (0, ROZ_ELINK, ...): the runtime keeps its
     * last good state, as it did */
    if (r->flags & ROZ_RECORD_FRESH) {
        memcpy(state, r->state, (size_t)p->n_states * sizeof state[0]);
        return r->read_rc == ROZ_EROBOT ? ROZ_EROBOT : 1;
    }
    return r->read_rc > 0 ? 0 : r->read_rc;
}

static int replay_write(void *self, const double *cmd, size_t n)
{
    (void)self;
    (void)cmd;
    (void)n;
    return ROZ_OK; /* the runtime keeps what it applied: roz_runtime_last_commands() */
}

static int replay_fault(void *self, roz_port_fault_t *out)
{
    (void)self;
    out->what = "the recorded robot";
    out->kind = "fault (replayed)";
    out->code = 0;
    return ROZ_OK;
}

static const roz_port_ops_t replay_ops = {
    .name = "replay", .read = replay_read, .write = replay_write, .fault = replay_fault,
};

/* ---- private ------------------------------------------------------------------ */

static roz_runtime_t rrt;
static roz_recorder_t rrec;
static roz_record_file_t rfile;
static roz_record_reader_t reader;
static rozrun_trace_t rtrace;

static const char *bits_hex(double v, char *buf, size_t n)
{
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    snprintf(buf, n, "%016llx", (unsigned long long)u);
    return buf;
}

/* The first channel whose bits differ in @p a and @p b, or -1. */
static int first_diff(const double *a, const double *b, uint16_t n)
{
    for (uint16_t i = 0; i < n; i++) {
        if (memcmp(&a[i], &b[i], sizeof a[i]) != 0)
            return (int)i;
    }
    return -1;
}

static void say_faults(char *buf, size_t n, unsigned bits)
{
    size_t k = 0;
    buf[0] = '\0';
    if (bits == 0) {
        snprintf(buf, n, "none");
        return;
    }
    for (unsigned b = 0; b < ROZ_FAULT_KIND_COUNT && k < n; b++) {
        if (bits & (1u << b))
            k += (size_t)snprintf(buf + k, n - k, "%s%s", k ? ", " : "", roz_fault_name(1u << b));
    }
}

/* Compares the tick's outputs with the recording; on the first difference
 * fills @p what and returns 1. */
static int compare(const roz_manifest_t *m, const roz_record_t *r, char *what, size_t n)
{
    const double *applied = roz_runtime_last_commands(&rrt);
    const double *target = roz_runtime_last_targets(&rrt);
    unsigned faults = roz_runtime_faults(&rrt);
    char a[24], b[24];
    int i;

    int stage = (int)roz_runtime_stage(&rrt);
    if (stage != r->stage) {
        snprintf(what, n, "deploy stage: recorded %s, replayed %s", roz_stage_name(r->stage),
                 roz_stage_name(stage));
        return 1;
    }
    if (faults != r->faults) {
        char fa[160], fb[160];
        say_faults(fa, sizeof fa, r->faults);
        say_faults(fb, sizeof fb, faults);
        snprintf(what, n, "latched faults: recorded %s, replayed %s", fa, fb);
        return 1;
    }
    /* the inputs the controller read (after the states: roz/inputs.h) */
    const double *in = roz_runtime_last_state(&rrt) + m->n_states;
    if (r->inputs != NULL && (i = first_diff(r->inputs, in, m->n_inputs)) >= 0) {
        snprintf(what, n, "input %s (input %d): recorded %.17g (%s), replayed %.17g (%s)",
                 m->inputs[i].name, i, r->inputs[i], bits_hex(r->inputs[i], a, sizeof a), in[i],
                 bits_hex(in[i], b, sizeof b));
        return 1;
    }
    /* what drove the tick, both sides: the deploy stage's commands while a
     * stage drives, the controller's targets otherwise */
    if ((r->flags & ROZ_RECORD_TARGETS) && target != NULL &&
        (i = first_diff(r->target, target, m->n_commands)) >= 0) {
        snprintf(what, n, "target %s (command %d): recorded %.17g (%s), replayed %.17g (%s)",
                 m->commands[i].name, i, r->target[i], bits_hex(r->target[i], a, sizeof a),
                 target[i], bits_hex(target[i], b, sizeof b));
        return 1;
    }
    if ((r->flags & ROZ_RECORD_WROTE) &&
        (i = first_diff(r->applied, applied, m->n_commands)) >= 0) {
        snprintf(what, n, "applied %s (command %d): recorded %.17g (%s), replayed %.17g (%s)",
                 m->commands[i].name, i, r->applied[i], bits_hex(r->applied[i], a, sizeof a),
                 applied[i], bits_hex(applied[i], b, sizeof b));
        return 1;
    }
    return 0;
}

/* Whether two sequences are the same, bit for bit. */
static int stages_equal(const roz_stages_config_t *a, const roz_stages_config_t *b, uint16_t n)
{
    return memcmp(a->stand, b->stand, (size_t)n * sizeof a->stand[0]) == 0 &&
           memcmp(&a->move_s, &b->move_s, sizeof a->move_s) == 0 &&
           memcmp(&a->stop_damping, &b->stop_damping, sizeof a->stop_damping) == 0 &&
           a->start == b->start && a->run == b->run && a->stand_input == b->stand_input &&
           a->stop == b->stop;
}

/* The robot of the recording: --robot, checked, or the built-in of its id. */
static const roz_manifest_t *replay_robot(const roz_record_run_t *run, const char *path,
                                          const roz_manifest_t *robot)
{
    const roz_manifest_t *m = robot != NULL ? robot : roz_builtin_find(run->robot_id);
    if (m == NULL) {
        fprintf(stderr, "rozrun: %s records robot \"%s\", which is not built in: pass its "
                        "robot.toml with --robot\n", path, run->robot_id);
        return NULL;
    }
    uint64_t h = roz_manifest_interface_hash(m);
    if (strcmp(m->robot_id, run->robot_id) != 0 || h != run->interface_hash ||
        m->n_commands != run->n_commands || m->n_states != run->n_states) {
        fprintf(stderr, "rozrun: %s records robot \"%s\" (interface hash %016llx, %u commands, "
                        "%u states); --robot is \"%s\" (%016llx, %u commands, %u states)\n",
                path, run->robot_id, (unsigned long long)run->interface_hash,
                (unsigned)run->n_commands, (unsigned)run->n_states, m->robot_id,
                (unsigned long long)h, (unsigned)m->n_commands, (unsigned)m->n_states);
        return NULL;
    }
    if (m->n_inputs != run->n_inputs) {
        /* a file from before /roz/inputs: the controller's inputs are not in it */
        fprintf(stderr, "rozrun: %s records %u operator inputs; robot \"%s\" has %u (a "
                        "recording from before /roz/inputs cannot replay a robot with "
                        "inputs)\n", path, (unsigned)run->n_inputs, m->robot_id,
                (unsigned)m->n_inputs);
        return NULL;
    }
    return m;
}

/* ---- public ------------------------------------------------------------------- */

int rozrun_replay(const rozrun_replay_options_t *o, const roz_manifest_t *robot)
{
    static uint8_t wasm[ROZ_CFG_WASM_MAX_MODULE_BYTES];
    static char err[ROZRUN_PATH_MAX + 256], what[ROZRUN_PATH_MAX + 256]; /* start-up */
    size_t len = 0;
    int status = 0, tracing = 0, recording = 0;

    if (roz_record_reader_open(&reader, o->recording, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "rozrun: --replay: %s\n", err);
        return 2;
    }
    const roz_record_run_t *run = roz_record_reader_run(&reader);
    const roz_manifest_t *m = replay_robot(run, o->recording, robot);
    if (m == NULL) {
        roz_record_reader_close(&reader);
        return 2;
    }
    if (run->decimation != 1) {
        fprintf(stderr, "rozrun: %s was recorded every %u ticks: replay needs every tick\n",
                o->recording, (unsigned)run->decimation);
        roz_record_reader_close(&reader);
        return 2;
    }
    if (roz_module_read_file(o->controller, wasm, sizeof wasm, &len, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "rozrun: %s\n", err);
        roz_record_reader_close(&reader);
        return 2;
    }
    uint64_t hash = roz_recorder_hash(wasm, len);

    static replay_port_t rp;
    rp.n_states = m->n_states;
    roz_port_t port = { &replay_ops, &rp, 0 };
    (void)roz_port_open(&port, m, NULL, err, sizeof err); /* no open op: open */
    roz_runtime_config_t cfg;
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = port;
    cfg.clock = roz_clock_monotonic_ns; /* times only: the deadline is off */
    cfg.stale_ticks = run->stale_ticks;
    cfg.fuel_per_tick = run->fuel_per_tick;
    cfg.budget_ns = ROZ_BUDGET_OFF; /* the fuel alone decides, as on any machine */
    cfg.monitor_jitter = 0;
    cfg.allow_foreign_controller = run->allow_foreign_controller;
    if (o->record != NULL) {
        size_t bytes = 64u * roz_recorder_slot_bytes(m);
        void *ring = malloc(bytes);
        if (ring == NULL || roz_recorder_init(&rrec, m, ring, bytes, 1) != ROZ_OK) {
            fprintf(stderr, "rozrun: no memory for the recorder's ring\n");
            return 2;
        }
        cfg.recorder = &rrec;
    }
    if (roz_runtime_init(&rrt, &cfg) != ROZ_OK) {
        fprintf(stderr, "rozrun: cannot set up the runtime for %s\n", m->robot_id);
        return 2;
    }
    /* the recorded deploy sequence, or --deploy's to try another on the
     * recorded run (the stages then differ where the sequences do) */
    static rozrun_deploy_t dep;
    const roz_stages_config_t *seq = roz_record_reader_stages(&reader);
    int seq_same = 1;
    if (o->deploy != NULL) {
        if (rozrun_deploy_load(&dep, o->deploy, m) != 0)
            return 2;
        seq_same = seq != NULL && stages_equal(seq, &dep.cfg, m->n_commands);
        seq = &dep.cfg;
    }
    if (seq != NULL && roz_runtime_stages_set(&rrt, seq, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "rozrun: %s: %s: %s\n", o->deploy != NULL ? o->deploy : o->recording,
                o->deploy != NULL ? "deploy sequence" : "its /roz/deploy", err);
        return 2;
    }
    if (roz_runtime_load(&rrt, wasm, len, NULL) != ROZ_OK) {
        fprintf(stderr, "rozrun: controller %s refused: %s\n", o->controller,
                roz_runtime_error(&rrt));
        return 2;
    }
    if (o->record != NULL) {
        /* on the recorded run's timeline */
        roz_record_file_options_t ro = { o->controller, run->start_time_ns,
                                         o->record_compression };
        if (roz_record_file_open(&rfile, o->record, &rrt, &rrec, &ro, err, sizeof err) != ROZ_OK) {
            fprintf(stderr, "rozrun: cannot record: %s\n", err);
            return 2;
        }
        recording = 1;
    }
    if (o->trace != NULL) {
        if (rozrun_trace_open(&rtrace, o->trace, m, 0, err, sizeof err) != 0) {
            fprintf(stderr, "rozrun: %s\n", err);
            return 2;
        }
        tracing = 1;
    }
    if (roz_runtime_start(&rrt) != ROZ_OK)
        return 2;

    roz_record_t rec;
    uint64_t offset = 0, ticks = 0, differing = 0, first_tick = 0, recorded_hash = 0;
    int same = -1, level = 0, rc, stopped = 0;
    char first[sizeof what] = "";
    uint64_t first_offset = 0;
    while ((rc = roz_record_reader_next(&reader, &rec, &offset, err, sizeof err)) == 1) {
        if (rec.tick != ticks) {
            snprintf(what, sizeof what, "the recording has tick %llu where tick %llu was due: "
                     "ticks are missing (its recorder's ring was full)",
                     (unsigned long long)rec.tick, (unsigned long long)ticks);
            stopped = 1;
            break;
        }
        if (rec.controller_hash != 0) {
            if (same < 0) {
                recorded_hash = rec.controller_hash;
                same = recorded_hash == hash;
            } else if (rec.controller_hash != recorded_hash) {
                snprintf(what, sizeof what, "the recording swaps to another controller (hash "
                         "%016llx) at tick %llu: replayed up to there",
                         (unsigned long long)rec.controller_hash, (unsigned long long)rec.tick);
                stopped = 1;
                break;
            }
        }
        /* the inputs of the tick, as they came then */
        int lv = (rec.flags & ROZ_RECORD_ESTOP_LEVEL) != 0;
        if (lv != level)
            roz_runtime_estop_set(&rrt, lv);
        else if ((rec.flags & ROZ_RECORD_ESTOP_PRESS) && !lv)
            roz_runtime_estop(&rrt);
        level = lv;
        if (rec.flags & ROZ_RECORD_CLEAR)
            if (roz_runtime_clear_faults(&rrt) != ROZ_OK) { /* as it did then, or not */
            }
        /* the operator's inputs as the controller read them then: each is
         * within its limits and within its rate cap of the last, so the
         * tick's rules give it back bit for bit (roz_inputs_tick()) */
        for (uint16_t k = 0; rec.inputs != NULL && k < m->n_inputs; k++)
            (void)roz_runtime_input_set(&rrt, k, rec.inputs[k]);
        /* the stage request the tick took then (rozrun --stage-at, the API);
         * the buttons' transitions come from the inputs above */
        if (rec.stage_request >= 0)
            (void)roz_runtime_stage_request(&rrt, (roz_stage_t)rec.stage_request);
        rp.rec = &rec;
        if (roz_runtime_tick(&rrt) == ROZ_ESTATE)
            break;
        ticks++;
        if (tracing)
            rozrun_trace_push(&rtrace, rec.tick, (double)rec.tick / m->control_rate_hz,
                              roz_runtime_last_targets(&rrt), roz_runtime_last_commands(&rrt),
                              roz_runtime_last_state(&rrt), NULL, roz_runtime_faults(&rrt), 0);
        if (compare(m, &rec, what, sizeof what)) {
            if (differing++ == 0) {
                first_tick = rec.tick;
                first_offset = offset;
                memcpy(first, what, sizeof first);
            }
            if ((same == 1 || same < 0) && seq_same)
                break; /* the same controller: the first divergence is the report */
        }
        if (tracing)
            (void)rozrun_trace_drain(&rtrace);
        if (recording)
            (void)roz_record_file_drain(&rfile);
    }
    if (rc < 0) {
        fprintf(stderr, "rozrun: --replay: %s\n", err);
        status = 2;
    }
    if (roz_record_reader_warning(&reader)[0] != '\0')
        fprintf(stderr, "rozrun: warning: %s\n", roz_record_reader_warning(&reader));

    printf("\n== rozrun replay ==\n");
    printf("  recording              %s (%s, %u Hz, %u commands, %u states)\n", o->recording,
           m->robot_id, (unsigned)m->control_rate_hz, (unsigned)m->n_commands,
           (unsigned)m->n_states);
    /* the log times are this plus simulated time (docs/recording-format.md) */
    time_t start = (time_t)(run->start_time_ns / 1000000000u);
    const struct tm *utc = run->start_time_ns != 0 ? gmtime(&start) : NULL;
    char when[32] = "unknown (an older file)";
    if (utc != NULL)
        strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", utc);
    printf("  recorded at            %s\n", when);
    printf("  controller             %s (hash %016llx): %s\n", o->controller,
           (unsigned long long)hash,
           same == 1   ? "the recorded one"
           : same == 0 ? "another one than the recorded (hash differs)"
                       : "the recording has no controller");
    if (seq != NULL)
        printf("  deploy                 %s; stage %s at the end\n",
               o->deploy == NULL ? "the recorded sequence"
               : seq_same        ? "the recorded sequence (--deploy: the same)"
                                 : "--deploy's, another than the recorded",
               roz_stage_name(roz_runtime_stage(&rrt)));
    printf("  ticks replayed         %llu\n", (unsigned long long)ticks);
    if (differing == 0 && status == 0) {
        printf("  result                 identical: targets, applied commands and faults "
               "bit for bit at every tick\n");
    } else if (differing != 0 && same != 0 && seq_same) {
        printf("  result                 DIVERGED at tick %llu (file offset %llu): %s\n",
               (unsigned long long)first_tick, (unsigned long long)first_offset, first);
        status = 4;
    } else if (differing != 0) {
        printf("  result                 %llu of %llu ticks differ from the recording, the "
               "first at tick %llu: %s\n", (unsigned long long)differing,
               (unsigned long long)ticks, (unsigned long long)first_tick, first);
    }
    if (stopped)
        printf("  stopped                %s\n", what);
    roz_runtime_log_drain(&rrt);
    if (tracing && rozrun_trace_close(&rtrace) != 0) {
        fprintf(stderr, "rozrun: %s\n", rtrace.error);
        status = status ? status : 3;
    } else if (tracing) {
        printf("  trace                  %s\n", o->trace);
    }
    if (recording && roz_record_file_close(&rfile, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "rozrun: %s\n", err);
        status = status ? status : 3;
    } else if (recording) {
        printf("  new recording          %s (compare: roz-recording compare %s %s "
               "out.png)\n", o->record, o->recording, o->record);
    }
    roz_runtime_deinit(&rrt);
    roz_record_reader_close(&reader);
    return status;
}
