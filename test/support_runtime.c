/* SPDX-License-Identifier: Apache-2.0 */
#include "support_runtime.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

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

void roz_test_loopback_config(roz_runtime_config_t *cfg, roz_loopback_t *lb,
                              const roz_manifest_t *m, const roz_params_t *params,
                              roz_test_clock_t *clk)
{
    char err[200] = "";
    roz_port_t port = roz_loopback_port(lb, NULL, NULL);

    if (roz_port_open(&port, m, params, err, sizeof err) != ROZ_OK)
        fail_msg("%s: loopback open: %s", m->robot_id, err);
    roz_test_runtime_config(cfg, m, port, clk);
}

void roz_test_runtime_start(roz_runtime_t *rt, const roz_runtime_config_t *cfg,
                            const char *controller)
{
    int rc = roz_runtime_init(rt, cfg);

    if (rc != ROZ_OK)
        fail_msg("%s: roz_runtime_init: %s", cfg->manifest->robot_id, roz_strerror(rc));
    if (controller != NULL) {
        size_t len;
        const uint8_t *w = roz_test_controller(controller, &len);
        if (roz_runtime_load(rt, w, len, NULL) != ROZ_OK)
            fail_msg("%s: %s refused: %s", cfg->manifest->robot_id, controller,
                     roz_runtime_error(rt));
    }
    rc = roz_runtime_start(rt);
    if (rc != ROZ_OK)
        fail_msg("%s: roz_runtime_start: %s", cfg->manifest->robot_id, roz_strerror(rc));
}
