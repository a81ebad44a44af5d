/* SPDX-License-Identifier: Apache-2.0 */
#include "schedule.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "roz/module.h"
#include "trace.h"

/* The options, by kind. */
static const char *const opt_names[] = {
    "--estop-at", "--estop-release-at", "--stage-at", "--swap-at", "--clear-at",
};

/* The option and value of an action, as the user wrote it. */
/* An action as given ("--swap-at 50:path/to/ctl.wasm"): room for any path. */
#define WHAT_MAX (ROZRUN_PATH_MAX + 64)

static void describe(const rozrun_action_t *a, char *buf, size_t len)
{
    if (a->kind == ROZRUN_SWAP)
        snprintf(buf, len, "%s %llu:%s", opt_names[a->kind], (unsigned long long)a->tick,
                 a->file);
    else if (a->kind == ROZRUN_STAGE)
        snprintf(buf, len, "%s %llu:%s", opt_names[a->kind], (unsigned long long)a->tick,
                 roz_stage_name(a->stage));
    else
        snprintf(buf, len, "%s %llu", opt_names[a->kind], (unsigned long long)a->tick);
}

/* ---- parsing and checking ------------------------------------------------ */

int rozrun_schedule_add(rozrun_schedule_t *s, const char *opt, const char *value)
{
    rozrun_action_t a = { 0, ROZRUN_ESTOP_PRESS, NULL, 0, NULL, 0 };
    const char *p = value;
    int kind = -1;

    for (int k = 0; k < (int)(sizeof opt_names / sizeof opt_names[0]); k++) {
        if (strcmp(opt, opt_names[k]) == 0)
            kind = k;
    }
    if (kind < 0)
        return -1;
    a.kind = (rozrun_action_kind_t)kind;
    if (s->n == ROZRUN_MAX_ACTIONS) {
        fprintf(stderr,
                "rozrun: %s %s: at most %d of --estop-at, --estop-release-at, --stage-at, "
                "--clear-at and --swap-at in all\n", opt, value, ROZRUN_MAX_ACTIONS);
        return -1;
    }
    if (*p < '0' || *p > '9')
        goto bad;
    for (; *p >= '0' && *p <= '9'; p++) {
        uint64_t d = (uint64_t)(*p - '0');
        if (a.tick > (UINT64_MAX / 2 - d) / 10u) {
            fprintf(stderr, "rozrun: %s \"%s\": the tick is too large (at most %llu)\n", opt,
                    value, (unsigned long long)(UINT64_MAX / 2));
            return -1;
        }
        a.tick = a.tick * 10u + d;
    }
    if (a.kind == ROZRUN_SWAP) {
        if (*p != ':' || p[1] == '\0')
            goto bad;
        a.file = p + 1;
    } else if (a.kind == ROZRUN_STAGE) {
        a.stage = *p == ':' ? roz_stage_from_name(p + 1) : -1;
        if (a.stage != ROZ_STAGE_MOVE && a.stage != ROZ_STAGE_RUN && a.stage != ROZ_STAGE_STOP &&
            a.stage != ROZ_STAGE_ZERO)
            goto bad;
    } else if (*p != '\0') {
        goto bad;
    }
    s->a[s->n++] = a;
    return 0;
bad:
    fprintf(stderr, "rozrun: %s \"%s\": expected %s\n", opt, value,
            a.kind == ROZRUN_SWAP    ? "TICK:FILE (a tick number, a colon, a controller)"
            : a.kind == ROZRUN_STAGE ? "TICK:STAGE (a tick number, a colon, one of move, run, "
                                       "stop, zero)"
                                     : "TICK (a tick number, from 0)");
    return -1;
}

/* Order of execution: by tick, then by kind; the order given otherwise. */
static int before(const rozrun_action_t *x, const rozrun_action_t *y)
{
    return x->tick < y->tick || (x->tick == y->tick && x->kind < y->kind);
}

