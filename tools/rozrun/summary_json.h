/* SPDX-License-Identifier: Apache-2.0 */
/* rozrun's summary as JSON (--summary-json FILE, docs/rozrun.md): what a
 * program judges a run by (roz-campaign), beside the summary a person reads.
 *
 * The watch follows the run tick by tick, on the tick's thread, without heap
 * or text: the simulator's base height (lowest, when, final), its largest
 * tilt, a decimated series of the height for plots, the peak joint speed
 * the robot's state reported (each "<joint>/velocity" state), and the applied commands
 * checked against the manifest's limits (what reached the port: never
 * outside them, so the count stays 0 behind the filter). The file is written
 * once, after the run, to FILE.tmp and renamed, so a reader never sees half
 * of one. */
#ifndef ROZRUN_SUMMARY_JSON_H
#define ROZRUN_SUMMARY_JSON_H

#include <stdint.h>
#include <stdio.h>

#include "roz/manifest.h"
#include "roz/port.h"

/* Points of the height series at most (decimated to fit). */
#define ROZRUN_SERIES_MAX 1000u

typedef struct rozrun_watch {
    int      truth;          /* 1: the port gave a floating base's truth at least once */
    uint64_t every;          /* a series point every this many ticks */
    double   z_min, z_final, z_start;
    uint64_t z_min_tick;
    double   tilt_max;       /* rad, largest |roll| or |pitch| */
    double   x0, y0, x_final, y_final;
    double   series[ROZRUN_SERIES_MAX];
    uint32_t n_series;
    uint64_t wire_violations; /* applied values outside their channel's limits, or not finite */
    uint64_t ticks;
    int      speeds_found;   /* the joint velocity states below were looked up */
    uint16_t n_speeds, speeds[ROZ_CFG_MAX_STATES]; /* "<joint>/velocity" states */
    double   speed_max;      /* |rad/s| (or m/s), the largest any of them reported; -1: none */
    int32_t  speed_state;    /* which; -1: none yet */
    uint64_t speed_tick;
} rozrun_watch_t;

/* Start-up: @p ticks the run's length (0: until stopped). */
void rozrun_watch_init(rozrun_watch_t *w, uint64_t ticks);

/* The tick's thread, after each tick: @p applied the commands the port was
 * given this tick (n_commands), NULL when none; @p state the state the tick
 * read (n_states), NULL when none. No heap, no text (the joints' velocity
 * states are found by name once, on the first tick). */
void rozrun_watch_tick(rozrun_watch_t *w, const roz_port_t *port, const roz_manifest_t *m,
                       const double *applied, const double *state);

/* The JSON writer's helpers, for main.c's summary: a string (escaped), a
 * number (null when not finite), "key": before either. */
void rozrun_json_str(FILE *f, const char *s);
void rozrun_json_num(FILE *f, double x);
void rozrun_json_key(FILE *f, int *first, const char *key);

/* The watch's part of the summary: "truth": {...} (null without a floating
 * base), "wire_violations" and "joint_speed_max" ({"value", "joint",
 * "time_s"}; null without joint velocity states). */
void rozrun_watch_json(FILE *f, int *first, const rozrun_watch_t *w, const roz_manifest_t *m,
                       uint32_t rate_hz);

#endif /* ROZRUN_SUMMARY_JSON_H */
