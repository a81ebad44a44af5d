/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/record_file.h
 * @brief Flight recordings as MCAP files (host builds; roz/mcap.h): the
 *        recorder's drain side, and the reader replay uses.
 *
 * docs/recording.md lists the topics and schemas, the field names, the
 * chunks, and the calls: roz_record_file_open() after roz_runtime_init()
 * with a recorder, roz_record_file_drain() from a non-real-time thread (or
 * between ticks), roz_record_file_close() at the end; roz_record_reader_open()
 * and roz_record_reader_next() to read a file tick by tick;
 * docs/recording-format.md has the file's layout and limits.
 */
#ifndef ROZ_RECORD_FILE_H
#define ROZ_RECORD_FILE_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/mcap.h"
#include "roz/private.h"
#include "roz/recorder.h"
#include "roz/runtime.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A recording being written. Fields are private to record_file.c. */
typedef struct roz_record_file {
    roz_mcap_writer_t      ROZ_PRIVATE(w);
    roz_recorder_t        *ROZ_PRIVATE(rec);
    const roz_manifest_t  *ROZ_PRIVATE(m);
    uint16_t               ROZ_PRIVATE(ch_run), ROZ_PRIVATE(ch_controller), ROZ_PRIVATE(ch_tick),
                           ROZ_PRIVATE(ch_state), ROZ_PRIVATE(ch_target), ROZ_PRIVATE(ch_applied),
                           ROZ_PRIVATE(ch_fault), ROZ_PRIVATE(ch_truth), /* ch_truth 0: none */
                           ROZ_PRIVATE(ch_inputs), /* 0: the robot has no inputs */
                           ROZ_PRIVATE(ch_deploy), ROZ_PRIVATE(ch_stage); /* 0: no sequence */
    roz_port_t             ROZ_PRIVATE(port);   /* names a truth sample's bodies */
    uint64_t               ROZ_PRIVATE(last_hash);
    int                    ROZ_PRIVATE(have_hash);
    const char            *ROZ_PRIVATE(controller_name);
    unsigned char         *ROZ_PRIVATE(msg);    /* one message being encoded */
    size_t                 ROZ_PRIVATE(msg_cap);
    uint64_t               ROZ_PRIVATE(ticks), ROZ_PRIVATE(bytes_before);
    uint64_t               ROZ_PRIVATE(start_ns);
    int                    ROZ_PRIVATE(failed);
} roz_record_file_t;

/** How a recording is written. */
typedef struct roz_record_file_options {
    const char *controller_name; /**< named in /roz/controller (e.g. the file's path) */
    uint64_t    start_time_ns;   /**< the wall clock at tick 0, Unix time in ns (0: 1970) */
    int         compression;     /**< ROZ_MCAP_COMPRESS_NONE or _ZSTD */
} roz_record_file_options_t;

/**
 * @brief Create @p path, write the schemas, the channels and the run's
 *        /roz/run message (from @p rt's configuration and manifest, and
 *        @p rec's decimation).
 * @param[in] opt  NULL: no controller name, start 0, uncompressed
 * @retval ROZ_OK, ROZ_EIO (err names the file), ROZ_ENOMEM, ROZ_EINVAL (no recorder)
 * @retval ROZ_ENOTSUP the compression asked for is not in this build
 * Context: start-up, a non-real-time thread; allocates.
 */
ROZ_NODISCARD int roz_record_file_open(roz_record_file_t *f, const char *path,
                                       const roz_runtime_t *rt, roz_recorder_t *rec,
                                       const roz_record_file_options_t *opt, char *err,
                                       size_t errlen);

/**
 * @brief As roz_record_file_open(), but a stream to @p sink (a live viewer's
 *        pipe, roz/record_live.h): the same schemas, channels and messages,
 *        one chunk per tick, no indexes and no summary (roz_mcap_open_stream()).
 * @param[in] name  names the stream in errors
 * Context: start-up, a non-real-time thread; allocates.
 */
ROZ_NODISCARD int roz_record_file_open_stream(roz_record_file_t *f, const char *name,
                                              const roz_runtime_t *rt, roz_recorder_t *rec,
                                              const roz_record_file_options_t *opt,
                                              roz_mcap_sink_fn sink, void *ctx, char *err,
                                              size_t errlen);

/**
 * @brief Write one record that the caller's own drain handed out (when one
 *        drain feeds a file and a stream: roz_recorder_drain() with a sink
 *        that calls this for each). Its messages end at a chunk boundary.
 * @retval ROZ_OK, ROZ_EIO once a write failed (roz_record_file_error())
 * Context: the recorder's one consumer thread.
 */
int roz_record_file_put(roz_record_file_t *f, const roz_record_t *r);

/**
 * @brief Drain the recorder into the file.
 * @return records written (>= 0), or ROZ_EIO once a write failed (the
 *         records are still drained, so the tick's ring never fills)
 * Context: the recorder's one consumer thread (roz_recorder_drain()).
 */
