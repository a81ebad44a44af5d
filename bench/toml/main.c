/* SPDX-License-Identifier: Apache-2.0 */
/*
 * bench/toml: how long roz's C TOML reader (roz_toml_parse) and the
 * robot.toml loader (roz_manifest_toml_load: parse, every rule, build) take
 * on each FILE, in the process's CPU time (preemption by other processes
 * does not count), the median of several runs.
 *
 *   roz_bench_toml [--min-seconds S] FILE...
 *
 * One line per file, tab-separated, for bench/toml/bench_toml.py (which
 * puts Python's tomllib and rozgen beside them):
 *
 *   <file> <bytes> <runs> <reader seconds> <loader seconds> <loader verdict>
 *
 * The verdict is "ok" or the loader's first rule id ("storage" for a file
 * beyond this build's limits: it is still parsed and checked in full). A
 * benchmark, not a test: it prints, it never fails on a time.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "roz/manifest_toml.h"

#define MAX_FILE (16u << 20)
#define MAX_RUNS 101

static char text[MAX_FILE];
static roz_manifest_storage_t storage;
static roz_manifest_toml_problem_t problem;
ROZ_TOML_DOC_DEFINE(doc, 1u << 20, 8u << 20);

static double cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof v[0], cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Runs the reader (@loader 0) or the loader (1) on @len bytes of text at
 * least 3 times and until @min_s seconds have gone by; the median run. */
static double time_runs(int loader, size_t len, double min_s, int *runs, const char **verdict)
{
    static double t[MAX_RUNS];
    double spent = 0.0;
    int n = 0;
    while (n < MAX_RUNS && (n < 3 || spent < min_s)) {
        size_t found = 0;
        double t0 = cpu_seconds();
        int rc;
        roz_toml_init(&doc, doc_nodes, sizeof doc_nodes / sizeof doc_nodes[0], doc_arena,
                      sizeof doc_arena);
        if (loader)
            rc = roz_manifest_toml_load(&storage, &doc, text, len, &problem, 1, &found);
        else
            rc = roz_toml_parse(&doc, text, len, NULL);
        t[n] = cpu_seconds() - t0;
        spent += t[n++];
        if (loader)
            *verdict = rc == ROZ_OK ? "ok" : found > 0 ? problem.rule : "?";
        else if (rc != ROZ_OK)
            *verdict = "toml-error";
    }
    *runs = n;
    return median(t, n);
}

int main(int argc, char **argv)
{
    double min_s = 0.5;
    int first = 1;
    if (argc > 2 && strcmp(argv[1], "--min-seconds") == 0) {
        min_s = atof(argv[2]);
        first = 3;
    }
    if (first >= argc) {
        fprintf(stderr, "usage: roz_bench_toml [--min-seconds S] FILE...\n");
        return 2;
    }
    for (int i = first; i < argc; i++) {
        size_t len = 0;
        int runs_r, runs_l;
        const char *verdict = "ok", *parsed = "ok";
        double reader, loader;
        if (roz_manifest_toml_read_file(argv[i], text, sizeof text, &len, &problem) != ROZ_OK) {
            fprintf(stderr, "%s%s\n", argv[i], problem.text);
            return 1;
        }
        reader = time_runs(0, len, min_s, &runs_r, &parsed);
        loader = time_runs(1, len, min_s, &runs_l, &verdict);
        printf("%s\t%lu\t%d\t%.9f\t%.9f\t%s\n", argv[i], (unsigned long)len,
               runs_r < runs_l ? runs_r : runs_l, reader, loader,
               strcmp(parsed, "ok") == 0 ? verdict : parsed);
    }
    return 0;
}
