/* SPDX-License-Identifier: Apache-2.0 */
#include "support_runtime.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

void roz_test_loopback_config(roz_runtime_config_t *cfg, roz_loopback_t *lb,
                              const roz_manifest_t *m, const roz_params_t *params,
                              roz_test_clock_t *clk)
{
    char err[200] = "";
    roz_port_t port = roz_loopback_port(lb, NULL, NULL);

    if (roz_port_open(&port, m, params, err, sizeof err) != ROZ_OK)
        fail_msg("%s: loopback open: %s", m->robot_id, err);
    roz_runtime_config_default(cfg);
    cfg->manifest = m;
    cfg->port = port;
    cfg->clock = roz_test_clock;
    cfg->clock_ctx = clk;
}