int roz_record_file_drain(roz_record_file_t *f);

/** @brief Ticks written so far. Context: the consumer thread. */
uint64_t roz_record_file_ticks(const roz_record_file_t *f);

/** @brief The first write error ("" none), naming the file. Context: the
 *  consumer thread. */
const char *roz_record_file_error(const roz_record_file_t *f);

/**
 * @brief Drain what is left, finish the file (summary, footer), close it.
 * @retval ROZ_OK  complete; ROZ_EIO  a write failed (err says the first)
 * Context: the consumer thread, after the tick stopped.
 */
int roz_record_file_close(roz_record_file_t *f, char *err, size_t errlen);

/** What /roz/run says about a recording. */
typedef struct roz_record_run {
    char     robot_id[64];
    char     robot_class[64];
    uint32_t control_rate_hz;
    uint64_t interface_hash;
    uint16_t n_commands, n_states;
    uint16_t n_inputs;      /**< operator inputs, in /roz/inputs (0 in files before them) */
    uint32_t stale_ticks;
    uint64_t fuel_per_tick;
    uint64_t budget_ns;
    uint32_t decimation;
    int      allow_foreign_controller;
    uint64_t start_time_ns; /**< wall clock at tick 0 (Unix ns); 0 in files before it */
} roz_record_run_t;

/** A recording being read. Fields are private to record_file.c. */
typedef struct roz_record_reader {
    roz_mcap_reader_t ROZ_PRIVATE(r);
    roz_record_run_t  ROZ_PRIVATE(run);
    int               ROZ_PRIVATE(have_tick);
    roz_record_t      ROZ_PRIVATE(tick);          /* being assembled */
    uint64_t          ROZ_PRIVATE(tick_offset);
    double           *ROZ_PRIVATE(state), *ROZ_PRIVATE(inputs), *ROZ_PRIVATE(target),
                     *ROZ_PRIVATE(applied); /* n_states, n_inputs, n_commands, n_commands */
    uint32_t          ROZ_PRIVATE(parts);         /* which of state/inputs/target/applied the tick has */
    char              ROZ_PRIVATE(fault_message)[256];
    uint64_t          ROZ_PRIVATE(controller_hash_seen);
    roz_mcap_message_t ROZ_PRIVATE(pending);      /* a /roz/tick read ahead */
    int               ROZ_PRIVATE(have_pending);
    roz_stages_config_t ROZ_PRIVATE(stages);      /* /roz/deploy's; stand in stand */
    double           *ROZ_PRIVATE(stand);         /* n_commands */
    int               ROZ_PRIVATE(has_stages);
    int32_t           ROZ_PRIVATE(stage_now);     /* the stage as of the last /roz/stage */
} roz_record_reader_t;

/**
 * @brief Open a recording and read its /roz/run message.
 * @retval ROZ_OK, ROZ_EIO, ROZ_ENOMEM, ROZ_EINVAL (err names the file, the
 *         offset and what is wrong: not MCAP, a CRC mismatch, no /roz/run
 *         first, a message of the wrong size)
 * Context: a non-real-time thread; allocates.
 */
ROZ_NODISCARD int roz_record_reader_open(roz_record_reader_t *rd, const char *path, char *err,
                                         size_t errlen);

/** @brief The run's account. Context: as roz_record_reader_open(). */
const roz_record_run_t *roz_record_reader_run(const roz_record_reader_t *rd);

/** @brief The recording's deploy sequence (/roz/deploy: its stand, move
 *  time, stop damping and inputs), or NULL: the run had none. Not checked
 *  against a manifest (roz_runtime_stages_set() does that). Context: as
 *  roz_record_reader_open(). */
const roz_stages_config_t *roz_record_reader_stages(const roz_record_reader_t *rd);

/**
 * @brief The next recorded tick, with its state, targets and applied
 *        commands (pointers valid until the next call), and its stage (the
 *        last /roz/stage's; zero before any in a run with a sequence).
 * @param[out] offset  where the tick's /roz/tick message is in the file
 *                     (its chunk's offset); may be NULL
 * @retval 1 a tick; 0 the end (rd->r.warning says when the file was cut
 *         short); ROZ_EINVAL a corrupt file (err names the offset)
 * Context: as roz_record_reader_open().
 */
int roz_record_reader_next(roz_record_reader_t *rd, roz_record_t *out, uint64_t *offset,
                           char *err, size_t errlen);

/** @brief Where a file cut short ends ("" for a complete file, or before
 *  the end was reached). Context: as roz_record_reader_open(). */
const char *roz_record_reader_warning(const roz_record_reader_t *rd);

/** @brief Free; idempotent. Context: as roz_record_reader_open(). */
void roz_record_reader_close(roz_record_reader_t *rd);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_RECORD_FILE_H */
