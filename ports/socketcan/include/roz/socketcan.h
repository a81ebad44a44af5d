/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/socketcan.h
 * @brief The port `socketcan`: quasi-direct-drive actuators speaking "MIT
 *        mode" (roz/mit_codec.h) on a Linux SocketCAN bus, one actuator per
 *        joint of the manifest's `[hardware]` table (roz/can_config.h).
 *
 * Threads. A receive thread reads every frame of a CAN_RAW socket bound to
 * `network_interface`; a command writer thread sends, every
 * `command_writer_period_us`, one frame to each joint of this round's
 * round-robin group (every joint each round when the bus has room), or,
 * with a period of 0, one round each time the tick writes (and on
 * roz_socketcan_send_round()). They meet the tick through latest-value
 * buffers (roz/buffer.h) and atomics only; nothing blocks the tick, nothing
 * in the tick allocates or formats text.
 *
 * Replies. A reply is a standard data frame, not RTR, from the actuator's
 * own CAN id or from `master_id`, whose first byte is the low byte of the
 * actuator's id and which is as long as its reply layout; each is unpacked
 * with that actuator's ranges and turned into the joint's position,
 * velocity and effort (direction, zero_offset). Every other frame is
 * counted and dropped: frames of other ids (roz_socketcan_counters_t
 * `unknown`), too short (`short_frames`), RTR or 29-bit frames (`unknown`),
 * error frames (`bus_errors`, and the CRC errors the controller reports in
 * the link's `crc_errors`).
 *
 * What the wire cannot tell, and what the port does instead. MIT-mode
 * frames carry no CRC of their own and no sequence number. The bus
 * checksums every frame in hardware: a frame damaged in transit never
 * reaches software, the controller reports an error frame (counted as a
 * CRC error) and the sender retransmits it. In place of a sequence the
 * port uses what the protocol promises, that a reply follows each command:
 * a reply is taken only while a frame to its actuator is unanswered (the
 * number of frames sent to it is the reply's "sequence", roz/hal/link.h);
 * one more is a replay, dropped and counted (a frame the bus delivered
 * twice, a stuck gateway). A reply that the receive thread reads only after
 * the next frame to its actuator went out answers that frame, and the
 * reply to it is then counted as a replay: under load the values can lag a
 * round, never go back further. A frozen actuator that still answers at
 * rest with its last values cannot be told from a resting one; the port
 * checks that position follows velocity (`consistency_margin`): a position
 * that stays put while the velocity says it moves, or that jumps further
 * than the velocity explains (the time between the replies counted in
 * command intervals; as much travel allowed for timing as the faster
 * velocity covers in one interval, or in the time by which the host's clock
 * disagrees with that count, if longer: a late thread is not a jump), is
 * a fault of that actuator (read() returns ROZ_EROBOT once per detection;
 * fault() names the joint). An actuator that reboots answers again out of
 * motor mode: the port sees that only as a silence (below), so a reboot
 * faster than `reply_timeout_us` goes unseen until its position jumps.
 *
 * Silence. An actuator whose oldest unanswered frame is older than
 * `reply_timeout_us` is lost: read() returns 0 (nothing fresh) while any
 * is, the runtime latches STALE after stale_ticks, and fault() names the
 * joint and its CAN id. When a lost actuator answers again, read()
 * returns ROZ_ELINK once (the runtime latches LINK) and its start-up
 * begins again.
 *
 * Safe start-up, three layers. (1) The writer sends each actuator "enter
 * motor mode" until it replies (which also asks for its state); nothing
 * else goes to it before. (2) Until every actuator has replied once, every
 * one that has gets a hold: its measured position (at the joint's position
 * limit if measured past it), velocity 0, kp 0, kd 0,
 * torque 0 (read() returns ROZ_ENOENT meanwhile: there is no whole state).
 * (3) The first command the tick writes after that goes out as the hold
 * too; the next as written. A lost actuator that answers again gets "enter
 * motor mode" once, then the hold, and the first command written after it
 * as the hold.
 *
 * Errors. With the `temperature_error` layout, a reply whose error byte is
 * not 0 makes read() return ROZ_EROBOT for every fresh frame while any
 * actuator reports one (a level); fault() names the joint, "actuator error
 * code" and the code (the runtime latches ROBOT).
 *
 * Commands. Per joint, the commands `position`, `velocity`, `stiffness`,
 * `damping`, `effort` become the actuator's p, v, kp, kd, t (p =
 * direction * (position - zero_offset), v and t times direction); a joint
 * without a position command sends its measured position, without the
 * others 0. Values outside the actuator's ranges are saturated and counted
 * (`saturated`; the configuration check and the safety filter keep it at 0).
 *
 * Command watchdog (roz/hal/cmd_watchdog.h). When the latest command the
 * tick wrote is older than `command_timeout_us` (the tick stopped: a killed
 * or stuck control loop), the writer sends every actuator the zero-gain
 * hold at its measured position in place of that command, every round (with
 * a period of 0, a round every control period, on its own); read() returns
 * ROZ_EWATCHDOG once (the runtime latches COMMAND_TIMEOUT naming how long
 * the tick was silent), and the tick's writes go out as the hold until
 * every round-robin group got one; a command written before the trip is
 * never sent.
 *
 * Shutdown. deactivate() stops the writer, then sends every actuator that
 * answered a zero-gain hold and "exit motor mode", then stops the receive
 * thread. The port never sends "set zero".
 *
 * The socket layer is the only part that sees Linux's CAN headers
 * (socketcan_adapt.c). For tests the port takes a file descriptor instead
 * of opening the interface: one end of a socketpair(AF_UNIX,
 * SOCK_SEQPACKET) carrying `struct can_frame` records reads and writes as
 * a CAN_RAW socket does.
 *
 * Context: open, activate, deactivate, close, set_log from the
 * application's thread; read, write, fault from the tick; counters, info,
 * link and send_round from any thread.
 */
#ifndef ROZ_SOCKETCAN_H
#define ROZ_SOCKETCAN_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/atomic.h"
#include "roz/buffer.h"
#include "roz/can_config.h"
#include "roz/hal/cmd_watchdog.h"
#include "roz/hal/link.h"
#include "roz/log.h"
#include "roz/manifest.h"
#include "roz/monitor.h"
#include "roz/port.h"

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
    uint64_t exit_sent;       /**< "exit motor mode" frames */
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
} roz_socketcan_tx_joint_t;

