/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port/socketcan.h
 * @brief The port `socketcan`: quasi-direct-drive actuators speaking "MIT
 *        mode" (roz/port/mit_codec.h) on a Linux SocketCAN bus, one actuator per
 *        joint of the manifest's `[hardware]` table (roz/port/can_config.h).
 *
 * docs/ports/socketcan.md describes the port: its threads, which replies it
 * takes, what the wire cannot tell and what the port does instead (replays,
 * a stuck, silent or rebooted actuator), the three start-up layers, error
 * codes, the command watchdog and shutdown. Only socketcan_adapt.c sees
 * Linux's CAN headers.
 *
 * Context: open, activate, deactivate, close, set_log from the
 * application's thread; read, write, fault from the tick; counters, info,
 * link and send_round from any thread.
 */
#ifndef ROZ_PORT_SOCKETCAN_H
#define ROZ_PORT_SOCKETCAN_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/atomic.h"
#include "roz/buffer.h"
#include "roz/port/can_config.h"
#include "roz/port/can_hold.h"
#include "roz/hal/cmd_watchdog.h"
#include "roz/hal/link.h"
#include "roz/log.h"
#include "roz/manifest.h"
#include "roz/monitor.h"
#include "roz/port.h"
#include "roz/private.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Values in the state image the receive thread publishes: the states,
 *  then per joint its session, error code and consistency faults. */
#define ROZ_SOCKETCAN_IMAGE ((ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1) + 3 * ROZ_CAN_MAX_JOINTS)
/** Send times a writer keeps per joint: when a reply comes, the frame
 *  after the one it answered is the oldest unanswered, and its time is
 *  among these (the writer looks every round). */
#define ROZ_SOCKETCAN_SENT_RING 8
/** Bytes of a precomputed fault text per joint. */
#define ROZ_SOCKETCAN_TEXT 96

/** The port's counters (roz_socketcan_counters()). */
typedef struct roz_socketcan_counters {
    uint64_t frames_received; /**< frames read from the socket */
    uint64_t replies;         /**< replies accepted */
    uint64_t unknown;         /**< frames of no actuator of ours: other ids, RTR, 29-bit */
    uint64_t short_frames;    /**< an actuator's id, shorter than its reply layout */
    uint64_t bus_errors;      /**< error frames (CRC errors among them) */
    uint64_t bus_off;         /**< error frames saying the controller went bus-off */
    uint64_t error_replies;   /**< replies with an error code */
    uint64_t inconsistent;    /**< replies whose position did not follow their velocity */
    uint64_t lost;            /**< actuators judged silent (each time) */
    uint64_t rounds;          /**< writer rounds */
    uint64_t frames_sent;     /**< frames the writer and shutdown sent */
    uint64_t send_errors;     /**< frames the socket refused (bus busy, down) */
    uint64_t enter_sent;      /**< "enter motor mode" frames */
    uint64_t holds_sent;      /**< hold frames (zero gains at the measured position) */
    uint64_t commands_sent;   /**< frames from the tick's commands */
    uint64_t exit_sent;       /**< "exit motor mode" frames (the port sends none: its exit is the hold) */
    uint64_t saturated;       /**< command fields outside the actuator's range */
    uint64_t writes;          /**< write() calls */
    uint64_t writer_missed;   /**< periods the writer fell a whole period behind */
    uint64_t rx_errors;       /**< socket read errors of the receive thread */
    uint64_t wakes;           /**< rounds asked for with a period of 0 (write, send_round) */
    uint64_t wakes_served;    /**< of those, asked before a round that has been sent */
    uint64_t watchdog_holds;  /**< holds the command watchdog sent in place of a command */
    uint64_t command_timeouts;/**< command watchdog trips: the tick went silent */
} roz_socketcan_counters_t;

/** What the port knows about the bus (roz_socketcan_info()). */
typedef struct roz_socketcan_info {
    const char *network_interface; /**< "" with an injected descriptor */
    uint32_t    bitrate;
    uint32_t    round_us;          /**< a round: the writer's period, or the control period */
    uint32_t    groups;            /**< round-robin groups */
    uint32_t    joint_interval_us; /**< each joint is commanded this often */
    uint32_t    reply_timeout_us;
    uint32_t    command_timeout_us;/**< the command watchdog */
    double      bus_load;          /**< worst case, the busiest round's share of the bus */
    uint16_t    n_joints;
} roz_socketcan_info_t;

