/* SPDX-License-Identifier: Apache-2.0 */
/* Uses what a consumer gets: its own generated table, its own controller
 * (reach.c, built to wasm32 by roz_add_wasm_controller(); the path of
 * reach.wasm is argv[1]), the core, the loopback port and the built-in
 * registry. Exits non-zero on the first surprise. */
#include <stdio.h>
#include <string.h>

#include "my_arm_manifest.h"
#include "roz/config.h"
#if ROZ_HAS_BUILTIN_MANIFESTS
#include "roz/builtin.h"
#endif
#include "roz/module.h"
#include "roz/port/loopback.h"
#include "roz/manifest.h"
#include "roz/ports.h"
#include "roz/runtime.h"

#define CHECK(cond)                                                   \
    do {                                                              \
        if (!(cond)) {                                                \
            fprintf(stderr, "consumer: check failed: %s\n", #cond);   \
            return 1;                                                 \
        }                                                             \
    } while (0)

/* (module (func (export "process") (param i64))): the smallest controller */
static const uint8_t idle_wasm[] = {
    0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00, 0x01, 0x05, 0x01, 0x60, 0x01,
    0x7e, 0x00, 0x03, 0x02, 0x01, 0x00, 0x07, 0x0b, 0x01, 0x07, 0x70, 0x72, 0x6f,
    0x63, 0x65, 0x73, 0x73, 0x00, 0x00, 0x0a, 0x04, 0x01, 0x02, 0x00, 0x0b,
};

/* (func $f (param i64) (result i64) (i64.add (call $f (i64.add (local.get 0)
 * (i64.const 1))) (local.get 0))), called from process: endless recursion */
static const uint8_t deep_wasm[] = {
    0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00, 0x01, 0x0a, 0x02, 0x60, 0x01, 0x7e, 0x01, 0x7e,
    0x60, 0x01, 0x7e, 0x00, 0x03, 0x03, 0x02, 0x00, 0x01, 0x07, 0x0b, 0x01, 0x07, 0x70, 0x72, 0x6f,
    0x63, 0x65, 0x73, 0x73, 0x00, 0x01, 0x0a, 0x16, 0x02, 0x0c, 0x00, 0x20, 0x00, 0x42, 0x01, 0x7c,
    0x10, 0x00, 0x20, 0x00, 0x7c, 0x0b, 0x07, 0x00, 0x42, 0x00, 0x10, 0x00, 0x1a, 0x0b,
};

static roz_runtime_t rt;
static roz_loopback_t lb;
static uint8_t reach_wasm[ROZ_CFG_WASM_MAX_MODULE_BYTES];

int main(int argc, char **argv)
{
    const roz_manifest_t *m = &roz_manifest_my_arm;

    if (argc != 2) {
        fprintf(stderr, "usage: consumer reach.wasm\n");
        return 2;
    }

    CHECK(roz_manifest_validate(m, NULL) == ROZ_OK);
    CHECK(ROZ_MY_ARM_N_COMMANDS == 2 && m->n_commands == 2);
    CHECK(roz_manifest_find_command(m, "joint2/velocity") == ROZ_MY_ARM_CMD_JOINT2_VELOCITY);
    CHECK(m->commands[ROZ_MY_ARM_CMD_JOINT2_VELOCITY].position_state ==
          ROZ_MY_ARM_STATE_JOINT2_POSITION);
#if ROZ_HAS_BUILTIN_MANIFESTS
    const roz_manifest_t *ur5 = roz_builtin_find("ur5");
    CHECK(ur5 != NULL && ur5->n_commands == 6);
#endif    /* the runtime on the loopback port, as an installed package gives it */
    roz_runtime_config_t cfg;
    char err[128];
    /* the loopback from the registry of the ports the package holds */
    const roz_port_entry_t *pe = roz_ports_find("loopback");
    CHECK(pe != NULL && pe->size == sizeof lb && pe->ops == &roz_loopback_ops);
    roz_port_t port = pe->construct(&lb, NULL, NULL);
    CHECK(roz_port_open(&port, m, NULL, err, sizeof err) == ROZ_OK);
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = port;
    CHECK(roz_runtime_init(&rt, &cfg) == ROZ_OK);
    CHECK(roz_runtime_load(&rt, idle_wasm, sizeof idle_wasm, NULL) == ROZ_OK);
    CHECK(roz_runtime_start(&rt) == ROZ_OK);
    for (int t = 0; t < 10; t++)
        CHECK(roz_runtime_tick(&rt) == ROZ_OK);
    roz_runtime_stats_t st;
    CHECK(roz_runtime_stats(&rt, &st) == ROZ_OK);
    CHECK(st.runtime.writes == 10 && roz_loopback_counters(&lb).violations == 0);
    roz_runtime_deinit(&rt);

    /* endless recursion is refused at verification: by wasm3's value stack,
     * or first by roz's C stack limit where that is small */
    CHECK(roz_port_open(&port, m, NULL, err, sizeof err) == ROZ_OK);
    CHECK(roz_runtime_init(&rt, &cfg) == ROZ_OK);
    CHECK(roz_runtime_load(&rt, deep_wasm, sizeof deep_wasm, NULL) == ROZ_EVERIFY);
    printf("consumer: endless recursion refused: %s\n", roz_runtime_error(&rt));
#if ROZ_CFG_NATIVE_STACK_BYTES <= 8192
    CHECK(strstr(roz_runtime_error(&rt), "native stack limit") != NULL);
#endif
    roz_runtime_deinit(&rt);

    /* the consumer's controller: 300 ticks (3 s) take joint2 to 1 rad */
    size_t len = 0;
    double q[2];
    CHECK(roz_module_read_file(argv[1], reach_wasm, sizeof reach_wasm, &len, err, sizeof err) ==
          ROZ_OK);
    CHECK(roz_port_open(&port, m, NULL, err, sizeof err) == ROZ_OK);
    CHECK(roz_runtime_init(&rt, &cfg) == ROZ_OK);
    CHECK(roz_runtime_load(&rt, reach_wasm, len, NULL) == ROZ_OK);
    CHECK(roz_runtime_start(&rt) == ROZ_OK);
    for (int t = 0; t < 300; t++)
        CHECK(roz_runtime_tick(&rt) == ROZ_OK);
    roz_loopback_true_state(&lb, q);
    CHECK(q[ROZ_MY_ARM_STATE_JOINT2_POSITION] > 0.99 && q[ROZ_MY_ARM_STATE_JOINT2_POSITION] < 1.01);
    CHECK(q[ROZ_MY_ARM_STATE_JOINT1_POSITION] == 0.0);
    CHECK(roz_runtime_faults(&rt) == 0 && roz_loopback_counters(&lb).violations == 0);
    printf("consumer: reach.wasm (%zu bytes) took joint2 to %.4f rad in 300 ticks\n", len,
           q[ROZ_MY_ARM_STATE_JOINT2_POSITION]);
    roz_runtime_deinit(&rt);

    printf("consumer: my_arm %u commands, %u states; built-ins %s; max commands %d; roz %s\n",
           (unsigned)m->n_commands, (unsigned)m->n_states,
           ROZ_HAS_BUILTIN_MANIFESTS ? "found" : "off", ROZ_CFG_MAX_COMMANDS, ROZ_VERSION_STRING);
    return 0;
}
