/* SPDX-License-Identifier: Apache-2.0 */
/* The firmware images' application, portable: it runs on the Cortex-M
 * boards (cortex_m/) and, unchanged, on the host (host/), which is how the
 * host's fingerprint of the same controller, manifest and tick count is
 * computed for comparison. It loads a controller (verified), runs it for a
 * number of ticks through roz_runtime_tick() on the image's plant, and
 * prints what it saw, one line at a time, through the platform's print. */
#ifndef ROZ_FW_APP_H
#define ROZ_FW_APP_H

#include <stddef.h>
#include <stdint.h>

#include "roz/aot.h"
#include "roz/controller.h"
#include "roz/manifest.h"
#include "roz/port.h"
#include "roz/runtime.h"

/** The robot the application drives: a port, and the count of values
 *  outside the manifest that reached the robot through it. Each image links
 *  one definition of fw_plant: the loopback simulator (fw_plant_loopback.c)
 *  or a drive's registers in memory with no simulator (fw_plant_regs.c, the
 *  shape of a firmware's own port). */
typedef struct fw_plant {
    roz_port_t (*port)(void);       /* the port, constructed, not yet open */
    uint64_t (*violations)(void);   /* after the run */
} fw_plant_t;

extern const fw_plant_t fw_plant;

/** What the platform gives the application. */
typedef struct fw_platform {
    const char  *name;      /* "cortex-m4f (mps2-an386)", "host" */
    roz_clock_fn clock;     /* the runtime's clock (deadline, monitor); NULL = none */
    void        *clock_ctx;
    void (*print)(const char *line); /* one line, without its newline */
    roz_load_scratch_t *scratch;     /* the validator's scratch; NULL: the stack */
} fw_platform_t;

/** 1: the image's controller is compiled into it ahead of time (roz/aot.h)
 *  and the application never calls wasm3's loader, so the image links no
 *  interpreter and no module validator (the build ran it). */
#ifndef FW_AOT
#define FW_AOT 0
#endif

/** One image: a controller on a robot for a number of ticks. */
typedef struct fw_image {
    const char           *controller; /* its name, for the report */
    const roz_manifest_t *manifest;
    const uint8_t        *wasm;       /* the module wasm3 loads (not FW_AOT) */
    size_t                wasm_len;
    const roz_aot_module_t *aot;      /* the compiled controller (FW_AOT) */
    uint32_t              ticks;
    int                   use_clock;  /* 0: the runtime gets no clock (fuel alone) */
} fw_image_t;

/** What a run found. */
typedef struct fw_result {
    int      load_rc;         /* roz_runtime_load()'s (or _load_aot()'s) result */
    uint64_t fingerprint;     /* FNV-1a 64 over every tick's state and commands */
    unsigned faults;          /* latched at the end */
    uint32_t faulted_ticks;   /* ticks that ended with a fault latched */
    uint32_t tick_errors;     /* roz_runtime_tick() calls that did not return ROZ_OK */
    uint32_t fault_tick;      /* the tick the first fault latched at, or UINT32_MAX */
    uint64_t violations;      /* values outside the manifest at the robot: must be 0 */
} fw_result_t;

/** Runs the image; prints the report lines. Returns 0 when the controller
 *  loaded and every tick ran (faults are reported, not failures). */
int fw_app_run(const fw_image_t *img, const fw_platform_t *pf, fw_result_t *out);

/** Ticks per run of the images. */
#define FW_TICKS 1000u

#endif /* ROZ_FW_APP_H */
