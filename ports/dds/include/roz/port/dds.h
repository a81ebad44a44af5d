/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port/dds.h
 * @brief roz::dds, the Cyclone DDS plumbing every DDS port shares: the
 *        participant and its configuration, QoS profiles, a receive path into
 *        preallocated storage, and the command writer thread.
 *
 * docs/ports/dds.md describes it: the participant's configuration on `lo`
 * and elsewhere (CYCLONEDDS_URI wins), the receive path, the periodic and
 * event-driven writer, the command watchdog, the spin for low latency, the
 * threads, and why entities are int32_t here (no Cyclone header is public).
 */
#ifndef ROZ_PORT_DDS_H
#define ROZ_PORT_DDS_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/atomic.h"
#include "roz/buffer.h"
#include "roz/hal/cmd_watchdog.h"
#include "roz/hal/joints.h"
#include "roz/hal/params.h"
#include "roz/log.h"
#include "roz/manifest.h"
#include "roz/monitor.h"
#include "roz/hal/thread.h"
#include "roz/port.h"
#include "roz/private.h"

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
#define ROZ_DDS_CONFIG_MAX 1600
/** Samples one data-available call takes at most before it yields. */
#define ROZ_DDS_TAKE_MAX 64u
/** Shortest writer period, microseconds (0 = event-driven). */
#define ROZ_DDS_MIN_PERIOD_US 100u
/** Longest spin of an event-driven writer for the tick's command (us). */
#define ROZ_DDS_MAX_SPIN_US 10000
/** Longest writer period, microseconds. */
#define ROZ_DDS_MAX_PERIOD_US 1000000u

/* ---- parameters ------------------------------------------------------------ */

/** The parameters every DDS port understands (roz/hal/params.h). */
typedef struct roz_dds_params {
    char     network_interface[ROZ_DDS_IFNAME_MAX + 1]; /**< "lo" */
    uint32_t domain;                   /**< dds_domain, 0..ROZ_DDS_MAX_DOMAIN */
    int      enable_monitor;           /**< 1: latency and jitter monitored and warned */
    int      exit_damping;             /**< exit_stop = damping: the last command on the way
                                            out is damping, not the stop's hold */
    uint32_t command_writer_period_us; /**< 2000; 0: event-driven */
    uint32_t state_decimation;         /**< 1: full conversion of every state frame */
    uint32_t command_timeout_us;       /**< the command watchdog (roz/hal/cmd_watchdog.h) */
    uint32_t command_writer_spin_us;   /**< event-driven: roz_dds_writer_spin(); 0: none */
    roz_thread_config_t writer_thread; /**< the command writer thread's scheduling
                                            (command_writer_sched, ..., roz/hal/thread.h) */
    roz_thread_config_t cyclone_threads; /**< Cyclone's receive, delivery and timed-event
                                            threads (dds_threads_sched, _priority,
                                            _stack_kib), through its configuration */
} roz_dds_params_t;

/** The rows of roz_dds_params_parse()'s keys in a port's parameter table
 *  (roz_port_info_t::params), with @p domain: dds_domain's default, text.
 *  roz_dds_params_parse() reads its numeric rows' bounds and defaults. */
