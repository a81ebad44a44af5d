/* SPDX-License-Identifier: Apache-2.0 */
/*
 * roz_bench_mujoco [TICKS] [--json FILE]: the whole roz tick on the MuJoCo
 * G1 (the example stand controller, the safety filter, the port's actuator
 * law and sensors, one 2 ms physics step a tick) against a bare loop of the
 * same mj_step calls on the same model in the same run: the bare loop
 * replays the controls the roz run applied, from the same start, so it
 * steps through the same states and contacts. Also: simulated seconds per
 * wall-clock second, and the port's open. Each tick and each bare step is
 * timed; the two runs alternate in blocks so a slow spell of the machine
 * falls on both.
 */
/* white-box: the bare loop steps the port's own model and data (roz/private.h) */
#define ROZ_PRIVATE_ACCESS
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mujoco/mujoco.h>

#include "bench_json.h"
#include "roz/builtin.h"
#include "roz/hal/clock.h"
#include "roz/module.h"
#include "roz/port/mujoco.h"
#include "roz/runtime.h"

#define BLOCK 100

static roz_mujoco_t mj;
static roz_runtime_t rt;
static bench_json_t json;

static uint64_t now(void)
{
    return roz_clock_monotonic_ns(NULL);
}

int main(int argc, char **argv)
{
    argc = bench_json_args(&json, "mujoco", argc, argv);
    if (argc < 0)
        return 2;
    int ticks = argc > 1 ? atoi(argv[1]) : 1000; /* it stands for all of them */
    if (ticks < BLOCK)
        ticks = BLOCK;
    ticks -= ticks % BLOCK;
    const roz_manifest_t *m = roz_builtin_find("unitree_g1");
    roz_port_t port = roz_mujoco_port(&mj, NULL, NULL);
    /* one step a tick, so the controls of each step are those the tick left;
     * the gantry for the stand's ramp, so the run stays on its feet */
    roz_param_t items[2] = { { "timestep", "0.002" }, { "gantry", "0:500" } };
    roz_params_t params = { items, 2 };
    char err[512];
    uint64_t t0 = now();
    if (roz_port_open(&port, m, &params, err, sizeof err) != ROZ_OK) {
        fprintf(stderr, "roz_bench_mujoco: %s\n", err);
        return 2;
    }
    uint64_t open_ns = now() - t0;

    static uint8_t wasm[ROZ_CFG_WASM_MAX_MODULE_BYTES];
    size_t len = 0;
    if (roz_module_read_file(ROZ_BENCH_CONTROLLER, wasm, sizeof wasm, &len, err, sizeof err) !=
        ROZ_OK) {
        fprintf(stderr, "roz_bench_mujoco: %s\n", err);
        return 2;
    }
    roz_runtime_config_t cfg;
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = port;
    cfg.clock = roz_clock_monotonic_ns;
    cfg.budget_ns = UINT64_MAX;
    cfg.monitor_jitter = 0;
    if (roz_runtime_init(&rt, &cfg) != ROZ_OK || roz_runtime_load(&rt, wasm, len, NULL) != ROZ_OK ||
        roz_runtime_start(&rt) != ROZ_OK) {
        fprintf(stderr, "roz_bench_mujoco: the runtime refused: %s\n", roz_runtime_error(&rt));
        return 2;
    }

    /* the bare side: a copy of the port's model and its start */
    mjModel *bm = mj_copyModel(NULL, mj.model);
    mjData *bd = mj_copyData(NULL, bm, mj.data);
    int nu = bm->nu;
    double *ctrl = malloc((size_t)ticks * (size_t)nu * sizeof *ctrl);
    uint8_t *gantry = malloc((size_t)ticks);
    uint64_t *roz_ns = malloc((size_t)ticks * sizeof *roz_ns);
    uint64_t *bare_ns = malloc((size_t)ticks * sizeof *bare_ns);
    uint64_t *ctl_ns = malloc((size_t)ticks * sizeof *ctl_ns); /* process() of each tick */
    uint64_t *own_ns = malloc((size_t)ticks * sizeof *own_ns); /* the tick less process() */
    if (ctrl == NULL || gantry == NULL || roz_ns == NULL || bare_ns == NULL || ctl_ns == NULL ||
        own_ns == NULL)
        return 2;
    int rc = roz_runtime_tick(&rt); /* tick 0: the first read steps nothing */
    uint64_t steps0 = mj.steps, roz_total = 0, bare_total = 0;
    for (int b = 0; b < ticks; b += BLOCK) {
        for (int t = b; t < b + BLOCK; t++) {
            uint64_t a = now();
            rc = roz_runtime_tick(&rt);
            roz_ns[t] = now() - a;
            roz_total += roz_ns[t];
            roz_runtime_stats_t st;
            ctl_ns[t] = roz_runtime_stats(&rt, &st) == ROZ_OK ? st.last_process_ns : 0u;
            own_ns[t] = roz_ns[t] > ctl_ns[t] ? roz_ns[t] - ctl_ns[t] : 0u;
            memcpy(ctrl + (size_t)t * nu, mj.data->ctrl, (size_t)nu * sizeof *ctrl);
            gantry[t] = mj.gantry_eq >= 0 ? mj.data->eq_active[mj.gantry_eq] : 0;
        }
        for (int t = b; t < b + BLOCK; t++) {
            if (mj.gantry_eq >= 0) {
                bd->eq_active[mj.gantry_eq] = gantry[t];
                memcpy(bm->eq_data, mj.model->eq_data, (size_t)bm->neq * mjNEQDATA * sizeof(mjtNum));
            }
            memcpy(bd->ctrl, ctrl + (size_t)t * nu, (size_t)nu * sizeof *ctrl);
            uint64_t a = now();
            mj_step(bm, bd);
            bare_ns[t] = now() - a;
            bare_total += bare_ns[t];
        }
    }
    (void)rc;
    uint64_t steps = mj.steps - steps0;
    double drift = 0.0;
    for (int i = 0; i < bm->nq; i++) {
        double e = bd->qpos[i] - mj.data->qpos[i];
        drift += e < 0 ? -e : e;
    }
    roz_mujoco_base_t base;
    roz_mujoco_base(&mj, &base);
    double sim_s = (double)steps * mj.timestep;
    printf("G1 on MuJoCo %s, %d ticks (%.1f simulated s, %llu steps of %g s); open %.1f ms\n",
           mj_versionString(), ticks, sim_s, (unsigned long long)steps, mj.timestep,
           open_ns / 1e6);
    printf("  roz tick (controller, filter, law, sensors, mj_step): %.1f us a tick\n",
           roz_total / 1e3 / ticks);
    printf("  bare mj_step, the same controls:                       %.1f us a step\n",
           bare_total / 1e3 / ticks);
    printf("  roz adds %.1f %% (%.1f us a tick); %.1fx real time (roz), %.1fx (bare)\n",
           100.0 * ((double)roz_total / (double)bare_total - 1.0),
           (roz_total - (double)bare_total) / 1e3 / ticks, sim_s / (roz_total / 1e9),
           sim_s / (bare_total / 1e9));
    uint64_t ctl_total = 0;
    for (int t = 0; t < ticks; t++)
        ctl_total += ctl_ns[t];
    printf("  of the roz tick, process() (the controller) %.1f us; the rest adds %.1f %%\n",
           ctl_total / 1e3 / ticks,
           100.0 * ((double)(roz_total - ctl_total) / (double)bare_total - 1.0));
    printf("  the bare loop's state differs from roz's by %g (sum |qpos|): %s; pelvis %.3f m\n",
           drift, drift == 0.0 ? "the same steps" : "NOT the same steps", base.pos[2]);
    bench_json_timing(&json, "unitree_g1: whole roz tick", bench_stats(roz_ns, (size_t)ticks));
    bench_json_timing(&json, "unitree_g1: bare mj_step", bench_stats(bare_ns, (size_t)ticks));
    bench_json_timing(&json, "unitree_g1: process()", bench_stats(ctl_ns, (size_t)ticks));
    bench_json_timing(&json, "unitree_g1: roz tick less process()",
                      bench_stats(own_ns, (size_t)ticks));
    bench_json_value(&json, "unitree_g1: real-time factor (roz)", sim_s / (roz_total / 1e9), "x");
    bench_json_value(&json, "unitree_g1: real-time factor (bare)", sim_s / (bare_total / 1e9), "x");
    bench_json_value(&json, "unitree_g1: open", open_ns / 1e6, "ms");
    bench_json_close(&json);
    roz_runtime_deinit(&rt);
    roz_port_close(&port);
    mj_deleteData(bd);
    mj_deleteModel(bm);
    free(ctrl);
    free(gantry);
    free(roz_ns);
    free(bare_ns);
    free(ctl_ns);
    free(own_ns);
    return 0;
}
