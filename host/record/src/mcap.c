/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L /* fseeko, ftello: files past 2 GiB */
#define _FILE_OFFSET_BITS 64
/* MCAP, written and read from the public specification (format version 0):
 * records are an opcode byte, a little-endian u64 length and the content;
 * strings and byte arrays have a u32 length prefix, maps a u32 byte length. */
#include "roz/mcap.h"

#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#ifndef ROZ_MCAP_ZSTD
#define ROZ_MCAP_ZSTD 0 /* 1: chunks compressed and read with zstd (host/record/CMakeLists.txt) */
#endif
#if ROZ_MCAP_ZSTD
#include <zstd.h>
#endif

/* zstd's level for chunks: 1, its fastest; a G1's float64 channels shrink
 * about as much at level 3 for twice the time (bench/record) */
#define ROZ_MCAP_ZSTD_LEVEL 1

/* ---- types ------------------------------------------------------------------ */

enum {
    OP_HEADER = 0x01,
    OP_FOOTER = 0x02,
    OP_SCHEMA = 0x03,
    OP_CHANNEL = 0x04,
    OP_MESSAGE = 0x05,
    OP_CHUNK = 0x06,
    OP_MESSAGE_INDEX = 0x07,
    OP_CHUNK_INDEX = 0x08,
    OP_STATISTICS = 0x0B,
    OP_SUMMARY_OFFSET = 0x0E,
    OP_DATA_END = 0x0F,
};