#define ROZ_DDS_PARAM_INFO(domain)                                                              \
    ROZ_PORT_PARAM_TEXT_ROW("network_interface", "an interface name", "lo",                     \
                            "the interface DDS talks on"),                                      \
    ROZ_PORT_PARAM_TEXT_ROW("dds_domain", "0..232", domain, "the DDS domain"),                  \
    ROZ_PORT_PARAM_TEXT_ROW("enable_monitor", "true|false", "true",                             \
                            "latency and jitter monitored and warned"),                         \
    ROZ_PORT_PARAM_TEXT_ROW("exit_stop", "hold|damping", "hold",                                \
                            "the last command when the port closes: the stop's hold, or "       \
                            "damping (kp 0)"),                                                  \
    ROZ_PORT_PARAM_TEXT_ROW("command_writer_period_us", "0, 100..1000000", "2000",              \
                            "the command writer's period; 0: as soon as the tick writes"),      \
    ROZ_PORT_PARAM_U32_ROW("command_writer_spin_us", 0, ROZ_DDS_MAX_SPIN_US, 0,                 \
                           "with period 0: how long the writer spins for the tick's command"),  \
    ROZ_PORT_PARAM_U32_ROW("state_decimation", 1, 1000, 1,                                      \
                           "every Nth state frame converted in full"),                          \
    ROZ_THREAD_PARAM_INFO("command_writer", "the command writer thread"),                       \
    ROZ_PORT_PARAM_TEXT_ROW("dds_threads_sched", "other|fifo", "other",                         \
                            "scheduling of Cyclone's receive, delivery and timed-event "        \
                            "threads"),                                                         \
    ROZ_PORT_PARAM_TEXT_ROW("dds_threads_priority", "1..99", "", "their priority with fifo"),   \
    ROZ_PORT_PARAM_TEXT_ROW("dds_threads_stack_kib", ROZ_THREAD_STACK_RANGE, "",                \
                            "their stack size (default: the system's)"),                        \
    ROZ_PORT_PARAM_TEXT_ROW(ROZ_CMD_WATCHDOG_KEY, "up to 60000000", "50000",                    \
                            "the command watchdog: the tick silent this long, the port sends "  \
                            "its safe command")

/** The rows of a DDS robot port's link and hold parameters in its table:
 *  the silence that loses the robot (its numeric row's bounds and default
 *  read by the port), then roz_dds_params_damping()'s keys. */
#define ROZ_DDS_HOLD_PARAM_INFO                                                                 \
    ROZ_PORT_PARAM_U32_ROW("peer_timeout_ms", 10, 60000, 500,                                   \
                           "the robot silent this long is lost"),                               \
    ROZ_PORT_PARAM_TEXT_ROW("startup_damping", "the damping channels' range", "0",              \
                            "kd of the start-up hold"),                                         \
    ROZ_PORT_PARAM_TEXT_ROW("shutdown_damping", "the damping channels' range",                  \
                            "the channels' default",                                            \
                            "kd of the damping command at shut-down and on a watchdog trip")

/**
 * @brief Read startup_damping (0, or the least the damping channels allow)
 *        and shutdown_damping (NaN when absent: each joint's damping
 *        default), both within the range every bound joint's damping
 *        channel allows (roz_joints_damping_range()).
 * @param[in] report where each problem goes, as @p rule (ROZ_PARAMS_STEP());
 *                   NULL: the first problem is the error
 * @retval ROZ_OK, or ROZ_EINVAL with @p err naming the key and the value
 * Context: start-up; no heap.
 */
int roz_dds_params_damping(const roz_params_t *p, const roz_manifest_t *m,
                           const roz_joint_channels_t *joint, uint16_t n, double *startup_kd,
                           double *shutdown_kd, const char *rule, roz_params_problem_fn report,
                           void *ctx, char *err, size_t errlen);

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

/** Cyclone's threads that roz_dds_config_xml() configures: the receive
 *  threads, the user data's delivery and the timed events (retransmits,
 *  heartbeats); NULL-terminated. */
extern const char *const roz_dds_cyclone_threads[];

/**
 * @brief The Cyclone configuration for @p iface (see the file comment), with
 *        @p threads for Cyclone's threads (roz_dds_cyclone_threads;
 *        Threads/Thread[@Name]/Scheduling/Class, Priority and StackSize;
 *        NULL or all zero: Cyclone's defaults; Cyclone sets no affinity).
 * @return the length written, or ROZ_EINVAL for a bad name or an rr
 *         policy (Cyclone has none), ROZ_ENOSPC when @p len is too small
 * Context: any; pure.
 */
int roz_dds_config_xml(const char *iface, const roz_thread_config_t *threads, char *out,
                       size_t len);

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
 * @param[in] threads Cyclone's threads (roz_dds_config_xml()); NULL: defaults
 * @param[in] log  where to say which configuration is used (NULL: silent)
 * @retval ROZ_OK     open
 * @retval ROZ_EINVAL a bad interface name or domain; @p err says which
 * @retval ROZ_ENOENT no such network interface
 * @retval ROZ_EIO    Cyclone refused; @p err has its message
 * Context: start-up; allocates (Cyclone), starts Cyclone's threads.
 */
