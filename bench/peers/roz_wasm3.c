/* SPDX-License-Identifier: Apache-2.0 */
/*
 * bench/peers/roz_wasm3.c: roz's side of the peer comparison. The G1 PD
 * controller under roz's controller host (wasm3 with roz's metering), fed
 * the state sequence the peer harnesses use (bench/peers/README.md), timed
 * as they time theirs:
 *   - with --reference FILE, the outputs after REF_TICKS ticks (every
 *     target's bits and the ABI's counters), which the peers must match;
 *   - load: roz's validator (the module scan), the whole controller load
 *     (validator, wasm3 parse, link, compile), and the 100 verification
 *     ticks a load runs, 20 times each;
 *   - process() per call, metered (the runtime's default budget: fuel and
 *     a deadline) and compiled without charges, alternating rounds;
 *   - resident memory added by one loaded controller that ran.
 * Prints one JSON object on stdout. A benchmark: it never fails on a time.
 *
 *   - with --bulk G1_PD_BULK.wasm, the same for the PD through the bulk
 *     calls, whose outputs must equal the per-channel PD's.
 *   - with --nn POLICY.wasm (bench/nn/policy.c: one inference through the
 *     nn imports a call), process() per call metered and not, and with
 *     --nn-reference FILE its outputs after REF_TICKS ticks (the metrics'
 *     count and FNV-1a, the ABI's counters), which the peers must match.
 *     Metered with NN_FUEL a tick (an inference needs more than the G1's
 *     default budget, as docs/policies.md says) and a deadline of a second.
 *
 *   roz_bench_peers_roz G1_PD.wasm [--bulk G1_PD_BULK.wasm] [--calls N]
 *                       [--reference FILE] [--nn POLICY.wasm [--nn-reference FILE]]
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "roz/controller.h"
#include "roz/hal/clock.h"
#include "bench_json.h"
#include "controller_bench.h"
#include "unitree_g1_manifest.h"
#include "wasm_scan.h"

#define REF_TICKS 1000
#define LOAD_REPS 20
#define VERIFY_TICKS 100
#define NN_FUEL 100000u /* a tick's fuel for the nn policy (about 47,000 an inference) */
/* its deadline: checked as the PD's is, but long, so that a loaded machine
 * cannot stop the reference run (a benchmark never fails on a time) */
#define NN_DEADLINE_NS 1000000000ull

static double state[ROZ_CFG_MAX_STATES];

/* The state of tick t (bench/peers/common/src/lib.rs, fill_state). */
static void fill_state(double *s, size_t n, int64_t t)
{
    for (size_t i = 0; i < n; i++) {
        int64_t k = ((int64_t)i * 37 + t * 11) % 2003;
        s[i] = (double)k / 1000.0 - 1.0;
    }
    if (n > 0 && t % 7 == 3)
        s[t % (int64_t)n] = NAN;
}

static uint8_t *read_file(const char *path, size_t *len)
{
    return bench_read_file(path, ROZ_CFG_WASM_MAX_MODULE_BYTES, len);
}

static long rss_kib(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    long kib = 0;
    if (f == NULL)
        return 0;
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, "VmRSS:", 6) == 0)
            kib = strtol(line + 6, NULL, 10);
    }
    fclose(f);
    return kib;
}

static uint64_t clock_ns(void *ctx)
{
    return roz_clock_monotonic_ns(ctx);
}

static const roz_manifest_t *m = &roz_manifest_unitree_g1;

/* Loads `wasm`: metered with the runtime's default budget (a tick's fuel at
 * ROZ_CFG_FUEL_PER_SECOND, the period as deadline), or without charges. */
