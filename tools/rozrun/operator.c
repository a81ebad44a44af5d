/* SPDX-License-Identifier: Apache-2.0 */
#include "operator.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define OPERATOR_MAX_BYTES (16u << 20)

/* One CSV field of @p line from @p at: [*b, *e), trimmed of spaces. */
static const char *field(const char *at, const char **b, const char **e)
{
    const char *end = at;
    while (*end != '\0' && *end != ',')
        end++;
    *b = at;
    *e = end;
    while (*b < *e && (**b == ' ' || **b == '\t'))
        (*b)++;
    while (*e > *b && ((*e)[-1] == ' ' || (*e)[-1] == '\t'))
        (*e)--;
    return *end == ',' ? end + 1 : NULL;
}

/* A number filling [b, e) ("nan" and "inf" too: the runtime refuses them,
 * which is what a test of that rule wants). */
static int number(const char *b, const char *e, double *out)
{
    char buf[64], *end;
    size_t n = (size_t)(e - b);
    if (n == 0 || n >= sizeof buf)
        return -1;
    memcpy(buf, b, n);
    buf[n] = '\0';
    errno = 0;
    *out = strtod(buf, &end);
    return *end == '\0' && errno != ERANGE ? 0 : -1;
}

static char *read_all(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    char *buf;
    if (f == NULL) {
        fprintf(stderr, "rozrun: --operator %s: %s\n", path, strerror(errno));
        return NULL;
    }
    buf = malloc(OPERATOR_MAX_BYTES + 1u);
    *len = buf != NULL ? fread(buf, 1, OPERATOR_MAX_BYTES + 1u, f) : 0;
    if (buf == NULL || ferror(f) || *len > OPERATOR_MAX_BYTES) {
        fprintf(stderr, "rozrun: --operator %s: %s\n", path,
                buf == NULL ? "out of memory" : ferror(f) ? "cannot read it"
                                                          : "larger than 16 MiB");
        free(buf);
        fclose(f);
        return NULL;
    }
    fclose(f);
    buf[*len] = '\0';
    if (strlen(buf) != *len) {
        fprintf(stderr, "rozrun: --operator %s: a NUL byte: not a CSV file\n", path);
        free(buf);
        return NULL;
    }
    return buf;
}

#define FAIL(line, col, ...)                                                            \
    do {                                                                                \
        fprintf(stderr, "rozrun: %s:%lu:%lu: ", path, (unsigned long)(line),            \
                (unsigned long)(col));                                                  \
        fprintf(stderr, __VA_ARGS__);                                                   \
        fputc('\n', stderr);                                                            \
        goto fail;                                                                      \
    } while (0)

