/* SPDX-License-Identifier: Apache-2.0 */
/* rozrun's summary as JSON: summary_json.h says what. */
#include "summary_json.h"

#include <math.h>
#include <string.h>

#include "trace.h"

void rozrun_watch_init(rozrun_watch_t *w, uint64_t ticks)
{
    memset(w, 0, sizeof *w);
    w->z_min = INFINITY;
    w->z_final = w->z_start = NAN;
    w->every = ticks / ROZRUN_SERIES_MAX + 1u;
    w->speed_max = -1.0;
    w->speed_state = -1;
}

/* The states that are a joint's velocity: "<joint>/velocity", of type
 * velocity (the IMU's angular velocity is "base_imu/angular_velocity.x"). */
static void find_speeds(rozrun_watch_t *w, const roz_manifest_t *m)
{
    static const char suffix[] = "/velocity";
    w->speeds_found = 1;
    for (uint16_t i = 0; i < m->n_states; i++) {
        const char *name = m->states[i].name;
        size_t n = strlen(name), k = sizeof suffix - 1u;
        if (m->states[i].type == ROZ_IF_VELOCITY && n > k && strcmp(name + n - k, suffix) == 0)
            w->speeds[w->n_speeds++] = i;
    }
}

void rozrun_watch_tick(rozrun_watch_t *w, const roz_port_t *port, const roz_manifest_t *m,
                       const double *applied, const double *state)
{
    uint64_t tick = w->ticks++;
    if (!w->speeds_found)
        find_speeds(w, m);
    if (state != NULL) {
        for (uint16_t k = 0; k < w->n_speeds; k++) {
            double v = fabs(state[w->speeds[k]]);
            if (v > w->speed_max) { /* NaN never is */
                w->speed_max = v;
                w->speed_state = w->speeds[k];
                w->speed_tick = tick;
            }
        }
    }
    if (applied != NULL) {
        for (uint16_t i = 0; i < m->n_commands; i++) {
            double v = applied[i];
            if (!isfinite(v) || v < m->commands[i].min || v > m->commands[i].max)
                w->wire_violations++;
        }
    }
    double t[ROZRUN_TRUTH_VALUES];
    if (!rozrun_trace_truth(port, t))
        return;
    if (!w->truth) {
        w->truth = 1;
        w->z_start = t[2];
        w->x0 = t[0];
        w->y0 = t[1];
    }
    if (t[2] < w->z_min) {
        w->z_min = t[2];
        w->z_min_tick = tick;
    }
    w->z_final = t[2];
    w->x_final = t[0];
    w->y_final = t[1];
    double tilt = fmax(fabs(t[3]), fabs(t[4]));
    if (tilt > w->tilt_max)
        w->tilt_max = tilt;
    if (tick % w->every == 0 && w->n_series < ROZRUN_SERIES_MAX)
        w->series[w->n_series++] = t[2];
}

void rozrun_json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)(s != NULL ? s : ""); *p != '\0'; p++) {
        if (*p == '"' || *p == '\\')
            fprintf(f, "\\%c", *p);
        else if (*p < 0x20)
            fprintf(f, "\\u%04x", *p);
        else
            fputc(*p, f);
    }
    fputc('"', f);
}

void rozrun_json_num(FILE *f, double x)
{
    if (isfinite(x))
        fprintf(f, "%.17g", x);
    else
        fputs("null", f);
}

void rozrun_json_key(FILE *f, int *first, const char *key)
{
    fputs(*first ? "\n  " : ",\n  ", f);
    *first = 0;
    rozrun_json_str(f, key);
    fputs(": ", f);
}

void rozrun_watch_json(FILE *f, int *first, const rozrun_watch_t *w, const roz_manifest_t *m,
                       uint32_t rate_hz)
{
    rozrun_json_key(f, first, "wire_violations");
    fprintf(f, "%llu", (unsigned long long)w->wire_violations);
    rozrun_json_key(f, first, "joint_speed_max");
    if (w->speed_state < 0) {
        fputs("null", f);
    } else {
        const char *name = m->states[w->speed_state].name;
        fputs("{\"value\": ", f);
        rozrun_json_num(f, w->speed_max);
        fputs(", \"joint\": ", f);
        fprintf(f, "\"%.*s\"", (int)(strlen(name) - strlen("/velocity")), name);
        fputs(", \"time_s\": ", f);
        rozrun_json_num(f, (double)w->speed_tick / rate_hz);
        fputc('}', f);
    }
    rozrun_json_key(f, first, "truth");
    if (!w->truth) {
        fputs("null", f);
        return;
    }
    double dx = w->x_final - w->x0, dy = w->y_final - w->y0;
    fputs("{\"base_height_start\": ", f);
    rozrun_json_num(f, w->z_start);
    fputs(", \"base_height_min\": ", f);
    rozrun_json_num(f, w->z_min);
    fputs(", \"base_height_min_time_s\": ", f);
    rozrun_json_num(f, (double)w->z_min_tick / rate_hz);
    fputs(", \"base_height_final\": ", f);
    rozrun_json_num(f, w->z_final);
    fputs(", \"tilt_max_deg\": ", f);
    rozrun_json_num(f, w->tilt_max * 57.29577951308232);
    fputs(", \"base_drift_m\": ", f);
    rozrun_json_num(f, sqrt(dx * dx + dy * dy));
    fputs(",\n    \"base_height_series\": {\"every_s\": ", f);
    rozrun_json_num(f, (double)w->every / rate_hz);
    fputs(", \"values\": [", f);
    for (uint32_t i = 0; i < w->n_series; i++) {
        if (i > 0)
            fputs(", ", f);
        fprintf(f, "%.6g", w->series[i]);
    }
    fputs("]}}", f);
}
