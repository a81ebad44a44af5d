/* SPDX-License-Identifier: Apache-2.0 */
#include "support_runtime.h"

#include <math.h> /* isfinite */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "support_stats.h"

void roz_test_runtime_config(roz_runtime_config_t *cfg, const roz_manifest_t *m,
                             roz_port_t port, roz_test_clock_t *clk)
{
    char err[200] = "";

    if (!port.opened && roz_port_open(&port, m, NULL, err, sizeof err) != ROZ_OK)
        fail_msg("%s: %s open: %s", m->robot_id, port.ops->name, err);
    roz_runtime_config_default(cfg);
    cfg->manifest = m;
    cfg->port = port;
    if (clk != NULL) {
        cfg->clock = roz_test_clock;
        cfg->clock_ctx = clk;
    }
}

void roz_test_port_open(roz_port_t *port, const roz_manifest_t *m, const roz_params_t *params)
{
    char err[512] = "";

    if (roz_port_open(port, m, params, err, sizeof err) != ROZ_OK)
        fail_msg("%s: %s open: %s", m->robot_id, port->ops->name, err);
}

roz_params_t roz_test_params_kv(const char *kv, roz_param_t *item, char *buf, size_t n)
{
    const char *eq = kv != NULL ? strchr(kv, '=') : NULL;

    if (eq == NULL)
        return (roz_params_t){ item, 0 };
    snprintf(buf, n, "%.*s", (int)(eq - kv), kv);
    item->key = buf;
    item->value = eq + 1;
    return (roz_params_t){ item, 1 };
}

void roz_test_physics_config(roz_runtime_config_t *cfg, const roz_manifest_t *m,
                             roz_port_t port, roz_test_clock_t *clk)
{
    *clk = (roz_test_clock_t){ 0, 1000 };
    roz_test_runtime_config(cfg, m, port, clk);
    cfg->budget_ns = UINT64_MAX;
    cfg->monitor_jitter = 0;
}

void roz_test_loopback_config(roz_runtime_config_t *cfg, roz_loopback_t *lb,
                              const roz_manifest_t *m, const roz_params_t *params,
                              roz_test_clock_t *clk)
{
    roz_port_t port = roz_loopback_port(lb, NULL, NULL);

    roz_test_port_open(&port, m, params);
    roz_test_runtime_config(cfg, m, port, clk);
}

void roz_test_runtime_load(roz_runtime_t *rt, const uint8_t *w, size_t len, const char *name)
{
    if (roz_runtime_load(rt, w, len, NULL) != ROZ_OK)
        fail_msg("%s refused: %s", name, roz_runtime_error(rt));
}

void roz_test_runtime_start_wasm(roz_runtime_t *rt, const roz_runtime_config_t *cfg,
                                 const uint8_t *w, size_t len, const char *name)
{
    int rc = roz_runtime_init(rt, cfg);

    if (rc != ROZ_OK)
        fail_msg("%s: roz_runtime_init: %s", cfg->manifest->robot_id, roz_strerror(rc));
    if (w != NULL)
        roz_test_runtime_load(rt, w, len, name);
    rc = roz_runtime_start(rt);
    if (rc != ROZ_OK)
        fail_msg("%s: roz_runtime_start: %s", cfg->manifest->robot_id, roz_strerror(rc));
}

void roz_test_runtime_start(roz_runtime_t *rt, const roz_runtime_config_t *cfg,
                            const char *controller)
{
    size_t len = 0;
    const uint8_t *w = controller != NULL ? roz_test_controller(controller, &len) : NULL;

    roz_test_runtime_start_wasm(rt, cfg, w, len, controller);
}

void roz_test_frames_reset(roz_test_frames_t *f, const roz_runtime_t *rt,
                           const roz_manifest_t *m, int limit_stops_jump)
{
    memset(f, 0, sizeof *f);
    f->rt = rt;
    f->m = m;
    f->limit_stops_jump = limit_stops_jump;
}

void roz_test_frames_check(roz_test_frames_t *f, const double *cmd, unsigned long long tick)
{
    int immediate = (roz_runtime_faults(f->rt) & ROZ_FAULT_IMMEDIATE_MASK) != 0;

    for (uint16_t i = 0; i < f->m->n_commands; i++) {
        const roz_channel_t *c = &f->m->commands[i];
        uint32_t stops = roz_test_channel(f->rt, i).limit_stops;
        int limited = f->limit_stops_jump && stops != f->stops_before[i];
        f->stops_before[i] = stops;
        if (!isfinite(cmd[i]) || cmd[i] < c->min || cmd[i] > c->max)
            fail_msg("tick %llu: command %u = %g outside [%g, %g]", tick, i, cmd[i], c->min,
                     c->max);
        double step = cmd[i] > f->prev[i] ? cmd[i] - f->prev[i] : f->prev[i] - cmd[i];
        if (f->have_prev && !immediate && !limited && c->max_rate > 0.0 &&
            step > c->max_rate + 1e-12)
            fail_msg("tick %llu: command %u jumped %g -> %g, max_rate %g", tick, i, f->prev[i],
                     cmd[i], c->max_rate);
        f->prev[i] = cmd[i];
    }
    f->have_prev = 1;
}

int roz_test_buffer_port_read(void *self, double *state, size_t n)
{
    roz_buffer_frame_t f;
    int rc = roz_buffer_read((roz_buffer_t *)self, &f);

    if (rc >= 0)
        memcpy(state, f.values, n * sizeof state[0]);
    return rc;
}
