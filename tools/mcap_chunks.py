# SPDX-License-Identifier: Apache-2.0
"""Chunks of an MCAP file decompressed within the size they state, for
tools/recording.py and tools/live.py: a chunk record states its size once
decompressed, and its zstd or lz4 frame may state another (or none). The
PyPI mcap reader sizes its output from the frame (python-zstandard
allocates what a zstd frame header says: 4 GiB for a 131 KB file) or
from nothing at all (lz4); here the stated size, itself at most
MAX_RECORD, is a hard cap on a streaming decompressor, and a chunk whose
data or frame says otherwise is refused, naming the chunk and the limit
(docs/recording-format.md; test/record/test_recording.py,
test_readers_refuse_chunks_that_lie)."""
import io
import zlib

import lz4.frame
import mcap.stream_reader
import zstandard
from mcap.exceptions import McapError
from mcap.stream_reader import ReadDataStream

# the largest record, and chunk once decompressed, read (roz/mcap.h)
MAX_RECORD = 16 * 1024 * 1024


class ChunkError(McapError):
    """A chunk refused: its text names the chunk and the limit."""


def _name(chunk):
    return (f"the {chunk.compression} chunk of messages {chunk.message_start_time}.."
            f"{chunk.message_end_time} ns")


def chunk_data(chunk):
    """The chunk's records, decompressed to at most its stated size."""
    try:
        return _chunk_data(chunk)
    except (zstandard.ZstdError, RuntimeError) as e:  # lz4's errors are RuntimeErrors
        raise ChunkError(f"{_name(chunk)}: its data cannot be decompressed: "
                         f"{str(e) or type(e).__name__}") from None


def _chunk_data(chunk):
    cap = chunk.uncompressed_size
    if cap > MAX_RECORD:
        raise ChunkError(f"{_name(chunk)}: {cap} bytes uncompressed, past this reader's "
                         f"limit of {MAX_RECORD} bytes")
    if chunk.compression == "":
        data = bytes(chunk.data)
    elif chunk.compression == "zstd":
        framed = zstandard.frame_content_size(chunk.data) if len(chunk.data) >= 18 else -1
        if framed not in (-1, cap):
            raise ChunkError(f"{_name(chunk)}: its zstd frame states {framed} bytes, the "
                             f"chunk {cap} (the limit)")
        dctx = zstandard.ZstdDecompressor(max_window_size=MAX_RECORD)
        parts, got = [], 0
        with dctx.stream_reader(io.BytesIO(chunk.data), read_across_frames=True) as r:
            while got <= cap:
                part = r.read(cap + 1 - got)
                if not part:
                    break
                parts.append(part)
                got += len(part)
        data = b"".join(parts)
    elif chunk.compression == "lz4":
        d = lz4.frame.LZ4FrameDecompressor()
        data = d.decompress(chunk.data, max_length=cap + 1)
    else:
        raise ChunkError(f"{_name(chunk)}: compression '{chunk.compression}' unknown")
    if len(data) > cap:
        raise ChunkError(f"{_name(chunk)}: decompresses past its stated size, the limit of "
                         f"{cap} bytes")
    if len(data) < cap:
        raise ChunkError(f"{_name(chunk)}: decompresses to {len(data)} bytes, not its stated "
                         f"{cap}")
    return data


def _get_chunk_data_stream(chunk, validate_crc=False):
    data = chunk_data(chunk)
    if validate_crc and chunk.uncompressed_crc != 0 and zlib.crc32(data) != chunk.uncompressed_crc:
        raise mcap.stream_reader.CRCValidationError(expected=chunk.uncompressed_crc,
                                                    actual=zlib.crc32(data), record=chunk)
    return ReadDataStream(io.BytesIO(data)), len(data)


def install():
    """Makes the mcap package's readers (make_reader, StreamReader) take
    every chunk through chunk_data(). mcap 1.x looks the function up in its
    stream_reader module at each chunk (tools/requirements.txt pins it)."""
    mcap.stream_reader.get_chunk_data_stream = _get_chunk_data_stream