static const unsigned char magic[8] = { 0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n' };

/* A growable byte buffer (host side: the heap, never in a tick). */
typedef struct {
    unsigned char **p;
    size_t         *len, *cap;
} buf_t;

/* ---- CRC-32 ----------------------------------------------------------------- */

/* CRC-32/ISO-HDLC (zlib's): reflected polynomial 0xEDB88320, one table
 * entry per byte value (const: no first-use race between two writers). */
static const uint32_t crc_table[256] = {
    0x00000000u, 0x77073096u, 0xee0e612cu, 0x990951bau, 0x076dc419u, 0x706af48fu,
    0xe963a535u, 0x9e6495a3u, 0x0edb8832u, 0x79dcb8a4u, 0xe0d5e91eu, 0x97d2d988u,
    0x09b64c2bu, 0x7eb17cbdu, 0xe7b82d07u, 0x90bf1d91u, 0x1db71064u, 0x6ab020f2u,
    0xf3b97148u, 0x84be41deu, 0x1adad47du, 0x6ddde4ebu, 0xf4d4b551u, 0x83d385c7u,
    0x136c9856u, 0x646ba8c0u, 0xfd62f97au, 0x8a65c9ecu, 0x14015c4fu, 0x63066cd9u,
    0xfa0f3d63u, 0x8d080df5u, 0x3b6e20c8u, 0x4c69105eu, 0xd56041e4u, 0xa2677172u,
    0x3c03e4d1u, 0x4b04d447u, 0xd20d85fdu, 0xa50ab56bu, 0x35b5a8fau, 0x42b2986cu,
    0xdbbbc9d6u, 0xacbcf940u, 0x32d86ce3u, 0x45df5c75u, 0xdcd60dcfu, 0xabd13d59u,
    0x26d930acu, 0x51de003au, 0xc8d75180u, 0xbfd06116u, 0x21b4f4b5u, 0x56b3c423u,
    0xcfba9599u, 0xb8bda50fu, 0x2802b89eu, 0x5f058808u, 0xc60cd9b2u, 0xb10be924u,
    0x2f6f7c87u, 0x58684c11u, 0xc1611dabu, 0xb6662d3du, 0x76dc4190u, 0x01db7106u,
    0x98d220bcu, 0xefd5102au, 0x71b18589u, 0x06b6b51fu, 0x9fbfe4a5u, 0xe8b8d433u,
    0x7807c9a2u, 0x0f00f934u, 0x9609a88eu, 0xe10e9818u, 0x7f6a0dbbu, 0x086d3d2du,
    0x91646c97u, 0xe6635c01u, 0x6b6b51f4u, 0x1c6c6162u, 0x856530d8u, 0xf262004eu,
    0x6c0695edu, 0x1b01a57bu, 0x8208f4c1u, 0xf50fc457u, 0x65b0d9c6u, 0x12b7e950u,
    0x8bbeb8eau, 0xfcb9887cu, 0x62dd1ddfu, 0x15da2d49u, 0x8cd37cf3u, 0xfbd44c65u,
    0x4db26158u, 0x3ab551ceu, 0xa3bc0074u, 0xd4bb30e2u, 0x4adfa541u, 0x3dd895d7u,
    0xa4d1c46du, 0xd3d6f4fbu, 0x4369e96au, 0x346ed9fcu, 0xad678846u, 0xda60b8d0u,
    0x44042d73u, 0x33031de5u, 0xaa0a4c5fu, 0xdd0d7cc9u, 0x5005713cu, 0x270241aau,
    0xbe0b1010u, 0xc90c2086u, 0x5768b525u, 0x206f85b3u, 0xb966d409u, 0xce61e49fu,
    0x5edef90eu, 0x29d9c998u, 0xb0d09822u, 0xc7d7a8b4u, 0x59b33d17u, 0x2eb40d81u,
    0xb7bd5c3bu, 0xc0ba6cadu, 0xedb88320u, 0x9abfb3b6u, 0x03b6e20cu, 0x74b1d29au,
    0xead54739u, 0x9dd277afu, 0x04db2615u, 0x73dc1683u, 0xe3630b12u, 0x94643b84u,
    0x0d6d6a3eu, 0x7a6a5aa8u, 0xe40ecf0bu, 0x9309ff9du, 0x0a00ae27u, 0x7d079eb1u,
    0xf00f9344u, 0x8708a3d2u, 0x1e01f268u, 0x6906c2feu, 0xf762575du, 0x806567cbu,
    0x196c3671u, 0x6e6b06e7u, 0xfed41b76u, 0x89d32be0u, 0x10da7a5au, 0x67dd4accu,
    0xf9b9df6fu, 0x8ebeeff9u, 0x17b7be43u, 0x60b08ed5u, 0xd6d6a3e8u, 0xa1d1937eu,
    0x38d8c2c4u, 0x4fdff252u, 0xd1bb67f1u, 0xa6bc5767u, 0x3fb506ddu, 0x48b2364bu,
    0xd80d2bdau, 0xaf0a1b4cu, 0x36034af6u, 0x41047a60u, 0xdf60efc3u, 0xa867df55u,
    0x316e8eefu, 0x4669be79u, 0xcb61b38cu, 0xbc66831au, 0x256fd2a0u, 0x5268e236u,
    0xcc0c7795u, 0xbb0b4703u, 0x220216b9u, 0x5505262fu, 0xc5ba3bbeu, 0xb2bd0b28u,
    0x2bb45a92u, 0x5cb36a04u, 0xc2d7ffa7u, 0xb5d0cf31u, 0x2cd99e8bu, 0x5bdeae1du,
    0x9b64c2b0u, 0xec63f226u, 0x756aa39cu, 0x026d930au, 0x9c0906a9u, 0xeb0e363fu,
    0x72076785u, 0x05005713u, 0x95bf4a82u, 0xe2b87a14u, 0x7bb12baeu, 0x0cb61b38u,
    0x92d28e9bu, 0xe5d5be0du, 0x7cdcefb7u, 0x0bdbdf21u, 0x86d3d2d4u, 0xf1d4e242u,
    0x68ddb3f8u, 0x1fda836eu, 0x81be16cdu, 0xf6b9265bu, 0x6fb077e1u, 0x18b74777u,
    0x88085ae6u, 0xff0f6a70u, 0x66063bcau, 0x11010b5cu, 0x8f659effu, 0xf862ae69u,
    0x616bffd3u, 0x166ccf45u, 0xa00ae278u, 0xd70dd2eeu, 0x4e048354u, 0x3903b3c2u,
    0xa7672661u, 0xd06016f7u, 0x4969474du, 0x3e6e77dbu, 0xaed16a4au, 0xd9d65adcu,
    0x40df0b66u, 0x37d83bf0u, 0xa9bcae53u, 0xdebb9ec5u, 0x47b2cf7fu, 0x30b5ffe9u,
    0xbdbdf21cu, 0xcabac28au, 0x53b39330u, 0x24b4a3a6u, 0xbad03605u, 0xcdd70693u,
    0x54de5729u, 0x23d967bfu, 0xb3667a2eu, 0xc4614ab8u, 0x5d681b02u, 0x2a6f2b94u,
    0xb40bbe37u, 0xc30c8ea1u, 0x5a05df1bu, 0x2d02ef8du,
};

uint32_t roz_mcap_crc32(uint32_t crc, const void *data, size_t len)
{
    const unsigned char *p = (const unsigned char *)data;
    crc = ~crc;
    for (size_t i = 0; i < len; i++)
        crc = crc_table[(crc ^ p[i]) & 0xFFu] ^ (crc >> 8);
    return ~crc;
}

/* ---- writer: encoding -------------------------------------------------------- */

static int grow(buf_t b, size_t more)
{
    if (*b.len + more <= *b.cap)
        return 0;
    size_t cap = *b.cap ? *b.cap : 256u;
    while (cap < *b.len + more)
        cap *= 2u;
    unsigned char *n = realloc(*b.p, cap);
    if (n == NULL)
        return -1;
    *b.p = n;
    *b.cap = cap;
    return 0;
}

static int put(buf_t b, const void *src, size_t n)
{
    if (grow(b, n) != 0)
        return -1;
    memcpy(*b.p + *b.len, src, n);
    *b.len += n;
    return 0;
}

static int put_u8(buf_t b, uint8_t v)
{
    return put(b, &v, 1);
}

static int put_le(buf_t b, uint64_t v, int bytes)
{
    unsigned char t[8];
    for (int i = 0; i < bytes; i++)
        t[i] = (unsigned char)(v >> (8 * i));
    return put(b, t, (size_t)bytes);
}

static int put_str(buf_t b, const char *s)
{
    size_t n = strlen(s);
    return put_le(b, n, 4) | put(b, s, n);
}

/* Opens a record: opcode and a length patched by rec_end(). */
static size_t rec_begin(buf_t b, uint8_t op)
{
    (void)put_u8(b, op);
    (void)put_le(b, 0, 8);
    return *b.len;
}

static void rec_end(buf_t b, size_t start)
{
    uint64_t n = *b.len - start;
    for (int i = 0; i < 8; i++)
        (*b.p)[start - 8 + (size_t)i] = (unsigned char)(n >> (8 * i));
}

static void fail(roz_mcap_writer_t *w, const char *what, int err)
{
    if (w->error[0] == '\0')
        snprintf(w->error, sizeof w->error, "%s: %s%s%s", w->path, what, err ? ": " : "",
                 err ? strerror(err) : "");
}

/* Writes bytes to the file, counting them into the data section's CRC. */
static int emit(roz_mcap_writer_t *w, const void *p, size_t n, int data_section)
{
    if (w->error[0] != '\0')
        return ROZ_EIO;
    if (w->sink != NULL) {
        if (n != 0 && w->sink(w->sink_ctx, p, n) != 0) {
            fail(w, "the stream took no more", 0);
            return ROZ_EIO;
        }
    } else if (n != 0 && fwrite(p, 1, n, w->out) != n) {
        fail(w, "write failed", errno);
        return ROZ_EIO;
    }
    if (data_section)
        w->data_crc = roz_mcap_crc32(w->data_crc, p, n);
    w->offset += n;
    return ROZ_OK;
}

/* ---- writer: chunks ---------------------------------------------------------- */

static buf_t chunk_buf(roz_mcap_writer_t *w)
{
    buf_t b = { &w->chunk, &w->chunk_len, &w->chunk_cap };
    return b;
}

/* Compresses the open chunk's records into w->zbuf (zstd, one frame that
 * states its content size). */
static int compress_chunk(roz_mcap_writer_t *w, size_t *out_len)
{
#if ROZ_MCAP_ZSTD
    size_t bound = ZSTD_compressBound(w->chunk_len);
    if (bound > w->zbuf_cap) {
        unsigned char *n = realloc(w->zbuf, bound);
        if (n == NULL)
            return ROZ_ENOMEM;
        w->zbuf = n;
        w->zbuf_cap = bound;
    }
    if (w->zctx == NULL && (w->zctx = ZSTD_createCCtx()) == NULL)
        return ROZ_ENOMEM;
    size_t z = ZSTD_compressCCtx(w->zctx, w->zbuf, bound, w->chunk, w->chunk_len,
                                 ROZ_MCAP_ZSTD_LEVEL);
    if (ZSTD_isError(z)) {
        if (w->error[0] == '\0')
            snprintf(w->error, sizeof w->error, "%s: zstd: %s", w->path, ZSTD_getErrorName(z));
        return ROZ_EIO;
    }
    *out_len = z;
    return ROZ_OK;
#else
    (void)w;
    (void)out_len;
    return ROZ_ENOTSUP;
#endif
}

/* Writes the open chunk and its message indexes; adds its chunk index. */
static int flush_chunk(roz_mcap_writer_t *w)
{
    unsigned char *rec = NULL;
    size_t len = 0, cap = 0;
    buf_t b = { &rec, &len, &cap };
    uint64_t chunk_start = w->offset, chunk_len;
    int rc = ROZ_OK;

    if (w->chunk_messages == 0)
        return ROZ_OK;
    /* the chunk: its records, compressed when asked (the CRC is theirs) */
    const unsigned char *body = w->chunk;
    size_t body_len = w->chunk_len;
    const char *compression = "";
    if (w->compression == ROZ_MCAP_COMPRESS_ZSTD) {
        rc = compress_chunk(w, &body_len);
        if (rc != ROZ_OK)
            return rc;
        body = w->zbuf;
        compression = "zstd";
    }
    size_t s = rec_begin(b, OP_CHUNK);
    int e = put_le(b, w->chunk_start, 8) | put_le(b, w->chunk_end, 8) |
            put_le(b, w->chunk_len, 8) |
            put_le(b, roz_mcap_crc32(0, w->chunk, w->chunk_len), 4) | put_str(b, compression) |
            put_le(b, body_len, 8) | put(b, body, body_len);
    rec_end(b, s);
    if (e != 0) {
        free(rec);
        return ROZ_ENOMEM;
    }
    rc = emit(w, rec, len, 1);
    chunk_len = len;
    /* its message indexes, and where each went */
    uint64_t index_at[ROZ_MCAP_MAX_CHANNELS + 1] = { 0 };
    uint64_t index_start = w->offset;
    for (uint16_t c = 1; c <= w->n_channels && rc == ROZ_OK && w->sink == NULL; c++) {
        if (w->index_len[c] == 0)
            continue;
        len = 0;
        s = rec_begin(b, OP_MESSAGE_INDEX);
        e = put_le(b, c, 2) | put_le(b, w->index_len[c] * 8u, 4);
        for (size_t i = 0; i < w->index_len[c]; i++)
            e |= put_le(b, w->index[c][i], 8);
        rec_end(b, s);
        if (e != 0) {
            rc = ROZ_ENOMEM;
            break;
        }
        index_at[c] = w->offset;
        rc = emit(w, rec, len, 1);
    }
    uint64_t index_len = w->offset - index_start;
    /* the chunk index, for the summary (a stream has none) */
    if (rc == ROZ_OK && w->sink == NULL) {
        buf_t ci = { &w->chunk_indexes, &w->chunk_indexes_len, &w->chunk_indexes_cap };
        uint32_t n_idx = 0;
        for (uint16_t c = 1; c <= w->n_channels; c++)
            n_idx += w->index_len[c] != 0;
        s = rec_begin(ci, OP_CHUNK_INDEX);
        e = put_le(ci, w->chunk_start, 8) | put_le(ci, w->chunk_end, 8) |
            put_le(ci, chunk_start, 8) | put_le(ci, chunk_len, 8) | put_le(ci, n_idx * 10u, 4);
        for (uint16_t c = 1; c <= w->n_channels; c++) {
            if (w->index_len[c] != 0)
                e |= put_le(ci, c, 2) | put_le(ci, index_at[c], 8);
        }
        e |= put_le(ci, index_len, 8) | put_str(ci, compression) | put_le(ci, body_len, 8) |
             put_le(ci, w->chunk_len, 8);
        rec_end(ci, s);
        if (e != 0)
            rc = ROZ_ENOMEM;
        w->n_chunks++;
    }
    free(rec);
    w->chunk_len = 0;
    w->chunk_messages = 0;
    for (uint16_t c = 1; c <= w->n_channels; c++)
        w->index_len[c] = 0;
    return rc;
}

/* ---- writer: public ---------------------------------------------------------- */

/* The magic and the header, once w->out or w->sink is set. */
static int write_start(roz_mcap_writer_t *w, const char *library)
{
    unsigned char *rec = NULL;
    size_t len = 0, cap = 0;
    buf_t b = { &rec, &len, &cap };

    size_t s = rec_begin(b, OP_HEADER);
    int e = put_str(b, "ros2") | put_str(b, library);
    rec_end(b, s);
    if (e != 0) {
        free(rec);
        return ROZ_ENOMEM;
    }
    int rc = emit(w, magic, sizeof magic, 1);
    if (rc == ROZ_OK)
        rc = emit(w, rec, len, 1);
    free(rec);
    return rc;
}

int roz_mcap_open(roz_mcap_writer_t *w, const char *path, const char *library,
                  size_t chunk_bytes)
{
    memset(w, 0, sizeof *w);
    w->path = path;
    w->chunk_target = chunk_bytes != 0 ? chunk_bytes : (size_t)1 << 20;
    w->out = fopen(path, "wb");
    if (w->out == NULL) {
        fail(w, "cannot create", errno);
        return ROZ_EIO;
    }
    return write_start(w, library);
}

int roz_mcap_open_stream(roz_mcap_writer_t *w, const char *name, const char *library,
                         size_t chunk_bytes, roz_mcap_sink_fn sink, void *ctx)
{
    memset(w, 0, sizeof *w);
    w->path = name;
    w->chunk_target = chunk_bytes != 0 ? chunk_bytes : (size_t)1 << 20;
    w->sink = sink;
    w->sink_ctx = ctx;
    return write_start(w, library);
}

uint16_t roz_mcap_schema(roz_mcap_writer_t *w, const char *name, const char *encoding,
                         const char *text)
{
    buf_t sb = { &w->schemas, &w->schemas_len, &w->schemas_cap };
    size_t before = w->schemas_len;

    if (w->n_schemas >= ROZ_MCAP_MAX_CHANNELS)
        return 0;
    uint16_t id = (uint16_t)(w->n_schemas + 1u);
    size_t s = rec_begin(sb, OP_SCHEMA);
    int e = put_le(sb, id, 2) | put_str(sb, name) | put_str(sb, encoding) | put_str(sb, text);
    rec_end(sb, s);
    /* in the chunk too: a reader that reads the data section alone sees it */
    if (e != 0 || put(chunk_buf(w), w->schemas + before, w->schemas_len - before) != 0)
        return 0;
    w->n_schemas = id;
    return id;
}

uint16_t roz_mcap_channel(roz_mcap_writer_t *w, uint16_t schema_id, const char *topic,
                          const char *message_encoding)
{
    buf_t cb = { &w->channels, &w->channels_len, &w->channels_cap };
    size_t before = w->channels_len;

    if (w->n_channels >= ROZ_MCAP_MAX_CHANNELS || schema_id > w->n_schemas)
        return 0;
    uint16_t id = (uint16_t)(w->n_channels + 1u);
    size_t s = rec_begin(cb, OP_CHANNEL);
    int e = put_le(cb, id, 2) | put_le(cb, schema_id, 2) | put_str(cb, topic) |
            put_str(cb, message_encoding) | put_le(cb, 0, 4);
    rec_end(cb, s);
    if (e != 0 || put(chunk_buf(w), w->channels + before, w->channels_len - before) != 0)
        return 0;
    w->n_channels = id;
    return id;
}

int roz_mcap_message(roz_mcap_writer_t *w, uint16_t channel, uint64_t log_time,
                     uint64_t publish_time, const void *data, size_t len)
{
    buf_t b = chunk_buf(w);

    if (channel == 0 || channel > w->n_channels)
        return ROZ_EINVAL;
    if (w->error[0] != '\0')
        return ROZ_EIO;
    /* a chunk no reader refuses: its records stay within ROZ_MCAP_MAX_RECORD */
    if (w->chunk_len + 64u > ROZ_MCAP_MAX_RECORD ||
        len > ROZ_MCAP_MAX_RECORD - 64u - w->chunk_len)
        return ROZ_ENOSPC;
    /* the message index: (log time, offset in the chunk's records); none
     * in a stream */
    if (w->sink == NULL) {
        if (w->index_len[channel] + 2u > w->index_cap[channel]) {
            size_t cap = w->index_cap[channel] ? 2u * w->index_cap[channel] : 512u;
            uint64_t *n = realloc(w->index[channel], cap * sizeof n[0]);
            if (n == NULL)
                return ROZ_ENOMEM;
            w->index[channel] = n;
            w->index_cap[channel] = cap;
        }
        w->index[channel][w->index_len[channel]++] = log_time;
        w->index[channel][w->index_len[channel]++] = w->chunk_len;
    }
    size_t s = rec_begin(b, OP_MESSAGE);
    int e = put_le(b, channel, 2) | put_le(b, w->sequence[channel]++, 4) |
            put_le(b, log_time, 8) | put_le(b, publish_time, 8) | put(b, data, len);
    rec_end(b, s);
    if (e != 0)
        return ROZ_ENOMEM;
    if (w->chunk_messages == 0 || log_time < w->chunk_start)
        w->chunk_start = w->chunk_messages == 0 ? log_time : w->chunk_start;
    if (w->chunk_messages == 0 || log_time > w->chunk_end)
        w->chunk_end = log_time;
    if (w->n_messages == 0 || log_time < w->first_time)
        w->first_time = log_time;
    if (w->n_messages == 0 || log_time > w->last_time)
        w->last_time = log_time;
    w->chunk_messages++;
    w->n_messages++;
    w->channel_messages[channel]++;
    return ROZ_OK;
}

int roz_mcap_boundary(roz_mcap_writer_t *w)
{
    if ((w->out == NULL && w->sink == NULL) || w->error[0] != '\0')
        return ROZ_EIO;
    if (w->chunk_len >= w->chunk_target)
        return flush_chunk(w);
    return ROZ_OK;
}

int roz_mcap_set_compression(roz_mcap_writer_t *w, int compression)
{
    if (compression == ROZ_MCAP_COMPRESS_NONE || (compression == ROZ_MCAP_COMPRESS_ZSTD &&
                                                  roz_mcap_compression_supported(compression))) {
        w->compression = compression;
        return ROZ_OK;
    }
    return compression == ROZ_MCAP_COMPRESS_ZSTD ? ROZ_ENOTSUP : ROZ_EINVAL;
}

int roz_mcap_compression_supported(int compression)
{
    return compression == ROZ_MCAP_COMPRESS_NONE ||
           (compression == ROZ_MCAP_COMPRESS_ZSTD && ROZ_MCAP_ZSTD);
}

/* One summary group: its records, and a summary offset pointing at them. */
static int summary_group(roz_mcap_writer_t *w, buf_t offsets, uint8_t op, const void *p,
                         size_t n)
{
    if (n == 0)
        return ROZ_OK;
    size_t s = rec_begin(offsets, OP_SUMMARY_OFFSET);
    int e = put_u8(offsets, op) | put_le(offsets, w->offset, 8) | put_le(offsets, n, 8);
    rec_end(offsets, s);
    if (e != 0)
        return ROZ_ENOMEM;
    return emit(w, p, n, 0);
}

/* Frees what a writer holds. */
static void free_writer(roz_mcap_writer_t *w)
{
    free(w->chunk);
    free(w->schemas);
    free(w->channels);
    free(w->chunk_indexes);
    free(w->zbuf);
#if ROZ_MCAP_ZSTD
    ZSTD_freeCCtx(w->zctx);
#endif
    w->zbuf = NULL;
    w->zctx = NULL;
    for (int c = 0; c <= ROZ_MCAP_MAX_CHANNELS; c++)
        free(w->index[c]);
    w->chunk = w->schemas = w->channels = w->chunk_indexes = NULL;
    for (int c = 0; c <= ROZ_MCAP_MAX_CHANNELS; c++)
        w->index[c] = NULL;
}

/* A stream's end: the data end (CRC 0, "not computed"), a footer with no
 * summary (both offsets and the CRC 0), the magic. */
static int close_stream(roz_mcap_writer_t *w, int rc)
{
    /* data end: opcode, length 4, CRC; footer: opcode, length 20, 20 zeros */
    unsigned char end[13 + 29] = { 0 };
    end[0] = OP_DATA_END;
    end[1] = 4;
    end[13] = OP_FOOTER;
    end[14] = 20;
    if (rc == ROZ_OK)
        rc = emit(w, end, sizeof end, 0);
    if (rc == ROZ_OK)
        rc = emit(w, magic, sizeof magic, 0);
    w->sink = NULL;
    free_writer(w);
    if (rc != ROZ_OK && w->error[0] == '\0')
        fail(w, rc == ROZ_ENOMEM ? "out of memory" : "write failed", 0);
    return rc == ROZ_OK ? ROZ_OK : ROZ_EIO;
}

int roz_mcap_close(roz_mcap_writer_t *w)
{
    unsigned char *rec = NULL, *offs = NULL;
    size_t len = 0, cap = 0, olen = 0, ocap = 0;
    buf_t b = { &rec, &len, &cap }, ob = { &offs, &olen, &ocap };
    int rc = ROZ_OK;

    if (w->out == NULL && w->sink == NULL)
        return w->error[0] != '\0' ? ROZ_EIO : ROZ_OK;
    rc = flush_chunk(w);
    if (w->sink != NULL)
        return close_stream(w, rc);
    /* the data end, with the data section's CRC */
    size_t s = rec_begin(b, OP_DATA_END);
    (void)put_le(b, w->data_crc, 4);
    rec_end(b, s);
    if (rc == ROZ_OK)
        rc = emit(w, rec, len, 0);
    /* the summary: CRC from its first byte through the footer's offsets */
    uint64_t summary_start = w->offset;
    long summary_pos = ftell(w->out);
    if (rc == ROZ_OK)
        rc = summary_group(w, ob, OP_SCHEMA, w->schemas, w->schemas_len);
    if (rc == ROZ_OK)
        rc = summary_group(w, ob, OP_CHANNEL, w->channels, w->channels_len);
    len = 0;
    s = rec_begin(b, OP_STATISTICS);
    int e = put_le(b, w->n_messages, 8) | put_le(b, w->n_schemas, 2) |
            put_le(b, w->n_channels, 4) | put_le(b, 0, 4) | put_le(b, 0, 4) |
            put_le(b, w->n_chunks, 4) | put_le(b, w->first_time, 8) |
            put_le(b, w->last_time, 8) | put_le(b, (uint64_t)w->n_channels * 10u, 4);
    for (uint16_t c = 1; c <= w->n_channels; c++)
        e |= put_le(b, c, 2) | put_le(b, w->channel_messages[c], 8);
    rec_end(b, s);
    if (e != 0 && rc == ROZ_OK)
        rc = ROZ_ENOMEM;
    if (rc == ROZ_OK)
        rc = summary_group(w, ob, OP_STATISTICS, rec, len);
    if (rc == ROZ_OK)
        rc = summary_group(w, ob, OP_CHUNK_INDEX, w->chunk_indexes, w->chunk_indexes_len);
    uint64_t offsets_start = w->offset;
    if (rc == ROZ_OK)
        rc = emit(w, offs, olen, 0);
    /* the footer */
    len = 0;
    /* summary start u64, summary offset start u64, summary CRC u32: 20 bytes,
     * the CRC covering everything from the summary's start to just before it */
    (void)put_u8(b, OP_FOOTER);
    (void)put_le(b, 20, 8);
    (void)put_le(b, summary_start, 8);
    (void)put_le(b, offsets_start, 8);
    if (rc == ROZ_OK)
        rc = emit(w, rec, len, 0); /* without its CRC field yet */
    /* the summary CRC: re-read what was written since summary_start */
    uint32_t crc = 0;
    if (rc == ROZ_OK && fflush(w->out) == 0) {
        FILE *in = fopen(w->path, "rb");
        if (in == NULL || fseek(in, summary_pos, SEEK_SET) != 0) {
            fail(w, "cannot re-read the summary", errno);
            rc = ROZ_EIO;
        } else {
            unsigned char tmp[4096];
            size_t n;
            while ((n = fread(tmp, 1, sizeof tmp, in)) > 0)
                crc = roz_mcap_crc32(crc, tmp, n);
        }
        if (in != NULL)
            fclose(in);
    }
    len = 0;
    (void)put_le(b, crc, 4);
    (void)put(b, magic, sizeof magic);
    if (rc == ROZ_OK)
        rc = emit(w, rec, len, 0);
    if (fclose(w->out) != 0 && rc == ROZ_OK) {
        fail(w, "closing", errno);
        rc = ROZ_EIO;
    }
    w->out = NULL;
    free(rec);
    free(offs);
    free_writer(w);
    if (rc != ROZ_OK && w->error[0] == '\0')
        fail(w, rc == ROZ_ENOMEM ? "out of memory" : "write failed", 0);
    return rc == ROZ_OK ? ROZ_OK : ROZ_EIO;
}

/* ---- reader ------------------------------------------------------------------ */

__attribute__((format(printf, 5, 6)))
static void rerr(const roz_mcap_reader_t *r, char *err, size_t errlen, uint64_t at,
                 const char *fmt, ...)
{
    char what[160];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    if (err != NULL && errlen > 0)
        snprintf(err, errlen, "%s: at offset %llu: %s", r->path, (unsigned long long)at, what);
}

static uint64_t get_le(const unsigned char *p, int bytes)
{
    uint64_t v = 0;
    for (int i = 0; i < bytes; i++)
        v |= (uint64_t)p[i] << (8 * i);
    return v;
}

/* A string field at *at within [.., end): copied (truncated) into dst. */
static int get_str(const unsigned char *p, size_t *at, size_t end, char *dst, size_t cap)
{
    if (*at + 4u > end)
        return -1;
    size_t n = (size_t)get_le(p + *at, 4);
    *at += 4u;
    if (n > end - *at)
        return -1;
    size_t k = n < cap - 1u ? n : cap - 1u;
    memcpy(dst, p + *at, k);
    dst[k] = '\0';
    *at += n;
    return 0;
}

/* Reads @p n bytes at @p at into *dst (grown as needed, never past
 * ROZ_MCAP_MAX_RECORD: the caller checked n against it). */
static int read_at(roz_mcap_reader_t *r, uint64_t at, size_t n, unsigned char **dst,
                   size_t *cap)
{
    if (n > *cap) {
        unsigned char *p = realloc(*dst, n);
        if (p == NULL)
            return ROZ_ENOMEM;
        *dst = p;
        *cap = n;
    }
    if (fseeko(r->in, (off_t)at, SEEK_SET) != 0 || fread(*dst, 1, n, r->in) != n)
        return ROZ_EIO;
    return ROZ_OK;
}

int roz_mcap_reader_open(roz_mcap_reader_t *r, const char *path, char *err, size_t errlen)
{
    unsigned char head[17], tail[8];

    memset(r, 0, sizeof *r);
    r->path = path;
    r->in = fopen(path, "rb");
    if (r->in == NULL) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return ROZ_EIO;
    }
    off_t size;
    if (fseeko(r->in, 0, SEEK_END) != 0 || (size = ftello(r->in)) < 0) {
        snprintf(err, errlen, "%s: cannot read: %s", path, strerror(errno));
        roz_mcap_reader_close(r);
        return ROZ_EIO;
    }
    r->size = (uint64_t)size;
    size_t got = 0;
    if (fseeko(r->in, 0, SEEK_SET) == 0)
        got = fread(head, 1, sizeof head, r->in);
    if (got < sizeof magic || memcmp(head, magic, sizeof magic) != 0) {
        rerr(r, err, errlen, 0, "not an MCAP file (no MCAP magic)");
        roz_mcap_reader_close(r);
        return ROZ_EINVAL;
    }
    uint64_t n = got == sizeof head ? get_le(head + 9, 8) : 0;
    if (got < sizeof head || head[8] != OP_HEADER || n > r->size - 17u ||
        n > ROZ_MCAP_MAX_RECORD) {
        rerr(r, err, errlen, 8, "no complete header record");
        roz_mcap_reader_close(r);
        return ROZ_EINVAL;
    }
    r->pos = 17u + n;
    r->complete = r->size >= 2u * sizeof magic + 17u &&
                  fseeko(r->in, (off_t)(r->size - sizeof tail), SEEK_SET) == 0 &&
                  fread(tail, 1, sizeof tail, r->in) == sizeof tail &&
                  memcmp(tail, magic, sizeof magic) == 0;
    return ROZ_OK;
}