static int load_with(roz_controller_t *c, roz_abi_t *abi, double *target,
                     roz_metric_ring_t *ring, const uint8_t *wasm, size_t len, int metered,
                     uint64_t fuel, uint64_t deadline_ns)
{
    roz_budget_t b = { fuel, deadline_ns, clock_ns, NULL };
    roz_controller_init(c);
    roz_abi_init(abi, m, target, ring);
    roz_abi_begin_tick(abi, 0, state);
    if (!metered)
        return roz__controller_load_unmetered(c, wasm, len, abi);
    int rc = roz_controller_load(c, wasm, len, abi);
    return rc == ROZ_OK ? roz_controller_set_budget(c, &b) : rc;
}

static int load(roz_controller_t *c, roz_abi_t *abi, double *target, const uint8_t *wasm,
                size_t len, int metered)
{
    return load_with(c, abi, target, NULL, wasm, len, metered,
                     (uint64_t)ROZ_CFG_FUEL_PER_SECOND / m->control_rate_hz,
                     1000000000ull / m->control_rate_hz);
}

static int call(roz_controller_t *c, roz_abi_t *abi, int64_t t)
{
    fill_state(state, m->n_states, t);
    roz_abi_begin_tick(abi, t, state);
    return roz_controller_process(c, t);
}

static void print_timing(const char *name, bench_stats_t s, int *first)
{
    printf("%s    {\"name\": \"%s\", \"unit\": \"us\", \"p50\": %.4f, \"p99\": %.4f, "
           "\"max\": %.4f}",
           *first ? "" : ",\n", name, s.p50, s.p99, s.max);
    *first = 0;
}

/* The nn policy: its reference outputs (metered and not, which must
 * agree) into @p ref (NULL: none), then process() per call metered and
 * not, alternating rounds of 100, into @p ns[0], ns[1]. 0, or 2. */
/* Tick @p t of @p c timed: the state filled, then process() alone timed
 * into *ns; its result. */
static int timed_tick(roz_controller_t *c, roz_abi_t *a, int64_t t, uint64_t *ns)
{
    fill_state(state, m->n_states, t);
    roz_abi_begin_tick(a, t, state);
    uint64_t t0 = roz_clock_monotonic_ns(NULL);
    int rc = roz_controller_process(c, t);
    *ns = roz_clock_monotonic_ns(NULL) - t0;
    return rc;
}

/* Writes what the reference run gave to @p ref: its ticks, the ABI's
 * counters @p c (with the nn and metric counts and @p metric_fnv unless it
 * is NULL), then the targets @p target; 0, or 2 when it cannot. */
static int write_ref(const char *ref, const roz_abi_counters_t *c, const uint64_t *metric_fnv,
                     const double *target)
{
    FILE *f = fopen(ref, "w");
    if (f == NULL) {
        fprintf(stderr, "roz_bench_peers_roz: cannot write %s\n", ref);
        return 2;
    }
    fprintf(f, "ticks %d\nsets %llu\nset_clamped %llu\nset_bad_index %llu\n"
               "set_nonfinite %llu\nget_bad_index %llu\n",
            REF_TICKS, (unsigned long long)c->sets, (unsigned long long)c->set_clamped,
            (unsigned long long)c->set_bad_index, (unsigned long long)c->set_nonfinite,
            (unsigned long long)c->get_bad_index);
    if (metric_fnv != NULL)
        fprintf(f, "metrics %llu\nnn_calls %llu\nnn_refused %llu\nmetric_fnv 0x%016llx\n",
                (unsigned long long)c->metrics, (unsigned long long)c->nn_calls,
                (unsigned long long)c->nn_refused, (unsigned long long)*metric_fnv);
    for (uint16_t i = 0; i < m->n_commands; i++) {
        uint64_t bits;
        memcpy(&bits, &target[i], sizeof bits);
        fprintf(f, "target 0x%016llx\n", (unsigned long long)bits);
    }
    fclose(f);
    return 0;
}

