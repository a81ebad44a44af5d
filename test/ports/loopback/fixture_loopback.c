/* SPDX-License-Identifier: Apache-2.0 */
/* The loopback port's conformance fixture: its simulated robot is the peer.
 * The loopback makes a state frame inside each read(), so the fixture sets
 * up one tick's fault injection for the read that follows. */
#include <string.h>

#include "port_fixture.h"
#include "roz/port/loopback.h"

static roz_loopback_t lb;
static roz_port_t the_port;
static const roz_manifest_t *the_m;

static int lb_fx_open(const roz_manifest_t *m, const roz_params_t *params, roz_port_t *port,
                      char *err, size_t errlen)
{
    the_port = roz_loopback_port(&lb, NULL, NULL);
    the_m = m;
    *port = the_port;
    int rc = roz_port_open(port, m, params, err, errlen);
    return rc != ROZ_OK ? rc : roz_port_activate(port);
}

/* A fault over the next read only (spent injections make room). */
static void one_tick(roz_inject_kind_t kind)
{
    uint64_t t = roz_loopback_counters(&lb).tick;
    roz_loopback_fault_t f = { kind, t, t + 1, -1, 0 };
    (void)roz_loopback_inject(&lb, &f);
}

static void spend_reads(uint64_t n)
{
    double scratch[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    for (uint64_t i = 0; i < n; i++)
        (void)roz_port_read(&the_port, scratch, the_m->n_states);
}

static void lb_fx_peer(roz_peer_frame_t what)
{
    switch (what) {
    case ROZ_PEER_SEND:
        break;
    case ROZ_PEER_SILENT:
        one_tick(ROZ_INJECT_FREEZE);
        break;
    case ROZ_PEER_CORRUPT:
        one_tick(ROZ_INJECT_CORRUPT);
        break;
    case ROZ_PEER_REPLAY:
        one_tick(ROZ_INJECT_DUPLICATE);
        break;
    case ROZ_PEER_RESTART:
        /* the robot is down for one tick, which a read of ours spends, then
         * boots: the next read brings its first frame */
        one_tick(ROZ_INJECT_RESTART);
        spend_reads(1);
        break;
    case ROZ_PEER_VANISH: {
        /* silent past the peer timeout, a read of ours a tick */
        uint64_t period_ns = 1000000000u / the_m->control_rate_hz; /* the port's */
        uint64_t n = ROZ_LOOPBACK_PEER_TIMEOUT_NS / period_ns + 1;
        uint64_t t = roz_loopback_counters(&lb).tick;
        roz_loopback_fault_t f = { ROZ_INJECT_FREEZE, t, t + n, -1, 0 };
        (void)roz_loopback_inject(&lb, &f);
        spend_reads(n);
        break;
    }
    }
}

static void lb_fx_settle(void)
{
    /* write() hands the frame to the robot before it returns */
}

static void lb_fx_peer_sent(double *state)
{
    roz_loopback_true_state(&lb, state);
}

static const double *lb_fx_peer_command(void)
{
    return roz_loopback_last_command(&lb);
}

static void lb_fx_corrupt_next_command(void)
{
    /* write() follows the read of this tick */
    uint64_t t = roz_loopback_counters(&lb).tick;
    roz_loopback_fault_t f = { ROZ_INJECT_CORRUPT_CMD, t > 0 ? t - 1 : 0, t, -1, 0 };
    (void)roz_loopback_inject(&lb, &f);
}

static void lb_fx_link(roz_link_t *out)
{
    *out = roz_loopback_link(&lb);
}

static void lb_fx_close(void)
{
    (void)roz_port_deactivate(&the_port);
    roz_port_close(&the_port);
}

const roz_port_fixture_t roz_fixture_loopback = {
    .name = "loopback",
    .open = lb_fx_open,
    .peer = lb_fx_peer,
    .peer_sent = lb_fx_peer_sent,
    .settle = lb_fx_settle,
    .peer_command = lb_fx_peer_command,
    .corrupt_next_command = lb_fx_corrupt_next_command,
    .link = lb_fx_link,
    .close = lb_fx_close,
};