int rozrun_schedule_check(rozrun_schedule_t *s, uint64_t ticks)
{
    static char what[WHAT_MAX], other[WHAT_MAX]; /* start-up, one thread */
    int pressed = 0;
    const rozrun_action_t *press = NULL;

    /* insertion sort: stable, and at most ROZRUN_MAX_ACTIONS entries */
    for (size_t i = 1; i < s->n; i++) {
        rozrun_action_t x = s->a[i];
        size_t j = i;
        for (; j > 0 && before(&x, &s->a[j - 1]); j--)
            s->a[j] = s->a[j - 1];
        s->a[j] = x;
    }
    for (size_t i = 0; i < s->n; i++) {
        const rozrun_action_t *a = &s->a[i];
        describe(a, what, sizeof what);
        if (ticks != 0 && a->tick >= ticks) {
            fprintf(stderr, "rozrun: %s: after the run (--ticks %llu runs ticks 0..%llu)\n",
                    what, (unsigned long long)ticks, (unsigned long long)(ticks - 1u));
            return -1;
        }
        if (a->kind == ROZRUN_SWAP && a->tick == 0) {
            fprintf(stderr, "rozrun: %s: tick 0 runs --controller; a swap needs a tick from 1\n",
                    what);
            return -1;
        }
        if (i > 0 && s->a[i - 1].tick == a->tick && s->a[i - 1].kind == a->kind) {
            describe(&s->a[i - 1], other, sizeof other);
            if (a->kind == ROZRUN_SWAP)
                fprintf(stderr, "rozrun: %s: %s is at the same tick; one swap a tick\n", what,
                        other);
            else
                fprintf(stderr, "rozrun: %s: given twice\n", what);
            return -1;
        }
        if (a->kind == ROZRUN_ESTOP_RELEASE && i > 0 && s->a[i - 1].tick == a->tick &&
            s->a[i - 1].kind == ROZRUN_ESTOP_PRESS) {
            fprintf(stderr,
                    "rozrun: %s: --estop-at %llu is at the same tick; a release needs a later "
                    "tick than its press\n", what, (unsigned long long)a->tick);
            return -1;
        }
        if (a->kind == ROZRUN_ESTOP_PRESS) {
            if (pressed) {
                describe(press, other, sizeof other);
                fprintf(stderr,
                        "rozrun: %s: the e-stop is still pressed then (%s, no release "
                        "between)\n", what, other);
                return -1;
            }
            pressed = 1;
            press = a;
        } else if (a->kind == ROZRUN_ESTOP_RELEASE) {
            if (!pressed) {
                fprintf(stderr,
                        "rozrun: %s: the e-stop is not pressed then (no --estop-at before "
                        "it since the last release)\n", what);
                return -1;
            }
            pressed = 0;
        }
    }
    return 0;
}

int rozrun_schedule_read_modules(rozrun_schedule_t *s)
{
    static char err[WHAT_MAX], what[WHAT_MAX]; /* start-up, one thread */

    for (size_t i = 0; i < s->n; i++) {
        rozrun_action_t *a = &s->a[i];
        if (a->kind != ROZRUN_SWAP)
            continue;
        /* start-up, not the tick: rozrun allocates here */
        a->wasm = malloc(ROZ_CFG_WASM_MAX_MODULE_BYTES);
        if (a->wasm == NULL) {
            describe(a, what, sizeof what);
            fprintf(stderr, "rozrun: %s: out of memory\n", what);
            return -1;
        }
        if (roz_module_read_file(a->file, a->wasm, ROZ_CFG_WASM_MAX_MODULE_BYTES, &a->len, err,
                                 sizeof err) != ROZ_OK) {
            describe(a, what, sizeof what);
            fprintf(stderr, "rozrun: %s: %s\n", what, err);
            return -1;
        }
        uint8_t *fit = realloc(a->wasm, a->len > 0 ? a->len : 1u);
        if (fit != NULL)
            a->wasm = fit;
    }
    return 0;
}

