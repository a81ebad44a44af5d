/* SPDX-License-Identifier: Apache-2.0 */
/* Flight recordings as MCAP: the roz messages in ROS 2 CDR (XCDR1, little
 * endian: a 4-byte encapsulation header 00 01 00 00, then every primitive
 * aligned to its size counted from the end of that header; a string is a
 * u32 length with its NUL, the bytes and the NUL; a sequence a u32 count). */
#include "roz/record_file.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "roz/identity.h"

/* ---- types ------------------------------------------------------------------ */

typedef struct {
    unsigned char **p;
    size_t         *cap;
    size_t          len;
    int             oom;
} cdr_t;

static const char tick_schema[] =
    "# one tick of the roz runtime (roz/recorder.h, roz_record_t)\n"
    "uint64 tick\n"
    "int64 controller_tick\n"
    "uint64 sim_time_ns\n"
    "uint64 wall_time_ns\n"
    "uint64 fuel\n"
    "uint64 process_ns\n"
    "uint64 tick_ns\n"
    "uint64 controller_hash\n"
    "uint32 faults\n"
    "uint32 cleared\n"
    "int32 read_rc\n"
    "uint32 flags\n"
    "bool fresh\n"
    "bool ran\n"
    "bool wrote\n"
    "# the safety filter's counters after this tick, totals since the start (as\n"
    "# rozrun's summary counts them; absent in files before them)\n"
    "uint64 clamps  # values moved into [min, max], at command.set or by the filter\n"
    "uint64 rate_caps  # values held back by max_rate\n"
    "uint64 limit_stops  # values held back by position-limit enforcement\n"
    "uint64 nonfinite  # non-finite targets replaced by the safe default\n";

static const char run_schema[] =
    "# a roz run, once per recording\n"
    "string robot_id\n"
    "string robot_class\n"
    "uint32 control_rate_hz\n"
    "uint64 interface_hash\n"
    "string[] command_names\n"
    "string[] state_names\n"
    "uint32 stale_ticks\n"
    "uint64 fuel_per_tick\n"
    "uint64 budget_ns\n"
    "uint32 decimation\n"
    "bool allow_foreign_controller\n"
    "# the wall clock (Unix time, ns) at tick 0: every message's log time is\n"
    "# start_time_ns + sim_time_ns\n"
    "uint64 start_time_ns\n"
    "# the operator inputs (robot.toml's [[manifest.inputs]]), in /roz/inputs\n"
    "# (absent in files before them)\n"
    "string[] input_names\n";

static const char controller_schema[] =
    "# the controller that drives from this tick on\n"
    "uint64 hash\n"
    "string name\n";

static const char fault_schema[] =
    "# the latched faults changed\n"
    "uint32 faults\n"
    "uint32 cleared\n"
    "string message\n";

static const char deploy_schema[] =
    "# the run's deploy sequence (roz/stages.h, roz_stages_config_t; docs/deploy.md),\n"
    "# once, after /roz/run; a run without a sequence has none\n"
    "float64[] stand  # the stand's command, one per /roz/run command_names entry\n"
    "float64 move_s  # the move to the stand, s\n"
    "float64 stop_damping  # the stop's damping on every damping channel\n"
    "# the inputs that switch (indices into /roz/run's input_names; -1 none)\n"
    "int32 start_input  # zero -> move\n"
    "int32 run_input  # hold -> run\n"
    "int32 stand_input  # run -> move\n"
    "int32 stop_input  # any -> stop\n";

static const char stage_schema[] =
    "# the deploy sequence at a tick where its stage changed or the tick took a\n"
    "# stage request (rozrun --stage-at, roz_runtime_stage_request()); the run\n"
    "# starts in zero\n"
    "uint8 stage  # after the tick: 1 zero, 2 move, 3 hold, 4 run, 5 stop\n"
    "string name\n"
    "int8 request  # the request the tick took, allowed or refused; -1 none\n"
    "string request_name  # \"\" none\n";

static const char truth_schema[] =
    "# a simulator's truth at this tick (roz/port.h, roz_port_truth_t): not a\n"
    "# sensor; what tells standing from fallen\n"
    "bool floating  # false: a fixed base, the pose fields NaN\n"
    "float64 x  # base position, m, world\n"
    "float64 y\n"
    "float64 height  # base height above the ground (world z), m\n"
    "float64 qw  # base orientation\n"
    "float64 qx\n"
    "float64 qy\n"
    "float64 qz\n"
    "float64 roll  # rad, Z-Y-X\n"
    "float64 pitch\n"
    "float64 yaw\n"
    "uint32 contacts  # contacts between the robot and the ground\n"
    "string[] bodies  # the robot's bodies touching the ground (at most 8)\n";

/* ---- CDR ---------------------------------------------------------------------- */

static void cdr_begin(cdr_t *c, unsigned char **p, size_t *cap)
{
    c->p = p;
    c->cap = cap;
    c->len = 0;
    c->oom = 0;
    static const unsigned char hdr[4] = { 0x00, 0x01, 0x00, 0x00 }; /* CDR_LE */
    if (*cap < 4096u) {
        unsigned char *n = realloc(*p, 4096u);
        if (n == NULL) {
            c->oom = 1;
            return;
        }
        *p = n;
        *cap = 4096u;
    }
    memcpy(*p, hdr, 4);
    c->len = 4;
}

