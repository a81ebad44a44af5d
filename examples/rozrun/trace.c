/* SPDX-License-Identifier: Apache-2.0 */
#include "trace.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int rozrun_trace_open(rozrun_trace_t *t, const char *path, const roz_manifest_t *m, char *err,
                      size_t errlen)
{
    memset(t, 0, sizeof *t);
    t->m = m;
    t->width = 2u + 2u * m->n_commands + m->n_states;
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
    fprintf(t->out, "\n");
    return 0;
}

void rozrun_trace_push(rozrun_trace_t *t, uint64_t tick, double time_s, const double *targets,
                       const double *applied, const double *state)
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
    for (uint16_t i = 0; i < m->n_states; i++)
        row[k++] = state[i];
    atomic_store_explicit(&t->head, head + 1, memory_order_release);
}

void rozrun_trace_drain(rozrun_trace_t *t)
{
    size_t tail = atomic_load_explicit(&t->tail, memory_order_relaxed);
    size_t head = atomic_load_explicit(&t->head, memory_order_acquire);

    for (; tail != head; tail++) {
        const double *row = &t->rows[(tail & (t->capacity - 1)) * t->width];
        fprintf(t->out, "%.0f,%.6f", row[0], row[1]);
        for (size_t k = 2; k < t->width; k++)
            fprintf(t->out, ",%.9g", row[k]);
        fprintf(t->out, "\n");
        t->written++;
    }
    atomic_store_explicit(&t->tail, tail, memory_order_release);
}

int rozrun_trace_close(rozrun_trace_t *t)
{
    int rc = 0;
    if (t->out != NULL) {
        rozrun_trace_drain(t);
        rc = fclose(t->out) == 0 ? 0 : -1;
        t->out = NULL;
    }
    free(t->rows);
    t->rows = NULL;
    return rc;
}