/* Takes a schema or channel record in (content at p, n bytes). */
static int take_definition(roz_mcap_reader_t *r, uint8_t op, const unsigned char *p, size_t n)
{
    size_t at = 0;
    if (op == OP_SCHEMA) {
        if (n < 2u)
            return -1;
        uint16_t id = (uint16_t)get_le(p, 2);
        at = 2;
        char name[64];
        if (get_str(p, &at, n, name, sizeof name) != 0)
            return -1;
        if (id >= 1u && id <= ROZ_MCAP_MAX_CHANNELS)
            memcpy(r->schema_names[id], name, sizeof name);
    } else if (op == OP_CHANNEL) {
        if (n < 4u)
            return -1;
        uint16_t id = (uint16_t)get_le(p, 2), schema = (uint16_t)get_le(p + 2, 2);
        at = 4;
        char topic[64];
        if (get_str(p, &at, n, topic, sizeof topic) != 0)
            return -1;
        if (id >= 1u && id <= ROZ_MCAP_MAX_CHANNELS) {
            memcpy(r->topics[id], topic, sizeof topic);
            r->channel_schema[id] = schema;
        }
    }
    return 0;
}

/* A chunk record at @p at (content p, n bytes, in r->rec): its records
 * (decompressed into r->chunk when compressed, never past the limit) checked
 * against its CRC, then read one by one by roz_mcap_reader_next(). */