static void cdr_raw(cdr_t *c, const void *src, size_t n)
{
    if (c->oom)
        return;
    if (c->len + n > *c->cap) {
        size_t cap = *c->cap * 2u;
        while (cap < c->len + n)
            cap *= 2u;
        unsigned char *p = realloc(*c->p, cap);
        if (p == NULL) {
            c->oom = 1;
            return;
        }
        *c->p = p;
        *c->cap = cap;
    }
    memcpy(*c->p + c->len, src, n);
    c->len += n;
}

static void cdr_align(cdr_t *c, size_t a)
{
    static const unsigned char zero[8] = { 0 };
    size_t pad = (a - (c->len - 4u) % a) % a;
    cdr_raw(c, zero, pad);
}

static void cdr_u(cdr_t *c, uint64_t v, size_t bytes)
{
    unsigned char t[8];
    cdr_align(c, bytes);
    for (size_t i = 0; i < bytes; i++)
        t[i] = (unsigned char)(v >> (8u * i));
    cdr_raw(c, t, bytes);
}

static void cdr_f64(cdr_t *c, double v)
{
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    cdr_u(c, u, 8);
}

static void cdr_str(cdr_t *c, const char *s)
{
    size_t n = strlen(s) + 1u;
    cdr_u(c, n, 4);
    cdr_raw(c, s, n);
}

/* ---- field names -------------------------------------------------------------- */

/* A channel's field name (see the header); @p taken: the names so far, for
 * uniqueness. */
static void field_name(const roz_channel_t *ch, size_t index, char *out, size_t cap,
                       const char *taken, size_t taken_len)
{
    size_t k = 0;
    int sep = 0;
    for (const char *s = ch->name; *s != '\0' && k + 12u < cap; s++) {
        char c = *s;
        if (c >= 'A' && c <= 'Z')
            c = (char)(c - 'A' + 'a');
        if ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9')) {
            if (sep && k > 0)
                out[k++] = '_';
            sep = 0;
            if (k == 0 && c >= '0' && c <= '9') {
                out[k++] = 'c';
                out[k++] = '_';
            }
            out[k++] = c;
        } else {
            sep = 1;
        }
    }
    if (k == 0)
        out[k++] = 'c';
    out[k] = '\0';
    /* taken: "\nname\n" entries */
    char probe[160];
    snprintf(probe, sizeof probe, "\n%s\n", out);
    if (taken != NULL && taken_len > 0 && strstr(taken, probe) != NULL)
        snprintf(out + k, cap - k, "_%lu", (unsigned long)index);
}

/* The ros2msg text of a manifest's states or commands: one float64 each. */
static char *values_schema(const roz_channel_t *chs, uint16_t n, const char *what)
{
    size_t cap = 128u + (size_t)n * 96u, len = 0;
    char *text = malloc(cap), *taken = malloc(cap);
    size_t taken_len = 0;
    if (text == NULL || taken == NULL) {
        free(text);
        free(taken);
        return NULL;
    }
    taken[0] = '\n';
    taken[1] = '\0';
    taken_len = 1;
    len += (size_t)snprintf(text + len, cap - len, "# %s, in manifest order\n", what);
    for (uint16_t i = 0; i < n; i++) {
        char name[80];
        field_name(&chs[i], i, name, sizeof name, taken, taken_len);
        len += (size_t)snprintf(text + len, cap - len, "float64 %s  # %s [%s]\n", name,
                                chs[i].name, chs[i].unit != NULL ? chs[i].unit : "");
        taken_len += (size_t)snprintf(taken + taken_len, cap - taken_len, "%s\n", name);
    }
    free(taken);
    return text;
}

/* ---- writing ------------------------------------------------------------------- */

/* @p t: the tick's simulated time; logged at the run's wall-clock start plus it */
static int put_msg(roz_record_file_t *f, uint16_t ch, uint64_t t, cdr_t *c)
{
    if (c->oom)
        return ROZ_ENOMEM;
    return roz_mcap_message(&f->w, ch, f->start_ns + t, f->start_ns + t, *c->p, c->len);
}

static int write_run(roz_record_file_t *f, const roz_runtime_config_t *cfg)
{
    const roz_manifest_t *m = f->m;
    cdr_t c;
    cdr_begin(&c, &f->msg, &f->msg_cap);
    cdr_str(&c, m->robot_id);
    cdr_str(&c, m->robot_class != NULL ? m->robot_class : "");
    cdr_u(&c, m->control_rate_hz, 4);
    cdr_u(&c, roz_manifest_interface_hash(m), 8);
    cdr_u(&c, m->n_commands, 4);
    for (uint16_t i = 0; i < m->n_commands; i++)
        cdr_str(&c, m->commands[i].name);
    cdr_u(&c, m->n_states, 4);
    for (uint16_t i = 0; i < m->n_states; i++)
        cdr_str(&c, m->states[i].name);
    cdr_u(&c, cfg->stale_ticks, 4);
    cdr_u(&c, cfg->fuel_per_tick, 8);
    cdr_u(&c, cfg->budget_ns, 8);
    cdr_u(&c, roz_recorder_decimation(f->rec), 4);
    cdr_u(&c, cfg->allow_foreign_controller ? 1u : 0u, 1);
    cdr_u(&c, f->start_ns, 8);
    cdr_u(&c, m->n_inputs, 4);
    for (uint16_t k = 0; k < m->n_inputs; k++)
        cdr_str(&c, m->inputs[k].name);
    return put_msg(f, f->ch_run, 0, &c);
}

