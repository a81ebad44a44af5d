/* SPDX-License-Identifier: Apache-2.0 */
/* The firmware images' application (fw_app.h). Nothing here knows the
 * board: the same file runs on the host for the fingerprint comparison. */
#include "fw_app.h"

#include <string.h>

#include "roz/filter.h"
#include "roz/format.h"
#include "roz/monitor.h"

/* Large: static storage, never the stack. */
static roz_runtime_t rt;
static roz_port_t port;
static roz_filter_t filter; /* the safety filter alone, for its cost */
static double filter_out[ROZ_CFG_MAX_COMMANDS];

/* Calls of the safety filter timed for its cost. */
#define FILTER_RUNS 64

/* ---- the fingerprint --------------------------------------------------------- */

/* FNV-1a 64 over little-endian bytes: the same on every target. */
#define FNV_OFFSET 0xcbf29ce484222325u
#define FNV_PRIME  0x100000001b3u

static uint64_t fnv_u64(uint64_t h, uint64_t v)
{
    for (int i = 0; i < 8; i++) {
        h ^= (uint8_t)(v >> (8 * i));
        h *= FNV_PRIME;
    }
    return h;
}

static uint64_t fnv_doubles(uint64_t h, const double *v, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        uint64_t bits;
        memcpy(&bits, &v[i], sizeof bits);
        h = fnv_u64(h, bits);
    }
    return h;
}

/* ---- the report -------------------------------------------------------------- */

static void say(const fw_platform_t *pf, const char *fmt, ...) ROZ_FORMAT_CHECK(2, 3);

static void say(const fw_platform_t *pf, const char *fmt, ...)
{
    char line[ROZ_CFG_ERROR_LEN + 64];
    va_list ap;

    va_start(ap, fmt);
    roz_vformat(line, sizeof line, fmt, ap);
    va_end(ap);
    pf->print(line);
}

/* Mean and largest of one monitored kind, in clock units: instructions
 * under QEMU's -icount shift=0 (one instruction is one nanosecond of virtual
 * time), emulation estimates of the cost on a real core. Returns the mean. */
static uint64_t cost(const fw_platform_t *pf, roz_monitor_kind_t kind, const char *what)
{
    static roz_monitor_stat_t s; /* 2 KiB: not the stack */

    if (roz_monitor_snapshot(roz_runtime_monitor(&rt), kind, &s) != ROZ_OK || s.count == 0)
        return 0;
    say(pf, "cost: %-12s mean %6llu max %6llu", what,
        (unsigned long long)roz_monitor_stat_mean(&s), (unsigned long long)s.max_ns);
    return roz_monitor_stat_mean(&s);
}

/* ---- public ------------------------------------------------------------------- */

