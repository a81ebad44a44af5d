/* SPDX-License-Identifier: Apache-2.0 */
/* The firmware images' application (fw_app.h). Nothing here knows the
 * board: the same file runs on the host for the fingerprint comparison. */
#include "fw_app.h"

#include <string.h>

#include "roz/format.h"
#include "roz/loopback.h"
#include "roz/monitor.h"

/* Large: static storage, never the stack. */
static roz_runtime_t rt;
static roz_loopback_t sim;
static roz_port_t port;

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

/* Mean and largest of one monitored kind, in clock units (instructions
 * under QEMU's -icount shift=0: one instruction is one nanosecond). */
static void cost(const fw_platform_t *pf, roz_monitor_kind_t kind, const char *what)
{
    static roz_monitor_stat_t s; /* 2 KiB: not the stack */

    if (roz_monitor_snapshot(roz_runtime_monitor(&rt), kind, &s) != ROZ_OK || s.count == 0)
        return;
    say(pf, "cost: %s mean %llu max %llu", what,
        (unsigned long long)roz_monitor_stat_mean(&s), (unsigned long long)s.max_ns);
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
    say(pf, "roz firmware: %s on %s, controller %s (%zu bytes), %u ticks", m->robot_id, pf->name,
        img->controller, img->wasm_len, (unsigned)img->ticks);

    port = roz_loopback_port(&sim);
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
    out->load_rc = roz_runtime_load(&rt, img->wasm, img->wasm_len, &rep);
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
    out->violations = sim.violations;
    say(pf, "violations: %llu", (unsigned long long)out->violations);
    say(pf, "fingerprint: %016llx", (unsigned long long)out->fingerprint);
    if (cfg.clock != NULL) {
        cost(pf, ROZ_MON_TICK, "tick");
        cost(pf, ROZ_MON_PROCESS, "process");
        cost(pf, ROZ_MON_READ, "port read");
        cost(pf, ROZ_MON_WRITE, "port write");
    }
    roz_runtime_deinit(&rt);
    roz_port_close(&port);
    return 0;
}