void rozrun_schedule_free(rozrun_schedule_t *s)
{
    for (size_t i = 0; i < s->n; i++) {
        free(s->a[i].wasm);
        s->a[i].wasm = NULL;
    }
}

/* ---- carrying out ---------------------------------------------------------- */

unsigned rozrun_schedule_inputs(rozrun_schedule_t *s, roz_runtime_t *rt, uint64_t tick)
{
    unsigned ev = 0;

    for (size_t i = s->next_input; i < s->n && s->a[i].tick <= tick; i++) {
        const rozrun_action_t *a = &s->a[i];
        if (a->tick < tick || a->kind > ROZRUN_STAGE)
            continue; /* past ones were done; the loader's are not ours */
        if (a->kind == ROZRUN_STAGE) {
            /* dropped by the tick when the stage it finds does not allow
             * it: counted in the runtime's stage counters */
            (void)roz_runtime_stage_request(rt, (roz_stage_t)a->stage);
            s->in.stages++;
            continue;
        }
        roz_runtime_estop_set(rt, a->kind == ROZRUN_ESTOP_PRESS);
        if (a->kind == ROZRUN_ESTOP_PRESS) {
            s->in.presses++;
            ev |= ROZRUN_EV_ESTOP;
        } else {
            s->in.releases++;
            ev |= ROZRUN_EV_ESTOP_RELEASE;
        }
    }
    while (s->next_input < s->n && s->a[s->next_input].tick <= tick)
        s->next_input++;
    return ev;
}

static size_t next_loader(const rozrun_schedule_t *s, size_t from)
{
    while (from < s->n && s->a[from].kind < ROZRUN_SWAP)
        from++;
    return from;
}

int rozrun_schedule_loader_due(const rozrun_schedule_t *s, uint64_t done)
{
    size_t i = next_loader(s, s->next_loader);
    return i < s->n && s->a[i].tick <= done;
}

/* The fault names in @p bits, joined with ", ". */
static void fault_list(unsigned bits, char *buf, size_t len)
{
    size_t at = 0;

    buf[0] = '\0';
    for (unsigned b = 0; b < ROZ_FAULT_KIND_COUNT && at < len; b++) {
        if (bits & (1u << b)) {
            int n = snprintf(buf + at, len - at, "%s%s", at ? ", " : "", roz_fault_name(1u << b));
            at += n > 0 ? (size_t)n : 0u;
        }
    }
}

static unsigned do_swap(rozrun_schedule_t *s, roz_runtime_t *rt, const rozrun_action_t *a)
{
    roz_verify_report_t rep;
    int rc = roz_runtime_load(rt, a->wasm, a->len, &rep);

    if (rc == ROZ_OK) {
        s->ld.swaps++;
        char from[48] = "the next tick boundary";
        if (s->simulated)
            snprintf(from, sizeof from, "tick %llu", (unsigned long long)a->tick);
        fprintf(stderr,
                "rozrun: tick %llu: swap: %s verified (%u ticks, at most %llu fuel units a "
                "tick); it drives from %s\n",
                (unsigned long long)a->tick, a->file, (unsigned)rep.ticks_run,
                (unsigned long long)rep.max_fuel, from);
        return ROZRUN_EV_SWAP;
    }
    s->ld.swaps_refused++;
    fprintf(stderr, "rozrun: tick %llu: swap: %s refused, the running controller stays: %s\n",
            (unsigned long long)a->tick, a->file, roz_runtime_error(rt));
    return rc == ROZ_EVERIFY ? ROZRUN_EV_VERIFY_REFUSED : ROZRUN_EV_LOAD_REFUSED;
}

/* Instances the runtime rebuilt so far (a loader's counter, current in
 * the stats on the loader's thread). */
static uint64_t rebuilds(const roz_runtime_t *rt)
{
    roz_runtime_stats_t st;
    return roz_runtime_stats(rt, &st) == ROZ_OK ? st.runtime.rebuilds : 0;
}