static int open_chunk(roz_mcap_reader_t *r, uint64_t at, const unsigned char *p, size_t n,
                      char *err, size_t errlen)
{
    if (n < 8u * 3u + 4u + 4u + 8u) {
        rerr(r, err, errlen, at, "a chunk record of %lu bytes", (unsigned long)n);
        return ROZ_EINVAL;
    }
    uint64_t usize = get_le(p + 16, 8);
    uint32_t crc = (uint32_t)get_le(p + 24, 4);
    size_t q = 28;
    char comp[32];
    if (get_str(p, &q, n, comp, sizeof comp) != 0 || q + 8u > n) {
        rerr(r, err, errlen, at, "a malformed chunk record");
        return ROZ_EINVAL;
    }
    uint64_t clen = get_le(p + q, 8);
    q += 8u;
    if (clen > n - q) {
        rerr(r, err, errlen, at, "a chunk whose records (%llu bytes) do not fit it",
             (unsigned long long)clen);
        return ROZ_EINVAL;
    }
    if (usize > ROZ_MCAP_MAX_RECORD) {
        rerr(r, err, errlen, at, "a chunk of %llu bytes uncompressed, past this reader's "
             "limit of %lu bytes", (unsigned long long)usize, (unsigned long)ROZ_MCAP_MAX_RECORD);
        return ROZ_EINVAL;
    }
    const unsigned char *records = p + q;
    if (comp[0] == '\0') {
        if (clen != usize) {
            rerr(r, err, errlen, at, "a chunk whose records (%llu bytes) do not fit it",
                 (unsigned long long)clen);
            return ROZ_EINVAL;
        }
    } else if (strcmp(comp, "zstd") == 0 && ROZ_MCAP_ZSTD) {
#if ROZ_MCAP_ZSTD
        if (usize > r->chunk_cap) {
            unsigned char *b = realloc(r->chunk, usize ? (size_t)usize : 1u);
            if (b == NULL) {
                rerr(r, err, errlen, at, "out of memory for a chunk of %llu bytes",
                     (unsigned long long)usize);
                return ROZ_ENOMEM;
            }
            r->chunk = b;
            r->chunk_cap = (size_t)usize;
        }
        size_t z = ZSTD_decompress(r->chunk, (size_t)usize, records, (size_t)clen);
        if (ZSTD_isError(z) || z != usize) {
            rerr(r, err, errlen, at, "a zstd chunk that does not decompress to the %llu bytes it "
                 "states (%s)", (unsigned long long)usize,
                 ZSTD_isError(z) ? ZSTD_getErrorName(z) : "another size");
            return ROZ_EINVAL;
        }
        records = r->chunk;
#endif
    } else {
        rerr(r, err, errlen, at, "a chunk compressed with \"%s\", which this reader "
             "does not decompress", comp);
        return ROZ_EINVAL;
    }
    uint32_t got = roz_mcap_crc32(0, records, (size_t)usize);
    if (crc != 0 && got != crc) {
        rerr(r, err, errlen, at, "chunk CRC mismatch (stored %08lx, computed %08lx): "
             "the file is corrupt", (unsigned long)crc, (unsigned long)got);
        return ROZ_EINVAL;
    }
    r->chunk_data = records;
    r->chunk_pos = 0;
    r->chunk_end = (size_t)usize;
    r->chunk_base = at;
    r->in_chunk = 1;
    return ROZ_OK;
}

