/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/mcap.h
 * @brief A small MCAP writer and reader (host builds: stdio and the heap, at
 *        open and while writing, never in a tick).
 *
 * MCAP (format version 0) is the container ROS 2 bags, Foxglove and many
 * robotics tools read. This writer puts schemas, channels and messages in
 * chunks (zstd-compressed when asked), each followed by its message
 * indexes, a chunk closed only at a boundary its caller marks; the summary
 * repeats the schemas and channels and holds the statistics and a chunk
 * index, with summary offsets; the data section and the summary carry their
 * CRC-32, and every chunk the CRC of its records. The reader is what replay
 * needs: the messages in file order, every chunk's CRC checked, and every
 * error naming the byte offset at fault. It reads one record at a time and
 * refuses any record, and any chunk's records once decompressed, larger
 * than ROZ_MCAP_MAX_RECORD before it allocates for it (docs/recording-format.md).
 */
#ifndef ROZ_MCAP_H
#define ROZ_MCAP_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "roz/error.h"
#include "roz/private.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Channels (and schemas) one file may have. */
#define ROZ_MCAP_MAX_CHANNELS 16

/** The largest record (and chunk, decompressed) the reader takes and the
 *  writer writes, in bytes: 16 MiB (roz's chunks are 64 KiB and a tick). */
#define ROZ_MCAP_MAX_RECORD (16ul * 1024ul * 1024ul)

/** Chunk compression (roz_mcap_set_compression()). */
enum {
    ROZ_MCAP_COMPRESS_NONE = 0,
    ROZ_MCAP_COMPRESS_ZSTD = 1, /**< zstd, level 1 (built with Debian's libzstd) */
};

/** Where a stream's bytes go (roz_mcap_open_stream()): all @p n bytes, or
 *  non-zero when it cannot take them (the writer then fails). */
typedef int (*roz_mcap_sink_fn)(void *ctx, const void *data, size_t n);

/** A writer. Fields are private to mcap.c. */
typedef struct roz_mcap_writer {
    FILE          *ROZ_PRIVATE(out);
    roz_mcap_sink_fn ROZ_PRIVATE(sink);      /* a stream's (roz_mcap_open_stream()), else NULL */
    void          *ROZ_PRIVATE(sink_ctx);
    const char    *ROZ_PRIVATE(path);
    uint64_t       ROZ_PRIVATE(offset);      /* bytes written */
    uint32_t       ROZ_PRIVATE(data_crc);    /* CRC-32 state of the data section so far */
    unsigned char *ROZ_PRIVATE(chunk);       /* records of the open chunk */
    size_t         ROZ_PRIVATE(chunk_len), ROZ_PRIVATE(chunk_cap), ROZ_PRIVATE(chunk_target);
    uint64_t       ROZ_PRIVATE(chunk_start), ROZ_PRIVATE(chunk_end); /* message times of the open chunk */
    uint64_t       ROZ_PRIVATE(chunk_messages);
    /* per channel: the open chunk's message index (time, offset pairs) */
    uint64_t      *ROZ_PRIVATE(index)[ROZ_MCAP_MAX_CHANNELS + 1];
    size_t         ROZ_PRIVATE(index_len)[ROZ_MCAP_MAX_CHANNELS + 1], ROZ_PRIVATE(index_cap)[ROZ_MCAP_MAX_CHANNELS + 1];
    /* the summary: schema and channel records as written, chunk indexes */
    unsigned char *ROZ_PRIVATE(schemas), *ROZ_PRIVATE(channels), *ROZ_PRIVATE(chunk_indexes);
    size_t         ROZ_PRIVATE(schemas_len), ROZ_PRIVATE(channels_len), ROZ_PRIVATE(chunk_indexes_len);
    size_t         ROZ_PRIVATE(schemas_cap), ROZ_PRIVATE(channels_cap), ROZ_PRIVATE(chunk_indexes_cap);
    uint16_t       ROZ_PRIVATE(n_schemas), ROZ_PRIVATE(n_channels);
    uint32_t       ROZ_PRIVATE(n_chunks);
    uint64_t       ROZ_PRIVATE(n_messages), ROZ_PRIVATE(first_time), ROZ_PRIVATE(last_time);
    uint64_t       ROZ_PRIVATE(channel_messages)[ROZ_MCAP_MAX_CHANNELS + 1];
    uint32_t       ROZ_PRIVATE(sequence)[ROZ_MCAP_MAX_CHANNELS + 1];
    int            ROZ_PRIVATE(compression);
    void          *ROZ_PRIVATE(zctx);        /* zstd's context, made at the first chunk */
    unsigned char *ROZ_PRIVATE(zbuf);        /* a compressed chunk */
    size_t         ROZ_PRIVATE(zbuf_cap);
    char           ROZ_PRIVATE(error)[192]; /* the first error, "" none */
} roz_mcap_writer_t;

