/* SPDX-License-Identifier: Apache-2.0 */
#include "trace.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "roz/port.h"
#include "roz/runtime.h"

static const char *const event_names[ROZRUN_EV_COUNT] = {
    "estop", "estop-release", "swap", "load-refused", "verify-refused",
    "clear", "clear-while-pressed", "clear-refused", "rebuild",
};

/* The first write error, once (consumer). errno is read right after the
 * failing call, before anything else could change it. */
static void write_failed(rozrun_trace_t *t, const char *what, int err)
{
    if (t->error[0] == '\0')
        snprintf(t->error, sizeof t->error, "cannot write trace %s: %s%s", t->path, what,
                 err != 0 ? strerror(err) : "write error");
}

int rozrun_trace_truth(const roz_port_t *port, double out[ROZRUN_TRUTH_VALUES])
{
    roz_port_truth_t t;
    if (!roz_port_has_truth(port) || roz_port_truth(port, &t) != ROZ_OK || !t.floating)
        return 0;
    out[0] = t.pos[0];
    out[1] = t.pos[1];
    out[2] = t.pos[2];
    out[3] = t.roll;
    out[4] = t.pitch;
    out[5] = t.yaw;
    return 1;
}

int rozrun_trace_open(rozrun_trace_t *t, const char *path, const roz_manifest_t *m, int truth,
                      char *err, size_t errlen)
{
    memset(t, 0, sizeof *t);
    t->m = m;
    t->path = path;
    t->truth = truth != 0;
    t->width = 2u + 2u * m->n_commands + m->n_states + m->n_inputs + (t->truth ? ROZRUN_TRUTH_VALUES : 0u) + 2u;
    t->capacity = 4096;
    t->rows = calloc(t->capacity * t->width, sizeof(double));
    if (t->rows == NULL) {
        snprintf(err, errlen, "out of memory for the trace ring");
        return -1;
    }
    t->out = fopen(path, "w");
    if (t->out == NULL) {
        snprintf(err, errlen, "cannot write trace %s: %s", path, strerror(errno));
        free(t->rows);
        t->rows = NULL;
        return -1;
    }
    atomic_init(&t->head, 0);
    atomic_init(&t->tail, 0);
    fprintf(t->out, "tick,time_s");
    for (uint16_t i = 0; i < m->n_commands; i++)
        fprintf(t->out, ",target:%s", m->commands[i].name);
    for (uint16_t i = 0; i < m->n_commands; i++)
        fprintf(t->out, ",applied:%s", m->commands[i].name);
    for (uint16_t i = 0; i < m->n_states; i++)
        fprintf(t->out, ",state:%s", m->states[i].name);
    for (uint16_t i = 0; i < m->n_inputs; i++) /* the runtime's state, after the port's */
        fprintf(t->out, ",input:%s", m->inputs[i].name);
    if (t->truth)
        fprintf(t->out, ",truth:base.x,truth:base.y,truth:base.z,truth:base.roll,"
                        "truth:base.pitch,truth:base.yaw");
    fprintf(t->out, ",faults,events\n");
    return 0;
}

void rozrun_trace_push(rozrun_trace_t *t, uint64_t tick, double time_s, const double *targets,
                       const double *applied, const double *state, const double *truth,
                       unsigned faults, unsigned events)
{
    size_t head = atomic_load_explicit(&t->head, memory_order_relaxed);
    size_t tail = atomic_load_explicit(&t->tail, memory_order_acquire);
    const roz_manifest_t *m = t->m;

    if (head - tail >= t->capacity) {
        t->dropped++;
        return;
    }
    double *row = &t->rows[(head & (t->capacity - 1)) * t->width];
    size_t k = 0;
    row[k++] = (double)tick;
    row[k++] = time_s;
    for (uint16_t i = 0; i < m->n_commands; i++)
        row[k++] = targets != NULL ? targets[i] : NAN;
    for (uint16_t i = 0; i < m->n_commands; i++)
        row[k++] = applied[i];
    for (uint16_t i = 0; i < (uint16_t)(m->n_states + m->n_inputs); i++)
        row[k++] = state[i];
    for (size_t i = 0; t->truth && i < ROZRUN_TRUTH_VALUES; i++)
        row[k++] = truth != NULL ? truth[i] : NAN;
    row[k++] = (double)faults; /* small integers: exact in a double */
    row[k++] = (double)events;
    atomic_store_explicit(&t->head, head + 1, memory_order_release);
}

/* One fault token: fault:<name> or cleared:<name>, spaces as '-'. */
static void put_fault(FILE *f, const char *prefix, unsigned bit, int *first)
{
    fprintf(f, "%s%s:", *first ? "" : " ", prefix);
    for (const char *c = roz_fault_name(bit); *c != '\0'; c++)
        fputc(*c == ' ' ? '-' : *c, f);
    *first = 0;
}

static void put_events(rozrun_trace_t *t, unsigned faults, unsigned events)
{
    int first = 1;

    for (unsigned b = 0; b < ROZRUN_EV_COUNT; b++) {
        if (events & (1u << b)) {
            fprintf(t->out, "%s%s", first ? "" : " ", event_names[b]);
            first = 0;
        }
    }
    for (unsigned b = 0; b < ROZ_FAULT_KIND_COUNT; b++) {
        unsigned bit = 1u << b;
        if ((faults & bit) && !(t->faults & bit))
            put_fault(t->out, "fault", bit, &first);
        else if (!(faults & bit) && (t->faults & bit))
            put_fault(t->out, "cleared", bit, &first);
    }
    t->faults = faults;
}

int rozrun_trace_drain(rozrun_trace_t *t)
{
    size_t tail = atomic_load_explicit(&t->tail, memory_order_relaxed);
    size_t head = atomic_load_explicit(&t->head, memory_order_acquire);

    for (; tail != head; tail++) {
        const double *row = &t->rows[(tail & (t->capacity - 1)) * t->width];
        if (t->error[0] != '\0') {
            t->lost++; /* the file is broken: the rest of the run is not in it */
            continue;
        }
        fprintf(t->out, "%.0f,%.6f", row[0], row[1]);
        for (size_t k = 2; k < t->width - 2u; k++)
            fprintf(t->out, ",%.9g", row[k]);
        fprintf(t->out, ",%u,", (unsigned)row[t->width - 2u]);
        put_events(t, (unsigned)row[t->width - 2u], (unsigned)row[t->width - 1u]);
        fputc('\n', t->out);
        /* stdio reports a failed write of its buffer through the stream's
         * error flag; checked per row, so the count of rows is honest */
        if (ferror(t->out)) {
            write_failed(t, "", errno);
            t->lost++;
            continue;
        }
        t->written++;
    }
    atomic_store_explicit(&t->tail, tail, memory_order_release);
    return t->error[0] != '\0' ? -1 : 0;
}

int rozrun_trace_close(rozrun_trace_t *t)
{
    if (t->out != NULL) {
        rozrun_trace_drain(t);
        /* the last rows sit in stdio's buffer until now */
        if (fflush(t->out) != 0 || ferror(t->out))
            write_failed(t, "", errno);
        if (fclose(t->out) != 0)
            write_failed(t, "closing: ", errno);
        t->out = NULL;
    }
    free(t->rows);
    t->rows = NULL;
    return t->error[0] != '\0' ? -1 : 0;
}
