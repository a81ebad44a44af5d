/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/dds.h
 * @brief roz::dds, the Cyclone DDS plumbing every DDS port shares: the
 *        participant and its configuration, QoS profiles, a receive path into
 *        preallocated storage, and the command writer thread.
 *
 * Participant. Built from two parameters: `network_interface` (default
 * `lo`) and `dds_domain`. roz passes Cyclone its configuration as an XML
 * string when it creates the domain (roz_dds_config_xml()):
 * - on `lo`: that interface only, multicast off, 127.0.0.1 as the discovery
 *   peer, participant indices assigned automatically up to
 *   ROZ_DDS_MAX_PARTICIPANT_INDEX (Cyclone's default allows 10 participants
 *   per host and domain; with multicast off and no peer, discovery fails, and
 *   Cyclone's defaults would multicast out of other interfaces);
 * - on any other interface: that interface only, Cyclone's defaults
 *   otherwise (multicast discovery, as the robots' own DDS stacks use).
 * A user's own CYCLONEDDS_URI wins when it is set: roz then leaves the
 * configuration to Cyclone and says so through the log callback.
 *
 * Receive path. A reader calls the port's function for each valid sample,
 * on Cyclone's receive thread, with the sample taken (dds_take) into storage
 * the port preallocated at open and zeroed before every take: no heap in
 * roz's code. A type with sequences or strings (a ROS 2 message) keeps its
 * storage between takes instead (roz_dds_reader_open_kept()): the port sizes
 * its sequences and strings once at open (roz_dds_seq_reserve(),
 * roz_dds_string_reserve()) and Cyclone's deserializer fills them in place;
 * it allocates only for a sample longer than they are (on its own thread).
 *
 * Command writer. A thread of its own publishes the port's latest command:
 * periodically (every `command_writer_period_us`, absolute deadlines, jitter
 * monitored against the period), or, with a period of 0, as soon as the
 * tick hands it a frame (roz_dds_writer_wake(): an atomic add, and a
 * semaphore post if the writer sleeps; it never blocks). The port fills
 * each sample in the writer thread (roz_dds_fill_fn) from the sample
 * storage roz zeroes before every fill. An event-driven writer may also
 * spin for the tick's command (`command_writer_spin_us`): the receive path
 * wakes it when a state frame arrives (roz_dds_writer_expect()), so the
 * thread wake-up happens while the tick runs instead of after it, and the
 * command goes out about as soon as the tick writes it.
 *
 * Command watchdog. Every DDS port runs roz/hal/cmd_watchdog.h between its
 * tick and its writer (`command_timeout_us`, read here with the other
 * common parameters): its fill judges each frame and fills the port's safe
 * command when the tick has gone silent. A periodic writer looks every
 * period anyway; an event-driven one, given the watchdog
 * (roz_dds_writer_watch()), also wakes on its own when the last frame it
 * sent expires, and then repeats the safe command every repeat period
 * until the tick writes again.
 *
 * Threads: a reader's function runs on a Cyclone thread, the fill function
 * on the writer thread; they hand frames to the tick through roz/buffer.h
 * and atomics, never a lock the tick could wait on.
 *
 * Only the .c files of this library include Cyclone's headers: entities are
 * kept as int32_t (dds_entity_t), topic descriptors as opaque pointers.
 */
#ifndef ROZ_DDS_H
#define ROZ_DDS_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/atomic.h"
#include "roz/hal/cmd_watchdog.h"
#include "roz/log.h"
#include "roz/monitor.h"
#include "roz/port.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Longest interface name (Linux IFNAMSIZ less the NUL). */
#define ROZ_DDS_IFNAME_MAX 15
/** Largest domain id (Cyclone's port mapping allows 0..232). */
#define ROZ_DDS_MAX_DOMAIN 232u
/** Highest participant index on `lo`: 64 participants per host and domain. */
#define ROZ_DDS_MAX_PARTICIPANT_INDEX 63
/** Room for the configuration XML. */
#define ROZ_DDS_CONFIG_MAX 640
/** Samples one data-available call takes at most before it yields. */
#define ROZ_DDS_TAKE_MAX 64u
/** Shortest writer period, microseconds (0 = event-driven). */
#define ROZ_DDS_MIN_PERIOD_US 100u
/** Longest spin of an event-driven writer for the tick's command (us). */
#define ROZ_DDS_MAX_SPIN_US 10000u
/** Longest writer period, microseconds. */
#define ROZ_DDS_MAX_PERIOD_US 1000000u

/* ---- parameters ------------------------------------------------------------ */

/** The parameters every DDS port understands (roz/hal/params.h). */
typedef struct roz_dds_params {
    char     network_interface[ROZ_DDS_IFNAME_MAX + 1]; /**< "lo" */
    uint32_t domain;                   /**< dds_domain, 0..ROZ_DDS_MAX_DOMAIN */
    int      enable_monitor;           /**< 1: latency and jitter monitored and warned */
    uint32_t command_writer_period_us; /**< 2000; 0: event-driven */
    uint32_t state_decimation;         /**< 1: full conversion of every state frame */
    uint32_t command_timeout_us;       /**< the command watchdog (roz/hal/cmd_watchdog.h) */
    uint32_t command_writer_spin_us;   /**< event-driven: roz_dds_writer_spin(); 0: none */
} roz_dds_params_t;

/** The keys roz_dds_params_parse() reads, for a port's list of known keys. */
#define ROZ_DDS_PARAM_KEYS                                                          \
    "network_interface", "dds_domain", "enable_monitor", "command_writer_period_us", \
        "command_writer_spin_us", "state_decimation", ROZ_CMD_WATCHDOG_KEY

/** The rows of roz_dds_params_parse()'s keys in a port's parameter table
 *  (roz_port_info_t::params), with @p domain: dds_domain's default, text. */
#define ROZ_DDS_PARAM_INFO(domain)                                                           \
    { "network_interface", "an interface name", "lo", "the interface DDS talks on" },         \
    { "dds_domain", "0..232", domain, "the DDS domain" },                                    \
    { "enable_monitor", "true|false", "true", "latency and jitter monitored and warned" },    \
    { "command_writer_period_us", "0, 100..1000000", "2000",                                 \
      "the command writer's period; 0: as soon as the tick writes" },                        \
    { "command_writer_spin_us", "0..10000", "0",                                             \
      "with period 0: how long the writer spins for the tick's command" },                   \
    { "state_decimation", "1..1000", "1", "every Nth state frame converted in full" },        \
    { ROZ_CMD_WATCHDOG_KEY, "up to 60000000", "50000",                                        \
      "the command watchdog: the tick silent this long, the port sends its safe command" }

/**
 * @brief Read the common DDS parameters.
 * @param[out] out            the values (defaults where absent)
 * @param[in]  p              the parameters (NULL: all defaults)
 * @param[in]  default_domain dds_domain when absent (the robot's own)
 * @param[in]  control_rate_hz the manifest's tick rate, for command_timeout_us's
 *                            default and least value (roz_cmd_watchdog_param())
 * @retval ROZ_OK     read
 * @retval ROZ_EINVAL a bad value; @p err names the key and the value
 * Context: start-up.
 */
int roz_dds_params_parse(roz_dds_params_t *out, const roz_params_t *p, uint32_t default_domain,
                         uint32_t control_rate_hz, char *err, size_t errlen);

/**
 * @brief Check an interface name: 1..ROZ_DDS_IFNAME_MAX characters from
 *        [A-Za-z0-9_.:-] (it goes into XML, so nothing else passes).
 * @retval ROZ_OK or ROZ_EINVAL (@p err names the key and the value)
 * Context: any; pure.
 */
int roz_dds_check_interface(const char *name, char *err, size_t errlen);

/* ---- participant ------------------------------------------------------------ */

/**
 * @brief The Cyclone configuration for @p iface (see the file comment).
 * @return the length written, or ROZ_EINVAL for a bad name,
 *         ROZ_ENOSPC when @p len is too small
 * Context: any; pure.
 */
int roz_dds_config_xml(const char *iface, char *out, size_t len);

/** A participant; caller-owned. */
typedef struct roz_dds_participant {
    int32_t  domain_entity;  /**< the domain roz created, 0 when Cyclone made it */
    int32_t  participant;    /**< 0 when not open */
    uint32_t domain;
    int      user_config;    /**< 1: CYCLONEDDS_URI was set and used */
    char     iface[ROZ_DDS_IFNAME_MAX + 1];
    char     config[ROZ_DDS_CONFIG_MAX]; /**< the XML passed to Cyclone, "" when none */
} roz_dds_participant_t;

/**
 * @brief Create the domain with roz's configuration (or the user's) and a
 *        participant in it.
 * @param[in] log  where to say which configuration is used (NULL: silent)
 * @retval ROZ_OK     open
 * @retval ROZ_EINVAL a bad interface name or domain; @p err says which
 * @retval ROZ_ENOENT no such network interface
 * @retval ROZ_EIO    Cyclone refused; @p err has its message
 * Context: start-up; allocates (Cyclone), starts Cyclone's threads.
 */
int roz_dds_participant_open(roz_dds_participant_t *p, const char *iface, uint32_t domain,
                             roz_log_fn log, void *log_ctx, char *err, size_t errlen);

/** @brief Delete the participant (and every entity in it) and the domain.
 *  Idempotent. Context: shutdown, after the writer and readers stopped. */
void roz_dds_participant_close(roz_dds_participant_t *p);

/* ---- QoS ----------------------------------------------------------------- */

/** A QoS profile for one reader or writer. */
typedef struct roz_dds_qos {
    uint8_t  reliable;        /**< 1 RELIABLE, 0 BEST_EFFORT */
    uint8_t  transient_local; /**< 1 TRANSIENT_LOCAL, 0 VOLATILE */
    uint16_t depth;           /**< KEEP_LAST depth, >= 1 */
    uint32_t max_blocking_us; /**< RELIABLE writers: longest a write may wait */
} roz_dds_qos_t;

/** ROS 2's default: KEEP_LAST 10, RELIABLE, VOLATILE. */
extern const roz_dds_qos_t roz_dds_qos_ros2_default;
/** ROS 2's sensor data: KEEP_LAST 5, BEST_EFFORT, VOLATILE. */
extern const roz_dds_qos_t roz_dds_qos_sensor_data;
/** A robot's state, read: KEEP_LAST 1, BEST_EFFORT, VOLATILE; matches any
 *  writer, and only the latest frame matters. */
extern const roz_dds_qos_t roz_dds_qos_robot_state;
/** A robot's commands, written: KEEP_LAST 1, RELIABLE, VOLATILE; matches a
 *  RELIABLE or BEST_EFFORT reader and never queues an old command behind a
 *  new one. */
extern const roz_dds_qos_t roz_dds_qos_robot_command;

/* ---- reader ------------------------------------------------------------------ */

/** A sample arrived: @p sample is the reader's storage, valid during the
 *  call; @p now_ns the monotonic receive time. Context: a Cyclone thread;
 *  one call at a time per reader; must not block or allocate. */
typedef void (*roz_dds_sample_fn)(void *ctx, void *sample, uint64_t now_ns);

/** A reader; caller-owned. The counters are written by the receive thread. */
typedef struct roz_dds_reader {
    int32_t              topic, reader;
    void                *sample;      /* the port's storage for one sample */
    size_t               sample_size;
    roz_dds_sample_fn    fn;
    void                *ctx;
    roz_monitor_t       *monitor;     /* ROZ_MON_STATE_HANDLER; NULL: not monitored */
    int                  keep;        /* 1: storage kept between takes (not zeroed) */
    /* The hand-overs to, between and from Cyclone's threads are roz's own,
     * not only Cyclone's internal locks (which ThreadSanitizer cannot see
     * in an uninstrumented libddsc): armed is set (release) once the fields
     * above are, before the reader exists, and loaded (acquire) by every
     * listener call; busy lets one call take at a time (Cyclone calls a
     * reader's listener from its delivery thread, or from a writer's
     * thread delivering locally), pending makes the one taking look again
     * when another came meanwhile; calls (release at the end of a call) is
     * loaded (acquire) by close() once Cyclone returned. */
    ROZ_ATOMIC(uint32_t) armed;
    ROZ_ATOMIC(uint32_t) busy;
    ROZ_ATOMIC(uint32_t) pending;
    ROZ_ATOMIC(uint64_t) calls;
    ROZ_ATOMIC(uint64_t) samples;     /**< valid samples handed to fn */
    ROZ_ATOMIC(uint64_t) invalid;     /**< samples without data (dispose, unregister) */
    ROZ_ATOMIC(uint64_t) take_errors; /**< dds_take failures */
} roz_dds_reader_t;

/**
 * @brief Create a topic and a reader that hands every valid sample to @p fn.
 * @param[in] descriptor  the type's `const dds_topic_descriptor_t *` (idlc's
 *                        `<type>_desc`)
 * @param[in] storage     room for one sample of that type, @p size bytes,
 *                        kept for the reader's life
 * @param[in] monitor     records each call's duration (NULL: none)
 * @retval ROZ_OK, ROZ_EINVAL, ROZ_EIO (@p err names the topic)
 * Context: start-up; @p fn may be called from the moment this returns.
 */
int roz_dds_reader_open(roz_dds_reader_t *r, const roz_dds_participant_t *p, const char *topic,
                        const void *descriptor, const roz_dds_qos_t *qos, void *storage,
                        size_t size, roz_dds_sample_fn fn, void *ctx, roz_monitor_t *monitor,
                        char *err, size_t errlen);

/**
 * @brief As roz_dds_reader_open(), for a type with sequences or strings: the
 *        storage is not zeroed before a take, so the buffers its members
 *        were given at open (roz_dds_seq_reserve(), roz_dds_string_reserve())
 *        are reused by every take. Cyclone 0.10 fills a sequence in place
 *        while the sample's elements fit its room, and grows it with its own
 *        allocator (its thread, not roz's code) for a longer sample; a string
 *        in place while the received one is no longer than the last, so a
 *        topic whose strings keep their length (joint names) reaches a steady
 *        state with no allocation. The members' padding is not zeroed: no
 *        CRC may cover such a type. Free the members with
 *        roz_dds_sample_free() after roz_dds_reader_close().
 * Context: start-up; @p fn may be called from the moment this returns.
 */
int roz_dds_reader_open_kept(roz_dds_reader_t *r, const roz_dds_participant_t *p,
                             const char *topic, const void *descriptor, const roz_dds_qos_t *qos,
                             void *storage, size_t size, roz_dds_sample_fn fn, void *ctx,
                             roz_monitor_t *monitor, char *err, size_t errlen);

/** @brief Writers matched with this reader now. Context: any thread. */
uint32_t roz_dds_reader_matched(const roz_dds_reader_t *r);

/** @brief Delete the reader: when it returns, @p fn runs no more.
 *  Idempotent. Context: shutdown. */
void roz_dds_reader_close(roz_dds_reader_t *r);

/* ---- samples with sequences and strings (ROS 2 messages) ------------------------ */

/**
 * @brief Give a sequence member of a sample (any idlc `dds_sequence_*`:
 *        _maximum, _length, _buffer, _release) room for @p n elements of
 *        @p elem_size bytes, zeroed, length 0. The buffer comes from
 *        Cyclone's allocator and the sequence owns it (_release), so
 *        Cyclone may grow it for a longer sample and roz_dds_sample_free()
 *        frees it.
 * @retval ROZ_OK, ROZ_EINVAL (n or elem_size 0, the member not empty),
 *         ROZ_ENOSPC (no memory)
 * Context: start-up (a port's open); allocates.
 */
int roz_dds_seq_reserve(void *seq, uint32_t n, size_t elem_size);

/**
 * @brief Give a string member (`char *`) room for @p len characters: a
 *        buffer from Cyclone's allocator holding @p len non-NUL characters,
 *        so that Cyclone's deserializer copies any string up to @p len
 *        characters into it in place (it reallocates only a buffer whose
 *        current string is shorter than the one received).
 * @retval ROZ_OK, ROZ_EINVAL (len 0, the member not NULL), ROZ_ENOSPC
 * Context: start-up (a port's open); allocates.
 */
int roz_dds_string_reserve(char **s, size_t len);

/**
 * @brief Free what the members of @p sample own (sequence buffers that
 *        _release, strings), not the sample itself, and zero it. Idempotent.
 * @param[in] descriptor the type's `const dds_topic_descriptor_t *`
 * Context: shutdown, after the reader that took into it closed.
 */
void roz_dds_sample_free(void *sample, size_t size, const void *descriptor);

/* ---- writer -------------------------------------------------------------------- */

/** Fill @p sample (zeroed by roz) with the command to publish now.
 *  @return 1 to publish it, 0 to publish nothing this time.
 *  Context: the writer thread; must not block or allocate. */
typedef int (*roz_dds_fill_fn)(void *ctx, void *sample, uint64_t now_ns);

/** A writer and its thread; caller-owned. Fields are private; the counters
 *  are written by the writer thread and read with atomic loads. */
typedef struct roz_dds_writer {
    int32_t              topic, writer;
    void                *sample;
    size_t               sample_size;
    roz_dds_fill_fn      fill;
    void                *ctx;
    roz_monitor_t       *monitor;   /* JITTER (periodic), COMMAND_WRITER; NULL: none */
    uint64_t             period_ns; /* 0: event-driven */
    ROZ_ATOMIC(int)      stop;
    ROZ_ATOMIC(int)      running;   /* the thread is started */
    ROZ_ATOMIC(uint64_t) passes;    /**< passes begun (fill calls) */
    ROZ_ATOMIC(uint64_t) done;      /**< passes ended (published, declined or failed) */
    ROZ_ATOMIC(uint64_t) published; /**< samples written */
    ROZ_ATOMIC(uint64_t) errors;    /**< dds_write failures */
    ROZ_ATOMIC(uint64_t) missed;    /**< periods missed by more than a period (skipped) */
    const roz_cmd_watchdog_t *watchdog; /* event-driven: wake when it is due; NULL: none */
    uint64_t             repeat_ns;  /* event-driven, tripped: the safe command's period */
    uint64_t             fired_due;  /* the last deadline a wait timed out at */
    uint64_t             last_pass_ns;
    /* event-driven: the tick's posts and the receive path's heads-up; the
     * writer sleeps on the semaphore only with `sleeping` set, so a post
     * while it is awake or spinning is an atomic add, not a syscall */
    ROZ_ATOMIC(uint64_t) posts;     /* roz_dds_writer_wake() calls */
    ROZ_ATOMIC(uint64_t) expects;   /* roz_dds_writer_expect() calls */
    ROZ_ATOMIC(int)      sleeping;
    ROZ_ATOMIC(int)      spin_on;   /* started, event-driven, spin_ns > 0 */
    uint64_t             handled;   /* posts the writer has passed for */
    uint64_t             expected;  /* expects it has spun for */
    uint64_t             spin_ns;   /* 0: no spinning ahead of a command */
    unsigned long        thread;    /* pthread_t, kept opaque */
    union {
        unsigned char bytes[64];
        long double   align;
    } wake;                         /* sem_t, kept opaque */
    int                  wake_ready;
} roz_dds_writer_t;

/**
 * @brief Create a topic and a writer (no thread yet).
 * @param[in] storage  room for one sample, @p size bytes, kept for the
 *                     writer's life; the writer thread owns it
 * @retval ROZ_OK, ROZ_EINVAL, ROZ_EIO (@p err names the topic)
 * Context: start-up.
 */
int roz_dds_writer_open(roz_dds_writer_t *w, const roz_dds_participant_t *p, const char *topic,
                        const void *descriptor, const roz_dds_qos_t *qos, void *storage,
                        size_t size, char *err, size_t errlen);

/**
 * @brief Start the writer thread.
 * @param[in] period_us  publish every period_us (ROZ_DDS_MIN_PERIOD_US ..
 *                       ROZ_DDS_MAX_PERIOD_US); 0: on roz_dds_writer_wake()
 * @param[in] monitor    jitter against the period and the time of each pass
 *                       (NULL: not monitored)
 * @retval ROZ_OK, ROZ_EINVAL (bad period, not open), ROZ_ESTATE (running),
 *         ROZ_EIO (no thread)
 * Context: start-up.
 */
int roz_dds_writer_start(roz_dds_writer_t *w, uint32_t period_us, roz_dds_fill_fn fill,
                         void *ctx, roz_monitor_t *monitor);

/**
 * @brief Let an event-driven writer keep the port's command watchdog: it
 *        wakes by itself when the last frame the fill judged expires (a pass
 *        whose fill judges it again, trips, and fills the safe command), and
 *        while tripped passes every @p repeat_us until the tick writes. A
 *        periodic writer passes every period and needs none of this.
 * @param[in] wd        the watchdog the fill judges frames with (the writer
 *                      thread reads roz_cmd_watchdog_next_ns() only)
 * @param[in] repeat_us the safe command's period while tripped (the robot's
 *                      command period), > 0
 * @retval ROZ_OK, ROZ_EINVAL, ROZ_ESTATE (running)
 * Context: start-up, before roz_dds_writer_start().
 */
int roz_dds_writer_watch(roz_dds_writer_t *w, const roz_cmd_watchdog_t *wd, uint32_t repeat_us);

/** @brief Event-driven mode: publish now. Never blocks (an atomic add, and
 *  a semaphore post when the writer sleeps); nothing in periodic mode.
 *  Context: any thread (the tick); RT-safe. */
void roz_dds_writer_wake(roz_dds_writer_t *w);

/**
 * @brief Event-driven mode with a spin (roz_dds_writer_spin()): a state
 *        frame has arrived and the tick's command will follow. Wakes the
 *        writer now, while the tick runs, so the tick's
 *        roz_dds_writer_wake() finds it awake. Nothing is published without
 *        that wake. Never blocks; nothing otherwise.
 * Context: any thread (the port's receive path); RT-safe.
 */
void roz_dds_writer_expect(roz_dds_writer_t *w);

/**
 * @brief Let an event-driven writer, woken by roz_dds_writer_expect(), spin
 *        (yielding the CPU between looks) for up to @p spin_us for the
 *        tick's command instead of going back to sleep: the command then
 *        goes out without a thread wake-up on its path, at the cost of that
 *        CPU time per state frame. 0 (the default): no spinning.
 * @retval ROZ_OK, ROZ_EINVAL (above ROZ_DDS_MAX_SPIN_US), ROZ_ESTATE (running)
 * Context: start-up, before roz_dds_writer_start().
 */
int roz_dds_writer_spin(roz_dds_writer_t *w, uint32_t spin_us);

/**
 * @brief Publish one sample now from the calling thread, through @p fill:
 *        for a last command before the thread stops (which must not run at
 *        the same time: call after roz_dds_writer_stop()), or for a writer
 *        that never has a thread of its own, published from another
 *        writer's pass (a port with several command topics runs one writer
 *        thread: its fill publishes the other topics' writers this way, so
 *        every topic's sample of a pass carries the same command frame).
 * @retval 1 published, 0 fill declined, ROZ_EIO write failed, ROZ_ESTATE running
 * Context: shutdown; or the one thread that publishes a writer without a
 *          thread of its own. Must not block or allocate in @p fill.
 */
int roz_dds_writer_publish(roz_dds_writer_t *w, roz_dds_fill_fn fill, void *ctx);

/** How long a port's deactivate waits for reliable readers to acknowledge
 *  its last (damping) command: a robot, or a peer on a loaded machine, may be
 *  slow to (200 ms lost it under load). Bounded; off the tick path. */
#define ROZ_DDS_SHUTDOWN_FLUSH_MS 1000u

/** How long a port's deactivate repeats its last (damping) command, one
 *  sample every ROZ_DDS_SHUTDOWN_REPEAT_US: a best-effort reader (the robots
 *  do not say what theirs is) loses a single sample when its socket buffer is
 *  full, and the command the robot would then keep is the controller's last,
 *  with its gains. */
#define ROZ_DDS_SHUTDOWN_REPEAT_MS 100u
#define ROZ_DDS_SHUTDOWN_REPEAT_US 2000u

/**
 * @brief The last command of a port: publish through @p fill from the
 *        calling thread every ROZ_DDS_SHUTDOWN_REPEAT_US for
 *        ROZ_DDS_SHUTDOWN_REPEAT_MS, then wait up to ROZ_DDS_SHUTDOWN_FLUSH_MS
 *        for reliable readers to acknowledge it. Call after
 *        roz_dds_writer_stop().
 * @retval 1 published (at least once), 0 fill declined, ROZ_EIO every write
 *         failed, ROZ_ESTATE running
 * Context: shutdown (sleeps; bounded by the two constants).
 */
int roz_dds_writer_publish_final(roz_dds_writer_t *w, roz_dds_fill_fn fill, void *ctx);

/** @brief Wait until every reader acknowledged what was written, at most
 *  @p timeout_ms. @retval ROZ_OK, ROZ_ETIMEDOUT. Context: shutdown. */
int roz_dds_writer_flush(roz_dds_writer_t *w, uint32_t timeout_ms);

/** @brief Readers matched with this writer now. Context: any thread. */
uint32_t roz_dds_writer_matched(const roz_dds_writer_t *w);

/** @brief Stop and join the thread (it finishes its pass). Idempotent.
 *  Context: shutdown; blocks up to one pass. */
void roz_dds_writer_stop(roz_dds_writer_t *w);

/** @brief Stop, then delete the writer. Idempotent. Context: shutdown. */
void roz_dds_writer_close(roz_dds_writer_t *w);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_DDS_H */