static unsigned do_clear(rozrun_schedule_t *s, roz_runtime_t *rt, const rozrun_action_t *a)
{
    char seen[128];
    unsigned faults = roz_runtime_faults(rt);
    uint64_t rebuilt = rebuilds(rt);
    int rc = roz_runtime_clear_faults(rt);
    unsigned ev = 0;

    s->ld.clears++;
    fault_list(faults, seen, sizeof seen);
    if (rebuilds(rt) != rebuilt) {
        s->ld.rebuilds++;
        ev |= ROZRUN_EV_REBUILD;
    }
    if (rc == ROZ_OK && faults == 0) {
        fprintf(stderr, "rozrun: tick %llu: clear: nothing was latched\n",
                (unsigned long long)a->tick);
        ev |= ROZRUN_EV_CLEAR;
    } else if (rc == ROZ_OK) {
        fprintf(stderr, "rozrun: tick %llu: clear: %s cleared%s\n", (unsigned long long)a->tick, seen,
                ev & ROZRUN_EV_REBUILD
                    ? "; the controller's instance that trapped or ran out of budget is "
                      "rebuilt and verified"
                    : "");
        ev |= ROZRUN_EV_CLEAR;
    } else if (rc == ROZ_ESTATE) {
        /* rozrun is the only loader, so not "another load is running": the
         * e-stop input is pressed, and all the faults seen but e-stop go */
        s->ld.clears_held++;
        fprintf(stderr,
                "rozrun: tick %llu: clear: the e-stop input is still pressed, so e-stop stays "
                "latched (latched: %s)\n", (unsigned long long)a->tick, seen);
        ev |= ROZRUN_EV_CLEAR_PRESSED;
    } else {
        s->ld.clears_refused++;
        fprintf(stderr, "rozrun: tick %llu: clear refused, nothing cleared (latched: %s): %s\n",
                (unsigned long long)a->tick, seen, roz_runtime_error(rt));
        ev |= ROZRUN_EV_CLEAR_REFUSED;
    }
    return ev;
}

unsigned rozrun_schedule_loader(rozrun_schedule_t *s, roz_runtime_t *rt, uint64_t done)
{
    unsigned ev = 0;
    size_t i;

    for (i = next_loader(s, s->next_loader); i < s->n && s->a[i].tick <= done;
         i = next_loader(s, i + 1)) {
        const rozrun_action_t *a = &s->a[i];
        ev |= a->kind == ROZRUN_SWAP ? do_swap(s, rt, a) : do_clear(s, rt, a);
    }
    s->next_loader = i;
    return ev;
}

size_t rozrun_schedule_left(const rozrun_schedule_t *s)
{
    size_t left = 0;

    for (size_t i = s->next_input; i < s->n; i++)
        left += s->a[i].kind <= ROZRUN_STAGE;
    for (size_t i = next_loader(s, s->next_loader); i < s->n; i = next_loader(s, i + 1))
        left++;
    return left;
}

void rozrun_schedule_summary(const rozrun_schedule_t *s, char *buf, size_t len)
{
    const rozrun_schedule_counts_t *in = &s->in, *ld = &s->ld;

    if (s->n == 0) {
        buf[0] = '\0';
        return;
    }
    snprintf(buf, len,
             "e-stop %llu pressed, %llu released; clears %llu (%llu while pressed, %llu "
             "refused); swaps %llu, %llu refused; rebuilds %llu",
             (unsigned long long)in->presses, (unsigned long long)in->releases,
             (unsigned long long)ld->clears, (unsigned long long)ld->clears_held,
             (unsigned long long)ld->clears_refused, (unsigned long long)ld->swaps,
             (unsigned long long)ld->swaps_refused, (unsigned long long)ld->rebuilds);
    for (size_t i = 0; i < s->n; i++) {
        if (s->a[i].kind == ROZRUN_STAGE) { /* --stage-at given: say what it asked */
            size_t at = strlen(buf);
            snprintf(buf + at, len - at, "; stage requests %llu", (unsigned long long)in->stages);
            break;
        }
    }
}
