/* SPDX-License-Identifier: Apache-2.0 */
/* What the port conformance suite (test_port_conformance.c) needs from a
 * port's test fixture: the port, and a robot peer on the other end that the
 * suite can drive frame by frame. Every port provides one fixture; the
 * suite runs the same checks against each (docs/ports/adding-a-port.md).
 * The loopback's fixture is fixture_loopback.c; a hardware port's fixture
 * wraps its fake robot peer, which speaks the real wire protocol over
 * loopback networking.
 *
 * The suite calls a fixture from one thread. A port with threads of its own
 * (a DDS port) makes each call synchronous: peer() waits until the port's
 * receive thread has judged the frame (one of its link counters moved),
 * settle() until the peer has received every command frame written so far,
 * each with a timeout that fails the test. */
#ifndef ROZ_TEST_PORT_FIXTURE_H
#define ROZ_TEST_PORT_FIXTURE_H

#include <stddef.h>

#include "roz/hal/link.h"
#include "roz/port.h"
#include "roz/manifest.h"

/* The peer's next state frame. */
typedef enum {
    ROZ_PEER_SEND = 0, /* a good frame, newer than the last */
    ROZ_PEER_SILENT,   /* nothing for one frame period */
    ROZ_PEER_CORRUPT,  /* a frame with one bit flipped after its CRC (ROZ_PORT_CAP_CRC) */
    ROZ_PEER_REPLAY,   /* the frame it sent last, again */
    ROZ_PEER_RESTART,  /* the peer restarts (sequence from 0); then its first frame */
    ROZ_PEER_VANISH,   /* silent for longer than the port's peer timeout; then a
                          frame, newer than the last */
} roz_peer_frame_t;

typedef struct roz_port_fixture {
    const char *name;
    /* The manifests the port serves, NULL-terminated; NULL: the suite's
     * own (UR5 and G1). */
    const roz_manifest_t *const *manifests;
    /* What the port keeps and what its wire can express (the start-up hold,
     * a CRC, a sequence that restarts with the peer, a command watchdog) is
     * the port's own: its ops' caps and info (roz/port.h), which the suite
     * reads; a fixture does not restate it. */
    /* A state frame is this many samples on topics of their own, each with
     * its own link checks (0 counts as 1): a replayed, restarted or returning
     * peer counts once per topic. */
    int state_topics;
    /* What the peer applies for a command written as @p in (n_commands
     * values), where the wire narrows them (float32, a field of 12 bits);
     * NULL: exactly that. */
    void (*wire_command)(const double *in, double *out);
    /* Open the port on @p m with @p params against a new peer that has sent
     * nothing yet; the port is activated. ROZ_OK, or the open's error. */
    int (*open)(const roz_manifest_t *m, const roz_params_t *params, roz_port_t *port, char *err,
                size_t errlen);
    /* Make the peer's next state frame and return once the port has taken
     * it in (for SILENT: once a frame period has passed; RESTART and VANISH
     * may spend reads of the port's own), so that the next read() sees it. */
    void (*peer)(roz_peer_frame_t what);
    /* The last state frame the peer sent, as the port should deliver it
     * (n_states values; converted where the wire narrows or reorders them). */
    void (*peer_sent)(double *state);
    /* Return once every command frame written so far has reached the peer
     * (or was lost on the way). */
    void (*settle)(void);
    /* The command the peer applies (n_commands values), NULL before its
     * first good command frame (and after a restart). Call settle() first. */
    const double *(*peer_command)(void);
    /* Flip one bit of the next command frame in transit (ROZ_PORT_CAP_CRC). */
    void (*corrupt_next_command)(void);
    /* A copy of the port's checks on state frames, taken consistently. */
    void (*link)(roz_link_t *out);
    /* Deactivate and close the port, stop the peer. */
    void (*close)(void);
} roz_port_fixture_t;

/* The fixtures this build holds, by port (its roz_add_port() NAME): one row
 * per fixture that test/ports/common/CMakeLists.txt builds, generated there
 * (conformance_fixtures.c); a row with a NULL fixture says why it is not
 * built here. The table ends with a row whose port is NULL. The suite runs
 * every registered port's (roz/ports.h) and fails for a port without a row. */
typedef struct roz_port_fixture_entry {
    const char               *port;
    const roz_port_fixture_t *fixture;
    const char               *unavailable;
} roz_port_fixture_entry_t;

extern const roz_port_fixture_entry_t roz_port_fixtures[];

/* The fixtures the ports' own tests use besides the suite. */
extern const roz_port_fixture_t roz_fixture_unitree_g1;
extern const roz_port_fixture_t roz_fixture_engineai_pm01;
extern const roz_port_fixture_t roz_fixture_agibot_x2;

#endif /* ROZ_TEST_PORT_FIXTURE_H */