int roz_mcap_reader_next(roz_mcap_reader_t *r, roz_mcap_message_t *out, char *err,
                         size_t errlen)
{
    for (;;) {
        if (r->done)
            return 0;
        if (r->in_chunk) {
            if (r->chunk_pos >= r->chunk_end) {
                r->in_chunk = 0;
                continue;
            }
            size_t at = r->chunk_pos;
            uint64_t file_at = r->chunk_base;
            if (r->chunk_end - at < 9u) {
                rerr(r, err, errlen, file_at, "chunk: a record cut short at byte %lu of its records",
                     (unsigned long)at);
                return ROZ_EINVAL;
            }
            uint8_t op = r->chunk_data[at];
            uint64_t n = get_le(r->chunk_data + at + 1, 8);
            if (n > r->chunk_end - at - 9u) {
                rerr(r, err, errlen, file_at, "chunk: a record of %llu bytes runs past its end",
                     (unsigned long long)n);
                return ROZ_EINVAL;
            }
            const unsigned char *p = r->chunk_data + at + 9;
            r->chunk_pos = at + 9u + (size_t)n;
            if (op == OP_SCHEMA || op == OP_CHANNEL) {
                if (take_definition(r, op, p, (size_t)n) != 0) {
                    rerr(r, err, errlen, file_at, "chunk: a malformed %s record",
                         op == OP_SCHEMA ? "schema" : "channel");
                    return ROZ_EINVAL;
                }
                continue;
            }
            if (op != OP_MESSAGE)
                continue;
            if (n < 22u) {
                rerr(r, err, errlen, file_at, "chunk: a message record of %llu bytes",
                     (unsigned long long)n);
                return ROZ_EINVAL;
            }
            out->channel = (uint16_t)get_le(p, 2);
            out->sequence = (uint32_t)get_le(p + 2, 4);
            out->log_time = get_le(p + 6, 8);
            out->publish_time = get_le(p + 14, 8);
            out->data = p + 22;
            out->len = (size_t)n - 22u;
            out->offset = file_at;
            if (out->channel == 0 || out->channel > ROZ_MCAP_MAX_CHANNELS ||
                r->topics[out->channel][0] == '\0') {
                rerr(r, err, errlen, file_at, "a message on channel %u, which no channel record "
                     "defines", (unsigned)out->channel);
                return ROZ_EINVAL;
            }
            out->topic = r->topics[out->channel];
            uint16_t sc = r->channel_schema[out->channel];
            out->schema = sc >= 1u && sc <= ROZ_MCAP_MAX_CHANNELS ? r->schema_names[sc] : "";
            return 1;
        }
        /* the data section, record by record: the header first, the length
         * checked against the limit and the file before anything is read */
        uint64_t at = r->pos;
        unsigned char head[9];
        if (r->size - at < 9u || fseeko(r->in, (off_t)at, SEEK_SET) != 0 ||
            fread(head, 1, sizeof head, r->in) != sizeof head) {
            r->done = 1;
            snprintf(r->warning, sizeof r->warning,
                     "%s: cut short at offset %llu (no data end, summary or footer): read up "
                     "to there", r->path, (unsigned long long)at);
            return 0;
        }
        uint8_t op = head[0];
        uint64_t n = get_le(head + 1, 8);
        int wanted = op == OP_CHUNK || op == OP_SCHEMA || op == OP_CHANNEL || op == OP_MESSAGE;
        if (wanted && n > ROZ_MCAP_MAX_RECORD) {
            rerr(r, err, errlen, at, "a record (opcode 0x%02x) of %llu bytes, past this "
                 "reader's limit of %lu bytes", (unsigned)op, (unsigned long long)n,
                 (unsigned long)ROZ_MCAP_MAX_RECORD);
            return ROZ_EINVAL;
        }
        if (n > r->size - at - 9u) {
            r->done = 1;
            snprintf(r->warning, sizeof r->warning,
                     "%s: cut short at offset %llu (a record of %llu bytes runs past the end "
                     "of the file): read up to there", r->path, (unsigned long long)at,
                     (unsigned long long)n);
            return 0;
        }
        r->pos = at + 9u + n;
        if (op == OP_DATA_END || op == OP_FOOTER) {
            r->done = 1;
            if (!r->complete)
                snprintf(r->warning, sizeof r->warning,
                         "%s: no trailing magic: the file is cut short after offset %llu",
                         r->path, (unsigned long long)at);
            return 0;
        }
        if (!wanted)
            continue; /* message indexes, attachments, metadata: not needed here */
        int rc = read_at(r, at + 9u, (size_t)n, &r->rec, &r->rec_cap);
        if (rc != ROZ_OK) {
            rerr(r, err, errlen, at, "%s", rc == ROZ_ENOMEM ? "out of memory" : "cannot read");
            return rc;
        }
        const unsigned char *p = r->rec;
        switch (op) {
        case OP_SCHEMA:
        case OP_CHANNEL:
            if (take_definition(r, op, p, (size_t)n) != 0) {
                rerr(r, err, errlen, at, "a malformed %s record",
                     op == OP_SCHEMA ? "schema" : "channel");
                return ROZ_EINVAL;
            }
            break;
        case OP_CHUNK: {
            rc = open_chunk(r, at, p, (size_t)n, err, errlen);
            if (rc != ROZ_OK)
                return rc;
            break;
        }
        default: /* OP_MESSAGE */
            rerr(r, err, errlen, at, "a message outside a chunk (roz writes none)");
            return ROZ_EINVAL;
        }
    }
}

void roz_mcap_reader_close(roz_mcap_reader_t *r)
{
    if (r->in != NULL)
        fclose(r->in);
    r->in = NULL;
    free(r->rec);
    free(r->chunk);
    r->rec = r->chunk = NULL;
    r->rec_cap = r->chunk_cap = 0;
}