int rozrun_operator_load(rozrun_operator_t *op, const char *path, const roz_manifest_t *m)
{
    size_t len, cap_rows = 0, lineno = 0;
    char *text = read_all(path, &len), *next, *start;
    int have_header = 0;

    memset(op, 0, sizeof *op);
    op->path = path;
    if (text == NULL)
        return -1;
    /* a spreadsheet's UTF-8 byte order mark is no part of the header */
    start = len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? text + 3 : text;
    if (m->n_inputs == 0) {
        fprintf(stderr, "rozrun: --operator %s: robot %s has no operator inputs "
                        "([[manifest.inputs]] in its robot.toml)\n", path, m->robot_id);
        goto fail;
    }
    for (char *line = start; line != NULL; line = next) {
        const char *at, *b, *e;
        size_t col = 0;
        next = strchr(line, '\n');
        if (next != NULL)
            *next++ = '\0';
        lineno++;
        size_t n = strlen(line);
        if (n > 0 && line[n - 1] == '\r')
            line[--n] = '\0';
        at = line;
        while (*at == ' ' || *at == '\t')
            at++;
        if (*at == '\0' || *at == '#')
            continue;
        if (!have_header) {
            at = field(line, &b, &e);
            if ((size_t)(e - b) != 6 || memcmp(b, "time_s", 6) != 0)
                FAIL(lineno, (size_t)(b - line) + 1, "the header must start with \"time_s\", "
                     "then the names of the inputs to set");
            op->col_input = malloc(sizeof op->col_input[0] * m->n_inputs);
            if (op->col_input == NULL)
                FAIL(lineno, 1, "out of memory");
            while (at != NULL) {
                const char *fb;
                at = field(at, &fb, &e);
                int k = -1;
                for (uint16_t i = 0; i < m->n_inputs && k < 0; i++) {
                    if (strlen(m->inputs[i].name) == (size_t)(e - fb) &&
                        memcmp(m->inputs[i].name, fb, (size_t)(e - fb)) == 0)
                        k = i;
                }
                if (k < 0) {
                    fprintf(stderr, "rozrun: %s:%lu:%lu: \"%.*s\" is not an input of robot %s "
                                    "(inputs:", path, (unsigned long)lineno,
                            (unsigned long)(fb - line) + 1, (int)(e - fb), fb, m->robot_id);
                    for (uint16_t i = 0; i < m->n_inputs; i++)
                        fprintf(stderr, " %s", m->inputs[i].name);
                    fputs(")\n", stderr);
                    goto fail;
                }
                for (uint16_t c = 0; c < op->n_cols; c++) {
                    if (op->col_input[c] == (uint16_t)k)
                        FAIL(lineno, (size_t)(fb - line) + 1, "input \"%s\" named twice",
                             m->inputs[k].name);
                }
                op->col_input[op->n_cols++] = (uint16_t)k;
            }
            have_header = 1;
            continue;
        }
        if (op->n_rows == cap_rows) {
            size_t cap = cap_rows == 0 ? 64 : 2 * cap_rows;
            double *t = realloc(op->time_s, cap * sizeof *t);
            if (t != NULL)
                op->time_s = t;
            double *v = t != NULL ? realloc(op->value, cap * op->n_cols * sizeof *v) : NULL;
            if (v == NULL)
                FAIL(lineno, 1, "out of memory");
            op->value = v;
            cap_rows = cap;
        }
        at = line;
        for (col = 0; col <= op->n_cols; col++) {
            double x;
            if (at == NULL)
                FAIL(lineno, n + 1, "%lu values for %u columns (time_s and %u inputs)",
                     (unsigned long)col, (unsigned)op->n_cols + 1u, (unsigned)op->n_cols);
            at = field(at, &b, &e);
            if (number(b, e, &x) != 0)
                FAIL(lineno, (size_t)(b - line) + 1, "\"%.*s\" is not a number (column %s)",
                     (int)(e - b), b, col == 0 ? "time_s" : m->inputs[op->col_input[col - 1]].name);
            if (col == 0) {
                if (!isfinite(x) || x < 0.0)
                    FAIL(lineno, (size_t)(b - line) + 1, "time_s %.*s: must be a finite "
                         "number of seconds, from 0", (int)(e - b), b);
                if (op->n_rows > 0 && x < op->time_s[op->n_rows - 1])
                    FAIL(lineno, (size_t)(b - line) + 1, "time_s %.*s: before the row above "
                         "(%g): rows go forward in time", (int)(e - b), b,
                         op->time_s[op->n_rows - 1]);
                op->time_s[op->n_rows] = x;
            } else {
                op->value[op->n_rows * op->n_cols + (col - 1)] = x;
            }
        }
        if (at != NULL)
            FAIL(lineno, (size_t)(at - line) + 1, "more values than the %u columns of the header",
                 (unsigned)op->n_cols + 1u);
        op->n_rows++;
    }
    if (!have_header)
        FAIL(lineno, 1, "no header (\"time_s\" then the names of the inputs to set)");
    free(text);
    op->row = op->n_rows;
    return 0;
fail:
    free(text);
    rozrun_operator_free(op);
    return -1;
}

void rozrun_operator_tick(rozrun_operator_t *op, roz_runtime_t *rt, uint64_t tick,
                          uint32_t rate_hz)
{
    double t = (double)tick / (double)rate_hz;
    size_t r = op->row == op->n_rows ? 0 : op->row;
    if (op->n_rows == 0 || op->time_s[0] > t)
        return; /* before the first row: the inputs keep their defaults */
    while (r + 1 < op->n_rows && op->time_s[r + 1] <= t)
        r++;
    op->row = r;
    for (uint16_t c = 0; c < op->n_cols; c++)
        (void)roz_runtime_input_set(rt, op->col_input[c], op->value[r * op->n_cols + c]);
}

void rozrun_operator_free(rozrun_operator_t *op)
{
    free(op->col_input);
    free(op->time_s);
    free(op->value);
    op->col_input = NULL;
    op->time_s = NULL;
    op->value = NULL;
    op->n_rows = 0;
    op->n_cols = 0;
}