static int write_deploy(roz_record_file_t *f, const roz_stages_config_t *seq)
{
    cdr_t c;
    cdr_begin(&c, &f->msg, &f->msg_cap);
    cdr_u(&c, f->m->n_commands, 4);
    for (uint16_t i = 0; i < f->m->n_commands; i++)
        cdr_f64(&c, seq->stand[i]);
    cdr_f64(&c, seq->move_s);
    cdr_f64(&c, seq->stop_damping);
    cdr_u(&c, (uint32_t)seq->start, 4);
    cdr_u(&c, (uint32_t)seq->run, 4);
    cdr_u(&c, (uint32_t)seq->stand_input, 4);
    cdr_u(&c, (uint32_t)seq->stop, 4);
    return put_msg(f, f->ch_deploy, 0, &c);
}

static const char *stage_text(int stage)
{
    const char *name = roz_stage_name(stage);
    return name != NULL ? name : "";
}

/* A file (@p sink NULL) or a stream to @p sink. */
static int open_any(roz_record_file_t *f, const char *path, const roz_runtime_t *rt,
                    roz_recorder_t *rec, const roz_record_file_options_t *opt,
                    roz_mcap_sink_fn sink, void *ctx, char *err, size_t errlen)
{
    static const roz_record_file_options_t none = { NULL, 0, ROZ_MCAP_COMPRESS_NONE };
    const roz_runtime_config_t *cfg = roz_runtime_config(rt);
    char pkg[96];
    int rc;

    memset(f, 0, sizeof *f);
    if (rec == NULL || cfg->recorder != rec) {
        snprintf(err, errlen, "%s: the runtime records into no recorder, or another one", path);
        return ROZ_EINVAL;
    }
    if (opt == NULL)
        opt = &none;
    f->rec = rec;
    f->m = cfg->manifest;
    f->controller_name = opt->controller_name != NULL ? opt->controller_name : "";
    f->start_ns = opt->start_time_ns;
    if (!roz_mcap_compression_supported(opt->compression)) {
        snprintf(err, errlen, "%s: this build cannot compress with %s", path,
                 opt->compression == ROZ_MCAP_COMPRESS_ZSTD ? "zstd (no libzstd)" : "that");
        return ROZ_ENOTSUP;
    }
    /* 64 KiB chunks: a recording whose writer died loses at most the last;
     * a stream's chunk is one tick, so a viewer loses or gets whole ticks */
    if (sink != NULL)
        rc = roz_mcap_open_stream(&f->w, path, "roz", 1u, sink, ctx);
    else
        rc = roz_mcap_open(&f->w, path, "roz", 64u * 1024u);
    if (rc == ROZ_OK)
        rc = roz_mcap_set_compression(&f->w, opt->compression);
    if (rc != ROZ_OK) {
        snprintf(err, errlen, "%s", f->w.error[0] ? f->w.error : "cannot compress");
        (void)roz_mcap_close(&f->w);
        return rc;
    }
    char *state_text = values_schema(f->m->states, f->m->n_states, "the state channels");
    char *cmd_text = values_schema(f->m->commands, f->m->n_commands, "the command channels");
    /* the operator's inputs as the controller read them, after their rules */
    char *input_text = f->m->n_inputs > 0u
                           ? values_schema(f->m->inputs, f->m->n_inputs,
                                           "the operator inputs as the controller read them")
                           : NULL;
    if (state_text == NULL || cmd_text == NULL || (f->m->n_inputs > 0u && input_text == NULL)) {
        free(state_text);
        free(cmd_text);
        free(input_text);
        (void)roz_mcap_close(&f->w);
        snprintf(err, errlen, "%s: out of memory", path);
        return ROZ_ENOMEM;
    }
    uint16_t s_run = roz_mcap_schema(&f->w, "roz_msgs/msg/Run", "ros2msg", run_schema);
    uint16_t s_ctl = roz_mcap_schema(&f->w, "roz_msgs/msg/Controller", "ros2msg",
                                     controller_schema);
    uint16_t s_tick = roz_mcap_schema(&f->w, "roz_msgs/msg/Tick", "ros2msg", tick_schema);
    snprintf(pkg, sizeof pkg, "roz_%s/msg/State", f->m->robot_id);
    uint16_t s_state = roz_mcap_schema(&f->w, pkg, "ros2msg", state_text);
    snprintf(pkg, sizeof pkg, "roz_%s/msg/Commands", f->m->robot_id);
    uint16_t s_cmd = roz_mcap_schema(&f->w, pkg, "ros2msg", cmd_text);
    uint16_t s_fault = roz_mcap_schema(&f->w, "roz_msgs/msg/Fault", "ros2msg", fault_schema);
    uint16_t s_inputs = 0;
    if (input_text != NULL) {
        snprintf(pkg, sizeof pkg, "roz_%s/msg/Inputs", f->m->robot_id);
        s_inputs = roz_mcap_schema(&f->w, pkg, "ros2msg", input_text);
    }
    free(state_text);
    free(cmd_text);
    free(input_text);
    f->ch_run = roz_mcap_channel(&f->w, s_run, "/roz/run", "cdr");
    f->ch_controller = roz_mcap_channel(&f->w, s_ctl, "/roz/controller", "cdr");
    f->ch_tick = roz_mcap_channel(&f->w, s_tick, "/roz/tick", "cdr");
    f->ch_state = roz_mcap_channel(&f->w, s_state, "/roz/state", "cdr");
    f->ch_target = roz_mcap_channel(&f->w, s_cmd, "/roz/target", "cdr");
    f->ch_applied = roz_mcap_channel(&f->w, s_cmd, "/roz/applied", "cdr");
    f->ch_fault = roz_mcap_channel(&f->w, s_fault, "/roz/fault", "cdr");
    if (s_inputs != 0)
        f->ch_inputs = roz_mcap_channel(&f->w, s_inputs, "/roz/inputs", "cdr");
    if (f->ch_fault == 0 || (f->m->n_inputs > 0u && f->ch_inputs == 0))
        rc = ROZ_ENOMEM;
    /* the deploy sequence: its configuration once, its stages as they change */
    const roz_stages_config_t *seq = roz_runtime_stages_config(rt);
    if (rc == ROZ_OK && seq != NULL) {
        uint16_t s_deploy = roz_mcap_schema(&f->w, "roz_msgs/msg/Deploy", "ros2msg",
                                            deploy_schema);
        uint16_t s_stage = roz_mcap_schema(&f->w, "roz_msgs/msg/Stage", "ros2msg", stage_schema);
        f->ch_deploy = roz_mcap_channel(&f->w, s_deploy, "/roz/deploy", "cdr");
        f->ch_stage = roz_mcap_channel(&f->w, s_stage, "/roz/stage", "cdr");
        if (f->ch_deploy == 0 || f->ch_stage == 0)
            rc = ROZ_ENOMEM;
    }
    f->port = cfg->port;
    if (rc == ROZ_OK && roz_port_has_truth(&f->port)) {
        uint16_t s_truth = roz_mcap_schema(&f->w, "roz_msgs/msg/Truth", "ros2msg", truth_schema);
        f->ch_truth = roz_mcap_channel(&f->w, s_truth, "/roz/truth", "cdr");
        if (f->ch_truth == 0)
            rc = ROZ_ENOMEM;
    }
    if (rc == ROZ_OK)
        rc = write_run(f, cfg);
    if (rc == ROZ_OK && f->ch_deploy != 0)
        rc = write_deploy(f, seq);
    if (rc == ROZ_OK)
        rc = roz_mcap_boundary(&f->w);
    if (rc != ROZ_OK) {
        snprintf(err, errlen, "%s: %s", path, f->w.error[0] ? f->w.error : "out of memory");
        (void)roz_mcap_close(&f->w);
        free(f->msg);
        f->msg = NULL;
        return rc;
    }
    return ROZ_OK;
}