static int nn_side(const char *path, const char *ref, size_t calls, uint64_t *ns[2])
{
    static roz_controller_t c[2];
    static roz_abi_t a[2];
    static double target[2][ROZ_CFG_MAX_COMMANDS];
    static roz_metric_ring_t ring[2];
    uint64_t fnv[2] = { 0xcbf29ce484222325ull, 0xcbf29ce484222325ull };
    size_t len;
    uint8_t *wasm = read_file(path, &len);
    if (wasm == NULL) {
        fprintf(stderr, "roz_bench_peers_roz: cannot read %s\n", path);
        return 2;
    }
    for (int k = 0; k < 2; k++) {
        if (load_with(&c[k], &a[k], target[k], &ring[k], wasm, len, k == 0, NN_FUEL,
                      NN_DEADLINE_NS) != ROZ_OK) {
            fprintf(stderr, "roz_bench_peers_roz: %s: %s\n", path, roz_controller_error(&c[k]));
            return 2;
        }
        for (int64_t t = 0; t < REF_TICKS; t++) {
            roz_metric_t mt;
            if (call(&c[k], &a[k], t) != ROZ_OK) {
                fprintf(stderr, "roz_bench_peers_roz: %s: %s\n", path,
                        roz_controller_error(&c[k]));
                return 2;
            }
            while (roz_metric_ring_pop(&ring[k], &mt) == 1) {
                uint64_t bits;
                memcpy(&bits, &mt.value, sizeof bits);
                for (int i = 0; i < 8; i++)
                    fnv[k] = (fnv[k] ^ ((bits >> (8 * i)) & 0xffu)) * 0x100000001b3ull;
            }
        }
    }
    roz_abi_counters_t cnt[2];
    roz_abi_counters_get(&a[0], &cnt[0]);
    roz_abi_counters_get(&a[1], &cnt[1]);
    if (fnv[0] != fnv[1] || memcmp(&cnt[0], &cnt[1], sizeof cnt[0]) != 0 ||
        roz_metric_ring_dropped(&ring[0]) != 0) {
        fprintf(stderr, "roz_bench_peers_roz: %s: unmetered outputs differ from metered\n", path);
        return 1;
    }
    if (ref != NULL && write_ref(ref, &cnt[0], &fnv[0], target[0]) != 0)
        return 2;
    roz_metric_t drop;
    for (size_t r = 0; r < calls; r += 100) {
        for (int k = 0; k < 2; k++) {
            for (size_t i = r; i < r + 100 && i < calls; i++) {
                int rc = timed_tick(&c[k], &a[k], REF_TICKS + (int64_t)i, &ns[k][i]);
                while (roz_metric_ring_pop(&ring[k], &drop) == 1)
                    ;
                if (rc != ROZ_OK) {
                    fprintf(stderr, "roz_bench_peers_roz: %s: %s\n", path,
                            roz_controller_error(&c[k]));
                    return 2;
                }
            }
        }
    }
    roz_controller_unload(&c[0]);
    roz_controller_unload(&c[1]);
    free(wasm);
    return 0;
}