int roz_dds_participant_open(roz_dds_participant_t *p, const char *iface, uint32_t domain,
                             const roz_thread_config_t *threads, roz_log_fn log,
                             void *log_ctx, char *err, size_t errlen);

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
    uint64_t             last_pass_ns; /* on the watchdog's clock */
    uint64_t           (*clock)(void *ctx); /* the watchdog's (roz_dds_writer_watch()) */
    void                *clock_ctx;
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
    roz_thread_config_t  thread_cfg; /* how the thread is started (roz_dds_writer_set_thread()) */
    char                 thread_err[160]; /* why it was not, after ROZ_EIO */
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

/** @brief How roz_dds_writer_start() creates the thread (roz/hal/thread.h);
 *  NULL or never called: the system's defaults. Context: start-up. */
void roz_dds_writer_set_thread(roz_dds_writer_t *w, const roz_thread_config_t *cfg);

/** @brief Why the last roz_dds_writer_start() could not start the thread
 *  ("" when it did). Context: start-up. */
const char *roz_dds_writer_thread_error(const roz_dds_writer_t *w);

/** @brief What the running writer thread carries (roz_thread_describe()).
 *  @retval ROZ_OK, ROZ_ESTATE (not running), ROZ_EIO. Context: any thread. */
int roz_dds_writer_thread(const roz_dds_writer_t *w, roz_thread_config_t *out);

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
 * @param[in] clock     the clock @p wd counts on (its deadlines, the repeat),
 *                      with @p clock_ctx; NULL: roz_clock_monotonic_ns().
 *                      The writer judges on it whether a pass is due; its
 *                      sleeps stay on CLOCK_MONOTONIC, each as long as the
 *                      time left by that clock when it began (a test's clock
 *                      that stands still: the test moves it, then calls
 *                      roz_dds_writer_nudge())
 * @retval ROZ_OK, ROZ_EINVAL, ROZ_ESTATE (running)
 * Context: start-up, before roz_dds_writer_start().
 */
int roz_dds_writer_watch(roz_dds_writer_t *w, const roz_cmd_watchdog_t *wd, uint32_t repeat_us,
                         uint64_t (*clock)(void *ctx), void *clock_ctx);

/** @brief Event-driven mode: wake the writer to look at the watchdog's
 *  clock again, no frame posted (a test that moved its clock: a pass
 *  follows only if one is due by it). Never blocks. Context: any thread. */
void roz_dds_writer_nudge(roz_dds_writer_t *w);

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

/* ---- command path: the tick's write and the writer's pass ---------------------- */

/*
 * What every DDS port does with the tick's commands, written once for all
 * of them (roz_dds_cmd_t): the tick's write(), the writer thread's pass over
 * the latest command frame, the watchdog's report in read(), and the last
 * command on deactivate. The port supplies what belongs to its wire
 * (roz_dds_cmd_ops_t): how the start-up hold, the tick's frame and the
 * damping command become its messages, and which robot session its
 * receive path sees.
 *
 * The tick (roz_dds_cmd_write()): nothing before the first state frame
 * (counted withheld; roz/port.h's first layer). The first write for a
 * robot, its first or a restarted one as the port's read() saw it, is the
 * start-up hold (ops->hold: every joint at its measured position, zero
 * stiffness), and so is every write while the command watchdog asks for one
 * after a trip (roz/hal/cmd_watchdog.h); any other write is the tick's frame
 * clamped to its channels (roz_commands_clamp()). The frame goes into a
 * latest-value buffer with the meta words below, the port's own after them,
 * and the writer is woken.
 *
 * The writer thread (its pass): the latest frame is sent (ops->send) unless
 * it was written for another session than the receive path's now (counted
 * stale: a robot that restarted gets nothing until the tick writes for it),
 * the port refuses it (ops->refuse, counted refused), or the watchdog judges
 * it too old or of an earlier epoch: then the watchdog's hold (ops->watchdog,
 * counted safe), nothing to a robot that never got a command.
 *
 * Deactivate (roz_dds_cmd_stop()): the writer thread stopped, the damping
 * command is published from the caller's thread for
 * ROZ_DDS_SHUTDOWN_REPEAT_MS (roz_dds_writer_publish_final()), if the robot
 * ever got a command.
 *
 * Memory ordering: frames go through roz/buffer.h (wait-free, never torn).
 * written_seq is stored with release after the frame is committed, and
 * handled_seq with release at the end of the pass that took it, before the
 * writer publishes the sample: a reader that loads both with acquire and
 * finds them equal, and the writer's passes equal to its done, knows the
 * pass over the last frame written has ended (the settle() of the port
 * tests' fixtures). shutdown is stored with release after the writer
 * thread was joined and loaded with acquire by the pass; the writer
 * thread's own fields (sent_any, the port's last positions) reach the
 * final pass through that join. The watchdog's hand-over is
 * roz/hal/cmd_watchdog.h's. The other counters are relaxed adds, loaded
 * with acquire.
 *
 * No heap, no lock: the tick's write is O(n_commands + n_extra) and never
 * blocks (the writer's wake is an atomic add, and a semaphore post when it
 * sleeps); a pass is one frame and the port's hooks.
 */