/** One joint's atomics, shared by the threads (see socketcan.c). */
typedef struct roz_socketcan_shared {
    ROZ_ATOMIC(uint32_t) sent;      /**< writer: frames sent to it, counted before each send */
    ROZ_ATOMIC(uint32_t) replies;   /**< receive: replies accepted */
    ROZ_ATOMIC(uint32_t) answered;  /**< receive: `sent` as the last accepted reply found it */
    ROZ_ATOMIC(uint32_t) lost;      /**< writer: replies + 1 when it judged it silent */
    ROZ_ATOMIC(uint32_t) session;   /**< receive: 1 at the first reply, +1 at each return */
    ROZ_ATOMIC(uint32_t) hold_code; /**< receive: the last reply's position code */
} roz_socketcan_shared_t;

/** The receive thread's view of one joint. */
typedef struct roz_socketcan_rx_joint {
    roz_link_t link;          /* sequence: frames sent to it when a reply came */
    uint16_t   last_pcode;    /* consistency: the last reply */
    double     last_p, last_v;
    uint32_t   last_seq;
    uint64_t   last_t;        /* when it came, host clock */
    double     frozen_travel; /* what the velocity says it moved at one position code */
    uint32_t   inconsistent;  /* consistency faults seen */
    uint8_t    error;         /* the last reply's error code */
    int        have;          /* a reply since its session began */
} roz_socketcan_rx_joint_t;

/** The writer's view of one joint. */
typedef struct roz_socketcan_tx_joint {
    uint32_t session_seen;   /* the session its phase belongs to */
    int      enter_pending;  /* a returned actuator: "enter motor mode" once */
    uint64_t ready_seq;      /* command sequence when it became ready */
    uint64_t hold_seq;       /* the command sent as the hold (layer 3); 0 = none yet */
    uint64_t sent_ns[ROZ_SOCKETCAN_SENT_RING]; /* loss: when frame k went out, at k mod ring */
    uint32_t answered_seen;  /* loss: `answered` when it last looked */
    uint64_t oldest_ns;      /* loss: when the oldest unanswered frame went out; 0 = none */
    roz_can_last_t last;     /* the last command frame: what the watchdog's hold keeps */
} roz_socketcan_tx_joint_t;

/** The port's data; caller-owned (static storage: it is large). Its fields
 *  are private (roz/private.h): use the functions below. */
typedef struct roz_socketcan {
    roz_can_config_t          ROZ_PRIVATE(cfg);
    const roz_manifest_t     *ROZ_PRIVATE(m);
    int                       ROZ_PRIVATE(given_fd);  /* from roz_socketcan_set_fd(); -1 = open the interface */
    int                       ROZ_PRIVATE(fd);
    int                       ROZ_PRIVATE(own_fd);
    roz_log_fn                ROZ_PRIVATE(log);
    void                     *ROZ_PRIVATE(log_ctx);
    int                       ROZ_PRIVATE(opened), ROZ_PRIVATE(active);
    roz_socketcan_shared_t    ROZ_PRIVATE(shared)[ROZ_CAN_MAX_JOINTS];
    roz_mit_codes_t           ROZ_PRIVATE(zero_codes)[ROZ_CAN_MAX_JOINTS]; /* v, kp, kd, t codes of 0 */
    char                      ROZ_PRIVATE(stale_text)[ROZ_CAN_MAX_JOINTS][ROZ_SOCKETCAN_TEXT];
    char                      ROZ_PRIVATE(jump_text)[ROZ_CAN_MAX_JOINTS][ROZ_SOCKETCAN_TEXT];

    /* receive thread */
    roz_socketcan_rx_joint_t  ROZ_PRIVATE(rx)[ROZ_CAN_MAX_JOINTS];
    double                    ROZ_PRIVATE(rx_image)[ROZ_SOCKETCAN_IMAGE];
    roz_buffer_t              ROZ_PRIVATE(state_buf);
    double                    ROZ_PRIVATE(state_slots)[3 * ROZ_SOCKETCAN_IMAGE];
    roz_link_t                ROZ_PRIVATE(link_total);  /* the sums of the joints' links, published */

    /* writer thread */
    roz_socketcan_tx_joint_t  ROZ_PRIVATE(tx)[ROZ_CAN_MAX_JOINTS];
    roz_buffer_t              ROZ_PRIVATE(cmd_buf);  /* the commands, then the watchdog's epoch and hold */
    double                    ROZ_PRIVATE(cmd_slots)[3 * (ROZ_CFG_MAX_COMMANDS + 2)];
    double                    ROZ_PRIVATE(tx_cmd)[ROZ_CFG_MAX_COMMANDS];
    uint64_t                  ROZ_PRIVATE(tx_cmd_seq);
    uint32_t                  ROZ_PRIVATE(tx_epoch);     /* the watchdog: the frame's epoch, */
    int                       ROZ_PRIVATE(tx_hold);      /* whether it is a hold, */
    uint64_t                  ROZ_PRIVATE(tx_stamp);     /* when the tick wrote it, */
    uint32_t                  ROZ_PRIVATE(hold_rounds);  /* rounds that sent it (a group each) */
    uint64_t                  ROZ_PRIVATE(last_round_ns);
    roz_cmd_watchdog_t        ROZ_PRIVATE(watchdog);
    uint32_t                  ROZ_PRIVATE(round);
    roz_monitor_t             ROZ_PRIVATE(monitor);

    /* the tick */
    uint32_t                  ROZ_PRIVATE(tick_session)[ROZ_CAN_MAX_JOINTS];
    uint32_t                  ROZ_PRIVATE(tick_inconsistent)[ROZ_CAN_MAX_JOINTS];
    int                       ROZ_PRIVATE(fault_joint);  /* fault(): the joint, -1 none */
    int                       ROZ_PRIVATE(fault_kind);   /* 1 error code, 2 consistency, 3 silent,
                                               4 command timeout */
    uint32_t                  ROZ_PRIVATE(fault_code);

    /* threads, counters */
    ROZ_ATOMIC(int)           ROZ_PRIVATE(stop_rx);
    ROZ_ATOMIC(int)           ROZ_PRIVATE(stop_tx);
    ROZ_ATOMIC(uint64_t)      ROZ_PRIVATE(n)[sizeof(roz_socketcan_counters_t) / sizeof(uint64_t)];
    ROZ_ATOMIC(uint64_t)      ROZ_PRIVATE(link_n)[6]; /* accepted, crc, replays, restarts, returns, missing */
    unsigned long             ROZ_PRIVATE(rx_thread), ROZ_PRIVATE(tx_thread); /* pthread_t, kept opaque */
    int                       ROZ_PRIVATE(rx_started), ROZ_PRIVATE(tx_started);
    struct { long double align; unsigned char bytes[64]; } ROZ_PRIVATE(wake); /* sem_t, kept opaque */
    int                       ROZ_PRIVATE(wake_ready);
} roz_socketcan_t;