int main(int argc, char **argv)
{
    const char *path = NULL, *ref = NULL, *bulk_path = NULL, *nn_path = NULL, *nn_ref = NULL;
    size_t calls = 20000, len, bulk_len = 0;
    /* 0, 1: the PD metered and not; 2, 3: the bulk PD likewise */
    static roz_controller_t ctl[4];
    static roz_abi_t abi[4];
    static double target[4][ROZ_CFG_MAX_COMMANDS];
    char why[ROZ_CFG_ERROR_LEN];

    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--calls") == 0 && i + 1 < argc)
            calls = strtoul(argv[++i], NULL, 10);
        else if (strcmp(argv[i], "--reference") == 0 && i + 1 < argc)
            ref = argv[++i];
        else if (strcmp(argv[i], "--bulk") == 0 && i + 1 < argc)
            bulk_path = argv[++i];
        else if (strcmp(argv[i], "--nn") == 0 && i + 1 < argc)
            nn_path = argv[++i];
        else if (strcmp(argv[i], "--nn-reference") == 0 && i + 1 < argc)
            nn_ref = argv[++i];
        else
            path = argv[i];
    }
    if (path == NULL || calls < 100) {
        fprintf(stderr, "usage: %s G1_PD.wasm [--calls N>=100] [--reference FILE]\n", argv[0]);
        return 2;
    }
    uint8_t *wasm = read_file(path, &len);
    uint8_t *bulk = bulk_path != NULL ? read_file(bulk_path, &bulk_len) : NULL;
    if (wasm == NULL || (bulk_path != NULL && bulk == NULL)) {
        fprintf(stderr, "roz_bench_peers_roz: cannot read %s\n", wasm == NULL ? path : bulk_path);
        return 2;
    }
    int n_ctl = bulk != NULL ? 4 : 2;

    /* resident memory added by one controller, loaded and run */
    long rss0 = rss_kib();
    if (load(&ctl[0], &abi[0], target[0], wasm, len, 1) != ROZ_OK) {
        fprintf(stderr, "roz_bench_peers_roz: %s: %s\n", path, roz_controller_error(&ctl[0]));
        return 2;
    }
    for (int64_t t = 0; t < VERIFY_TICKS; t++)
        call(&ctl[0], &abi[0], t);
    long rss1 = rss_kib();
    roz_controller_unload(&ctl[0]);

    /* the reference: outputs after REF_TICKS ticks, metered and not */
    for (int k = 0; k < n_ctl; k++) {
        if (load(&ctl[k], &abi[k], target[k], k < 2 ? wasm : bulk, k < 2 ? len : bulk_len,
                 k % 2 == 0) != ROZ_OK) {
            fprintf(stderr, "roz_bench_peers_roz: %s\n", roz_controller_error(&ctl[k]));
            return 2;
        }
        for (int64_t t = 0; t < REF_TICKS; t++) {
            if (call(&ctl[k], &abi[k], t) != ROZ_OK) {
                fprintf(stderr, "roz_bench_peers_roz: %s\n", roz_controller_error(&ctl[k]));
                return 2;
            }
        }
    }
    roz_abi_counters_t cnt[4];
    for (int k = 0; k < n_ctl; k++) {
        roz_abi_counters_get(&abi[k], &cnt[k]);
        if (memcmp(target[0], target[k], sizeof target[0]) != 0 ||
            memcmp(&cnt[0], &cnt[k], sizeof cnt[0]) != 0) {
            fprintf(stderr, "roz_bench_peers_roz: %s outputs differ from the metered PD's\n",
                    k == 1 ? "unmetered" : k == 2 ? "the bulk PD's" : "the unmetered bulk PD's");
            return 1;
        }
    }
    if (ref != NULL && write_ref(ref, &cnt[0], NULL, target[0]) != 0)
        return 2;

    /* load, LOAD_REPS times: the validator alone, the whole load, verify */
    static uint64_t scan_ns[LOAD_REPS], load_ns[LOAD_REPS], verify_ns[LOAD_REPS];
    static roz_controller_t lc;
    static roz_abi_t la;
    static double lt[ROZ_CFG_MAX_COMMANDS];
    for (int r = 0; r < LOAD_REPS; r++) {
        uint32_t process_index;
        uint64_t t0 = roz_clock_monotonic_ns(NULL);
        static roz_load_scratch_t scratch;
        int rc = roz__wasm_scan(wasm, len, &scratch, &process_index, why, sizeof why);
        uint64_t t1 = roz_clock_monotonic_ns(NULL);
        if (rc != ROZ_OK) {
            fprintf(stderr, "roz_bench_peers_roz: %s\n", why);
            return 2;
        }
        scan_ns[r] = t1 - t0;
        t0 = roz_clock_monotonic_ns(NULL);
        rc = load(&lc, &la, lt, wasm, len, 1);
        t1 = roz_clock_monotonic_ns(NULL);
        if (rc != ROZ_OK)
            return 2;
        load_ns[r] = t1 - t0;
        /* the verification: 100 ticks on the current state, outputs discarded */
        t0 = roz_clock_monotonic_ns(NULL);
        for (int64_t t = 0; t < VERIFY_TICKS; t++) {
            roz_abi_begin_tick(&la, t, state);
            rc |= roz_controller_process(&lc, t);
        }
        t1 = roz_clock_monotonic_ns(NULL);
        verify_ns[r] = t1 - t0;
        roz_controller_unload(&lc);
        if (rc != ROZ_OK)
            return 2;
    }

    /* process(), metered and not, alternating rounds of 100 */
    uint64_t *ns[4];
    for (int k = 0; k < 4; k++) {
        ns[k] = calloc(calls, sizeof(uint64_t));
        if (ns[k] == NULL)
            return 2;
    }
    for (size_t r = 0; r < calls; r += 100) {
        for (int k = 0; k < n_ctl; k++) {
            for (size_t i = r; i < r + 100 && i < calls; i++) {
                int rc = timed_tick(&ctl[k], &abi[k], REF_TICKS + (int64_t)i, &ns[k][i]);
                if (rc != ROZ_OK) {
                    fprintf(stderr, "roz_bench_peers_roz: %s\n", roz_controller_error(&ctl[k]));
                    return 2;
                }
            }
        }
    }
    uint64_t units = roz_controller_fuel_used(&ctl[0]);
    uint64_t *nn_ns[2] = { NULL, NULL };
    if (nn_path != NULL) {
        nn_ns[0] = calloc(calls, sizeof(uint64_t));
        nn_ns[1] = calloc(calls, sizeof(uint64_t));
        if (nn_ns[0] == NULL || nn_ns[1] == NULL)
            return 2;
        int rc = nn_side(nn_path, nn_ref, calls, nn_ns);
        if (rc != 0)
            return rc;
    }

    int first = 1;
    printf("{\n  \"engine\": \"roz (wasm3)\",\n  \"version\": \"0.5.0\",\n"
           "  \"checked\": \"reference outputs after %d ticks; metered and unmetered%s equal%s\",\n"
           "  \"figures\": [\n",
           REF_TICKS, bulk != NULL ? ", per channel and bulk," : "",
           nn_path != NULL ? "; the nn policy's likewise" : "");
    print_timing("validate (roz's module scan)", bench_stats(scan_ns, LOAD_REPS), &first);
    print_timing("compile (validate, parse, link, compile)", bench_stats(load_ns, LOAD_REPS),
                 &first);
    print_timing("verify (100 ticks)", bench_stats(verify_ns, LOAD_REPS), &first);
    print_timing("process, metering fuel+deadline", bench_stats(ns[0], calls), &first);
    print_timing("process, metering off", bench_stats(ns[1], calls), &first);
    if (bulk != NULL) {
        print_timing("process, bulk, metering fuel+deadline", bench_stats(ns[2], calls), &first);
        print_timing("process, bulk, metering off", bench_stats(ns[3], calls), &first);
    }
    if (nn_path != NULL) {
        print_timing("process, nn policy, metering fuel+deadline", bench_stats(nn_ns[0], calls),
                     &first);
        print_timing("process, nn policy, metering off", bench_stats(nn_ns[1], calls), &first);
        free(nn_ns[0]);
        free(nn_ns[1]);
    }
    printf(",\n    {\"name\": \"fuel per call\", \"unit\": \"units\", \"value\": %llu}",
           (unsigned long long)units);
    printf(",\n    {\"name\": \"resident memory added\", \"unit\": \"KiB\", \"value\": %ld}\n  ]\n}\n",
           rss1 - rss0);
    for (int k = 0; k < 4; k++) {
        roz_controller_unload(&ctl[k]);
        free(ns[k]);
    }
    free(wasm);
    free(bulk);
    return 0;
}
