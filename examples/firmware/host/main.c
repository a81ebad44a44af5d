/* SPDX-License-Identifier: Apache-2.0 */
/* The firmware images' application (../app/fw_app.c) on the host: the same
 * controller, manifest and tick count give the same report lines and the
 * same fingerprint as the image in QEMU, which the firmware tests compare.
 *
 *   roz_fw_host ROBOT_ID CONTROLLER.wasm [TICKS]
 *
 * The host run has no clock (nothing it prints depends on one). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fw_app.h"
#include "roz/builtin.h"
#include "roz/module.h"

static uint8_t wasm[ROZ_CFG_WASM_MAX_MODULE_BYTES];

static void print_line(const char *line)
{
    puts(line);
}

int main(int argc, char **argv)
{
    fw_platform_t pf = { "host", NULL, NULL, print_line, NULL };
    fw_image_t img;
    fw_result_t res;
    char err[256];
    size_t len = 0;
    const char *name;

    if (argc < 3 || argc > 4) {
        fprintf(stderr, "usage: %s ROBOT_ID CONTROLLER.wasm [TICKS]\n", argv[0]);
        return 2;
    }
    const roz_manifest_t *m = roz_builtin_find(argv[1]);
    if (m == NULL) {
        fprintf(stderr, "%s: no built-in manifest '%s'\n", argv[0], argv[1]);
        return 2;
    }
    if (roz_module_read_file(argv[2], wasm, sizeof wasm, &len, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", argv[0], err);
        return 2;
    }
    name = strrchr(argv[2], '/');
    memset(&img, 0, sizeof img);
    img.controller = name != NULL ? name + 1 : argv[2];
    img.manifest = m;
    img.wasm = wasm;
    img.wasm_len = len;
    img.ticks = argc == 4 ? (uint32_t)strtoul(argv[3], NULL, 10) : FW_TICKS;
    return fw_app_run(&img, &pf, &res);
}