int fw_app_run(const fw_image_t *img, const fw_platform_t *pf, fw_result_t *out)
{
    const roz_manifest_t *m = img->manifest;
    roz_runtime_config_t cfg;
    roz_verify_report_t rep;
    roz_runtime_stats_t st;
    char err[ROZ_CFG_ERROR_LEN];
    uint64_t h = FNV_OFFSET;

    memset(out, 0, sizeof *out);
    out->fault_tick = UINT32_MAX;
#if FW_AOT
    say(pf, "roz firmware: %s on %s, controller %s (compiled ahead of time), %u ticks",
        m->robot_id, pf->name, img->controller, (unsigned)img->ticks);
#else
    say(pf, "roz firmware: %s on %s, controller %s (%zu bytes), %u ticks", m->robot_id, pf->name,
        img->controller, img->wasm_len, (unsigned)img->ticks);
#endif

    port = fw_plant.port();
    if (roz_port_open(&port, m, NULL, err, sizeof err) != ROZ_OK) {
        say(pf, "error: port: %s", err);
        return 1;
    }
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = port;
    cfg.monitor_jitter = 0; /* ticks run back to back, in simulated time */
    cfg.load_scratch = pf->scratch;
    if (img->use_clock) {
        cfg.clock = pf->clock;
        cfg.clock_ctx = pf->clock_ctx;
    }
    if (roz_runtime_init(&rt, &cfg) != ROZ_OK) {
        say(pf, "error: runtime init");
        return 1;
    }
#if FW_AOT
    out->load_rc = roz_runtime_load_aot(&rt, img->aot, &rep);
#else
    out->load_rc = roz_runtime_load(&rt, img->wasm, img->wasm_len, &rep);
#endif
    if (out->load_rc != ROZ_OK) {
        say(pf, "error: load: %s", roz_runtime_error(&rt));
        return 1;
    }
    say(pf, "verify: %u ticks, fuel max %llu of %llu per tick", (unsigned)rep.ticks_run,
        (unsigned long long)rep.max_fuel, (unsigned long long)rep.fuel_budget);
    if (roz_port_activate(&port) != ROZ_OK || roz_runtime_start(&rt) != ROZ_OK) {
        say(pf, "error: start");
        return 1;
    }

    for (uint32_t t = 0; t < img->ticks; t++) {
        /* not ROZ_OK while a fault is latched: counted, reported below */
        if (roz_runtime_tick(&rt) != ROZ_OK)
            out->tick_errors++;
        unsigned f = roz_runtime_faults(&rt);
        if (f != 0u) {
            out->faulted_ticks++;
            if (out->fault_tick == UINT32_MAX)
                out->fault_tick = t;
        }
        h = fnv_u64(h, t);
        h = fnv_u64(h, f);
        h = fnv_doubles(h, roz_runtime_last_state(&rt), m->n_states);
        h = fnv_doubles(h, roz_runtime_last_commands(&rt), m->n_commands);
    }
    out->fingerprint = h;
    out->faults = roz_runtime_faults(&rt);

    if (roz_runtime_stats(&rt, &st) != ROZ_OK) {
        say(pf, "error: stats");
        return 1;
    }
    say(pf, "run: %llu ticks, %llu by the controller, %llu writes, faults 0x%x",
        (unsigned long long)st.runtime.ticks, (unsigned long long)st.runtime.controller_ticks,
        (unsigned long long)st.runtime.writes, out->faults);
    if (out->faults != 0u) {
        say(pf, "fault: %s", roz_runtime_fault_message(&rt));
        say(pf, "fault: latched at tick %lu; %lu ticks ran with it latched, %lu of them "
            "returned an error", (unsigned long)out->fault_tick,
            (unsigned long)out->faulted_ticks, (unsigned long)out->tick_errors);
    }
    out->violations = fw_plant.violations();
    say(pf, "violations: %llu", (unsigned long long)out->violations);
    say(pf, "fingerprint: %016llx", (unsigned long long)out->fingerprint);
    if (cfg.clock != NULL) {
        say(pf, "cost: instructions per tick, emulation estimates (QEMU -icount shift=0)");
        uint64_t tick = cost(pf, ROZ_MON_TICK, "tick");
        uint64_t proc = cost(pf, ROZ_MON_PROCESS, "process()");
        uint64_t rd = cost(pf, ROZ_MON_READ, "port read");
        uint64_t wr = cost(pf, ROZ_MON_WRITE, "port write");
        /* the rest of the tick: the snapshot, the safety filter, the
         * buffers, the monitor and the counters */
        if (tick > proc + rd + wr)
            say(pf, "cost: %-12s mean %6llu", "runtime",
                (unsigned long long)(tick - proc - rd - wr));
        /* of which the safety filter: the runtime's own, on the last
         * tick's targets and state, timed alone (FILTER_RUNS calls, less
         * as many empty clock readings) */
        const double *targets = roz_runtime_last_targets(&rt);
        if (targets != NULL && roz_filter_init(&filter, m) == ROZ_OK) {
            const double *state = roz_runtime_last_state(&rt);
            roz_filter_prime(&filter, state);
            uint64_t t0 = pf->clock(pf->clock_ctx);
            for (int i = 0; i < FILTER_RUNS; i++)
                roz_filter_apply(&filter, targets, state, ROZ_STOP_NONE, filter_out);
            uint64_t t1 = pf->clock(pf->clock_ctx);
            uint64_t t2 = pf->clock(pf->clock_ctx);
            uint64_t spent = (t1 - t0) > (t2 - t1) ? (t1 - t0) - (t2 - t1) : 0;
            say(pf, "cost: %-12s mean %6llu (of the runtime's)", "filter",
                (unsigned long long)(spent / FILTER_RUNS));
        }
    }
    roz_runtime_deinit(&rt);
    roz_port_close(&port);
    return 0;
}