int roz_record_file_open(roz_record_file_t *f, const char *path, const roz_runtime_t *rt,
                         roz_recorder_t *rec, const roz_record_file_options_t *opt, char *err,
                         size_t errlen)
{
    return open_any(f, path, rt, rec, opt, NULL, NULL, err, errlen);
}

int roz_record_file_open_stream(roz_record_file_t *f, const char *name, const roz_runtime_t *rt,
                                roz_recorder_t *rec, const roz_record_file_options_t *opt,
                                roz_mcap_sink_fn sink, void *ctx, char *err, size_t errlen)
{
    if (sink == NULL) {
        snprintf(err, errlen, "%s: a stream needs a sink", name);
        return ROZ_EINVAL;
    }
    return open_any(f, name, rt, rec, opt, sink, ctx, err, errlen);
}

static int write_values(roz_record_file_t *f, uint16_t ch, uint64_t t, const double *v,
                        uint16_t n)
{
    cdr_t c;
    cdr_begin(&c, &f->msg, &f->msg_cap);
    for (uint16_t i = 0; i < n; i++)
        cdr_f64(&c, v[i]);
    return put_msg(f, ch, t, &c);
}

static int write_record(void *ctx, const roz_record_t *r)
{
    roz_record_file_t *f = ctx;
    const roz_manifest_t *m = f->m;
    uint64_t t = r->sim_ns;
    int rc = ROZ_OK;
    cdr_t c;

    if (f->failed)
        return 0; /* drained, not written: the ring must not fill */
    if (!f->have_hash || r->controller_hash != f->last_hash) {
        cdr_begin(&c, &f->msg, &f->msg_cap);
        cdr_u(&c, r->controller_hash, 8);
        cdr_str(&c, r->controller_hash != 0 ? f->controller_name : "");
        rc = put_msg(f, f->ch_controller, t, &c);
        f->have_hash = 1;
        f->last_hash = r->controller_hash;
    }
    cdr_begin(&c, &f->msg, &f->msg_cap);
    cdr_u(&c, r->tick, 8);
    cdr_u(&c, (uint64_t)r->controller_tick, 8);
    cdr_u(&c, r->sim_ns, 8);
    cdr_u(&c, r->wall_ns, 8);
    cdr_u(&c, r->fuel, 8);
    cdr_u(&c, r->process_ns, 8);
    cdr_u(&c, r->tick_ns, 8);
    cdr_u(&c, r->controller_hash, 8);
    cdr_u(&c, r->faults, 4);
    cdr_u(&c, r->cleared, 4);
    cdr_u(&c, (uint32_t)r->read_rc, 4);
    cdr_u(&c, r->flags, 4);
    cdr_u(&c, (r->flags & ROZ_RECORD_FRESH) ? 1u : 0u, 1);
    cdr_u(&c, (r->flags & ROZ_RECORD_RAN) ? 1u : 0u, 1);
    cdr_u(&c, (r->flags & ROZ_RECORD_WROTE) ? 1u : 0u, 1);
    cdr_u(&c, r->clamps, 8);
    cdr_u(&c, r->rate_caps, 8);
    cdr_u(&c, r->limit_stops, 8);
    cdr_u(&c, r->nonfinite, 8);
    if (rc == ROZ_OK)
        rc = put_msg(f, f->ch_tick, t, &c);
    if (rc == ROZ_OK)
        rc = write_values(f, f->ch_state, t, r->state, m->n_states);
    if (rc == ROZ_OK && f->ch_inputs != 0 && r->inputs != NULL)
        rc = write_values(f, f->ch_inputs, t, r->inputs, m->n_inputs);
    if (rc == ROZ_OK)
        rc = write_values(f, f->ch_target, t, r->target, m->n_commands);
    if (rc == ROZ_OK)
        rc = write_values(f, f->ch_applied, t, r->applied, m->n_commands);
    if (rc == ROZ_OK && f->ch_stage != 0 && (r->flags & ROZ_RECORD_STAGE)) {
        cdr_begin(&c, &f->msg, &f->msg_cap);
        cdr_u(&c, (uint8_t)r->stage, 1);
        cdr_str(&c, stage_text(r->stage));
        cdr_u(&c, (uint8_t)(int8_t)r->stage_request, 1);
        cdr_str(&c, r->stage_request >= 0 ? stage_text(r->stage_request) : "");
        rc = put_msg(f, f->ch_stage, t, &c);
    }
    if (rc == ROZ_OK && f->ch_truth != 0 && r->truth != NULL) {
        const roz_port_truth_t *tr = r->truth;
        uint32_t nb = tr->n_bodies < ROZ_PORT_TRUTH_MAX_BODIES ? tr->n_bodies
                                                               : ROZ_PORT_TRUTH_MAX_BODIES;
        cdr_begin(&c, &f->msg, &f->msg_cap);
        cdr_u(&c, tr->floating ? 1u : 0u, 1);
        const double v[10] = { tr->pos[0], tr->pos[1], tr->pos[2], tr->quat[0], tr->quat[1],
                               tr->quat[2], tr->quat[3], tr->roll, tr->pitch, tr->yaw };
        for (int k = 0; k < 10; k++)
            cdr_f64(&c, v[k]);
        cdr_u(&c, tr->contacts, 4);
        cdr_u(&c, nb, 4);
        for (uint32_t k = 0; k < nb; k++) {
            const char *name = roz_port_truth_body(&f->port, tr->bodies[k]);
            cdr_str(&c, name != NULL ? name : "?");
        }
        rc = put_msg(f, f->ch_truth, t, &c);
    }
    if (rc == ROZ_OK && r->fault_message != NULL) {
        cdr_begin(&c, &f->msg, &f->msg_cap);
        cdr_u(&c, r->faults, 4);
        cdr_u(&c, r->cleared, 4);
        cdr_str(&c, r->fault_message);
        rc = put_msg(f, f->ch_fault, t, &c);
    }
    /* a tick's messages share one chunk: chunks never overlap in time */
    if (rc == ROZ_OK)
        rc = roz_mcap_boundary(&f->w);
    if (rc != ROZ_OK)
        f->failed = 1;
    else
        f->ticks++;
    return 0;
}

