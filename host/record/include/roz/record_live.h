/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/record_live.h
 * @brief A run's recording streamed live to a viewer through a pipe or a
 *        FIFO (host builds; docs/live.md): the MCAP of roz/record_file.h,
 *        one chunk per tick, written without ever waiting for the reader.
 *
 * The pipe is written non-blocking; each tick's chunk goes into a bounded
 * queue whole or is dropped and counted (the viewer is slow, stalled or
 * gone), so a viewer slows neither the tick nor the drain that feeds a file
 * recording beside it. roz_record_live_flush() after each drain writes what
 * the pipe takes. test/record/test_record_live.c and test/live/test_live.py
 * hold these rules. A write to a pipe whose reader has gone raises SIGPIPE:
 * the application ignores it (rozrun does); the stream then ends and the
 * ticks after it count as dropped.
 */
#ifndef ROZ_RECORD_LIVE_H
#define ROZ_RECORD_LIVE_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/private.h"
#include "roz/record_file.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Bytes a live stream queues for a slow reader (beside the pipe's own). */
#define ROZ_RECORD_LIVE_QUEUE_BYTES (1u << 20)
/** Ticks it queues. */
#define ROZ_RECORD_LIVE_QUEUE_TICKS 4096u

/** A live stream. Fields are private to record_live.c. */
typedef struct roz_record_live {
    roz_record_file_t ROZ_PRIVATE(f);
    const char       *ROZ_PRIVATE(path);
    int               ROZ_PRIVATE(fd);
    unsigned char    *ROZ_PRIVATE(q);          /* queued bytes: [q_head, q_len) */
    size_t            ROZ_PRIVATE(q_head), ROZ_PRIVATE(q_len);
    unsigned char    *ROZ_PRIVATE(one);        /* the chunk being encoded (the sink's) */
    size_t            ROZ_PRIVATE(one_len), ROZ_PRIVATE(one_cap);
    uint32_t         *ROZ_PRIVATE(ent);        /* queued pieces: length, top bit a tick */
    uint32_t          ROZ_PRIVATE(ent_head), ROZ_PRIVATE(ent_n);
    size_t            ROZ_PRIVATE(ent_done);   /* bytes of the first piece written */
    uint64_t          ROZ_PRIVATE(ticks), ROZ_PRIVATE(sent), ROZ_PRIVATE(dropped);
    int               ROZ_PRIVATE(gone);       /* the reader went away (or a write failed) */
    int               ROZ_PRIVATE(lost_start); /* the stream's start could not be queued */
    char              ROZ_PRIVATE(error)[192];
} roz_record_live_t;

/**
 * @brief Open @p path for a live stream and queue the stream's start (the
 *        MCAP header, the schemas and channels of the recording, /roz/run).
 *        @p path is a FIFO or a pipe (/dev/fd/N) with a reader already on
 *        it, or a regular file (created).
 * @param[in] rec  the runtime's recorder; records reach the stream through
 *                 roz_record_live_put() from the caller's drain
 * @retval ROZ_OK, ROZ_EIO (err names the path: cannot open, no reader on the
 *         FIFO yet), ROZ_ENOMEM, ROZ_EINVAL (@p path "-": standard output
 *         is not taken, it carries the application's own output)
 * Context: start-up, a non-real-time thread; allocates.
 */
ROZ_NODISCARD int roz_record_live_open(roz_record_live_t *l, const char *path,
                                       const roz_runtime_t *rt, roz_recorder_t *rec,
                                       const roz_record_file_options_t *opt, char *err,
                                       size_t errlen);

/** @brief Encode one drained record and queue it, or drop it when the queue
 *  has no room. Context: the recorder's consumer thread. */
void roz_record_live_put(roz_record_live_t *l, const roz_record_t *r);

/** @brief Write what the pipe takes now, without waiting. Context: as
 *  roz_record_live_put(), after each drain. */
void roz_record_live_flush(roz_record_live_t *l);

/**
 * @brief End the stream (its data end, footer and magic queued), wait at most
 *        @p wait_ms for the reader to take what is queued, then close; what
 *        it did not take counts as dropped.
 * Context: as roz_record_live_put(), after the tick stopped.
 */
void roz_record_live_close(roz_record_live_t *l, unsigned wait_ms);

/** @brief Ticks put, sent whole to the reader, and dropped. Context: as
 *  roz_record_live_put(). */
uint64_t roz_record_live_ticks(const roz_record_live_t *l);
uint64_t roz_record_live_sent(const roz_record_live_t *l);
uint64_t roz_record_live_dropped(const roz_record_live_t *l);

/** @brief Why the stream ended early ("" it did not): the viewer went
 *  away, a write failed, it was still behind when the stream closed. Context: as
 *  roz_record_live_put(). */
const char *roz_record_live_error(const roz_record_live_t *l);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_RECORD_LIVE_H */