/** Values after the commands in a command frame that the command path
 *  writes: the robot session, hold (1: the frame is the start-up hold),
 *  sequence, watchdog epoch. The port's own n_extra values follow. */
#define ROZ_DDS_CMD_META 4

/** What the port supplies; every hook gets the port's instance first. */
typedef struct roz_dds_cmd_ops {
    /** The hold into @p cmd (n_commands, manifest order). @p last NULL:
     *  the start-up hold, every joint's position command its measured
     *  position, kd the port's `startup_damping`, everything else 0. Else
     *  (the tick back after a watchdog trip) the stop's hold from @p last,
     *  the tick's last command before the trip (roz_joints_hold_keep(): the
     *  hold gains, the torque kept, kd `shutdown_damping`): the robot is
     *  held already, and a frame without stiffness between two holds would
     *  let it go limp (test_g1_trip_write_trip_keeps_the_torque). Each value
     *  clamped. Context: the tick; RT-safe. */
    void (*hold)(void *port, const double *last, double *cmd);
    /** The robot session the receive path has seen, compared with the one
     *  the tick wrote a frame for. Context: the writer thread; RT-safe. */
    uint32_t (*rx_session)(void *port);
    /** Optional (NULL: never refuses): 1 to send nothing for this frame.
     *  Called at the start of every pass that has a frame, before
     *  rx_session: what it loads (acquire) that the receive path stores
     *  after the session comes with that session or a later one.
     *  Context: the writer thread; RT-safe. */
    int (*refuse)(void *port);
    /** The tick's frame into @p sample (zeroed): @p cmd its n_commands
     *  values, @p extra the port's n_extra values the tick gave with it;
     *  @p hold 1 when the frame is a hold the port made (start-up, or after
     *  a trip), which the port's watchdog and exit never take for the
     *  controller's last command. Other topics' samples of the pass are
     *  published from here (roz_dds_writer_publish()). @return 1 to publish
     *  @p sample. Context: the writer thread; RT-safe. */
    int (*send)(void *port, void *sample, const double *cmd, const double *extra, int hold);
    /** The last command on the way out (the port's deactivate) into
     *  @p sample (zeroed): the stop's hold as the watchdog sends it, or
     *  with `exit_stop = damping` the damping command (kp 0, kd the port's
     *  `shutdown_damping`, q the positions last sent). @return 1 to publish.
     *  Context: the writer thread, or the caller's once it stopped; RT-safe. */
    int (*safe)(void *port, void *sample);
    /** The watchdog's command into @p sample (zeroed), once the tick has
     *  been silent for the timeout: the stop's hold from the controller's
     *  last command (roz_joints_hold_setpoint(): kp each joint's stiffness
     *  default, the manifest's hold gain; the setpoint keeping the torque
     *  within the band; a joint without a position command at its measured
     *  position), kd the port's `shutdown_damping`. NULL: safe().
     *  @return 1 to publish. Context: the writer thread; RT-safe. */
    int (*watchdog)(void *port, void *sample);
} roz_dds_cmd_ops_t;