int roz_record_file_put(roz_record_file_t *f, const roz_record_t *r)
{
    (void)write_record(f, r);
    return f->failed ? ROZ_EIO : ROZ_OK;
}

int roz_record_file_drain(roz_record_file_t *f)
{
    uint64_t before = f->ticks;
    (void)roz_recorder_drain(f->rec, write_record, f, 0);
    if (f->failed)
        return ROZ_EIO;
    return (int)(f->ticks - before > 0x7fffffffu ? 0x7fffffff : f->ticks - before);
}

uint64_t roz_record_file_ticks(const roz_record_file_t *f)
{
    return f->ticks;
}

const char *roz_record_file_error(const roz_record_file_t *f)
{
    return f->w.error;
}

int roz_record_file_close(roz_record_file_t *f, char *err, size_t errlen)
{
    (void)roz_record_file_drain(f);
    int rc = roz_mcap_close(&f->w);
    if (f->failed || rc != ROZ_OK) {
        snprintf(err, errlen, "%s", f->w.error[0] ? f->w.error : "the recording could not be "
                                                                "written (out of memory)");
        rc = ROZ_EIO;
    }
    free(f->msg);
    f->msg = NULL;
    f->msg_cap = 0;
    return rc;
}

/* ---- reading ------------------------------------------------------------------- */

