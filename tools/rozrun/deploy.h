/* SPDX-License-Identifier: Apache-2.0 */
/* rozrun --deploy FILE: the deploy sequence of one deployment (roz/stages.h,
 * docs/deploy.md), a TOML file beside the controller:
 *   [deploy]        robot, move_s, stop_damping, and the inputs that switch
 *                   (start, run, stand, stop: names of [[manifest.inputs]])
 *   [deploy.stand]  joints (default: every position command's joint, in the
 *                   manifest's order), pose, kp, kd: one value a joint
 * Every joint with a position command must be in the stand; every value is
 * checked against the manifest, and an error names the file, the key and
 * the channel. Read once at start-up. */
#ifndef ROZRUN_DEPLOY_H
#define ROZRUN_DEPLOY_H

#include "roz/runtime.h"

typedef struct rozrun_deploy {
    roz_stages_config_t cfg;
    double stand[ROZ_CFG_MAX_COMMANDS];
} rozrun_deploy_t;

/* Reads @p path against @p m into @p d. 0, or -1 with a message on stderr. */
int rozrun_deploy_load(rozrun_deploy_t *d, const char *path, const roz_manifest_t *m);

#endif /* ROZRUN_DEPLOY_H */