/** How roz_dds_cmd_init() sets a command path up. */
typedef struct roz_dds_cmd_config {
    const roz_manifest_t    *m;
    const roz_dds_cmd_ops_t *ops;
    void                    *port;       /**< the hooks' first argument */
    roz_dds_writer_t        *writer;     /**< the writer whose thread passes (open
                                              before roz_dds_cmd_attach()) */
    double                  *slots;      /**< the frames' storage: 3 * (n_commands +
                                              ROZ_DDS_CMD_META + n_extra) doubles */
    uint16_t                 n_extra;    /**< the port's values after the meta words */
    uint32_t                 timeout_us; /**< `command_timeout_us` */
    /** The clock the watchdog counts on: the tick's writes are stamped,
     *  the pass judges a frame's age and read() the silence with it.
     *  NULL: roz_clock_monotonic_ns() (every port). Another (a test's,
     *  which it moves on itself): an event-driven writer judges by it
     *  when the watchdog is due, and the test wakes it after moving it
     *  (roz_dds_writer_watch(), roz_dds_writer_nudge()). */
    uint64_t               (*clock)(void *ctx);
    void                    *clock_ctx;  /**< @p clock's argument */
} roz_dds_cmd_config_t;

/** What the tick's read() saw of the robot, for roz_dds_cmd_write(). */
typedef struct roz_dds_cmd_tick {
    int           has_state; /**< a fresh state frame was read: before, nothing is sent */
    uint32_t      robot;     /**< which robot it came from: a new value makes this
                                  write the start-up hold */
    uint32_t      session;   /**< the session the pass compares with ops->rx_session() */
    const double *extra;     /**< n_extra values for ops->send(); NULL when n_extra is 0 */
} roz_dds_cmd_tick_t;

/** The command path's counters (roz_dds_cmd_count()). */
typedef enum roz_dds_cmd_counter {
    ROZ_DDS_CMD_WRITES = 0,  /**< write() calls */
    ROZ_DDS_CMD_WITHHELD,    /**< writes before the first state frame (nothing sent) */
    ROZ_DDS_CMD_HOLDS,       /**< writes that became the start-up hold */
    ROZ_DDS_CMD_CLAMPED,     /**< written values outside their channel (clamped) */
    ROZ_DDS_CMD_STALE,       /**< passes that sent nothing: written for another session */
    ROZ_DDS_CMD_REFUSED,     /**< passes that sent nothing: ops->refuse() */
    ROZ_DDS_CMD_HANDLED_SEQ, /**< sequence of the last frame a pass judged */
    ROZ_DDS_CMD_WRITTEN_SEQ, /**< sequence of the last frame the tick wrote */
    ROZ_DDS_CMD_SAFE,        /**< watchdog passes that sent the damping command */
    ROZ_DDS_CMD_HOLD_SENT_SEQ, /**< sequence of the last start-up hold a pass sent */
    ROZ_DDS_CMD_COUNTERS
} roz_dds_cmd_counter_t;

/** A command path; caller-owned (a member of the port's instance). Fields
 *  are private (roz/private.h). */
typedef struct roz_dds_cmd {
    /* set at init, then read-only */
    const roz_manifest_t    *ROZ_PRIVATE(m);
    const roz_dds_cmd_ops_t *ROZ_PRIVATE(ops);
    void                    *ROZ_PRIVATE(port);
    roz_dds_writer_t        *ROZ_PRIVATE(writer);
    uint16_t                 ROZ_PRIVATE(n_extra);
    uint32_t                 ROZ_PRIVATE(timeout_us);
    uint64_t               (*ROZ_PRIVATE(clock))(void *ctx); /* the watchdog's */
    void                    *ROZ_PRIVATE(clock_ctx);
    /* the tick's */
    uint32_t                 ROZ_PRIVATE(write_robot); /* the robot of the last write */
    uint64_t                 ROZ_PRIVATE(write_seq);
    uint64_t                 ROZ_PRIVATE(hold_seq);    /* the last hold's sequence */
    int                      ROZ_PRIVATE(hold_after_trip); /* it follows a watchdog trip */
    int                      ROZ_PRIVATE(has_last);  /* last_cmd holds a tick's command */
    double                   ROZ_PRIVATE(last_cmd)[ROZ_CFG_MAX_COMMANDS]; /* the tick's last
                                                       command that was not a hold (tick) */
    /* tick <-> writer thread */
    roz_cmd_watchdog_t       ROZ_PRIVATE(watchdog);
    roz_buffer_t             ROZ_PRIVATE(buf);
    ROZ_ATOMIC(int)          ROZ_PRIVATE(shutdown);    /* 1: the pass sends the damping */
    /* a test's hook: 1 holds the writer back (its passes send nothing and
     * leave the frame), so that the tick writes again before a frame went
     * out (test_g1_hold_reaches_the_wire_first) */
    ROZ_ATOMIC(int)          ROZ_PRIVATE(held_back);
    /* the writer thread's */
    int                      ROZ_PRIVATE(sent_any);    /* ops->send() was called */
    /* written by one thread each, read by any */
    ROZ_ATOMIC(uint64_t)     ROZ_PRIVATE(count)[ROZ_DDS_CMD_COUNTERS];
} roz_dds_cmd_t;