typedef struct {
    const unsigned char *p;
    size_t               len, at;
    int                  bad;
} rd_t;

static uint64_t rd_u(rd_t *d, size_t bytes)
{
    size_t pad = (bytes - (d->at - 4u) % bytes) % bytes;
    if (d->bad || d->at + pad + bytes > d->len) {
        d->bad = 1;
        return 0;
    }
    d->at += pad;
    uint64_t v = 0;
    for (size_t i = 0; i < bytes; i++)
        v |= (uint64_t)d->p[d->at + i] << (8u * i);
    d->at += bytes;
    return v;
}

static void rd_str(rd_t *d, char *out, size_t cap)
{
    size_t n = (size_t)rd_u(d, 4);
    if (d->bad || n == 0 || n > d->len - d->at) {
        d->bad = 1;
        if (cap > 0)
            out[0] = '\0';
        return;
    }
    if (out != NULL && cap > 0) {
        size_t k = n - 1u < cap - 1u ? n - 1u : cap - 1u;
        memcpy(out, d->p + d->at, k);
        out[k] = '\0';
    }
    d->at += n;
}

static void rd_begin(rd_t *d, const roz_mcap_message_t *msg)
{
    d->p = msg->data;
    d->len = msg->len;
    d->at = 4;
    d->bad = msg->len < 4u || msg->data[1] != 0x01; /* CDR little endian */
}

static int read_values(const roz_mcap_message_t *msg, double *out, uint16_t n)
{
    if (msg->len != 4u + 8u * (size_t)n)
        return -1;
    for (uint16_t i = 0; i < n; i++) {
        uint64_t u = 0;
        for (int b = 0; b < 8; b++)
            u |= (uint64_t)msg->data[4u + 8u * i + (unsigned)b] << (8 * b);
        memcpy(&out[i], &u, sizeof u);
    }
    return 0;
}

/* /roz/deploy: the run's sequence, its shape checked (its values are
 * roz_stages_check()'s to judge, against the manifest replay runs). */
static int read_deploy(roz_record_reader_t *rd, const roz_mcap_message_t *msg, char *err,
                       size_t errlen)
{
    rd_t d;
    roz_stages_config_t *c = &rd->stages;
    rd_begin(&d, msg);
    uint64_t n = rd_u(&d, 4);
    for (uint64_t i = 0; i < n && i < rd->run.n_commands && !d.bad; i++) {
        uint64_t u = rd_u(&d, 8);
        memcpy(&rd->stand[i], &u, sizeof u);
    }
    uint64_t v = rd_u(&d, 8);
    memcpy(&c->move_s, &v, sizeof v);
    v = rd_u(&d, 8);
    memcpy(&c->stop_damping, &v, sizeof v);
    int32_t *in[4] = { &c->start, &c->run, &c->stand_input, &c->stop };
    for (int k = 0; k < 4; k++) {
        *in[k] = (int32_t)(uint32_t)rd_u(&d, 4);
        if (*in[k] < -1 || *in[k] >= (int32_t)rd->run.n_inputs)
            d.bad = 1;
    }
    if (d.bad || n != rd->run.n_commands) {
        snprintf(err, errlen, "%s: at offset %llu: a malformed /roz/deploy message (%llu stand "
                 "values for %u commands, or an input out of range)", rd->r.path,
                 (unsigned long long)msg->offset, (unsigned long long)n,
                 (unsigned)rd->run.n_commands);
        return ROZ_EINVAL;
    }
    c->stand = rd->stand;
    rd->has_stages = 1;
    rd->stage_now = ROZ_STAGE_ZERO; /* a sequence starts there */
    return ROZ_OK;
}