/** The port's data; caller-owned (static storage: it is large). Fields are
 *  private to the port: use the functions below. */
typedef struct roz_socketcan {
    roz_can_config_t          cfg;
    const roz_manifest_t     *m;
    int                       given_fd;  /* from roz_socketcan_set_fd(); -1 = open the interface */
    int                       fd;
    int                       own_fd;
    roz_log_fn                log;
    void                     *log_ctx;
    int                       opened, active;
    roz_socketcan_shared_t    shared[ROZ_CAN_MAX_JOINTS];
    roz_mit_codes_t           zero_codes[ROZ_CAN_MAX_JOINTS]; /* v, kp, kd, t codes of 0 */
    char                      stale_text[ROZ_CAN_MAX_JOINTS][ROZ_SOCKETCAN_TEXT];
    char                      jump_text[ROZ_CAN_MAX_JOINTS][ROZ_SOCKETCAN_TEXT];

    /* receive thread */
    roz_socketcan_rx_joint_t  rx[ROZ_CAN_MAX_JOINTS];
    double                    rx_image[ROZ_SOCKETCAN_IMAGE];
    roz_buffer_t              state_buf;
    double                    state_slots[3 * ROZ_SOCKETCAN_IMAGE];
    roz_link_t                link_total;  /* the sums of the joints' links, published */

    /* writer thread */
    roz_socketcan_tx_joint_t  tx[ROZ_CAN_MAX_JOINTS];
    roz_buffer_t              cmd_buf;  /* the commands, then the watchdog's epoch and hold */
    double                    cmd_slots[3 * (ROZ_CFG_MAX_COMMANDS + 2)];
    double                    tx_cmd[ROZ_CFG_MAX_COMMANDS];
    uint64_t                  tx_cmd_seq;
    uint32_t                  tx_epoch;     /* the watchdog: the frame's epoch, */
    int                       tx_hold;      /* whether it is a hold, */
    uint64_t                  tx_stamp;     /* when the tick wrote it, */
    uint32_t                  hold_rounds;  /* rounds that sent it (a group each) */
    uint64_t                  last_round_ns;
    roz_cmd_watchdog_t        watchdog;
    uint32_t                  round;
    roz_monitor_t             monitor;

    /* the tick */
    uint32_t                  tick_session[ROZ_CAN_MAX_JOINTS];
    uint32_t                  tick_inconsistent[ROZ_CAN_MAX_JOINTS];
    int                       fault_joint;  /* fault(): the joint, -1 none */
    int                       fault_kind;   /* 1 error code, 2 consistency, 3 silent,
                                               4 command timeout */
    uint32_t                  fault_code;

    /* threads, counters */
    ROZ_ATOMIC(int)           stop_rx;
    ROZ_ATOMIC(int)           stop_tx;
    ROZ_ATOMIC(uint64_t)      n[sizeof(roz_socketcan_counters_t) / sizeof(uint64_t)];
    ROZ_ATOMIC(uint64_t)      link_n[6]; /* accepted, crc, replays, restarts, returns, missing */
    unsigned long             rx_thread, tx_thread; /* pthread_t, kept opaque */
    int                       rx_started, tx_started;
    struct { long double align; unsigned char bytes[64]; } wake; /* sem_t, kept opaque */
    int                       wake_ready;
} roz_socketcan_t;

/** The ops table. Parameters: robot.toml's [hardware.params] with the
 *  caller's over them (roz/can_config.h). */
extern const roz_port_ops_t roz_socketcan_ops;

/** @brief A roz_port_t over @p sc, not yet open. @p log: where the
 *  writer's jitter warnings go (roz/monitor.h); NULL: none.
 *  Context: start-up. */
roz_port_t roz_socketcan_port(roz_socketcan_t *sc, roz_log_fn log, void *log_ctx);

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

#endif /* ROZ_SOCKETCAN_H */
