/* SPDX-License-Identifier: Apache-2.0 */
/* rozrun --replay: a recording's states fed tick by tick to a controller
 * through the runtime (a port of its own that plays the recording back),
 * its targets and applied commands compared bit for bit with the recorded
 * ones. */
#ifndef ROZRUN_REPLAY_H
#define ROZRUN_REPLAY_H

#include "roz/manifest.h"

typedef struct rozrun_replay_options {
    const char *recording;  /* the MCAP file */
    const char *controller; /* the module to replay */
    const char *robot;      /* --robot, or NULL: the recording's robot, built in */
    const char *record;     /* --record: the new run as MCAP, or NULL */
    const char *trace;      /* --trace: the new run as CSV, or NULL */
    int         record_compression; /* the new recording's (ROZ_MCAP_COMPRESS_*) */
    const char *deploy;     /* --deploy: another sequence than the recorded, or NULL */
} rozrun_replay_options_t;

/* Runs the replay and prints its report. @p robot: the manifest --robot
 * named, or NULL. Returns rozrun's exit status: 0 identical (or another
 * controller ran through), 4 diverged, 2 a bad recording, robot or
 * controller, 3 the new recording or trace could not be written. */
int rozrun_replay(const rozrun_replay_options_t *o, const roz_manifest_t *robot);

#endif /* ROZRUN_REPLAY_H */