int roz_record_reader_open(roz_record_reader_t *rd, const char *path, char *err, size_t errlen)
{
    roz_mcap_message_t msg;
    int rc;

    memset(rd, 0, sizeof *rd);
    rc = roz_mcap_reader_open(&rd->r, path, err, errlen);
    if (rc != ROZ_OK)
        return rc;
    rc = roz_mcap_reader_next(&rd->r, &msg, err, errlen);
    if (rc < 0) {
        roz_record_reader_close(rd);
        return rc;
    }
    if (rc == 0 && rd->r.warning[0] != '\0') {
        snprintf(err, errlen, "%s; not one complete chunk: nothing to read", rd->r.warning);
        roz_record_reader_close(rd);
        return ROZ_EINVAL;
    }
    if (rc == 0 || strcmp(msg.topic, "/roz/run") != 0) {
        snprintf(err, errlen, "%s: at offset %llu: not a roz recording (its first message is "
                 "not /roz/run)", path, rc == 0 ? 0ull : (unsigned long long)msg.offset);
        roz_record_reader_close(rd);
        return ROZ_EINVAL;
    }
    rd_t d;
    roz_record_run_t *run = &rd->run;
    rd_begin(&d, &msg);
    rd_str(&d, run->robot_id, sizeof run->robot_id);
    rd_str(&d, run->robot_class, sizeof run->robot_class);
    run->control_rate_hz = (uint32_t)rd_u(&d, 4);
    run->interface_hash = rd_u(&d, 8);
    uint64_t nc = rd_u(&d, 4);
    for (uint64_t i = 0; i < nc && !d.bad; i++)
        rd_str(&d, NULL, 0);
    uint64_t ns = rd_u(&d, 4);
    for (uint64_t i = 0; i < ns && !d.bad; i++)
        rd_str(&d, NULL, 0);
    run->stale_ticks = (uint32_t)rd_u(&d, 4);
    run->fuel_per_tick = rd_u(&d, 8);
    run->budget_ns = rd_u(&d, 8);
    run->decimation = (uint32_t)rd_u(&d, 4);
    run->allow_foreign_controller = (int)rd_u(&d, 1);
    run->start_time_ns = d.at < d.len ? rd_u(&d, 8) : 0; /* absent in older files */
    uint64_t ni = !d.bad && d.at < d.len ? rd_u(&d, 4) : 0; /* absent in older files */
    for (uint64_t k = 0; k < ni && k <= ROZ_CFG_MAX_INPUTS && !d.bad; k++)
        rd_str(&d, NULL, 0);
    if (d.bad || nc > ROZ_CFG_MAX_COMMANDS || ns > ROZ_CFG_MAX_STATES ||
        ni > ROZ_CFG_MAX_INPUTS || run->control_rate_hz == 0) {
        snprintf(err, errlen, "%s: at offset %llu: a malformed /roz/run message", path,
                 (unsigned long long)msg.offset);
        roz_record_reader_close(rd);
        return ROZ_EINVAL;
    }
    run->n_commands = (uint16_t)nc;
    run->n_states = (uint16_t)ns;
    run->n_inputs = (uint16_t)ni;
    rd->state = calloc((size_t)ns + (size_t)ni + 3u * (size_t)nc + 1u, sizeof(double));
    if (rd->state == NULL) {
        snprintf(err, errlen, "%s: out of memory", path);
        roz_record_reader_close(rd);
        return ROZ_ENOMEM;
    }
    rd->inputs = rd->state + ns;
    rd->target = rd->inputs + ni;
    rd->applied = rd->target + nc;
    rd->stand = rd->applied + nc;
    rd->stage_now = ROZ_STAGE_NONE;
    /* the deploy sequence, when the run had one, comes next; anything else
     * is the first tick's (a /roz/tick kept for roz_record_reader_next()) */
    rc = roz_mcap_reader_next(&rd->r, &msg, err, errlen);
    if (rc == 1 && strcmp(msg.topic, "/roz/deploy") == 0)
        rc = read_deploy(rd, &msg, err, errlen);
    if (rc == 1 && strcmp(msg.topic, "/roz/tick") == 0) {
        rd->pending = msg;
        rd->have_pending = 1;
    }
    if (rc < 0) {
        roz_record_reader_close(rd);
        return rc;
    }
    return ROZ_OK;
}

const roz_stages_config_t *roz_record_reader_stages(const roz_record_reader_t *rd)
{
    return rd->has_stages ? &rd->stages : NULL;
}

const roz_record_run_t *roz_record_reader_run(const roz_record_reader_t *rd)
{
    return &rd->run;
}

enum { HAS_STATE = 1, HAS_TARGET = 2, HAS_APPLIED = 4, HAS_INPUTS = 8, HAS_STAGE = 16 };

/* Takes a /roz/tick message as the start of the next tick. */
static int begin_tick(roz_record_reader_t *rd, const roz_mcap_message_t *msg, char *err,
                      size_t errlen)
{
    rd_t d;
    roz_record_t *t = &rd->tick;
    rd_begin(&d, msg);
    memset(t, 0, sizeof *t);
    t->tick = rd_u(&d, 8);
    t->controller_tick = (int64_t)rd_u(&d, 8);
    t->sim_ns = rd_u(&d, 8);
    t->wall_ns = rd_u(&d, 8);
    t->fuel = rd_u(&d, 8);
    t->process_ns = rd_u(&d, 8);
    t->tick_ns = rd_u(&d, 8);
    t->controller_hash = rd_u(&d, 8);
    t->faults = (uint32_t)rd_u(&d, 4);
    t->cleared = (uint32_t)rd_u(&d, 4);
    t->read_rc = (int32_t)(uint32_t)rd_u(&d, 4);
    t->flags = (uint32_t)rd_u(&d, 4);
    (void)rd_u(&d, 1); /* fresh, ran, wrote: the flags say it */
    (void)rd_u(&d, 1);
    (void)rd_u(&d, 1);
    if (!d.bad && d.at < d.len) { /* absent in files before the filter's counters */
        t->clamps = rd_u(&d, 8);
        t->rate_caps = rd_u(&d, 8);
        t->limit_stops = rd_u(&d, 8);
        t->nonfinite = rd_u(&d, 8);
    }
    if (d.bad) {
        snprintf(err, errlen, "%s: at offset %llu: a malformed /roz/tick message", rd->r.path,
                 (unsigned long long)msg->offset);
        return ROZ_EINVAL;
    }
    t->stage = rd->stage_now;
    t->stage_request = -1;
    rd->tick_offset = msg->offset;
    rd->parts = 0;
    rd->fault_message[0] = '\0';
    rd->have_tick = 1;
    return ROZ_OK;
}

