/* SPDX-License-Identifier: Apache-2.0 */
/*
 * What the benchmarks share: p50/p99/max of a set of durations, their
 * machine-readable output, and a controller's file read whole. With `--json FILE` a bench appends one JSON
 * object per figure to FILE (JSON Lines), which bench/report.py turns into
 * BENCHMARKS.md:
 *   {"bench": "tick", "name": "process(), wasm3", "unit": "us",
 *    "p50": 2.1, "p99": 2.9, "max": 14.0}
 *   {"bench": "tick", "name": "allocations", "unit": "count", "value": 0}
 * Header-only, for the bench programs alone.
 */
#ifndef ROZ_BENCH_JSON_H
#define ROZ_BENCH_JSON_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double p50, p99, max; /* microseconds */
} bench_stats_t;

static inline int bench_cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* Sorts v (nanoseconds) and gives its p50, p99 and max in microseconds. */
static inline bench_stats_t bench_stats(uint64_t *v, size_t n)
{
    bench_stats_t s = { 0, 0, 0 };
    if (n == 0)
        return s;
    qsort(v, n, sizeof v[0], bench_cmp_u64);
    s.p50 = v[n / 2] / 1000.0;
    s.p99 = v[(n * 99) / 100] / 1000.0;
    s.max = v[n - 1] / 1000.0;
    return s;
}

/* The JSON output: NULL (no --json) writes nothing. */
typedef struct {
    FILE *f;
    const char *bench;
} bench_json_t;

/* Takes `--json FILE` out of argv (shifting the rest down) and opens FILE
 * for appending; returns the new argc, or -1 when FILE cannot be opened. */
static inline int bench_json_args(bench_json_t *j, const char *bench, int argc, char **argv)
{
    j->f = NULL;
    j->bench = bench;
    for (int i = 1; i + 1 < argc; i++) {
        if (strcmp(argv[i], "--json") == 0) {
            j->f = fopen(argv[i + 1], "a");
            if (j->f == NULL) {
                fprintf(stderr, "%s: cannot open %s\n", bench, argv[i + 1]);
                return -1;
            }
            memmove(&argv[i], &argv[i + 2], (size_t)(argc - i - 2 + 1) * sizeof argv[0]);
            return argc - 2;
        }
    }
    return argc;
}

static inline void bench_json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"' || *s == '\\')
            fputc('\\', f);
        if ((unsigned char)*s >= 0x20)
            fputc(*s, f);
    }
    fputc('"', f);
}

/* The file at @p path, at most @p cap bytes of it, in a buffer of @p cap
 * bytes from malloc (its length in *len); NULL when it cannot be opened. */
static inline uint8_t *bench_read_file(const char *path, size_t cap, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    uint8_t *buf = malloc(cap);
    *len = buf ? fread(buf, 1, cap, f) : 0;
    fclose(f);
    return buf;
}

/* A line's start: the bench's name and the figure's @p name. */
static inline void bench_json_head(const bench_json_t *j, const char *name)
{
    fputs("{\"bench\": ", j->f);
    bench_json_str(j->f, j->bench);
    fputs(", \"name\": ", j->f);
    bench_json_str(j->f, name);
}

/* A timed figure: p50/p99/max in microseconds. */
static inline void bench_json_timing(const bench_json_t *j, const char *name, bench_stats_t s)
{
    if (j->f == NULL)
        return;
    bench_json_head(j, name);
    fprintf(j->f, ", \"unit\": \"us\", \"p50\": %.4f, \"p99\": %.4f, \"max\": %.4f}\n", s.p50,
            s.p99, s.max);
    fflush(j->f);
}

/* A single value with its unit. */
static inline void bench_json_value(const bench_json_t *j, const char *name, double value,
                                    const char *unit)
{
    if (j->f == NULL)
        return;
    bench_json_head(j, name);
    fputs(", \"unit\": ", j->f);
    bench_json_str(j->f, unit);
    fprintf(j->f, ", \"value\": %.17g}\n", value);
    fflush(j->f);
}

static inline void bench_json_close(bench_json_t *j)
{
    if (j->f != NULL)
        fclose(j->f);
    j->f = NULL;
}

#endif /* ROZ_BENCH_JSON_H */