/**
 * @brief Set a command path up over @p cfg: its buffer, its watchdog (armed,
 *        epoch 0), its counters at 0, no robot written for, nothing sent.
 * Context: start-up (a port's open), before the port's threads run; no I/O.
 */
void roz_dds_cmd_init(roz_dds_cmd_t *c, const roz_dds_cmd_config_t *cfg);

/**
 * @brief Wire the command path to its writer (open by now): the spin ahead
 *        of the tick's command (roz_dds_writer_spin()).
 * @retval ROZ_OK, or the writer's error
 * Context: start-up (a port's open), after roz_dds_writer_open().
 */
int roz_dds_cmd_attach(roz_dds_cmd_t *c, uint32_t spin_us);

/**
 * @brief Start the writer thread with the command path's pass
 *        (roz_dds_writer_start()), the watchdog kept by an event-driven
 *        writer on the path's clock, repeating the safe command at the
 *        tick's rate (roz_dds_writer_watch()); the shutdown of a previous
 *        activation is forgotten.
 * @retval ROZ_OK, or the writer's error
 * Context: start-up (a port's activate).
 */
int roz_dds_cmd_start(roz_dds_cmd_t *c, uint32_t period_us, roz_monitor_t *monitor);

/**
 * @brief The tick's write (see above); the port checked it is open.
 * @param[in] cmd n values, manifest order
 * @param[in] t   what the port's read() saw
 * @retval ROZ_OK     written, held, or withheld before the first state frame
 * @retval ROZ_EINVAL @p n is not the manifest's n_commands
 * Context: the tick; RT-safe, never blocks; no heap.
 */
int roz_dds_cmd_write(roz_dds_cmd_t *c, const double *cmd, size_t n, const roz_dds_cmd_tick_t *t);

/**
 * @brief The watchdog's side of the tick's read(): a trip not yet reported
 *        takes the place of a plain frame (@p rc 0 or 1; the frame is read,
 *        and the hold that follows holds its positions); after a link or
 *        robot fault, at the next read.
 * @param[in]  rc    what the port's read would return
 * @param[out] fault filled for a trip: ROZ_CMD_WATCHDOG_KEY, how long the
 *                   tick was silent (code, us), the timeout (limit)
 * @return ROZ_EWATCHDOG for a trip, else @p rc
 * Context: the tick (read()); RT-safe.
 */
int roz_dds_cmd_report(roz_dds_cmd_t *c, int rc, roz_port_fault_t *fault);

/**
 * @brief The last command: stop the writer thread, then publish the damping
 *        command from here (roz_dds_writer_publish_final()), if the robot
 *        ever got a command.
 * @return roz_dds_writer_publish_final()'s: 1 published, 0 nothing to send
 *         (the robot never got a command), ROZ_EIO every write failed
 * Context: shutdown (a port's deactivate); sleeps, bounded.
 */
int roz_dds_cmd_stop(roz_dds_cmd_t *c);

/** @brief Counter @p k (one atomic load). Context: any thread. */
uint64_t roz_dds_cmd_count(const roz_dds_cmd_t *c, roz_dds_cmd_counter_t k);

/** @brief Command watchdog trips: the tick went silent. Context: any thread. */
uint32_t roz_dds_cmd_timeouts(const roz_dds_cmd_t *c);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_DDS_H */