/** The ops table. Parameters: robot.toml's [hardware.params] with the
 *  caller's over them (roz/port/can_config.h). */
extern const roz_port_ops_t roz_socketcan_ops;

/* The library half of the constructor below: the caller's layout and
 * instance size, refused when they are not the library's. */
roz_port_t roz__socketcan_port(roz_socketcan_t *sc, const roz_port_layout_t *caller,
                               size_t bytes, roz_log_fn log, void *log_ctx);

/** @brief A roz_port_t over @p sc, not yet open. @p log: where the
 *  writer's jitter warnings go (roz/monitor.h); NULL: none.
 *  Context: start-up. */
static inline roz_port_t roz_socketcan_port(roz_socketcan_t *sc, roz_log_fn log, void *log_ctx)
{
    /* the instance as this translation unit lays it out (roz/port.h) */
    const roz_port_layout_t caller = ROZ_PORT_LAYOUT_INIT;
    return roz__socketcan_port(sc, &caller, sizeof *sc, log, log_ctx);
}

/** @brief A socket to use instead of opening `network_interface` (a
 *  CAN_RAW socket the caller bound, or a socketpair end for tests; the
 *  port does not close it), or -1 (the default) to open the interface.
 *  Call after roz_socketcan_port(), before roz_port_open().
 *  Context: start-up. */
void roz_socketcan_set_fd(roz_socketcan_t *sc, int fd);

/** @brief A copy of the counters. Context: any thread; wait-free; each
 *  counter exact, not a snapshot of all at one instant. */
void roz_socketcan_counters(const roz_socketcan_t *sc, roz_socketcan_counters_t *out);

/** @brief The replies' link checks, summed over the actuators (the
 *  sequence is the frames sent to each; crc_errors the bus's CRC errors).
 *  Context: any thread; wait-free. */
void roz_socketcan_link(const roz_socketcan_t *sc, roz_link_t *out);

/** @brief The bus figures of the open port. Context: any thread after open. */
void roz_socketcan_info(const roz_socketcan_t *sc, roz_socketcan_info_t *out);

/** @brief With command_writer_period_us = 0: send a round now (each joint
 *  of the next group gets its frame: its command, its hold, or "enter motor
 *  mode"); write() does this itself. Ignored in periodic mode.
 *  Context: any thread; wait-free (a semaphore post). */
void roz_socketcan_send_round(roz_socketcan_t *sc);

/** @brief The writer's monitor (jitter, pass time). Context: any thread. */
const roz_monitor_t *roz_socketcan_monitor(const roz_socketcan_t *sc);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_SOCKETCAN_H */