/**
 * @brief Create @p path and write the magic and the header (profile "ros2").
 * @param[in] chunk_bytes  a chunk is closed at the first roz_mcap_boundary()
 *                         once its records pass this size (0: 1 MiB)
 * @retval ROZ_OK    open
 * @retval ROZ_EIO   the file could not be created (w->error says why)
 * @retval ROZ_ENOMEM
 * Context: a non-real-time thread.
 */
ROZ_NODISCARD int roz_mcap_open(roz_mcap_writer_t *w, const char *path, const char *library,
                                size_t chunk_bytes);

/**
 * @brief Start a stream (a pipe to a live viewer, docs/live.md): the magic
 *        and the header go to @p sink now, every record after them as it is
 *        made. A stream keeps no indexes: its chunks have no message indexes,
 *        roz_mcap_close() writes the data end (CRC 0: a stream may lose whole
 *        chunks on the way), a footer that says there is no summary, and the
 *        magic. Its memory is the open chunk's, whatever the length of the run.
 * @param[in] name  names the stream in w->error
 * @retval ROZ_OK, ROZ_EIO (the sink refused), ROZ_ENOMEM
 * Context: a non-real-time thread.
 */
ROZ_NODISCARD int roz_mcap_open_stream(roz_mcap_writer_t *w, const char *name,
                                       const char *library, size_t chunk_bytes,
                                       roz_mcap_sink_fn sink, void *ctx);

/** @brief Add a schema (encoding "ros2msg"): ids from 1, in order of the
 *  calls. @return the id, or 0 on error. Context: as roz_mcap_open(). */
uint16_t roz_mcap_schema(roz_mcap_writer_t *w, const char *name, const char *encoding,
                         const char *text);

/** @brief Add a channel on @p schema_id (message encoding "cdr"): ids from 1.
 *  @return the id, or 0 on error. Context: as roz_mcap_open(). */
uint16_t roz_mcap_channel(roz_mcap_writer_t *w, uint16_t schema_id, const char *topic,
                          const char *message_encoding);

/**
 * @brief Add one message (its bytes copied into the open chunk).
 * @retval ROZ_OK, ROZ_EINVAL (unknown channel), ROZ_EIO (w->error), ROZ_ENOMEM
 * @retval ROZ_ENOSPC the open chunk would pass ROZ_MCAP_MAX_RECORD (no
 *                    roz_mcap_boundary() for too long)
 * Context: as roz_mcap_open().
 */
ROZ_NODISCARD int roz_mcap_message(roz_mcap_writer_t *w, uint16_t channel, uint64_t log_time,
                                   uint64_t publish_time, const void *data, size_t len);

/**
 * @brief Mark a place where a chunk may end (after a tick's messages): the
 *        open chunk is written (compressed, when asked) if it passed
 *        chunk_bytes. Messages between two boundaries share one chunk, so
 *        chunks never overlap in time when each group has its own time.
 * @retval ROZ_OK, ROZ_EIO (w->error), ROZ_ENOMEM
 * Context: as roz_mcap_open().
 */
int roz_mcap_boundary(roz_mcap_writer_t *w);

/**
 * @brief Compress the chunks written from now on (ROZ_MCAP_COMPRESS_*).
 * @retval ROZ_OK, ROZ_ENOTSUP (built without zstd), ROZ_EINVAL
 * Context: as roz_mcap_open().
 */
int roz_mcap_set_compression(roz_mcap_writer_t *w, int compression);