int roz_record_reader_next(roz_record_reader_t *rd, roz_record_t *out, uint64_t *offset,
                           char *err, size_t errlen)
{
    roz_mcap_message_t msg;
    const roz_record_run_t *run = &rd->run;

    rd->have_tick = 0;
    if (rd->have_pending) {
        rd->have_pending = 0;
        if (begin_tick(rd, &rd->pending, err, errlen) != ROZ_OK)
            return ROZ_EINVAL;
    }
    for (;;) {
        int rc = roz_mcap_reader_next(&rd->r, &msg, err, errlen);
        if (rc < 0)
            return rc;
        if (rc == 0)
            break;
        if (strcmp(msg.topic, "/roz/tick") == 0) {
            if (rd->have_tick) {
                rd->pending = msg;
                rd->have_pending = 1;
                break;
            }
            if (begin_tick(rd, &msg, err, errlen) != ROZ_OK)
                return ROZ_EINVAL;
            continue;
        }
        if (!rd->have_tick)
            continue; /* /roz/controller before its tick */
        /* the tick's values: their topic, where they go, how many, their part */
        const struct {
            const char *topic;
            double     *out;
            uint16_t    n;
            uint32_t    part;
        } values[] = {
            { "/roz/state", rd->state, run->n_states, HAS_STATE },
            { "/roz/inputs", rd->inputs, run->n_inputs, HAS_INPUTS },
            { "/roz/target", rd->target, run->n_commands, HAS_TARGET },
            { "/roz/applied", rd->applied, run->n_commands, HAS_APPLIED },
        };
        size_t k = 0;
        while (k < sizeof values / sizeof values[0] && strcmp(msg.topic, values[k].topic) != 0)
            k++;
        int bad = 0;
        if (k < sizeof values / sizeof values[0]) {
            bad = read_values(&msg, values[k].out, values[k].n);
            rd->parts |= values[k].part;
        } else if (strcmp(msg.topic, "/roz/stage") == 0) {
            rd_t d;
            rd_begin(&d, &msg);
            int32_t stage = (int32_t)rd_u(&d, 1);
            rd_str(&d, NULL, 0);
            int32_t req = (int32_t)(int8_t)(uint8_t)rd_u(&d, 1);
            bad = d.bad || roz_stage_name(stage) == NULL || stage == ROZ_STAGE_NONE ||
                  (req != -1 && roz_stage_name(req) == NULL);
            rd->tick.stage = rd->stage_now = stage;
            rd->tick.stage_request = req;
            rd->parts |= HAS_STAGE;
        } else if (strcmp(msg.topic, "/roz/fault") == 0) {
            rd_t d;
            rd_begin(&d, &msg);
            (void)rd_u(&d, 4);
            (void)rd_u(&d, 4);
            rd_str(&d, rd->fault_message, sizeof rd->fault_message);
            bad = d.bad;
        }
        if (bad) {
            snprintf(err, errlen, "%s: at offset %llu: a malformed %s message (%lu bytes) at "
                     "tick %llu", rd->r.path, (unsigned long long)msg.offset, msg.topic,
                     (unsigned long)msg.len, (unsigned long long)rd->tick.tick);
            return ROZ_EINVAL;
        }
    }
    if (!rd->have_tick)
        return 0;
    uint32_t all = HAS_STATE | HAS_TARGET | HAS_APPLIED | (run->n_inputs > 0u ? HAS_INPUTS : 0u) |
                   (rd->has_stages && (rd->tick.flags & ROZ_RECORD_STAGE) ? HAS_STAGE : 0u);
    if (rd->parts != all) {
        if (!rd->have_pending && rd->r.warning[0] != '\0')
            return 0; /* the last tick of a file cut short: incomplete, left out */
        snprintf(err, errlen, "%s: at offset %llu: tick %llu lacks its %s message",
                 rd->r.path, (unsigned long long)rd->tick_offset,
                 (unsigned long long)rd->tick.tick,
                 !(rd->parts & HAS_STATE)    ? "/roz/state"
                 : !(rd->parts & HAS_INPUTS) && run->n_inputs > 0u ? "/roz/inputs"
                 : !(rd->parts & HAS_TARGET) ? "/roz/target"
                 : !(rd->parts & HAS_APPLIED) ? "/roz/applied"
                                              : "/roz/stage");
        return ROZ_EINVAL;
    }
    *out = rd->tick;
    out->state = rd->state;
    out->inputs = run->n_inputs > 0u ? rd->inputs : NULL;
    out->target = rd->target;
    out->applied = rd->applied;
    out->fault_message = (rd->tick.flags & ROZ_RECORD_FAULT_CHANGED) ? rd->fault_message : NULL;
    /* /roz/truth is not read back (replay never feeds it to a controller):
     * the flag goes with it, so a record never says "truth" without one */
    out->flags &= ~(uint32_t)ROZ_RECORD_TRUTH;
    out->truth = NULL;
    if (offset != NULL)
        *offset = rd->tick_offset;
    return 1;
}

const char *roz_record_reader_warning(const roz_record_reader_t *rd)
{
    return rd->r.warning;
}

void roz_record_reader_close(roz_record_reader_t *rd)
{
    roz_mcap_reader_close(&rd->r);
    free(rd->state);
    rd->state = NULL;
}