/** @brief 1 when this build writes and reads @p compression. Context: any. */
int roz_mcap_compression_supported(int compression);

/**
 * @brief Close the last chunk, write the data end, the summary, its offsets,
 *        the footer and the magic; close the file; free. Idempotent.
 * @retval ROZ_OK  the file is complete
 * @retval ROZ_EIO a write failed, now or before (w->error says the first)
 * Context: as roz_mcap_open().
 */
int roz_mcap_close(roz_mcap_writer_t *w);

/** One message as the reader hands it out (valid until the next call). */
typedef struct roz_mcap_message {
    uint16_t             channel;
    const char          *topic;     /**< the channel's topic */
    const char          *schema;    /**< its schema's name, "" none */
    uint32_t             sequence;
    uint64_t             log_time, publish_time;
    const unsigned char *data;
    size_t               len;
    uint64_t             offset;    /**< where the message record starts in the
                                         file (inside a chunk: the chunk's offset) */
} roz_mcap_message_t;

/** A reader: one record in memory at a time. Fields are private to mcap.c. */
typedef struct roz_mcap_reader {
    const char    *ROZ_PRIVATE(path);
    FILE          *ROZ_PRIVATE(in);
    uint64_t       ROZ_PRIVATE(size);       /* the file's */
    uint64_t       ROZ_PRIVATE(pos);        /* next record of the data section */
    unsigned char *ROZ_PRIVATE(rec), *ROZ_PRIVATE(chunk); /* a record; a chunk decompressed */
    size_t         ROZ_PRIVATE(rec_cap), ROZ_PRIVATE(chunk_cap);
    size_t         ROZ_PRIVATE(chunk_pos), ROZ_PRIVATE(chunk_end); /* inside a chunk's records */
    uint64_t       ROZ_PRIVATE(chunk_base); /* the chunk record's offset */
    const unsigned char *ROZ_PRIVATE(chunk_data); /* the chunk's records (rec or chunk) */
    int            ROZ_PRIVATE(in_chunk), ROZ_PRIVATE(done), ROZ_PRIVATE(complete);
    uint16_t       ROZ_PRIVATE(channel_schema)[ROZ_MCAP_MAX_CHANNELS + 1];
    char           ROZ_PRIVATE(topics)[ROZ_MCAP_MAX_CHANNELS + 1][64];
    char           ROZ_PRIVATE(schema_names)[ROZ_MCAP_MAX_CHANNELS + 1][64];
    char           ROZ_PRIVATE(warning)[192]; /* a file cut short: where, "" none */
} roz_mcap_reader_t;

/**
 * @brief Open @p path and check its magic, header and trailing magic. A
 *        file cut short
 *        (a recording whose writer died) is readable up to its last whole
 *        record; r->warning says where it ends.
 * @retval ROZ_OK     open
 * @retval ROZ_EIO    the file cannot be read (err says why)
 * @retval ROZ_EINVAL not an MCAP file, or a malformed header (err names the offset)
 * @retval ROZ_ENOMEM
 * Context: a non-real-time thread.
 */
ROZ_NODISCARD int roz_mcap_reader_open(roz_mcap_reader_t *r, const char *path, char *err,
                                       size_t errlen);

/**
 * @brief The next message in file order; schemas and channels on the way
 *        are taken in, every chunk's CRC is checked before its records are.
 * @retval 1          a message in @p out
 * @retval 0          the end of the data section (or of a file cut short)
 * @retval ROZ_EINVAL a malformed record or a CRC mismatch: @p err names the
 *                    file, the offset and what is wrong
 * Context: as roz_mcap_reader_open().
 */
int roz_mcap_reader_next(roz_mcap_reader_t *r, roz_mcap_message_t *out, char *err,
                         size_t errlen);

/** @brief Free; idempotent. Context: as roz_mcap_reader_open(). */
void roz_mcap_reader_close(roz_mcap_reader_t *r);

/** @brief CRC-32 (ISO-HDLC, as zlib) of @p len bytes, continued from @p crc
 *  (0 to start). Context: any. */
uint32_t roz_mcap_crc32(uint32_t crc, const void *data, size_t len);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_MCAP_H */
